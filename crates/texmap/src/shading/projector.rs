//! Projective textures: a slide projector. A [`Projector`] is a point light whose colour
//! passes through an image (the slide) framed by a perspective frustum — the lectures'
//! "projective textures", after Segal et al. 1992: a surface point `P` is carried into the
//! projector's clip space, divided by its `w` (the projective divide) and read at
//!
//! ```text
//! u = ½ + ½·x/(w·tan(fov/2)·aspect),   v = ½ − ½·y/(w·tan(fov/2)),   w = −z_view > 0
//! ```
//!
//! so the slide's top row falls above the projector's axis (in the direction of `up`) and its
//! left column to the left, as seen from the projector. Nothing is lit behind the projector
//! (`w ≤ 0`) or outside its frustum (the slide is read with a transparent black border, so its
//! edges are filtered like any texel). The read's footprint comes from the pixel's position
//! derivatives through the divide's Jacobian ([`Projector::footprint`]), so a slide thrown
//! at a grazing angle is filtered like any other texture.
//!
//! What it delivers at `P` is the light `I·T(u, v)` from the projector's position (its
//! premultiplied texel: a transparent texel passes nothing), attenuated by the inverse square
//! distance unless `falloff` is off, lit by the material's own model (or toon ramp) like any
//! light (diffuse and specular), and, when the projector casts, scaled by the lit fraction of
//! its own depth map (the shadow-map code of [`super::shadow`]).

use glam::{Mat4, Vec2, Vec3};

use super::material::TextureSlot;
use crate::texture::Footprint;

/// A slide projector (see the module docs).
#[derive(Clone, Debug)]
pub struct Projector {
    pub position: Vec3,
    /// The point the projector aims at.
    pub target: Vec3,
    pub up: Vec3,
    /// Vertical field of view of the frustum, degrees (0 < fov < 180).
    pub fov_deg: f32,
    /// Width over height of the frustum (by default the image's).
    pub aspect: f32,
    /// The slide: its image and sampler (a border wrap with transparent black by default).
    pub slide: TextureSlot,
    /// Colour × intensity, linear: the light of a white texel (at distance 1 with falloff).
    pub color: Vec3,
    /// Inverse-square falloff with the distance (true), or the same light at every distance.
    pub falloff: bool,
    /// Occluded by its own depth map (a shadow map drawn from the projector).
    pub shadows: bool,
}

impl Projector {
    /// The projector's view transform (looking down −z, `up` as +y).
    #[must_use]
    pub fn view_from_world(&self) -> Mat4 {
        Mat4::look_at_rh(self.position, self.target, self.up)
    }

    /// The unit axis the projector points along.
    #[must_use]
    pub fn axis(&self) -> Vec3 {
        (self.target - self.position).normalize_or_zero()
    }

    /// tan of half the vertical and half the horizontal field of view.
    #[must_use]
    pub fn tan_half(&self) -> Vec2 {
        let ty = (0.5 * self.fov_deg).to_radians().tan();
        Vec2::new(ty * self.aspect, ty)
    }

    /// The half angle of the cone around the axis that holds the frustum (through its
    /// corners), degrees.
    #[must_use]
    pub fn cone_half_deg(&self) -> f32 {
        self.tan_half().length().atan().to_degrees()
    }

    /// What makes the projector unusable, if anything: a position, target or up that is not
    /// finite, a target at the position, an up along the axis, a field of view outside
    /// (0, 180), an aspect that is not positive, a negative or non-finite colour.
    ///
    /// # Errors
    /// The problem, in words, for the loader to prefix with the file and entry.
    pub fn check(&self) -> Result<(), String> {
        if !(self.position.is_finite() && self.target.is_finite() && self.up.is_finite()) {
            return Err("position, target and up must be finite".into());
        }
        let axis = self.target - self.position;
        if axis.length_squared() <= f32::MIN_POSITIVE {
            return Err("target is the position: the projector points nowhere".into());
        }
        if axis.normalize().cross(self.up).length_squared() < 1e-8 {
            return Err(format!("up {} is along the axis", self.up));
        }
        if !(self.fov_deg > 0.0 && self.fov_deg < 180.0) {
            return Err(format!("fov {}° is not between 0 and 180", self.fov_deg));
        }
        if !(self.aspect > 0.0 && self.aspect.is_finite()) {
            return Err(format!("aspect {} must be positive", self.aspect));
        }
        if !self.color.is_finite() || self.color.min_element() < 0.0 {
            return Err(format!(
                "colour × intensity {} must be finite and ≥ 0",
                self.color
            ));
        }
        Ok(())
    }

    /// The projector's frustum made ready for per-pixel lookups (its view transform and
    /// the divide's scale, computed once).
    #[must_use]
    pub fn view(&self) -> ProjectorView {
        let t = self.tan_half();
        ProjectorView {
            view_from_world: self.view_from_world(),
            scale: Vec2::new(0.5 / t.x, -0.5 / t.y),
        }
    }

    /// Where world point `p` falls on the slide: [`ProjectorView::footprint`] (prefer
    /// [`Projector::view`] once and its lookups per pixel).
    #[must_use]
    pub fn footprint(&self, p: Vec3, dp_dx: Vec3, dp_dy: Vec3) -> Option<Footprint> {
        self.view().footprint(p, dp_dx, dp_dy)
    }
}

/// A projector's frustum, ready for lookups ([`Projector::view`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProjectorView {
    pub view_from_world: Mat4,
    /// `(½/tan_x, −½/tan_y)`: slide coordinates per unit of `x/w` and `y/w`.
    pub scale: Vec2,
}

impl ProjectorView {
    /// Where world point `p` falls on the slide, with the derivatives of `(u, v)` along the
    /// screen from the point's own (`dp_dx`, `dp_dy`): the footprint the slide is read
    /// with. `None` behind the projector (`w ≤ 0`) and where the whole footprint is off the
    /// slide (the border would read zero).
    #[inline]
    #[must_use]
    pub fn footprint(&self, p: Vec3, dp_dx: Vec3, dp_dy: Vec3) -> Option<Footprint> {
        let view = &self.view_from_world;
        let q = view.transform_point3(p);
        let w = -q.z;
        if !(w > 1e-6 * (1.0 + q.x.abs() + q.y.abs())) {
            return None;
        }
        let inv_w = 1.0 / w;
        let s = Vec2::new(q.x, q.y) * inv_w;
        let uv = Vec2::splat(0.5) + s * self.scale;
        // d(x/w) = (dx + (x/w)·dz_view)/w with w = −z_view.
        let d = |dp: Vec3| {
            let dq = view.transform_vector3(dp);
            (Vec2::new(dq.x, dq.y) + s * dq.z) * inv_w * self.scale
        };
        let (dx, dy) = (d(dp_dx), d(dp_dy));
        let reach = dx.abs() + dy.abs();
        let lo = uv + reach;
        let hi = uv - reach;
        if lo.x < 0.0 || lo.y < 0.0 || hi.x > 1.0 || hi.y > 1.0 {
            return None;
        }
        Some(Footprint::new(uv, dx, dy))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::texture::{Sampler, Texture2D, TextureOptions};
    use proptest::prelude::*;
    use std::sync::Arc;

    fn projector(fov: f32, aspect: f32) -> Projector {
        Projector {
            position: Vec3::new(0.0, 2.0, 3.0),
            target: Vec3::new(0.0, 0.0, 0.0),
            up: Vec3::Y,
            fov_deg: fov,
            aspect,
            slide: TextureSlot::new(
                Arc::new(
                    Texture2D::from_fn(2, 2, TextureOptions::default(), |_, _| glam::Vec4::ONE)
                        .unwrap(),
                ),
                Sampler::default(),
            ),
            color: Vec3::ONE,
            falloff: true,
            shadows: false,
        }
    }

    #[test]
    fn the_axis_hits_the_slide_centre_and_up_is_its_top() {
        let p = projector(40.0, 1.5);
        let fp = p.footprint(Vec3::ZERO, Vec3::ZERO, Vec3::ZERO).unwrap();
        assert!(
            (fp.uv - Vec2::splat(0.5)).abs().max_element() < 1e-6,
            "{}",
            fp.uv
        );
        // A point a little above the target (towards up) reads a smaller v: the top rows.
        let up = p.footprint(Vec3::new(0.0, 0.1, 0.0), Vec3::ZERO, Vec3::ZERO);
        assert!(up.unwrap().uv.y < 0.5);
        // Seen from the projector looking down −z-ish, +x world is to its right.
        let right = p.footprint(Vec3::new(0.1, 0.0, 0.0), Vec3::ZERO, Vec3::ZERO);
        assert!(right.unwrap().uv.x > 0.5);
    }

    #[test]
    fn nothing_behind_the_projector_or_outside_its_frustum() {
        let p = projector(40.0, 1.0);
        let behind = p.position + (p.position - p.target);
        assert!(p.footprint(behind, Vec3::ZERO, Vec3::ZERO).is_none());
        assert!(p.footprint(p.position, Vec3::ZERO, Vec3::ZERO).is_none());
        let far_side = Vec3::new(10.0, 0.0, 0.0);
        assert!(p.footprint(far_side, Vec3::ZERO, Vec3::ZERO).is_none());
    }

    #[test]
    fn the_frustum_edge_is_at_half_the_field_of_view() {
        let p = Projector {
            position: Vec3::ZERO,
            target: -Vec3::Z,
            ..projector(60.0, 2.0)
        };
        let t = p.tan_half();
        // Just inside the top edge and the right edge.
        let top = p.footprint(Vec3::new(0.0, 0.999 * t.y, -1.0), Vec3::ZERO, Vec3::ZERO);
        assert!(top.unwrap().uv.y < 1e-3);
        let right = p.footprint(Vec3::new(0.999 * t.x, 0.0, -1.0), Vec3::ZERO, Vec3::ZERO);
        assert!(right.unwrap().uv.x > 0.999);
        assert!(p
            .footprint(Vec3::new(1.01 * t.x, 0.0, -1.0), Vec3::ZERO, Vec3::ZERO)
            .is_none());
        assert!((p.cone_half_deg() - t.length().atan().to_degrees()).abs() < 1e-5);
    }

    #[test]
    fn bad_projectors_are_named() {
        let ok = projector(40.0, 1.0);
        assert!(ok.check().is_ok());
        let same = Projector {
            target: ok.position,
            ..ok.clone()
        };
        assert!(same.check().unwrap_err().contains("points nowhere"));
        let along = Projector {
            up: ok.target - ok.position,
            ..ok.clone()
        };
        assert!(along.check().unwrap_err().contains("along the axis"));
        assert!(projector(180.0, 1.0).check().is_err());
        assert!(projector(30.0, 0.0).check().is_err());
    }

    proptest! {
        /// The footprint's derivatives are those of the projective divide: finite
        /// differences of `uv` agree with them.
        #[test]
        fn derivatives_match_finite_differences(
            x in -0.5f32..0.5, y in -0.5f32..0.5, z in -0.5f32..0.5,
            dx in prop::array::uniform3(-1.0f32..1.0),
        ) {
            let p = projector(50.0, 1.3);
            let at = Vec3::new(x, y, z);
            let d = Vec3::from(dx) * 1e-3;
            let (Some(a), Some(b)) = (
                p.footprint(at, d, Vec3::ZERO),
                p.footprint(at + d, Vec3::ZERO, Vec3::ZERO),
            ) else {
                return Ok(());
            };
            let diff = b.uv - a.uv;
            let tolerance = 2e-5 + 0.02 * diff.abs().max_element();
            prop_assert!(
                (diff - a.duv_dx).abs().max_element() < tolerance,
                "{} vs {}",
                diff,
                a.duv_dx
            );
        }
    }
}
