//! glTF textures → [`TextureSlot`]s: the image (a bufferView, a `data:` URI or a file beside
//! the asset, through the scene's texture cache, so each image is decoded once per colour
//! space and alpha handling), the sampler mapped straight onto texmap's OpenGL filters and wraps (undefined
//! filters are trilinear, undefined wraps repeat), the uv set, and `KHR_texture_transform`
//! as [`TextureTransform`] — on every texture, normal and occlusion ones included. KTX2 and
//! DDS images load through the texture containers (KTX2 holding Basis Universal is
//! transcoded); WebP images are a warning and left out, as in the peer.
//! A texture with `MSFT_texture_dds` or `KHR_texture_basisu` reads the DDS or KTX2 image its
//! extension names, in place of the fallback `source`.

use std::sync::Arc;

use glam::Vec2;

use super::document::Loader;
use crate::scene::files::{decode_data_uri, percent_decode, resolve_reference};
use crate::scene::texture_cache::{channel_color_space, AlphaChannel, ImageSource};
use crate::shading::{MapChannel, Material, TextureSlot};
use crate::texture::{
    ColorSpace, Filter, MagFilter, MinFilter, Sampler, Texture2D, TextureTransform, Wrap,
};
use crate::Result;

impl Loader<'_> {
    /// The slot for texture `tex` read with uv set `tex_coord` and an optional transform, its
    /// image decoded in `color_space` with its alpha kept or dropped; `None` when the image
    /// is left out.
    pub(super) fn slot(
        &mut self,
        tex: &gltf::Texture,
        tex_coord: u32,
        transform: Option<gltf::texture::TextureTransform>,
        color_space: ColorSpace,
        alpha: AlphaChannel,
    ) -> Result<Option<TextureSlot>> {
        let image = [DDS, BASISU]
            .into_iter()
            .find_map(|ext| extension_source(self.doc, tex, ext))
            .unwrap_or_else(|| tex.source());
        let Some(texture) = self.image(&image, color_space, alpha)? else {
            return Ok(None);
        };
        let mut slot = TextureSlot::new(texture, sampler(&tex.sampler()));
        slot.tex_coord = tex_coord;
        if let Some(t) = transform {
            slot.transform = TextureTransform {
                offset: Vec2::from(t.offset()),
                rotation: t.rotation(),
                scale: Vec2::from(t.scale()),
            };
            if let Some(tc) = t.tex_coord() {
                slot.tex_coord = tc;
            }
        }
        if slot.tex_coord > 1 {
            self.warnings.push(format!(
                "{}: texture {} reads TEXCOORD_{}; texmap reads sets 0 and 1 only (uv = 0)",
                self.path.display(),
                tex.index(),
                slot.tex_coord
            ));
        }
        Ok(Some(slot))
    }

    fn image(
        &mut self,
        img: &gltf::Image,
        color_space: ColorSpace,
        alpha: AlphaChannel,
    ) -> Result<Option<Arc<Texture2D>>> {
        let key = image_key(img.index());
        let unsupported = |mime: Option<&str>| matches!(mime, Some("image/webp"));
        match img.source() {
            gltf::image::Source::View { view, mime_type } => {
                let name = format!(
                    "{} (image {}, {mime_type})",
                    self.path.display(),
                    img.index()
                );
                if unsupported(Some(mime_type)) {
                    return self.skip_image(name);
                }
                let bytes = self.acc.view_bytes(&view)?;
                self.textures
                    .get(&key, ImageSource::Bytes { name, bytes }, color_space, alpha)
            }
            gltf::image::Source::Uri { uri, mime_type } if uri.starts_with("data:") => {
                let data = decode_data_uri(self.path, uri, self.options.max_buffer_bytes)?;
                let name = format!("{} (image {}, data URI)", self.path.display(), img.index());
                if unsupported(data.mime.as_deref().or(mime_type)) {
                    return self.skip_image(name);
                }
                self.textures.get(
                    &key,
                    ImageSource::Bytes {
                        name,
                        bytes: &data.bytes,
                    },
                    color_space,
                    alpha,
                )
            }
            gltf::image::Source::Uri { uri, mime_type } => {
                let p = resolve_reference(self.path, &percent_decode(uri), self.options)?;
                if unsupported(mime_type) {
                    return self.skip_image(p.display().to_string());
                }
                self.textures
                    .get(&key, ImageSource::File(p), color_space, alpha)
            }
        }
    }

    /// Builds the images of every material's core textures (base colour, metallic-roughness,
    /// normal, occlusion, emissive, transmission) at once, in parallel, before the materials
    /// ask for them one by one ([`crate::scene::texture_cache::TextureCache::prefetch`]):
    /// with the same keys, colour spaces and alpha handling as [`Loader::slot`] gives them.
    /// Images in data URIs and the extensions' other textures load when asked.
    pub(super) fn prefetch_images(&mut self) {
        use gltf::material::AlphaMode;
        let mut wanted = Vec::new();
        for m in self.doc.materials() {
            let pbr = m.pbr_metallic_roughness();
            let space = channel_color_space;
            if let Some(i) = pbr.base_color_texture() {
                let alpha = if m.alpha_mode() == AlphaMode::Opaque {
                    AlphaChannel::Drop
                } else {
                    AlphaChannel::Keep
                };
                wanted.push((i.texture(), ColorSpace::Srgb, alpha));
            }
            let keep = AlphaChannel::Keep;
            if let Some(i) = pbr.metallic_roughness_texture() {
                wanted.push((i.texture(), space(MapChannel::MetallicRoughness), keep));
            }
            if let Some(n) = m.normal_texture() {
                wanted.push((n.texture(), space(MapChannel::Normal), keep));
            }
            if let Some(o) = m.occlusion_texture() {
                wanted.push((o.texture(), space(MapChannel::Occlusion), keep));
            }
            if let Some(i) = m.emissive_texture() {
                wanted.push((i.texture(), space(MapChannel::Emissive), keep));
            }
            if let Some(i) = m.transmission().and_then(|t| t.transmission_texture()) {
                wanted.push((i.texture(), space(MapChannel::Transmission), keep));
            }
        }
        let mut requests = Vec::new();
        for (tex, color_space, alpha) in wanted {
            let img = [DDS, BASISU]
                .into_iter()
                .find_map(|ext| extension_source(self.doc, &tex, ext))
                .unwrap_or_else(|| tex.source());
            let key = image_key(img.index());
            let source = match img.source() {
                gltf::image::Source::View { view, mime_type } if mime_type != "image/webp" => {
                    let name = format!(
                        "{} (image {}, {mime_type})",
                        self.path.display(),
                        img.index()
                    );
                    match self.acc.view_bytes(&view) {
                        Ok(bytes) => ImageSource::Bytes { name, bytes },
                        Err(_) => continue, // reported when the material asks
                    }
                }
                gltf::image::Source::Uri { uri, mime_type }
                    if !uri.starts_with("data:") && mime_type != Some("image/webp") =>
                {
                    match resolve_reference(self.path, &percent_decode(uri), self.options) {
                        Ok(p) => ImageSource::File(p),
                        Err(_) => continue,
                    }
                }
                _ => continue,
            };
            requests.push((key, source, color_space, alpha));
        }
        let packs = self.occlusion_packs();
        self.textures.prefetch(requests, &packs);
    }

    fn skip_image(&mut self, name: String) -> Result<Option<Arc<Texture2D>>> {
        self.warnings.push(format!(
            "{name}: image format not decoded by texmap; the texture is left out"
        ));
        Ok(None)
    }
}

pub(super) const DDS: &str = "MSFT_texture_dds";
pub(super) const BASISU: &str = "KHR_texture_basisu";

/// The texture cache's key of image `index` of the asset.
pub(super) fn image_key(index: usize) -> String {
    format!("image{index}")
}

/// The image a texture names in the image extension `ext` (`MSFT_texture_dds`,
/// `KHR_texture_basisu`); `None` without the extension, or when its `source` names no image:
/// the texture's own `source` is then read.
pub(super) fn extension_source<'a>(
    doc: &'a gltf::Document,
    tex: &gltf::Texture,
    ext: &str,
) -> Option<gltf::Image<'a>> {
    let index = tex.extension_value(ext)?.get("source")?.as_u64()?;
    doc.images().nth(usize::try_from(index).ok()?)
}

/// glTF sampler → texmap sampler (undefined filters are trilinear, undefined wraps repeat).
fn sampler(s: &gltf::texture::Sampler) -> Sampler {
    use gltf::texture::{MagFilter as GM, MinFilter as Gm, WrappingMode as W};
    let mag = match s.mag_filter() {
        Some(GM::Nearest) => MagFilter::Nearest,
        _ => MagFilter::Linear,
    };
    let min = match s.min_filter() {
        Some(Gm::Nearest) => MinFilter::Nearest,
        Some(Gm::Linear) => MinFilter::Linear,
        Some(Gm::NearestMipmapNearest) => MinFilter::NearestMipmapNearest,
        Some(Gm::LinearMipmapNearest) => MinFilter::LinearMipmapNearest,
        Some(Gm::NearestMipmapLinear) => MinFilter::NearestMipmapLinear,
        Some(Gm::LinearMipmapLinear) | None => MinFilter::LinearMipmapLinear,
    };
    let wrap = |w: W| match w {
        W::ClampToEdge => Wrap::ClampToEdge,
        W::MirroredRepeat => Wrap::MirroredRepeat,
        W::Repeat => Wrap::Repeat,
    };
    let mut out = Sampler::new(Filter::Gl { mag, min }, Wrap::Repeat);
    out.wrap_u = wrap(s.wrap_s());
    out.wrap_v = wrap(s.wrap_t());
    out
}

pub(super) const TRANSFORM: &str = "KHR_texture_transform";

/// Sets the transform (and uv set override) of the last map of `mat`, if it feeds `channel`,
/// from a raw `KHR_texture_transform` object: `offset`, `rotation`, `scale`, `texCoord`, each
/// optional; malformed members keep their defaults.
pub(super) fn apply_raw_transform(
    mat: &mut Material,
    channel: MapChannel,
    value: Option<&gltf::json::Value>,
) {
    let (Some(value), Some(map)) = (value, mat.maps.last_mut()) else {
        return;
    };
    if map.channel != channel {
        return;
    }
    let pair = |key: &str, default: Vec2| {
        value
            .get(key)
            .and_then(|v| v.as_array())
            .and_then(|a| {
                Some(Vec2::new(
                    a.first()?.as_f64()? as f32,
                    a.get(1)?.as_f64()? as f32,
                ))
            })
            .filter(|v| v.is_finite())
            .unwrap_or(default)
    };
    map.slot.transform = TextureTransform {
        offset: pair("offset", Vec2::ZERO),
        rotation: value
            .get("rotation")
            .and_then(|v| v.as_f64())
            .map(|r| r as f32)
            .filter(|r| r.is_finite())
            .unwrap_or(0.0),
        scale: pair("scale", Vec2::ONE),
    };
    if let Some(tc) = value.get("texCoord").and_then(|v| v.as_u64()) {
        map.slot.tex_coord = u32::try_from(tc).unwrap_or(u32::MAX);
    }
}
