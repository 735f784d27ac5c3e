//! Procedural colour sources of the fragment stage, evaluated at the object-space point: solid
//! textures (box-filtered over the pixel's footprint), images through a generated projection
//! (analytic derivatives, no seam) and 3D textures over an object-space box.

use glam::Vec4;

use super::draw::DrawInfo;
use crate::pipeline::Quad;
use crate::shading::Procedural;
use crate::texture::{sample, sample_3d, Footprint, Footprint3};

impl DrawInfo<'_> {
    /// The procedural colour of pixel `j` of a quad (white when the draw has none, or lacks
    /// the object point).
    pub(super) fn procedural_color(&self, proc: &Procedural, quad: &Quad, j: usize) -> Vec4 {
        let Some(pos) = self.layout.object_position else {
            return Vec4::ONE;
        };
        match proc {
            Procedural::Solid {
                solid,
                colors,
                antialias,
            } => {
                let (p, extent) = self.object_point(quad, j, *antialias);
                solid.color(p, extent, *colors).extend(1.0)
            }
            // The slot's image, sampler and affine transform, resolved once per draw.
            Procedural::Projected { .. } => {
                let (Some(map), Some(projection), Some(normal)) =
                    (&self.projected, &self.projection, self.layout.object_normal)
                else {
                    return Vec4::ONE;
                };
                let fp = projection.map_footprint(
                    pos.pixel3(quad, j),
                    pos.ddx3(quad),
                    pos.ddy3(quad),
                    normal.pixel3(quad, j),
                );
                let fp = Footprint::new(
                    map.linear * fp.uv + map.offset,
                    map.linear * fp.duv_dx,
                    map.linear * fp.duv_dy,
                );
                sample(map.tex, &map.sampler, &fp)
            }
            Procedural::Texture3D {
                texture,
                sampler,
                min,
                max,
                colors,
            } => {
                let inv = (*max - *min).recip();
                let fp = Footprint3 {
                    uvw: (pos.pixel3(quad, j) - *min) * inv,
                    duvw_dx: pos.ddx3(quad) * inv,
                    duvw_dy: pos.ddy3(quad) * inv,
                };
                let sampler = self.sampler_3d.as_ref().unwrap_or(sampler);
                let value = sample_3d(texture, sampler, &fp).x.clamp(0.0, 1.0);
                colors[0].lerp(colors[1], value).extend(1.0)
            }
        }
    }
}
