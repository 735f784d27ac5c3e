//! Block-compressed texel formats (BC1–BC7, BC6H): 4×4 blocks decoded by the formats' rules.
//!
//! API skeleton: the decoders land in the next commits.

use crate::{Error, Result};

/// A block-compressed format: the image is cut in 4×4 texel blocks, each stored in
/// [`BlockFormat::block_bytes`] bytes, blocks row-major. Edge blocks of a level whose size is
/// not a multiple of 4 are whole blocks whose texels past the edge are ignored.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BlockFormat {
    /// BC1 (DXT1): RGB with 1-bit alpha, 8 bytes a block.
    Bc1,
    /// BC2 (DXT3): BC1 colour with explicit 4-bit alpha, 16 bytes.
    Bc2,
    /// BC3 (DXT5): BC1 colour with interpolated alpha, 16 bytes.
    Bc3,
    /// BC4 unsigned: one channel (red), 8 bytes.
    Bc4,
    /// BC4 signed.
    Bc4Signed,
    /// BC5 unsigned: two channels (red, green), 16 bytes.
    Bc5,
    /// BC5 signed.
    Bc5Signed,
    /// BC6H unsigned half float RGB, 16 bytes.
    Bc6hUnsigned,
    /// BC6H signed half float RGB.
    Bc6hSigned,
    /// BC7: RGBA, 8 modes, 16 bytes.
    Bc7,
}

impl BlockFormat {
    /// Bytes per 4×4 block.
    #[must_use]
    pub const fn block_bytes(self) -> usize {
        match self {
            BlockFormat::Bc1 | BlockFormat::Bc4 | BlockFormat::Bc4Signed => 8,
            _ => 16,
        }
    }

    /// True for BC6H, whose texels are half floats, not 8-bit values.
    #[must_use]
    pub const fn is_float(self) -> bool {
        matches!(self, BlockFormat::Bc6hUnsigned | BlockFormat::Bc6hSigned)
    }

    /// The format's usual name ("BC1", "BC5 signed", …).
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            BlockFormat::Bc1 => "BC1",
            BlockFormat::Bc2 => "BC2",
            BlockFormat::Bc3 => "BC3",
            BlockFormat::Bc4 => "BC4",
            BlockFormat::Bc4Signed => "BC4 signed",
            BlockFormat::Bc5 => "BC5",
            BlockFormat::Bc5Signed => "BC5 signed",
            BlockFormat::Bc6hUnsigned => "BC6H unsigned",
            BlockFormat::Bc6hSigned => "BC6H signed",
            BlockFormat::Bc7 => "BC7",
        }
    }

    /// Bytes of one `width`×`height` level: whole blocks, rounded up at the edges.
    #[must_use]
    pub const fn level_bytes(self, width: u32, height: u32) -> u64 {
        let bx = (width as u64).div_ceil(4);
        let by = (height as u64).div_ceil(4);
        bx * by * self.block_bytes() as u64
    }
}

/// Decodes one block into 16 texels, row-major, as 8-bit RGBA. BC6H is not 8-bit: use
/// [`decode_block_f32`].
pub fn decode_block_rgba8(format: BlockFormat, block: &[u8], out: &mut [[u8; 4]; 16]) {
    let _ = (format, block, out);
    unimplemented!("BC decoders land in the next commits")
}

/// Decodes one block into 16 texels, row-major, as `f32` RGBA (8-bit formats: value / 255,
/// signed: the snorm rule; BC6H: the half-float value; alpha 1 where the format has none).
pub fn decode_block_f32(format: BlockFormat, block: &[u8], out: &mut [[f32; 4]; 16]) {
    let _ = (format, block, out);
    unimplemented!("BC decoders land in the next commits")
}

/// Decodes a whole `width`×`height` level to tightly packed RGBA8 rows (4 bytes a texel).
/// `data` must be exactly [`BlockFormat::level_bytes`] long.
pub fn decode_level_rgba8(
    format: BlockFormat,
    data: &[u8],
    width: u32,
    height: u32,
) -> Result<Vec<u8>> {
    check_level(format, data, width, height)?;
    unimplemented!("BC decoders land in the next commits")
}

/// Decodes a whole `width`×`height` level to packed `f32` RGBA (4 floats a texel).
pub fn decode_level_f32(
    format: BlockFormat,
    data: &[u8],
    width: u32,
    height: u32,
) -> Result<Vec<f32>> {
    check_level(format, data, width, height)?;
    unimplemented!("BC decoders land in the next commits")
}

fn check_level(format: BlockFormat, data: &[u8], width: u32, height: u32) -> Result<()> {
    let want = format.level_bytes(width, height);
    if data.len() as u64 != want {
        return Err(Error::Unsupported(format!(
            "{} level {width}x{height} needs {want} bytes, got {}",
            format.name(),
            data.len()
        )));
    }
    Ok(())
}
