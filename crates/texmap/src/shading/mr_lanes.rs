//! [`metallic_roughness`](super::pbr::metallic_roughness) for the four pixels of a 2×2 quad
//! at once, one pixel per `Vec4` lane, under every kind of light: the plain metallic-roughness
//! material (no clearcoat or sheen; those keep the per-pixel rule).
//!
//! As in [`super::lanes`], every lane follows the per-pixel rule's operations in its order
//! (the lobe's F0, F90 and α, the albedo table's lookup, each light's half vector, Fresnel,
//! GGX and Smith terms), so the factors equal the per-pixel rule's bit for bit (tested); only
//! NaN inputs could tell them apart. The albedo table is read per lane (`AlbedoLanes`: in
//! eight lanes, each lane's rows loaded whole and transposed).

use std::f32::consts::PI;

use glam::{Vec2, Vec4};

use super::albedo::{albedo_table, ALBEDO_N};
use super::lanes::{incidence, normalize_lanes, sqrt4, transpose, Lanes3, QuadFactors};
use super::pbr::MIN_ROUGHNESS;
use super::wide::Lane;
use super::{Lighting, Surface, Viewer};

/// What the metallic-roughness model reads at a quad's four pixels (one pixel per lane; in
/// eight lanes, two quads' pixels): the surface after its maps.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MrQuad<L = Vec4> {
    /// World positions.
    pub position: [L; 3],
    /// Unit normals (after the normal map; towards the viewer on double-sided back faces).
    pub normal: [L; 3],
    /// Straight-alpha base colours (the f0 of metals).
    pub base_color: [L; 3],
    pub metallic: L,
    pub roughness: L,
    /// Ambient occlusion (1 = none).
    pub occlusion: L,
    /// I_E.
    pub emissive: [L; 3],
}

/// The factors `(D, S)` of the metallic-roughness model at four pixels `q` seen by `viewer`
/// (`I = C·D + S`, one vector per pixel, fourth components 0), ambient term and emission
/// included: [`metallic_roughness`](super::pbr::metallic_roughness) per lane. `s` is the
/// draw's surface: its `ambient`, `ior` and `lobes` are read (the lobes not layered: a coat
/// or a sheen takes the per-pixel rule), not its position, normal or maps' parameters.
#[inline(always)]
#[must_use]
pub fn metallic_roughness_quad(
    s: &Surface,
    q: &MrQuad,
    lighting: &Lighting,
    viewer: Viewer,
) -> QuadFactors {
    let (d, sp) = metallic_roughness_lanes(s, q, lighting, viewer);
    QuadFactors::from_lanes(d, sp)
}

/// [`metallic_roughness_quad`]'s factors `(D, S)` as lanes (R, G and B, one pixel per lane).
#[inline(always)]
#[must_use]
pub fn metallic_roughness_lanes(
    s: &Surface,
    q: &MrQuad,
    lighting: &Lighting,
    viewer: Viewer,
) -> (Lanes3, Lanes3) {
    mr_lanes(s, q, lighting, viewer)
}

/// [`metallic_roughness_lanes`] on any lane type: on [`F32x8`](super::wide::F32x8), two
/// quads at once, each lane the value `Vec4` lanes give it (the same operations).
#[inline(always)]
#[must_use]
pub(crate) fn mr_lanes<L: AlbedoLanes>(
    s: &Surface,
    q: &MrQuad<L>,
    lighting: &Lighting,
    viewer: Viewer,
) -> ([L; 3], [L; 3]) {
    debug_assert!(!s.lobes.layered());
    let (one, zero) = (L::splat(1.0), L::splat(0.0));
    let splat = L::splat;
    // The lobe (`MrLobe::new`): F0 and F90 with the metal's base colour blended in, α, V, N·V.
    let metallic = q.metallic.max(zero).min(one);
    let (f0_d, f90_d) = s.lobes.dielectric(super::ibl::dielectric_f0(s.ior));
    let p = q.position;
    let [nx, ny, nz] = q.normal;
    let [vx, vy, vz] = match viewer {
        Viewer::Point(eye) => {
            let [px, py, pz] = p;
            normalize_lanes([splat(eye.x) - px, splat(eye.y) - py, splat(eye.z) - pz])
        }
        Viewer::Direction(v) => [splat(v.x), splat(v.y), splat(v.z)],
    };
    let keep = one - metallic;
    // (Arrays written out: `array::from_fn`'s and `array::map`'s closures were left as
    // calls, and on `F32x8` their vector operations too.)
    let b = &q.base_color;
    let f0 = [
        splat(f0_d[0]) * keep + b[0] * metallic,
        splat(f0_d[1]) * keep + b[1] * metallic,
        splat(f0_d[2]) * keep + b[2] * metallic,
    ];

    let f90 = splat(f90_d) + splat(1.0 - f90_d) * metallic;
    let r = q.roughness;
    let r = L::select(
        r.is_finite_mask(),
        r.max(splat(MIN_ROUGHNESS)).min(one),
        one,
    );
    let a = r * r;
    let n_dot_v = (nx * vx + ny * vy + nz * vz).max(splat(1e-4));

    // The ambient term: K_A·I_AL·O·(c_diff·(1 − E) + E), E the lobe's albedo.
    let k = splat(s.ambient) * q.occlusion;
    let ia = lighting.ambient;
    let ambient = [splat(ia.x) * k, splat(ia.y) * k, splat(ia.z) * k];
    let mut d = [zero; 3];
    let mut sp = q.emissive;
    let lit = L::bitmask(ambient[0].cmpne(zero) | ambient[1].cmpne(zero) | ambient[2].cmpne(zero));
    if lit != 0 {
        // The albedo table read in lanes (its texels gathered per lane).
        let (ea, eb) = L::specular_albedo(n_dot_v, a.sqrt());
        let eb = eb * f90;
        let mask = L::mask_from_bits(lit);
        for c in 0..3 {
            let e = f0[c] * ea + eb;
            d[c] = L::select(mask, ambient[c] * keep * (one - e), zero);
            sp[c] = L::select(mask, sp[c] + ambient[c] * e, sp[c]);
        }
    }

    // Every light's diffuse and specular terms (`pbr::lights`).
    let a2 = a * a;
    let (one_minus_a2, nv_term) = (one - a2, n_dot_v * n_dot_v);
    for (i, light) in lighting.lights.iter().enumerate() {
        let Some(inc) = incidence(light, p) else {
            continue;
        };
        let [lx, ly, lz] = inc.l;
        let n_dot_l = nx * lx + ny * ly + nz * lz;
        let on = inc.reaches & L::bitmask(n_dot_l.cmpgt(zero));
        if on == 0 {
            continue;
        }
        let mask = L::mask_from_bits(on);
        let mut intensity = inc.intensity;
        if let Some(maps) = lighting.shadows {
            // The shadow maps' lookups quad by quad.
            let quad = |v: &[L; 3], k: usize| [v[0].quad(k), v[1].quad(k), v[2].quad(k)];
            let v = L::from_quads(|k| {
                let facing = on >> (4 * k) & 0b1111;
                maps.visibility_quad(i, quad(&p, k), quad(&q.normal, k), quad(&inc.l, k), facing)
            });
            intensity = [intensity[0] * v, intensity[1] * v, intensity[2] * v];
        }
        let [hx, hy, hz] = normalize_lanes([lx + vx, ly + vy, lz + vz]);
        // Schlick with F90: f0 + (f90 − f0)(1 − V·H)⁵.
        let m = (one - (vx * hx + vy * hy + vz * hz)).max(zero).min(one);
        let m2 = m * m;
        let m5 = m2 * m2 * m;
        let n_dot_h = (nx * hx + ny * hy + nz * hz).max(zero);
        // GGX D and the height-correlated Smith visibility.
        let t = n_dot_h * n_dot_h * (a2 - one) + one;
        let distribution = a2 / (splat(PI) * t * t);
        let gv = n_dot_l * (nv_term * one_minus_a2 + a2).sqrt();
        let gl = n_dot_v * (n_dot_l * n_dot_l * one_minus_a2 + a2).sqrt();
        let sum = gv + gl;
        let visibility = L::select(sum.cmpgt(zero), splat(0.5) / sum, zero);
        let spec = splat(PI) * distribution * visibility * n_dot_l;
        let kd = keep * n_dot_l;
        for c in 0..3 {
            let f = f0[c] + (f90 - f0[c]) * m5;
            d[c] = L::select(mask, d[c] + intensity[c] * (one - f) * kd, d[c]);
            sp[c] = L::select(mask, sp[c] + intensity[c] * f * spec, sp[c]);
        }
    }
    (d, sp)
}

/// Four pixels' premultiplied colours as straight-alpha lanes (R, G and B): each divided by
/// its alpha where that is above 0 and not 1, as [`combine`](super::combine) divides it (the
/// same bits). A quad with no such pixel (an opaque one) makes no division.
#[inline(always)]
#[must_use]
pub fn straight_lanes(colors: &[Vec4; 4]) -> Lanes3 {
    let [r, g, b, a] = transpose(*colors);
    let divide = a.cmpgt(Vec4::ZERO) & a.cmpne(Vec4::ONE);
    if divide.any() {
        [r, g, b].map(|c| Vec4::select(divide, c / a, c))
    } else {
        [r, g, b]
    }
}

/// [`combine`](super::combine) of four opaque pixels in lanes: straight colours `straight`
/// ([`straight_lanes`]) times `D` plus `S`, alpha 1, one colour per pixel (the same bits).
#[inline(always)]
#[must_use]
pub fn opaque_colors(straight: Lanes3, d: Lanes3, s: Lanes3) -> [Vec4; 4] {
    let c = |k: usize| straight[k] * d[k] + s[k];
    transpose([c(0), c(1), c(2), Vec4::ONE])
}

/// A lane type the albedo table is read in: [`specular_albedo`](super::pbr::specular_albedo)
/// lane by lane, as `(A, B)`, the same bits in every lane type.
pub(crate) trait AlbedoLanes: Lane {
    fn specular_albedo(n_dot_v: Self, roughness: Self) -> (Self, Self);
}

impl AlbedoLanes for Vec4 {
    #[inline(always)]
    fn specular_albedo(n_dot_v: Vec4, roughness: Vec4) -> (Vec4, Vec4) {
        specular_albedo_quad(n_dot_v, roughness)
    }
}

#[cfg(target_arch = "x86_64")]
impl AlbedoLanes for super::wide::F32x8 {
    /// [`specular_albedo_quad`] in eight lanes: the same cells, weights and blends; each
    /// lane's two rows of two texels loaded whole, lanes `l` and `l + 4` in one vector, and
    /// the four vectors of each row transposed in 256-bit shuffles; no bounds checks (the
    /// clamped cells are inside the table). It was two quads' rows assembled from scalar
    /// loads, bounds-checked, transposed quad by quad: 195 instructions a pair of quads.
    /// (AVX2 gathers, eight a pair, made it 65 instructions and the pair slower on this
    /// host's AMD EPYC: 31–40 against 24–26 ns for eight lanes.)
    #[inline(always)]
    fn specular_albedo(n_dot_v: Self, roughness: Self) -> (Self, Self) {
        use super::wide::F32x8;
        use std::arch::x86_64::{
            _mm256_add_epi32, _mm256_cvtepi32_ps, _mm256_cvttps_epi32, _mm256_slli_epi32,
            _mm256_storeu_si256,
        };
        const N: usize = ALBEDO_N;
        let table = albedo_table();
        assert_eq!(table.len(), N * N);
        let (zero, one) = (F32x8::splat(0.0), F32x8::splat(1.0));
        let last = F32x8::splat((N - 1) as f32);
        let x = n_dot_v.max(zero).min(one).sqrt() * last;
        let y = roughness.max(zero).min(one) * last;
        let top = F32x8::splat((N - 2) as f32);
        // SAFETY: AVX2 is available where `F32x8` is used (its module's rule). Each cell's
        // ⌊x⌋ and ⌊y⌋ are at most N − 2 (clamped first; a NaN lane is 0, as `max` makes it),
        // so its rows, two cells from `j·N + i` and from `(j + 1)·N + i`, are inside the N²
        // cells (`table`, checked above), each cell's `(A, B)` two `f32`s.
        unsafe {
            let (i, j) = (
                _mm256_cvttps_epi32(x.max(zero).min(top).m256()),
                _mm256_cvttps_epi32(y.max(zero).min(top).m256()),
            );
            let fx = x - F32x8::from_m256(_mm256_cvtepi32_ps(i));
            let fy = y - F32x8::from_m256(_mm256_cvtepi32_ps(j));
            // Each lane's cell, j·N + i (N a power of two).
            const SHIFT: i32 = N.trailing_zeros() as i32;
            const _: () = assert!(N.is_power_of_two());
            let mut at = [0i32; 8];
            _mm256_storeu_si256(
                at.as_mut_ptr().cast(),
                _mm256_add_epi32(_mm256_slli_epi32::<SHIFT>(j), i),
            );
            let cells = table.as_ptr().cast::<f32>();
            // (A function, not a closure: closures here were compiled on their own, without
            // AVX, their vector operations left as calls.)
            let [a0, b0, a1, b1] = albedo_corners(cells, &at, 0);
            let [a2, b2, a3, b3] = albedo_corners(cells, &at, 2 * N);
            let (gx, gy) = (one - fx, one - fy);
            let top_a = a0 * gx + a1 * fx;
            let bottom_a = a2 * gx + a3 * fx;
            let top_b = b0 * gx + b1 * fx;
            let bottom_b = b2 * gx + b3 * fx;
            (top_a * gy + bottom_a * fy, top_b * gy + bottom_b * fy)
        }
    }
}

/// The (A, B) of the left and right texels of a row of eight lanes' cells (`cells` the
/// table's floats, `at` each lane's cell, `off` the row's first float from it: 0 the top
/// row, 2N the bottom one), each corner's A and B in lanes: every lane's row loaded whole
/// and the rows transposed ([`F32x8::transpose`](super::wide::F32x8::transpose)).
///
/// # Safety
/// AVX (the [`F32x8`](super::wide::F32x8) rule); every lane's row, four floats from
/// `2·at[l] + off`, inside the table.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn albedo_corners(cells: *const f32, at: &[i32; 8], off: usize) -> [super::wide::F32x8; 4] {
    use std::arch::x86_64::_mm_loadu_ps;
    // SAFETY: the caller's rules.
    let row = |l: usize| Vec4::from(unsafe { _mm_loadu_ps(cells.add(2 * at[l] as usize + off)) });
    super::wide::F32x8::transpose(
        &[row(0), row(1), row(2), row(3)],
        &[row(4), row(5), row(6), row(7)],
    )
}

/// [`specular_albedo`](super::pbr::specular_albedo) at four points (one per lane), as
/// `(A, B)`: the table's cells located in lanes, its texels gathered, the same bilinear
/// weights and blends (bit for bit).
#[inline(always)]
#[must_use]
pub fn specular_albedo_quad(n_dot_v: Vec4, roughness: Vec4) -> (Vec4, Vec4) {
    const N: usize = ALBEDO_N;
    let table = albedo_table();
    let (zero, one) = (Vec4::ZERO, Vec4::ONE);
    let last = Vec4::splat((N - 1) as f32);
    let x = sqrt4(n_dot_v.max(zero).min(one)) * last;
    let y = roughness.max(zero).min(one) * last;
    // The cell: ⌊x⌋ and ⌊y⌋ at most N − 2, in lanes (a NaN lane is 0, as `max` makes it;
    // clamped first, so the truncation is in range), as integers and as floats (converted
    // in lanes: as four scalar conversions they were 16 instructions a quad pair).
    let cell = |t: Vec4| {
        use crate::texture::filter::{float4, truncate4};
        let i = truncate4(t.max(zero).min(Vec4::splat((N - 2) as f32)));
        (i.map(|i| i as usize), float4(i))
    };
    let ((i, i_f), (j, j_f)) = (cell(x), cell(y));
    let fx = x - i_f;
    let fy = y - j_f;
    // Each lane's cell: its two rows of two texels, (A, B) of the left one then of the right
    // one (one bounds check a cell); the four lanes' rows transposed give each corner's A and
    // B in lanes.
    let cell = |k: usize| {
        let at = j[k] * N + i[k];
        let c = &table[at..at + N + 2];
        let row = |l: Vec2, r: Vec2| Vec4::new(l.x, l.y, r.x, r.y);
        (row(c[0], c[1]), row(c[N], c[N + 1]))
    };
    let cells = [cell(0), cell(1), cell(2), cell(3)];
    let [a0, b0, a1, b1] = transpose(cells.map(|c| c.0));
    let [a2, b2, a3, b3] = transpose(cells.map(|c| c.1));
    let lerp = |a: Vec4, b: Vec4, f: Vec4| a * (one - f) + b * f;
    let blend = |[c0, c1, c2, c3]: [Vec4; 4]| {
        let top = lerp(c0, c1, fx);
        let bottom = lerp(c2, c3, fx);
        lerp(top, bottom, fy)
    };
    (blend([a0, a1, a2, a3]), blend([b0, b1, b2, b3]))
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;
    use crate::shading::pbr::metallic_roughness;
    use crate::shading::{Light, Material, ShadingModel};

    fn lanes(v: &[Vec3; 4]) -> Lanes3 {
        std::array::from_fn(|c| Vec4::from_array(std::array::from_fn(|j| v[j][c])))
    }

    #[test]
    fn opaque_colors_in_lanes_are_combine_pixel_by_pixel() {
        use crate::shading::{combine, AlphaMode};
        // Opaque, translucent, zero, negative and NaN alphas; a quad of only opaque pixels
        // (no division) and mixed ones.
        let alphas = [1.0, 0.5, 0.0, 0.25, -0.5, f32::NAN, 1.0, 0.75];
        for k in 0..64 {
            let t = k as f32 / 63.0;
            let c: [Vec4; 4] = std::array::from_fn(|j| {
                let a = if k % 2 == 0 {
                    1.0
                } else {
                    alphas[(k + j) % alphas.len()]
                };
                Vec4::new(0.9 * t, 0.3 + 0.1 * j as f32, 1.0 - t, a)
            });
            let d: [Vec3; 4] = std::array::from_fn(|j| Vec3::new(t, 0.5 * j as f32, 2.0 - t));
            let s: [Vec3; 4] = std::array::from_fn(|j| Vec3::new(0.1 * j as f32, t * t, -0.0));
            let out = opaque_colors(straight_lanes(&c), lanes(&d), lanes(&s));
            for j in 0..4 {
                let e = combine(AlphaMode::Opaque, c[j], d[j], s[j]).expect("opaque keeps all");
                let same =
                    |x: f32, y: f32| x.to_bits() == y.to_bits() || (x.is_nan() && y.is_nan());
                assert!(
                    (0..4).all(|i| same(out[j][i], e[i])),
                    "pixel {j} of case {k}: {} against {e}",
                    out[j]
                );
            }
        }
    }

    #[test]
    fn albedo_quad_equals_the_table_read() {
        use crate::shading::pbr::specular_albedo;
        for k in 0..200 {
            let t = k as f32 / 199.0;
            let nv = Vec4::new(t, 1.0 - t, t * t, -t);
            let r = Vec4::new(1.0 - t, t, 0.5 * t, 1.0 + t);
            let (a, b) = specular_albedo_quad(nv, r);
            for j in 0..4 {
                let e = specular_albedo(nv[j], r[j]);
                assert_eq!((a[j], b[j]), (e.x, e.y), "{} {}", nv[j], r[j]);
            }
        }
    }

    /// The albedo table read in eight lanes (rows transposed) gives each lane the bits four
    /// lanes give it ([`specular_albedo_quad`], the table read's where no input is NaN:
    /// `albedo_quad_equals_the_table_read`): in range, at the table's edges, outside it,
    /// infinite and NaN.
    #[cfg(target_arch = "x86_64")]
    #[test]
    fn albedo_in_eight_lanes_equals_the_table_read() {
        if !crate::cpu::available(crate::cpu::Level::V3) {
            eprintln!("skipped: this CPU has no AVX2");
            return;
        }
        // SAFETY: the CPU has x86-64-v3 (checked above).
        unsafe { albedo_eight_lanes() }
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,movbe")]
    fn albedo_eight_lanes() {
        use crate::shading::wide::F32x8;
        let special = [
            0.0,
            1.0,
            -0.0,
            -0.5,
            1.5,
            f32::INFINITY,
            f32::NAN,
            30.0 / 31.0,
        ];
        for k in 0..400 {
            let t = k as f32 / 399.0;
            let v: [f32; 16] = std::array::from_fn(|l| match (k + l) % 5 {
                0 => special[(k + 3 * l) % special.len()],
                _ => ((l as f32 + 1.0) * 0.37 + t * 1.7).fract(),
            });
            let nv = F32x8::join(Vec4::from_slice(&v[0..4]), Vec4::from_slice(&v[4..8]));
            let r = F32x8::join(Vec4::from_slice(&v[8..12]), Vec4::from_slice(&v[12..16]));
            let (a, b) = <F32x8 as AlbedoLanes>::specular_albedo(nv, r);
            for q in 0..2 {
                let (ea, eb) = specular_albedo_quad(nv.quad(q), r.quad(q));
                for (got, want) in [(a.quad(q), ea), (b.quad(q), eb)] {
                    let bits = |v: Vec4| v.to_array().map(f32::to_bits);
                    assert_eq!(bits(got), bits(want), "{} {}", nv.quad(q), r.quad(q));
                }
            }
        }
    }

    /// Two quads in eight lanes give each quad's `Vec4` factors, bit for bit, under every
    /// kind of light, with and without an ambient light, from a point and a direction.
    #[cfg(target_arch = "x86_64")]
    #[test]
    fn two_quads_in_eight_lanes_are_each_quads_factors() {
        if !crate::cpu::available(crate::cpu::Level::V3) {
            eprintln!("skipped: this CPU has no AVX2");
            return;
        }
        // SAFETY: the CPU has x86-64-v3 (checked above).
        unsafe { eight_lanes() }
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,movbe")]
    fn eight_lanes() {
        use crate::shading::wide::F32x8;
        let lights = test_lights();
        let material = Material {
            model: ShadingModel::MetallicRoughness,
            ambient: 0.8,
            ..Default::default()
        };
        let s = Surface::new(&material, Vec3::ZERO, Vec3::ZERO);
        let quads = [0.0f32, 1.0, 2.5].map(test_quad);
        for (a, b) in [(0, 1), (1, 2), (2, 0)] {
            let (qa, qb) = (&quads[a], &quads[b]);
            let j3 = |x: [Vec4; 3], y: [Vec4; 3]| [0, 1, 2].map(|c| F32x8::join(x[c], y[c]));
            let wide = MrQuad {
                position: j3(qa.position, qb.position),
                normal: j3(qa.normal, qb.normal),
                base_color: j3(qa.base_color, qb.base_color),
                metallic: F32x8::join(qa.metallic, qb.metallic),
                roughness: F32x8::join(qa.roughness, qb.roughness),
                occlusion: F32x8::join(qa.occlusion, qb.occlusion),
                emissive: j3(qa.emissive, qb.emissive),
            };
            for (lighting, viewer) in lightings(&[&lights[..], &lights[1..2], &lights[3..], &[]]) {
                let (d, sp) = mr_lanes(&s, &wide, &lighting, viewer);
                for (k, q) in [qa, qb].into_iter().enumerate() {
                    let (ed, es) = mr_lanes(&s, q, &lighting, viewer);
                    for c in 0..3 {
                        for (got, want) in [(d[c].quad(k), ed[c]), (sp[c].quad(k), es[c])] {
                            let same = (0..4).all(|i| {
                                got[i].to_bits() == want[i].to_bits()
                                    || (got[i].is_nan() && want[i].is_nan())
                            });
                            assert!(same, "quad {k} channel {c}: {got} vs {want}");
                        }
                    }
                }
            }
        }
    }

    /// Every lighting the tests try: each of `sets` of lights with the ambient light off and
    /// on, seen from a point and from a direction.
    fn lightings<'a>(sets: &[&'a [Light]]) -> Vec<(Lighting<'a>, Viewer)> {
        let mut out = Vec::new();
        for ambient in [Vec3::ZERO, Vec3::new(0.3, 0.35, 0.4)] {
            for &lights in sets {
                for viewer in [
                    Viewer::Point(Vec3::new(0.5, 3.0, 4.0)),
                    Viewer::Direction(Vec3::new(0.0, 0.6, 0.8)),
                ] {
                    let shadows = None;
                    out.push((
                        Lighting {
                            lights,
                            ambient,
                            shadows,
                        },
                        viewer,
                    ));
                }
            }
        }
        out
    }

    /// Directional, point (with and without a range) and spot lights.
    fn test_lights() -> [Light; 4] {
        [
            Light::Directional {
                direction: Vec3::new(0.3, 0.8, 0.5).normalize(),
                color: Vec3::new(1.0, 0.9, 0.8),
            },
            Light::Point {
                position: Vec3::new(1.0, 3.0, 2.5),
                color: Vec3::new(8.0, 6.8, 4.8),
                range: Some(6.0),
            },
            Light::Point {
                position: Vec3::new(-2.0, 1.0, 0.5),
                color: Vec3::splat(2.0),
                range: None,
            },
            Light::Spot {
                position: Vec3::new(0.0, 4.0, 0.0),
                direction: Vec3::new(0.1, -1.0, 0.2).normalize(),
                color: Vec3::new(5.0, 5.0, 4.0),
                inner_deg: 20.0,
                outer_deg: 50.0,
            },
        ]
    }

    /// A quad of varied pixels (a zero normal, one facing away, metals and dielectrics, a
    /// clamped and an infinite roughness, occlusion 0 on one), moved by `t`.
    fn test_quad(t: f32) -> MrQuad {
        let v = |f: &dyn Fn(usize) -> Vec3| lanes(&std::array::from_fn(f));
        MrQuad {
            position: v(&|j| Vec3::new(j as f32 - 1.5 + t, 0.1 * j as f32, t - 1.0)),
            normal: v(&|j| match (j + t as usize) % 4 {
                0 => Vec3::new(0.1, 2.0, 0.3 + t).normalize(),
                1 => Vec3::new(-1.0, 0.2, 0.9).normalize(),
                2 => Vec3::ZERO,
                _ => Vec3::new(0.2, -1.0, 0.1).normalize(),
            }),
            base_color: v(&|j| Vec3::new(0.9, 0.5 * j as f32 / 3.0, 0.1 + 0.2 * t)),
            metallic: Vec4::new(1.0, 0.0, 0.5, 0.25 * t),
            roughness: Vec4::new(0.0, 0.5, f32::INFINITY, 1.0 - 0.2 * t),
            occlusion: Vec4::new(1.0, 0.0, 0.5, 0.75),
            emissive: v(&|j| Vec3::new(0.1 * j as f32, t, 0.0)),
        }
    }

    #[test]
    fn quad_equals_the_per_pixel_rule_under_every_light() {
        let lights = test_lights();
        // Normals (one zero, one facing away), positions spread out (one outside the spot's
        // cone, one beyond the first point light's range), metals and dielectrics, a mirror
        // (clamped roughness) and an infinite roughness, occlusion 0 (no ambient term) on one.
        let normals = [
            Vec3::new(0.1, 2.0, 0.3).normalize(),
            Vec3::new(-1.0, 0.2, 0.9).normalize(),
            Vec3::ZERO,
            Vec3::new(0.2, -1.0, 0.1).normalize(),
        ];
        let positions = [
            Vec3::new(-4.0, 0.0, -5.0),
            Vec3::new(-0.5, 0.1, -1.0),
            Vec3::new(0.5, 0.2, 0.0),
            Vec3::new(1.5, 0.3, 1.0),
        ];
        let base = [
            Vec3::new(0.9, 0.5, 0.1),
            Vec3::ONE,
            Vec3::new(0.2, 0.3, 0.4),
            Vec3::ZERO,
        ];
        let metallic = [1.0, 0.0, 0.5, 0.25];
        let roughness = [0.0, 0.5, f32::INFINITY, 1.0];
        let occlusion = [1.0, 0.0, 0.5, 0.75];
        let emissive = [Vec3::ZERO, Vec3::new(0.1, 0.2, 0.3), Vec3::ONE, Vec3::ZERO];
        for ior in [1.5, 1.33] {
            let material = Material {
                model: ShadingModel::MetallicRoughness,
                ambient: 0.8,
                ior,
                ..Default::default()
            };
            let template = Surface::new(&material, Vec3::ZERO, Vec3::ZERO);
            let q = MrQuad {
                position: lanes(&positions),
                normal: lanes(&normals),
                base_color: lanes(&base),
                metallic: Vec4::from_array(metallic),
                roughness: Vec4::from_array(roughness),
                occlusion: Vec4::from_array(occlusion),
                emissive: lanes(&emissive),
            };
            for (lighting, viewer) in lightings(&[&lights[..], &lights[..1], &[]]) {
                let quad = metallic_roughness_quad(&template, &q, &lighting, viewer);
                for j in 0..4 {
                    let s = Surface {
                        position: positions[j],
                        normal: normals[j],
                        base_color: base[j],
                        metallic: metallic[j],
                        roughness: roughness[j],
                        occlusion: occlusion[j],
                        emissive: emissive[j],
                        ..template
                    };
                    let (d, sp) = metallic_roughness(&s, &lighting, viewer);
                    let (qd, qs) = (quad.d[j].truncate(), quad.s[j].truncate());
                    // The same operations in the same order: equal, not just close.
                    assert!(
                        d == qd && sp == qs,
                        "pixel {j} {viewer:?} ior {ior} ambient {}: {d} {sp} vs {qd} {qs}",
                        lighting.ambient
                    );
                    assert_eq!((quad.d[j].w, quad.s[j].w), (0.0, 0.0));
                }
            }
        }
    }
}
