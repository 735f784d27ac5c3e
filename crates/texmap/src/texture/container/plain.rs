//! The uncompressed texel formats containers hold, and their decoding to RGBA8 and `f32`.
//!
//! Packed floats follow the formats' definitions (DXGI, Vulkan and OpenGL agree): R11G11B10F
//! is, in a little-endian `u32`, red in bits 0–10 and green in 11–21 (5-bit exponent, 6-bit
//! mantissa, bias 15, no sign) and blue in 22–31 (5-bit mantissa); RGB9E5 holds three 9-bit
//! mantissas (bits 0–8, 9–17, 18–26) and a shared 5-bit exponent (27–31):
//! `value = mantissa · 2^(exponent − 15 − 9)`.

use crate::texture::f16_to_f32;

/// An uncompressed texel format.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PlainFormat {
    /// One 8-bit channel, red.
    R8,
    /// One 8-bit luminance channel, read as grey.
    L8,
    /// Two 8-bit channels, red and green.
    Rg8,
    /// 8-bit red, green, blue, alpha.
    Rgba8,
    /// 8-bit red, green, blue and an unused byte (alpha 1).
    Rgbx8,
    /// 8-bit blue, green, red, alpha.
    Bgra8,
    /// 8-bit blue, green, red and an unused byte (alpha 1).
    Bgrx8,
    /// Half-float RGBA.
    Rgba16F,
    /// Float RGBA.
    Rgba32F,
    /// Packed unsigned floats: 11-bit red and green, 10-bit blue.
    R11G11B10F,
    /// Three 9-bit mantissas sharing a 5-bit exponent.
    Rgb9E5,
}

impl PlainFormat {
    /// Bytes per texel.
    #[must_use]
    pub const fn bytes_per_texel(self) -> usize {
        match self {
            PlainFormat::R8 | PlainFormat::L8 => 1,
            PlainFormat::Rg8 => 2,
            PlainFormat::Rgba8
            | PlainFormat::Rgbx8
            | PlainFormat::Bgra8
            | PlainFormat::Bgrx8
            | PlainFormat::R11G11B10F
            | PlainFormat::Rgb9E5 => 4,
            PlainFormat::Rgba16F => 8,
            PlainFormat::Rgba32F => 16,
        }
    }

    /// The bytes a big-endian file swaps in each unit of the texel (1: none).
    #[must_use]
    pub(super) const fn swap_unit(self) -> usize {
        match self {
            PlainFormat::Rgba16F => 2,
            PlainFormat::Rgba32F | PlainFormat::R11G11B10F | PlainFormat::Rgb9E5 => 4,
            _ => 1,
        }
    }

    /// True for the float formats.
    #[must_use]
    pub const fn is_float(self) -> bool {
        matches!(
            self,
            PlainFormat::Rgba16F
                | PlainFormat::Rgba32F
                | PlainFormat::R11G11B10F
                | PlainFormat::Rgb9E5
        )
    }

    /// The format's name.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            PlainFormat::R8 => "R8",
            PlainFormat::L8 => "L8",
            PlainFormat::Rg8 => "RG8",
            PlainFormat::Rgba8 => "RGBA8",
            PlainFormat::Rgbx8 => "RGBX8",
            PlainFormat::Bgra8 => "BGRA8",
            PlainFormat::Bgrx8 => "BGRX8",
            PlainFormat::Rgba16F => "RGBA16F",
            PlainFormat::Rgba32F => "RGBA32F",
            PlainFormat::R11G11B10F => "R11G11B10F",
            PlainFormat::Rgb9E5 => "RGB9E5",
        }
    }
}

/// Texels as RGBA8 (float formats clamped to [0, 1], no transfer function).
pub(super) fn decode_rgba8(format: PlainFormat, bytes: &[u8]) -> Vec<u8> {
    let n = bytes.len() / format.bytes_per_texel();
    let mut out = Vec::with_capacity(n * 4);
    match format {
        PlainFormat::R8 => bytes.iter().for_each(|&r| out.extend([r, 0, 0, 255])),
        PlainFormat::L8 => bytes.iter().for_each(|&l| out.extend([l, l, l, 255])),
        PlainFormat::Rg8 => bytes
            .chunks_exact(2)
            .for_each(|t| out.extend([t[0], t[1], 0, 255])),
        PlainFormat::Rgba8 => out.extend_from_slice(bytes),
        PlainFormat::Rgbx8 => bytes
            .chunks_exact(4)
            .for_each(|t| out.extend([t[0], t[1], t[2], 255])),
        PlainFormat::Bgra8 => bytes
            .chunks_exact(4)
            .for_each(|t| out.extend([t[2], t[1], t[0], t[3]])),
        PlainFormat::Bgrx8 => bytes
            .chunks_exact(4)
            .for_each(|t| out.extend([t[2], t[1], t[0], 255])),
        PlainFormat::Rgba16F
        | PlainFormat::Rgba32F
        | PlainFormat::R11G11B10F
        | PlainFormat::Rgb9E5 => out.extend(
            decode_f32(format, bytes)
                .into_iter()
                .map(crate::color::linear_to_unorm8),
        ),
    }
    out
}

/// Any format's texels as RGBA `f32` (8-bit values `v/255`).
pub(super) fn decode_f32(format: PlainFormat, bytes: &[u8]) -> Vec<f32> {
    let word = |t: &[u8]| u32::from_le_bytes([t[0], t[1], t[2], t[3]]);
    match format {
        PlainFormat::Rgba16F => bytes
            .chunks_exact(2)
            .map(|h| f16_to_f32(u16::from_le_bytes([h[0], h[1]])))
            .collect(),
        PlainFormat::Rgba32F => bytes
            .chunks_exact(4)
            .map(|f| f32::from_le_bytes([f[0], f[1], f[2], f[3]]))
            .collect(),
        PlainFormat::R11G11B10F => bytes
            .chunks_exact(4)
            .flat_map(|t| {
                let [r, g, b] = r11g11b10f(word(t));
                [r, g, b, 1.0]
            })
            .collect(),
        PlainFormat::Rgb9E5 => bytes
            .chunks_exact(4)
            .flat_map(|t| {
                let [r, g, b] = rgb9e5(word(t));
                [r, g, b, 1.0]
            })
            .collect(),
        _ => decode_rgba8(format, bytes)
            .into_iter()
            .map(|v| f32::from(v) / 255.0)
            .collect(),
    }
}

/// An unsigned float of `mantissa_bits` and a 5-bit exponent (bias 15), as in R11G11B10F.
fn small_float(v: u32, mantissa_bits: u32) -> f32 {
    let m = v & ((1 << mantissa_bits) - 1);
    let e = (v >> mantissa_bits) & 31;
    let scale = (1u32 << mantissa_bits) as f32;
    match e {
        0 => m as f32 / scale * 2f32.powi(-14),
        31 if m == 0 => f32::INFINITY,
        31 => f32::NAN,
        _ => (1.0 + m as f32 / scale) * 2f32.powi(e as i32 - 15),
    }
}

/// R11G11B10F: red and green 11 bits, blue 10.
#[must_use]
pub(super) fn r11g11b10f(v: u32) -> [f32; 3] {
    [
        small_float(v & 0x7ff, 6),
        small_float((v >> 11) & 0x7ff, 6),
        small_float(v >> 22, 5),
    ]
}

/// RGB9E5: three 9-bit mantissas, one exponent.
#[must_use]
pub(super) fn rgb9e5(v: u32) -> [f32; 3] {
    let scale = 2f32.powi((v >> 27) as i32 - 15 - 9);
    [v & 0x1ff, (v >> 9) & 0x1ff, (v >> 18) & 0x1ff].map(|m| m as f32 * scale)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn packed_floats_decode_by_their_definitions() {
        // 1.0 in an 11-bit float: exponent 15, mantissa 0 → 15 << 6; in 10 bits 15 << 5.
        let one11 = 15 << 6;
        let one10 = 15 << 5;
        assert_eq!(r11g11b10f(one11), [1.0, 0.0, 0.0]);
        assert_eq!(r11g11b10f(one11 << 11), [0.0, 1.0, 0.0]);
        assert_eq!(r11g11b10f(one10 << 22), [0.0, 0.0, 1.0]);
        // 2.5 = 1.25 · 2¹: exponent 16, mantissa 0.25 · 64 = 16 (11 bits), 8 (10 bits).
        let v = (16 << 6 | 16) | ((16 << 5 | 8) << 22);
        assert_eq!(r11g11b10f(v), [2.5, 0.0, 2.5]);
        // The largest 11-bit value: (1 + 63/64) · 2¹⁵ = 65024; a denormal: 1/64 · 2⁻¹⁴.
        assert_eq!(r11g11b10f(30 << 6 | 63)[0], 65024.0);
        assert_eq!(r11g11b10f(1)[0], 2f32.powi(-20));
        assert!(r11g11b10f(31 << 6)[0].is_infinite());
        // RGB9E5: exponent 15 + 9 = 24 makes a mantissa m worth m; exponent 16, m/256.
        assert_eq!(rgb9e5(24 << 27 | 3 | 5 << 9 | 511 << 18), [3.0, 5.0, 511.0]);
        assert_eq!(rgb9e5(16 << 27 | 256), [1.0, 0.0, 0.0]);
        assert_eq!(rgb9e5(0), [0.0, 0.0, 0.0]);
    }

    #[test]
    fn eight_bit_formats_swizzle_and_fill_alpha() {
        assert_eq!(
            decode_rgba8(PlainFormat::Bgra8, &[1, 2, 3, 4]),
            [3, 2, 1, 4]
        );
        assert_eq!(
            decode_rgba8(PlainFormat::Bgrx8, &[1, 2, 3, 4]),
            [3, 2, 1, 255]
        );
        assert_eq!(
            decode_rgba8(PlainFormat::Rgbx8, &[1, 2, 3, 4]),
            [1, 2, 3, 255]
        );
        assert_eq!(decode_rgba8(PlainFormat::R8, &[7]), [7, 0, 0, 255]);
        assert_eq!(decode_rgba8(PlainFormat::L8, &[7]), [7, 7, 7, 255]);
        assert_eq!(decode_rgba8(PlainFormat::Rg8, &[7, 9]), [7, 9, 0, 255]);
        assert_eq!(
            decode_f32(PlainFormat::Rgba8, &[255, 0, 51, 255]),
            [1.0, 0.0, 0.2, 1.0]
        );
        let h = crate::texture::f32_to_f16(0.5).to_le_bytes();
        let f = decode_f32(PlainFormat::Rgba16F, &[h, h, h, h].concat());
        assert_eq!(f, [0.5; 4]);
    }
}
