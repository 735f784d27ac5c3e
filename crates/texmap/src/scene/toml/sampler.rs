//! A texture table's sampler keys → [`Sampler`]: `filter` (default trilinear), `wrap` for
//! both axes (default repeat) and `wrap_u` / `wrap_v` over it, `lod_bias`, the level-of-detail
//! clamps `min_lod` / `max_lod` (applied after the bias, as in OpenGL), and the `border`
//! colour.
//!
//! Rules:
//! - Filters and wraps are spelled as on the command line: they are parsed by
//!   [`Filter::parse`] and [`Wrap::parse`], never here, so the scene format and the CLI
//!   accept the same words.
//! - `min_lod` and `max_lod` are finite and `min_lod ≤ max_lod` (defaults: unbounded, the
//!   sampler's ±1000); a level of detail clamped by an empty range has no meaning.
//! - `border` is linear RGBA with straight alpha, like every colour in the format, with
//!   r, g, b ≥ 0 and a in [0, 1]; it is stored premultiplied, as [`Sampler::border`] is read.
//!   It is refused unless an axis wraps with `border`, where it would never be read.

use glam::Vec4;

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
/// `spellings`: the library's own lists, the ones the command line's help shows.
pub(super) fn filter_or_wrap_error(key: &str, value: &str, spellings: Spellings) -> Error {
    let expected = match spellings {
        Spellings::Filter => Filter::SPELLINGS,
        Spellings::GlFilter => Filter::GL_SPELLINGS,
        Spellings::Wrap => Wrap::SPELLINGS,
    };
    Error::parameter(format!("{key} {value:?}: expected one of: {expected}"))
}

/// The filter `value` of key `key` spells.
pub(super) fn parse_filter(key: &str, value: &str) -> Result<Filter> {
    Filter::parse(value).map_err(|_| filter_or_wrap_error(key, value, Spellings::Filter))
}

/// The wrap mode `value` of key `key` spells.
pub(super) fn parse_wrap(key: &str, value: &str) -> Result<Wrap> {
    Wrap::parse(value).map_err(|_| filter_or_wrap_error(key, value, Spellings::Wrap))
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
    let lod = |key: &str, v: Option<f32>, d: f32| -> Result<f32> {
        match v {
            None => Ok(d),
            Some(v) if v.is_finite() => Ok(v),
            Some(v) => Err(Error::parameter(format!(
                "{key} {v} is not a finite number"
            ))),
        }
    };
    sampler.min_lod = lod("min_lod", t.min_lod, sampler.min_lod)?;
    sampler.max_lod = lod("max_lod", t.max_lod, sampler.max_lod)?;
    if sampler.min_lod > sampler.max_lod {
        return Err(Error::parameter(format!(
            "min_lod {} is above max_lod {}",
            sampler.min_lod, sampler.max_lod
        )));
    }
    if let Some(b) = t.border {
        sampler.border = border(b, [sampler.wrap_u, sampler.wrap_v])?;
    }
    Ok(sampler)
}

/// The premultiplied border colour of a `border = [r, g, b, a]` key (straight alpha), read
/// by a sampler wrapping as `wraps`.
fn border(rgba: [f32; 4], wraps: [Wrap; 2]) -> Result<Vec4> {
    let c = Vec4::from(rgba);
    if !(c.is_finite() && c.truncate().min_element() >= 0.0 && (0.0..=1.0).contains(&c.w)) {
        return Err(Error::parameter(format!(
            "border {rgba:?}: expected linear [r, g, b, a] with r, g, b ≥ 0 and a in [0, 1]"
        )));
    }
    if !wraps.contains(&Wrap::ClampToBorder) {
        return Err(Error::parameter(
            "border is read only where the texture wraps with `border`; no axis does",
        ));
    }
    Ok((c.truncate() * c.w).extend(c.w))
}
