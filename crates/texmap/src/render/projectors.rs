//! Slide projectors in a frame ([`crate::shading::Projector`]): each lit pixel adds, for
//! every projector whose frustum holds it, the light `I·T(u, v)` through the material's own
//! model — the slide read through the sampling engine with the footprint of the pixel's
//! position carried through the projective divide, and, for a projector that casts, the lit
//! fraction of its depth map.
//!
//! Projectors light per pixel in every shading mode (the divide and the slide are per-pixel
//! quantities): in Phong shading with the pixel's surface after its maps; in Gouraud and
//! flat shading with the interpolated normal or the face's (from the position's
//! derivatives) and the material's own factors.

use glam::Vec3;

use super::draw::{DrawInfo, LightingPath};
use crate::shading::shadow::ShadowMaps;
use crate::shading::{Light, Lighting, Projector, ProjectorView, Surface, Viewer};
use crate::texture::{sample, Sampler};

/// One projector of a frame: the scene's, its sampler with the user's overrides.
pub(super) struct ProjectorRead<'a> {
    pub projector: &'a Projector,
    pub sampler: Sampler,
    /// Its frustum, made once per frame.
    pub view: ProjectorView,
}

/// The frame's projectors and their depth maps.
pub(super) struct Projectors<'a> {
    pub reads: Vec<ProjectorRead<'a>>,
    /// The maps of the projectors that cast (indexed like the scene's projectors).
    pub shadows: Option<&'a ShadowMaps>,
}

impl Projectors<'_> {
    /// The factors `(D, S)` every projector adds at surface `s` of draw `d` (its maps
    /// applied, its normal facing the viewer's side; lit as the draw lights: its model or
    /// its toon ramp), `dp_dx` and `dp_dy` being the position's
    /// derivatives across the pixel.
    #[inline]
    pub fn terms(
        &self,
        d: &DrawInfo,
        s: &Surface,
        dp_dx: Vec3,
        dp_dy: Vec3,
        viewer: Viewer,
    ) -> (Vec3, Vec3) {
        let mut sum = (Vec3::ZERO, Vec3::ZERO);
        // Only the projector's light: no emission, no ambient term.
        let lit = Surface {
            emissive: Vec3::ZERO,
            ..*s
        };
        for (k, r) in self.reads.iter().enumerate() {
            let pr = r.projector;
            let to = pr.position - s.position;
            let d2 = to.length_squared();
            if !(d2 > 0.0) {
                continue;
            }
            let inv_d = d2.sqrt().recip();
            let l = to * inv_d;
            if s.normal.dot(l) <= 0.0 {
                continue;
            }
            let Some(fp) = r.view.footprint(s.position, dp_dx, dp_dy) else {
                continue;
            };
            let texel = sample(&pr.slide.texture, &r.sampler, &fp);
            let mut color = pr.color * texel.truncate();
            if color.max_element() <= 0.0 {
                continue;
            }
            if pr.falloff {
                color *= inv_d * inv_d;
            }
            if let Some(maps) = self.shadows {
                color *= maps.projector_visibility(k, s.position, s.normal, l);
            }
            // The light as it arrives at this point: from `l`, already attenuated (a
            // directional light of that colour is the cheapest form the models take).
            let light = [Light::Directional {
                direction: l,
                color,
            }];
            let lighting = Lighting {
                lights: &light,
                ambient: Vec3::ZERO,
                shadows: None,
            };
            // The draw's own lighting: its model, or its toon ramp.
            let (df, sp) = d.lit_factors(&lit, &lighting, viewer);
            sum.0 += df;
            sum.1 += sp;
        }
        sum
    }
}

impl DrawInfo<'_> {
    /// The draw lit by the frame's projectors too (`on`: the frame has some): its varyings
    /// gain the world position (and in Gouraud shading the normal), and its quads leave the
    /// plain path. Unlit draws are left as they are.
    #[must_use]
    pub fn with_projectors(mut self, on: bool) -> Self {
        if !on || self.path == LightingPath::Unlit {
            return self;
        }
        if self.layout.position.is_none() {
            self.layout.position = Some(self.layout.add());
        }
        if self.path == LightingPath::Interpolated && !self.flat && self.layout.normal.is_none() {
            self.layout.normal = Some(self.layout.add());
        }
        self.plain = false;
        self.projectors = true;
        self
    }
}
