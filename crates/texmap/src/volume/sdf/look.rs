//! How a distance field's surface looks (Miller & Jones §5): a plain colour or a solid
//! texture indexed by the surface point, so the object looks carved from the block; the
//! gradient normal optionally bumped by the noise gradient; lit by the volume shading
//! (Blinn-Phong, the scene's lights or the headlight).
//!
//! Rules:
//! - Texture space is the field's box, centred and scaled by its largest side (the object
//!   fills about `[−½, ½]`), so a pattern's defaults fit a spot in metres and a head in
//!   millimetres alike. Patterns are antialiased by the pixel's footprint on the surface.
//! - Bump (Blinn's perturbation with a solid noise, as the paper does on the GPU): the
//!   normal loses `bump ×` the tangential part of the gradient of fBm at `bump_frequency ×`
//!   the texture-space point (three octaves): `n' = normalize(n − k·(∇N − (∇N·n)·n))`.
//! - Colours are linear RGB; the surface is opaque.

use glam::{DVec3, Mat4, Vec3};

use crate::texture::procedural::perlin::fbm_with_gradient;
use crate::texture::procedural::Solid;
use crate::{Error, Result};

/// A distance-field surface's material.
#[derive(Clone, Debug, PartialEq)]
pub struct SurfaceLook {
    /// The colour without a solid texture (linear RGB).
    pub color: Vec3,
    /// A solid pattern (marble, wood, granite, …) indexed by the surface point.
    pub solid: Option<Solid>,
    /// The pattern's two colours (value 0, value 1); `None`: the pattern's own.
    pub solid_colors: Option<[Vec3; 2]>,
    /// Bump strength (0: none).
    pub bump: f32,
    /// The bump noise's frequency, per object size.
    pub bump_frequency: f32,
}

impl Default for SurfaceLook {
    fn default() -> Self {
        SurfaceLook {
            color: Vec3::splat(0.8),
            solid: None,
            solid_colors: None,
            bump: 0.0,
            bump_frequency: 24.0,
        }
    }
}

impl SurfaceLook {
    /// Checks the numbers.
    ///
    /// # Errors
    /// [`Error::Parameter`] for a negative or non-finite colour or bump value.
    pub fn validate(&self) -> Result<()> {
        if !(self.color.is_finite() && self.color.min_element() >= 0.0) {
            return Err(Error::parameter("surface color must be finite and ≥ 0"));
        }
        if !(self.bump.is_finite() && self.bump >= 0.0) {
            return Err(Error::parameter(format!("bump {} must be ≥ 0", self.bump)));
        }
        if !(self.bump_frequency.is_finite() && self.bump_frequency > 0.0) {
            return Err(Error::parameter(format!(
                "bump frequency {} must be > 0",
                self.bump_frequency
            )));
        }
        Ok(())
    }

    /// The colour at world point `p` (texture space through `texture_from_world`), the
    /// footprint `width` in texture units.
    #[inline]
    pub(crate) fn color_at(&self, texture_from_world: &Mat4, p: Vec3, width: f32) -> Vec3 {
        match &self.solid {
            None => self.color,
            Some(s) => {
                let q = texture_from_world.transform_point3(p).as_dvec3();
                let colors = self.solid_colors.unwrap_or_else(|| s.default_colors());
                s.color(q, DVec3::splat(f64::from(width)), colors)
            }
        }
    }

    /// `n` (unit, world) bumped at world point `p`.
    #[inline]
    pub(crate) fn bumped(&self, texture_from_world: &Mat4, p: Vec3, n: Vec3) -> Vec3 {
        if self.bump == 0.0 {
            return n;
        }
        let q = texture_from_world.transform_point3(p).as_dvec3() * f64::from(self.bump_frequency);
        let (_, g) = fbm_with_gradient(q, 3.0, 2.0, 0.5);
        // Texture space is world space scaled uniformly: the gradient's direction is the
        // world's, and its size (per noise unit) makes the strength independent of units.
        let g = g.as_vec3();
        let tangential = g - n * g.dot(n);
        (n - tangential * self.bump).try_normalize().unwrap_or(n)
    }
}

/// The field's texture space: its box's centre at the origin, its largest side 1.
#[must_use]
pub(crate) fn texture_from_world(lo: Vec3, hi: Vec3) -> Mat4 {
    let size = (hi - lo).max_element().max(1e-12);
    Mat4::from_scale(Vec3::splat(1.0 / size)) * Mat4::from_translation(-(lo + hi) * 0.5)
}
