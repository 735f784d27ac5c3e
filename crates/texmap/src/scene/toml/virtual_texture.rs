//! A `virtual_texture` table → a [`TextureSlot`] reading a [`VirtualTexture`]: the source
//! (`pattern = "quadtree"`, `size`, `seed`), how it is read (`filter`: an OpenGL filter or
//! anisoN; `wrap`: repeat or clamp; `lod_bias`; `uv_scale`) and the resident cache
//! (`budget_mib`, default [`DEFAULT_BUDGET_MIB`]; the command line's `--vt-budget` replaces
//! it). `resident = true` holds the same texels whole as an ordinary texture instead (sides
//! up to 4096), which is what paged reads are compared with. `Error::Parameter` messages are the table's, for the caller to prefix.

use std::sync::Arc;

use super::sampler::{parse_filter, parse_wrap};
use super::spec::VirtualTextureSpec;
use crate::shading::TextureSlot;
use crate::texture::{Filter, Sampler, VirtualTexture, Wrap};
use crate::{Error, Result};

/// The cache's budget when the table names none, in MiB.
pub const DEFAULT_BUDGET_MIB: f64 = 64.0;

/// The slot `v` describes; its `texture` is the virtual texture's coarse level.
pub(super) fn virtual_slot(v: &VirtualTextureSpec) -> Result<TextureSlot> {
    if v.pattern != "quadtree" {
        return Err(Error::parameter(format!(
            "pattern {:?} is not one texmap makes (quadtree)",
            v.pattern
        )));
    }
    let filter = v
        .filter
        .as_deref()
        .map(|f| parse_filter("filter", f))
        .transpose()?
        .unwrap_or(Filter::TRILINEAR);
    let wrap = v
        .wrap
        .as_deref()
        .map(|w| parse_wrap("wrap", w))
        .transpose()?
        .unwrap_or(Wrap::Repeat);
    if !(v.uv_scale.is_finite() && v.lod_bias.is_finite()) {
        return Err(Error::parameter("uv_scale and lod_bias must be finite"));
    }
    let mib = v.budget_mib.unwrap_or(DEFAULT_BUDGET_MIB);
    if !(mib.is_finite() && mib > 0.0 && mib <= 1024.0 * 1024.0) {
        return Err(Error::parameter(format!(
            "budget_mib {mib} is not a size in MiB (above 0, at most 1048576)"
        )));
    }
    let budget = (mib * (1u64 << 20) as f64) as u64;
    let vt = VirtualTexture::quadtree(v.size, v.seed, (wrap, wrap), budget)?;
    let sampler = Sampler::new(filter, wrap).with_lod_bias(v.lod_bias);
    vt.check_sampler(&sampler).map_err(|e| match e {
        Error::Unsupported(m) => Error::Parameter(m),
        other => other,
    })?;
    if v.resident {
        let mut slot = TextureSlot::new(Arc::new(vt.resident_texture()?), sampler);
        slot.uv_scale = v.uv_scale;
        return Ok(slot);
    }
    let coarse = Arc::new(vt.coarse_texture()?);
    let mut slot = TextureSlot::new(coarse, sampler);
    slot.uv_scale = v.uv_scale;
    slot.virtual_texture = Some(Arc::new(vt));
    Ok(slot)
}
