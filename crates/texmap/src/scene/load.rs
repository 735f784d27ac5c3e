//! Loading scene files: the entry point [`load`], its options, what it returns, and the rules
//! every loader shares (where a referenced file may live, how big a buffer may be, what a
//! missing texture becomes).
//!
//! Safety rules, the same for every format:
//! - A reference inside an asset (a glTF URI, an MTL or texture path in an OBJ) resolves from
//!   the asset's folder and may not leave it (`..` above it, an absolute path, a symbolic
//!   link pointing out) unless [`LoadOptions::allow_outside_paths`] is set.
//! - Nothing is fetched over the network: `http:` / `https:` (and any other scheme but
//!   `data:`) are errors.
//! - Files, buffers and data URIs are bounded by [`LoadOptions::max_buffer_bytes`]; images by
//!   the texture [`Limits`].
//! - A TOML scene is written by the user, like a command line: its own paths may point
//!   anywhere (relative ones resolve from the scene file's folder); the assets it names still
//!   follow the rules above inside their own folders.

use std::collections::HashMap;
use std::path::{Component, Path, PathBuf};
use std::sync::Arc;

use super::Scene;
use crate::camera::Camera;
use image::DynamicImage;

use crate::texture::load::{decode_image, decode_image_bytes, texture_from_image, Limits};
use crate::texture::{ColorSpace, Format, Texture2D, TextureOptions};
use crate::{Error, Result};

/// How scene files are read.
#[derive(Clone, Debug)]
pub struct LoadOptions {
    /// Let references leave the asset's folder (`..`, absolute paths).
    pub allow_outside_paths: bool,
    /// A missing or undecodable texture becomes a warning and a magenta placeholder.
    pub lenient: bool,
    /// Size limits for images.
    pub limits: Limits,
    /// Largest file, buffer or decoded data URI accepted, in bytes (default 1 GiB).
    pub max_buffer_bytes: u64,
}

impl Default for LoadOptions {
    fn default() -> Self {
        LoadOptions {
            allow_outside_paths: false,
            lenient: false,
            limits: Limits::default(),
            max_buffer_bytes: 1 << 30,
        }
    }
}

/// A texture as `texmap info` lists it.
#[derive(Clone, Debug)]
pub struct TextureInfo {
    /// File name, or a description of where embedded data came from.
    pub name: String,
    pub width: u32,
    pub height: u32,
    pub format: Format,
    pub color_space: ColorSpace,
    /// True for the magenta placeholder that stands for a missing texture (`--lenient`).
    pub placeholder: bool,
}

/// What a loaded file holds, beyond the renderable [`Scene`]: names and sources for `info`.
#[derive(Clone, Debug, Default)]
pub struct AssetInfo {
    /// "glTF", "OBJ", "TOML scene".
    pub format: String,
    /// One name per `Scene::meshes` entry.
    pub mesh_names: Vec<String>,
    /// One name per `Scene::materials` entry.
    pub material_names: Vec<String>,
    /// Every texture loaded, once each.
    pub textures: Vec<TextureInfo>,
    /// One name (the file) per [`Loaded::volumes`] entry.
    pub volumes: Vec<String>,
    /// True when the file defines no light and the loader added the peers' directional
    /// light (volumes then shade with a headlight instead).
    pub default_light: bool,
}

/// A loaded scene file.
#[derive(Clone, Debug)]
pub struct Loaded {
    /// What to render; `scene.camera` is the file's first camera, if any.
    pub scene: Scene,
    /// Every camera the file defines, in file order.
    pub cameras: Vec<Camera>,
    pub info: AssetInfo,
    /// Volumes placed in the scene (TOML `[[volumes]]`), with their transfer functions and
    /// rendering options; drawn by [`crate::volume::render_with_volumes`].
    pub volumes: Vec<crate::volume::SceneVolume>,
    /// Problems that did not stop loading (unsupported optional extensions, skipped
    /// primitives, placeholders), one line each, for stderr.
    pub warnings: Vec<String>,
}

/// Loads a `.gltf`, `.glb`, `.obj` or `.toml` scene file.
///
/// # Errors
/// An [`Error`] naming the file (the scene file or the asset it references) and the problem.
pub fn load(path: &Path, options: &LoadOptions) -> Result<Loaded> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .unwrap_or_default();
    match ext.as_str() {
        "gltf" | "glb" => super::gltf::load(path, options),
        "obj" => super::obj::load(path, options),
        "toml" => super::toml::load(path, options),
        _ => Err(Error::Unsupported(format!(
            "{}: not a scene file texmap reads (.gltf, .glb, .obj, .toml)",
            path.display()
        ))),
    }
}

/// Reads a whole file, refusing it when it is larger than `max_bytes`.
pub(crate) fn read_bounded(path: &Path, max_bytes: u64) -> Result<Vec<u8>> {
    let meta = std::fs::metadata(path).map_err(|e| Error::io(path, e))?;
    if meta.len() > max_bytes {
        return Err(Error::limits(
            path,
            format!(
                "file is {} bytes, above the limit of {max_bytes}",
                meta.len()
            ),
        ));
    }
    std::fs::read(path).map_err(|e| Error::io(path, e))
}

/// Resolves a reference `rel` made by the asset `asset` (a file path, already decoded from
/// any URI escaping), enforcing the folder rule.
pub(crate) fn resolve_reference(asset: &Path, rel: &str, allow_outside: bool) -> Result<PathBuf> {
    let lower = rel.to_ascii_lowercase();
    if lower.starts_with("http:") || lower.starts_with("https:") {
        return Err(Error::Unsupported(format!(
            "{}: refers to {rel}: texmap never fetches over the network",
            asset.display()
        )));
    }
    if let Some((scheme, _)) = rel.split_once(':') {
        // A URI scheme (letters, then ':'), but not a Windows drive letter.
        if scheme.len() > 1
            && scheme
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || "+.-".contains(c))
        {
            return Err(Error::Unsupported(format!(
                "{}: refers to {rel}: only relative paths and data: URIs are read",
                asset.display()
            )));
        }
    }
    let base = asset.parent().unwrap_or(Path::new(""));
    let rel_path = Path::new(rel);
    let joined = base.join(rel_path);
    if allow_outside {
        return Ok(joined);
    }
    let refused = || {
        Error::parameter(format!(
            "{}: refers to {rel}, outside the asset's folder (allow with --allow-outside-paths)",
            asset.display()
        ))
    };
    // Lexically: no absolute path, and `..` never climbs above the folder.
    let mut depth = 0i32;
    for c in rel_path.components() {
        match c {
            Component::Prefix(_) | Component::RootDir => return Err(refused()),
            Component::ParentDir => {
                depth -= 1;
                if depth < 0 {
                    return Err(refused());
                }
            }
            Component::Normal(_) => depth += 1,
            Component::CurDir => {}
        }
    }
    // Through symbolic links: the real file must be inside the real folder.
    if let (Ok(real), Ok(real_base)) = (
        joined.canonicalize(),
        if base.as_os_str().is_empty() {
            Path::new(".").canonicalize()
        } else {
            base.canonicalize()
        },
    ) {
        if !real.starts_with(&real_base) {
            return Err(refused());
        }
    }
    Ok(joined)
}

/// Decodes `%XX` escapes of a URI path.
pub(crate) fn percent_decode(s: &str) -> String {
    let b = s.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'%' && i + 2 < b.len() {
            let hex = std::str::from_utf8(&b[i + 1..i + 3]).ok();
            if let Some(v) = hex.and_then(|h| u8::from_str_radix(h, 16).ok()) {
                out.push(v);
                i += 3;
                continue;
            }
        }
        out.push(b[i]);
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}

/// Decodes a `data:` URI's payload (base64 or percent-encoded), bounded by `max_bytes`.
pub(crate) fn decode_data_uri(
    asset: &Path,
    uri: &str,
    max_bytes: u64,
) -> Result<(Option<String>, Vec<u8>)> {
    let rest = &uri[5..];
    let (header, payload) = rest
        .split_once(',')
        .ok_or_else(|| Error::decode(asset, "malformed data: URI (no comma)"))?;
    // Base64 yields 3 bytes per 4 characters.
    if (payload.len() as u64 / 4) * 3 > max_bytes {
        return Err(Error::limits(
            asset,
            format!("a data: URI holds more than the limit of {max_bytes} bytes"),
        ));
    }
    let mime = header
        .split(';')
        .next()
        .filter(|m| !m.is_empty())
        .map(str::to_string);
    let bytes = if header.ends_with(";base64") {
        use base64::Engine;
        base64::engine::general_purpose::STANDARD
            .decode(payload.trim())
            .map_err(|e| Error::decode(asset, format!("bad base64 in a data: URI: {e}")))?
    } else {
        percent_decode(payload).into_bytes()
    };
    Ok((mime, bytes))
}

/// Where a texture's bytes come from.
pub(crate) enum ImageSource<'a> {
    File(PathBuf),
    Bytes { name: String, bytes: &'a [u8] },
}

/// Loads textures once per (source, colour space), applying `--lenient` and recording
/// [`TextureInfo`]s and warnings.
pub(crate) struct TextureCache {
    cache: HashMap<(String, bool), Option<Arc<Texture2D>>>,
    pub infos: Vec<TextureInfo>,
    pub warnings: Vec<String>,
    lenient: bool,
    limits: Limits,
}

impl TextureCache {
    pub fn new(options: &LoadOptions) -> Self {
        TextureCache {
            cache: HashMap::new(),
            infos: Vec::new(),
            warnings: Vec::new(),
            lenient: options.lenient,
            limits: options.limits,
        }
    }

    /// The texture, `None` when the image format is one texmap cannot decode (KTX2, WebP:
    /// a warning, the channel reads as absent), or an error for a missing/corrupt image
    /// unless lenient (then a magenta placeholder). `opaque` drops the alpha channel (for
    /// glTF's OPAQUE base colour, whose alpha is ignored: a texel with alpha 0 keeps its
    /// colour instead of being premultiplied to black).
    pub fn get(
        &mut self,
        key: &str,
        source: ImageSource<'_>,
        srgb: bool,
        opaque: bool,
    ) -> Result<Option<Arc<Texture2D>>> {
        let key = format!("{key}{}", if opaque { "#opaque" } else { "" });
        let key = key.as_str();
        if let Some(t) = self.cache.get(&(key.to_string(), srgb)) {
            return Ok(t.clone());
        }
        let cs = if srgb {
            ColorSpace::Srgb
        } else {
            ColorSpace::Linear
        };
        let name = match &source {
            ImageSource::File(p) => p.display().to_string(),
            ImageSource::Bytes { name, .. } => name.clone(),
        };
        let lower = name.to_ascii_lowercase();
        if lower.ends_with(".ktx2")
            || lower.ends_with(".webp")
            || lower.ends_with(".basis")
            || lower.ends_with(".dds")
        {
            self.warnings.push(format!(
                "{name}: image format not decoded by texmap; the texture is left out"
            ));
            self.cache.insert((key.to_string(), srgb), None);
            return Ok(None);
        }
        let decoded = match &source {
            ImageSource::File(p) => decode_image(p, &self.limits),
            ImageSource::Bytes { name, bytes } => {
                decode_image_bytes(bytes, Path::new(name), &self.limits)
            }
        };
        let decoded = decoded.map(|img| if opaque { drop_alpha(img) } else { img });
        let result = decoded.and_then(|img| {
            texture_from_image(img, cs, TextureOptions::default())
                .map_err(|e| Error::decode(&name, e.to_string()))
        });
        let (tex, placeholder) = match result {
            Ok(t) => (Arc::new(t), false),
            Err(e @ Error::Limits { .. }) => return Err(e),
            Err(e) if self.lenient => {
                self.warnings
                    .push(format!("{e} (using a magenta placeholder)"));
                (placeholder_texture(), true)
            }
            Err(e) => return Err(e),
        };
        self.infos.push(TextureInfo {
            name,
            width: tex.width(),
            height: tex.height(),
            format: tex.format(),
            color_space: tex.color_space(),
            placeholder,
        });
        self.cache
            .insert((key.to_string(), srgb), Some(tex.clone()));
        Ok(Some(tex))
    }
}

/// The image without its alpha channel.
fn drop_alpha(img: DynamicImage) -> DynamicImage {
    if !img.color().has_alpha() {
        return img;
    }
    match img {
        DynamicImage::ImageLumaA8(_) => DynamicImage::ImageLuma8(img.to_luma8()),
        DynamicImage::ImageRgba8(_) => DynamicImage::ImageRgb8(img.to_rgb8()),
        DynamicImage::ImageRgba32F(_) => DynamicImage::ImageRgb32F(img.to_rgb32f()),
        other => DynamicImage::ImageRgb16(other.to_rgb16()),
    }
}

/// The 2×2 magenta texture that stands for a missing one.
#[must_use]
pub fn placeholder_texture() -> Arc<Texture2D> {
    let px = [255u8, 0, 255, 255].repeat(4);
    Arc::new(
        Texture2D::from_rgba8(2, 2, ColorSpace::Srgb, &px)
            .expect("a 2x2 RGBA8 buffer of 16 bytes is a valid texture"),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn references_stay_in_the_asset_folder() {
        let a = Path::new("/tmp/models/x.gltf");
        assert!(resolve_reference(a, "tex/a.png", false).is_ok());
        assert!(resolve_reference(a, "tex/../a.png", false).is_ok());
        assert!(resolve_reference(a, "../a.png", false).is_err());
        assert!(resolve_reference(a, "tex/../../a.png", false).is_err());
        assert!(resolve_reference(a, "/etc/passwd", false).is_err());
        assert!(resolve_reference(a, "../a.png", true).is_ok());
        assert!(resolve_reference(a, "http://example.com/a.png", true).is_err());
        assert!(resolve_reference(a, "file:///etc/passwd", true).is_err());
    }

    #[test]
    fn percent_decoding() {
        assert_eq!(percent_decode("a%20b%2"), "a b%2");
        assert_eq!(percent_decode("%41%42"), "AB");
    }

    #[test]
    fn data_uris_decode_and_are_bounded() {
        let a = Path::new("x.gltf");
        let (m, b) = decode_data_uri(a, "data:application/octet-stream;base64,AAEC", 100).unwrap();
        assert_eq!(m.as_deref(), Some("application/octet-stream"));
        assert_eq!(b, [0, 1, 2]);
        assert!(decode_data_uri(a, "data:;base64,AAECAAEC", 3).is_err());
    }
}
