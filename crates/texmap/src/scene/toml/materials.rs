//! `[materials.NAME]` → [`Material`]: factors over the white Phong default, the shading
//! model (`phong`, or `pbr` for glTF's metallic-roughness), the alpha mode, the base colour
//! texture, at most one computed colour source (`procedural`, `projected`, `solid_texture`,
//! see `procedural`), solid textures on roughness and bump, and one texture table per other
//! channel under `maps`. Images on colour channels (base colour, emissive, ambient,
//! specular) are sRGB unless the table says otherwise, the others linear data.

use std::path::Path;

use glam::{Vec3, Vec4};

use super::procedural::{colour_source, solid_maps};
use super::spec::MaterialSpec;
use super::textures::slot;
use super::virtual_texture::virtual_slot;
use crate::pipeline::CullMode;
use crate::scene::texture_cache::{channel_color_space, TextureCache};
use crate::shading::{AlphaMode, MapChannel, Material, MaterialMap, ShadingModel};
use crate::texture::ColorSpace;
use crate::{Error, Result};

/// The material a `[materials.NAME]` table describes. `Error::Parameter` messages are the
/// table's problem, for the caller to prefix.
pub(super) fn material(
    dir: &Path,
    m: &MaterialSpec,
    textures: &mut TextureCache,
) -> Result<Material> {
    let d = Material::default();
    let alpha_mode = match m.alpha_mode.as_deref() {
        None | Some("opaque") => AlphaMode::Opaque,
        Some("mask") => AlphaMode::Mask(m.alpha_cutoff.unwrap_or(0.5)),
        Some("blend") => AlphaMode::Blend,
        Some(other) => {
            return Err(Error::parameter(format!(
                "alpha_mode {other:?} is not opaque, mask or blend"
            )))
        }
    };
    let model = match m.model.as_deref() {
        None | Some("phong") => ShadingModel::Phong,
        Some("pbr") => ShadingModel::MetallicRoughness,
        Some(other) => {
            return Err(Error::parameter(format!(
                "model {other:?} is not phong or pbr"
            )))
        }
    };
    let mut mat = Material {
        model,
        base_color: m.base_color.map_or(d.base_color, Vec4::from),
        ambient: m.ambient.unwrap_or(d.ambient),
        diffuse: m.diffuse.unwrap_or(d.diffuse),
        specular: m.specular.unwrap_or(d.specular),
        shininess: m.shininess.unwrap_or(d.shininess),
        emissive: m.emissive.map_or(d.emissive, Vec3::from),
        metallic: m.metallic.unwrap_or(d.metallic),
        // Phong materials read the roughness only to blur the environment they reflect.
        roughness: m.roughness.unwrap_or(match model {
            ShadingModel::Phong => 0.0,
            ShadingModel::MetallicRoughness => d.roughness,
        }),
        reflection: m.reflection.unwrap_or(d.reflection),
        transmission: m.transmission.unwrap_or(d.transmission),
        ior: m.ior.unwrap_or(d.ior),
        unlit: m.unlit,
        double_sided: m.double_sided,
        cull: match m.cull.as_deref() {
            None | Some("none") => CullMode::None,
            Some("back") => CullMode::Back,
            Some("front") => CullMode::Front,
            Some(other) => {
                return Err(Error::parameter(format!(
                    "cull {other:?} is not none, back or front"
                )))
            }
        },
        alpha_mode,
        ..d
    };
    for (key, v, lo, hi) in [
        ("reflection", mat.reflection, 0.0, 1.0),
        ("transmission", mat.transmission, 0.0, 1.0),
        ("ior", mat.ior, 1.0, 10.0),
    ] {
        if !(lo..=hi).contains(&v) {
            return Err(Error::parameter(format!(
                "{key} {v} is outside {lo}..={hi}"
            )));
        }
    }
    if let Some(t) = &m.base_color_texture {
        mat.base_color_texture = slot(dir, "base_color_texture", t, ColorSpace::Srgb, textures)?;
    }
    if let Some(v) = &m.virtual_texture {
        if m.base_color_texture.is_some() {
            return Err(Error::parameter(
                "virtual_texture and base_color_texture are both given; keep one",
            ));
        }
        mat.base_color_texture = Some(virtual_slot(v).map_err(|e| match e {
            Error::Parameter(msg) => Error::Parameter(format!("virtual_texture: {msg}")),
            other => other,
        })?);
    }
    mat.procedural = colour_source(dir, m, textures)?;
    mat.solid_maps.extend(solid_maps(m)?);
    let maps = &m.maps;
    for (channel, table, spec) in [
        (
            MapChannel::MetallicRoughness,
            "maps.metallic_roughness",
            &maps.metallic_roughness,
        ),
        (MapChannel::Normal, "maps.normal", &maps.normal),
        (
            MapChannel::NormalObject,
            "maps.normal_object",
            &maps.normal_object,
        ),
        (MapChannel::Occlusion, "maps.occlusion", &maps.occlusion),
        (MapChannel::Emissive, "maps.emissive", &maps.emissive),
        (MapChannel::Ambient, "maps.ambient", &maps.ambient),
        (MapChannel::Specular, "maps.specular", &maps.specular),
        (MapChannel::Shininess, "maps.shininess", &maps.shininess),
        (MapChannel::Alpha, "maps.alpha", &maps.alpha),
        (MapChannel::Bump, "maps.bump", &maps.bump),
        (
            MapChannel::Transmission,
            "maps.transmission",
            &maps.transmission,
        ),
    ] {
        if let Some(spec) = spec {
            let space = channel_color_space(channel);
            if let Some(s) = slot(dir, table, spec, space, textures)? {
                mat.maps.push(MaterialMap {
                    channel,
                    slot: s,
                    scale: spec.scale,
                });
            }
        }
    }
    super::layers::surface_detail(dir, m, &mut mat, textures)?;
    if let Some(p) = &m.parallax {
        mat.parallax = Some(super::relief::parallax(dir, p, textures)?);
    }
    if let Some(d) = &m.displacement {
        mat.displacement = Some(super::relief::displacement(dir, d, textures)?);
    }
    Ok(mat)
}
