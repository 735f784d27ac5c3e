//! Images loaded for a scene's materials: each source decoded once per colour space and
//! alpha handling ([`AlphaChannel`]), a `--lenient` load turning a missing or corrupt image
//! into a magenta placeholder, and every texture recorded as a [`TextureInfo`] for
//! `texmap info`.
//!
//! Rules: image limits (size, decoded bytes) are never relaxed by `--lenient`: an image over
//! them is an error. DDS, KTX and KTX2 files (told by their magic bytes) load through
//! [`crate::texture::container`] (KTX2 holding Basis Universal is transcoded there). Formats
//! texmap cannot decode (WebP, `.basis` files, a container format it does not support) are a
//! warning and the channel is left out, not an error, as in the peer.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use image::DynamicImage;
use rayon::prelude::*;

use super::asset::{LoadOptions, TextureInfo};
use crate::shading::MapChannel;
use crate::texture::container::{self, Container, TextureFile};
use crate::texture::load::{
    decode_image, decode_image_bytes, texture_from_image, with_red_from, Limits,
};
use crate::texture::{ColorSpace, Storage, Texture2D, TextureOptions};
use crate::{Error, Result};

/// Where a texture's bytes come from.
pub(crate) enum ImageSource<'a> {
    File(PathBuf),
    Bytes { name: String, bytes: &'a [u8] },
}

impl ImageSource<'_> {
    /// The name messages give the source.
    fn name(&self) -> String {
        match self {
            ImageSource::File(p) => p.display().to_string(),
            ImageSource::Bytes { name, .. } => name.clone(),
        }
    }
}

/// Whether a source's name marks a format texmap does not decode (WebP, `.basis`).
fn not_decoded(name: &str) -> bool {
    let lower = name.to_ascii_lowercase();
    lower.ends_with(".webp") || lower.ends_with(".basis")
}

/// Whether an image's alpha channel is kept.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(crate) enum AlphaChannel {
    /// As stored: texels are premultiplied by it when read.
    Keep,
    /// Dropped at load, every texel opaque: for glTF's OPAQUE base colour, whose alpha the
    /// specification says to ignore (a texel with alpha 0 keeps its colour instead of being
    /// premultiplied to black).
    Drop,
}

/// The colour space a channel's image is decoded in unless the file says otherwise: sRGB
/// for colour channels ([`MapChannel::is_color`]), linear for data.
#[must_use]
pub(crate) fn channel_color_space(channel: MapChannel) -> ColorSpace {
    if channel.is_color() {
        ColorSpace::Srgb
    } else {
        ColorSpace::Linear
    }
}

/// What one decoded texture is: its source, and how it was decoded.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
struct CacheKey {
    source: String,
    color_space: ColorSpace,
    alpha: AlphaChannel,
    storage: Storage,
}

/// A texture [`TextureCache::prefetch`] builds: its key, source and name, and a second
/// image whose red channel it takes (its key, source, name, and the name its texture's
/// [`TextureInfo`] gives it).
struct Job<'a> {
    key: CacheKey,
    source: ImageSource<'a>,
    name: String,
    red: Option<(CacheKey, ImageSource<'a>, String, String)>,
}

/// A texture [`TextureCache::prefetch`] built: its key, the result, and for a packed texture
/// the key of the image packed into it and the texture's name.
type Built = (CacheKey, Result<Texture2D>, Option<(CacheKey, String)>);

/// Loads textures once per (source, colour space, alpha), applying `--lenient` and recording
/// [`TextureInfo`]s and warnings.
pub(crate) struct TextureCache {
    cache: HashMap<CacheKey, Option<Arc<Texture2D>>>,
    /// Textures built ahead by [`TextureCache::prefetch`], not yet asked for.
    ready: HashMap<CacheKey, Result<Texture2D>>,
    /// Textures packed into another's red channel (`packs` of [`TextureCache::prefetch`]):
    /// asking for one gives the texture it went into.
    packed: HashMap<CacheKey, CacheKey>,
    /// A packed texture's name for its [`TextureInfo`] (both images named).
    packed_names: HashMap<CacheKey, String>,
    pub infos: Vec<TextureInfo>,
    pub warnings: Vec<String>,
    lenient: bool,
    limits: Limits,
    /// How textures are held unless one says otherwise (`--texture-storage`).
    storage: Storage,
    /// How the volumes a scene's textures come from (3D solid textures) are read.
    pub volumes: crate::volume::VolumeOptions,
}

impl TextureCache {
    pub fn new(options: &LoadOptions) -> Self {
        TextureCache {
            volumes: options.volume_options(),
            cache: HashMap::new(),
            ready: HashMap::new(),
            packed: HashMap::new(),
            packed_names: HashMap::new(),
            infos: Vec::new(),
            warnings: Vec::new(),
            lenient: options.lenient,
            limits: options.limits,
            storage: options.texture_storage,
        }
    }

    /// The texture `key` names (a file path, or an index inside the asset), decoded from
    /// `source` in `color_space`; `None` when the image format is one texmap cannot decode
    /// (WebP, `.basis`: a warning, the channel reads as absent), or an error for a
    /// missing/corrupt image unless lenient (then a magenta placeholder).
    pub fn get(
        &mut self,
        key: &str,
        source: ImageSource<'_>,
        color_space: ColorSpace,
        alpha: AlphaChannel,
    ) -> Result<Option<Arc<Texture2D>>> {
        self.get_stored(key, source, color_space, alpha, None)
    }

    /// [`TextureCache::get`], held as `storage` says (the load's storage when `None`).
    pub fn get_stored(
        &mut self,
        key: &str,
        source: ImageSource<'_>,
        color_space: ColorSpace,
        alpha: AlphaChannel,
        storage: Option<Storage>,
    ) -> Result<Option<Arc<Texture2D>>> {
        let storage = storage.unwrap_or(self.storage);
        let key = CacheKey {
            source: key.to_string(),
            color_space,
            alpha,
            storage,
        };
        let key = self.packed.get(&key).cloned().unwrap_or(key);
        if let Some(t) = self.cache.get(&key) {
            return Ok(t.clone());
        }
        let name = source.name();
        // A packed texture is named for both images, whichever map asks first.
        let name = self.packed_names.get(&key).cloned().unwrap_or(name);
        if not_decoded(&name) {
            self.warnings.push(format!(
                "{name}: image format not decoded by texmap; the texture is left out"
            ));
            self.cache.insert(key, None);
            return Ok(None);
        }
        let result = match self.ready.remove(&key) {
            Some(built) => built,
            None => self.build(&source, &name, color_space, alpha, storage),
        };
        let (tex, placeholder) = match result {
            Ok(t) => (Arc::new(t), false),
            Err(Error::Unsupported(e)) => {
                // A format texmap does not decode: left out, as the peer leaves it.
                self.warnings.push(format!("{e}; the texture is left out"));
                self.cache.insert(key, None);
                return Ok(None);
            }
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
            storage: tex.storage(),
            bytes: tex.texel_bytes(),
            block_format: tex.block_format(),
            placeholder,
        });
        self.cache.insert(key, Some(tex.clone()));
        Ok(Some(tex))
    }
}

impl TextureCache {
    /// Builds the textures of `requests` (key, source, colour space, alpha, as
    /// [`TextureCache::get`] takes them) in parallel (rayon), each decoded and its chain
    /// made on its own thread, and holds each result, texture or error, until `get` asks for
    /// it: warnings, errors and [`TextureInfo`]s then come in the order the scene asks, as
    /// without prefetching. Keys already built, repeated, or of a format not decoded are
    /// skipped.
    ///
    /// `packs` names pairs of linear requests (alpha kept) to build as one texture where
    /// [`with_red_from`] can: `(into, from, from's name)`, the second image's red channel in
    /// the first's, after which asking for `from` gives `into`'s texture. The caller vouches
    /// that nothing reads `into`'s red channel and nothing reads `from` but through its red
    /// channel, with those keys (a glTF occlusion map and the metallic-roughness map its
    /// materials pair it with). A pair that cannot be packed is built as two textures.
    pub fn prefetch(
        &mut self,
        requests: Vec<(String, ImageSource<'_>, ColorSpace, AlphaChannel)>,
        packs: &[(String, String, String)],
    ) {
        let storage = self.storage;
        let mut todo: Vec<Job<'_>> = Vec::new();
        for (key, source, color_space, alpha) in requests {
            let key = CacheKey {
                source: key,
                color_space,
                alpha,
                storage,
            };
            let name = source.name();
            let known = self.cache.contains_key(&key) || self.ready.contains_key(&key);
            if known || not_decoded(&name) || todo.iter().any(|j| j.key == key) {
                continue;
            }
            todo.push(Job {
                key,
                source,
                name,
                red: None,
            });
        }
        // Each pair found among the requests: one job, `from` riding with `into`.
        for (into, from, from_name) in packs {
            let linear = |source: &String| CacheKey {
                source: source.clone(),
                color_space: ColorSpace::Linear,
                alpha: AlphaChannel::Keep,
                storage,
            };
            let (into, from) = (linear(into), linear(from));
            let Some(f) = todo.iter().position(|j| j.key == from && j.red.is_none()) else {
                continue;
            };
            if into == from || !todo.iter().any(|j| j.key == into && j.red.is_none()) {
                continue;
            }
            let job = todo.remove(f);
            if let Some(target) = todo.iter_mut().find(|j| j.key == into) {
                target.red = Some((job.key, job.source, job.name, from_name.clone()));
            }
        }
        if todo.len() < 2 && todo.iter().all(|j| j.red.is_none()) {
            return; // nothing to overlap: `get` builds it
        }
        // Largest first, each thread taking the next when it is done: the big textures'
        // decoding buffers are freed before the small ones are made (a lower peak of
        // memory), and the last to finish is a short one. The size is the image's texels
        // (its header's width × height; the encoded bytes where the header cannot be read,
        // as for DDS and KTX files), and sRGB colour is held in twice the bytes of linear
        // data (`Storage`). Not the encoded bytes alone: DamagedHelmet's emissive map
        // compresses ten times better than its base colour, came last and built its 16-bit
        // chain beside the four finished textures (the load's peak of memory).
        let weight = |key: &CacheKey, source: &ImageSource<'_>| {
            let bytes_a_texel = if key.color_space == ColorSpace::Srgb {
                2
            } else {
                1
            };
            texel_count(source) * bytes_a_texel
        };
        todo.sort_by_key(|j| {
            let red = j.red.as_ref().map_or(0, |(k, s, ..)| weight(k, s));
            std::cmp::Reverse(weight(&j.key, &j.source) + red)
        });
        let this = &*self;
        let next = std::sync::atomic::AtomicUsize::new(0);
        let workers = rayon::current_num_threads().min(todo.len());
        let built: Vec<_> = (0..workers)
            .into_par_iter()
            .flat_map_iter(|_| {
                let mut mine = Vec::new();
                while let Some(job) =
                    todo.get(next.fetch_add(1, std::sync::atomic::Ordering::Relaxed))
                {
                    this.run(job, storage, &mut mine);
                }
                mine
            })
            .collect();
        for (key, result, packed) in built {
            if let Some((from, name)) = packed {
                self.packed_names.insert(key.clone(), name);
                self.packed.insert(from, key.clone());
            }
            self.ready.insert(key, result);
        }
    }

    /// Builds `job` into `out`: its texture, or with a red channel to take, the one packed
    /// texture (with the key it stands for and that image's name) or, where they cannot be
    /// packed, the two.
    fn run(&self, job: &Job<'_>, storage: Storage, out: &mut Vec<Built>) {
        let build = |key: &CacheKey, source: &ImageSource<'_>, name: &str| {
            self.build(source, name, key.color_space, key.alpha, storage)
        };
        let Some((red_key, red_source, red_name, red_label)) = &job.red else {
            out.push((
                job.key.clone(),
                build(&job.key, &job.source, &job.name),
                None,
            ));
            return;
        };
        // Images the `image` crate decodes, each once (a container's texture is built as it
        // is: `None`).
        let image = |source: &ImageSource<'_>| {
            let plain = container_of(source).is_none();
            plain.then(|| self.decode(source))
        };
        let options = TextureOptions::default().with_storage(storage);
        let texture = |img, name: &str| {
            texture_from_image(img, ColorSpace::Linear, options)
                .map_err(|e| Error::decode(name, e.to_string()))
        };
        match (image(&job.source), image(red_source)) {
            (Some(Ok(into)), Some(Ok(from))) => match with_red_from(into, &from) {
                Ok(packed) => {
                    drop(from);
                    let name = format!("{}, red channel from {red_label}", job.name);
                    out.push((
                        job.key.clone(),
                        texture(packed, &job.name),
                        Some((red_key.clone(), name)),
                    ));
                }
                Err(into) => {
                    out.push((job.key.clone(), texture(into, &job.name), None));
                    out.push((red_key.clone(), texture(from, red_name), None));
                }
            },
            // Not both decoded: each built apart, from the image already decoded (or its
            // error), a container's from its file.
            (into, from) => {
                let apart =
                    |decoded: Option<Result<DynamicImage>>, key: &CacheKey, source, name| {
                        match decoded {
                            Some(img) => img.and_then(|img| texture(img, name)),
                            None => build(key, source, name),
                        }
                    };
                let t = apart(into, &job.key, &job.source, &job.name);
                out.push((job.key.clone(), t, None));
                let t = apart(from, red_key, red_source, red_name);
                out.push((red_key.clone(), t, None));
            }
        }
    }

    /// The texture `source` holds, decoded in `color_space` with its alpha as `alpha` says,
    /// held as `storage`.
    fn build(
        &self,
        source: &ImageSource<'_>,
        name: &str,
        color_space: ColorSpace,
        alpha: AlphaChannel,
        storage: Storage,
    ) -> Result<Texture2D> {
        let options = TextureOptions::default().with_storage(storage);
        if container_of(source).is_some() {
            self.container_texture(source, name, color_space, alpha, options)
        } else {
            self.image_texture(source, name, color_space, alpha, options)
        }
    }

    /// A texture from an image file or bytes the `image` crate decodes.
    fn image_texture(
        &self,
        source: &ImageSource<'_>,
        name: &str,
        color_space: ColorSpace,
        alpha: AlphaChannel,
        options: TextureOptions,
    ) -> Result<Texture2D> {
        let img = self.decode(source)?;
        let img = match alpha {
            AlphaChannel::Keep => img,
            AlphaChannel::Drop => drop_alpha(img),
        };
        texture_from_image(img, color_space, options)
            .map_err(|e| Error::decode(name, e.to_string()))
    }

    /// The image `source` holds, decoded by the `image` crate.
    fn decode(&self, source: &ImageSource<'_>) -> Result<DynamicImage> {
        match source {
            ImageSource::File(p) => decode_image(p, &self.limits),
            ImageSource::Bytes { name, bytes } => {
                decode_image_bytes(bytes, Path::new(name), &self.limits)
            }
        }
    }

    /// A texture from a DDS, KTX or KTX2 file or bytes.
    fn container_texture(
        &self,
        source: &ImageSource<'_>,
        name: &str,
        color_space: ColorSpace,
        alpha: AlphaChannel,
        options: TextureOptions,
    ) -> Result<Texture2D> {
        let file = match source {
            ImageSource::File(p) => container::read_texture_file(p, &self.limits)?,
            ImageSource::Bytes { bytes, .. } => {
                if bytes.len() as u64 > self.limits.max_bytes {
                    return Err(Error::limits(
                        name,
                        format!(
                            "texture file is {} bytes, above the limit of {}",
                            bytes.len(),
                            self.limits.max_bytes
                        ),
                    ));
                }
                TextureFile::from_bytes(bytes.to_vec(), Path::new(name), &self.limits)?
            }
        };
        container::texture_from_file_with(&file, color_space, options, alpha == AlphaChannel::Drop)
    }
}

/// The texture container (DDS, KTX, KTX2) `source` is, if it is one.
fn container_of(source: &ImageSource<'_>) -> Option<Container> {
    match source {
        ImageSource::File(p) => Container::of_file(p),
        ImageSource::Bytes { bytes, .. } => Container::sniff(bytes),
    }
}

/// The texels `source` holds by its header (width × height), or its encoded bytes when no
/// image header can be read (a container file, a corrupt image): an ordering guess only.
fn texel_count(source: &ImageSource<'_>) -> u64 {
    use image::ImageReader;
    let size = match source {
        ImageSource::File(p) => ImageReader::open(p)
            .and_then(ImageReader::with_guessed_format)
            .ok()
            .and_then(|r| r.into_dimensions().ok()),
        ImageSource::Bytes { bytes, .. } => ImageReader::new(std::io::Cursor::new(*bytes))
            .with_guessed_format()
            .ok()
            .and_then(|r| r.into_dimensions().ok()),
    };
    match size {
        Some((w, h)) => u64::from(w) * u64::from(h),
        None => match source {
            ImageSource::File(p) => std::fs::metadata(p).map_or(0, |m| m.len()),
            ImageSource::Bytes { bytes, .. } => bytes.len() as u64,
        },
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
pub(crate) fn placeholder_texture() -> Arc<Texture2D> {
    let px = [255u8, 0, 255, 255].repeat(4);
    Arc::new(
        Texture2D::from_rgba8(2, 2, ColorSpace::Srgb, &px)
            .expect("a 2x2 RGBA8 buffer of 16 bytes is a valid texture"),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn png(w: u32, h: u32, seed: u32) -> Vec<u8> {
        let img = image::RgbImage::from_fn(w, h, |x, y| {
            let v = (x * 7 + y * 13 + seed) as u8;
            image::Rgb([v, v.wrapping_mul(3), 255 - v])
        });
        let mut out = std::io::Cursor::new(Vec::new());
        img.write_to(&mut out, image::ImageFormat::Png).unwrap();
        out.into_inner()
    }

    /// The cache's answers for `sources` asked in order, after prefetching them or not:
    /// each texture's level 0, or its error message; and the infos' names.
    fn ask(sources: &[(&str, &[u8])], prefetch: bool) -> (Vec<String>, Vec<String>) {
        ask_in(sources, prefetch.then_some(&[]), ColorSpace::Srgb)
    }

    /// [`ask`] in `color_space`, prefetching with `packs` when given.
    fn ask_in(
        sources: &[(&str, &[u8])],
        packs: Option<&[(String, String, String)]>,
        color_space: ColorSpace,
    ) -> (Vec<String>, Vec<String>) {
        let mut cache = TextureCache::new(&LoadOptions::default());
        let source = |name: &str, bytes| ImageSource::Bytes {
            name: name.to_string(),
            bytes,
        };
        if let Some(packs) = packs {
            let requests = sources
                .iter()
                .map(|&(n, b)| (n.to_string(), source(n, b), color_space, AlphaChannel::Keep))
                .collect();
            cache.prefetch(requests, packs);
            assert_eq!(cache.ready.len(), sources.len());
        }
        let answers = sources
            .iter()
            .map(
                |&(n, b)| match cache.get(n, source(n, b), color_space, AlphaChannel::Keep) {
                    Ok(Some(t)) => format!("{:?}", t.decode_level(0)),
                    Ok(None) => "left out".into(),
                    Err(e) => e.to_string(),
                },
            )
            .collect();
        assert!(cache.ready.is_empty());
        (
            answers,
            cache.infos.iter().map(|i| i.name.clone()).collect(),
        )
    }

    /// A pair to pack that cannot be (an image broken, or two sizes) gives each texture, or
    /// its error, as asking for the two apart does.
    #[test]
    fn a_pair_that_cannot_be_packed_gives_what_asking_apart_gives() {
        let (a, b, c) = (png(9, 5, 1), png(9, 5, 2), png(4, 11, 3));
        let broken: &[u8] = b"\x89PNG\r\n\x1a\nnot a png";
        let packs = [(
            "mr.png".to_string(),
            "occ.png".to_string(),
            "occlusion".to_string(),
        )];
        for sources in [
            [("mr.png", &a[..]), ("occ.png", broken)],
            [("mr.png", broken), ("occ.png", &b[..])],
            [("mr.png", &a[..]), ("occ.png", &c[..])],
        ] {
            let apart = ask_in(&sources, None, ColorSpace::Linear);
            let fetched = ask_in(&sources, Some(&packs), ColorSpace::Linear);
            assert_eq!(fetched, apart);
            // The broken image's error names it; the other is a texture.
            for (answer, (name, bytes)) in apart.0.iter().zip(sources) {
                let error = answer.starts_with(&format!("{name}: "));
                assert_eq!(error, bytes == broken, "{answer}");
            }
        }
    }

    #[test]
    fn prefetched_textures_and_errors_are_what_asking_gives() {
        let (a, b) = (png(9, 5, 1), png(4, 11, 2));
        let sources: [(&str, &[u8]); 3] = [
            ("a.png", &a),
            ("broken.png", b"\x89PNG\r\n\x1a\nnot a png"),
            ("b.png", &b),
        ];
        let (plain, plain_infos) = ask(&sources, false);
        let (fetched, fetched_infos) = ask(&sources, true);
        assert_eq!(plain, fetched);
        assert_eq!(plain_infos, fetched_infos);
        assert!(plain[1].contains("broken.png"), "{}", plain[1]);
    }
}
