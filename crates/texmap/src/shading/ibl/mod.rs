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
//!   `E·O·P(R, roughness)` with `E = f0·A + B` the lobe's albedo
//!   ([`specular_albedo`](crate::shading::pbr::specular_albedo), the table the uniform
//!   ambient already used) and `P` the environment prefiltered by the
//!   GGX lobe; `KHR_materials_transmission` moves the share `transmission` of the diffuse
//!   lobe to the refracted direction, `c_diff·(1 − E)·transmission·P(T, roughness)`. K_A does
//!   not scale image-based light: it was the stand-in for the environment glTF scenes lack.
//!
//! Prefiltering (once per environment, cached in the [`Environment`] for the run, rayon over
//! faces and rows): the map is resampled to a cube (face size ≤ 256, its own mip chain); the
//! irradiance is integrated exactly over the cube's 32×32 level into a 32×32 cube; the
//! specular lobe is prefiltered at roughness k/8, k = 1…8, by filtered importance sampling
//! (GGX half vectors from a Hammersley set, N = V = R, each sample read at the source level
//! its solid angle covers with no extra level of blur, weighted by N·L: Karis's split sum),
//! into cubes of 128 down to 16 texels a side; when a material has a sheen
//! (`KHR_materials_sheen`), the same at sheen roughness k/8 with the Charlie lobe (half
//! vectors from `D(N·H)·N·H`, only those within 45° of N, which reflect above the surface; 16-texel
//! faces, 128 samples: the glTF sample viewer's sheen filter), read along the reflected
//! direction and scaled by the sheen's albedo. Each derived cube stores a one-texel apron computed from the directions
//! beyond its edges, so bilinear reads are seamless with no neighbour lookup.
//!
//! Reads and their footprints. Mirror reads (roughness 0) go to the map itself through the
//! sampling engine with the reflected direction's footprint, so they filter like the base
//! colour. Under roughness 1/8 a rough read blends the mirror with the first GGX level; there
//! the mirror is read from the [`MirrorCube`] (the map resampled to a mipmapped cube at its
//! own density, read trilinearly with the same footprint rule), several times cheaper than the
//! map's generic read, when the map's sampler is trilinear (any other filter the user asks
//! for reads the map itself). Rough reads interpolate the two prefiltered levels around the roughness (weights
//! linear in α², as GGX's tails grow), widened by the footprint (`α'² = α² + (w/2)²`, `w`
//! the reflected direction's angle across a pixel): a pixel seeing more of the environment
//! than the lobe does reads a blurrier level, which removes the sparkle at grazing angles.
//! Prefiltered faces have texels at most α/2 wide (128 texels at most).

//!
//! Files: `mod.rs` (the [`Environment`] and its cache), `prefilter.rs` (the irradiance and
//! GGX-prefiltered cubes), `terms.rs` (what a surface takes from the environment).

use std::sync::{Arc, OnceLock};

use crate::texture::environment::EnvironmentMap;
use crate::texture::{Filter, Sampler, TextureCube, Wrap};

mod prefilter;
mod terms;
use prefilter::{irradiance_cube, sheen_levels, source_cube, specular_levels};
#[cfg(test)]
mod tests;

pub use prefilter::{FaceSet, MirrorCube};
pub use terms::*;

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
    sheen: OnceLock<Vec<FaceSet>>,
    mirror: OnceLock<MirrorCube>,
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

    /// The sheen levels, the map prefiltered by the Charlie lobe at sheen roughness
    /// `k/LEVELS`, `k = 1…LEVELS` (module docs), computed on first use.
    #[must_use]
    pub fn sheen_levels(&self) -> &[FaceSet] {
        self.cache
            .sheen
            .get_or_init(|| sheen_levels(self.source_cube()))
    }

    /// The map as a [`MirrorCube`] (the sharp end of the specular reads), computed on first
    /// use.
    #[must_use]
    pub fn mirror_cube(&self) -> &MirrorCube {
        self.cache.mirror.get_or_init(|| MirrorCube::new(&self.map))
    }

    /// Computes every prefiltered form now (the renderer otherwise does it on first use).
    pub fn prefilter(&self) {
        let _ = self.irradiance();
        let _ = self.specular_levels();
        let _ = self.sheen_levels();
        let _ = self.mirror_cube();
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
