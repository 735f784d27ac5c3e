//! A plain metallic-roughness quad lit in lanes ([`DrawInfo::mr_lanes`]): the surface of its
//! four pixels made from the maps one pixel per `Vec4` lane — the tangent-space normal map,
//! occlusion, emission, metallic-roughness and the base colour — then
//! [`metallic_roughness_quad`]. Every step follows the per-pixel path's operations in its
//! order ([`DrawInfo::apply_maps`], [`DrawInfo::tangent_space`]), so the colours are the same
//! bits (tested, and the images are byte-identical).

use glam::Vec4;

use super::draw::DrawInfo;
use super::fragment::SceneShader;
use super::layers::surface_color;
use super::maps::QuadReads;
use crate::pipeline::Quad;
use crate::shading::lanes::{normalize_or_zero, transpose, Lanes3, QuadFactors};
use crate::shading::mr_lanes::{metallic_roughness_lanes, opaque_colors, straight_lanes, MrQuad};
use crate::shading::{combine, AlphaMode};

impl SceneShader<'_> {
    /// The colours of one quad of a [`DrawInfo::mr_lanes`] draw (no projectors, no parallax
    /// self-shadowing), its texture reads made.
    pub(super) fn shade_mr_quad(
        &self,
        d: &DrawInfo,
        quad: &Quad,
        reads: &QuadReads,
        out: &mut [Vec4; 4],
    ) -> u8 {
        let color = |j: usize| surface_color(d, quad, reads, j);
        let colors = [color(0), color(1), color(2), color(3)];
        let q = d.mr_surface(quad, reads, &colors);
        let (df, sp) = metallic_roughness_lanes(&d.surface, &q, &self.lighting, self.viewer);
        let alpha_mode = d.material.alpha_mode;
        if alpha_mode == AlphaMode::Opaque && reads.light.is_none() {
            // `combine` in lanes (the model's base colour is the straight colour); every
            // pixel kept.
            let colors = opaque_colors(q.base_color, df, sp);
            for (j, (o, c)) in out.iter_mut().zip(colors).enumerate() {
                if quad.mask & (1 << j) != 0 {
                    *o = c;
                }
            }
            return quad.mask;
        }
        let f = QuadFactors::from_lanes(df, sp);
        let mut kept = quad.mask;
        for j in 0..4 {
            if quad.mask & (1 << j) == 0 {
                continue;
            }
            let mut df = f.d[j].truncate();
            if let Some(l) = d.light_factor(reads, j) {
                df *= l;
            }
            match combine(alpha_mode, colors[j], df, f.s[j].truncate()) {
                Some(color) => out[j] = color,
                None => kept &= !(1 << j),
            }
        }
        kept
    }
}

impl DrawInfo<'_> {
    /// The surface of a quad's four pixels in lanes: [`DrawInfo::apply_maps`] for a plain
    /// metallic-roughness draw, `colors` the pixels' premultiplied surface colours.
    #[inline(always)]
    fn mr_surface(&self, quad: &Quad, reads: &QuadReads, colors: &[Vec4; 4]) -> MrQuad {
        let s = &self.surface;
        let maps = reads.maps.as_ref();
        let mut n = self
            .layout
            .normal
            .map_or([Vec4::ZERO; 3], |n| normalize_or_zero(n.lanes(quad)));
        let position = self
            .layout
            .position
            .map_or([Vec4::ZERO; 3], |p| p.lanes(quad));
        if let (Some(texels), Some(map), Some(tangent)) = (
            maps.and_then(|m| m.normals.as_ref()),
            &self.normal_map,
            self.layout.tangent,
        ) {
            n = tangent_space(n, tangent.lanes(quad), &transpose(*texels), map.scale);
        }
        let mut occlusion = Vec4::splat(s.occlusion);
        if let (Some(texels), Some(map)) =
            (maps.and_then(|m| m.occlusion.as_ref()), &self.occlusion_map)
        {
            // 1 + strength·(R − 1).
            let r = transpose(*texels)[0];
            occlusion = Vec4::ONE + Vec4::splat(map.scale) * (r - Vec4::ONE);
        }
        let e = s.emissive;
        let mut emissive: Lanes3 = [Vec4::splat(e.x), Vec4::splat(e.y), Vec4::splat(e.z)];
        if let Some(texels) = maps.and_then(|m| m.emission.as_ref()) {
            let t = transpose(*texels);
            emissive = [emissive[0] * t[0], emissive[1] * t[1], emissive[2] * t[2]];
        }
        let (mut roughness, mut metallic) = (Vec4::splat(s.roughness), Vec4::splat(s.metallic));
        if let Some(texels) = maps.and_then(|m| m.metal_rough.as_ref()) {
            let t = transpose(*texels);
            roughness *= t[1];
            metallic *= t[2];
        }
        let base_color = straight_lanes(colors);
        // Double-sided back faces are lit from their side, after the tilt.
        if self.material.double_sided && !quad.front_facing {
            n = n.map(|c| -c);
        }
        MrQuad {
            position,
            normal: n,
            base_color,
            metallic,
            roughness,
            occlusion,
            emissive,
        }
    }
}

/// [`DrawInfo::tangent_space`] in lanes: unit normals `n` tilted by the normal map's texels
/// (`texel` as x, y, z lanes) in the frame of the tangents `tangent` (x, y, z and the
/// handedness w); a lane keeps its normal where the tangent or the result is zero.
#[inline(always)]
fn tangent_space(n: Lanes3, tangent: [Vec4; 4], texel: &[Vec4; 4], scale: f32) -> Lanes3 {
    let [nx, ny, nz] = n;
    let [tx, ty, tz, w] = tangent;
    // T made orthogonal to N, B = (N × T)·sign(w).
    let k = nx * tx + ny * ty + nz * tz;
    let [tx, ty, tz] = normalize_or_zero([tx - nx * k, ty - ny * k, tz - nz * k]);
    let sign = w.signum();
    let (bx, by, bz) = (
        (ny * tz - ty * nz) * sign,
        (nz * tx - tz * nx) * sign,
        (nx * ty - tx * ny) * sign,
    );
    let two = Vec4::splat(2.0);
    let sx = (texel[0] * two - Vec4::ONE) * scale;
    let sy = (texel[1] * two - Vec4::ONE) * scale;
    let sz = texel[2] * two - Vec4::ONE;
    let [mx, my, mz] = normalize_or_zero([
        tx * sx + bx * sy + nx * sz,
        ty * sx + by * sy + ny * sz,
        tz * sx + bz * sy + nz * sz,
    ]);
    let zero = Vec4::ZERO;
    let nonzero = |[x, y, z]: Lanes3| x.cmpne(zero) | y.cmpne(zero) | z.cmpne(zero);
    let ok = nonzero([mx, my, mz]) & nonzero([tx, ty, tz]);
    [
        Vec4::select(ok, mx, nx),
        Vec4::select(ok, my, ny),
        Vec4::select(ok, mz, nz),
    ]
}
