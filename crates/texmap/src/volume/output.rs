//! What both volume methods (rays and slices) share at the frame's edges: the checks of a
//! request, and the conversion of their display-space result to the frame's colour.
//!
//! Rules:
//! - A request is checked before any table is built: a valid camera, an image of 1..=16384
//!   pixels a side, a positive finite step, and a depth buffer (when given) of one distance per
//!   pixel.
//! - Both methods composite display values, as VTK composites them; the frame stores
//!   `srgb_to_linear` of the result (premultiplied colour clamped to `[0, 1]`), so that writing
//!   it as sRGB gives back the composited bytes.

use glam::Vec4;

use super::params::MarchParams;
use crate::camera::Camera;
use crate::{Error, Result};

/// The checks of a `width × height` request seen by `camera` with `depth` (per pixel, when
/// given) under `params`, in this order: camera, image size, step, depth buffer length.
///
/// # Errors
/// [`Error::Parameter`] for the first that fails.
pub(crate) fn check_request(
    camera: &Camera,
    width: u32,
    height: u32,
    params: &MarchParams,
    depth: Option<&[f32]>,
) -> Result<()> {
    camera.validate()?;
    if width == 0 || height == 0 || width > 16384 || height > 16384 {
        return Err(Error::parameter(format!(
            "image size {width}x{height} is out of range"
        )));
    }
    params.check_step()?;
    match depth {
        Some(d) if d.len() != width as usize * height as usize => Err(Error::parameter(format!(
            "depth buffer has {} values for a {width}x{height} image",
            d.len()
        ))),
        _ => Ok(()),
    }
}

/// Display-space premultiplied colour → the frame's linear premultiplied colour.
#[inline]
#[must_use]
pub(crate) fn display_to_frame(c: Vec4) -> Vec4 {
    let f = |v: f32| crate::color::srgb_to_linear(v.clamp(0.0, 1.0));
    Vec4::new(f(c.x), f(c.y), f(c.z), c.w.clamp(0.0, 1.0))
}
