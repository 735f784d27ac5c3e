//! Occlusion maps packed into the metallic-roughness maps they go with.
//!
//! glTF reads occlusion from a texture's red channel and roughness and metalness from the
//! green and blue channels of another, whose red channel nothing reads; many assets pack
//! the three into one image (ORM), and a draw then reads it once (`render/fragment.rs`
//! reads an image once however many maps name it). An asset that keeps them in two images
//! of one size (DamagedHelmet) has them packed as the images are built: the occlusion
//! image's red channel is written into the decoded metallic-roughness image
//! ([`crate::texture::load::with_red_from`]: 8-bit images of one size, no translucent
//! texel; each level then reads as the two textures' would) and one texture is built for
//! both. One texture less to build and hold, one less to read a pixel.
//!
//! Only where no other read can tell: the metallic-roughness image is named by no texture
//! use but `metallicRoughnessTexture`, the occlusion image by none but `occlusionTexture`,
//! every material that names either names both, and neither texture takes its image from an
//! extension (DDS, Basis Universal).

use std::collections::HashMap;

use super::document::Loader;
use super::textures::{extension_source, image_key, BASISU, DDS};

/// How an image is used: as what (the texture info's key, `metallicRoughnessTexture`,
/// `occlusionTexture`, `clearcoatTexture`, …) in which material.
type Uses = HashMap<usize, Vec<(String, usize)>>;

impl Loader<'_> {
    /// The pairs of images to pack where the module's conditions hold, as
    /// [`crate::scene::texture_cache::TextureCache::prefetch`] takes them: the
    /// metallic-roughness image's key, the occlusion image's, and the occlusion image's name.
    pub(super) fn occlusion_packs(&self) -> Vec<(String, String, String)> {
        let uses = self.image_uses();
        let mut pairs: Vec<(usize, usize)> = Vec::new();
        for m in self.doc.materials() {
            let mr = m.pbr_metallic_roughness().metallic_roughness_texture();
            let (Some(mr), Some(ao)) = (mr, m.occlusion_texture()) else {
                continue;
            };
            let images = (
                self.plain_image(&mr.texture()),
                self.plain_image(&ao.texture()),
            );
            let (Some(mr), Some(ao)) = images else {
                continue;
            };
            if mr != ao && !pairs.contains(&(mr, ao)) {
                pairs.push((mr, ao));
            }
        }
        const MR: &str = "metallicRoughnessTexture";
        const AO: &str = "occlusionTexture";
        let only = |image: usize, key: &str, partner: usize, partner_key: &str| {
            uses[&image].iter().all(|(k, material)| {
                k == key
                    && uses[&partner]
                        .iter()
                        .any(|(pk, pm)| pk == partner_key && pm == material)
            })
        };
        pairs
            .into_iter()
            .filter(|&(mr, ao)| only(mr, MR, ao, AO) && only(ao, AO, mr, MR))
            .map(|(mr, ao)| (image_key(mr), image_key(ao), format!("image {ao}")))
            .collect()
    }

    /// The image texture `tex` reads, unless it reads one an extension names (as
    /// `Loader::slot` chooses it).
    fn plain_image(&self, tex: &gltf::Texture) -> Option<usize> {
        let extended = [DDS, BASISU]
            .into_iter()
            .any(|ext| extension_source(self.doc, tex, ext).is_some());
        (!extended).then(|| tex.source().index())
    }

    /// Every image's uses by the materials (core textures and any extension's), one entry
    /// per texture info.
    fn image_uses(&self) -> Uses {
        let mut uses: Uses = HashMap::new();
        let textures: Vec<gltf::Texture> = self.doc.textures().collect();
        for (mi, m) in self.doc.materials().enumerate() {
            let pbr = m.pbr_metallic_roughness();
            let mut named: Vec<(&str, usize)> = Vec::new();
            if let Some(t) = pbr.base_color_texture() {
                named.push(("baseColorTexture", t.texture().index()));
            }
            if let Some(t) = pbr.metallic_roughness_texture() {
                named.push(("metallicRoughnessTexture", t.texture().index()));
            }
            if let Some(t) = m.normal_texture() {
                named.push(("normalTexture", t.texture().index()));
            }
            if let Some(t) = m.occlusion_texture() {
                named.push(("occlusionTexture", t.texture().index()));
            }
            if let Some(t) = m.emissive_texture() {
                named.push(("emissiveTexture", t.texture().index()));
            }
            let mut ext = Vec::new();
            if let Some(e) = m.extensions() {
                for value in e.values() {
                    texture_infos(value, "", &mut ext);
                }
            }
            // Extensions the gltf crate parses into types are missing from the map above.
            if let Some(t) = m.transmission().and_then(|t| t.transmission_texture()) {
                ext.push(("transmissionTexture".to_string(), t.texture().index()));
            }
            let all = named
                .into_iter()
                .map(|(k, t)| (k.to_string(), t))
                .chain(ext);
            for (key, t) in all {
                if let Some(tex) = textures.get(t) {
                    // Every image the texture may read (its extensions' too).
                    let named = [DDS, BASISU]
                        .into_iter()
                        .filter_map(|ext| extension_source(self.doc, tex, ext));
                    let images =
                        std::iter::once(tex.source().index()).chain(named.map(|img| img.index()));
                    for i in images {
                        uses.entry(i).or_default().push((key.clone(), mi));
                    }
                }
            }
        }
        uses
    }
}

/// The texture infos inside an extension's JSON: every object under a key ending in
/// `Texture` with an `index`, as (key, texture index).
fn texture_infos(value: &gltf::json::Value, key: &str, out: &mut Vec<(String, usize)>) {
    use gltf::json::Value;
    match value {
        Value::Object(map) => {
            if key.ends_with("Texture") {
                if let Some(i) = map.get("index").and_then(Value::as_u64) {
                    out.push((key.to_string(), i as usize));
                }
            }
            for (k, v) in map {
                texture_infos(v, k, out);
            }
        }
        Value::Array(items) => {
            for v in items {
                texture_infos(v, key, out);
            }
        }
        _ => {}
    }
}
