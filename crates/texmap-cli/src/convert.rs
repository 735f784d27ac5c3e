//! `texmap convert IN OUT [--level N] [--face F] [--slice Z]`: one image of a texture file
//! written as PNG or OpenEXR.
//!
//! What the output holds: a PNG holds sRGB-encoded 8-bit RGBA, an EXR linear `f32` RGBA, so
//! both show the same picture. 8-bit sources (PNG, JPEG, TGA, BMP; DDS, KTX and KTX2 8-bit
//! and BC1–BC5, BC7 formats) are taken as they decode: a PNG gets exactly the decoded bytes
//! (no sRGB conversion, alpha kept, so a BC file's PNG can be compared byte for byte with
//! another decoder's), an EXR their sRGB decoding. Float sources (HDR, EXR, BC6H, the half,
//! float and packed float formats) go to an EXR as they are and to a PNG sRGB-encoded,
//! clamped to [0, 1]. 16-bit PNGs are rounded to 8 bits for a PNG.

use std::path::{Path, PathBuf};

use clap::Args;
use texmap::color::{linear_to_srgb8, linear_to_unorm8, srgb_to_linear};
use texmap::texture::container::{read_texture_file, Container, TextureFile};
use texmap::texture::load::{decode_image, Limits};
use texmap::Error;

use glam::Vec4;
use texmap::frame::Frame;

use crate::formats::{OutputFormat, Picture, Store};

#[derive(Args)]
pub struct ConvertArgs {
    /// The texture: PNG, JPEG, TGA, BMP, HDR, EXR, DDS, KTX or KTX2.
    input: PathBuf,
    /// The image to write: .png (8-bit RGBA) or .exr (float RGBA); `-` writes a PNG to stdout.
    output: PathBuf,
    /// The mip level (0, the default, is the full size).
    #[arg(long, default_value_t = 0)]
    level: u32,
    /// The cube map face: 0 to 5, or +x, -x, +y, -y, +z, -z (default 0).
    #[arg(long, allow_hyphen_values = true)]
    face: Option<String>,
    /// The array layer, or the depth slice of a volume texture at the level (default 0).
    #[arg(long, default_value_t = 0)]
    slice: u32,
}

/// The face names `--face` accepts, in face order.
const FACE_NAMES: [&str; 6] = ["+x", "-x", "+y", "-y", "+z", "-z"];

fn parse_face(s: &str) -> Result<u32, Error> {
    let lower = s.to_ascii_lowercase();
    if let Some(i) = FACE_NAMES.iter().position(|&n| n == lower) {
        return Ok(i as u32);
    }
    s.parse::<u32>().map_err(|_| {
        Error::parameter(format!(
            "--face {s}: give 0 to 5 or one of {}",
            FACE_NAMES.join(", ")
        ))
    })
}

/// How the output is encoded, from its name.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Kind {
    Png,
    Exr,
}

fn output_kind(path: &Path) -> Result<Kind, Error> {
    if path.as_os_str() == "-" {
        return Ok(Kind::Png);
    }
    match path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .as_deref()
    {
        Some("png") => Ok(Kind::Png),
        Some("exr") => Ok(Kind::Exr),
        _ => Err(Error::parameter(format!(
            "{}: the output is a .png (8-bit RGBA) or an .exr (float RGBA)",
            path.display()
        ))),
    }
}

/// One image's texels: 8-bit RGBA as decoded, or linear `f32` RGBA.
enum Texels {
    Rgba8(Vec<u8>),
    Rgba32F(Vec<f32>),
}

/// Refuses an index past `count`, naming the valid range; `what` is (one, many).
fn in_range(
    input: &Path,
    flag: &str,
    given: u32,
    count: u32,
    what: (&str, &str),
) -> Result<(), Error> {
    if given < count {
        return Ok(());
    }
    Err(Error::parameter(format!(
        "--{flag} {given} is out of range: {} has {count} {} (0 to {})",
        input.display(),
        if count == 1 { what.0 } else { what.1 },
        count - 1
    )))
}

const LEVELS: (&str, &str) = ("mip level", "mip levels");
const FACES: (&str, &str) = ("face", "faces");
const LAYERS: (&str, &str) = ("layer", "layers");

/// The chosen image of a container file.
fn container_texels(
    file: &TextureFile,
    args: &ConvertArgs,
    face: u32,
) -> Result<(u32, u32, Texels), Error> {
    let input = &args.input;
    in_range(input, "level", args.level, file.levels(), LEVELS)?;
    in_range(input, "face", face, file.faces(), FACES)?;
    let (w, h, d) = file.level_size(args.level);
    let slices = file.layers() * d;
    let what = if d > 1 {
        ("depth slice at this level", "depth slices at this level")
    } else {
        LAYERS
    };
    in_range(input, "slice", args.slice, slices, what)?;
    let (layer, z) = (args.slice / d, (args.slice % d) as usize);
    let n = w as usize * h as usize * 4;
    let texels = if file.format().is_float() {
        let all = file.decode_f32(layer, face, args.level)?;
        Texels::Rgba32F(all[z * n..(z + 1) * n].to_vec())
    } else {
        let all = file.decode_rgba8(layer, face, args.level)?;
        Texels::Rgba8(all[z * n..(z + 1) * n].to_vec())
    };
    Ok((w, h, texels))
}

/// An image file's only image.
fn image_texels(args: &ConvertArgs, face: u32) -> Result<(u32, u32, Texels), Error> {
    let input = &args.input;
    let img = decode_image(input, &Limits::default())?;
    in_range(input, "level", args.level, 1, LEVELS)?;
    in_range(input, "face", face, 1, FACES)?;
    in_range(input, "slice", args.slice, 1, LAYERS)?;
    let (w, h) = (img.width(), img.height());
    let float = matches!(
        img,
        image::DynamicImage::ImageRgb32F(_) | image::DynamicImage::ImageRgba32F(_)
    );
    let texels = if float {
        Texels::Rgba32F(img.to_rgba32f().into_raw())
    } else {
        Texels::Rgba8(img.to_rgba8().into_raw())
    };
    Ok((w, h, texels))
}

pub fn run(args: ConvertArgs) -> Result<(), Error> {
    let kind = output_kind(&args.output)?;
    let face = args.face.as_deref().map_or(Ok(0), parse_face)?;
    if crate::output::is_an_input(&args.output, &[&args.input]) {
        return Err(Error::parameter(format!(
            "{}: the output would overwrite the input",
            args.output.display()
        )));
    }
    let (w, h, texels) = if Container::of_file(&args.input).is_some() {
        let file = read_texture_file(&args.input, &Limits::default())?;
        container_texels(&file, &args, face)?
    } else {
        image_texels(&args, face)?
    };
    let out = &args.output;
    match (kind, texels) {
        (Kind::Png, Texels::Rgba8(rgba)) => write_rgba8(out, w, h, &rgba),
        (Kind::Png, Texels::Rgba32F(f)) => {
            let b: Vec<u8> = f
                .chunks_exact(4)
                .flat_map(|t| {
                    [
                        linear_to_srgb8(t[0]),
                        linear_to_srgb8(t[1]),
                        linear_to_srgb8(t[2]),
                        linear_to_unorm8(t[3]),
                    ]
                })
                .collect();
            write_rgba8(out, w, h, &b)
        }
        (Kind::Exr, Texels::Rgba8(b)) => {
            let color = b
                .chunks_exact(4)
                .map(|t| {
                    let c = |v: u8| srgb_to_linear(f32::from(v) / 255.0);
                    Vec4::new(c(t[0]), c(t[1]), c(t[2]), f32::from(t[3]) / 255.0)
                })
                .collect();
            write_exr(out, w, h, color)
        }
        (Kind::Exr, Texels::Rgba32F(f)) => {
            let color = f.chunks_exact(4).map(Vec4::from_slice).collect();
            write_exr(out, w, h, color)
        }
    }
}

/// The decoded bytes as an RGBA PNG.
fn write_rgba8(path: &Path, width: u32, height: u32, rgba: &[u8]) -> Result<(), Error> {
    let picture = Picture::Rgba8 {
        width,
        height,
        rgba,
    };
    crate::output::write_image(path, OutputFormat::Png, &picture)
}

/// Linear RGBA texels as an OpenEXR file (the values as they are: a texture's alpha is not
/// multiplied in).
fn write_exr(path: &Path, width: u32, height: u32, color: Vec<Vec4>) -> Result<(), Error> {
    let frame = Frame {
        width,
        height,
        color: color.into(),
        ..Frame::default()
    };
    crate::output::write_image(
        path,
        OutputFormat::Exr,
        &Picture::Linear(&frame, Store::SRGB),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn faces_parse_by_number_and_by_name() {
        assert_eq!(parse_face("3").unwrap(), 3);
        assert_eq!(parse_face("-Y").unwrap(), 3);
        assert_eq!(parse_face("+z").unwrap(), 4);
        let e = parse_face("up").unwrap_err().to_string();
        assert!(e.contains("0 to 5") && e.contains("+x, -x"), "{e}");
    }
}
