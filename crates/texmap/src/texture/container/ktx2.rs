//! KTX2, through the `ktx2` crate (the header and level index entries), with zstd
//! supercompression undone by the pure-Rust `ruzstd` decoder and zlib by `flate2`.
//!
//! Every level index entry is checked against the file here, so a level past the end is
//! named. The data format descriptor is read by hand, for its colour model alone (telling
//! UASTC): the crate's `Reader::new` parses every descriptor block and panics on a texel
//! block dimension byte of 255 (`NonZeroU8::new(dim + 1).unwrap()`, ktx2 0.5.0), which a
//! file can hold. The key/value data is not read. Inside a level: layers, each with its faces,
//! each with its depth slices, rows packed. Supercompressed levels are inflated at most to the
//! size the header's shape gives them (checked against the index's `uncompressedByteLength`
//! and the limits first). Basis Universal (ETC1S through BasisLZ, UASTC) is transcoded to
//! RGBA8 when read (`basis.rs`).

use std::io::Read as _;
use std::ops::Range;
use std::path::Path;

use ktx2::{Format as Vk, SupercompressionScheme};

use super::{Container, Desc, FileFormat, PlainFormat, TextureFile};
use crate::texture::compressed::BlockFormat;
use crate::texture::load::Limits;
use crate::texture::ColorSpace;
use crate::{Error, Result};

const HEADER: usize = 80;
const LEVEL_ENTRY: usize = 24;

/// The format and colour space and "no alpha" of a `VkFormat`.
fn vk_format(f: Vk) -> Option<(FileFormat, ColorSpace, bool)> {
    use BlockFormat as B;
    use ColorSpace::{Linear as L, Srgb as S};
    use FileFormat::{Block, Plain};
    use PlainFormat as P;
    Some(match f {
        Vk::R8_UNORM => (Plain(P::R8), L, false),
        Vk::R8_SRGB => (Plain(P::R8), S, false),
        Vk::R8G8_UNORM => (Plain(P::Rg8), L, false),
        Vk::R8G8_SRGB => (Plain(P::Rg8), S, false),
        Vk::R8G8B8A8_UNORM => (Plain(P::Rgba8), L, false),
        Vk::R8G8B8A8_SRGB => (Plain(P::Rgba8), S, false),
        Vk::B8G8R8A8_UNORM => (Plain(P::Bgra8), L, false),
        Vk::B8G8R8A8_SRGB => (Plain(P::Bgra8), S, false),
        Vk::R16G16B16A16_SFLOAT => (Plain(P::Rgba16F), L, false),
        Vk::R32G32B32A32_SFLOAT => (Plain(P::Rgba32F), L, false),
        Vk::B10G11R11_UFLOAT_PACK32 => (Plain(P::R11G11B10F), L, false),
        Vk::E5B9G9R9_UFLOAT_PACK32 => (Plain(P::Rgb9E5), L, false),
        Vk::BC1_RGB_UNORM_BLOCK => (Block(B::Bc1), L, true),
        Vk::BC1_RGB_SRGB_BLOCK => (Block(B::Bc1), S, true),
        Vk::BC1_RGBA_UNORM_BLOCK => (Block(B::Bc1), L, false),
        Vk::BC1_RGBA_SRGB_BLOCK => (Block(B::Bc1), S, false),
        Vk::BC2_UNORM_BLOCK => (Block(B::Bc2), L, false),
        Vk::BC2_SRGB_BLOCK => (Block(B::Bc2), S, false),
        Vk::BC3_UNORM_BLOCK => (Block(B::Bc3), L, false),
        Vk::BC3_SRGB_BLOCK => (Block(B::Bc3), S, false),
        Vk::BC4_UNORM_BLOCK => (Block(B::Bc4), L, false),
        Vk::BC4_SNORM_BLOCK => (Block(B::Bc4Signed), L, false),
        Vk::BC5_UNORM_BLOCK => (Block(B::Bc5), L, false),
        Vk::BC5_SNORM_BLOCK => (Block(B::Bc5Signed), L, false),
        Vk::BC6H_UFLOAT_BLOCK => (Block(B::Bc6hUnsigned), L, false),
        Vk::BC6H_SFLOAT_BLOCK => (Block(B::Bc6hSigned), L, false),
        Vk::BC7_UNORM_BLOCK => (Block(B::Bc7), L, false),
        Vk::BC7_SRGB_BLOCK => (Block(B::Bc7), S, false),
        _ => return None,
    })
}

/// The data format descriptor's colour model of UASTC.
const UASTC: u8 = 166;

/// The colour model of the first descriptor block, when it is a basic block inside the file:
/// the byte after the descriptor's length (4 bytes) and the block header (8 bytes).
fn dfd_color_model(bytes: &[u8], index: &ktx2::Index) -> Option<u8> {
    dfd_byte(bytes, index, 12)
}

/// Byte `at` of the descriptor (12: colour model, 14: transfer function — 2 is sRGB) when
/// its first block is a basic block inside the file.
fn dfd_byte(bytes: &[u8], index: &ktx2::Index, at: usize) -> Option<u8> {
    let start = index.dfd_byte_offset as usize;
    let end = start.checked_add(index.dfd_byte_length as usize)?;
    let dfd = bytes.get(start..end.min(bytes.len()))?;
    let block_header = super::le32(dfd.get(..8)?, 4);
    // Vendor 0 (Khronos), descriptor type 0 (basic).
    (block_header == 0).then_some(())?;
    dfd.get(at).copied()
}

/// Parses a KTX2 file (`bytes` start with its magic).
pub(super) fn parse(bytes: Vec<u8>, path: &Path, limits: &Limits) -> Result<TextureFile> {
    let len = bytes.len() as u64;
    if bytes.len() < HEADER {
        return Err(Error::decode(
            path,
            format!("KTX2 file is truncated: {len} bytes, the header alone is {HEADER}"),
        ));
    }
    let header_bytes: &[u8; HEADER] = bytes[..HEADER].try_into().expect("80 bytes");
    let header = ktx2::Header::from_bytes(header_bytes)
        .map_err(|e| Error::decode(path, format!("KTX2 header is invalid: {e}")))?;

    // The level index, entry by entry, before the crate reads it.
    let levels = header.level_count.max(1);
    let index_end = HEADER as u64 + u64::from(levels) * LEVEL_ENTRY as u64;
    if index_end > len {
        return Err(Error::decode(
            path,
            format!(
                "KTX2 level index of {levels} levels ends at byte {index_end}, past the end of \
                 the file ({len} bytes)"
            ),
        ));
    }
    let mut index = Vec::with_capacity(levels as usize);
    for level in 0..levels as usize {
        let at = HEADER + level * LEVEL_ENTRY;
        let entry: &[u8; LEVEL_ENTRY] = bytes[at..at + LEVEL_ENTRY].try_into().expect("24");
        let ktx2::LevelIndex {
            byte_offset: offset,
            byte_length: length,
            uncompressed_byte_length: uncompressed,
        } = ktx2::LevelIndex::from_bytes(entry);
        if offset.checked_add(length).is_none_or(|end| end > len) {
            return Err(Error::decode(
                path,
                format!(
                    "KTX2 level {level}'s data (offset {offset}, {length} bytes) runs past the \
                     end of the file ({len} bytes)"
                ),
            ));
        }
        index.push((offset as usize..(offset + length) as usize, uncompressed));
    }
    let scheme = header.supercompression_scheme;
    let Some(vk) = header.format else {
        let kind = if scheme == Some(SupercompressionScheme::BasisLZ) {
            "ETC1S"
        } else if dfd_color_model(&bytes, &header.index) == Some(UASTC) {
            "UASTC"
        } else {
            return Err(Error::decode(
                path,
                "KTX2 format is VK_FORMAT_UNDEFINED without Basis Universal data; texmap \
                 cannot tell its texels",
            ));
        };
        let color_space = match dfd_byte(&bytes, &header.index, 14) {
            Some(2) => ColorSpace::Srgb,
            _ => ColorSpace::Linear,
        };
        return super::basis::transcode(&bytes, path, limits, &header, color_space, kind);
    };
    let Some((format, color_space, opaque)) = vk_format(vk) else {
        return Err(Error::decode(
            path,
            format!(
                "KTX2 VkFormat {} ({vk:?}) is not one texmap reads (BC1–BC7, BC6H, R8, RG8, \
                 RGBA8, BGRA8, RGBA16F, RGBA32F, B10G11R11, E5B9G9R9)",
                vk.value()
            ),
        ));
    };
    let desc = Desc {
        container: Container::Ktx2,
        format,
        color_space,
        opaque,
        width: header.pixel_width,
        height: header.pixel_height.max(1),
        depth: header.pixel_depth.max(1),
        levels,
        faces: header.face_count,
        layers: header.layer_count.max(1),
    };
    // Stored levels must fit in the file; inflated ones in the memory budget.
    let available = if scheme.is_none() {
        len
    } else {
        limits.max_bytes
    };
    desc.check(path, limits, available)?;

    let per_level = |level: u32| desc.level_bytes(level).unwrap_or(u64::MAX);
    let file_bytes = len;
    let Some(scheme) = scheme else {
        for (level, (range, _)) in index.iter().enumerate() {
            if range.len() as u64 != per_level(level as u32) {
                return Err(level_size_error(
                    path,
                    &desc,
                    level as u32,
                    range.len() as u64,
                ));
            }
        }
        let starts: Vec<usize> = index.iter().map(|(r, _)| r.start).collect();
        let images = images_in_levels(&desc, &starts);
        return Ok(TextureFile::new(path, desc, file_bytes, bytes, images));
    };
    let name = match scheme {
        SupercompressionScheme::Zstandard => "zstd",
        SupercompressionScheme::ZLIB => "zlib",
        other => {
            return Err(Error::decode(
                path,
                format!("KTX2 supercompression scheme {other:?} is not supported"),
            ))
        }
    };
    let mut data = Vec::new();
    let mut starts = Vec::with_capacity(levels as usize);
    for (level, (range, uncompressed)) in index.iter().enumerate() {
        let want = per_level(level as u32);
        if *uncompressed != want {
            return Err(level_size_error(path, &desc, level as u32, *uncompressed));
        }
        starts.push(data.len());
        let before = data.len();
        let packed = &bytes[range.clone()];
        let inflated = if scheme == SupercompressionScheme::Zstandard {
            // A frame's window never needs to exceed twice its content.
            let window = (2 * want).max(1 << 20);
            ruzstd::decoding::StreamingDecoder::new_with_max_window_size(packed, window)
                .map_err(|e| e.to_string())
                .and_then(|d| {
                    d.take(want + 1)
                        .read_to_end(&mut data)
                        .map_err(|e| e.to_string())
                })
        } else {
            flate2::read::ZlibDecoder::new(packed)
                .take(want + 1)
                .read_to_end(&mut data)
                .map_err(|e| e.to_string())
        };
        if let Err(e) = inflated {
            return Err(Error::decode(
                path,
                format!("KTX2 level {level}'s {name} data is corrupt: {e}"),
            ));
        }
        let got = (data.len() - before) as u64;
        if got != want {
            return Err(Error::decode(
                path,
                format!(
                    "KTX2 level {level}'s {name} data inflates to {}{got} bytes; the level \
                     needs {want}",
                    if got > want { "more than " } else { "" }
                ),
            ));
        }
    }
    let images = images_in_levels(&desc, &starts);
    Ok(TextureFile::new(path, desc, file_bytes, data, images))
}

/// A level whose stored size disagrees with the header's shape.
fn level_size_error(path: &Path, desc: &Desc, level: u32, got: u64) -> Error {
    let (w, h, d) = desc.level_size(level);
    Error::decode(
        path,
        format!(
            "KTX2 level {level} holds {got} bytes; {} layer(s) x {} face(s) of {w}x{h}x{d} {} \
             need {}",
            desc.layers,
            desc.faces,
            desc.format.name(),
            desc.level_bytes(level).unwrap_or(0)
        ),
    )
}

/// The images of levels starting at `starts` (layer by layer, face by face inside each),
/// in `(layer, face, level)` order.
fn images_in_levels(desc: &Desc, starts: &[usize]) -> Vec<Range<usize>> {
    let count = desc.layers * desc.faces;
    let mut images = Vec::with_capacity((count * desc.levels) as usize);
    for i in 0..count as usize {
        for (level, &start) in starts.iter().enumerate() {
            let n = desc.image_bytes(level as u32) as usize;
            images.push(start + i * n..start + (i + 1) * n);
        }
    }
    images
}
