//! `[[projectors]]` → [`Projector`]: a slide projector at `position` aiming at `target`,
//! its slide `image` (a texture table, sRGB unless it says, read with a transparent black
//! border unless it names a wrap) framed by `fov` (vertical degrees) and `aspect` (the
//! image's by default), its light `color × intensity`, inverse-square `falloff` unless
//! false, occluded by its own depth map with `shadows = true`.

use std::path::Path;

use glam::{Vec3, Vec4};

use super::spec::ProjectorSpec;
use super::textures::slot;
use crate::scene::texture_cache::TextureCache;
use crate::shading::Projector;
use crate::texture::{ColorSpace, Wrap};
use crate::{Error, Result};

/// The projector entry `p` describes; `None` when its image is a format texmap leaves out
/// (a warning, as for any texture). `Error::Parameter` messages are the entry's problem, for
/// the caller to prefix with the file and the entry.
pub(super) fn projector(
    dir: &Path,
    p: &ProjectorSpec,
    textures: &mut TextureCache,
) -> Result<Option<Projector>> {
    let Some(mut slide) = slot(dir, "image", &p.image, ColorSpace::Srgb, textures)? else {
        return Ok(None);
    };
    let t = &p.image;
    if t.wrap.is_none() && t.wrap_u.is_none() && t.wrap_v.is_none() {
        slide.sampler.wrap_u = Wrap::ClampToBorder;
        slide.sampler.wrap_v = Wrap::ClampToBorder;
        if t.border.is_none() {
            slide.sampler.border = Vec4::ZERO;
        }
    }
    let (w, h) = (slide.texture.width(), slide.texture.height());
    let projector = Projector {
        position: Vec3::from(p.position),
        target: Vec3::from(p.target),
        up: Vec3::from(p.up),
        fov_deg: p.fov,
        aspect: p.aspect.unwrap_or(w as f32 / h.max(1) as f32),
        slide,
        color: Vec3::from(p.color) * p.intensity,
        falloff: p.falloff,
        shadows: p.shadows,
    };
    projector.check().map_err(Error::Parameter)?;
    Ok(Some(projector))
}
