//! A distance field's surface seen from a light: where the light's rays first meet its core
//! surface, so the surface can be drawn into shadow maps beside the meshes
//! (`render/field_shadow.rs`).
//!
//! Rules:
//! - The core surface is found as the frame's rays find it (`render/mod.rs`: sphere tracing,
//!   the crossing bisected to 1/100 voxel), melted and displaced as the frame draws it, so
//!   the shadow has the shape the eye sees; nothing is shaded.
//! - A hypertexture's material does not cast (a depth map holds one opaque depth per texel),
//!   and a hypertexture drawn without its core (smoke) casts nothing.

use glam::Vec3;

use super::super::grid::Volume;
use super::super::params::MarchParams;
use super::hyper::Hypertexture;
use super::look::SurfaceLook;
use super::render::Tracer;
use crate::camera::Camera;

/// A distance field's core surface, ready to be hit by rays.
pub struct FieldCaster<'a> {
    tracer: Tracer<'a>,
}

impl<'a> FieldCaster<'a> {
    /// The surface of `vol` as the frame draws it with `look`, `hyper` and `params` seen by
    /// `camera` (whose up is the melt's up).
    #[must_use]
    pub fn new(
        vol: &'a Volume,
        camera: &Camera,
        params: &'a MarchParams,
        look: &'a SurfaceLook,
        hyper: Option<&'a Hypertexture>,
    ) -> FieldCaster<'a> {
        let mut tracer = Tracer::new(vol, camera, 1, params, look, hyper);
        tracer.depth_only = true;
        FieldCaster { tracer }
    }

    /// The distance along the ray from `origin` in the unit direction `dir` to the first
    /// point of the surface, if it is closer than `t_max`.
    #[must_use]
    pub fn hit(&self, origin: Vec3, dir: Vec3, t_max: f32) -> Option<f32> {
        let (_, _, t) = self.tracer.trace(origin, dir, t_max, 0.0);
        (t < t_max).then_some(t)
    }
}
