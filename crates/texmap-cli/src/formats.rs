//! The image formats texmap writes, chosen by the output's name (or `--format`), and their
//! encoders. Where the bytes go (a file atomically, a stream, stdout) is `output.rs`.
//!
//! | extension | format | what it holds |
//! |---|---|---|
//! | `.png` | PNG, 8-bit | sRGB colour over black (RGB), or straight alpha (RGBA, `--alpha`) |
//! | `.exr` | OpenEXR, 32-bit float RGBA | the frame's linear colour, premultiplied, and its alpha |
//! | `.hdr` | Radiance RGBE | the frame's linear colour over black, no alpha |
//!
//! Extensions are case-insensitive. `-` (stdout) and a name without an extension (a device,
//! a FIFO) are PNG unless `--format` says otherwise; any other extension is refused before
//! anything is rendered. With `--format`, a name whose extension is another known format is
//! refused (PNG bytes under an `.exr` name were the fault this rule ends).
//!
//! OpenEXR is written through the `exr` crate (the one `image` uses), pixels read straight
//! from the frame (`image`'s encoder takes a byte buffer, a copy of 16 bytes a pixel), in
//! scanlines with RLE compression (lossless). Measured on `builtin:demo` at
//! 1920×1080 (the dev build, a loaded 2-core machine): RLE 29.3 MB and about as fast as the
//! PNG; ZIP 17.9 MB but 2–4 s more per frame; uncompressed 33.2 MB. Radiance through `image`'s
//! encoder, which truncates each channel to 8 bits of mantissa under the pixel's shared
//! exponent (error below 1/128 of the pixel's largest channel).

use std::io::{Seek, Write};
use std::path::Path;

use clap::ValueEnum;
use glam::Vec4;
use image::ImageEncoder;
use texmap::frame::Frame;
use texmap::Error;

/// An image format texmap writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum OutputFormat {
    /// PNG, 8-bit sRGB (RGB, or RGBA with `--alpha`; 16-bit with `--bit-depth 16`).
    Png,
    /// OpenEXR, 32-bit float linear RGBA, premultiplied.
    Exr,
    /// Radiance RGBE, linear RGB, no alpha.
    Hdr,
    /// JPEG, 8-bit sRGB RGB (`--quality`), no alpha.
    #[value(alias = "jpg")]
    Jpeg,
    /// Animated GIF: every frame of an input in one file, 8-bit palette per frame.
    Gif,
    /// Animated PNG: every frame of an input in one file (8 or 16-bit, alpha with `--alpha`).
    Apng,
}

impl OutputFormat {
    const ALL: [OutputFormat; 6] = [
        OutputFormat::Png,
        OutputFormat::Exr,
        OutputFormat::Hdr,
        OutputFormat::Jpeg,
        OutputFormat::Gif,
        OutputFormat::Apng,
    ];

    /// The file extension (lower case, no dot).
    #[must_use]
    pub fn extension(self) -> &'static str {
        match self {
            OutputFormat::Png => "png",
            OutputFormat::Exr => "exr",
            OutputFormat::Hdr => "hdr",
            OutputFormat::Jpeg => "jpg",
            OutputFormat::Gif => "gif",
            OutputFormat::Apng => "apng",
        }
    }

    /// The format an extension (lower case) names.
    fn for_extension(ext: &str) -> Option<OutputFormat> {
        match ext {
            "jpeg" => Some(OutputFormat::Jpeg),
            e => Self::ALL.into_iter().find(|f| f.extension() == e),
        }
    }

    /// The format's name in messages.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            OutputFormat::Png => "PNG",
            OutputFormat::Exr => "OpenEXR",
            OutputFormat::Hdr => "Radiance HDR",
            OutputFormat::Jpeg => "JPEG",
            OutputFormat::Gif => "GIF",
            OutputFormat::Apng => "APNG",
        }
    }

    /// True for the formats that hold every frame of an input in one file.
    #[must_use]
    pub fn is_animated(self) -> bool {
        matches!(self, OutputFormat::Gif | OutputFormat::Apng)
    }

    /// The format of an output named `path` (`flag` names the option in messages), with
    /// `explicit` the `--format` given, if any. See the module docs for the rule.
    ///
    /// # Errors
    /// [`Error::Parameter`]: an extension texmap does not write, or one that contradicts
    /// `explicit`.
    pub fn for_output(
        path: &Path,
        flag: &str,
        explicit: Option<OutputFormat>,
    ) -> Result<OutputFormat, Error> {
        let ext = if path.as_os_str() == "-" {
            None
        } else {
            path.extension().map(|e| e.to_string_lossy().to_lowercase())
        };
        let named = ext.as_deref().map(|e| Self::for_extension(e).ok_or(e));
        match (named, explicit) {
            (None, f) => Ok(f.unwrap_or(OutputFormat::Png)),
            (Some(Ok(n)), None) => Ok(n),
            (Some(Ok(n)), Some(f)) if n == f => Ok(f),
            (Some(Ok(n)), Some(f)) => Err(Error::parameter(format!(
                "{flag} {}: the name says {} (.{}) but --format is {}",
                path.display(),
                n.name(),
                n.extension(),
                f.extension()
            ))),
            (Some(Err(_)), Some(f)) => Ok(f),
            (Some(Err(e)), None) => Err(Error::parameter(format!(
                "{flag} {}: texmap does not write .{e} images (it writes .png, .exr, .hdr, \
                 .jpg, .gif and .apng; --format chooses for other names)",
                path.display()
            ))),
        }
    }

    /// True when the encoder seeks back in its output (an EXR's offset table): a stream
    /// gets the image encoded in memory first.
    #[must_use]
    pub fn needs_seek(self) -> bool {
        self == OutputFormat::Exr
    }

    /// The bytes per pixel the encoding holds in memory besides the frame, for the memory
    /// budget: an APNG frame's 8-bit rows (a still PNG holds a band of rows only); Radiance's float RGB copy; an EXR's encoded file when it goes
    /// to a stream (at most its uncompressed size, 16 bytes, and its block table).
    #[must_use]
    pub fn buffer_bytes_per_pixel(self) -> u64 {
        match self {
            // A still PNG is encoded a band of rows at a time (`png_bands`).
            OutputFormat::Png => 0,
            OutputFormat::Apng => 8,
            OutputFormat::Exr => 17,
            OutputFormat::Hdr => 12,
            OutputFormat::Jpeg | OutputFormat::Gif => 4,
        }
    }
}

/// How the 8/16-bit formats (PNG, JPEG, GIF, APNG) store a linear image.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Store {
    /// RGBA with straight alpha ([`Frame::to_srgba8`]); otherwise RGB, the colour
    /// composited over black ([`Frame::to_srgb8`]).
    pub alpha: bool,
    /// 16 bits a channel (PNG, APNG), sRGB-encoded exactly rounded.
    pub sixteen: bool,
    /// JPEG quality, 1–100.
    pub quality: u8,
}

impl Store {
    /// 8-bit sRGB RGB.
    pub const SRGB: Store = Store {
        alpha: false,
        sixteen: false,
        quality: 90,
    };

    /// A `png` encoder of an image of `size` with this store's colour type and bit depth.
    pub fn png_encoder<W: Write>(
        self,
        w: W,
        (width, height): (u32, u32),
    ) -> png::Encoder<'static, W> {
        let mut e = png::Encoder::new(w, width, height);
        e.set_color(if self.alpha {
            png::ColorType::Rgba
        } else {
            png::ColorType::Rgb
        });
        e.set_depth(if self.sixteen {
            png::BitDepth::Sixteen
        } else {
            png::BitDepth::Eight
        });
        e
    }

    /// The bytes of `frame` as PNG rows: 8-bit, or 16-bit big-endian with `big_endian`
    /// (else native-endian, as `image`'s PNG encoder takes them).
    pub fn png_rows(self, frame: &Frame, big_endian: bool) -> Vec<u8> {
        self.png_pixels(&frame.color, big_endian)
    }

    /// [`Store::png_rows`] of some pixels (whole rows of a frame).
    pub fn png_pixels(self, color: &[Vec4], big_endian: bool) -> Vec<u8> {
        match (self.sixteen, self.alpha) {
            (false, false) => texmap::frame::srgb8(color),
            (false, true) => texmap::frame::srgba8(color),
            (true, alpha) => {
                let mut out = Vec::with_capacity(color.len() * if alpha { 8 } else { 6 });
                let mut push = |v: u16| {
                    out.extend(if big_endian {
                        v.to_be_bytes()
                    } else {
                        v.to_ne_bytes()
                    })
                };
                for c in color {
                    let (rgb, a) = if alpha {
                        // Also NaN: nothing to divide by.
                        if c.w > 0.0 {
                            (c.truncate() / c.w.min(1.0), c.w)
                        } else {
                            (glam::Vec3::ZERO, 0.0)
                        }
                    } else {
                        (c.truncate(), 1.0)
                    };
                    for v in rgb.to_array() {
                        push(unorm16(texmap::color::linear_to_srgb(v)));
                    }
                    if alpha {
                        push(unorm16(a));
                    }
                }
                out
            }
        }
    }
}

/// `v` in 0..1 as a 16-bit code, rounded to nearest (NaN is 0).
fn unorm16(v: f32) -> u16 {
    if v > 0.0 {
        (v.min(1.0) * 65535.0 + 0.5) as u16
    } else {
        0
    }
}

/// What an image file is made from.
pub enum Picture<'a> {
    /// Linear premultiplied RGBA (a render, a baked pattern): any format; `Store` says how
    /// the 8/16-bit formats store it.
    Linear(&'a Frame, Store),
    /// 8-bit RGB rows, already encoded (a false-colour difference image, a pattern baked to
    /// PNG): PNG only.
    Rgb8 {
        width: u32,
        height: u32,
        rgb: &'a [u8],
    },
    /// 8-bit RGBA rows written as they are, straight alpha (a texture's decoded bytes, for
    /// `texmap convert`): PNG only.
    Rgba8 {
        width: u32,
        height: u32,
        rgba: &'a [u8],
    },
}

impl Picture<'_> {
    fn size(&self) -> (u32, u32) {
        match self {
            Picture::Linear(f, _) => (f.width, f.height),
            Picture::Rgb8 { width, height, .. } | Picture::Rgba8 { width, height, .. } => {
                (*width, *height)
            }
        }
    }
}

/// Encodes `picture` as `format` into `w`, which need not seek (not for EXR: see
/// [`OutputFormat::needs_seek`]). `path` names the output in errors.
pub fn encode_stream(
    w: impl Write,
    path: &Path,
    format: OutputFormat,
    picture: &Picture,
) -> Result<(), Error> {
    let mut w = std::io::BufWriter::new(w);
    let (width, height) = picture.size();
    match (format, picture) {
        (OutputFormat::Png, Picture::Rgb8 { rgb, .. }) => {
            png(&mut w, path, width, height, rgb, false)?
        }
        (OutputFormat::Png, Picture::Rgba8 { rgba, .. }) => {
            png(&mut w, path, width, height, rgba, true)?
        }
        (OutputFormat::Png, Picture::Linear(frame, store)) => {
            png_bands(&mut w, path, frame, *store)?
        }
        (OutputFormat::Jpeg, Picture::Linear(frame, store)) => {
            image::codecs::jpeg::JpegEncoder::new_with_quality(&mut w, store.quality)
                .write_image(
                    &frame.to_srgb8(),
                    width,
                    height,
                    image::ExtendedColorType::Rgb8,
                )
                .map_err(|e| encode_error(path, e))?;
        }
        (OutputFormat::Jpeg, Picture::Rgb8 { rgb, .. }) => {
            image::codecs::jpeg::JpegEncoder::new_with_quality(&mut w, Store::SRGB.quality)
                .write_image(rgb, width, height, image::ExtendedColorType::Rgb8)
                .map_err(|e| encode_error(path, e))?;
        }
        (OutputFormat::Gif | OutputFormat::Apng, Picture::Linear(frame, store)) => {
            let mut anim = crate::animation::Animation::new(
                &mut w,
                path,
                format,
                *store,
                1,
                1,
                (width, height),
            )?;
            anim.push(frame)?;
            anim.finish()?;
        }
        (OutputFormat::Gif | OutputFormat::Apng, _) => {
            return Err(Error::parameter(format!(
                "{}: texmap writes {} from a render only (write .png)",
                path.display(),
                format.name()
            )))
        }
        (OutputFormat::Jpeg, Picture::Rgba8 { .. }) => {
            return Err(Error::parameter(format!(
                "{}: this image has alpha, which JPEG cannot hold (write .png)",
                path.display()
            )))
        }
        (OutputFormat::Hdr, Picture::Linear(frame, _)) => {
            let rgb: Vec<image::Rgb<f32>> = frame
                .color
                .iter()
                .map(|&c| image::Rgb(rgbe_input(c)))
                .collect();
            image::codecs::hdr::HdrEncoder::new(&mut w)
                .encode(&rgb, width as usize, height as usize)
                .map_err(|e| encode_error(path, e))?;
        }
        (OutputFormat::Exr, _) => {
            return Err(Error::Unsupported(format!(
                "{}: an OpenEXR file is written to a seekable file or memory",
                path.display()
            )))
        }
        (OutputFormat::Hdr, Picture::Rgb8 { .. } | Picture::Rgba8 { .. }) => {
            return Err(eight_bit_only(path, format))
        }
    }
    w.flush().map_err(|e| Error::io(path, e))
}

/// Encodes `picture` as `format` into a file or buffer that can seek (any format).
pub fn encode_seekable(
    w: impl Write + Seek,
    path: &Path,
    format: OutputFormat,
    picture: &Picture,
) -> Result<(), Error> {
    match (format, picture) {
        (OutputFormat::Exr, Picture::Linear(frame, _)) => {
            let mut w = std::io::BufWriter::new(w);
            exr_rgba(&mut w, path, frame)?;
            w.flush().map_err(|e| Error::io(path, e))
        }
        (OutputFormat::Exr, Picture::Rgb8 { .. } | Picture::Rgba8 { .. }) => {
            Err(eight_bit_only(path, format))
        }
        _ => encode_stream(w, path, format, picture),
    }
}

/// The refusal of an 8-bit picture in a float format.
fn eight_bit_only(path: &Path, format: OutputFormat) -> Error {
    Error::parameter(format!(
        "{}: this image is 8-bit colour, written as PNG only, not {}",
        path.display(),
        format.name()
    ))
}

fn png(
    w: impl Write,
    path: &Path,
    width: u32,
    height: u32,
    samples: &[u8],
    alpha: bool,
) -> Result<(), Error> {
    let color = if alpha {
        image::ExtendedColorType::Rgba8
    } else {
        image::ExtendedColorType::Rgb8
    };
    image::codecs::png::PngEncoder::new(w)
        .write_image(samples, width, height, color)
        .map_err(|e| encode_error(path, e))
}

/// The rows [`png_bands`] encodes at a time.
const PNG_BAND_ROWS: usize = 64;

/// `frame` as a PNG, its rows encoded to 8 or 16 bits a band of [`PNG_BAND_ROWS`] at a time
/// and streamed into the compressor: no whole 8/16-bit copy of the frame is held (6 MB for a
/// 1080p RGB8 image). The settings are `image`'s defaults (fast compression, adaptive
/// filter), so the pixels are those its encoder wrote.
fn png_bands(w: impl Write, path: &Path, frame: &Frame, store: Store) -> Result<(), Error> {
    let err = |e| png_error(path, e);
    let mut e = store.png_encoder(w, (frame.width, frame.height));
    e.set_compression(png::Compression::Fast);
    e.set_filter(png::Filter::Adaptive);
    let mut writer = e.write_header().map_err(err)?;
    let mut stream = writer.stream_writer().map_err(err)?;
    let band = PNG_BAND_ROWS * frame.width as usize;
    let bands: Vec<&[Vec4]> = frame.color.chunks(band.max(1)).collect();
    let mut next = bands.first().map(|b| store.png_pixels(b, true));
    for i in 0..bands.len() {
        let rows = next.take().unwrap_or_default();
        // The next band encoded by the pool while this thread compresses this one (the
        // compressor runs on one thread: the encoding no longer waits for it, nor it for
        // the encoding).
        let written = rayon::in_place_scope(|s| {
            if let Some(b) = bands.get(i + 1) {
                s.spawn(|_| next = Some(store.png_pixels(b, true)));
            }
            stream.write_all(&rows)
        });
        written.map_err(|e| Error::io(path, e))?;
    }
    stream.finish().map_err(err)?;
    writer.finish().map_err(err)
}

/// RGBE holds non-negative finite values below 2¹²⁸: NaN and negatives become 0 and larger
/// values the largest it holds (the encoder's exponent would overflow).
fn rgbe_input(c: Vec4) -> [f32; 3] {
    [c.x, c.y, c.z].map(|v| if v > 0.0 { v.min(1e38) } else { 0.0 })
}

/// One layer of float R, G, B, A (premultiplied), read from the frame pixel by pixel.
fn exr_rgba(w: impl Write + Seek, path: &Path, frame: &Frame) -> Result<(), Error> {
    use exr::compression::Compression;
    use exr::image::Blocks;
    use exr::meta::attribute::LineOrder;
    use exr::prelude::{
        Encoding, Image, Layer, LayerAttributes, SpecificChannels, Vec2, WritableImage,
    };
    let width = frame.width as usize;
    let pixels = SpecificChannels::rgba(|Vec2(x, y): Vec2<usize>| {
        let c = frame.color[y * width + x];
        (c.x, c.y, c.z, c.w)
    });
    let attributes = LayerAttributes {
        software_name: Some(exr::prelude::Text::from("texmap")),
        ..LayerAttributes::default()
    };
    let layer = Layer::new(
        (width, frame.height as usize),
        attributes,
        Encoding {
            compression: Compression::RLE,
            blocks: Blocks::ScanLines,
            line_order: LineOrder::Increasing,
        },
        pixels,
    );
    Image::from_layer(layer)
        .write()
        .to_buffered(w)
        .map_err(|e| match e {
            exr::error::Error::Io(e) => Error::io(path, e),
            e => Error::decode(path, e.to_string()),
        })
}

/// A `png` encoder's failure, naming the output.
pub(crate) fn png_error(path: &Path, e: png::EncodingError) -> Error {
    match e {
        png::EncodingError::IoError(e) => Error::io(path, e),
        e => Error::decode(path, e.to_string()),
    }
}

fn encode_error(path: &Path, e: image::ImageError) -> Error {
    match e {
        image::ImageError::IoError(e) => Error::io(path, e),
        e => Error::decode(path, e.to_string()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn format(name: &str, explicit: Option<OutputFormat>) -> Result<OutputFormat, String> {
        OutputFormat::for_output(Path::new(name), "-o", explicit).map_err(|e| e.to_string())
    }

    #[test]
    fn the_extension_chooses_case_insensitively() {
        assert_eq!(format("a.png", None), Ok(OutputFormat::Png));
        assert_eq!(format("a.EXR", None), Ok(OutputFormat::Exr));
        assert_eq!(format("dir.d/a.Hdr", None), Ok(OutputFormat::Hdr));
        assert_eq!(format("frame_{frame}.exr", None), Ok(OutputFormat::Exr));
    }

    #[test]
    fn stdout_and_names_without_an_extension_are_png_unless_told() {
        assert_eq!(format("-", None), Ok(OutputFormat::Png));
        assert_eq!(format("/dev/null", None), Ok(OutputFormat::Png));
        assert_eq!(format("-", Some(OutputFormat::Exr)), Ok(OutputFormat::Exr));
        assert_eq!(
            format("/dev/null", Some(OutputFormat::Hdr)),
            Ok(OutputFormat::Hdr)
        );
    }

    #[test]
    fn unknown_extensions_are_refused_and_format_must_agree_with_the_name() {
        let e = format("a.webp", None).unwrap_err();
        assert!(
            e.contains("a.webp") && e.contains(".webp") && e.contains(".exr"),
            "{e}"
        );
        assert_eq!(format("a.JPEG", None), Ok(OutputFormat::Jpeg));
        assert_eq!(format("a.jpg", None), Ok(OutputFormat::Jpeg));
        assert_eq!(format("t.gif", None), Ok(OutputFormat::Gif));
        assert_eq!(format("t.apng", None), Ok(OutputFormat::Apng));
        assert!(format("a.TIFF", None).unwrap_err().contains(".tiff"));
        assert_eq!(
            format("a.out", Some(OutputFormat::Exr)),
            Ok(OutputFormat::Exr)
        );
        let e = format("a.exr", Some(OutputFormat::Png)).unwrap_err();
        assert!(
            e.contains("OpenEXR") && e.contains("--format is png"),
            "{e}"
        );
    }

    #[test]
    fn png_bands_hold_the_frame_in_every_store() {
        // More rows than a band, and a last band cut short; some pixels half covered.
        let (w, h) = (7u32, (2 * PNG_BAND_ROWS + 5) as u32);
        let color = (0..w * h)
            .map(|i| {
                let t = (i % 97) as f32 / 96.0;
                let a = if i % 3 == 0 { 0.5 } else { 1.0 };
                Vec4::new(t, 1.0 - t, t * t, 1.0) * a
            })
            .collect();
        let frame = Frame {
            width: w,
            height: h,
            color,
            ..Frame::default()
        };
        for (alpha, sixteen) in [(false, false), (true, false), (false, true), (true, true)] {
            let store = Store {
                alpha,
                sixteen,
                ..Store::SRGB
            };
            let mut file = Vec::new();
            png_bands(&mut file, Path::new("t.png"), &frame, store).unwrap();
            let img = image::load_from_memory(&file).unwrap();
            assert_eq!((img.width(), img.height()), (w, h));
            let want = store.png_rows(&frame, false);
            let got: Vec<u8> = match (sixteen, alpha) {
                (false, false) => img.to_rgb8().into_raw(),
                (false, true) => img.to_rgba8().into_raw(),
                (true, false) => img
                    .to_rgb16()
                    .into_raw()
                    .iter()
                    .flat_map(|v| v.to_ne_bytes())
                    .collect(),
                (true, true) => img
                    .to_rgba16()
                    .into_raw()
                    .iter()
                    .flat_map(|v| v.to_ne_bytes())
                    .collect(),
            };
            assert!(got == want, "alpha {alpha}, 16-bit {sixteen}");
        }
    }

    #[test]
    fn rgbe_input_is_finite_and_non_negative() {
        let c = rgbe_input(Vec4::new(f32::NAN, -1.0, f32::INFINITY, 1.0));
        assert_eq!(c, [0.0, 0.0, 1e38]);
    }
}
