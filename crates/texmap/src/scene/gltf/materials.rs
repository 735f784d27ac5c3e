//! glTF materials → [`Material`]: the metallic-roughness model
//! (`ShadingModel::MetallicRoughness`) unless `KHR_materials_unlit` (then Phong, unlit);
//! base colour factor × texture, metallic and roughness factors and their texture, normal
//! (+ scale), occlusion (+ strength), emissive (× `KHR_materials_emissive_strength`), the
//! alpha mode and cutoff, double-sided, `KHR_materials_transmission` (factor and texture,
//! drawn where an environment is given) and `KHR_materials_ior`; the specular, clearcoat,
//! sheen and volume extensions in `extensions`.
//! The base colour and emissive textures are sRGB, the others linear data; an OPAQUE base
//! colour's alpha is dropped at load (glTF says it is ignored). The default material, for
//! primitives without one, is glTF's: white, metallic 1, roughness 1.

use glam::{Vec3, Vec4};

use super::document::Loader;
use super::textures::{apply_raw_transform, TRANSFORM};
use crate::pipeline::CullMode;
use crate::scene::texture_cache::{channel_color_space, AlphaChannel};
use crate::shading::{AlphaMode, MapChannel, Material, MaterialMap, ShadingModel};
use crate::texture::ColorSpace;
use crate::Result;

impl Loader<'_> {
    /// Every material of the document, then glTF's default material, with their names.
    pub(super) fn load_materials(&mut self) -> Result<()> {
        let doc = self.doc;
        for m in doc.materials() {
            let mat = self.material(&m)?;
            self.scene.materials.push(mat);
            self.info.material_names.push(
                m.name()
                    .map(str::to_string)
                    .unwrap_or_else(|| format!("material {}", m.index().unwrap_or(0))),
            );
        }
        // glTF's default material, for primitives without one: every property at its default.
        self.scene.materials.push(Material {
            model: ShadingModel::MetallicRoughness,
            metallic: 1.0,
            roughness: 1.0,
            cull: CullMode::Back,
            ..Default::default()
        });
        self.info.material_names.push("(default)".into());
        Ok(())
    }

    fn material(&mut self, m: &gltf::Material) -> Result<Material> {
        let pbr = m.pbr_metallic_roughness();
        let mut mat = Material {
            base_color: Vec4::from(pbr.base_color_factor()),
            metallic: pbr.metallic_factor(),
            roughness: pbr.roughness_factor(),
            double_sided: m.double_sided(),
            // glTF: "back-face culling must be enabled" on single-sided materials.
            cull: CullMode::Back,
            unlit: m.unlit(),
            model: if m.unlit() {
                ShadingModel::Phong
            } else {
                ShadingModel::MetallicRoughness
            },
            alpha_mode: match m.alpha_mode() {
                gltf::material::AlphaMode::Opaque => AlphaMode::Opaque,
                gltf::material::AlphaMode::Mask => AlphaMode::Mask(m.alpha_cutoff().unwrap_or(0.5)),
                gltf::material::AlphaMode::Blend => AlphaMode::Blend,
            },
            emissive: Vec3::from(m.emissive_factor()) * m.emissive_strength().unwrap_or(1.0),
            ..Default::default()
        };
        if let Some(info) = pbr.base_color_texture() {
            mat.base_color_texture = self.slot(
                &info.texture(),
                info.tex_coord(),
                info.texture_transform(),
                ColorSpace::Srgb,
                // An OPAQUE material's alpha is ignored (module docs).
                if mat.alpha_mode == AlphaMode::Opaque {
                    AlphaChannel::Drop
                } else {
                    AlphaChannel::Keep
                },
            )?;
        }
        if let Some(info) = pbr.metallic_roughness_texture() {
            self.push_map(
                &mut mat,
                MapChannel::MetallicRoughness,
                &info.texture(),
                info.tex_coord(),
                info.texture_transform(),
                1.0,
            )?;
        }
        if let Some(n) = m.normal_texture() {
            self.push_map(
                &mut mat,
                MapChannel::Normal,
                &n.texture(),
                n.tex_coord(),
                None,
                n.scale(),
            )?;
            // The crate exposes KHR_texture_transform on `textureInfo` only; normal and
            // occlusion textures carry it too, read from their raw extension object.
            apply_raw_transform(&mut mat, MapChannel::Normal, n.extension_value(TRANSFORM));
        }
        if let Some(o) = m.occlusion_texture() {
            self.push_map(
                &mut mat,
                MapChannel::Occlusion,
                &o.texture(),
                o.tex_coord(),
                None,
                o.strength(),
            )?;
            apply_raw_transform(
                &mut mat,
                MapChannel::Occlusion,
                o.extension_value(TRANSFORM),
            );
        }
        if let Some(t) = m.transmission() {
            mat.transmission = t.transmission_factor().clamp(0.0, 1.0);
            if let Some(info) = t.transmission_texture() {
                self.push_map(
                    &mut mat,
                    MapChannel::Transmission,
                    &info.texture(),
                    info.tex_coord(),
                    info.texture_transform(),
                    1.0,
                )?;
            }
        }
        if let Some(ior) = m.ior() {
            // 0 is the extension's spelling of "f0 = 1"; texmap keeps ior ≥ 1.
            mat.ior = if ior >= 1.0 && ior.is_finite() {
                ior
            } else {
                1.5
            };
        }
        if let Some(info) = m.emissive_texture() {
            self.push_map(
                &mut mat,
                MapChannel::Emissive,
                &info.texture(),
                info.tex_coord(),
                info.texture_transform(),
                1.0,
            )?;
        }
        self.material_extensions(m, &mut mat)?;
        Ok(mat)
    }

    pub(super) fn push_map(
        &mut self,
        mat: &mut Material,
        channel: MapChannel,
        tex: &gltf::Texture,
        tex_coord: u32,
        transform: Option<gltf::texture::TextureTransform>,
        scale: f32,
    ) -> Result<()> {
        let color_space = channel_color_space(channel);
        if let Some(slot) = self.slot(tex, tex_coord, transform, color_space, AlphaChannel::Keep)? {
            mat.maps.push(MaterialMap {
                channel,
                slot,
                scale,
            });
        }
        Ok(())
    }
}
