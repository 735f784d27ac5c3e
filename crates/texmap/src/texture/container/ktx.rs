//! KTX 1, parsed by hand: a 64-byte header (its endianness told by a marker), key/value
//! data, then for each mip level an `imageSize` and the level's images.
//!
//! Inside a level: array elements, each with its faces, each with its depth slices, each
//! with its rows; uncompressed rows are padded to 4 bytes (OpenGL's unpack alignment) and a
//! non-array cube map pads each face to 4 bytes, then each level is padded to 4 bytes.
//! `imageSize` is one face's bytes for a non-array cube map, the whole level's otherwise.
//! The format is told by `glInternalFormat` (some writers, open3d's skybox among them, put
//! the internal format in `glType` too); `glFormat` tells RGBA from BGRA.
//!
//! A big-endian file has its header, `imageSize`s and multi-byte texel units swapped; those
//! and row-padded formats are copied into a packed buffer, every other file is read in place.

use std::ops::Range;
use std::path::Path;

use super::{Container, Desc, FileFormat, PlainFormat, TextureFile};
use crate::texture::compressed::BlockFormat;
use crate::texture::load::Limits;
use crate::texture::ColorSpace;
use crate::{Error, Result};

const HEADER: usize = 64;
const ENDIAN_LITTLE: u32 = 0x0403_0201;
const ENDIAN_BIG: u32 = 0x0102_0304;
const GL_BGRA: u32 = 0x80e1;

/// The format, colour space and "no alpha" of a GL internal format.
fn gl_format(internal: u32, gl_format: u32) -> Option<(FileFormat, ColorSpace, bool)> {
    use BlockFormat as B;
    use ColorSpace::{Linear as L, Srgb as S};
    use FileFormat::{Block, Plain};
    use PlainFormat as P;
    let bgra = gl_format == GL_BGRA;
    Some(match internal {
        0x8229 => (Plain(P::R8), L, false),  // GL_R8
        0x822b => (Plain(P::Rg8), L, false), // GL_RG8
        0x8058 if bgra => (Plain(P::Bgra8), L, false),
        0x8058 => (Plain(P::Rgba8), L, false), // GL_RGBA8
        0x8c43 if bgra => (Plain(P::Bgra8), S, false),
        0x8c43 => (Plain(P::Rgba8), S, false), // GL_SRGB8_ALPHA8
        0x881a => (Plain(P::Rgba16F), L, false), // GL_RGBA16F
        0x8814 => (Plain(P::Rgba32F), L, false), // GL_RGBA32F
        0x8c3a => (Plain(P::R11G11B10F), L, false), // GL_R11F_G11F_B10F
        0x8c3d => (Plain(P::Rgb9E5), L, false), // GL_RGB9_E5
        0x83f0 => (Block(B::Bc1), L, true),    // GL_COMPRESSED_RGB_S3TC_DXT1_EXT
        0x83f1 => (Block(B::Bc1), L, false),   // …_RGBA_S3TC_DXT1_EXT
        0x83f2 => (Block(B::Bc2), L, false),   // …_RGBA_S3TC_DXT3_EXT
        0x83f3 => (Block(B::Bc3), L, false),   // …_RGBA_S3TC_DXT5_EXT
        0x8c4c => (Block(B::Bc1), S, true),    // GL_COMPRESSED_SRGB_S3TC_DXT1_EXT
        0x8c4d => (Block(B::Bc1), S, false),   // …_SRGB_ALPHA_S3TC_DXT1_EXT
        0x8c4e => (Block(B::Bc2), S, false),   // …_SRGB_ALPHA_S3TC_DXT3_EXT
        0x8c4f => (Block(B::Bc3), S, false),   // …_SRGB_ALPHA_S3TC_DXT5_EXT
        0x8dbb => (Block(B::Bc4), L, false),   // GL_COMPRESSED_RED_RGTC1
        0x8dbc => (Block(B::Bc4Signed), L, false), // …_SIGNED_RED_RGTC1
        0x8dbd => (Block(B::Bc5), L, false),   // GL_COMPRESSED_RG_RGTC2
        0x8dbe => (Block(B::Bc5Signed), L, false), // …_SIGNED_RG_RGTC2
        0x8e8c => (Block(B::Bc7), L, false),   // GL_COMPRESSED_RGBA_BPTC_UNORM
        0x8e8d => (Block(B::Bc7), S, false),   // …_SRGB_ALPHA_BPTC_UNORM
        0x8e8e => (Block(B::Bc6hSigned), L, false), // …_RGB_BPTC_SIGNED_FLOAT
        0x8e8f => (Block(B::Bc6hUnsigned), L, false), // …_RGB_BPTC_UNSIGNED_FLOAT
        _ => return None,
    })
}

/// `n` rounded up to a multiple of 4.
fn pad4(n: u64) -> u64 {
    n.div_ceil(4) * 4
}

/// Parses a KTX 1 file (`bytes` start with its magic).
pub(super) fn parse(bytes: Vec<u8>, path: &Path, limits: &Limits) -> Result<TextureFile> {
    let truncated = |what: &str| Error::decode(path, format!("KTX file is truncated: {what}"));
    if bytes.len() < HEADER {
        return Err(truncated(&format!(
            "{} bytes, the header alone is {HEADER}",
            bytes.len()
        )));
    }
    let big = match super::le32(&bytes, 12) {
        ENDIAN_LITTLE => false,
        ENDIAN_BIG => true,
        other => {
            return Err(Error::decode(
                path,
                format!("KTX endianness marker is {other:#010x}, neither 0x04030201 nor its swap"),
            ))
        }
    };
    let word = |at: usize| {
        let v = super::le32(&bytes, at);
        if big {
            v.swap_bytes()
        } else {
            v
        }
    };
    let h = |i: usize| word(16 + 4 * i);
    let (gl_fmt, internal) = (h(2), h(3));
    let (width, height, depth) = (h(5), h(6), h(7));
    let (elements, faces, mips, kvd) = (h(8), h(9), h(10), h(11));
    let Some((format, color_space, opaque)) = gl_format(internal, gl_fmt) else {
        return Err(Error::decode(
            path,
            format!(
                "KTX glInternalFormat {internal:#06x} is not one texmap reads (RGBA8, \
                 SRGB8_ALPHA8, R8, RG8, RGBA16F, RGBA32F, R11F_G11F_B10F, RGB9_E5, S3TC, RGTC, \
                 BPTC)"
            ),
        ));
    };
    let desc = Desc {
        container: Container::Ktx,
        format,
        color_space,
        opaque,
        width,
        height: height.max(1),
        depth: depth.max(1),
        levels: mips.max(1),
        faces,
        layers: elements.max(1),
    };
    let start = HEADER as u64 + u64::from(kvd);
    if start > bytes.len() as u64 {
        return Err(truncated(&format!(
            "its key/value data ({kvd} bytes) runs past the end ({} bytes)",
            bytes.len()
        )));
    }
    desc.check(path, limits, bytes.len() as u64 - start)?;

    // Rows of uncompressed formats are padded to 4 bytes.
    let row_padded = |level: u32| match format {
        FileFormat::Plain(p) => {
            let (w, _, _) = desc.level_size(level);
            let row = u64::from(w) * p.bytes_per_texel() as u64;
            pad4(row) != row
        }
        FileFormat::Block(_) => false,
    };
    let swap = match format {
        FileFormat::Plain(p) if big => p.swap_unit(),
        _ => 1,
    };
    // Only uncompressed formats are ever repacked.
    let repack = match format {
        FileFormat::Plain(p) if swap > 1 || (0..desc.levels).any(row_padded) => Some(p),
        _ => None,
    };
    let cube = desc.faces == 6 && elements == 0;

    // Walk the levels: the stored (padded) extent of every image.
    let mut stored: Vec<Range<usize>> = Vec::with_capacity((desc.layers * desc.faces) as usize);
    let mut per_level: Vec<Vec<Range<usize>>> = Vec::with_capacity(desc.levels as usize);
    let mut at = start;
    let len = bytes.len() as u64;
    for level in 0..desc.levels {
        let (w, h, d) = desc.level_size(level);
        let row = match format {
            FileFormat::Plain(p) => pad4(u64::from(w) * p.bytes_per_texel() as u64),
            FileFormat::Block(b) => b.level_bytes(w, 4),
        };
        let rows = match format {
            FileFormat::Plain(_) => u64::from(h),
            FileFormat::Block(_) => u64::from(h.div_ceil(4)),
        };
        let image = row * rows * u64::from(d);
        let images = u64::from(desc.layers * desc.faces);
        let want = if cube { image } else { image * images };
        if at + 4 > len {
            return Err(truncated(&format!(
                "level {level}'s imageSize is past the end"
            )));
        }
        let size = u64::from(word(at as usize));
        at += 4;
        if size != want {
            return Err(Error::decode(
                path,
                format!(
                    "KTX level {level}'s imageSize is {size} bytes; a {w}x{h}x{d} {} level \
                     needs {want}",
                    format.name()
                ),
            ));
        }
        stored.clear();
        for _ in 0..images {
            if at + image > len {
                return Err(truncated(&format!(
                    "level {level} needs {want} bytes at offset {at}, the file ends at {len}"
                )));
            }
            stored.push(at as usize..(at + image) as usize);
            at += if cube { pad4(image) } else { image };
        }
        at = pad4(at);
        per_level.push(stored.clone());
    }

    // (layer, face, level) order, packed when rows are padded or texels are swapped.
    let file_bytes = len;
    let count = (desc.layers * desc.faces) as usize;
    let Some(p) = repack else {
        let images = (0..count)
            .flat_map(|i| per_level.iter().map(move |l| l[i].clone()))
            .collect();
        return Ok(TextureFile::new(path, desc, file_bytes, bytes, images));
    };
    let mut data = Vec::with_capacity(desc.total_bytes().unwrap_or(0) as usize);
    let mut images = Vec::with_capacity(count * desc.levels as usize);
    for i in 0..count {
        for (level, l) in per_level.iter().enumerate() {
            let (w, _, _) = desc.level_size(level as u32);
            let row = u64::from(w) as usize * p.bytes_per_texel();
            let begin = data.len();
            for padded in bytes[l[i].clone()].chunks_exact(pad4(row as u64) as usize) {
                data.extend_from_slice(&padded[..row]);
            }
            if swap > 1 {
                data[begin..]
                    .chunks_exact_mut(swap)
                    .for_each(<[u8]>::reverse);
            }
            images.push(begin..data.len());
        }
    }
    Ok(TextureFile::new(path, desc, file_bytes, data, images))
}
