//! Sampler state: wrap modes, filter, level-of-detail bias and clamps, border colour.

use glam::Vec4;

use super::{LodRule, Wrap};

/// OpenGL's magnification filters.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum MagFilter {
    Nearest,
    #[default]
    Linear,
}

/// OpenGL's six minification filters.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum MinFilter {
    /// Nearest texel of level 0.
    Nearest,
    /// Bilinear on level 0.
    Linear,
    /// Nearest texel of the nearest level.
    NearestMipmapNearest,
    /// Bilinear on the nearest level.
    LinearMipmapNearest,
    /// Nearest texel of the two nearest levels, blended.
    NearestMipmapLinear,
    /// Bilinear on the two nearest levels, blended (trilinear).
    #[default]
    LinearMipmapLinear,
}

/// How a footprint becomes a colour.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Filter {
    /// OpenGL's filters: magnification when λ ≤ 0, else minification.
    Gl { mag: MagFilter, min: MinFilter },
    /// Up to `max_aniso` trilinear taps along the footprint's major axis, the level from the
    /// minor axis (1 ≤ `max_aniso` ≤ 16).
    Anisotropic { max_aniso: u32 },
    /// Heckbert's elliptical weighted average with a Gaussian, the ellipse's eccentricity
    /// clamped to `max_eccentricity`.
    Ewa { max_eccentricity: f32 },
    /// A box over the footprint's bounding rectangle, read from summed-area tables.
    SummedArea,
}

impl Filter {
    /// `GL_NEAREST` for both magnification and minification, no mipmaps.
    pub const NEAREST: Filter = Filter::Gl {
        mag: MagFilter::Nearest,
        min: MinFilter::Nearest,
    };
    /// `GL_LINEAR` for both, no mipmaps.
    pub const BILINEAR: Filter = Filter::Gl {
        mag: MagFilter::Linear,
        min: MinFilter::Linear,
    };
    /// `GL_LINEAR` / `GL_LINEAR_MIPMAP_LINEAR`.
    pub const TRILINEAR: Filter = Filter::Gl {
        mag: MagFilter::Linear,
        min: MinFilter::LinearMipmapLinear,
    };

    /// Parses the command-line spelling: `nearest`, `bilinear`, `trilinear`, `anisoN`
    /// (N in 1..=16), `ewa`, `sat`.
    pub fn parse(s: &str) -> Option<Filter> {
        Some(match s {
            "nearest" => Filter::NEAREST,
            "bilinear" => Filter::BILINEAR,
            "trilinear" => Filter::TRILINEAR,
            "ewa" => Filter::Ewa {
                max_eccentricity: 16.0,
            },
            "sat" => Filter::SummedArea,
            _ => {
                let n: u32 = s.strip_prefix("aniso")?.parse().ok()?;
                if !(1..=16).contains(&n) {
                    return None;
                }
                Filter::Anisotropic { max_aniso: n }
            }
        })
    }

    /// True when the filter reads mip levels below 0.
    #[must_use]
    pub fn uses_mipmaps(self) -> bool {
        !matches!(
            self,
            Filter::Gl {
                min: MinFilter::Nearest | MinFilter::Linear,
                ..
            }
        )
    }
}

/// Everything about how a texture is read, apart from the texture and the footprint.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sampler {
    pub wrap_u: Wrap,
    pub wrap_v: Wrap,
    /// The third axis, for 3D textures.
    pub wrap_w: Wrap,
    pub filter: Filter,
    /// Linear, premultiplied colour read outside the image with [`Wrap::ClampToBorder`].
    pub border: Vec4,
    /// Added to λ before clamping.
    pub lod_bias: f32,
    pub min_lod: f32,
    pub max_lod: f32,
    pub lod_rule: LodRule,
}

impl Default for Sampler {
    fn default() -> Self {
        Sampler {
            wrap_u: Wrap::Repeat,
            wrap_v: Wrap::Repeat,
            wrap_w: Wrap::Repeat,
            filter: Filter::TRILINEAR,
            border: Vec4::ZERO,
            lod_bias: 0.0,
            min_lod: -1000.0,
            max_lod: 1000.0,
            lod_rule: LodRule::GlMax,
        }
    }
}

impl Sampler {
    /// A sampler with `filter` and the same `wrap` on every axis.
    #[must_use]
    pub fn new(filter: Filter, wrap: Wrap) -> Self {
        Sampler {
            wrap_u: wrap,
            wrap_v: wrap,
            wrap_w: wrap,
            filter,
            ..Default::default()
        }
    }

    /// Applies bias and clamps to a raw λ.
    #[inline]
    #[must_use]
    pub fn adjust_lod(&self, lod: f32) -> f32 {
        (lod + self.lod_bias).clamp(self.min_lod, self.max_lod)
    }
}
