//! Texel formats and their decoders.
//!
//! A texel is stored in its own format and decoded to linear `f32` RGBA when it is read. Every
//! unorm channel decodes through a lookup table chosen once per texture (linear or sRGB), so the
//! sRGB decode costs one load per channel and no branch. Alpha is always linear.

use glam::Vec4;

/// How texels are stored.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Format {
    R8,
    Rg8,
    Rgb8,
    Rgba8,
    R16,
    Rgba16,
    Rgba16F,
    R32F,
    Rgba32F,
    /// RGBA, 16-bit unorm, linear light, premultiplied alpha: the filtering format 8-bit
    /// colour textures are stored in by default ([`super::Storage::Linear16`]), read with no
    /// lookup table and no multiply by alpha.
    Rgba16Premultiplied,
}

pub use crate::color::ColorSpace;

impl Format {
    /// Bytes per texel.
    #[must_use]
    pub const fn bytes_per_texel(self) -> usize {
        match self {
            Format::R8 => 1,
            Format::Rg8 => 2,
            Format::Rgb8 => 3,
            Format::Rgba8 => 4,
            Format::R16 => 2,
            Format::Rgba16 => 8,
            Format::Rgba16F => 8,
            Format::R32F => 4,
            Format::Rgba32F => 16,
            Format::Rgba16Premultiplied => 8,
        }
    }

    /// Number of channels stored.
    #[must_use]
    pub const fn channels(self) -> usize {
        match self {
            Format::R8 | Format::R16 | Format::R32F => 1,
            Format::Rg8 => 2,
            Format::Rgb8 => 3,
            _ => 4,
        }
    }

    /// True when the format stores an alpha channel.
    #[must_use]
    pub const fn has_alpha(self) -> bool {
        self.channels() == 4
    }

    /// True for formats whose channels can be sRGB-encoded (the unorm ones).
    #[must_use]
    pub const fn is_unorm(self) -> bool {
        !matches!(
            self,
            Format::Rgba16F | Format::R32F | Format::Rgba32F | Format::Rgba16Premultiplied
        )
    }

    /// Encodes one linear, straight-alpha RGBA value into `out` (`bytes_per_texel` long),
    /// colour channels in `color_space` (alpha and float formats are always linear).
    pub fn encode(self, c: Vec4, color_space: ColorSpace, out: &mut [u8]) {
        let srgb = color_space == ColorSpace::Srgb;
        let enc8 = |v: f32| {
            if srgb {
                crate::color::linear_to_srgb8(v)
            } else {
                crate::color::linear_to_unorm8(v)
            }
        };
        let enc16 = |v: f32| {
            let v = if srgb {
                crate::color::linear_to_srgb(v)
            } else {
                v.clamp(0.0, 1.0)
            };
            ((v * 65535.0 + 0.5) as u16).to_le_bytes()
        };
        let a8 = crate::color::linear_to_unorm8(c.w);
        match self {
            Format::R8 => out[0] = enc8(c.x),
            Format::Rg8 => {
                out[0] = enc8(c.x);
                out[1] = enc8(c.y);
            }
            Format::Rgb8 => {
                out[0] = enc8(c.x);
                out[1] = enc8(c.y);
                out[2] = enc8(c.z);
            }
            Format::Rgba8 => {
                out[0] = enc8(c.x);
                out[1] = enc8(c.y);
                out[2] = enc8(c.z);
                out[3] = a8;
            }
            Format::R16 => out[..2].copy_from_slice(&enc16(c.x)),
            Format::Rgba16 => {
                out[0..2].copy_from_slice(&enc16(c.x));
                out[2..4].copy_from_slice(&enc16(c.y));
                out[4..6].copy_from_slice(&enc16(c.z));
                let a = ((c.w.clamp(0.0, 1.0) * 65535.0 + 0.5) as u16).to_le_bytes();
                out[6..8].copy_from_slice(&a);
            }
            Format::Rgba16F => {
                for (i, v) in c.to_array().into_iter().enumerate() {
                    out[2 * i..2 * i + 2].copy_from_slice(&f32_to_f16(v).to_le_bytes());
                }
            }
            Format::R32F => out[..4].copy_from_slice(&c.x.to_le_bytes()),
            Format::Rgba16Premultiplied => {
                let a = c.w.clamp(0.0, 1.0);
                let p = (c.truncate() * a).extend(a);
                for (i, v) in p.to_array().into_iter().enumerate() {
                    let q = (v.clamp(0.0, 1.0) * 65535.0 + 0.5) as u16;
                    out[2 * i..2 * i + 2].copy_from_slice(&q.to_le_bytes());
                }
            }
            Format::Rgba32F => {
                for (i, v) in c.to_array().into_iter().enumerate() {
                    out[4 * i..4 * i + 4].copy_from_slice(&v.to_le_bytes());
                }
            }
        }
    }
}

/// The table a texture of `format` with channels in `color_space` decodes through (16-bit
/// codes for the 16-bit unorm formats, 8-bit codes otherwise): 2D and 3D textures choose it
/// the same way.
#[must_use]
pub(crate) fn decode_table(format: Format, color_space: ColorSpace) -> &'static [f32] {
    use crate::color::{lut16, lut8};
    let sixteen_bit = matches!(format, Format::R16 | Format::Rgba16);
    match (sixteen_bit, color_space) {
        (true, cs) => lut16(cs),
        (false, cs) => lut8(cs),
    }
}

/// Decodes one texel of a format: the static half of the sampler state, so the filters are
/// compiled once per format and the per-texel loop has no format branch.
pub(crate) trait Codec: Copy + Send + Sync + 'static {
    const BPP: usize;
    const HAS_ALPHA: bool;
    /// True for [`Blocks`]: levels held block-compressed are read through the block cache
    /// (`storage/blocks.rs`), the others as this codec's texels.
    const BLOCKS: bool = false;
    /// Straight-alpha linear RGBA; `lut` maps unorm codes to linear values.
    fn decode(bytes: &[u8], lut: &[f32]) -> Vec4;

    /// Linear RGBA with alpha premultiplied (what every filter reads).
    #[inline(always)]
    fn decode_premultiplied(bytes: &[u8], lut: &[f32]) -> Vec4 {
        let c = Self::decode(bytes, lut);
        if Self::HAS_ALPHA {
            (c.truncate() * c.w).extend(c.w)
        } else {
            c
        }
    }
}

macro_rules! codec {
    ($name:ident, $bpp:expr, $alpha:expr, |$b:ident, $lut:ident| $body:expr) => {
        #[derive(Clone, Copy)]
        pub(crate) struct $name;
        impl Codec for $name {
            const BPP: usize = $bpp;
            const HAS_ALPHA: bool = $alpha;
            #[inline(always)]
            fn decode($b: &[u8], $lut: &[f32]) -> Vec4 {
                $body
            }
        }
    };
}

#[inline(always)]
fn u16le(b: &[u8], i: usize) -> usize {
    u16::from_le_bytes([b[i], b[i + 1]]) as usize
}

#[inline(always)]
fn f32le(b: &[u8], i: usize) -> f32 {
    f32::from_le_bytes([b[i], b[i + 1], b[i + 2], b[i + 3]])
}

codec!(CodecR8, 1, false, |b, l| Vec4::new(
    l[b[0] as usize],
    0.0,
    0.0,
    1.0
));
codec!(CodecRg8, 2, false, |b, l| Vec4::new(
    l[b[0] as usize],
    l[b[1] as usize],
    0.0,
    1.0
));
codec!(CodecRgb8, 3, false, |b, l| Vec4::new(
    l[b[0] as usize],
    l[b[1] as usize],
    l[b[2] as usize],
    1.0
));
codec!(CodecRgba8, 4, true, |b, l| Vec4::new(
    l[b[0] as usize],
    l[b[1] as usize],
    l[b[2] as usize],
    b[3] as f32 * (1.0 / 255.0)
));
codec!(CodecR16, 2, false, |b, l| Vec4::new(
    l[u16le(b, 0)],
    0.0,
    0.0,
    1.0
));
codec!(CodecRgba16, 8, true, |b, l| Vec4::new(
    l[u16le(b, 0)],
    l[u16le(b, 2)],
    l[u16le(b, 4)],
    u16le(b, 6) as f32 * (1.0 / 65535.0)
));
codec!(CodecRgba16F, 8, true, |b, _l| Vec4::new(
    f16_to_f32(u16le(b, 0) as u16),
    f16_to_f32(u16le(b, 2) as u16),
    f16_to_f32(u16le(b, 4) as u16),
    f16_to_f32(u16le(b, 6) as u16)
));
codec!(CodecR32F, 4, false, |b, _l| Vec4::new(
    f32le(b, 0),
    0.0,
    0.0,
    1.0
));
codec!(CodecRgba32F, 16, true, |b, _l| Vec4::new(
    f32le(b, 0),
    f32le(b, 4),
    f32le(b, 8),
    f32le(b, 12)
));

// Already premultiplied: `HAS_ALPHA` is false so readers do not multiply again.
codec!(CodecRgba16Premultiplied, 8, false, |b, _l| decode_rgba16(b));

/// Four little-endian u16 → `Vec4` in [0, 1]: one 8-byte load, a zero-extend and a
/// conversion (SSE2), the inner step of every filter on the default storage.
#[inline(always)]
fn decode_rgba16(b: &[u8]) -> Vec4 {
    let b: &[u8; 8] = b[..8].try_into().unwrap_or(&[0; 8]);
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{__m128i, _mm_unpacklo_epi16};
        use std::arch::x86_64::{_mm_cvtepi32_ps, _mm_loadl_epi64, _mm_setzero_si128};
        // SAFETY: SSE2 is part of x86_64; `b` is 8 readable bytes and `_mm_loadl_epi64`
        // reads exactly 8, unaligned.
        let v = unsafe {
            let q = _mm_loadl_epi64(b.as_ptr().cast::<__m128i>());
            _mm_cvtepi32_ps(_mm_unpacklo_epi16(q, _mm_setzero_si128()))
        };
        Vec4::from(v) * (1.0 / 65535.0)
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        let q = u64::from_le_bytes(*b);
        let lane = |k: u32| ((q >> (16 * k)) & 0xffff) as i32 as f32;
        Vec4::new(lane(0), lane(1), lane(2), lane(3)) * (1.0 / 65535.0)
    }
}

/// Runs `$body` with the type alias `$C` bound to the codec of `$format`.
macro_rules! with_codec {
    ($format:expr, $C:ident => $body:expr) => {{
        use $crate::texture::format::*;
        match $format {
            Format::R8 => {
                type $C = CodecR8;
                $body
            }
            Format::Rg8 => {
                type $C = CodecRg8;
                $body
            }
            Format::Rgb8 => {
                type $C = CodecRgb8;
                $body
            }
            Format::Rgba8 => {
                type $C = CodecRgba8;
                $body
            }
            Format::R16 => {
                type $C = CodecR16;
                $body
            }
            Format::Rgba16 => {
                type $C = CodecRgba16;
                $body
            }
            Format::Rgba16F => {
                type $C = CodecRgba16F;
                $body
            }
            Format::R32F => {
                type $C = CodecR32F;
                $body
            }
            Format::Rgba32F => {
                type $C = CodecRgba32F;
                $body
            }
            Format::Rgba16Premultiplied => {
                type $C = CodecRgba16Premultiplied;
                $body
            }
        }
    }};
}
pub(crate) use with_codec;

/// The codec of a texture held block-compressed ([`super::Storage::Compressed`]): its levels
/// with blocks are decoded through the per-thread block cache; levels built from them (a
/// file without its full chain) are texels of `T`.
#[derive(Clone, Copy)]
pub(crate) struct Blocks<T>(std::marker::PhantomData<T>);

impl<T: Codec> Codec for Blocks<T> {
    const BPP: usize = T::BPP;
    const HAS_ALPHA: bool = T::HAS_ALPHA;
    const BLOCKS: bool = true;
    #[inline(always)]
    fn decode(bytes: &[u8], lut: &[f32]) -> Vec4 {
        T::decode(bytes, lut)
    }
}

/// Runs `$body` with `$C` bound to the codec a 2D texture's texels are read with: its
/// storage format's, or [`Blocks`] of it when the texture is held block-compressed (the
/// formats block textures keep their other levels in: RGBA8, RGBA16F, RGBA32F).
macro_rules! with_texture_codec {
    ($texture:expr, $C:ident => $body:expr) => {{
        use $crate::texture::format::*;
        let texture: &$crate::texture::Texture2D = $texture;
        if texture.block_format().is_some() {
            match texture.storage_format() {
                Format::Rgba16F => {
                    type $C = Blocks<CodecRgba16F>;
                    $body
                }
                Format::Rgba32F => {
                    type $C = Blocks<CodecRgba32F>;
                    $body
                }
                _ => {
                    type $C = Blocks<CodecRgba8>;
                    $body
                }
            }
        } else {
            with_codec!(texture.storage_format(), $C => $body)
        }
    }};
}
pub(crate) use with_texture_codec;

/// IEEE half → single precision (subnormals, infinities and NaN included).
#[must_use]
pub fn f16_to_f32(h: u16) -> f32 {
    let sign = ((h >> 15) as u32) << 31;
    let exp = ((h >> 10) & 0x1f) as u32;
    let man = (h & 0x3ff) as u32;
    let bits = match (exp, man) {
        (0, 0) => sign,
        (0, m) => {
            // Subnormal: value = m · 2^-24.
            let v = m as f32 * (1.0 / 16_777_216.0);
            return if sign != 0 { -v } else { v };
        }
        (0x1f, m) => sign | 0x7f80_0000 | (m << 13),
        (e, m) => sign | ((e + 112) << 23) | (m << 13),
    };
    f32::from_bits(bits)
}

/// Single → IEEE half precision, round to nearest even; overflow becomes infinity.
#[must_use]
pub fn f32_to_f16(f: f32) -> u16 {
    let bits = f.to_bits();
    let sign = ((bits >> 16) & 0x8000) as u16;
    let exp = ((bits >> 23) & 0xff) as i32;
    let man = bits & 0x7f_ffff;
    if exp == 0xff {
        return sign | 0x7c00 | if man != 0 { 0x200 } else { 0 };
    }
    let e = exp - 127 + 15;
    if e >= 0x1f {
        return sign | 0x7c00;
    }
    if e <= 0 {
        if e < -10 {
            return sign;
        }
        let m = man | 0x80_0000;
        let shift = (14 - e) as u32;
        let half = 1u32 << (shift - 1);
        let rem = m & ((1 << shift) - 1);
        let mut r = m >> shift;
        if rem > half || (rem == half && r & 1 == 1) {
            r += 1;
        }
        return sign | r as u16;
    }
    let rem = man & 0x1fff;
    let mut r = ((e as u32) << 10) | (man >> 13);
    if rem > 0x1000 || (rem == 0x1000 && r & 1 == 1) {
        r += 1;
    }
    sign | r as u16
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn half_round_trips_every_finite_code() {
        for h in 0..=0xffffu16 {
            let f = f16_to_f32(h);
            if f.is_nan() {
                continue;
            }
            assert_eq!(f32_to_f16(f), h, "code {h:#06x}");
        }
    }

    #[test]
    fn encode_then_decode_every_format() {
        let c = Vec4::new(0.25, 0.5, 0.75, 0.5);
        for f in [
            Format::R8,
            Format::Rg8,
            Format::Rgb8,
            Format::Rgba8,
            Format::R16,
            Format::Rgba16,
            Format::Rgba16F,
            Format::R32F,
            Format::Rgba32F,
        ] {
            let mut buf = vec![0u8; f.bytes_per_texel()];
            f.encode(c, ColorSpace::Linear, &mut buf);
            let lut: &[f32] = if f.bytes_per_texel() / f.channels() == 2 && f.is_unorm() {
                crate::color::lut16(ColorSpace::Linear)
            } else {
                crate::color::lut8(ColorSpace::Linear)
            };
            let d = with_codec!(f, C => C::decode(&buf, lut));
            for i in 0..f.channels() {
                let want = if i == 3 || f.channels() > i {
                    c[i]
                } else {
                    0.0
                };
                assert!(
                    (d[i] - want).abs() < 2.0 / 255.0,
                    "{f:?} channel {i}: {}",
                    d[i]
                );
            }
        }
    }
}
