//! DDS (DirectDraw Surface), parsed by hand: the 124-byte header after the magic `DDS `,
//! its pixel format (a FourCC, or bit masks), and the optional 20-byte DX10 header.
//!
//! Data order: for each array element (for cube maps each face is an element, +X … −Z, and
//! a DX10 cube array holds six per layer), every mip level; a volume texture's level holds
//! its depth slices one after another. Rows are packed (no padding), block formats store
//! whole 4×4 blocks.
//!
//! The `ddsfile` crate (0.6) was not used: it sizes levels with unchecked `u32` arithmetic
//! (a declared 65535×65535 texture with mips overflows it), reads every byte after the
//! header into a second buffer, and brings four dependencies for what is 150 lines here.

use std::path::Path;

use super::{contiguous_images, le32, Container, Desc, FileFormat, PlainFormat, TextureFile};
use crate::texture::compressed::BlockFormat;
use crate::texture::load::Limits;
use crate::texture::ColorSpace;
use crate::{Error, Result};

const HEADER: usize = 4 + 124;
const DX10_HEADER: usize = 20;

// Pixel-format flags.
const DDPF_ALPHAPIXELS: u32 = 0x1;
const DDPF_FOURCC: u32 = 0x4;
const DDPF_RGB: u32 = 0x40;
const DDPF_LUMINANCE: u32 = 0x2_0000;
// Caps2.
const DDSCAPS2_CUBEMAP: u32 = 0x200;
const DDSCAPS2_CUBEMAP_ALLFACES: u32 = 0xfc00;
const DDSCAPS2_VOLUME: u32 = 0x20_0000;
// DX10 header.
const DIMENSION_TEXTURE1D: u32 = 2;
const DIMENSION_TEXTURE2D: u32 = 3;
const DIMENSION_TEXTURE3D: u32 = 4;
const MISC_TEXTURECUBE: u32 = 0x4;

/// The format and colour space a DXGI format number names.
fn dxgi_format(n: u32) -> Option<(FileFormat, ColorSpace)> {
    use BlockFormat as B;
    use ColorSpace::{Linear as L, Srgb as S};
    use FileFormat::{Block, Plain};
    use PlainFormat as P;
    Some(match n {
        2 => (Plain(P::Rgba32F), L),
        10 => (Plain(P::Rgba16F), L),
        26 => (Plain(P::R11G11B10F), L),
        27 | 28 => (Plain(P::Rgba8), L),
        29 => (Plain(P::Rgba8), S),
        48 | 49 => (Plain(P::Rg8), L),
        60 | 61 => (Plain(P::R8), L),
        67 => (Plain(P::Rgb9E5), L),
        87 | 90 => (Plain(P::Bgra8), L),
        91 => (Plain(P::Bgra8), S),
        88 | 92 => (Plain(P::Bgrx8), L),
        93 => (Plain(P::Bgrx8), S),
        70 | 71 => (Block(B::Bc1), L),
        72 => (Block(B::Bc1), S),
        73 | 74 => (Block(B::Bc2), L),
        75 => (Block(B::Bc2), S),
        76 | 77 => (Block(B::Bc3), L),
        78 => (Block(B::Bc3), S),
        79 | 80 => (Block(B::Bc4), L),
        81 => (Block(B::Bc4Signed), L),
        82 | 83 => (Block(B::Bc5), L),
        84 => (Block(B::Bc5Signed), L),
        94 | 95 => (Block(B::Bc6hUnsigned), L),
        96 => (Block(B::Bc6hSigned), L),
        97 | 98 => (Block(B::Bc7), L),
        99 => (Block(B::Bc7), S),
        _ => return None,
    })
}

/// The format a legacy FourCC (or a D3DFMT number in its place) names.
fn fourcc_format(fourcc: [u8; 4]) -> Option<FileFormat> {
    use BlockFormat as B;
    use FileFormat::{Block, Plain};
    Some(match &fourcc {
        b"DXT1" => Block(B::Bc1),
        b"DXT2" | b"DXT3" => Block(B::Bc2),
        b"DXT4" | b"DXT5" => Block(B::Bc3),
        b"ATI1" | b"BC4U" => Block(B::Bc4),
        b"BC4S" => Block(B::Bc4Signed),
        b"ATI2" | b"BC5U" => Block(B::Bc5),
        b"BC5S" => Block(B::Bc5Signed),
        _ => match u32::from_le_bytes(fourcc) {
            113 => Plain(PlainFormat::Rgba16F), // D3DFMT_A16B16G16R16F
            116 => Plain(PlainFormat::Rgba32F), // D3DFMT_A32B32G32R32F
            _ => return None,
        },
    })
}

/// The format a legacy pixel format's bit masks describe.
fn mask_format(flags: u32, bits: u32, masks: [u32; 4]) -> Option<PlainFormat> {
    let alpha = flags & DDPF_ALPHAPIXELS != 0;
    let a = if alpha { masks[3] } else { 0 };
    let rgb = [masks[0], masks[1], masks[2]];
    Some(match (bits, rgb, a) {
        (32, [0xff_0000, 0xff00, 0xff], 0xff00_0000) => PlainFormat::Bgra8,
        (32, [0xff_0000, 0xff00, 0xff], 0) => PlainFormat::Bgrx8,
        (32, [0xff, 0xff00, 0xff_0000], 0xff00_0000) => PlainFormat::Rgba8,
        (32, [0xff, 0xff00, 0xff_0000], 0) => PlainFormat::Rgbx8,
        (16, [0xff, 0xff00, 0], 0) => PlainFormat::Rg8,
        (8, [0xff, 0, 0], 0) if flags & DDPF_LUMINANCE != 0 => PlainFormat::L8,
        (8, [0xff, 0, 0], 0) => PlainFormat::R8,
        _ => return None,
    })
}

/// Parses a DDS file (`bytes` start with `DDS `).
pub(super) fn parse(bytes: Vec<u8>, path: &Path, limits: &Limits) -> Result<TextureFile> {
    if bytes.len() < HEADER {
        return Err(Error::decode(
            path,
            format!(
                "DDS file is truncated: {} bytes, the header alone is {HEADER}",
                bytes.len()
            ),
        ));
    }
    let h = |i: usize| le32(&bytes, 4 + 4 * i);
    let size = h(0);
    if size != 124 {
        return Err(Error::decode(
            path,
            format!("DDS header declares a size of {size} bytes; it is 124"),
        ));
    }
    let (height, width, depth_field, mips) = (h(2), h(3), h(5), h(6));
    let pf_flags = h(19);
    let fourcc: [u8; 4] = bytes[84..88].try_into().expect("4 bytes");
    let bits = h(21);
    let masks = [h(22), h(23), h(24), h(25)];
    let caps2 = h(27);

    let mut desc = Desc {
        container: Container::Dds,
        format: FileFormat::Plain(PlainFormat::Rgba8),
        color_space: ColorSpace::Linear,
        opaque: false,
        width,
        height,
        depth: if caps2 & DDSCAPS2_VOLUME != 0 {
            depth_field.max(1)
        } else {
            1
        },
        levels: mips.max(1),
        faces: 1,
        layers: 1,
    };
    let mut start = HEADER;
    if pf_flags & DDPF_FOURCC != 0 && &fourcc == b"DX10" {
        if bytes.len() < HEADER + DX10_HEADER {
            return Err(Error::decode(
                path,
                format!(
                    "DDS file is truncated: {} bytes, the DX10 header ends at {}",
                    bytes.len(),
                    HEADER + DX10_HEADER
                ),
            ));
        }
        let x = |i: usize| le32(&bytes, HEADER + 4 * i);
        let (dxgi, dimension, misc, array) = (x(0), x(1), x(2), x(3));
        let Some((format, color_space)) = dxgi_format(dxgi) else {
            return Err(Error::decode(
                path,
                format!("DDS DXGI format {dxgi} is not one texmap reads (BC1–BC7, BC6H, RGBA8, BGRA8, BGRX8, R8, RG8, RGBA16F, RGBA32F, R11G11B10F, RGB9E5)"),
            ));
        };
        desc.format = format;
        desc.color_space = color_space;
        desc.layers = array.max(1);
        match dimension {
            DIMENSION_TEXTURE1D => desc.height = 1,
            DIMENSION_TEXTURE2D => desc.depth = 1,
            DIMENSION_TEXTURE3D => desc.depth = depth_field.max(1),
            other => {
                return Err(Error::decode(
                    path,
                    format!("DDS DX10 header declares resource dimension {other}; 2, 3 or 4 (1D, 2D, 3D) are textures"),
                ))
            }
        }
        if misc & MISC_TEXTURECUBE != 0 {
            desc.faces = 6;
        }
        start += DX10_HEADER;
    } else {
        desc.format = if pf_flags & DDPF_FOURCC != 0 {
            fourcc_format(fourcc).ok_or_else(|| {
                let shown: String = fourcc
                    .iter()
                    .map(|&b| if b.is_ascii_graphic() { b as char } else { '?' })
                    .collect();
                Error::decode(
                    path,
                    format!(
                        "DDS FourCC '{shown}' ({}) is not one texmap reads (DXT1–DXT5, ATI1, \
                         ATI2, BC4U/S, BC5U/S, DX10)",
                        u32::from_le_bytes(fourcc)
                    ),
                )
            })?
        } else if pf_flags & (DDPF_RGB | DDPF_LUMINANCE) != 0 {
            FileFormat::Plain(mask_format(pf_flags, bits, masks).ok_or_else(|| {
                Error::decode(
                    path,
                    format!(
                        "DDS pixel format of {bits} bits with masks {:#x} {:#x} {:#x} {:#x} is \
                         not one texmap reads (RGBA8, BGRA8, BGRX8, RG8, R8, L8)",
                        masks[0], masks[1], masks[2], masks[3]
                    ),
                )
            })?)
        } else {
            return Err(Error::decode(
                path,
                format!("DDS pixel format flags {pf_flags:#x} name neither a FourCC nor RGB masks"),
            ));
        };
        if caps2 & DDSCAPS2_CUBEMAP != 0 {
            let present = (caps2 & DDSCAPS2_CUBEMAP_ALLFACES).count_ones();
            if present != 6 {
                return Err(Error::decode(
                    path,
                    format!("DDS cube map holds {present} of its 6 faces; partial cube maps are not supported"),
                ));
            }
            desc.faces = 6;
        }
    }
    let available = (bytes.len() - start) as u64;
    desc.check(path, limits, available)?;
    let images = contiguous_images(&desc, start);
    let file_bytes = bytes.len() as u64;
    Ok(TextureFile::new(path, desc, file_bytes, bytes, images))
}
