//! Prefiltering an environment: the source cube, the irradiance cube and the GGX lobe's
//! levels (the `ibl` module docs give the method).

use std::f32::consts::{FRAC_1_PI, PI, TAU};

use glam::{Vec3, Vec3A, Vec4};
use rayon::prelude::*;

use super::super::pbr;
use super::LEVELS;
use crate::texture::environment::EnvironmentMap;
use crate::texture::{
    sample_cube, CubeFace, CubeFootprint, Filter, Sampler, Texture2D, TextureCube, TextureOptions,
    Wrap,
};

/// Six square faces of `n × n` linear RGB values with a one-texel apron, read bilinearly and
/// seamlessly by direction (faces in OpenGL's order and orientation, world directions).
#[derive(Clone, Debug)]
pub struct FaceSet {
    n: usize,
    /// Per face `(n + 2)²` values, row-major, the apron around the face's own `n × n`
    /// (16-byte SIMD values: a bilinear read is four loads and three vector lerps).
    texels: Vec<Vec3A>,
}

/// The face a direction hits, and its face coordinates `(sc, tc)/|ma|` in [−1, 1].
#[inline]
fn face_coords(d: Vec3) -> (usize, f32, f32) {
    let (f, s, t, m) = CubeFace::select(d);
    let inv = if m > 0.0 { 1.0 / m } else { 0.0 };
    (f, s * inv, t * inv)
}

impl FaceSet {
    /// Evaluates `f` at the direction through every texel centre (apron included), in
    /// parallel.
    pub fn from_fn(n: usize, f: impl Fn(Vec3) -> Vec3 + Sync) -> Self {
        Self::from_face_fn(n, |face, sc, tc| {
            f(CubeFace::direction(face, sc, tc).normalize())
        })
    }

    /// Evaluates `f(face, sc, tc)` at every texel centre's face coordinates (apron included,
    /// so `sc` or `tc` may pass ±1 by a texel), in parallel.
    fn from_face_fn(n: usize, f: impl Fn(usize, f32, f32) -> Vec3 + Sync) -> Self {
        let m = n + 2;
        let mut texels = vec![Vec3A::ZERO; 6 * m * m];
        texels.par_chunks_mut(m).enumerate().for_each(|(row, out)| {
            let (face, y) = (row / m, row % m);
            let tc = 2.0 * (y as f32 - 0.5) / n as f32 - 1.0;
            for (x, o) in out.iter_mut().enumerate() {
                let sc = 2.0 * (x as f32 - 0.5) / n as f32 - 1.0;
                *o = f(face, sc, tc).into();
            }
        });
        FaceSet { n, texels }
    }

    /// Face size in texels (without the apron).
    #[must_use]
    pub fn size(&self) -> usize {
        self.n
    }

    /// The bilinear value along `d` (any length).
    #[inline]
    #[must_use]
    pub fn read(&self, d: Vec3) -> Vec3A {
        let (f, sc, tc) = face_coords(d);
        self.read_at(f, sc, tc)
    }

    /// The bilinear values of `self` and `other` along `d`: one face selection for both
    /// (the two prefiltered levels a rough read blends).
    #[inline]
    #[must_use]
    pub fn read_pair(&self, other: &FaceSet, d: Vec3) -> (Vec3A, Vec3A) {
        let (f, sc, tc) = face_coords(d);
        (self.read_at(f, sc, tc), other.read_at(f, sc, tc))
    }

    /// The bilinear value at face coordinates `(sc, tc)` of face `f`.
    #[inline]
    pub(super) fn read_at(&self, f: usize, sc: f32, tc: f32) -> Vec3A {
        let n = self.n as u32 as f32;
        let m = self.n + 2;
        // Texel centre i sits at face coordinate 2(i + ½)/n − 1; the apron shifts by one.
        // `max` then `min` (no NaN assertion: `max` maps NaN to 0): x and y are finite and in
        // [0, n + 1], so the truncations below need no saturation. This is the hot read of
        // image-based light.
        let x = ((sc + 1.0) * 0.5 * n + 0.5).max(0.0).min(n + 1.0);
        let y = ((tc + 1.0) * 0.5 * n + 0.5).max(0.0).min(n + 1.0);
        // SAFETY: x and y are finite, non-negative and at most n + 1 (clamped above), so
        // they fit in a u32 (`n` is a face size of at most a few thousand texels).
        let (xt, yt): (u32, u32) = unsafe { (x.to_int_unchecked(), y.to_int_unchecked()) };
        let (x0, y0) = (
            xt.min(self.n as u32) as usize,
            yt.min(self.n as u32) as usize,
        );
        let (fx, fy) = (x - x0 as f32, y - y0 as f32);
        let base = f * m * m + y0 * m + x0;
        let (top, bottom) = (
            &self.texels[base..base + 2],
            &self.texels[base + m..base + m + 2],
        );
        let top = top[0].lerp(top[1], fx);
        let bottom = bottom[0].lerp(bottom[1], fx);
        top.lerp(bottom, fy)
    }
}

/// The map itself as a mip chain of [`FaceSet`]s, for the sharp reads of shading (a
/// reflection under roughness 1/8 blends it with the first GGX level): face size the map's own
/// density rounded up to a power of two, at most 512, each texel the map read with that
/// texel's footprint (trilinear), down to one texel a face. A trilinear read here is a face
/// selection and two bilinear reads of four vector loads, where the map itself (an
/// equirectangular image in 4×4 tiles) costs a generic filtered read; the background still
/// reads the map.
#[derive(Clone, Debug)]
pub struct MirrorCube {
    levels: Vec<FaceSet>,
}

impl MirrorCube {
    /// Resamples `map` (module docs: rayon over faces and rows).
    pub(super) fn new(map: &EnvironmentMap) -> Self {
        let n0 = (face_density(map).max(1.0) as usize)
            .next_power_of_two()
            .min(512);
        let levels = std::iter::successors(Some(n0), |&n| (n > 1).then_some(n / 2))
            .map(|n| {
                let step = 2.0 / n as f32;
                FaceSet::from_face_fn(n, |face, sc, tc| {
                    read_face_texel(map, face, sc, tc, step).truncate()
                })
            })
            .collect();
        MirrorCube { levels }
    }

    /// Face size of level 0.
    #[must_use]
    pub fn size(&self) -> usize {
        self.levels[0].n
    }

    /// The trilinear value along the footprint `fp` (λ by `sampler`'s rule, bias and clamps
    /// from the face-coordinate derivatives, as the cube sampler computes them), with the
    /// face and face coordinates it read at (for a second read at the same place).
    #[inline]
    #[must_use]
    pub fn read(&self, sampler: &Sampler, fp: &CubeFootprint) -> (Vec3A, (usize, f32, f32)) {
        let (f, s, t, ma) = CubeFace::select(fp.dir);
        if !(ma > 0.0) || !ma.is_finite() {
            return (Vec3A::ZERO, (0, 0.0, 0.0));
        }
        let inv = 1.0 / ma;
        let (sc, tc) = (s * inv, t * inv);
        // d(s/m) = (ds − (s/m)·dm)/m, in level-0 texels (a face is 2 units across).
        let k = 0.5 * self.levels[0].n as f32 * inv;
        let texels = |dd: Vec3| {
            let (ds, dt, dm) = CubeFace::axes(f, dd);
            glam::Vec2::new((ds - sc * dm) * k, (dt - tc * dm) * k)
        };
        let (dx, dy) = (texels(fp.ddir_dx), texels(fp.ddir_dy));
        let lod = if dx.length_squared().max(dy.length_squared()) > 0.0 {
            sampler.adjust_lod(sampler.lod_rule.lod(dx, dy))
        } else {
            sampler.adjust_lod(f32::NEG_INFINITY)
        };
        let top = (self.levels.len() - 1) as f32;
        let lod = if lod > 0.0 { lod.min(top) } else { 0.0 };
        let l0 = lod as usize;
        let frac = lod - l0 as f32;
        let a = self.levels[l0].read_at(f, sc, tc);
        let c = if frac > 0.0 {
            a.lerp(self.levels[l0 + 1].read_at(f, sc, tc), frac)
        } else {
            a
        };
        (c, (f, sc, tc))
    }
}

/// The solid angle of texel `(x, y)` of an `n × n` face: the integral of `dA/(1 + s² + t²)^{3/2}`
/// over its square (by its corners' `atan` form).
fn texel_solid_angle(x: usize, y: usize, n: usize) -> f32 {
    let corner = |s: f64, t: f64| (s * t).atan2((s * s + t * t + 1.0).sqrt());
    let step = 2.0 / n as f64;
    let (s0, t0) = (x as f64 * step - 1.0, y as f64 * step - 1.0);
    let (s1, t1) = (s0 + step, t0 + step);
    (corner(s0, t0) - corner(s0, t1) - corner(s1, t0) + corner(s1, t1)) as f32
}

/// The face size at which a cube holds as many texels as `map` does (its density).
fn face_density(map: &EnvironmentMap) -> f32 {
    (map.texels_per_steradian() * 4.0 * PI / 6.0).sqrt()
}

/// `map` read trilinearly over the face texel of side `step` (face units) at `(sc, tc)` of
/// `face`: its footprint the directions to the neighbouring texel centres.
fn read_face_texel(map: &EnvironmentMap, face: usize, sc: f32, tc: f32, step: f32) -> Vec4 {
    let dir = CubeFace::direction(face, sc, tc);
    let fp = CubeFootprint {
        dir,
        ddir_dx: CubeFace::direction(face, sc + step, tc) - dir,
        ddir_dy: CubeFace::direction(face, sc, tc + step) - dir,
    };
    map.sample(&Sampler::new(Filter::TRILINEAR, Wrap::ClampToEdge), &fp)
}

/// The map resampled to a world-direction cube of face size `min(256, the map's own
/// density)`, each texel read with its footprint, mipmapped.
pub(super) fn source_cube(map: &EnvironmentMap) -> TextureCube {
    let n = (face_density(map).max(16.0) as u32)
        .next_power_of_two()
        .min(256);
    let step = 2.0 / n as f32;
    let faces: Vec<Texture2D> = (0..6)
        .into_par_iter()
        .map(|face| {
            let rows: Vec<Vec<Vec4>> = (0..n)
                .into_par_iter()
                .map(|y| {
                    let tc = (y as f32 + 0.5) * step - 1.0;
                    (0..n)
                        .map(|x| {
                            let sc = (x as f32 + 0.5) * step - 1.0;
                            read_face_texel(map, face, sc, tc, step)
                                .truncate()
                                .extend(1.0)
                        })
                        .collect()
                })
                .collect();
            Texture2D::from_fn(n, n, TextureOptions::default(), |x, y| {
                rows[y as usize][x as usize]
            })
            .expect("a square face")
        })
        .collect();
    TextureCube::new(faces.try_into().expect("six faces")).expect("equal faces")
}

/// `I_env` (the module docs: irradiance / π) on an `n`-texel cube, integrated over the
/// source's level nearest 32 texels a side: every texel a small light of its solid angle.
pub(super) fn irradiance_cube(source: &TextureCube, n: usize) -> FaceSet {
    let face0 = &source.faces()[0];
    let level = face0
        .levels()
        .iter()
        .position(|l| l.width() <= 32)
        .unwrap_or(face0.levels().len() - 1);
    let size = face0.levels()[level].width() as usize;
    let mut lights: Vec<(Vec3, Vec3)> = Vec::with_capacity(6 * size * size);
    for (face, tex) in source.faces().iter().enumerate() {
        let texels = tex.decode_level(level);
        for y in 0..size {
            for x in 0..size {
                let sc = 2.0 * (x as f32 + 0.5) / size as f32 - 1.0;
                let tc = 2.0 * (y as f32 + 0.5) / size as f32 - 1.0;
                let d = CubeFace::direction(face, sc, tc).normalize();
                let w = texel_solid_angle(x, y, size);
                lights.push((d, texels[y * size + x].truncate() * w));
            }
        }
    }
    FaceSet::from_fn(n, |normal| {
        let mut sum = Vec3::ZERO;
        for &(d, lw) in &lights {
            let c = normal.dot(d);
            if c > 0.0 {
                sum += lw * c;
            }
        }
        sum * FRAC_1_PI
    })
}

/// The base-2 radical inverse of `k` (van der Corput).
fn radical_inverse(k: u32) -> f32 {
    (f64::from(k.reverse_bits()) / 4_294_967_296.0) as f32
}

/// Face size and sample count of the level at `roughness`: a face texel (2/n radians at a
/// face's centre) at most half of α, 16…128 texels, so the bilinear read adds little to the
/// lobe; more samples for wider lobes.
fn level_shape(roughness: f32, source: usize) -> (usize, u32) {
    let alpha = roughness * roughness;
    let n = ((4.0 / alpha) as usize)
        .next_power_of_two()
        .clamp(16, 128)
        .min(source);
    let samples = if roughness < 0.2 {
        32
    } else if roughness < 0.3 {
        64
    } else {
        128
    };
    (n, samples)
}

/// The GGX-prefiltered levels (module docs), roughness `k/LEVELS` for `k = 1…LEVELS`.
pub(super) fn specular_levels(source: &TextureCube) -> Vec<FaceSet> {
    let n_src = source.size() as f32;
    let levels = source.faces()[0].levels().len() as f32;
    // The solid angle of a level-0 texel at a face's centre.
    let texel_omega = 4.0 * PI / (6.0 * n_src * n_src);
    (1..=LEVELS)
        .map(|k| {
            let roughness = k as f32 / LEVELS as f32;
            let alpha = roughness * roughness;
            let a2 = alpha * alpha;
            let (n, samples) = level_shape(roughness, source.size() as usize);
            // Half vectors (tangent space) and the source level each sample reads.
            let taps: Vec<(Vec3, f32)> = (0..samples)
                .map(|i| {
                    let u1 = (i as f32 + 0.5) / samples as f32;
                    let u2 = radical_inverse(i);
                    let cos_h = ((1.0 - u1) / (1.0 + (a2 - 1.0) * u1)).sqrt();
                    let sin_h = (1.0 - cos_h * cos_h).max(0.0).sqrt();
                    let phi = TAU * u2;
                    let h = Vec3::new(sin_h * phi.cos(), sin_h * phi.sin(), cos_h);
                    // pdf(L) = D(N·H)/4 with N = V; the sample's solid angle 1/(M·pdf).
                    let pdf = pbr::distribution(cos_h, alpha) * 0.25;
                    let omega = 1.0 / (samples as f32 * pdf);
                    let lod = (0.5 * (omega / texel_omega).log2()).clamp(0.0, levels - 1.0);
                    (h, lod)
                })
                .collect();
            lobe_average(source, n, &taps)
        })
        .collect()
}

/// An `n`-texel cube of the source averaged over a lobe about each texel's direction `N`
/// (`N = V = R`): `taps` are half vectors in the normal's tangent space and the source level
/// each reads; `L` is `N` reflected about each, weighted by `N·L` (those below the surface
/// skipped).
fn lobe_average(source: &TextureCube, n: usize, taps: &[(Vec3, f32)]) -> FaceSet {
    FaceSet::from_fn(n, |normal| {
        let (t, b) = orthonormal_basis(normal);
        let mut sum = Vec3::ZERO;
        let mut weight = 0.0;
        for &(h, lod) in taps {
            let h = t * h.x + b * h.y + normal * h.z;
            let l = h * (2.0 * normal.dot(h)) - normal;
            let n_dot_l = normal.dot(l);
            if n_dot_l <= 0.0 {
                continue;
            }
            let s = Sampler::new(Filter::TRILINEAR, Wrap::ClampToEdge).with_lod_clamp(lod, lod);
            let c = sample_cube(
                source,
                &s,
                &CubeFootprint {
                    dir: l,
                    ..Default::default()
                },
            );
            sum += c.truncate() * n_dot_l;
            weight += n_dot_l;
        }
        if weight > 0.0 {
            sum / weight
        } else {
            Vec3::ZERO
        }
    })
}

/// Face size and sample count of every sheen level: the Charlie lobe is broad (its
/// reflected directions lie near the horizon of the normal), so the result varies slowly
/// with the normal.
const SHEEN_FACE: usize = 16;
const SHEEN_SAMPLES: u32 = 128;

/// The environment prefiltered by the sheen's Charlie lobe ([`crate::shading::sheen`]) at
/// sheen roughness `k/LEVELS`, `k = 1…LEVELS`, as the glTF sample viewer's Charlie filter:
/// `N = V = R`, half vectors drawn from `D(N·H)·(N·H)` (`sin θ_h = u^{α/(2α+1)}`, α = r²),
/// `L` the view reflected about each, weighted by `N·L`. Only half vectors within 45° of
/// the normal reflect above the surface, so `u` is drawn from that range alone (the same
/// weighted mean, with no wasted samples); each sample reads the source level its solid
/// angle `1/(M·pdf)` covers, `pdf = D/4` divided by the share of the range.
pub(super) fn sheen_levels(source: &TextureCube) -> Vec<FaceSet> {
    let n_src = source.size() as f32;
    let levels = source.faces()[0].levels().len() as f32;
    let texel_omega = 4.0 * PI / (6.0 * n_src * n_src);
    (1..=LEVELS)
        .map(|k| {
            let r = (k as f32 / LEVELS as f32).max(crate::shading::sheen::MIN_SHEEN_ROUGHNESS);
            let alpha = f64::from(r * r);
            let power = alpha / (2.0 * alpha + 1.0);
            // sin θ_h ≤ 1/√2 ⇔ u ≤ (1/√2)^{1/power}.
            let u_max = std::f64::consts::FRAC_1_SQRT_2.powf(1.0 / power);
            let taps: Vec<(Vec3, f32)> = (0..SHEEN_SAMPLES)
                .map(|i| {
                    let u = (f64::from(i) + 0.5) / f64::from(SHEEN_SAMPLES) * u_max;
                    let sin_h = u.powf(power).min(1.0) as f32;
                    let cos_h = (1.0 - sin_h * sin_h).max(0.0).sqrt();
                    let phi = TAU * radical_inverse(i);
                    let h = Vec3::new(sin_h * phi.cos(), sin_h * phi.sin(), cos_h);
                    let pdf = crate::shading::sheen::distribution(cos_h, r) * 0.25 / u_max as f32;
                    let omega = 1.0 / (SHEEN_SAMPLES as f32 * pdf);
                    let lod = (0.5 * (omega / texel_omega).log2()).clamp(0.0, levels - 1.0);
                    (h, lod)
                })
                .collect();
            lobe_average(source, SHEEN_FACE, &taps)
        })
        .collect()
}

/// Two unit vectors completing `n` to an orthonormal basis (Duff et al.'s branchless form).
fn orthonormal_basis(n: Vec3) -> (Vec3, Vec3) {
    let sign = 1f32.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (
        Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
        Vec3::new(b, sign + n.y * n.y * a, -n.y),
    )
}
