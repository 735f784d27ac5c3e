//! glTF material extensions the `gltf` crate's enabled features do not parse, read from the
//! material's raw `extensions` map into [`Lobes`] and extension maps:
//! `KHR_materials_specular`, `KHR_materials_clearcoat`, `KHR_materials_sheen` and
//! `KHR_materials_volume`. Each texture is a raw `textureInfo` (`index`, `texCoord`, its own
//! `KHR_texture_transform`), read through the same slot as every other map. A malformed
//! member keeps the extension's default.

use glam::Vec3;

use super::document::Loader;
use super::textures::{apply_raw_transform, TRANSFORM};
use crate::shading::lobes::Lobes;
use crate::shading::{MapChannel, Material};
use crate::Result;

pub(super) const SPECULAR: &str = "KHR_materials_specular";
pub(super) const CLEARCOAT: &str = "KHR_materials_clearcoat";
pub(super) const SHEEN: &str = "KHR_materials_sheen";
pub(super) const VOLUME: &str = "KHR_materials_volume";

type Json = gltf::json::Value;

fn number(v: &Json, key: &str, default: f32) -> f32 {
    v.get(key)
        .and_then(Json::as_f64)
        .map(|x| x as f32)
        .filter(|x| x.is_finite())
        .unwrap_or(default)
}

fn color(v: &Json, key: &str, default: Vec3) -> Vec3 {
    v.get(key)
        .and_then(Json::as_array)
        .and_then(|a| {
            let c = |i: usize| a.get(i).and_then(Json::as_f64).map(|x| x as f32);
            Some(Vec3::new(c(0)?, c(1)?, c(2)?))
        })
        .filter(|c| c.is_finite())
        .unwrap_or(default)
}

impl Loader<'_> {
    /// The extension lobes and maps of material `m` into `mat`.
    pub(super) fn material_extensions(
        &mut self,
        m: &gltf::Material,
        mat: &mut Material,
    ) -> Result<()> {
        let mut l = Lobes::default();
        if let Some(e) = m.extension_value(SPECULAR) {
            l.specular = number(e, "specularFactor", 1.0).clamp(0.0, 1.0);
            l.specular_color = color(e, "specularColorFactor", Vec3::ONE).max(Vec3::ZERO);
            self.raw_map(mat, e, "specularTexture", MapChannel::SpecularWeight)?;
            self.raw_map(mat, e, "specularColorTexture", MapChannel::SpecularColor)?;
        }
        if let Some(e) = m.extension_value(CLEARCOAT) {
            l.clearcoat = number(e, "clearcoatFactor", 0.0).clamp(0.0, 1.0);
            l.clearcoat_roughness = number(e, "clearcoatRoughnessFactor", 0.0).clamp(0.0, 1.0);
            self.raw_map(mat, e, "clearcoatTexture", MapChannel::Clearcoat)?;
            self.raw_map(
                mat,
                e,
                "clearcoatRoughnessTexture",
                MapChannel::ClearcoatRoughness,
            )?;
            self.raw_map(
                mat,
                e,
                "clearcoatNormalTexture",
                MapChannel::ClearcoatNormal,
            )?;
        }
        if let Some(e) = m.extension_value(SHEEN) {
            l.sheen_color = color(e, "sheenColorFactor", Vec3::ZERO).clamp(Vec3::ZERO, Vec3::ONE);
            l.sheen_roughness = number(e, "sheenRoughnessFactor", 0.0).clamp(0.0, 1.0);
            self.raw_map(mat, e, "sheenColorTexture", MapChannel::SheenColor)?;
            self.raw_map(mat, e, "sheenRoughnessTexture", MapChannel::SheenRoughness)?;
        }
        if let Some(e) = m.extension_value(VOLUME) {
            l.thickness = number(e, "thicknessFactor", 0.0).max(0.0);
            l.attenuation_distance =
                number(e, "attenuationDistance", f32::INFINITY).max(f32::MIN_POSITIVE);
            l.attenuation_color =
                color(e, "attenuationColor", Vec3::ONE).clamp(Vec3::ZERO, Vec3::ONE);
            self.raw_map(mat, e, "thicknessTexture", MapChannel::Thickness)?;
        }
        mat.lobes = l;
        Ok(())
    }

    /// The map of the raw `textureInfo` at `e[key]`, if present and naming a texture.
    fn raw_map(
        &mut self,
        mat: &mut Material,
        e: &Json,
        key: &str,
        channel: MapChannel,
    ) -> Result<()> {
        let Some(info) = e.get(key) else {
            return Ok(());
        };
        let Some(tex) = info
            .get("index")
            .and_then(Json::as_u64)
            .and_then(|i| self.doc.textures().nth(usize::try_from(i).ok()?))
        else {
            self.warnings.push(format!(
                "{}: {key} names no texture of the file; it is left out",
                self.path.display()
            ));
            return Ok(());
        };
        let tex_coord = info
            .get("texCoord")
            .and_then(Json::as_u64)
            .map_or(0, |c| u32::try_from(c).unwrap_or(u32::MAX));
        // A normal texture's `scale` (1 by default); the others have none.
        let scale = number(info, "scale", 1.0);
        let before = mat.maps.len();
        self.push_map(mat, channel, &tex, tex_coord, None, scale)?;
        if mat.maps.len() > before {
            apply_raw_transform(
                mat,
                channel,
                info.get("extensions").and_then(|x| x.get(TRANSFORM)),
            );
        }
        Ok(())
    }
}
