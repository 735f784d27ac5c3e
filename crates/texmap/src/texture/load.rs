//! Loading textures from image files: PNG (8 and 16 bit), JPEG, TGA, BMP, Radiance HDR and
//! OpenEXR, through the `image` crate, and the texture containers DDS, KTX and KTX2
//! ([`super::container`], told by their magic bytes), with size limits checked before any
//! large allocation.

use std::path::Path;

use image::{DynamicImage, ImageReader};

use super::container::{read_texture_file, texture_from_file, Container};
use super::{ColorSpace, Format, Texture2D, TextureOptions};
use crate::{Error, Result};

/// Upper bounds on what a file may make texmap allocate.
///
/// Built from [`Limits::default`] and the `with_*` methods, so a bound added later breaks no
/// caller (the type is `#[non_exhaustive]`); the fields stay public to read and assign.
///
/// ```
/// use texmap::texture::load::Limits;
/// let l = Limits::default().with_max_dimension(4096).with_max_bytes(256 << 20);
/// assert_eq!((l.max_width, l.max_height, l.max_bytes), (4096, 4096, 256 << 20));
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub struct Limits {
    /// Largest accepted width in texels (default 16384).
    pub max_width: u32,
    /// Largest accepted height in texels (default 16384).
    pub max_height: u32,
    /// Largest decoded size in bytes (default 1 GiB).
    pub max_bytes: u64,
}

impl Default for Limits {
    fn default() -> Self {
        Limits {
            max_width: 16384,
            max_height: 16384,
            max_bytes: 1 << 30,
        }
    }
}

impl Limits {
    /// These limits with the largest width and height both `texels`.
    #[must_use]
    pub fn with_max_dimension(self, texels: u32) -> Self {
        self.with_max_width(texels).with_max_height(texels)
    }

    /// These limits with the largest width `texels`.
    #[must_use]
    pub fn with_max_width(mut self, texels: u32) -> Self {
        self.max_width = texels;
        self
    }

    /// These limits with the largest height `texels`.
    #[must_use]
    pub fn with_max_height(mut self, texels: u32) -> Self {
        self.max_height = texels;
        self
    }

    /// These limits with the largest decoded size `bytes`.
    #[must_use]
    pub fn with_max_bytes(mut self, bytes: u64) -> Self {
        self.max_bytes = bytes;
        self
    }
}

/// Decodes an image file into a texture with a full mip chain.
///
/// `color_space` says what 8- and 16-bit channels hold (sRGB colour or linear data); float
/// images (HDR, EXR) are always linear. Grey images are expanded to RGB(A) so they read grey.
/// A DDS, KTX or KTX2 file gives its 2D texture with its own mip chain when complete, its
/// `_SRGB` formats decoded as sRGB whatever `color_space` says
/// ([`super::container::texture_from_file`]); a cube map, array or volume texture is refused.
pub fn load_texture(path: &Path, color_space: ColorSpace, limits: &Limits) -> Result<Texture2D> {
    load_texture_with(path, color_space, limits, TextureOptions::default())
}

/// [`load_texture`] with the mip chain, layout and storage `options` say (with
/// [`super::Storage::Compressed`], a block-compressed file's levels stay its blocks).
pub fn load_texture_with(
    path: &Path,
    color_space: ColorSpace,
    limits: &Limits,
    options: TextureOptions,
) -> Result<Texture2D> {
    if Container::of_file(path).is_some() {
        let file = read_texture_file(path, limits)?;
        return texture_from_file(&file, color_space, options);
    }
    let img = decode_image(path, limits)?;
    texture_from_image(img, color_space, options).map_err(|e| Error::decode(path, e.to_string()))
}

/// Decodes an image file, refusing it before allocation when it breaks `limits`.
pub fn decode_image(path: &Path, limits: &Limits) -> Result<DynamicImage> {
    crate::files::check_regular(path)?;
    decode_with(|| ImageReader::open(path), path, limits)
}

/// Decodes an image held in memory (`name` is used in messages; the format comes from the
/// bytes), refusing it before allocation when it breaks `limits`.
pub fn decode_image_bytes(bytes: &[u8], name: &Path, limits: &Limits) -> Result<DynamicImage> {
    decode_with(
        || Ok(ImageReader::new(std::io::Cursor::new(bytes))),
        name,
        limits,
    )
}

/// The decoding both sources share: `open` is called twice, once to read the header alone.
fn decode_with<R: std::io::BufRead + std::io::Seek>(
    open: impl Fn() -> std::io::Result<ImageReader<R>>,
    name: &Path,
    limits: &Limits,
) -> Result<DynamicImage> {
    let guessed = || {
        open()
            .and_then(|r| r.with_guessed_format())
            .map_err(|e| Error::io(name, e))
    };
    let mut reader = guessed()?;
    if reader.format().is_none() {
        return Err(Error::decode(
            name,
            "not an image format texmap reads (PNG, JPEG, TGA, BMP, HDR, EXR; DDS, KTX, KTX2)",
        ));
    }
    // Read the header first: refuse oversized images before the decoder allocates.
    let (w, h) = guessed()?
        .into_dimensions()
        .map_err(|e| image_error(name, e))?;
    check_size(name, w, h, limits)?;
    let mut l = image::Limits::default();
    l.max_image_width = Some(limits.max_width);
    l.max_image_height = Some(limits.max_height);
    l.max_alloc = Some(limits.max_bytes);
    reader.limits(l);
    reader.decode().map_err(|e| image_error(name, e))
}

fn check_size(path: &Path, w: u32, h: u32, limits: &Limits) -> Result<()> {
    if w > limits.max_width || h > limits.max_height {
        return Err(Error::limits(
            path,
            format!(
                "image is {w}x{h}, above the limit of {}x{}",
                limits.max_width, limits.max_height
            ),
        ));
    }
    // The widest texel we may decode to: 4 × f32.
    let bytes = w as u64 * h as u64 * 16;
    if bytes > limits.max_bytes {
        return Err(Error::limits(
            path,
            format!(
                "image is {w}x{h}: up to {} MiB decoded, above the limit of {} MiB",
                bytes >> 20,
                limits.max_bytes >> 20
            ),
        ));
    }
    Ok(())
}

fn image_error(path: &Path, e: image::ImageError) -> Error {
    match e {
        image::ImageError::Limits(l) => Error::limits(path, l.to_string()),
        image::ImageError::IoError(io) => Error::io(path, io),
        other => Error::decode(path, other.to_string()),
    }
}

/// Converts a decoded image to a texture in the closest [`Format`].
pub fn texture_from_image(
    img: DynamicImage,
    color_space: ColorSpace,
    options: TextureOptions,
) -> Result<Texture2D> {
    let (w, h) = (img.width(), img.height());
    let (format, bytes): (Format, Vec<u8>) = match img {
        DynamicImage::ImageRgb8(b) => (Format::Rgb8, b.into_raw()),
        DynamicImage::ImageRgba8(b) => (Format::Rgba8, b.into_raw()),
        DynamicImage::ImageLuma8(_) => (Format::Rgb8, img.to_rgb8().into_raw()),
        DynamicImage::ImageLumaA8(_) => (Format::Rgba8, img.to_rgba8().into_raw()),
        DynamicImage::ImageRgb32F(_) | DynamicImage::ImageRgba32F(_) => {
            let data = img.to_rgba32f().into_raw();
            (
                Format::Rgba32F,
                data.iter().flat_map(|v| v.to_le_bytes()).collect(),
            )
        }
        other => {
            // 16-bit and anything else: RGBA16 unorm.
            let data = other.to_rgba16().into_raw();
            (
                Format::Rgba16,
                data.iter().flat_map(|v| v.to_le_bytes()).collect(),
            )
        }
    };
    Texture2D::from_texels(w, h, format, color_space, &bytes, options)
}

/// `into` with its red channel taken from `from` (glTF's occlusion packed into its
/// metallic-roughness image, whose red channel nothing reads): built as one texture, whose
/// every level reads as `into`'s would in green, blue and alpha and as `from`'s would in red
/// (8-bit channels are filtered and halved each on its own; tested for every storage). Only
/// for 8-bit images of one size with no alpha below 255 (`into` RGB or RGBA, `from` RGB,
/// RGBA or grey); `Err(into)`, unchanged, otherwise.
pub fn with_red_from(
    into: DynamicImage,
    from: &DynamicImage,
) -> std::result::Result<DynamicImage, DynamicImage> {
    let opaque = |img: &DynamicImage| match img {
        DynamicImage::ImageRgb8(_) | DynamicImage::ImageLuma8(_) => true,
        DynamicImage::ImageRgba8(b) => b.pixels().all(|p| p.0[3] == 255),
        _ => false,
    };
    let same_size = (into.width(), into.height()) == (from.width(), from.height());
    let into_rgb = matches!(
        into,
        DynamicImage::ImageRgb8(_) | DynamicImage::ImageRgba8(_)
    );
    if !(same_size && into_rgb && opaque(&into) && opaque(from)) {
        return Err(into);
    }
    // `from`'s red as its texture holds it: a grey image's value in every channel.
    let red: Vec<u8> = match from {
        DynamicImage::ImageRgb8(b) => b.pixels().map(|p| p.0[0]).collect(),
        DynamicImage::ImageRgba8(b) => b.pixels().map(|p| p.0[0]).collect(),
        DynamicImage::ImageLuma8(b) => b.pixels().map(|p| p.0[0]).collect(),
        _ => return Err(into),
    };
    let mut into = into;
    match &mut into {
        DynamicImage::ImageRgb8(b) => b.pixels_mut().zip(&red).for_each(|(p, &r)| p.0[0] = r),
        DynamicImage::ImageRgba8(b) => b.pixels_mut().zip(&red).for_each(|(p, &r)| p.0[0] = r),
        _ => {}
    }
    Ok(into)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_packed_red_channel_reads_as_the_image_it_came_from() {
        use crate::texture::Storage;
        // An odd size (padded tiles, an uneven chain); the grey and RGBA cases too.
        let (w, h) = (37u32, 21u32);
        let rgb = |seed: u32| {
            DynamicImage::ImageRgb8(image::RgbImage::from_fn(w, h, |x, y| {
                let v = |k: u32| ((x * (31 + seed + k) + y * (17 + k) + seed * 7) % 256) as u8;
                image::Rgb([v(0), v(1), v(2)])
            }))
        };
        let grey = DynamicImage::ImageLuma8(image::GrayImage::from_fn(w, h, |x, y| {
            image::Luma([((x * 13 + y * 29) % 256) as u8])
        }));
        let rgba = DynamicImage::ImageRgba8(rgb(3).to_rgba8());
        for storage in [
            Storage::Linear16,
            Storage::Rgba8,
            Storage::Native,
            Storage::Compressed,
        ] {
            let options = TextureOptions::default().with_storage(storage);
            let build =
                |img: DynamicImage| texture_from_image(img, ColorSpace::Linear, options).unwrap();
            for (into, from) in [
                (rgb(1), rgb(2)),
                (rgb(1), grey.clone()),
                (rgba.clone(), rgb(2)),
            ] {
                let packed = build(with_red_from(into.clone(), &from).unwrap());
                let (into, from) = (build(into), build(from));
                for i in 0..packed.levels().len() {
                    let (p, a, b) = (
                        packed.decode_level(i),
                        into.decode_level(i),
                        from.decode_level(i),
                    );
                    for k in 0..p.len() {
                        assert_eq!(p[k].x, b[k].x, "{storage:?} level {i} texel {k}: red");
                        let rest = |c: glam::Vec4| [c.y, c.z, c.w];
                        assert_eq!(rest(p[k]), rest(a[k]), "{storage:?} level {i} texel {k}");
                    }
                }
            }
        }
        // Not packed: another size, translucent texels, 16 bits.
        let small = DynamicImage::ImageRgb8(image::RgbImage::new(4, 4));
        assert!(with_red_from(rgb(1), &small).is_err());
        let mut clear = rgb(2).to_rgba8();
        clear.get_pixel_mut(3, 3).0[3] = 254;
        assert!(with_red_from(rgb(1), &DynamicImage::ImageRgba8(clear)).is_err());
        let deep = DynamicImage::ImageRgb16(image::ImageBuffer::new(w, h));
        assert!(with_red_from(rgb(1), &deep).is_err());
        assert!(with_red_from(deep, &rgb(1)).is_err());
    }

    fn tmp(name: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("texmap-load-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir.join(name)
    }

    #[test]
    fn png_8_and_16_bit_load() {
        let p8 = tmp("a8.png");
        image::RgbaImage::from_pixel(3, 2, image::Rgba([255, 0, 0, 255]))
            .save(&p8)
            .unwrap();
        let t = load_texture(&p8, ColorSpace::Srgb, &Limits::default()).unwrap();
        assert_eq!((t.width(), t.height(), t.format()), (3, 2, Format::Rgba8));
        let p16 = tmp("a16.png");
        image::ImageBuffer::<image::Rgb<u16>, _>::from_pixel(
            2,
            2,
            image::Rgb([65535u16, 32768, 0]),
        )
        .save(&p16)
        .unwrap();
        let t = load_texture(&p16, ColorSpace::Linear, &Limits::default()).unwrap();
        assert_eq!(t.format(), Format::Rgba16);
        let c = t.texel(0, 0, 0);
        assert!((c.y - 0.5).abs() < 1e-4, "{c}");
    }

    #[test]
    fn tga_bmp_jpeg_and_exr_load() {
        let rgb =
            image::RgbImage::from_fn(5, 3, |x, y| image::Rgb([x as u8 * 50, y as u8 * 80, 200]));
        for name in ["a.tga", "a.bmp", "a.jpg"] {
            let p = tmp(name);
            rgb.save(&p).unwrap();
            let t = load_texture(&p, ColorSpace::Srgb, &Limits::default()).unwrap();
            assert_eq!((t.width(), t.height()), (5, 3), "{name}");
            assert_eq!(t.format(), Format::Rgb8, "{name}");
        }
        // OpenEXR: float, linear whatever the declared colour space, values above 1 kept.
        let hdr = image::Rgb32FImage::from_fn(4, 2, |x, _| image::Rgb([x as f32 * 2.5, 0.5, 0.0]));
        let p = tmp("a.exr");
        image::DynamicImage::ImageRgb32F(hdr).save(&p).unwrap();
        let t = load_texture(&p, ColorSpace::Srgb, &Limits::default()).unwrap();
        assert_eq!(
            (t.format(), t.color_space()),
            (Format::Rgba32F, ColorSpace::Linear)
        );
        assert!((t.texel(0, 3, 0).x - 7.5).abs() < 1e-6);
    }

    #[test]
    fn corrupt_file_names_the_file() {
        let p = tmp("corrupt.png");
        std::fs::write(&p, b"\x89PNG\r\n\x1a\nthis is not a png").unwrap();
        let e = load_texture(&p, ColorSpace::Srgb, &Limits::default()).unwrap_err();
        assert!(e.to_string().contains("corrupt.png"), "{e}");
    }

    #[test]
    fn missing_file_names_the_file() {
        let e = load_texture(
            Path::new("/nonexistent/x.png"),
            ColorSpace::Srgb,
            &Limits::default(),
        )
        .unwrap_err();
        assert!(e.to_string().contains("/nonexistent/x.png"), "{e}");
    }

    #[test]
    fn oversized_image_is_refused_before_decoding() {
        let p = tmp("big.png");
        image::RgbImage::new(64, 40).save(&p).unwrap();
        let limits = Limits::default().with_max_width(32);
        let e = load_texture(&p, ColorSpace::Srgb, &limits).unwrap_err();
        assert!(matches!(e, Error::Limits { .. }), "{e}");
        assert!(e.to_string().contains("64x40"), "{e}");
        let limits = Limits::default().with_max_bytes(1000);
        assert!(matches!(
            load_texture(&p, ColorSpace::Srgb, &limits),
            Err(Error::Limits { .. })
        ));
    }
}
