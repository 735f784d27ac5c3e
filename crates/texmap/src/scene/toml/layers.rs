//! A material's surface detail: `[[materials.NAME.layers]]` (texture layers with OpenGL's
//! texture-environment modes), `[materials.NAME.light_map]` (a texture table read on uv set
//! 1 by default, its `scale` the intensity) and `[materials.NAME.toon]` (a ramp of bands or
//! an image, an optional outline); and the check that every mesh has the uv sets its
//! material's layers and light map read.

use std::path::Path;

use glam::{Vec3, Vec4};
use serde::Deserialize;

use super::spec::{MaterialSpec, TextureSpec};
use super::textures::slot;
use crate::scene::texture_cache::TextureCache;
use crate::scene::Scene;
use crate::shading::layers::{BaseFormat, TexEnvMode, TextureLayer};
use crate::shading::toon::{ramp_sampler, Outline, Toon};
use crate::shading::{MapChannel, Material, MaterialMap};
use crate::texture::{ColorSpace, Filter};
use crate::{Error, Result};

/// The most layers a material may have (OpenGL 1.x implementations offered 2 to 8 texture
/// units).
pub(super) const MAX_LAYERS: usize = 8;

/// A `[[materials.NAME.layers]]` entry.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct LayerSpec {
    /// One of [`TexEnvMode::NAMES`].
    pub(super) mode: String,
    /// One of [`BaseFormat::NAMES`] (default: rgba when the image has alpha, else rgb).
    pub(super) format: Option<String>,
    /// GL's environment colour, linear RGBA straight (blend, interpolate-constant).
    pub(super) constant: Option<[f32; 4]>,
    /// The image and how it is read (colour space default: sRGB, linear for `detail`).
    pub(super) texture: TextureSpec,
}

/// `[materials.NAME.toon]`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ToonSpec {
    /// A built-in ramp of this many hard bands (default 3 without `ramp`).
    pub(super) bands: Option<u32>,
    /// A ramp image (its middle row is read; wrap default clamp, filter default bilinear).
    pub(super) ramp: Option<TextureSpec>,
    /// The outline's colour, linear RGB (no outline without it).
    pub(super) outline: Option<[f32; 3]>,
    /// The outline's width in pixels (default 1.5).
    pub(super) outline_width: Option<f32>,
}

/// Fills `mat`'s layers, light map and toon from table `m`.
pub(super) fn surface_detail(
    dir: &Path,
    m: &MaterialSpec,
    mat: &mut Material,
    textures: &mut TextureCache,
) -> Result<()> {
    if m.layers.len() > MAX_LAYERS {
        return Err(Error::parameter(format!(
            "{} layers: at most {MAX_LAYERS}",
            m.layers.len()
        )));
    }
    for (i, l) in m.layers.iter().enumerate() {
        let table = format!("layers[{i}]");
        let bad = |msg: String| Error::parameter(format!("{table}: {msg}"));
        let mode = TexEnvMode::parse(&l.mode).ok_or_else(|| {
            bad(format!(
                "mode {:?} is not one of {}",
                l.mode,
                TexEnvMode::NAMES
            ))
        })?;
        let space = match mode {
            TexEnvMode::Detail => ColorSpace::Linear,
            _ => ColorSpace::Srgb,
        };
        let Some(s) = slot(dir, &table, &l.texture, space, textures)? else {
            continue;
        };
        let format = match l.format.as_deref() {
            Some(name) => BaseFormat::parse(name).ok_or_else(|| {
                bad(format!(
                    "format {name:?} is not one of {}",
                    BaseFormat::NAMES
                ))
            })?,
            None if s.texture.format().has_alpha() => BaseFormat::Rgba,
            None => BaseFormat::Rgb,
        };
        if mode == TexEnvMode::Decal && !matches!(format, BaseFormat::Rgb | BaseFormat::Rgba) {
            return Err(bad(format!(
                "mode decal is undefined for format {} (OpenGL defines it for rgb and rgba)",
                format.name()
            )));
        }
        let needs_constant = matches!(
            mode,
            TexEnvMode::Blend | TexEnvMode::Interpolate { by_constant: true }
        );
        let constant = match l.constant {
            Some(c) if c.iter().all(|v| (0.0..=1.0).contains(v)) => Vec4::from(c),
            Some(c) => return Err(bad(format!("constant {c:?} is outside 0..=1"))),
            None if needs_constant => {
                return Err(bad(format!("mode {} needs a constant", mode.name())))
            }
            None => Vec4::ZERO,
        };
        mat.layers.push(TextureLayer {
            slot: s,
            mode,
            format,
            constant,
            source: l.texture.file.display().to_string().into(),
        });
    }
    if let Some(t) = &m.light_map {
        if let Some(mut s) = slot(dir, "light_map", t, ColorSpace::Srgb, textures)? {
            s.tex_coord = t.tex_coord.unwrap_or(1);
            if !(t.scale.is_finite() && t.scale >= 0.0) {
                return Err(Error::parameter(format!(
                    "light_map: scale {} must be finite and ≥ 0",
                    t.scale
                )));
            }
            mat.maps.push(MaterialMap {
                channel: MapChannel::Light,
                slot: s,
                scale: t.scale,
            });
        }
    }
    if let Some(t) = &m.toon {
        mat.toon = Some(toon(dir, t, textures).map_err(|e| match e {
            Error::Parameter(msg) => Error::Parameter(format!("toon: {msg}")),
            other => other,
        })?);
    }
    Ok(())
}

fn toon(dir: &Path, t: &ToonSpec, textures: &mut TextureCache) -> Result<Toon> {
    let outline = match (t.outline, t.outline_width) {
        (None, Some(_)) => return Err(Error::parameter("outline_width without outline")),
        (None, None) => None,
        (Some(c), w) => {
            let width = w.unwrap_or(1.5);
            if !(width.is_finite() && width > 0.0 && width <= 64.0) {
                return Err(Error::parameter(format!(
                    "outline_width {width} is outside (0, 64] pixels"
                )));
            }
            Some(Outline {
                color: Vec3::from(c),
                width,
            })
        }
    };
    match (&t.ramp, t.bands) {
        (Some(_), Some(_)) => Err(Error::parameter("both bands and ramp; keep one")),
        (None, bands) => {
            let n = bands.unwrap_or(3);
            if !(2..=256).contains(&n) {
                return Err(Error::parameter(format!("bands {n} is outside 2..=256")));
            }
            Ok(Toon::bands(n, outline))
        }
        (Some(r), None) => {
            let Some(s) = slot(dir, "ramp", r, ColorSpace::Srgb, textures)? else {
                return Err(Error::parameter(format!(
                    "ramp: {} could not be read",
                    r.file.display()
                )));
            };
            let mut sampler = ramp_sampler(if r.filter.is_some() {
                s.sampler.filter
            } else {
                Filter::BILINEAR
            });
            if r.wrap.is_some() || r.wrap_u.is_some() || r.wrap_v.is_some() {
                sampler.wrap_u = s.sampler.wrap_u;
                sampler.wrap_v = s.sampler.wrap_v;
            }
            Ok(Toon {
                ramp: s.texture,
                sampler,
                source: r.file.display().to_string().into(),
                outline,
            })
        }
    }
}

/// Every mesh has the uv sets its material's layers and light map read: a set-1 read on a
/// mesh without a second uv set is refused (it would silently read set 0).
pub(super) fn check_uv_sets(scene: &Scene, names: &[String]) -> std::result::Result<(), String> {
    for (i, mesh) in scene.meshes.iter().enumerate() {
        let Some(m) = scene.materials.get(mesh.material) else {
            continue;
        };
        if mesh.uvs1.len() == mesh.positions.len() {
            continue;
        }
        let name = names.get(mesh.material).map_or("?", String::as_str);
        if m.map(MapChannel::Light)
            .is_some_and(|l| l.slot.tex_coord == 1)
        {
            return Err(format!(
                "mesh {i}: material {name}'s light_map reads uv set 1, which the mesh does not \
                 have (give the mesh texgen = {{ set = 1, … }}, or the light map tex_coord = 0)"
            ));
        }
        if let Some(k) = m.layers.iter().position(|l| l.slot.tex_coord == 1) {
            return Err(format!(
                "mesh {i}: material {name}'s layers[{k}] reads uv set 1, which the mesh does not \
                 have (give the mesh texgen = {{ set = 1, … }}, or the layer tex_coord = 0)"
            ));
        }
    }
    Ok(())
}
