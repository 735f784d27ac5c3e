//! The shaded composite loop ([`super::composite::cells`] with shading) with eight samples of
//! a ray in AVX2 lanes, lit by the headlight with a whole specular power (VTK's light and
//! `vtk_volume.py`'s power, the defaults): the samples' cells and levels as
//! [`super::composite_lanes`] reads them, their table entries, the eight corners' normals
//! (one gather each), the normals' trilinear blend and the headlight's Blinn-Phong in lanes,
//! then the shaded colours composited in order.
//!
//! Rules:
//! - The same samples and, per lane, the scalar loop's operations in its order (a multiply
//!   and an add never fused; glam's `lerp` as `a·(1 − t) + b·t`, `dot` as `(x·x + y·y) + z·z`,
//!   the power by the same squarings, [`super::shade`]): the colour and the sample count are
//!   the bits of the scalar loop (tested).
//! - Every lane is shaded, also those the table makes transparent, which the scalar loop does
//!   not shade: they composite nothing either way.
//! - Scene lights, a specular power that is not a whole number in `0..=64`, and grids the
//!   lanes do not fit ([`LaneGrid::new`]) run the scalar loop.

use glam::Vec3;

use super::cell::voxel_count;
use super::composite_lanes::LaneGrid;
use super::marcher::{Marcher, Traced};
use super::rays::RaySamples;
use super::shade::Reflectance;

/// What the shaded lanes take of a frame, prepared once per frame.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ShadedGrid {
    grid: LaneGrid,
    k: Reflectance,
    power: u32,
}

impl ShadedGrid {
    /// The shaded lanes on `grid` (the frame's [`LaneGrid::new`]) for `m`'s frame and its
    /// per-voxel `normals`, or `None` when the light is not the headlight with a whole
    /// specular power, the normals are short of the grid, or the table is too long for
    /// 32-bit offsets.
    pub fn new(grid: LaneGrid, m: &Marcher, normals: &[[i8; 4]]) -> Option<Self> {
        let (k, power) = m.headlight_by_squaring()?;
        let fits = normals.len() >= voxel_count(m.dims) && m.table().len() < 1 << 28;
        fits.then_some(ShadedGrid { grid, k, power })
    }
}

/// The shaded composite of the samples `s` of one ray lit along `light`, as
/// [`super::composite::cells`]`::<true>` gives it with the same `normals`.
pub(crate) fn cells(
    m: &Marcher,
    grid: &ShadedGrid,
    s: &RaySamples,
    light: Vec3,
    normals: &[[i8; 4]],
) -> Traced {
    #[cfg(target_arch = "x86_64")]
    {
        // SAFETY: a `ShadedGrid` exists only when the CPU has every feature `cells_v3`
        // enables, the grid fits the lanes and `normals` covers it (`ShadedGrid::new`).
        unsafe { cells_v3(m, grid, s, light, normals) }
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        let _ = grid;
        super::composite::cells::<true>(m, s, light, normals)
    }
}

/// Eight samples shaded: their straight colours and opacities.
#[cfg(target_arch = "x86_64")]
struct Shaded {
    rgb: [[f32; 8]; 3],
    alpha: [f32; 8],
}

/// One ray's constants for the shaded lanes.
#[cfg(target_arch = "x86_64")]
struct ShadeLanes {
    ray: super::composite_lanes::RayLanes,
    /// The per-voxel normals, one 32-bit word each (`[x, y, z, 0]` as `i8`).
    normals: *const i32,
    /// The transfer table, `[r, g, b, a_step]` per entry.
    table: *const f32,
    light: [std::arch::x86_64::__m256; 3],
    ambient: std::arch::x86_64::__m256,
    diffuse: std::arch::x86_64::__m256,
    specular: std::arch::x86_64::__m256,
    power: u32,
}

#[cfg(target_arch = "x86_64")]
impl ShadeLanes {
    /// # Safety
    /// The CPU has AVX2, `grid` was made by [`ShadedGrid::new`] for `m` and `normals`.
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,movbe")]
    unsafe fn new(
        m: &Marcher,
        grid: &ShadedGrid,
        s: &RaySamples,
        light: Vec3,
        normals: &[[i8; 4]],
    ) -> Self {
        use std::arch::x86_64::_mm256_set1_ps;
        ShadeLanes {
            ray: super::composite_lanes::RayLanes::new(m, &grid.grid, s),
            normals: normals.as_ptr().cast::<i32>(),
            table: m.table().as_ptr().cast::<f32>(),
            light: [light.x, light.y, light.z].map(|c| _mm256_set1_ps(c)),
            ambient: _mm256_set1_ps(grid.k.ambient),
            diffuse: _mm256_set1_ps(grid.k.diffuse),
            specular: _mm256_set1_ps(grid.k.specular),
            power: grid.power,
        }
    }

    /// Samples `k` to `k + 7` classified and shaded, as the scalar loop classifies
    /// ([`Marcher::classify`]), blends the cell's normals ([`super::cell::blend_cell`],
    /// [`super::normals::direction_or_zero_lanes`]) and shades them
    /// ([`super::shade::VolumeLights::shade`], the headlight). Not inlined, as
    /// [`super::composite_lanes`]'s batch.
    ///
    /// # Safety
    /// As [`Self::new`].
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,movbe")]
    #[inline(never)]
    unsafe fn batch(&self, k: u32) -> Shaded {
        use std::arch::x86_64::*;
        let (index, f) = self.ray.locate(k);
        let entry = self.ray.entry(index, f);
        // The entries' four channels, 16 bytes apart (the entries are clamped to the table,
        // whose length fits the offsets: `ShadedGrid::new`).
        let at = _mm256_slli_epi32::<2>(entry);
        let c = [0, 1, 2, 3].map(|ch| _mm256_i32gather_ps::<4>(self.table.add(ch), at));
        // A corner's normal, ×127, per axis: the word's bytes sign-extended.
        // SAFETY (the gathers): every index is a voxel of the cell whose lowest corner
        // `locate` clamped to the grid's last, and the normals cover the grid.
        let corner = |at: __m256i| {
            let w = _mm256_i32gather_epi32::<4>(self.normals, at);
            [
                _mm256_srai_epi32::<24>(_mm256_slli_epi32::<24>(w)),
                _mm256_srai_epi32::<24>(_mm256_slli_epi32::<16>(w)),
                _mm256_srai_epi32::<24>(_mm256_slli_epi32::<8>(w)),
            ]
            .map(|i| _mm256_cvtepi32_ps(i))
        };
        // glam's `lerp`: `a·(1 − t) + b·t`.
        let mix = |a: [__m256; 3], b: [__m256; 3], t: __m256| {
            let u = _mm256_sub_ps(_mm256_set1_ps(1.0), t);
            [0, 1, 2].map(|i| _mm256_add_ps(_mm256_mul_ps(a[i], u), _mm256_mul_ps(b[i], t)))
        };
        let pair = |at: __m256i| {
            let far = _mm256_add_epi32(at, _mm256_set1_epi32(1));
            mix(corner(at), corner(far), f[0])
        };
        let [row, slice, both] = self.ray.rows;
        let c00 = pair(index);
        let c10 = pair(_mm256_add_epi32(index, row));
        let c01 = pair(_mm256_add_epi32(index, slice));
        let c11 = pair(_mm256_add_epi32(index, both));
        let n127 = mix(mix(c00, c10, f[1]), mix(c01, c11, f[1]), f[2]);
        let dot = |a: [__m256; 3], b: [__m256; 3]| {
            _mm256_add_ps(
                _mm256_add_ps(_mm256_mul_ps(a[0], b[0]), _mm256_mul_ps(a[1], b[1])),
                _mm256_mul_ps(a[2], b[2]),
            )
        };
        // `direction_or_zero_lanes`: below half length, no normal (+0.0 in every axis).
        let v = n127.map(|x| _mm256_mul_ps(x, _mm256_set1_ps(1.0 / 127.0)));
        let keep = _mm256_cmp_ps::<_CMP_NLT_UQ>(dot(v, v), _mm256_set1_ps(0.25 * 0.25));
        let g = v.map(|x| _mm256_and_ps(x, keep));
        // The headlight: `c·(k_a + k_d·ndl) + k_s·ndl^p`, or `c·k_a` for a normal of length
        // at most 1e-6.
        let len = _mm256_sqrt_ps(dot(g, g));
        let ndl = _mm256_andnot_ps(_mm256_set1_ps(-0.0), _mm256_div_ps(dot(g, self.light), len));
        let spec = _mm256_mul_ps(self.specular, self.pow(ndl));
        let lit = _mm256_add_ps(self.ambient, _mm256_mul_ps(self.diffuse, ndl));
        let dark = _mm256_cmp_ps::<_CMP_LE_OQ>(len, _mm256_set1_ps(1e-6));
        let mut out = Shaded {
            rgb: [[0.0; 8]; 3],
            alpha: [0.0; 8],
        };
        for (ch, o) in out.rgb.iter_mut().enumerate() {
            let shaded = _mm256_add_ps(_mm256_mul_ps(c[ch], lit), spec);
            let ambient = _mm256_mul_ps(c[ch], self.ambient);
            _mm256_storeu_ps(o.as_mut_ptr(), _mm256_blendv_ps(shaded, ambient, dark));
        }
        _mm256_storeu_ps(out.alpha.as_mut_ptr(), c[3]);
        out
    }

    /// `x^power` by the squarings of [`super::shade`]'s `powi_by_squaring`, in its order.
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,movbe")]
    #[inline]
    fn pow(&self, x: std::arch::x86_64::__m256) -> std::arch::x86_64::__m256 {
        use std::arch::x86_64::{_mm256_mul_ps, _mm256_set1_ps};
        let (mut base, mut n) = (x, self.power);
        let mut acc = if n & 1 != 0 { x } else { _mm256_set1_ps(1.0) };
        loop {
            n >>= 1;
            if n == 0 {
                return acc;
            }
            base = _mm256_mul_ps(base, base);
            if n & 1 != 0 {
                acc = _mm256_mul_ps(acc, base);
            }
        }
    }
}

/// Composites the shaded samples `run` of `b` in order onto the colour `rgb` (its first three
/// lanes) and opacity `a`, as the scalar loop does (transparent samples skipped), stopping
/// once the opacity reaches `stop`: the new colour and opacity, and the sample it stopped at
/// (from the run's first). Not inlined, as [`super::composite_lanes`]'s composite.
#[cfg(target_arch = "x86_64")]
#[inline(never)]
fn composite(
    b: &Shaded,
    run: std::ops::Range<usize>,
    rgb: glam::Vec4,
    mut a: f32,
    stop: f32,
) -> (glam::Vec4, f32, Option<usize>) {
    let mut rgb = rgb.truncate();
    for (n, j) in run.enumerate() {
        let alpha = b.alpha[j];
        if alpha > 0.0 {
            let w = (1.0 - a) * alpha;
            rgb += Vec3::new(b.rgb[0][j], b.rgb[1][j], b.rgb[2][j]) * w;
            a += w;
            if a >= stop {
                return (rgb.extend(0.0), a, Some(n));
            }
        }
    }
    (rgb.extend(0.0), a, None)
}

/// [`cells`] in AVX2 lanes.
///
/// # Safety
/// As [`ShadeLanes::new`].
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,movbe")]
unsafe fn cells_v3(
    m: &Marcher,
    grid: &ShadedGrid,
    s: &RaySamples,
    light: Vec3,
    normals: &[[i8; 4]],
) -> Traced {
    let stop = m.p.early_termination;
    let lanes = ShadeLanes::new(m, grid, s, light, normals);
    let (color, a, samples) = super::composite_lanes::march(
        m,
        s,
        // SAFETY: as this function's.
        |k| unsafe { lanes.batch(k) },
        |b, run, rgb, a| composite(b, run, rgb, a, stop),
    );
    Traced {
        color: color.truncate().extend(a),
        samples,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::volume::params::MarchParams;
    use crate::volume::rays::{clip_to_box, VoxelRay};
    use crate::volume::{TransferFunction, Volume};

    #[test]
    fn shaded_lanes_give_the_bits_and_samples_of_the_scalar_loop() {
        if !crate::cpu::available(crate::cpu::Level::V3) {
            eprintln!("skipped: this CPU has no AVX2 (the lanes never run here)");
            return;
        }
        let mut r = crate::xorshift(0x85eb_ca6b);
        // A smooth blob with noise beside a slab of noise, some empty corners:
        // skipped and taken bricks, opaque and transparent samples.
        let dims = [33u32, 27, 21];
        let values: Vec<f32> = (0..voxel_count(dims))
            .map(|i| {
                let (x, y, z) = (
                    (i % 33) as f32,
                    ((i / 33) % 27) as f32,
                    (i / (33 * 27)) as f32,
                );
                let blob =
                    (-((x - 17.0).powi(2) + (y - 11.0).powi(2) + (z - 10.0).powi(2)) / 50.0).exp();
                // A slab of pure noise: normals that disagree, short after blending.
                let noise = if x < 9.0 { 255 } else { 24 };
                240.0 * blob * f32::from(x >= 9.0) + (r() % noise) as f32
            })
            .collect();
        let vol = Volume::from_scalars(dims, glam::Mat4::IDENTITY, values).unwrap();
        let normals = vol.normals().as_slice();
        let tf = TransferFunction::preset("synth").unwrap();
        let shiny = Reflectance {
            ambient: 0.1,
            diffuse: 0.6,
            specular: 0.5,
            power: 7.0,
        };
        let cases = [
            (0.5, 0.99, Reflectance::default()),
            (0.37, 0.95, shiny),
            (
                1.3,
                1.0,
                Reflectance {
                    power: 0.0,
                    ..shiny
                },
            ),
        ];
        for (step, stop, reflectance) in cases {
            let params = MarchParams {
                step,
                early_termination: stop,
                shade: true,
                reflectance,
                ..MarchParams::default()
            };
            let m = Marcher::new(&vol, &tf, &params, None).unwrap();
            let Some(grid) = LaneGrid::new(&m).and_then(|g| ShadedGrid::new(g, &m, normals)) else {
                eprintln!("skipped: TEXMAP_CPU=baseline (the lanes never run)");
                return;
            };
            for _ in 0..400 {
                let f = |v: u32| (v % 10_000) as f32 / 10_000.0;
                let o = Vec3::new(f(r()), f(r()), f(r())) * 80.0 - 20.0;
                let target = Vec3::new(f(r()) * 32.0, f(r()) * 26.0, f(r()) * 20.0);
                let dir = (target - o).normalize();
                let ray = VoxelRay { origin: o, dir };
                let Some(span) = clip_to_box(&ray, f32::INFINITY, m.lo, m.hi) else {
                    continue;
                };
                let samples = RaySamples::by_reciprocal(ray, span, step, f(r()));
                let lanes = cells(&m, &grid, &samples, dir, normals);
                let scalar = crate::volume::composite::cells::<true>(&m, &samples, dir, normals);
                assert_eq!(lanes.samples, scalar.samples, "{ray:?}");
                assert_eq!(
                    lanes.color.to_array().map(f32::to_bits),
                    scalar.color.to_array().map(f32::to_bits),
                    "{ray:?}"
                );
            }
        }
    }

    #[test]
    fn scene_lights_and_fractional_powers_keep_the_scalar_loop() {
        let vol = Volume::from_scalars([4, 4, 4], glam::Mat4::IDENTITY, vec![1.0; 64]).unwrap();
        let normals = vol.normals().as_slice();
        let tf = TransferFunction::preset("synth").unwrap();
        let fractional = MarchParams {
            shade: true,
            reflectance: Reflectance {
                power: 10.5,
                ..Reflectance::default()
            },
            ..MarchParams::default()
        };
        let lit = MarchParams {
            shade: true,
            lights: vec![crate::shading::Light::Directional {
                direction: Vec3::X,
                color: Vec3::ONE,
            }],
            ..MarchParams::default()
        };
        for params in [fractional, lit] {
            let m = Marcher::new(&vol, &tf, &params, None).unwrap();
            assert!(m.headlight_by_squaring().is_none());
            // (Without AVX2 there are no lanes either way.)
            if let Some(grid) = LaneGrid::new(&m) {
                assert!(ShadedGrid::new(grid, &m, normals).is_none());
            }
        }
    }
}
