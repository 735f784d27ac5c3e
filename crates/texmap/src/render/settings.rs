//! How a frame is made, apart from the scene and the camera: size, interpolation, shading,
//! visibility, anti-aliasing, the user's texture choices laid over every texture read, and
//! the user's shadow choices laid over the scene's.

use glam::Vec4;

use super::shadow::ShadowOverrides;
use crate::pipeline::{CullMode, Interpolation};
use crate::texture::{Filter, LodRule, Sampler, Wrap};
use crate::{Error, Result};

/// Where lighting is evaluated.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum ShadingMode {
    /// Once per triangle, at its centroid with the geometric normal.
    Flat,
    /// Per vertex, interpolated (the texture is still applied per pixel).
    Gouraud,
    /// Per pixel with the interpolated, renormalized normal.
    #[default]
    Phong,
}

/// How hidden surfaces are removed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Visibility {
    /// A per-sample `f32` depth buffer (test `LESS`).
    #[default]
    ZBuffer,
    /// Painter's algorithm: triangles drawn back to front by their farthest vertex, no depth
    /// buffer (wrong where triangles intersect or overlap cyclically).
    DepthSort,
}

/// Sampler state laid over every image-texture read of a frame (base colour, every material
/// map, projected and 3D solid textures): each field that is set replaces the texture's own.
/// The command line's `--filter`, `--wrap`, `--lod-bias`, `--lod-rule`, `--min-lod`,
/// `--max-lod` and `--border` fill it, whatever the scene came from.
///
/// ```
/// use texmap::render::TextureOverrides;
/// use texmap::texture::{Filter, Sampler};
/// let o = TextureOverrides::default().with_filter(Filter::NEAREST).with_lod_bias(1.0);
/// let s = o.apply(Sampler::default());
/// assert_eq!((s.filter, s.lod_bias), (Filter::NEAREST, 1.0));
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Default)]
#[non_exhaustive]
pub struct TextureOverrides {
    pub filter: Option<Filter>,
    /// Every axis.
    pub wrap: Option<Wrap>,
    pub lod_bias: Option<f32>,
    pub lod_rule: Option<LodRule>,
    pub min_lod: Option<f32>,
    pub max_lod: Option<f32>,
    /// Linear, premultiplied, read outside the image with [`Wrap::ClampToBorder`].
    pub border: Option<Vec4>,
}

impl TextureOverrides {
    #[must_use]
    pub fn with_filter(mut self, filter: Filter) -> Self {
        self.filter = Some(filter);
        self
    }
    #[must_use]
    pub fn with_wrap(mut self, wrap: Wrap) -> Self {
        self.wrap = Some(wrap);
        self
    }
    #[must_use]
    pub fn with_lod_bias(mut self, bias: f32) -> Self {
        self.lod_bias = Some(bias);
        self
    }
    #[must_use]
    pub fn with_lod_rule(mut self, rule: LodRule) -> Self {
        self.lod_rule = Some(rule);
        self
    }
    #[must_use]
    pub fn with_min_lod(mut self, lod: f32) -> Self {
        self.min_lod = Some(lod);
        self
    }
    #[must_use]
    pub fn with_max_lod(mut self, lod: f32) -> Self {
        self.max_lod = Some(lod);
        self
    }
    #[must_use]
    pub fn with_border(mut self, premultiplied: Vec4) -> Self {
        self.border = Some(premultiplied);
        self
    }

    /// True when nothing is overridden.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        *self == TextureOverrides::default()
    }

    /// `sampler` with every set field replaced.
    #[must_use]
    pub fn apply(&self, mut sampler: Sampler) -> Sampler {
        if let Some(f) = self.filter {
            sampler.filter = f;
        }
        if let Some(w) = self.wrap {
            sampler.wrap_u = w;
            sampler.wrap_v = w;
            sampler.wrap_w = w;
        }
        if let Some(b) = self.lod_bias {
            sampler.lod_bias = b;
        }
        if let Some(r) = self.lod_rule {
            sampler.lod_rule = r;
        }
        if let Some(l) = self.min_lod {
            sampler.min_lod = l;
        }
        if let Some(l) = self.max_lod {
            sampler.max_lod = l;
        }
        if let Some(b) = self.border {
            sampler.border = b;
        }
        sampler
    }

    /// Checks the values: finite bias and levels, `min_lod ≤ max_lod`, a finite border in
    /// [0, 1] with colour ≤ alpha (premultiplied).
    ///
    /// # Errors
    /// [`Error::Parameter`] naming the first bad value.
    pub fn validate(&self) -> Result<()> {
        for (name, v) in [
            ("lod bias", self.lod_bias),
            ("min lod", self.min_lod),
            ("max lod", self.max_lod),
        ] {
            if let Some(v) = v {
                if !v.is_finite() {
                    return Err(Error::parameter(format!("{name} {v} is not finite")));
                }
            }
        }
        if let (Some(lo), Some(hi)) = (self.min_lod, self.max_lod) {
            if lo > hi {
                return Err(Error::parameter(format!(
                    "min lod {lo} is above max lod {hi}"
                )));
            }
        }
        if let Some(b) = self.border {
            let ok = b.is_finite()
                && b.cmpge(Vec4::ZERO).all()
                && b.w <= 1.0
                && b.truncate().max_element() <= b.w;
            if !ok {
                return Err(Error::parameter(format!(
                    "border colour {b} is not premultiplied RGBA in [0, 1]"
                )));
            }
        }
        if let Some(Filter::Anisotropic { max_aniso, .. }) = self.filter {
            if !(1..=16).contains(&max_aniso) {
                return Err(Error::parameter(format!(
                    "anisotropy {max_aniso} is outside 1..=16"
                )));
            }
        }
        Ok(())
    }
}

/// Everything about how a frame is made, apart from the scene and the camera.
///
/// Start from [`Settings::new`] (or `Default`, 640×360) and set what differs; new fields get
/// defaults, so callers do not break:
///
/// ```
/// use texmap::render::{Settings, ShadingMode};
/// let s = Settings::new(320, 240).with_msaa(4).with_shading(ShadingMode::Gouraud);
/// assert!(s.validate().is_ok());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct Settings {
    pub width: u32,
    pub height: u32,
    pub interpolation: Interpolation,
    pub shading: ShadingMode,
    pub visibility: Visibility,
    /// Applies to single-sided materials; double-sided ones are never culled. `None` leaves
    /// it to each material ([`crate::shading::Material::cull`]: back faces for glTF's
    /// single-sided materials, as its specification says; none for OBJ and TOML unless the
    /// scene says otherwise).
    pub cull: Option<CullMode>,
    /// MSAA samples per pixel: 1, 2, 4, 8 or 16 (Direct3D's standard positions).
    pub msaa: u32,
    /// Supersampling: render at N× the size in each direction and box-filter (1..=8).
    pub ssaa: u32,
    /// Ignore lights: colour = base colour × texture × vertex colour.
    pub unlit: bool,
    /// Laid over every texture's sampler.
    pub textures: TextureOverrides,
    /// Laid over the scene's shadows (which lights cast, the maps' size, filter and biases).
    pub shadows: ShadowOverrides,
}

impl Default for Settings {
    fn default() -> Self {
        Settings::new(640, 360)
    }
}

/// The largest width or height accepted.
pub const MAX_SIZE: u32 = 16384;

impl Settings {
    /// A `width × height` frame: perspective-correct, Phong-shaded, z-buffered, culled as each
    /// material says,
    /// one sample per pixel, lit, every texture read as its own sampler says, shadows as the
    /// scene says.
    #[must_use]
    pub fn new(width: u32, height: u32) -> Self {
        Settings {
            width,
            height,
            interpolation: Interpolation::Perspective,
            shading: ShadingMode::Phong,
            visibility: Visibility::ZBuffer,
            cull: None,
            msaa: 1,
            ssaa: 1,
            unlit: false,
            textures: TextureOverrides::default(),
            shadows: ShadowOverrides::default(),
        }
    }
    #[must_use]
    pub fn with_size(mut self, width: u32, height: u32) -> Self {
        (self.width, self.height) = (width, height);
        self
    }
    #[must_use]
    pub fn with_interpolation(mut self, interpolation: Interpolation) -> Self {
        self.interpolation = interpolation;
        self
    }
    #[must_use]
    pub fn with_shading(mut self, shading: ShadingMode) -> Self {
        self.shading = shading;
        self
    }
    #[must_use]
    pub fn with_visibility(mut self, visibility: Visibility) -> Self {
        self.visibility = visibility;
        self
    }
    #[must_use]
    pub fn with_cull(mut self, cull: CullMode) -> Self {
        self.cull = Some(cull);
        self
    }
    #[must_use]
    pub fn with_msaa(mut self, samples: u32) -> Self {
        self.msaa = samples;
        self
    }
    #[must_use]
    pub fn with_ssaa(mut self, factor: u32) -> Self {
        self.ssaa = factor;
        self
    }
    #[must_use]
    pub fn with_unlit(mut self, unlit: bool) -> Self {
        self.unlit = unlit;
        self
    }
    #[must_use]
    pub fn with_textures(mut self, textures: TextureOverrides) -> Self {
        self.textures = textures;
        self
    }
    #[must_use]
    pub fn with_shadows(mut self, shadows: ShadowOverrides) -> Self {
        self.shadows = shadows;
        self
    }

    /// Checks the values: size in 1..=16384, msaa ∈ {1, 2, 4, 8, 16}, ssaa in 1..=8 with the
    /// supersampled size ≤ 32768, a finite subdivision error ≥ 0.01 pixel, valid texture
    /// and shadow overrides.
    ///
    /// # Errors
    /// [`Error::Parameter`] naming the first bad value.
    pub fn validate(&self) -> Result<()> {
        if self.width == 0 || self.height == 0 || self.width > MAX_SIZE || self.height > MAX_SIZE {
            return Err(Error::parameter(format!(
                "image size {}x{} is not within 1..={MAX_SIZE}",
                self.width, self.height
            )));
        }
        if !matches!(self.msaa, 1 | 2 | 4 | 8 | 16) {
            return Err(Error::parameter(format!(
                "msaa {} is not one of 1, 2, 4, 8, 16",
                self.msaa
            )));
        }
        if !(1..=8).contains(&self.ssaa) || self.width.max(self.height) * self.ssaa > 2 * MAX_SIZE {
            return Err(Error::parameter(format!(
                "ssaa {} is not within 1..=8 (or the supersampled image exceeds {} pixels)",
                self.ssaa,
                2 * MAX_SIZE
            )));
        }
        if let Interpolation::Subdivide { max_error_px } = self.interpolation {
            if !(max_error_px.is_finite() && max_error_px >= 0.01) {
                return Err(Error::parameter(format!(
                    "subdivision error {max_error_px} must be at least 0.01 pixel"
                )));
            }
        }
        self.textures.validate()?;
        self.shadows.validate()
    }
}
