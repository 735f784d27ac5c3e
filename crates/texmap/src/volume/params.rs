//! The options of a volume render, read by both methods (rays and slices): what a ray
//! computes, where classification happens, the sample distance, shading, skipping and the
//! early stop.
//!
//! Rules:
//! - Lengths are world units (the file's spacing units), like VTK's `SampleDistance`.
//! - The step (0.5), the reflectance and the early stop follow `vtk_volume.py` and VTK (whose
//!   fixed-point mapper stops a ray when its remaining transparency falls below 255/32768,
//!   hence 0.992). Jitter is on by default, where the peer turns VTK's off: it turns
//!   wood-grain banding into fine noise.
//! - Every option is plain data; the renderers check them (`check_step`) and derive their
//!   tables from them once per frame.

use super::shade::Reflectance;
use crate::shading::Light;
use crate::{Error, Result};

/// What a ray computes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Mode {
    /// Direct volume rendering: classification and front-to-back compositing.
    #[default]
    Composite,
    /// Maximum intensity projection (grey, the value range mapped to [0, 1]).
    Mip,
    /// The first crossing of the iso-value, refined by bisection, shaded.
    Iso,
    /// The average value along the ray (grey, the value range mapped to [0, 1]).
    Xray,
}

/// Where classification happens relative to interpolation.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Classification {
    /// Interpolate values, then classify (the default; sharpest).
    #[default]
    Post,
    /// Classify the eight voxels, then interpolate premultiplied colour and opacity.
    Pre,
    /// Classify each segment between two samples from a pre-integrated table.
    PreIntegrated,
}

/// How a volume is rendered.
#[derive(Clone, Debug, PartialEq)]
pub struct MarchParams {
    pub mode: Mode,
    /// Distance between samples along a ray, world units (> 0).
    pub step: f32,
    /// Blinn-Phong shading from central-difference gradients (composite mode).
    pub shade: bool,
    pub classification: Classification,
    /// How samples reflect light when shaded (Blinn-Phong coefficients).
    pub reflectance: Reflectance,
    /// Lights for shading, world space (a scene's lights); empty: a white headlight along
    /// the view direction (see `volume::shade`).
    pub lights: Vec<Light>,
    /// Iso-value for [`Mode::Iso`] (default: the transfer function's first opaque value).
    pub iso: Option<f32>,
    /// Opacity × a piecewise-linear function of the gradient magnitude: `(g, factor)` points
    /// (the 2D transfer function); empty for none.
    pub gradient_opacity: Vec<(f32, f32)>,
    /// Jittered ray starts (hides wood-grain banding).
    pub jitter: bool,
    pub empty_space_skipping: bool,
    /// Stop a ray once its opacity reaches this (1 or more: never). Default 0.992: VTK's
    /// fixed-point mapper stops when the remaining opacity falls below 255/32768.
    pub early_termination: f32,
    /// Read values through the texture engine instead of the plain copy (slow; for checks).
    pub engine_sampling: bool,
    /// A crop box in voxel coordinates (`x0, x1, y0, y1, z0, z1`, voxel centres at integers):
    /// only the part of the volume inside it is drawn, by rays and by slices. `None`: the
    /// whole volume.
    pub crop: Option<[f32; 6]>,
}

impl MarchParams {
    /// The box drawn, in voxel coordinates: `[0, n − 1]` on each axis, or the crop box
    /// within it.
    #[must_use]
    pub fn voxel_box(&self, dims: [u32; 3]) -> (glam::Vec3, glam::Vec3) {
        let hi = glam::Vec3::from_array(dims.map(|n| n.saturating_sub(1) as f32));
        match self.crop {
            None => (glam::Vec3::ZERO, hi),
            Some(c) => (
                glam::Vec3::new(c[0], c[2], c[4]).clamp(glam::Vec3::ZERO, hi),
                glam::Vec3::new(c[1], c[3], c[5]).clamp(glam::Vec3::ZERO, hi),
            ),
        }
    }

    /// Checks the crop box against a volume of `dims`: finite, each low end below its high
    /// end, overlapping the volume.
    ///
    /// # Errors
    /// The problem, for the caller to name the file.
    pub fn check_crop(&self, dims: [u32; 3]) -> std::result::Result<(), String> {
        let Some(c) = self.crop else {
            return Ok(());
        };
        for (a, name) in ["x", "y", "z"].iter().enumerate() {
            let (lo, hi) = (c[2 * a], c[2 * a + 1]);
            let n = dims[a].saturating_sub(1) as f32;
            if !(lo.is_finite() && hi.is_finite() && lo < hi) {
                return Err(format!(
                    "crop {name} {lo}..{hi} is not a range (low < high)"
                ));
            }
            if hi <= 0.0 || lo >= n {
                return Err(format!(
                    "crop {name} {lo}..{hi} misses the volume's voxels 0..{n}"
                ));
            }
        }
        Ok(())
    }
}

impl Default for MarchParams {
    fn default() -> Self {
        MarchParams {
            mode: Mode::Composite,
            step: 0.5,
            shade: false,
            classification: Classification::Post,
            reflectance: Reflectance::default(),
            lights: Vec::new(),
            iso: None,
            gradient_opacity: Vec::new(),
            jitter: true,
            empty_space_skipping: true,
            early_termination: 0.992,
            engine_sampling: false,
            crop: None,
        }
    }
}

/// The most samples one ray may take through a volume (and slices one frame may draw): a
/// step that asks for more is refused instead of running for hours.
pub const MAX_SAMPLES_PER_RAY: f32 = 1.0e6;

impl MarchParams {
    /// The step must be positive, finite, and take at most [`MAX_SAMPLES_PER_RAY`] samples
    /// over `length` (the longest path through the volume, its box's diagonal).
    ///
    /// # Errors
    /// [`Error::Parameter`] naming `--step` otherwise.
    pub fn check_samples(&self, length: f32) -> Result<()> {
        self.check_step()?;
        let n = length / self.step;
        if n > MAX_SAMPLES_PER_RAY {
            return Err(Error::parameter(format!(
                "--step {} takes {n:.0} samples across the volume (at most {MAX_SAMPLES_PER_RAY:.0})",
                self.step
            )));
        }
        Ok(())
    }

    /// The step must be positive and finite.
    ///
    /// # Errors
    /// [`Error::Parameter`] naming `--step` otherwise.
    pub fn check_step(&self) -> Result<()> {
        if self.step.is_finite() && self.step > 0.0 {
            Ok(())
        } else {
            Err(Error::parameter(format!(
                "--step {} must be > 0",
                self.step
            )))
        }
    }
}
