//! Block-compressed texel formats (BC1–BC7, BC6H): 4×4 blocks decoded by the formats' rules.
//!
//! One file per codec family: `bc1.rs` (the colour block of BC1, BC2 and BC3), `alpha.rs`
//! (BC2's explicit alpha; the interpolated channel of BC3's alpha, BC4 and BC5, unsigned and
//! signed), `bc6h.rs` (and its tests, `bc6h_tests.rs`), `bc7.rs` (`bc7_tests.rs`),
//! `partitions.rs` (the BPTC partition and anchor tables BC6H and BC7 share). This file
//! dispatches on [`BlockFormat`] and decodes whole levels; `tests.rs` holds the property tests.
//!
//! # What the outputs hold
//! The rules are those of Direct3D 11.3's functional specification (§19.5) and the Khronos Data
//! Format Specification (the S3TC, RGTC and BPTC chapters). The 8-bit output holds the values
//! those rules give, before any sRGB conversion (an sRGB format's bytes come out encoded; the
//! caller decodes them through the usual 8-bit table). Texels past the edge of a level whose
//! size is not a multiple of 4 are dropped.
//!
//! - **BC1–BC3 colour**: D3D defines the palette as UNORM8 values (endpoints promoted by bit
//!   replication, thirds and halves of them) and allows 1/255 of error, so the divisions
//!   truncate as the reference decoder used to check this module does (texture2ddecoder, a
//!   port of Perfare's Texture2DDecoder); `decode_block_f32` gives those bytes / 255.
//! - **BC1's three-colour mode** (`color_0 <= color_1`): code 3 is *transparent* black,
//!   (0, 0, 0, 0), as D3D's BC1 and Khronos's "BC1 with alpha" say. The reference gives opaque
//!   black there (its alpha is 255); that departs from the D3D rule, so it is not followed. A
//!   caller that knows its texture is Khronos's "BC1 with no alpha" reads alpha as 1.
//! - **BC2 and BC3 colour** always use the four-colour rule, whatever the endpoint order. The
//!   reference applies BC1's three-colour rule there; again a departure, not followed.
//! - **BC3 alpha, BC4, BC5**: D3D gives exact sevenths and fifths and requires them to 1/65535,
//!   finer than 8 bits. `decode_block_f32` gives the exact value (as an `f32`: what texmap
//!   samples); the 8-bit output truncates the integer division, `(6·a0 + a1)/7`, as the
//!   reference and most software decoders do (bcdec, Texture2DDecoder), so 8-bit dumps
//!   compare byte for byte; it is up to 6/7 of a step below the exact value.
//! - **BC4 → (R, 0, 0, 1), BC5 → (R, G, 0, 1)**: D3D's and Khronos's rule, and the
//!   reference's. BC5 does not reconstruct a normal's Z: that is the shader's business.
//! - **Signed BC4 and BC5**: endpoints `max(v, −127)/127` (so −128 and −127 are both −1),
//!   the eight- or six-value choice by a signed compare of the stored bytes;
//!   `decode_block_f32` gives the exact values in [−1, 1]. The 8-bit output holds each channel
//!   as a SNORM8 byte (two's complement, the nearest of `127·v`): R (and G), B = 0 and
//!   A = 127, i.e. (R, G, 0, 1) in SNORM8. The reference does not decode the signed formats.
//! - **BC6H** (unsigned and signed) decodes to half floats bit-exactly as the specification
//!   requires; `decode_block_f32` gives them as `f32`, alpha 1. Its 8-bit output is an LDR
//!   view, each value clamped to [0, 1] and rounded to the nearest 255th, alpha 255. The
//!   reserved modes decode to 0 (alpha 1).
//! - **BC7** is bit-exact by the specification, and the same as the reference; the reserved
//!   mode (a zero low byte) decodes to (0, 0, 0, 0).
//!
//! # How this was checked
//! (2026-12-01.) Every level of every slice of the eight BC files in the shared assets'
//! `compressed/` (58 level-slices, 14,010,572 output bytes) against `bc_decode.py`'s PNGs:
//! BC1 and BC7 equal in every byte; BC3 too once its 8-bit alpha truncated as the reference
//! does (with rounding to nearest, 106,421 alpha bytes were one above it, and nothing else
//! differed). 100,000 random blocks of each of BC1, BC3, BC4, BC5 and BC7 against the same
//! reference: BC7 equal, every other difference one of the three departures above. BC6H
//! (200,000 random blocks over all modes, unsigned and signed) and BC7 against a second
//! independent decoder (the `bcdec_rs` crate): equal.

use rayon::prelude::*;

use super::f16_to_f32;
use crate::{Error, Result};

mod alpha;
mod bc1;
mod bc6h;
mod bc7;
mod partitions;
#[cfg(test)]
mod tests;

use alpha::{Channel, Signedness};
use bc1::ColourRule;

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
    /// Every block format.
    pub const ALL: [BlockFormat; 10] = [
        BlockFormat::Bc1,
        BlockFormat::Bc2,
        BlockFormat::Bc3,
        BlockFormat::Bc4,
        BlockFormat::Bc4Signed,
        BlockFormat::Bc5,
        BlockFormat::Bc5Signed,
        BlockFormat::Bc6hUnsigned,
        BlockFormat::Bc6hSigned,
        BlockFormat::Bc7,
    ];

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
        // At most 2^60 blocks; 16 bytes each overflow only at the very top, which saturates
        // (no slice is that long, so the length check still refuses it).
        (bx * by).saturating_mul(self.block_bytes() as u64)
    }
}

/// Decodes one block into 16 texels, row-major, as 8-bit RGBA: the values the format's rules
/// give (see the module docs: SNORM8 bytes for the signed formats; for BC6H, which is not 8-bit,
/// an LDR view, each value clamped to [0, 1]; use [`decode_block_f32`] for its values).
///
/// # Panics
/// If `block` is shorter than [`BlockFormat::block_bytes`] (extra bytes are ignored).
pub fn decode_block_rgba8(format: BlockFormat, block: &[u8], out: &mut [[u8; 4]; 16]) {
    match format {
        BlockFormat::Bc1 => bc1::decode(half(block, 0), ColourRule::Bc1, out),
        BlockFormat::Bc2 => {
            bc1::decode(half(block, 8), ColourRule::FourColour, out);
            let a = alpha::explicit_alpha(half(block, 0));
            set_channel(out, 3, &a);
        }
        BlockFormat::Bc3 => {
            bc1::decode(half(block, 8), ColourRule::FourColour, out);
            let a = Channel::decode(half(block, 0), Signedness::Unsigned).to_8bit();
            set_channel(out, 3, &a);
        }
        BlockFormat::Bc4 | BlockFormat::Bc4Signed | BlockFormat::Bc5 | BlockFormat::Bc5Signed => {
            let (signedness, one) = signedness(format);
            let r = Channel::decode(half(block, 0), signedness).to_8bit();
            let g = match format {
                BlockFormat::Bc5 | BlockFormat::Bc5Signed => {
                    Channel::decode(half(block, 8), signedness).to_8bit()
                }
                _ => [0; 16],
            };
            for (i, t) in out.iter_mut().enumerate() {
                *t = [r[i], g[i], 0, one];
            }
        }
        BlockFormat::Bc6hUnsigned | BlockFormat::Bc6hSigned => {
            let halves = bc6h::decode(whole(block), format == BlockFormat::Bc6hSigned);
            let ldr = |h: u16| (f16_to_f32(h).clamp(0.0, 1.0) * 255.0).round() as u8;
            for (t, h) in out.iter_mut().zip(halves) {
                *t = [ldr(h[0]), ldr(h[1]), ldr(h[2]), 255];
            }
        }
        BlockFormat::Bc7 => bc7::decode(whole(block), out),
    }
}

/// Decodes one block into 16 texels, row-major, as `f32` RGBA: for BC1, BC2, BC7 and BC3's
/// colour the UNORM8 values / 255; for BC3's alpha and BC4/BC5 the exact interpolated values
/// (signed ones in [−1, 1]); for BC6H the half-float values; alpha 1 where the format has none.
///
/// # Panics
/// If `block` is shorter than [`BlockFormat::block_bytes`] (extra bytes are ignored).
pub fn decode_block_f32(format: BlockFormat, block: &[u8], out: &mut [[f32; 4]; 16]) {
    let unorm = |v: u8| f32::from(v) / 255.0;
    match format {
        BlockFormat::Bc4 | BlockFormat::Bc4Signed | BlockFormat::Bc5 | BlockFormat::Bc5Signed => {
            let (signedness, _) = signedness(format);
            let r = Channel::decode(half(block, 0), signedness).to_f32();
            let g = match format {
                BlockFormat::Bc5 | BlockFormat::Bc5Signed => {
                    Channel::decode(half(block, 8), signedness).to_f32()
                }
                _ => [0.0; 16],
            };
            for (i, t) in out.iter_mut().enumerate() {
                *t = [r[i], g[i], 0.0, 1.0];
            }
        }
        BlockFormat::Bc6hUnsigned | BlockFormat::Bc6hSigned => {
            let halves = bc6h::decode(whole(block), format == BlockFormat::Bc6hSigned);
            for (t, h) in out.iter_mut().zip(halves) {
                *t = [f16_to_f32(h[0]), f16_to_f32(h[1]), f16_to_f32(h[2]), 1.0];
            }
        }
        BlockFormat::Bc1 | BlockFormat::Bc2 | BlockFormat::Bc3 | BlockFormat::Bc7 => {
            let mut rgba8 = [[0u8; 4]; 16];
            decode_block_rgba8(format, block, &mut rgba8);
            for (t, b) in out.iter_mut().zip(rgba8) {
                *t = b.map(unorm);
            }
            if format == BlockFormat::Bc3 {
                let a = Channel::decode(half(block, 0), Signedness::Unsigned).to_f32();
                for (t, a) in out.iter_mut().zip(a) {
                    t[3] = a;
                }
            }
        }
    }
}

/// The channel blocks' signedness, and the 8-bit value of 1 for the alpha the formats lack.
fn signedness(format: BlockFormat) -> (Signedness, u8) {
    match format {
        BlockFormat::Bc4Signed | BlockFormat::Bc5Signed => (Signedness::Signed, 127),
        _ => (Signedness::Unsigned, 255),
    }
}

/// The 8 bytes of `block` from `start` (a 64-bit half of a 16-byte block, or a BC1/BC4 block).
fn half(block: &[u8], start: usize) -> &[u8; 8] {
    block[start..start + 8].try_into().expect("eight bytes")
}

/// The first 16 bytes of `block`.
fn whole(block: &[u8]) -> &[u8; 16] {
    block[..16].try_into().expect("sixteen bytes")
}

fn set_channel(out: &mut [[u8; 4]; 16], c: usize, values: &[u8; 16]) {
    for (t, v) in out.iter_mut().zip(values) {
        t[c] = *v;
    }
}

/// Decodes a whole `width`×`height` level to tightly packed RGBA8 rows (4 bytes a texel),
/// each texel as [`decode_block_rgba8`] gives it; texels past the edge are dropped.
/// `data` must be exactly [`BlockFormat::level_bytes`] long: any other length is an error,
/// reported before anything is allocated, and so is an output too large to allocate.
pub fn decode_level_rgba8(
    format: BlockFormat,
    data: &[u8],
    width: u32,
    height: u32,
) -> Result<Vec<u8>> {
    check_level(format, data, width, height)?;
    decode_level(
        format,
        data,
        width,
        height,
        |block, texels: &mut [[u8; 4]; 16]| decode_block_rgba8(format, block, texels),
    )
}

/// Decodes a whole `width`×`height` level to packed `f32` RGBA (4 floats a texel), each texel
/// as [`decode_block_f32`] gives it; the same rules on `data` as [`decode_level_rgba8`].
pub fn decode_level_f32(
    format: BlockFormat,
    data: &[u8],
    width: u32,
    height: u32,
) -> Result<Vec<f32>> {
    check_level(format, data, width, height)?;
    decode_level(
        format,
        data,
        width,
        height,
        |block, texels: &mut [[f32; 4]; 16]| decode_block_f32(format, block, texels),
    )
}

/// The level loop shared by both outputs: one row of blocks per task, each block decoded into
/// 16 texels and its rows copied in, clipped to the level. `data` has passed `check_level`.
fn decode_level<T, F>(
    format: BlockFormat,
    data: &[u8],
    width: u32,
    height: u32,
    decode_block: F,
) -> Result<Vec<T>>
where
    T: Copy + Default + Send + Sync,
    F: Fn(&[u8], &mut [[T; 4]; 16]) + Sync,
{
    let (w, h) = (width as usize, height as usize);
    let values = w
        .checked_mul(h)
        .and_then(|n| n.checked_mul(4))
        .filter(|&n| {
            n.checked_mul(std::mem::size_of::<T>())
                .is_some_and(|b| b <= isize::MAX as usize)
        });
    let too_big = || {
        Error::Unsupported(format!(
            "{} level {width}x{height} is too large to decode in memory",
            format.name()
        ))
    };
    let values = values.ok_or_else(too_big)?;
    let mut out = Vec::new();
    out.try_reserve_exact(values).map_err(|_| too_big())?;
    out.resize(values, T::default());
    if values == 0 {
        return Ok(out);
    }
    let block_bytes = format.block_bytes();
    let blocks_x = w.div_ceil(4);
    let row_values = 4 * w; // one texel row
    out.par_chunks_mut(4 * row_values)
        .zip(data.par_chunks(blocks_x * block_bytes))
        .for_each(|(rows, blocks)| {
            let mut texels = [[T::default(); 4]; 16];
            let rows_here = rows.len() / row_values;
            for (bx, block) in blocks.chunks_exact(block_bytes).enumerate() {
                decode_block(block, &mut texels);
                let x0 = 4 * bx;
                let cols = (w - x0).min(4);
                for y in 0..rows_here {
                    let dst = &mut rows[y * row_values + 4 * x0..][..4 * cols];
                    for (d, t) in dst.chunks_exact_mut(4).zip(&texels[4 * y..4 * y + cols]) {
                        d.copy_from_slice(t);
                    }
                }
            }
        });
    Ok(out)
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
