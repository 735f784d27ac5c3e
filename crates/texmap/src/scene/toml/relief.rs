//! `[materials.NAME.parallax]` and `[materials.NAME.displacement]` → the material's
//! [`Parallax`] and [`Displacement`]: a height map (`map`, a texture table read as linear
//! data), its `scale` in object units and `base` (the height at the mesh's surface), then
//! parallax's `mode` and step counts, or displacement's `level` or `edge_px`.

use std::path::Path;

use serde::Deserialize;

use super::spec::TextureSpec;
use super::textures::slot;
use crate::scene::texture_cache::TextureCache;
use crate::shading::relief::{Displacement, Parallax, ParallaxMode, Tessellation};
use crate::shading::TextureSlot;
use crate::texture::ColorSpace;
use crate::{Error, Result};

/// `[materials.NAME.parallax]`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ParallaxSpec {
    pub(super) map: TextureSpec,
    /// "offset" or "occlusion" (default).
    pub(super) mode: Option<String>,
    /// Object units of relief for heights 0 → 1 (default 0.05).
    pub(super) scale: Option<f32>,
    /// The height at the mesh's surface (default 1: the relief is carved in).
    pub(super) base: Option<f32>,
    /// Occlusion: steps head-on (default 8) and at grazing views (default 32).
    pub(super) min_steps: Option<u32>,
    pub(super) max_steps: Option<u32>,
    /// Self-shadowing towards the lights (default false).
    #[serde(default)]
    pub(super) shadows: bool,
}

/// `[materials.NAME.displacement]`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct DisplacementSpec {
    pub(super) map: TextureSpec,
    /// Object units of displacement for heights 0 → 1 (default 0.05).
    pub(super) scale: Option<f32>,
    /// The height left in place (default 0: the relief is raised).
    pub(super) base: Option<f32>,
    /// Uniform tessellation: each edge in 2^level segments (default 4 without `edge_px`).
    pub(super) level: Option<u32>,
    /// Tessellate until the longest projected edge is at most this many pixels.
    pub(super) edge_px: Option<f32>,
}

fn height_slot(
    dir: &Path,
    table: &str,
    t: &TextureSpec,
    textures: &mut TextureCache,
) -> Result<TextureSlot> {
    slot(dir, table, t, ColorSpace::Linear, textures)?
        .ok_or_else(|| Error::parameter(format!("{table}: the image's format is not read")))
}

/// The parallax table's [`Parallax`].
pub(super) fn parallax(
    dir: &Path,
    p: &ParallaxSpec,
    textures: &mut TextureCache,
) -> Result<Box<Parallax>> {
    let mode = match p.mode.as_deref() {
        None | Some("occlusion") => ParallaxMode::Occlusion,
        Some("offset") => ParallaxMode::Offset,
        Some(other) => {
            return Err(Error::parameter(format!(
                "parallax: mode {other:?} is not offset or occlusion"
            )))
        }
    };
    let out = Parallax {
        slot: height_slot(dir, "parallax.map", &p.map, textures)?,
        mode,
        scale: p.scale.unwrap_or(0.05),
        base: p.base.unwrap_or(1.0),
        min_steps: p.min_steps.unwrap_or(8),
        max_steps: p.max_steps.unwrap_or(32),
        shadows: p.shadows,
    };
    out.validate()
        .map_err(|e| Error::parameter(format!("parallax: {e}")))?;
    Ok(Box::new(out))
}

/// The displacement table's [`Displacement`].
pub(super) fn displacement(
    dir: &Path,
    d: &DisplacementSpec,
    textures: &mut TextureCache,
) -> Result<Box<Displacement>> {
    let tessellation = match (d.level, d.edge_px) {
        (Some(_), Some(_)) => {
            return Err(Error::parameter(
                "displacement: level and edge_px are both given; keep one",
            ))
        }
        (_, Some(e)) => Tessellation::EdgePixels(e),
        (l, None) => Tessellation::Level(l.unwrap_or(4)),
    };
    let out = Displacement {
        slot: height_slot(dir, "displacement.map", &d.map, textures)?,
        scale: d.scale.unwrap_or(0.05),
        base: d.base.unwrap_or(0.0),
        tessellation,
    };
    out.validate()
        .map_err(|e| Error::parameter(format!("displacement: {e}")))?;
    Ok(Box::new(out))
}
