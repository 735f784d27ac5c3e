//! Image-based light: an environment map as the light arriving from every direction, its
//! prefiltered forms, and the terms it adds to the illumination models.
//!
//! Units. An environment map holds radiance `L` (Mitsuba's convention, unscaled). texmap's
//! light of 1 lights a white Lambertian surface facing it to 1, which is what a uniform
//! environment of radiance 1 does (irradiance π, reflected radiance ρ·π/π = ρ). So the
//! environment's diffuse light in texmap's units is the irradiance divided by π,
//!
//! ```text
//! I_env(N) = (1/π) ∫ L(ω) max(N·ω, 0) dω        (a uniform L gives I_env = L)
//! ```
//!
//! and a Lambertian albedo ρ under it reflects `ρ·I_env(N)` — exactly Mitsuba's `ρ·E/π`;
//! specular terms read radiance directly. Both are scaled by [`Environment::intensity`].
//!
//! What each model takes from the environment when one is given (in place of the uniform
//! ambient light `I_AL`):
//! - **Phong**: the ambient term `K_A·O·C·I_env(N)` (or `K_A·O·I_env(N)·map_Ka`); the
//!   reflection `K_R·I_R` with `I_R` the environment along `R = 2(N·V)N − V`, and the
//!   transmission `K_T·I_T` along the refracted direction `T` (index of refraction `ior`,
//!   entering the surface once) — when the material transmits, the two are blended by
//!   Schlick's Fresnel, `K_R·F·I_R + K_T·(1 − F)·C·I_T`, `F = f0 + (1 − f0)(1 − N·V)⁵`,
//!   `f0 = ((ior − 1)/(ior + 1))²`; a material that only reflects is a mirror of reflectance
//!   `K_R` (metals hardly follow a dielectric's Fresnel). Reflections and refractions are read
//!   at the material's roughness (0, a mirror, by default for Phong materials).
//! - **Metallic-roughness** (the split sum): diffuse `c_diff·(1 − E)·O·I_env(N)` and specular
//!   `E·O·P(R, roughness)` with `E = f0·A + B` the lobe's albedo ([`pbr::specular_albedo`],
//!   the table the uniform ambient already used) and `P` the environment prefiltered by the
//!   GGX lobe; `KHR_materials_transmission` moves the share `transmission` of the diffuse
//!   lobe to the refracted direction, `c_diff·(1 − E)·transmission·P(T, roughness)`. K_A does
//!   not scale image-based light: it was the stand-in for the environment glTF scenes lack.
//!
//! Prefiltering (once per environment, cached in the [`Environment`] for the run, rayon over
//! faces and rows): the map is resampled to a cube (face size ≤ 256, its own mip chain); the
//! irradiance is integrated exactly over the cube's 32×32 level into a 32×32 cube; the
//! specular lobe is prefiltered at roughness k/8, k = 1…8, by filtered importance sampling
//! (GGX half vectors from a Hammersley set, N = V = R, each sample read at the source level
//! its solid angle covers, weighted by N·L: Karis's split sum), into cubes of 128 down to 16
//! texels a side. Each derived cube stores a one-texel apron computed from the directions
//! beyond its edges, so bilinear reads are seamless with no neighbour lookup.
//!
//! Reads and their footprints. Mirror reads (roughness 0) go to the map itself through the
//! sampling engine with the reflected direction's footprint, so they filter like the base
//! colour. Rough reads interpolate the two prefiltered levels around the roughness (weights
//! linear in α², as GGX's tails grow), widened by the footprint (`α'² = α² + (w/2)²`, `w`
//! the reflected direction's angle across a pixel): a pixel seeing more of the environment
//! than the lobe does reads a blurrier level, which removes the sparkle at grazing angles.
//! Prefiltered faces have texels at most α/2 wide (128 texels at most).

use std::f32::consts::{FRAC_1_PI, PI, TAU};
use std::sync::{Arc, OnceLock};

use glam::{Mat3, Vec2, Vec3, Vec4};
use rayon::prelude::*;

use super::{pbr, Surface, Viewer};
use crate::texture::environment::EnvironmentMap;
use crate::texture::{
    sample_cube, CubeFootprint, Filter, Sampler, Texture2D, TextureCube, TextureOptions, Wrap,
};

/// Roughness levels prefiltered above the mirror: roughness `k/LEVELS`, `k = 1…LEVELS`.
pub const LEVELS: usize = 8;

/// What is drawn where no surface covers a pixel, when the scene has an environment.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Background {
    /// The environment along each pixel's ray.
    #[default]
    Environment,
    /// The scene's background colour.
    Color,
    /// Nothing: transparent black.
    None,
}

impl Background {
    /// The names [`Background::parse`] accepts.
    pub const SPELLINGS: &'static str = "env, color, none";

    /// `env`, `color` or `none`.
    #[must_use]
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "env" => Some(Background::Environment),
            "color" => Some(Background::Color),
            "none" => Some(Background::None),
            _ => None,
        }
    }

    /// The name [`Background::parse`] reads back.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Background::Environment => "env",
            Background::Color => "color",
            Background::None => "none",
        }
    }
}

/// A scene's environment: the map, how it is placed and how bright it is, what it is used
/// for, and its prefiltered forms (computed when first needed, then shared by every clone
/// and every frame).
///
/// ```
/// use texmap::shading::ibl::Environment;
/// use texmap::texture::{EnvironmentMap, Texture2D, TextureOptions};
/// let sky = Texture2D::from_fn(16, 8, TextureOptions::default(), |_, _| glam::Vec4::ONE).unwrap();
/// let env = Environment::new(EnvironmentMap::Equirect(sky), "sky")
///     .with_rotation_deg(90.0)
///     .with_intensity(0.5);
/// assert_eq!((env.rotation_deg, env.intensity), (90.0, 0.5));
/// ```
#[derive(Clone, Debug)]
#[non_exhaustive]
pub struct Environment {
    map: Arc<EnvironmentMap>,
    /// Where the map came from (a file name), for messages and `texmap info`.
    pub source: String,
    /// Degrees about +y: the content the map holds along `e` is seen along `R_y(θ)·e`.
    pub rotation_deg: f32,
    /// Multiplies every value read.
    pub intensity: f32,
    pub background: Background,
    /// Image-based light (irradiance and the split-sum specular) in place of the uniform
    /// ambient light; off, the scene's `ambient_light` lights as without an environment.
    pub ibl: bool,
    /// Reflection and refraction terms (Phong `K_R`, `K_T`; metallic-roughness transmission).
    pub reflections: bool,
    /// How the map itself is read (mirror reflections, refractions, the background):
    /// trilinear by default; the wrap modes are the layout's own.
    pub sampler: Sampler,
    cache: Arc<Cache>,
}

#[derive(Debug, Default)]
struct Cache {
    source: OnceLock<TextureCube>,
    irradiance: OnceLock<FaceSet>,
    specular: OnceLock<Vec<FaceSet>>,
}

impl Environment {
    /// `map` unrotated at intensity 1, drawn as the background, lighting by IBL, reflected and
    /// refracted; `source` names it in messages.
    #[must_use]
    pub fn new(map: EnvironmentMap, source: impl Into<String>) -> Self {
        Environment {
            map: Arc::new(map),
            source: source.into(),
            rotation_deg: 0.0,
            intensity: 1.0,
            background: Background::Environment,
            ibl: true,
            reflections: true,
            sampler: Sampler::new(Filter::TRILINEAR, Wrap::Repeat),
            cache: Arc::default(),
        }
    }

    /// The map.
    #[must_use]
    pub fn map(&self) -> &EnvironmentMap {
        &self.map
    }

    /// This environment with another map (and a fresh cache), the rest kept.
    #[must_use]
    pub fn with_map(mut self, map: EnvironmentMap, source: impl Into<String>) -> Self {
        self.map = Arc::new(map);
        self.source = source.into();
        self.cache = Arc::default();
        self
    }
    #[must_use]
    pub fn with_rotation_deg(mut self, degrees: f32) -> Self {
        self.rotation_deg = degrees;
        self
    }
    #[must_use]
    pub fn with_intensity(mut self, intensity: f32) -> Self {
        self.intensity = intensity;
        self
    }
    #[must_use]
    pub fn with_background(mut self, background: Background) -> Self {
        self.background = background;
        self
    }
    #[must_use]
    pub fn with_ibl(mut self, on: bool) -> Self {
        self.ibl = on;
        self
    }
    #[must_use]
    pub fn with_reflections(mut self, on: bool) -> Self {
        self.reflections = on;
        self
    }
    #[must_use]
    pub fn with_sampler(mut self, sampler: Sampler) -> Self {
        self.sampler = sampler;
        self
    }

    /// The map resampled to a cube in world directions (face size ≤ 256, mipmapped): what the
    /// prefilters read.
    fn source_cube(&self) -> &TextureCube {
        self.cache.source.get_or_init(|| source_cube(&self.map))
    }

    /// The irradiance cube, `I_env` of the module docs (unscaled), computed on first use.
    #[must_use]
    pub fn irradiance(&self) -> &FaceSet {
        self.cache
            .irradiance
            .get_or_init(|| irradiance_cube(self.source_cube(), 32))
    }

    /// The specular levels at roughness `k/LEVELS`, `k = 1…LEVELS`, computed on first use.
    #[must_use]
    pub fn specular_levels(&self) -> &[FaceSet] {
        self.cache
            .specular
            .get_or_init(|| specular_levels(self.source_cube()))
    }

    /// Computes every prefiltered form now (the renderer otherwise does it on first use).
    pub fn prefilter(&self) {
        let _ = self.irradiance();
        let _ = self.specular_levels();
    }

    /// Checks the values: finite rotation, a finite intensity ≥ 0.
    ///
    /// # Errors
    /// [`crate::Error::Parameter`] naming the bad value.
    pub fn validate(&self) -> crate::Result<()> {
        if !self.rotation_deg.is_finite() {
            return Err(crate::Error::parameter(format!(
                "environment rotation {} is not finite",
                self.rotation_deg
            )));
        }
        if !(self.intensity.is_finite() && self.intensity >= 0.0) {
            return Err(crate::Error::parameter(format!(
                "environment intensity {} must be finite and ≥ 0",
                self.intensity
            )));
        }
        Ok(())
    }
}

/// Six square faces of `n × n` linear RGB values with a one-texel apron, read bilinearly and
/// seamlessly by direction (faces in OpenGL's order and orientation, world directions).
#[derive(Clone, Debug)]
pub struct FaceSet {
    n: usize,
    /// Per face `(n + 2)²` values, row-major, the apron around the face's own `n × n`.
    texels: Vec<Vec3>,
}

/// The face a direction hits, and its face coordinates `(sc, tc)/|ma|` in [−1, 1]
/// (OpenGL's table 8.19, as `texture::TextureCube`).
#[inline]
fn face_coords(d: Vec3) -> (usize, f32, f32) {
    let a = d.abs();
    let (f, s, t, m) = if a.x >= a.y && a.x >= a.z {
        if d.x >= 0.0 {
            (0, -d.z, -d.y, a.x)
        } else {
            (1, d.z, -d.y, a.x)
        }
    } else if a.y >= a.z {
        if d.y >= 0.0 {
            (2, d.x, d.z, a.y)
        } else {
            (3, d.x, -d.z, a.y)
        }
    } else if d.z >= 0.0 {
        (4, d.x, -d.y, a.z)
    } else {
        (5, -d.x, -d.y, a.z)
    };
    let inv = if m > 0.0 { 1.0 / m } else { 0.0 };
    (f, s * inv, t * inv)
}

/// The direction through face coordinates `(sc, tc)` of `face` (outside [−1, 1] on the
/// face's extended plane).
#[inline]
fn face_direction(face: usize, sc: f32, tc: f32) -> Vec3 {
    match face {
        0 => Vec3::new(1.0, -tc, -sc),
        1 => Vec3::new(-1.0, -tc, sc),
        2 => Vec3::new(sc, 1.0, tc),
        3 => Vec3::new(sc, -1.0, -tc),
        4 => Vec3::new(sc, -tc, 1.0),
        _ => Vec3::new(-sc, -tc, -1.0),
    }
}

impl FaceSet {
    /// Evaluates `f` at the direction through every texel centre (apron included), in
    /// parallel.
    pub fn from_fn(n: usize, f: impl Fn(Vec3) -> Vec3 + Sync) -> Self {
        let m = n + 2;
        let mut texels = vec![Vec3::ZERO; 6 * m * m];
        texels.par_chunks_mut(m).enumerate().for_each(|(row, out)| {
            let (face, y) = (row / m, row % m);
            let tc = 2.0 * (y as f32 - 0.5) / n as f32 - 1.0;
            for (x, o) in out.iter_mut().enumerate() {
                let sc = 2.0 * (x as f32 - 0.5) / n as f32 - 1.0;
                *o = f(face_direction(face, sc, tc).normalize());
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
    pub fn read(&self, d: Vec3) -> Vec3 {
        let (f, sc, tc) = face_coords(d);
        let n = self.n as f32;
        let m = self.n + 2;
        // Texel centre i sits at face coordinate 2(i + ½)/n − 1; the apron shifts by one.
        let x = ((sc + 1.0) * 0.5 * n + 0.5).clamp(0.0, n + 1.0);
        let y = ((tc + 1.0) * 0.5 * n + 0.5).clamp(0.0, n + 1.0);
        let (x0, y0) = ((x as usize).min(self.n), (y as usize).min(self.n));
        let (fx, fy) = (x - x0 as f32, y - y0 as f32);
        let base = f * m * m + y0 * m + x0;
        let t = &self.texels[base..base + m + 2];
        let top = t[0].lerp(t[1], fx);
        let bottom = t[m].lerp(t[m + 1], fx);
        top.lerp(bottom, fy)
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

/// The map resampled to a world-direction cube of face size `min(256, the map's own
/// density)`, each texel read with its footprint, mipmapped.
fn source_cube(map: &EnvironmentMap) -> TextureCube {
    let density = (map.texels_per_steradian() * 4.0 * PI / 6.0).sqrt();
    let n = (density.max(16.0) as u32).next_power_of_two().min(256);
    let sampler = Sampler::new(Filter::TRILINEAR, Wrap::ClampToEdge);
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
                            let dir = face_direction(face, sc, tc);
                            let fp = CubeFootprint {
                                dir,
                                ddir_dx: face_direction(face, sc + step, tc) - dir,
                                ddir_dy: face_direction(face, sc, tc + step) - dir,
                            };
                            let c = map.sample(&sampler, &fp);
                            c.truncate().extend(1.0)
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
fn irradiance_cube(source: &TextureCube, n: usize) -> FaceSet {
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
                let d = face_direction(face, sc, tc).normalize();
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
fn specular_levels(source: &TextureCube) -> Vec<FaceSet> {
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
                    let lod = (0.5 * (omega / texel_omega).log2() + 1.0).clamp(0.0, levels - 1.0);
                    (h, lod)
                })
                .collect();
            FaceSet::from_fn(n, |normal| {
                let (t, b) = orthonormal_basis(normal);
                let mut sum = Vec3::ZERO;
                let mut weight = 0.0;
                for &(h, lod) in &taps {
                    let h = t * h.x + b * h.y + normal * h.z;
                    let l = h * (2.0 * normal.dot(h)) - normal;
                    let n_dot_l = normal.dot(l);
                    if n_dot_l <= 0.0 {
                        continue;
                    }
                    let s =
                        Sampler::new(Filter::TRILINEAR, Wrap::ClampToEdge).with_lod_clamp(lod, lod);
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

/// The environment as one frame reads it: rotation, intensity and the prefiltered forms
/// resolved.
#[derive(Clone, Copy, Debug)]
pub struct EnvLight<'a> {
    pub env: &'a Environment,
    /// World → map directions (the inverse of the map's rotation).
    pub env_from_world: Mat3,
    /// `None` unless image-based light is on and some draw needs it.
    pub irradiance: Option<&'a FaceSet>,
    pub specular: Option<&'a [FaceSet]>,
    /// How the map itself is read: the environment's sampler, with any overrides of the
    /// frame laid over it (the wrap modes stay the layout's).
    pub sampler: Sampler,
}

impl<'a> EnvLight<'a> {
    /// `env` for a frame; `diffuse` and `specular` say which prefiltered forms the frame's
    /// draws read (computed now if not cached).
    #[must_use]
    pub fn new(env: &'a Environment, diffuse: bool, specular: bool) -> Self {
        EnvLight {
            env,
            env_from_world: Mat3::from_rotation_y(-env.rotation_deg.to_radians()),
            irradiance: diffuse.then(|| env.irradiance()),
            specular: specular.then(|| env.specular_levels()),
            sampler: env.sampler,
        }
    }

    /// `I_env(N)` (irradiance / π, times the intensity) for a world normal.
    #[inline]
    #[must_use]
    pub fn irradiance(&self, n: Vec3) -> Vec3 {
        match self.irradiance {
            Some(f) => f.read(self.env_from_world * n) * self.env.intensity,
            None => Vec3::ZERO,
        }
    }

    /// The map itself along a world-direction footprint (the background, mirror reflections),
    /// times the intensity: linear RGB.
    #[inline]
    #[must_use]
    pub fn mirror(&self, fp: &CubeFootprint) -> Vec3 {
        let m = self.env_from_world;
        let local = CubeFootprint {
            dir: m * fp.dir,
            ddir_dx: m * fp.ddir_dx,
            ddir_dy: m * fp.ddir_dy,
        };
        self.env.map.sample(&self.sampler, &local).truncate() * self.env.intensity
    }

    /// The environment seen through a GGX lobe of `roughness` around the world-direction
    /// footprint `fp` (its derivatives widen the lobe; module docs): the map itself at
    /// roughness 0, else the prefiltered levels.
    #[inline]
    #[must_use]
    pub fn radiance(&self, fp: &CubeFootprint, roughness: f32) -> Vec3 {
        let roughness = roughness.clamp(0.0, 1.0);
        let Some(levels) = self.specular.filter(|_| roughness > 0.0) else {
            return self.mirror(fp);
        };
        // The footprint's angle (the direction is unit length), as a lobe of α = w/2.
        let w2 = fp.ddir_dx.length_squared().max(fp.ddir_dy.length_squared());
        let a2 = roughness.powi(4) + 0.25 * w2;
        let r = a2.sqrt().sqrt().min(1.0);
        let k = ((r * LEVELS as f32) as usize).min(LEVELS - 1);
        // The blend of levels k and k + 1 is linear in α² (not in roughness): GGX's tails
        // grow as α², so this weighting keeps the blurred light a lobe spreads as the lobe
        // of this roughness does (linear in roughness, a roughness-0.3 metal was 26% too
        // bright where a bright sky leaks into its reflection of the ground).
        let a2_at = |k: usize| (k as f32 / LEVELS as f32).powi(4);
        let frac = ((a2.min(1.0) - a2_at(k)) / (a2_at(k + 1) - a2_at(k))).clamp(0.0, 1.0);
        let dir = self.env_from_world * fp.dir;
        let intensity = self.env.intensity;
        let lower = if k == 0 {
            self.mirror(fp)
        } else {
            levels[k - 1].read(dir) * intensity
        };
        if frac <= 0.0 {
            return lower;
        }
        lower.lerp(levels[k].read(dir) * intensity, frac)
    }

    /// The background along a world-direction footprint: premultiplied RGBA, alpha 1.
    #[must_use]
    pub fn background(&self, fp: &CubeFootprint) -> Vec4 {
        self.mirror(fp).extend(1.0)
    }
}

/// The material's environment parameters beside its [`Surface`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnvMaterial {
    /// K_R (Phong).
    pub reflection: f32,
    /// K_T (Phong) or `KHR_materials_transmission`'s factor (metallic-roughness), after its
    /// map.
    pub transmission: f32,
    /// The roughness the Phong reflection and transmission are read at.
    pub phong_roughness: f32,
}

/// Where a pixel looks into the environment: the reflected and refracted directions with
/// their screen derivatives.
#[derive(Clone, Copy, Debug, Default)]
pub struct EnvRays {
    pub reflected: CubeFootprint,
    pub refracted: CubeFootprint,
}

/// The unit reflection of the view direction: `R = 2(N·V)N − V`.
#[inline]
#[must_use]
pub fn reflect(n: Vec3, v: Vec3) -> Vec3 {
    n * (2.0 * n.dot(v)) - v
}

/// The direction of the ray from the eye (`−V`) refracted into the surface (`N` towards the
/// viewer, `ior` inside over outside): Snell's law; total internal reflection returns the
/// reflection.
#[inline]
#[must_use]
pub fn refract(n: Vec3, v: Vec3, ior: f32) -> Vec3 {
    let eta = 1.0 / ior.max(1e-3);
    let cos_i = n.dot(v).clamp(-1.0, 1.0);
    let k = 1.0 - eta * eta * (1.0 - cos_i * cos_i);
    if k < 0.0 {
        return reflect(n, v);
    }
    (-v * eta + n * (eta * cos_i - k.sqrt())).normalize_or_zero()
}

/// f0 of a dielectric of index of refraction `ior` in air: `((ior − 1)/(ior + 1))²`
/// ([`pbr::DIELECTRIC_F0`] exactly at 1.5).
#[inline]
#[must_use]
pub fn dielectric_f0(ior: f32) -> f32 {
    if ior == 1.5 {
        return pbr::DIELECTRIC_F0;
    }
    let r = (ior - 1.0) / (ior + 1.0);
    r * r
}

/// The factors `(D, S)` the environment adds at surface `s` seen by `viewer` (the lit colour
/// being `C·D + S`): the module docs' terms for `model`.
#[must_use]
pub fn environment_terms(
    model: super::ShadingModel,
    s: &Surface,
    m: &EnvMaterial,
    viewer: Viewer,
    rays: &EnvRays,
    light: &EnvLight,
) -> (Vec3, Vec3) {
    let env = light.env;
    let n = s.normal;
    let v = viewer.towards(s.position);
    let n_dot_v = n.dot(v).max(1e-4);
    let mut d = Vec3::ZERO;
    let mut sp = Vec3::ZERO;
    match model {
        super::ShadingModel::Phong => {
            if env.ibl {
                let ambient = light.irradiance(n) * (s.ambient * s.occlusion);
                match s.ambient_color {
                    None => d += ambient,
                    Some(a) => sp += ambient * a,
                }
            }
            if env.reflections && (m.reflection > 0.0 || m.transmission > 0.0) {
                let reflected = if m.reflection > 0.0 {
                    light.radiance(&rays.reflected, m.phong_roughness)
                } else {
                    Vec3::ZERO
                };
                if m.transmission > 0.0 {
                    let f = pbr::fresnel(Vec3::splat(dielectric_f0(s.ior)), n_dot_v).x;
                    let through = light.radiance(&rays.refracted, m.phong_roughness);
                    sp += reflected * (m.reflection * f) * s.specular_color;
                    d += through * (m.transmission * (1.0 - f));
                } else {
                    sp += reflected * m.reflection * s.specular_color;
                }
            }
        }
        super::ShadingModel::MetallicRoughness => {
            let metallic = s.metallic.clamp(0.0, 1.0);
            let f0 = Vec3::splat(dielectric_f0(s.ior)).lerp(s.base_color, metallic);
            let roughness = s.roughness.clamp(0.0, 1.0);
            let ab = pbr::specular_albedo(n_dot_v, pbr::alpha(roughness).sqrt());
            let e = f0 * ab.x + Vec3::splat(ab.y);
            let diffuse = (Vec3::ONE - e) * (1.0 - metallic);
            let transmission = if env.reflections {
                m.transmission.clamp(0.0, 1.0)
            } else {
                0.0
            };
            if env.ibl {
                d += light.irradiance(n) * diffuse * (s.occlusion * (1.0 - transmission));
                sp += light.radiance(&rays.reflected, roughness) * e * s.occlusion;
            }
            if transmission > 0.0 {
                d += light.radiance(&rays.refracted, roughness) * diffuse * transmission;
            }
        }
    }
    (d, sp)
}

/// Rays for a point with no neighbours (Gouraud vertices, flat faces): directions without
/// derivatives.
#[must_use]
pub fn point_rays(s: &Surface, viewer: Viewer) -> EnvRays {
    let v = viewer.towards(s.position);
    EnvRays {
        reflected: CubeFootprint {
            dir: reflect(s.normal, v),
            ..Default::default()
        },
        refracted: CubeFootprint {
            dir: refract(s.normal, v, s.ior),
            ..Default::default()
        },
    }
}

/// The lobe-widening angle a footprint stands for, for tests and diagnostics: the longer of
/// the direction's two derivatives.
#[must_use]
pub fn footprint_angle(fp: &CubeFootprint) -> f32 {
    Vec2::new(fp.ddir_dx.length(), fp.ddir_dy.length()).max_element()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shading::{Material, ShadingModel};

    fn uniform(c: Vec3) -> Environment {
        let t =
            Texture2D::from_fn(64, 32, TextureOptions::default(), |_, _| c.extend(1.0)).unwrap();
        Environment::new(EnvironmentMap::Equirect(t), "uniform")
    }

    /// A panorama lit by a small bright disc around `sun` (radius 5°) over a dim sky.
    fn sun_env(sun: Vec3) -> Environment {
        let (w, h) = (256, 128);
        let t = Texture2D::from_fn(w, h, TextureOptions::default(), |x, y| {
            let u = (x as f32 + 0.5) / w as f32;
            let v = y as f32 / (h - 1) as f32;
            let d = crate::texture::environment::equirect_direction(u, v);
            let c = if d.dot(sun) > 5f32.to_radians().cos() {
                100.0
            } else {
                0.1
            };
            Vec4::new(c, c, c, 1.0)
        })
        .unwrap();
        Environment::new(EnvironmentMap::Equirect(t), "sun")
    }

    #[test]
    fn a_uniform_environment_is_a_uniform_ambient_light_of_its_radiance() {
        // The furnace: radiance 0.7 everywhere gives I_env = 0.7 for every normal, and every
        // prefiltered level reads 0.7.
        let env = uniform(Vec3::splat(0.7));
        let light = EnvLight::new(&env, true, true);
        for n in [Vec3::X, -Vec3::Y, Vec3::new(0.3, 0.5, -0.8).normalize()] {
            let e = light.irradiance(n);
            assert!(
                (e - Vec3::splat(0.7)).abs().max_element() < 2e-3,
                "{n}: {e}"
            );
            for r in [0.1, 0.3, 0.55, 1.0] {
                let fp = CubeFootprint {
                    dir: n,
                    ..Default::default()
                };
                let l = light.radiance(&fp, r);
                assert!(
                    (l - Vec3::splat(0.7)).abs().max_element() < 2e-3,
                    "{r}: {l}"
                );
            }
        }
    }

    #[test]
    fn irradiance_of_a_small_sun_follows_the_cosine_law() {
        // A disc of radiance 100 and solid angle 2π(1 − cos 5°) over a sky of 0.1: facing it,
        // I_env = (100 − 0.1)·Ω·cos/π + 0.1.
        let sun = Vec3::new(0.3, 0.8, -0.5).normalize();
        let env = sun_env(sun);
        let light = EnvLight::new(&env, true, false);
        let omega = TAU * (1.0 - 5f32.to_radians().cos());
        for angle in [0.0f32, 30.0, 60.0] {
            // A normal `angle` degrees from the sun.
            let axis = sun.cross(Vec3::Y).normalize();
            let n = Mat3::from_axis_angle(axis, angle.to_radians()) * sun;
            let want = (100.0 - 0.1) * omega * angle.to_radians().cos() / PI + 0.1;
            let got = light.irradiance(n).x;
            assert!(
                (got - want).abs() < 0.02 * want,
                "{angle}°: {got} vs {want}"
            );
        }
    }

    #[test]
    fn rough_levels_blur_the_sun_and_keep_its_energy() {
        let sun = Vec3::new(0.0, 0.6, -0.8).normalize();
        let env = sun_env(sun);
        let light = EnvLight::new(&env, false, true);
        let at = |d: Vec3, r: f32| {
            light
                .radiance(
                    &CubeFootprint {
                        dir: d,
                        ..Default::default()
                    },
                    r,
                )
                .x
        };
        // Towards the sun the peak falls as the lobe widens; 25° away it rises.
        let away = Mat3::from_rotation_x(25f32.to_radians()) * sun;
        let (p3, p6, p9) = (at(sun, 0.3), at(sun, 0.6), at(sun, 0.9));
        assert!(p3 > p6 && p6 > p9, "{p3} {p6} {p9}");
        assert!(
            at(away, 0.9) > at(away, 0.3),
            "{} {}",
            at(away, 0.9),
            at(away, 0.3)
        );
        // A wide footprint reads a blurrier level than a point.
        let wide = CubeFootprint {
            dir: sun,
            ddir_dx: Vec3::new(0.5, 0.0, 0.0),
            ddir_dy: Vec3::ZERO,
        };
        assert!(light.radiance(&wide, 0.3).x < p3);
    }

    #[test]
    fn refraction_follows_snell_and_reflection_the_mirror_law() {
        let n = Vec3::Y;
        let v = Vec3::new(1.0, 1.0, 0.0).normalize();
        let r = reflect(n, v);
        assert!((r - Vec3::new(-1.0, 1.0, 0.0).normalize()).length() < 1e-6);
        let t = refract(n, v, 1.5);
        // sin θt = sin 45° / 1.5.
        let sin_t = t.x.abs() / t.length();
        assert!((sin_t - 45f32.to_radians().sin() / 1.5).abs() < 1e-5, "{t}");
        assert!(t.y < 0.0 && t.x < 0.0);
        // Head-on the ray goes straight through.
        assert!((refract(n, n, 1.5) + n).length() < 1e-6);
        assert_eq!(dielectric_f0(1.5), pbr::DIELECTRIC_F0);
    }

    #[test]
    fn phong_mirror_and_glass_weights() {
        let env = uniform(Vec3::splat(2.0));
        let light = EnvLight::new(&env, true, true);
        let mut m = Material {
            ambient: 0.0,
            ..Default::default()
        };
        m.ior = 1.5;
        let s = Surface::new(&m, Vec3::ZERO, Vec3::Z);
        let viewer = Viewer::Point(Vec3::Z * 3.0);
        let rays = point_rays(&s, viewer);
        let mirror = EnvMaterial {
            reflection: 1.0,
            transmission: 0.0,
            phong_roughness: 0.0,
        };
        let (d, sp) = environment_terms(ShadingModel::Phong, &s, &mirror, viewer, &rays, &light);
        assert_eq!(d, Vec3::ZERO);
        assert!((sp - Vec3::splat(2.0)).abs().max_element() < 1e-5, "{sp}");
        // Glass head-on: 4% reflected, 96% transmitted, summing to the environment.
        let glass = EnvMaterial {
            transmission: 1.0,
            ..mirror
        };
        let (d, sp) = environment_terms(ShadingModel::Phong, &s, &glass, viewer, &rays, &light);
        assert!(
            (sp.x - 0.08).abs() < 1e-4 && (d.x - 1.92).abs() < 1e-4,
            "{d} {sp}"
        );
    }
}
