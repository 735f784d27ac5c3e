//! A texture file made into the engine's textures: a [`Texture2D`] (one image with its mip
//! chain) or a [`TextureCube`] (six faces).
//!
//! 8-bit formats are held as [`Format::Rgba8`] in the colour space the file names (its
//! `_SRGB` formats) or else the caller's, so they take the usual 8-bit path (sRGB decoded
//! exactly as a PNG's texels are). Float formats are linear: the ones whose values are all
//! halves (RGBA16F, R11G11B10F, RGB9E5, BC6H) as [`Format::Rgba16F`], exactly, the rest
//! (RGBA32F, the signed BC4 and BC5) as [`Format::Rgba32F`]. The file's own mip chain is used
//! when it is complete; otherwise the chain is built from level 0, as for any image. With
//! [`Storage::Compressed`] a block-compressed file's levels stay its blocks
//! ([`Texture2D::from_blocks`]).

use super::{FileFormat, PlainFormat, TextureFile};
use crate::texture::compressed::BlockFormat;
use crate::texture::{
    f32_to_f16, ColorSpace, Format, Storage, Texture2D, TextureCube, TextureOptions,
};
use crate::{Error, Result};

/// The engine format `file`'s texels are held in.
fn engine_format(format: FileFormat) -> Format {
    match format {
        FileFormat::Plain(PlainFormat::Rgba16F | PlainFormat::R11G11B10F | PlainFormat::Rgb9E5)
        | FileFormat::Block(BlockFormat::Bc6hUnsigned | BlockFormat::Bc6hSigned) => Format::Rgba16F,
        f if f.is_float() || f.is_signed() => Format::Rgba32F,
        _ => Format::Rgba8,
    }
}

/// One image's texels as bytes of [`engine_format`], alpha 1 when `opaque`.
fn engine_texels(
    file: &TextureFile,
    (layer, face, level): (u32, u32, u32),
    opaque: bool,
) -> Result<Vec<u8>> {
    let floats = |file: &TextureFile| -> Result<Vec<f32>> {
        let mut f = file.decode_f32(layer, face, level)?;
        if opaque {
            f.chunks_exact_mut(4).for_each(|t| t[3] = 1.0);
        }
        Ok(f)
    };
    Ok(match engine_format(file.format()) {
        Format::Rgba8 => {
            let mut b = file.decode_rgba8(layer, face, level)?;
            if opaque {
                b.chunks_exact_mut(4).for_each(|t| t[3] = 255);
            }
            b
        }
        Format::Rgba16F => floats(file)?
            .into_iter()
            .flat_map(|v| f32_to_f16(v).to_le_bytes())
            .collect(),
        _ => floats(file)?
            .into_iter()
            .flat_map(f32::to_le_bytes)
            .collect(),
    })
}

/// `layer`'s `face` of `file` as a texture with its mip chain.
fn image_texture(
    file: &TextureFile,
    (layer, face): (u32, u32),
    color_space: ColorSpace,
    options: TextureOptions,
    opaque: bool,
) -> Result<Texture2D> {
    let color_space = if file.color_space() == ColorSpace::Srgb {
        ColorSpace::Srgb
    } else {
        color_space
    };
    let stored = if options.mipmaps && file.has_full_chain() {
        file.levels()
    } else {
        1
    };
    if let (Storage::Compressed, FileFormat::Block(format)) = (options.storage, file.format()) {
        // Kept as the file's blocks, decoded when read.
        let levels = (0..stored)
            .map(|level| file.data(layer, face, level))
            .collect::<Result<Vec<_>>>()?;
        return Texture2D::from_blocks(
            file.width(),
            file.height(),
            format,
            color_space,
            &levels,
            options,
            opaque,
        )
        .map_err(|e| Error::decode(file.path(), e.to_string()));
    }
    let levels = (0..stored)
        .map(|level| engine_texels(file, (layer, face, level), opaque))
        .collect::<Result<Vec<_>>>()?;
    let slices: Vec<&[u8]> = levels.iter().map(Vec::as_slice).collect();
    Texture2D::from_texel_levels(
        file.width(),
        file.height(),
        engine_format(file.format()),
        color_space,
        &slices,
        options,
    )
    .map_err(|e| Error::decode(file.path(), e.to_string()))
}

/// What a file is when it is not one flat 2D image, for messages ("a cube map", …).
fn shape_name(file: &TextureFile) -> Option<String> {
    if file.depth() > 1 {
        Some(format!("a volume texture ({} slices)", file.depth()))
    } else if file.faces() == 6 && file.layers() > 1 {
        Some(format!("a cube map array ({} cubes)", file.layers()))
    } else if file.faces() == 6 {
        Some("a cube map".to_string())
    } else if file.layers() > 1 {
        Some(format!("a texture array ({} layers)", file.layers()))
    } else {
        None
    }
}

/// The 2D texture a file holds: 8-bit texels in `color_space` unless the format is sRGB, the
/// file's mip chain when complete (else one is built as `options` say).
///
/// # Errors
/// One line naming the file: a cube map, array or volume texture (a 2D texture is needed),
/// or an image that fails to decode.
pub fn texture_from_file(
    file: &TextureFile,
    color_space: ColorSpace,
    options: TextureOptions,
) -> Result<Texture2D> {
    texture_from_file_with(file, color_space, options, false)
}

/// [`texture_from_file`], with every texel's alpha made 1 when `drop_alpha` (glTF's OPAQUE
/// base colour).
pub(crate) fn texture_from_file_with(
    file: &TextureFile,
    color_space: ColorSpace,
    options: TextureOptions,
    drop_alpha: bool,
) -> Result<Texture2D> {
    if let Some(shape) = shape_name(file) {
        return Err(Error::decode(
            file.path(),
            format!("is {shape}; a 2D texture is needed here"),
        ));
    }
    image_texture(file, (0, 0), color_space, options, drop_alpha)
}

/// Level 0 of a flat 2D file as an image: RGBA8 for 8-bit formats (values as stored), RGBA
/// `f32` for float and signed ones.
///
/// # Errors
/// One line naming the file: a cube map, array or volume texture, or an image that fails to
/// decode.
pub fn flat_image(file: &TextureFile) -> Result<image::DynamicImage> {
    if let Some(shape) = shape_name(file) {
        return Err(Error::decode(
            file.path(),
            format!("is {shape}; one flat image is needed here"),
        ));
    }
    let (w, h) = (file.width(), file.height());
    let lost = || Error::decode(file.path(), "decoded level 0 has the wrong size");
    if engine_format(file.format()) == Format::Rgba8 {
        let texels = file.decode_rgba8(0, 0, 0)?;
        image::RgbaImage::from_raw(w, h, texels)
            .map(image::DynamicImage::ImageRgba8)
            .ok_or_else(lost)
    } else {
        let texels = file.decode_f32(0, 0, 0)?;
        image::Rgba32FImage::from_raw(w, h, texels)
            .map(image::DynamicImage::ImageRgba32F)
            .ok_or_else(lost)
    }
}

/// The cube map a file holds, faces in the file's (and [`crate::texture::CubeFace::ALL`]'s)
/// order, each with its mip chain as in [`texture_from_file`].
///
/// # Errors
/// One line naming the file: not a cube map, a cube map array, or a face that fails to decode.
pub fn cube_from_file(
    file: &TextureFile,
    color_space: ColorSpace,
    options: TextureOptions,
) -> Result<TextureCube> {
    if file.faces() != 6 || file.layers() != 1 {
        let shape = shape_name(file).unwrap_or_else(|| "a 2D texture".to_string());
        return Err(Error::decode(
            file.path(),
            format!("is {shape}; a cube map (6 faces, 1 layer) is needed here"),
        ));
    }
    let faces = (0..6)
        .map(|face| image_texture(file, (0, face), color_space, options, false))
        .collect::<Result<Vec<_>>>()?;
    let faces: [Texture2D; 6] = faces
        .try_into()
        .map_err(|_| Error::decode(file.path(), "cube map lost a face"))?;
    TextureCube::new(faces).map_err(|e| Error::decode(file.path(), e.to_string()))
}
