//! A plain metallic-roughness quad lit in lanes ([`DrawInfo::mr_lanes`]): the surface of its
//! four pixels made from the maps one pixel per `Vec4` lane — the tangent-space normal map,
//! occlusion, emission, metallic-roughness and the base colour — then
//! [`metallic_roughness_quad`]. Every step follows the per-pixel path's operations in its
//! order ([`DrawInfo::apply_maps`], [`DrawInfo::tangent_space`]), so the colours are the same
//! bits (tested, and the images are byte-identical).

use glam::Vec4;

use super::draw::DrawInfo;
use super::fragment::SceneShader;
use super::layers::surface_colors;
use super::reads::{QuadReads, Read};
use crate::pipeline::Quad;
use crate::shading::lanes::{normalize_lanes, transpose, QuadFactors};
use crate::shading::mr_lanes::{mr_lanes, opaque_colors, straight_lanes, MrQuad};
use crate::shading::wide::Lane;
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
        let colors = surface_colors(d, quad, reads);
        let inputs = d.mr_inputs(quad, reads, &colors);
        let q = d.mr_surface(&inputs);
        let (df, sp) = mr_lanes(&d.surface, &q, &self.lighting, self.viewer);
        self.mr_colors(d, quad, reads, (&colors, inputs.base_color), (df, sp), out)
    }

    /// [`SceneShader::shade_mr_quad`] for two quads of the draw at once, their pixels in
    /// eight lanes ([`F32x8`](crate::shading::wide::F32x8)): the surface and the model in
    /// half the arithmetic instructions, each pixel's colour the same bits as one quad at a
    /// time gives it (the same operations lane for lane).
    ///
    /// # Safety
    /// The CPU must have x86-64-v3 ([`crate::cpu::level`]).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,movbe")]
    pub(super) unsafe fn shade_mr_pair(
        &self,
        d: &DrawInfo,
        quads: [&Quad; 2],
        reads: [&QuadReads; 2],
        out: [&mut [Vec4; 4]; 2],
    ) -> [u8; 2] {
        use crate::shading::wide::F32x8;
        let colors = [
            surface_colors(d, quads[0], reads[0]),
            surface_colors(d, quads[1], reads[1]),
        ];
        let inputs = d.mr_inputs_pair(quads, reads, &colors);
        let q = d.mr_surface(&inputs);
        let (df, sp) = mr_lanes(&d.surface, &q, &self.lighting, self.viewer);
        let [o0, o1] = out;
        let half = |v: &[F32x8; 3], k: usize| [v[0].quad(k), v[1].quad(k), v[2].quad(k)];
        [
            self.mr_colors(
                d,
                quads[0],
                reads[0],
                (&colors[0], half(&inputs.base_color, 0)),
                (half(&df, 0), half(&sp, 0)),
                o0,
            ),
            self.mr_colors(
                d,
                quads[1],
                reads[1],
                (&colors[1], half(&inputs.base_color, 1)),
                (half(&df, 1), half(&sp, 1)),
                o1,
            ),
        ]
    }

    /// The colours of a batch's quads of a [`DrawInfo::mr_lanes`] draw (`out[i]`, `kept[i]`
    /// for `quads[i]`, read into `reads[i]`), two at a time ([`SceneShader::shade_mr_pair`]),
    /// an odd last one alone.
    ///
    /// # Safety
    /// The CPU must have x86-64-v3 ([`crate::cpu::level`]).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,movbe")]
    pub(super) unsafe fn shade_mr_batch(
        &self,
        d: &DrawInfo,
        quads: &[Quad],
        reads: &[QuadReads],
        out: &mut [[Vec4; 4]],
        kept: &mut [u8],
    ) {
        let mut pairs = out.chunks_exact_mut(2);
        for (i, o) in (&mut pairs).enumerate() {
            let (q, r) = (&quads[2 * i..2 * i + 2], &reads[2 * i..2 * i + 2]);
            let [o0, o1] = o else { unreachable!() };
            // SAFETY: the CPU has x86-64-v3 (this function's contract).
            let k = unsafe { self.shade_mr_pair(d, [&q[0], &q[1]], [&r[0], &r[1]], [o0, o1]) };
            kept[2 * i..2 * i + 2].copy_from_slice(&k);
        }
        if let [o] = pairs.into_remainder() {
            let last = quads.len() - 1;
            kept[last] = self.shade_mr_quad(d, &quads[last], &reads[last], o);
        }
    }

    /// A quad's colours from its factors `(D, S)` in lanes, its premultiplied surface colours
    /// `colors` and their straight lanes `straight` (the model's base colour, made once for
    /// both): the pixels kept (bits).
    #[inline(always)]
    fn mr_colors(
        &self,
        d: &DrawInfo,
        quad: &Quad,
        reads: &QuadReads,
        (colors, straight): (&[Vec4; 4], [Vec4; 3]),
        (df, sp): ([Vec4; 3], [Vec4; 3]),
        out: &mut [Vec4; 4],
    ) -> u8 {
        let alpha_mode = d.material.alpha_mode;
        if alpha_mode == AlphaMode::Opaque && reads.get(Read::Light).is_none() {
            // `combine` in lanes (the model's base colour is the straight colour); every
            // pixel kept.
            let colors = opaque_colors(straight, df, sp);
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

/// What a quad's surface is made from, in lanes, before its normal is made a unit one and
/// tilted: the interpolated varyings and the maps' texels.
#[derive(Clone, Copy)]
struct MrInputs<L> {
    /// The interpolated normal (not yet normalized; zero without one).
    normal: [L; 3],
    position: [L; 3],
    /// The tangent (x, y, z and handedness) and the normal map's texels, for a draw with a
    /// tangent-space normal map.
    tilt: Option<([L; 4], [L; 4])>,
    /// Lanes whose normal is turned round (double-sided back faces).
    back: L,
    occlusion: L,
    emissive: [L; 3],
    roughness: L,
    metallic: L,
    base_color: [L; 3],
}

impl DrawInfo<'_> {
    /// Whether this draw's quads are shaded by [`SceneShader::shade_mr_quad`] (those without
    /// parallax self-shadowing): a plain metallic-roughness draw with no projectors and no
    /// environment map on its per-pixel path. `shade_read` and the batches' pairs both ask.
    #[inline(always)]
    pub(super) fn mr_quads(&self) -> bool {
        use super::draw::LightingPath;
        self.mr_lanes
            && !self.projectors
            && !(self.env.is_some() && self.path == LightingPath::PerPixel)
    }

    /// [`MrInputs`] of one quad of a plain metallic-roughness draw, `colors` the pixels'
    /// premultiplied surface colours: [`DrawInfo::apply_maps`]'s reads in lanes.
    #[inline(always)]
    fn mr_inputs(&self, quad: &Quad, reads: &QuadReads, colors: &[Vec4; 4]) -> MrInputs<Vec4> {
        let s = &self.surface;
        let normal = self
            .layout
            .normal
            .map_or([Vec4::ZERO; 3], |n| n.lanes(quad));
        let position = self
            .layout
            .position
            .map_or([Vec4::ZERO; 3], |p| p.lanes(quad));
        let tilt = match (
            reads.get(Read::Normals),
            &self.normal_map,
            self.layout.tangent,
        ) {
            (Some(texels), Some(_), Some(tangent)) => {
                Some((tangent.lanes(quad), transpose(*texels)))
            }
            _ => None,
        };
        let mut occlusion = Vec4::splat(s.occlusion);
        if let (Some(texels), Some(map)) = (reads.get(Read::Occlusion), &self.occlusion_map) {
            // 1 + strength·(R − 1).
            let r = transpose(*texels)[0];
            occlusion = Vec4::ONE + Vec4::splat(map.scale) * (r - Vec4::ONE);
        }
        let e = s.emissive;
        let mut emissive = [Vec4::splat(e.x), Vec4::splat(e.y), Vec4::splat(e.z)];
        if let Some(texels) = reads.get(Read::Emission) {
            let t = transpose(*texels);
            emissive = [emissive[0] * t[0], emissive[1] * t[1], emissive[2] * t[2]];
        }
        let (mut roughness, mut metallic) = (Vec4::splat(s.roughness), Vec4::splat(s.metallic));
        if let Some(texels) = reads.get(Read::MetalRough) {
            let t = transpose(*texels);
            roughness *= t[1];
            metallic *= t[2];
        }
        let back = self.material.double_sided && !quad.front_facing;
        MrInputs {
            normal,
            position,
            tilt,
            back: Vec4::splat(if back { 1.0 } else { 0.0 }),
            occlusion,
            emissive,
            roughness,
            metallic,
            base_color: straight_lanes(colors),
        }
    }

    /// [`DrawInfo::mr_inputs`] of two quads of the draw in eight lanes (quad `k` in lanes
    /// `4k..4k + 4`), `colors` their pixels' premultiplied surface colours: each texel read
    /// made lanes by one transpose of both quads' texels, each value by the operations one
    /// quad's lanes take (the same bits). The two quads are one draw's, so they have the
    /// same reads.
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    fn mr_inputs_pair(
        &self,
        quads: [&Quad; 2],
        reads: [&QuadReads; 2],
        colors: &[[Vec4; 4]; 2],
    ) -> MrInputs<crate::shading::wide::F32x8> {
        use crate::shading::wide::F32x8;
        let s = &self.surface;
        let splat = F32x8::splat;
        let (zero, one) = (splat(0.0), splat(1.0));
        let normal = self
            .layout
            .normal
            .map_or([zero; 3], |n| join3(n.lanes(quads[0]), n.lanes(quads[1])));
        let position = self
            .layout
            .position
            .map_or([zero; 3], |p| join3(p.lanes(quads[0]), p.lanes(quads[1])));
        let tilt = match (
            texels_pair(reads, Read::Normals),
            &self.normal_map,
            self.layout.tangent,
        ) {
            (Some(texels), Some(_), Some(t)) => {
                let (t0, t1) = (t.lanes(quads[0]), t.lanes(quads[1]));
                let tangent = [
                    F32x8::join(t0[0], t1[0]),
                    F32x8::join(t0[1], t1[1]),
                    F32x8::join(t0[2], t1[2]),
                    F32x8::join(t0[3], t1[3]),
                ];
                Some((tangent, texels))
            }
            _ => None,
        };
        let mut occlusion = splat(s.occlusion);
        if let (Some(t), Some(map)) = (texels_pair(reads, Read::Occlusion), &self.occlusion_map) {
            // 1 + strength·(R − 1).
            occlusion = one + splat(map.scale) * (t[0] - one);
        }
        let e = s.emissive;
        let mut emissive = [splat(e.x), splat(e.y), splat(e.z)];
        if let Some(t) = texels_pair(reads, Read::Emission) {
            emissive = [emissive[0] * t[0], emissive[1] * t[1], emissive[2] * t[2]];
        }
        let (mut roughness, mut metallic) = (splat(s.roughness), splat(s.metallic));
        if let Some(t) = texels_pair(reads, Read::MetalRough) {
            roughness = roughness * t[1];
            metallic = metallic * t[2];
        }
        let back = |q: &Quad| {
            let back = self.material.double_sided && !q.front_facing;
            Vec4::splat(if back { 1.0 } else { 0.0 })
        };
        // Straight colours (`straight_lanes`): divided by alpha where it is above 0 and
        // not 1.
        let [r, g, b, a] = F32x8::transpose(&colors[0], &colors[1]);
        let divide = a.cmpgt(zero) & a.cmpne(one);
        let base_color = if F32x8::bitmask(divide) != 0 {
            [
                F32x8::select(divide, r / a, r),
                F32x8::select(divide, g / a, g),
                F32x8::select(divide, b / a, b),
            ]
        } else {
            [r, g, b]
        };
        MrInputs {
            normal,
            position,
            tilt,
            back: F32x8::join(back(quads[0]), back(quads[1])),
            occlusion,
            emissive,
            roughness,
            metallic,
            base_color,
        }
    }

    /// The surface of a quad's pixels (two quads' in eight lanes) in lanes:
    /// [`DrawInfo::apply_maps`] for a plain metallic-roughness draw — the interpolated
    /// normal made a unit one, tilted by the normal map, turned round on back faces.
    #[inline(always)]
    fn mr_surface<L: Lane>(&self, q: &MrInputs<L>) -> MrQuad<L> {
        // A draw without normals has zero ones, which stay zero.
        let mut n = normalize_lanes(q.normal);
        if let (Some((tangent, texels)), Some(map)) = (&q.tilt, &self.normal_map) {
            n = tangent_space(n, *tangent, texels, map.scale);
        }
        // Double-sided back faces are lit from their side, after the tilt.
        let back = q.back.cmpne(L::splat(0.0));
        n = [
            L::select(back, -n[0], n[0]),
            L::select(back, -n[1], n[1]),
            L::select(back, -n[2], n[2]),
        ];
        MrQuad {
            position: q.position,
            normal: n,
            base_color: q.base_color,
            metallic: q.metallic,
            roughness: q.roughness,
            occlusion: q.occlusion,
            emissive: q.emissive,
        }
    }
}

/// [`DrawInfo::tangent_space`] in lanes: unit normals `n` tilted by the normal map's texels
/// (`texel` as x, y, z lanes) in the frame of the tangents `tangent` (x, y, z and the
/// handedness w); a lane keeps its normal where the tangent or the result is zero.
#[inline(always)]
fn tangent_space<L: Lane>(n: [L; 3], tangent: [L; 4], texel: &[L; 4], scale: f32) -> [L; 3] {
    let [nx, ny, nz] = n;
    let [tx, ty, tz, w] = tangent;
    // T made orthogonal to N, B = (N × T)·sign(w).
    let k = nx * tx + ny * ty + nz * tz;
    let [tx, ty, tz] = normalize_lanes([tx - nx * k, ty - ny * k, tz - nz * k]);
    let sign = w.signum();
    let (bx, by, bz) = (
        (ny * tz - ty * nz) * sign,
        (nz * tx - tz * nx) * sign,
        (nx * ty - tx * ny) * sign,
    );
    let (one, two, scale) = (L::splat(1.0), L::splat(2.0), L::splat(scale));
    let sx = (texel[0] * two - one) * scale;
    let sy = (texel[1] * two - one) * scale;
    let sz = texel[2] * two - one;
    let [mx, my, mz] = normalize_lanes([
        tx * sx + bx * sy + nx * sz,
        ty * sx + by * sy + ny * sz,
        tz * sx + bz * sy + nz * sz,
    ]);
    let zero = L::splat(0.0);
    let nonzero = |[x, y, z]: [L; 3]| x.cmpne(zero) | y.cmpne(zero) | z.cmpne(zero);
    let ok = nonzero([mx, my, mz]) & nonzero([tx, ty, tz]);
    [
        L::select(ok, mx, nx),
        L::select(ok, my, ny),
        L::select(ok, mz, nz),
    ]
}

/// Two quads' lanes of three values in eight lanes, quad `a` in the low four.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn join3(a: [Vec4; 3], b: [Vec4; 3]) -> [crate::shading::wide::F32x8; 3] {
    use crate::shading::wide::F32x8;
    [
        F32x8::join(a[0], b[0]),
        F32x8::join(a[1], b[1]),
        F32x8::join(a[2], b[2]),
    ]
}

/// Read `r`'s texels of two quads as lanes (value `c` of each pixel, quad 0 in the low
/// four), if made (for both: the quads are one draw's, which makes the same reads).
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn texels_pair(reads: [&QuadReads; 2], r: Read) -> Option<[crate::shading::wide::F32x8; 4]> {
    match (reads[0].get(r), reads[1].get(r)) {
        (Some(a), Some(b)) => Some(crate::shading::wide::F32x8::transpose(a, b)),
        (a, b) => {
            debug_assert!(
                a.is_none() && b.is_none(),
                "one draw's quads make the same reads"
            );
            None
        }
    }
}
