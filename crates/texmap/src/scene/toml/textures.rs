//! A texture table → [`TextureSlot`]: the image (`file`, relative to the scene file, loaded
//! once per colour space through the scene's texture cache), its sampler (`sampler`), its
//! colour space (`color_space`, else the channel's: sRGB for colour, linear for data), its
//! coordinates (`tex_coord` 0 or 1, `transform` in `KHR_texture_transform`'s order with the
//! rotation in degrees, then `uv_scale`) and how it is held (`storage`: decoded, native,
//! compressed or rgba8).

use std::path::Path;

use glam::Vec2;

use super::sampler::texture_sampler;
use super::spec::TextureSpec;
use crate::scene::texture_cache::{AlphaChannel, ImageSource, TextureCache};
use crate::shading::TextureSlot;
use crate::texture::{ColorSpace, Storage, TextureTransform};
use crate::{Error, Result};

/// The slot texture table `table` (`t`) describes; `None` when the image's format is one
/// texmap leaves out (a warning). `channel_space` is the colour space when the table names
/// none. `Error::Parameter` messages name the table, for the caller to prefix further.
pub(super) fn slot(
    dir: &Path,
    table: &str,
    t: &TextureSpec,
    channel_space: ColorSpace,
    textures: &mut TextureCache,
) -> Result<Option<TextureSlot>> {
    let in_table = |e: Error| match e {
        Error::Parameter(msg) => Error::Parameter(format!("{table}: {msg}")),
        other => other,
    };
    let sampler = texture_sampler(t).map_err(in_table)?;
    let color_space = match t.color_space.as_deref() {
        None => channel_space,
        Some("srgb") => ColorSpace::Srgb,
        Some("linear") => ColorSpace::Linear,
        Some(other) => {
            return Err(in_table(Error::parameter(format!(
                "color_space {other:?} is not srgb or linear"
            ))))
        }
    };
    let tex_coord = t.tex_coord.unwrap_or(0);
    if tex_coord > 1 {
        return Err(in_table(Error::parameter(format!(
            "tex_coord {tex_coord} is not 0 or 1"
        ))));
    }
    let storage = match t.storage.as_deref() {
        None => None,
        Some(name) => Some(Storage::from_name(name).ok_or_else(|| {
            let names: Vec<&str> = Storage::NAMES.iter().map(|(n, _)| *n).collect();
            in_table(Error::parameter(format!(
                "storage {name:?} is not one of {}",
                names.join(", ")
            )))
        })?),
    };
    let file = dir.join(&t.file);
    let Some(tex) = textures.get_stored(
        &file.to_string_lossy(),
        ImageSource::File(file.clone()),
        color_space,
        AlphaChannel::Keep,
        storage,
    )?
    else {
        return Ok(None);
    };
    let mut s = TextureSlot::new(tex, sampler);
    s.uv_scale = t.uv_scale;
    s.tex_coord = tex_coord;
    if let Some(tr) = &t.transform {
        s.transform = TextureTransform {
            offset: Vec2::from(tr.offset),
            rotation: tr.rotation.to_radians(),
            scale: Vec2::from(tr.scale),
        };
    }
    Ok(Some(s))
}
