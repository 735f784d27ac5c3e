//! A pixel's [`Surface`] from its draw's maps: the normal map and bumps tilt the normal,
//! occlusion, emission, metallic-roughness, the OBJ colour maps and solid textures set the
//! parameters the illumination models read.

use glam::{DVec3, Vec3, Vec4};

use super::draw::DrawInfo;
use super::reads::{QuadReads, Read};
use crate::pipeline::Quad;
use crate::shading::{bump, shininess_from_roughness, ShadingModel, Surface};

impl DrawInfo<'_> {
    /// Pixel `j`'s surface parameters from its maps: the normal map and bumps tilt the normal
    /// (world space, before any back-face flip), occlusion, emission, metallic-roughness and
    /// solid textures set the parameters, and metallic-roughness materials take the colour `c`.
    pub(super) fn apply_maps(
        &self,
        reads: &QuadReads,
        quad: &Quad,
        j: usize,
        c: Vec4,
        s: &mut Surface,
    ) {
        // Before the base's normal map: the coat's normal is the geometric one's.
        if reads.lobe_maps() {
            self.apply_lobe_maps(reads, quad, j, s);
        } else if s.lobes.clearcoat > 0.0 {
            s.clearcoat_normal = s.normal;
        }
        s.normal = self.mapped_normal(reads, quad, j, s.normal);
        if self.solid_roughness.is_some() || self.solid_bump.is_some() {
            self.solid_channels(quad, j, s);
        }
        if let (Some(texel), Some(map)) = (reads.get(Read::Occlusion), &self.occlusion_map) {
            // 1 + strength·(R − 1).
            s.occlusion = 1.0 + map.scale * (texel[j].x - 1.0);
        }
        if let Some(texel) = reads.get(Read::Emission) {
            s.emissive *= texel[j].truncate();
        }
        if let Some(texel) = reads.get(Read::MetalRough) {
            s.roughness *= texel[j].y;
            s.metallic *= texel[j].z;
        }
        if let Some(texel) = reads.get(Read::Ambient) {
            s.ambient_color = Some(straight(texel[j]));
        }
        if let Some(texel) = reads.get(Read::Specular) {
            s.specular_color = straight(texel[j]);
        }
        if let Some(texel) = reads.get(Read::Shininess) {
            // MTL: the map's value multiplies Ns (at least 1, so the lobe stays finite).
            s.shininess = (s.shininess * texel[j].x).max(1.0);
        }
        if self.model == ShadingModel::MetallicRoughness {
            s.base_color = straight(c);
        }
    }

    /// Pixel `j`'s normal `n` tilted by its draw's normal map, object-space normal map and
    /// bump maps (the solid bump is [`DrawInfo::apply_maps`]'s): all a helper pixel of a
    /// quad needs for its reflected direction.
    #[inline(always)]
    pub(super) fn mapped_normal(&self, reads: &QuadReads, quad: &Quad, j: usize, n: Vec3) -> Vec3 {
        let mut n = n;
        if let (Some(texel), Some(map)) = (reads.get(Read::Normals), &self.normal_map) {
            if let Some(mapped) = self.tangent_space(quad, j, n, texel[j], map.scale) {
                n = mapped;
            }
        }
        if let Some(texel) = reads.get(Read::ObjectNormals) {
            // Object space → world: the normal matrix; the vertex normal is replaced.
            let object = texel[j].truncate() * 2.0 - Vec3::ONE;
            if let Some(mapped) = (self.normal_from_object * object).try_normalize() {
                n = mapped;
            }
        }
        if let (Some(slopes), Some(p)) = (&reads.bumps, self.layout.position) {
            n = bump::tilt_screen_space(n, p.ddx3(quad), p.ddy3(quad), slopes[j]);
        }
        n
    }

    /// The world normal a tangent-space normal-map texel gives about unit normal `n` at pixel
    /// `j` (T, B = (N × T)·w, N; the map's x and y times `scale`); `None` without tangents.
    #[inline]
    fn tangent_space(
        &self,
        quad: &Quad,
        j: usize,
        n: Vec3,
        texel: Vec4,
        scale: f32,
    ) -> Option<Vec3> {
        let [tx, ty, tz, w] = self.layout.tangent?.pixel(quad, j);
        let t = Vec3::new(tx, ty, tz);
        let t = (t - n * n.dot(t)).normalize_or_zero();
        let b = n.cross(t) * w.signum();
        let ts = texel.truncate() * 2.0 - Vec3::ONE;
        let ts = Vec3::new(ts.x * scale, ts.y * scale, ts.z);
        let mapped = (t * ts.x + b * ts.y + n * ts.z).normalize_or_zero();
        (mapped != Vec3::ZERO && t != Vec3::ZERO).then_some(mapped)
    }

    /// glTF's extension maps at pixel `j` ([`crate::shading::lobes`]): each multiplies its
    /// factor; the clearcoat normal is the geometric normal, tilted by its own map.
    fn apply_lobe_maps(&self, reads: &QuadReads, quad: &Quad, j: usize, s: &mut Surface) {
        let l = &mut s.lobes;
        let t = |r: Read| reads.get(r).map(|t| t[j]);
        if let Some(t) = t(Read::SpecularWeight) {
            l.specular *= t.w;
        }
        if let Some(t) = t(Read::SpecularColor) {
            l.specular_color *= t.truncate();
        }
        if let Some(t) = t(Read::Clearcoat) {
            l.clearcoat *= t.x;
        }
        if let Some(t) = t(Read::ClearcoatRoughness) {
            l.clearcoat_roughness *= t.y;
        }
        if let Some(t) = t(Read::SheenColor) {
            l.sheen_color *= t.truncate();
        }
        if let Some(t) = t(Read::SheenRoughness) {
            l.sheen_roughness *= t.w;
        }
        if let Some(t) = t(Read::Thickness) {
            l.thickness *= t.y;
        }
        if l.clearcoat > 0.0 {
            s.clearcoat_normal = s.normal;
            if let (Some(t), Some(map)) =
                (t(Read::ClearcoatNormal), &self.lobe_maps.clearcoat_normal)
            {
                if let Some(mapped) = self.tangent_space(quad, j, s.normal, t, map.scale) {
                    s.clearcoat_normal = mapped;
                }
            }
        }
    }

    /// Solid textures on the roughness and bump channels at pixel `j`: the roughness (or, for
    /// Phong materials, the exponent it stands for) and the bump's tilt of the normal, into `s`.
    fn solid_channels(&self, quad: &Quad, j: usize, s: &mut Surface) {
        if let Some(r) = &self.solid_roughness {
            let (p, extent) = self.object_point(quad, j, r.map.antialias);
            let value = r.map.solid.value(p, extent) as f32;
            let roughness = r.range[0] + (r.range[1] - r.range[0]) * value;
            match self.model {
                ShadingModel::MetallicRoughness => s.roughness = roughness,
                ShadingModel::Phong => s.shininess = shininess_from_roughness(roughness),
            }
        }
        if let Some(b) = &self.solid_bump {
            let (p, extent) = self.object_point(quad, j, b.map.antialias);
            let (_, gradient) = b.map.solid.value_and_gradient(p, extent);
            let grad = b.world_from_gradient * gradient.as_vec3();
            s.normal = bump::tilt_by_gradient(s.normal, grad);
        }
    }

    /// The object-space position of pixel `j` and, when `antialias`, the footprint extent
    /// |∂P/∂x| + |∂P/∂y| of the quad (zero otherwise); the origin for draws that do not carry
    /// the object point.
    #[inline]
    pub(super) fn object_point(&self, quad: &Quad, j: usize, antialias: bool) -> (DVec3, DVec3) {
        let Some(slot) = self.layout.object_position else {
            return (DVec3::ZERO, DVec3::ZERO);
        };
        let p = slot.pixel3(quad, j);
        let extent = if antialias {
            (slot.ddx3(quad).abs() + slot.ddy3(quad).abs()).as_dvec3()
        } else {
            DVec3::ZERO
        };
        (p.as_dvec3(), extent)
    }
}

/// The straight-alpha colour of premultiplied `c`.
#[inline]
pub(super) fn straight(c: Vec4) -> Vec3 {
    if c.w > 0.0 && c.w != 1.0 {
        c.truncate() / c.w
    } else {
        c.truncate()
    }
}
