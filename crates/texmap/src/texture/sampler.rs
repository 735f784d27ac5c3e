//! Sampler state: wrap modes, filter, level-of-detail bias and clamps, border colour.
//!
//! Filters and wrap modes have one list of names each ([`Filter::SPELLINGS`],
//! [`Wrap::SPELLINGS`]): the parsers read them, their errors ([`UnknownName`]) quote them, and
//! the command line's help shows them, so the three cannot disagree.

use std::fmt;

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

/// The level anisotropic filtering's probes read, for a footprint whose ellipse has semi-axes
/// σ₁ ≥ σ₂ (in texels) taking `N = min(⌈σ₁/σ₂⌉, max_aniso)` probes along σ₁.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum AnisoLod {
    /// The GL extension's `λ = log2(σ₁/N)`: the probes' squares tile the major axis, so a
    /// footprint longer than `max_aniso` : 1 is blurred across it to cover it (`anisoN`).
    #[default]
    Gl,
    /// `λ = ½·log2(σ₁σ₂/N)`, at most one level below the extension's: the probes' squares
    /// together have the ellipse's area, so a footprint longer than `max_aniso` : 1 keeps
    /// more of its detail across (its probes spaced wider than their width) where the
    /// extension's blurs it (`anisoN-area`).
    Area,
}

/// How a footprint becomes a colour.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Filter {
    /// OpenGL's filters: magnification when λ ≤ 0, else minification.
    Gl { mag: MagFilter, min: MinFilter },
    /// Up to `max_aniso` trilinear taps along the footprint's major axis (1 ≤ `max_aniso` ≤
    /// 16), on the level `lod` names.
    Anisotropic { max_aniso: u32, lod: AnisoLod },
    /// Elliptical weighted average by probes: Heckbert's Gaussian over the footprint's
    /// ellipse (eccentricity clamped to `max_eccentricity`) sampled by trilinear probes along
    /// its major axis, as many as the eccentricity needs (Mavridis and Papaioannou 2011).
    Ewa { max_eccentricity: f32 },
    /// Heckbert's elliptical weighted average itself: every texel inside the ellipse
    /// weighted by the Gaussian (the reference [`Filter::Ewa`] approximates).
    EwaExact { max_eccentricity: f32 },
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

    /// Every spelling [`Filter::parse`] accepts, as `--help` text and error messages list them.
    pub const SPELLINGS: &'static str = "nearest, bilinear, trilinear, nearest-mipmap-nearest, \
        bilinear-mipmap-nearest, nearest-mipmap-linear, aniso1..aniso16, \
        aniso1-area..aniso16-area, ewa, ewa-exact, sat \
        (an OpenGL name may end in -mag-nearest or -mag-linear for the other magnification filter)";

    /// The OpenGL filters of [`Filter::SPELLINGS`] alone (what 3D textures take).
    pub const GL_SPELLINGS: &'static str = "nearest, bilinear, trilinear, \
        nearest-mipmap-nearest, bilinear-mipmap-nearest, nearest-mipmap-linear \
        (each may end in -mag-nearest or -mag-linear for the other magnification filter)";

    /// The OpenGL filters by name, each minification filter with its natural magnification
    /// filter: `nearest*` magnify nearest, `bilinear*` and `trilinear` linearly.
    const GL_NAMES: [(&'static str, MinFilter, MagFilter); 6] = [
        ("nearest", MinFilter::Nearest, MagFilter::Nearest),
        ("bilinear", MinFilter::Linear, MagFilter::Linear),
        (
            "trilinear",
            MinFilter::LinearMipmapLinear,
            MagFilter::Linear,
        ),
        (
            "nearest-mipmap-nearest",
            MinFilter::NearestMipmapNearest,
            MagFilter::Nearest,
        ),
        (
            "bilinear-mipmap-nearest",
            MinFilter::LinearMipmapNearest,
            MagFilter::Linear,
        ),
        (
            "nearest-mipmap-linear",
            MinFilter::NearestMipmapLinear,
            MagFilter::Nearest,
        ),
    ];

    /// The suffixes that set the magnification filter other than the name's natural one.
    const MAG_SUFFIXES: [(&'static str, MagFilter); 2] = [
        ("-mag-nearest", MagFilter::Nearest),
        ("-mag-linear", MagFilter::Linear),
    ];

    /// Anisotropic filtering with at most `max_aniso` probes on the GL extension's level
    /// (`anisoN`).
    #[must_use]
    pub const fn aniso(max_aniso: u32) -> Filter {
        Filter::Anisotropic {
            max_aniso,
            lod: AnisoLod::Gl,
        }
    }

    /// Parses one of [`Filter::SPELLINGS`]: an OpenGL pair by its minification filter's name
    /// (`trilinear` is `GL_LINEAR_MIPMAP_LINEAR` magnifying with `GL_LINEAR`;
    /// `trilinear-mag-nearest` magnifies with `GL_NEAREST`), `anisoN` for N in 1..=16 (the GL
    /// extension's level, [`AnisoLod::Gl`]) and `anisoN-area` ([`AnisoLod::Area`]), `ewa`
    /// and `ewa-exact` (eccentricity at most 16) or `sat`.
    ///
    /// ```
    /// use texmap::texture::{AnisoLod, Filter, MagFilter, MinFilter};
    /// assert_eq!(Filter::parse("trilinear"), Ok(Filter::TRILINEAR));
    /// assert_eq!(
    ///     Filter::parse("nearest-mipmap-linear"),
    ///     Ok(Filter::Gl { mag: MagFilter::Nearest, min: MinFilter::NearestMipmapLinear })
    /// );
    /// assert_eq!(Filter::parse("aniso8"), Ok(Filter::aniso(8)));
    /// assert_eq!(
    ///     Filter::parse("aniso5-area"),
    ///     Ok(Filter::Anisotropic { max_aniso: 5, lod: AnisoLod::Area })
    /// );
    /// assert!(Filter::parse("aniso32").unwrap_err().to_string().contains(Filter::SPELLINGS));
    /// ```
    pub fn parse(s: &str) -> Result<Filter, UnknownName> {
        let unknown = || UnknownName {
            given: s.to_string(),
            expected: Filter::SPELLINGS,
        };
        let gl = |name: &str| {
            Self::GL_NAMES
                .iter()
                .find(|(n, ..)| *n == name)
                .map(|&(_, min, mag)| (min, mag))
        };
        if let Some((min, mag)) = gl(s) {
            return Ok(Filter::Gl { mag, min });
        }
        for (suffix, mag) in Self::MAG_SUFFIXES {
            if let Some((min, _)) = s.strip_suffix(suffix).and_then(gl) {
                return Ok(Filter::Gl { mag, min });
            }
        }
        match s {
            "ewa" => Ok(Filter::Ewa {
                max_eccentricity: 16.0,
            }),
            "ewa-exact" => Ok(Filter::EwaExact {
                max_eccentricity: 16.0,
            }),
            "sat" => Ok(Filter::SummedArea),
            _ => {
                let aniso = s.strip_prefix("aniso").ok_or_else(unknown)?;
                let (digits, lod) = match aniso.strip_suffix("-area") {
                    Some(digits) => (digits, AnisoLod::Area),
                    None => (aniso, AnisoLod::Gl),
                };
                if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
                    return Err(unknown());
                }
                match digits.parse::<u32>() {
                    Ok(max_aniso) if (1..=16).contains(&max_aniso) => {
                        Ok(Filter::Anisotropic { max_aniso, lod })
                    }
                    _ => Err(unknown()),
                }
            }
        }
    }

    /// The spelling of this filter, which [`Filter::parse`] reads back to the same filter
    /// for every filter it can return and every OpenGL pair.
    ///
    /// Two filters have no spelling of their own and are named by the nearest one: an
    /// anisotropic count outside 1..=16 by the count sampling clamps it to (the same reads),
    /// and an EWA bound on the eccentricity other than 16 as `ewa` (or `ewa-exact`).
    ///
    /// ```
    /// use texmap::texture::{Filter, MagFilter, MinFilter};
    /// assert_eq!(Filter::TRILINEAR.name(), "trilinear");
    /// let f = Filter::Gl { mag: MagFilter::Nearest, min: MinFilter::LinearMipmapLinear };
    /// assert_eq!(f.name(), "trilinear-mag-nearest");
    /// assert_eq!(Filter::parse(&f.name()), Ok(f));
    /// ```
    #[must_use]
    pub fn name(self) -> String {
        match self {
            Filter::Gl { mag, min } => {
                let (name, natural) = Self::GL_NAMES
                    .iter()
                    .find(|(_, m, _)| *m == min)
                    .map(|&(n, _, mag)| (n, mag))
                    .expect("every min filter has a name");
                match Self::MAG_SUFFIXES.iter().find(|(_, m)| *m == mag) {
                    Some((suffix, _)) if mag != natural => format!("{name}{suffix}"),
                    _ => name.to_string(),
                }
            }
            Filter::Anisotropic { max_aniso, lod } => {
                let suffix = match lod {
                    AnisoLod::Gl => "",
                    AnisoLod::Area => "-area",
                };
                format!("aniso{}{suffix}", max_aniso.clamp(1, 16))
            }
            Filter::Ewa { .. } => "ewa".to_string(),
            Filter::EwaExact { .. } => "ewa-exact".to_string(),
            Filter::SummedArea => "sat".to_string(),
        }
    }
}

/// A name [`Filter::parse`] or [`Wrap::parse`] does not know. Its message lists the names
/// that are known (callers quote the name given, as a command line or a file names it).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct UnknownName {
    /// The name given.
    pub given: String,
    /// The names accepted: [`Filter::SPELLINGS`] or [`Wrap::SPELLINGS`].
    pub expected: &'static str,
}

impl fmt::Display for UnknownName {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "expected one of: {}", self.expected)
    }
}

impl std::error::Error for UnknownName {}

/// Everything about how a texture is read, apart from the texture and the footprint.
///
/// Built from [`Sampler::new`] or [`Sampler::default`] and the `with_*` methods, so a field
/// added later breaks no caller (the type is `#[non_exhaustive]`); the fields stay public to
/// read and assign.
///
/// ```
/// use texmap::texture::{Filter, LodRule, Sampler, Wrap};
/// let s = Sampler::new(Filter::TRILINEAR, Wrap::ClampToEdge)
///     .with_lod_bias(0.5)
///     .with_lod_clamp(0.0, 4.0)
///     .with_lod_rule(LodRule::RootSumSquares);
/// assert_eq!((s.wrap_u, s.lod_bias, s.max_lod), (Wrap::ClampToEdge, 0.5, 4.0));
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct Sampler {
    /// The wrap mode along u (texel columns).
    pub wrap_u: Wrap,
    /// The wrap mode along v (texel rows).
    pub wrap_v: Wrap,
    /// The third axis, for 3D textures.
    pub wrap_w: Wrap,
    pub filter: Filter,
    /// Linear, premultiplied colour read outside the image with [`Wrap::ClampToBorder`].
    pub border: Vec4,
    /// Added to λ before clamping.
    pub lod_bias: f32,
    /// The smallest λ after the bias (at most `max_lod`; reads panic otherwise).
    pub min_lod: f32,
    /// The largest λ after the bias.
    pub max_lod: f32,
    /// How λ comes from the footprint's derivatives.
    pub lod_rule: LodRule,
}

impl Default for Sampler {
    /// Trilinear, repeat on every axis, a transparent black border, no bias, λ unclamped
    /// (±1000), OpenGL's λ rule.
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
    /// A sampler with `filter` and the same `wrap` on every axis (the rest as
    /// [`Sampler::default`]).
    #[must_use]
    pub fn new(filter: Filter, wrap: Wrap) -> Self {
        Sampler::default().with_filter(filter).with_wrap(wrap)
    }

    /// This sampler with `filter`.
    #[must_use]
    pub fn with_filter(mut self, filter: Filter) -> Self {
        self.filter = filter;
        self
    }

    /// This sampler with `wrap` on every axis.
    #[must_use]
    pub fn with_wrap(self, wrap: Wrap) -> Self {
        self.with_wraps(wrap, wrap, wrap)
    }

    /// This sampler with a wrap mode per axis (`w` for 3D textures).
    #[must_use]
    pub fn with_wraps(mut self, u: Wrap, v: Wrap, w: Wrap) -> Self {
        (self.wrap_u, self.wrap_v, self.wrap_w) = (u, v, w);
        self
    }

    /// This sampler with the border colour (linear, premultiplied) of
    /// [`Wrap::ClampToBorder`].
    #[must_use]
    pub fn with_border(mut self, border: Vec4) -> Self {
        self.border = border;
        self
    }

    /// This sampler with `bias` added to every λ.
    #[must_use]
    pub fn with_lod_bias(mut self, bias: f32) -> Self {
        self.lod_bias = bias;
        self
    }

    /// This sampler with λ clamped to `[min, max]` after the bias.
    ///
    /// # Panics
    /// If `min > max` or either is NaN.
    #[must_use]
    pub fn with_lod_clamp(mut self, min: f32, max: f32) -> Self {
        assert!(min <= max, "level-of-detail clamp {min}..{max} is empty");
        (self.min_lod, self.max_lod) = (min, max);
        self
    }

    /// This sampler with λ from the derivatives by `rule`.
    #[must_use]
    pub fn with_lod_rule(mut self, rule: LodRule) -> Self {
        self.lod_rule = rule;
        self
    }

    /// Applies bias and clamps to a raw λ.
    #[inline]
    #[must_use]
    pub fn adjust_lod(&self, lod: f32) -> f32 {
        (lod + self.lod_bias).clamp(self.min_lod, self.max_lod)
    }

    /// [`Sampler::adjust_lod`] of four λ, one per lane: the same values (the clamp by
    /// selects: below the least to it, above the greatest to it, NaN left NaN).
    #[inline(always)]
    #[must_use]
    pub fn adjust_lod4(&self, lod: Vec4) -> Vec4 {
        let (lo, hi) = (Vec4::splat(self.min_lod), Vec4::splat(self.max_lod));
        let lod = lod + Vec4::splat(self.lod_bias);
        let lod = Vec4::select(lod.cmplt(lo), lo, lod);
        Vec4::select(lod.cmpgt(hi), hi, lod)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every filter a spelling names: the twelve OpenGL pairs, anisotropy 1..=16 on either
    /// level rule, EWA (both), SAT.
    fn named_filters() -> Vec<Filter> {
        let mins = Filter::GL_NAMES.map(|(_, min, _)| min);
        let mut v: Vec<Filter> = mins
            .iter()
            .flat_map(|&min| {
                [MagFilter::Nearest, MagFilter::Linear].map(|mag| Filter::Gl { mag, min })
            })
            .collect();
        for lod in [AnisoLod::Gl, AnisoLod::Area] {
            v.extend((1..=16).map(|max_aniso| Filter::Anisotropic { max_aniso, lod }));
        }
        v.extend([
            Filter::Ewa {
                max_eccentricity: 16.0,
            },
            Filter::EwaExact {
                max_eccentricity: 16.0,
            },
            Filter::SummedArea,
        ]);
        v
    }

    #[test]
    fn every_named_filter_round_trips_through_its_name() {
        for f in named_filters() {
            assert_eq!(Filter::parse(&f.name()), Ok(f), "{}", f.name());
        }
    }

    #[test]
    fn plain_names_keep_their_filters() {
        assert_eq!(Filter::parse("nearest"), Ok(Filter::NEAREST));
        assert_eq!(Filter::parse("bilinear"), Ok(Filter::BILINEAR));
        assert_eq!(Filter::parse("trilinear"), Ok(Filter::TRILINEAR));
        let gl = |mag, min| Ok(Filter::Gl { mag, min });
        use {MagFilter as Mag, MinFilter as Min};
        let named = [
            (
                "nearest-mipmap-nearest",
                gl(Mag::Nearest, Min::NearestMipmapNearest),
            ),
            (
                "bilinear-mipmap-nearest",
                gl(Mag::Linear, Min::LinearMipmapNearest),
            ),
            (
                "nearest-mipmap-linear",
                gl(Mag::Nearest, Min::NearestMipmapLinear),
            ),
            (
                "trilinear-mag-nearest",
                gl(Mag::Nearest, Min::LinearMipmapLinear),
            ),
            ("nearest-mag-linear", gl(Mag::Linear, Min::Nearest)),
            ("bilinear-mag-linear", gl(Mag::Linear, Min::Linear)),
        ];
        for (name, want) in named {
            assert_eq!(Filter::parse(name), want, "{name}");
        }
    }

    #[test]
    fn the_gl_list_is_the_start_of_the_full_list_and_names_only_gl_filters() {
        let gl = Filter::GL_SPELLINGS.split(" (").next().unwrap();
        assert!(Filter::SPELLINGS.starts_with(gl));
        for name in gl.split(", ") {
            assert!(
                matches!(Filter::parse(name), Ok(Filter::Gl { .. })),
                "{name}"
            );
        }
    }

    #[test]
    fn every_listed_spelling_parses_and_every_name_is_listed() {
        // The list's entries up to the parenthesis, with aniso1..aniso16 as its two ends.
        let list = Filter::SPELLINGS.split(" (").next().unwrap();
        for entry in list.split(", ") {
            for name in entry.split("..") {
                assert!(
                    Filter::parse(name).is_ok(),
                    "{name:?} is listed but does not parse"
                );
            }
        }
        for f in named_filters() {
            let name = f.name();
            let base = Filter::MAG_SUFFIXES
                .iter()
                .find_map(|(suffix, _)| name.strip_suffix(suffix))
                .unwrap_or(&name);
            assert!(
                base.starts_with("aniso") || list.split(", ").any(|e| e == base),
                "{name} is not listed"
            );
        }
    }

    #[test]
    fn unknown_names_are_refused_with_the_list() {
        for bad in [
            "",
            "linear",
            "aniso",
            "aniso0",
            "aniso17",
            "aniso+4",
            "ewa16",
            "Trilinear",
            "sat-mag-nearest",
            "aniso4-mag-linear",
            "aniso-area",
            "aniso17-area",
            "aniso4-area-area",
            "aniso4-Area",
            "area4",
        ] {
            let e = Filter::parse(bad).unwrap_err();
            assert_eq!(e.given, bad);
            assert_eq!(
                e.to_string(),
                format!("expected one of: {}", Filter::SPELLINGS)
            );
        }
    }

    #[test]
    fn filters_without_a_spelling_are_named_by_the_nearest_one() {
        assert_eq!(Filter::aniso(0).name(), "aniso1");
        assert_eq!(Filter::aniso(64).name(), "aniso16");
        let area = |max_aniso| Filter::Anisotropic {
            max_aniso,
            lod: AnisoLod::Area,
        };
        assert_eq!(area(0).name(), "aniso1-area");
        assert_eq!(area(64).name(), "aniso16-area");
        assert_eq!(
            Filter::Ewa {
                max_eccentricity: 4.0
            }
            .name(),
            "ewa"
        );
    }

    #[test]
    fn builders_set_their_fields_and_nothing_else() {
        let s = Sampler::new(Filter::NEAREST, Wrap::ClampToBorder);
        let d = Sampler::default();
        assert_eq!(
            (s.wrap_u, s.wrap_v, s.wrap_w),
            (
                Wrap::ClampToBorder,
                Wrap::ClampToBorder,
                Wrap::ClampToBorder
            )
        );
        assert_eq!(s.filter, Filter::NEAREST);
        assert_eq!(
            (s.border, s.lod_bias, s.min_lod, s.max_lod, s.lod_rule),
            (d.border, d.lod_bias, d.min_lod, d.max_lod, d.lod_rule)
        );
        let t = s
            .with_wraps(Wrap::Repeat, Wrap::MirroredRepeat, Wrap::ClampToEdge)
            .with_border(Vec4::ONE)
            .with_lod_bias(-0.5)
            .with_lod_clamp(1.0, 3.0)
            .with_lod_rule(LodRule::RootSumSquares)
            .with_filter(Filter::SummedArea);
        assert_eq!(
            (t.wrap_u, t.wrap_v, t.wrap_w),
            (Wrap::Repeat, Wrap::MirroredRepeat, Wrap::ClampToEdge)
        );
        assert_eq!(
            (t.border, t.lod_bias, t.min_lod, t.max_lod),
            (Vec4::ONE, -0.5, 1.0, 3.0)
        );
        assert_eq!(
            (t.lod_rule, t.filter),
            (LodRule::RootSumSquares, Filter::SummedArea)
        );
    }

    #[test]
    #[should_panic(expected = "is empty")]
    fn an_empty_lod_clamp_panics_when_built() {
        let _ = Sampler::default().with_lod_clamp(2.0, 1.0);
    }
}
