//! A texture table's sampler keys → [`Sampler`]: `filter` (default trilinear), `wrap` for
//! both axes (default repeat) and `wrap_u` / `wrap_v` over it, and `lod_bias`. Filters and
//! wraps are spelled as on the command line: they are parsed by [`Filter::parse`] and
//! [`Wrap::parse`], never here, so the scene format and the CLI accept the same words.

use super::spec::TextureSpec;
use crate::texture::{Filter, Sampler, Wrap};
use crate::{Error, Result};

/// Which spellings a key accepts, as its error lists them.
#[derive(Clone, Copy, Debug)]
pub(super) enum Spellings {
    /// Every filter [`Filter::parse`] reads.
    Filter,
    /// The OpenGL filters, the only ones 3D textures take.
    GlFilter,
    /// Every wrap mode [`Wrap::parse`] reads.
    Wrap,
}

/// The error for a `filter` or `wrap` value (named `key` in the message) that is not one of
/// `spellings`. The one place these messages list the spellings: when `Filter` and `Wrap`
/// publish their lists, each arm below becomes that list.
pub(super) fn filter_or_wrap_error(key: &str, value: &str, spellings: Spellings) -> Error {
    let expected = match spellings {
        Spellings::Filter => "nearest, bilinear, trilinear, aniso1..aniso16, ewa or sat",
        Spellings::GlFilter => "nearest, bilinear or trilinear",
        Spellings::Wrap => "repeat, mirror, clamp, border or mirror-clamp",
    };
    Error::parameter(format!("{key} {value:?}: expected {expected}"))
}

/// The filter `value` of key `key` spells.
pub(super) fn parse_filter(key: &str, value: &str) -> Result<Filter> {
    Filter::parse(value).ok_or_else(|| filter_or_wrap_error(key, value, Spellings::Filter))
}

/// The wrap mode `value` of key `key` spells.
pub(super) fn parse_wrap(key: &str, value: &str) -> Result<Wrap> {
    Wrap::parse(value).ok_or_else(|| filter_or_wrap_error(key, value, Spellings::Wrap))
}

/// The sampler a texture table describes. `Error::Parameter` messages are the table's
/// problem, for the caller to prefix.
pub(super) fn texture_sampler(t: &TextureSpec) -> Result<Sampler> {
    let filter = t
        .filter
        .as_deref()
        .map(|f| parse_filter("filter", f))
        .transpose()?
        .unwrap_or(Filter::TRILINEAR);
    let wrap = |key: &str, w: Option<&str>, d: Wrap| -> Result<Wrap> {
        Ok(w.map(|w| parse_wrap(key, w)).transpose()?.unwrap_or(d))
    };
    let both = wrap("wrap", t.wrap.as_deref(), Wrap::Repeat)?;
    let mut sampler = Sampler::new(filter, both);
    sampler.wrap_u = wrap("wrap_u", t.wrap_u.as_deref(), both)?;
    sampler.wrap_v = wrap("wrap_v", t.wrap_v.as_deref(), both)?;
    sampler.lod_bias = t.lod_bias;
    Ok(sampler)
}
