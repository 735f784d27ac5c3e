//! Colour: sRGB transfer functions and the lookup tables texel decoding uses.
//!
//! All shading and filtering happen in linear light with `f32` components; sRGB is decoded
//! when a texel is read and encoded once, when an image is written.

use std::sync::OnceLock;

use glam::Vec4;

/// The sRGB electro-optical transfer function: encoded value in [0, 1] → linear light.
#[must_use]
pub fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// The inverse of [`srgb_to_linear`]; the input is clamped to [0, 1].
#[must_use]
pub fn linear_to_srgb(c: f32) -> f32 {
    let c = c.clamp(0.0, 1.0);
    if c <= 0.003_130_8 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

/// Encodes a linear value to an 8-bit sRGB code, exactly rounded: code k for `c` in
/// [lin((k − ½)/255), lin((k + ½)/255)), 0 for NaN and values ≤ 0, 255 from 1 up.
///
/// No `powf` per channel (which dominated building a texture's mip chain), and no branch
/// on the value: the float's top 16 bits (its exponent and 7 bits of mantissa) choose a
/// slot of a table, which holds the code at the slot's start and the one threshold that may
/// fall inside the slot (the slots are narrower than the gaps between thresholds: 1/128 of
/// an octave against at least 0.89 % of the value), so one comparison finishes the code.
/// Values under 2⁻¹³ (below the first threshold) share a slot of code 0, values from 1 up
/// one of code 255. Encoding many values, [`Srgb8Encoder`] looks the table up once.
#[inline]
#[must_use]
pub fn linear_to_srgb8(c: f32) -> u8 {
    Srgb8Encoder::new().encode(c)
}

/// [`linear_to_srgb8`] with its table at hand: for loops over a frame's pixels.
#[derive(Clone, Copy)]
pub struct Srgb8Encoder {
    table: &'static Srgb8Table,
}

/// The slots' keys (`bits >> 16` of a positive float) span [2⁻¹³, 1): 13 octaves of 128.
const KEY_LO: u32 = 114 << 7;
const KEY_HI: u32 = 127 << 7;
/// The spanned keys, and one slot below them and one above.
const SLOTS: usize = (KEY_HI - KEY_LO) as usize + 2;

/// Slot `i`: the threshold inside it (NaN when none: no value is at or above it) and the
/// code at its start.
struct Srgb8Table {
    slots: [Slot; SLOTS],
}

/// A slot of [`Srgb8Table`], laid out as the lanes' gathers read it (`lanes.rs`).
#[derive(Clone, Copy)]
#[repr(C)]
struct Slot {
    threshold: f32,
    start: u32,
}

impl Default for Srgb8Encoder {
    fn default() -> Self {
        Self::new()
    }
}

impl Srgb8Encoder {
    /// The encoder (its table is built on first use, once per process).
    #[must_use]
    pub fn new() -> Self {
        static TABLE: OnceLock<Srgb8Table> = OnceLock::new();
        let table = TABLE.get_or_init(|| {
            let thresholds: [f32; 255] =
                std::array::from_fn(|k| srgb_to_linear((k as f32 + 0.5) / 255.0));
            let code_at = |v: f32| thresholds.partition_point(|&t| t <= v);
            let slot = |threshold, start| Slot { threshold, start };
            let slots = std::array::from_fn(|i| match i {
                0 => slot(f32::NAN, 0),
                _ if i == SLOTS - 1 => slot(f32::NAN, 255),
                _ => {
                    let key = KEY_LO + i as u32 - 1;
                    let start = f32::from_bits(key << 16);
                    let k = code_at(start);
                    let end = f32::from_bits((key + 1) << 16);
                    // At most one threshold inside a slot (the encoding's premise).
                    assert!(k + 2 > 255 || thresholds[k + 1] >= end, "slot {key:#x}");
                    let inside = thresholds.get(k).copied().filter(|&t| t < end);
                    slot(inside.unwrap_or(f32::NAN), k as u32)
                }
            });
            Srgb8Table { slots }
        });
        Srgb8Encoder { table }
    }

    /// [`linear_to_srgb8`] of `c`.
    #[inline]
    #[must_use]
    pub fn encode(self, c: f32) -> u8 {
        let key = c.to_bits() >> 16;
        // Below the span: slot 0; from 1 up (and negative values, NaN): the last slot.
        let slot = ((key + 1).saturating_sub(KEY_LO) as usize).min(SLOTS - 1);
        let Slot { threshold, start } = self.table.slots[slot];
        let code = start + u32::from(c >= threshold);
        // NaN, zero and negative values encode to 0.
        if c > 0.0 {
            code as u8
        } else {
            0
        }
    }
}

/// [`linear_to_srgb8`] of each pixel's colour, composited over black (the premultiplied
/// colour as it is): three bytes a pixel in `out` (RGB), alpha dropped. Eight pixels at a
/// time in AVX2 lanes where the CPU has them (`lanes.rs`: the same table, the same codes).
///
/// # Panics
/// If `out` does not hold three bytes a pixel.
pub fn encode_srgb8(color: &[Vec4], out: &mut [u8]) {
    encode_rows(
        color,
        out,
        #[cfg(target_arch = "x86_64")]
        lanes::srgb8,
        |e, c| [e.encode(c.x), e.encode(c.y), e.encode(c.z)],
    );
}

/// Each pixel with straight (un-premultiplied) alpha, as PNG stores it: four bytes a pixel in
/// `out`, the colour the sRGB code of `rgb / a` ([`linear_to_srgb8`]), alpha
/// [`linear_to_unorm8`] of `a`; a pixel whose alpha is not above 0 (NaN too) is all zero.
/// In AVX2 lanes where the CPU has them, as [`encode_srgb8`].
///
/// # Panics
/// If `out` does not hold four bytes a pixel.
pub fn encode_srgba8(color: &[Vec4], out: &mut [u8]) {
    encode_rows(
        color,
        out,
        #[cfg(target_arch = "x86_64")]
        lanes::srgba8,
        straight8,
    );
}

/// The pixels of `color` encoded `N` bytes each into `out`: whole blocks by `lanes` where
/// the CPU has x86-64-v3 (it returns how many pixels it encoded), the rest by `pixel`.
fn encode_rows<const N: usize>(
    color: &[Vec4],
    out: &mut [u8],
    #[cfg(target_arch = "x86_64")] lanes: unsafe fn(Srgb8Encoder, &[Vec4], &mut [u8]) -> usize,
    pixel: impl Fn(Srgb8Encoder, Vec4) -> [u8; N],
) {
    assert_eq!(out.len(), N * color.len(), "{N} bytes a pixel");
    let e = Srgb8Encoder::new();
    let mut done = 0;
    #[cfg(target_arch = "x86_64")]
    if crate::cpu::level() == crate::cpu::Level::V3 {
        // SAFETY: the CPU has x86-64-v3 (`cpu::level`), and `out` holds `N` bytes a pixel.
        done = unsafe { lanes(e, color, out) };
    }
    for (o, c) in out[N * done..].chunks_exact_mut(N).zip(&color[done..]) {
        o.copy_from_slice(&pixel(e, *c));
    }
}

/// One pixel of [`encode_srgba8`].
#[inline]
fn straight8(e: Srgb8Encoder, c: Vec4) -> [u8; 4] {
    // Also NaN: nothing to divide by (the pixel stays zero).
    if c.w > 0.0 {
        let s = c.truncate() / c.w.min(1.0);
        [
            e.encode(s.x),
            e.encode(s.y),
            e.encode(s.z),
            linear_to_unorm8(c.w),
        ]
    } else {
        [0; 4]
    }
}

#[cfg(target_arch = "x86_64")]
mod lanes;

/// Encodes a linear value to an 8-bit code without a transfer function (round to nearest).
#[must_use]
pub fn linear_to_unorm8(c: f32) -> u8 {
    (c.clamp(0.0, 1.0) * 255.0 + 0.5) as u8
}

/// What the stored values of a colour channel mean.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum ColorSpace {
    /// sRGB-encoded colour (the default for colour images): decoded before filtering.
    #[default]
    Srgb,
    /// Linear data (normal, roughness, height maps; float images).
    Linear,
}

/// The linear value of every `N`-level code in `color_space`. One loop per space, so the
/// linear table never evaluates the sRGB curve.
fn table<const N: usize>(color_space: ColorSpace) -> Box<[f32]> {
    let max = (N - 1) as f32;
    let codes = (0..N).map(|i| i as f32 / max);
    match color_space {
        ColorSpace::Srgb => codes.map(srgb_to_linear).collect(),
        ColorSpace::Linear => codes.collect(),
    }
}

/// Decoding table for 8-bit codes: `lut8(ColorSpace::Srgb)[code]` is the linear value of an
/// sRGB code.
pub fn lut8(color_space: ColorSpace) -> &'static [f32] {
    static LIN: OnceLock<Box<[f32]>> = OnceLock::new();
    static SRGB: OnceLock<Box<[f32]>> = OnceLock::new();
    match color_space {
        ColorSpace::Srgb => SRGB.get_or_init(|| table::<256>(color_space)),
        ColorSpace::Linear => LIN.get_or_init(|| table::<256>(color_space)),
    }
}

/// Decoding table for 16-bit codes, as [`lut8`].
pub fn lut16(color_space: ColorSpace) -> &'static [f32] {
    static LIN: OnceLock<Box<[f32]>> = OnceLock::new();
    static SRGB: OnceLock<Box<[f32]>> = OnceLock::new();
    match color_space {
        ColorSpace::Srgb => SRGB.get_or_init(|| table::<65536>(color_space)),
        ColorSpace::Linear => LIN.get_or_init(|| table::<65536>(color_space)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_round_trips_every_8bit_code() {
        for i in 0..=255u8 {
            let lin = lut8(ColorSpace::Srgb)[i as usize];
            assert_eq!(linear_to_srgb8(lin), i);
        }
    }

    #[test]
    fn fast_encoder_matches_the_formula() {
        for i in 0..=100_000 {
            let c = i as f32 / 100_000.0;
            let direct = (linear_to_srgb(c) * 255.0 + 0.5) as u8;
            let fast = linear_to_srgb8(c);
            assert!(direct.abs_diff(fast) <= 1, "{c}: {direct} vs {fast}");
        }
        assert_eq!(linear_to_srgb8(-1.0), 0);
        assert_eq!(linear_to_srgb8(7.0), 255);
    }

    #[test]
    fn srgb_known_values() {
        assert!((srgb_to_linear(0.5) - 0.214_041).abs() < 1e-5);
        assert_eq!(srgb_to_linear(0.0), 0.0);
        assert!((srgb_to_linear(1.0) - 1.0).abs() < 1e-6);
    }

    #[test]
    fn srgb8_encoding_rounds_exactly_at_every_threshold() {
        let lin = |c: f32| srgb_to_linear(c / 255.0);
        let code = |v: f32| {
            // The definition: the number of thresholds lin((k + ½)/255) at or below v.
            (0..255).filter(|&k| lin(k as f32 + 0.5) <= v).count() as u8
        };
        let mut values = vec![f32::NAN, -1.0, 0.0, 1.0, 2.0, f32::INFINITY];
        for k in 0..255 {
            let t = lin(k as f32 + 0.5);
            let (below, above) = (
                f32::from_bits(t.to_bits() - 1),
                f32::from_bits(t.to_bits() + 1),
            );
            values.extend([t, below, above, lin(k as f32)]);
        }
        values.extend((0..10_000).map(|i| i as f32 / 10_000.0));
        for v in values {
            let want = if v.is_nan() { 0 } else { code(v) };
            assert_eq!(linear_to_srgb8(v), want, "v = {v:e}");
        }
    }

    #[test]
    fn srgb8_encoding_is_exact_over_the_floats() {
        // Every 61st float from 0 to 1 (about 17 million, every slot many times over), the
        // slots' edges and their neighbours, negative values and the specials: against
        // the definition, by a search of the thresholds.
        let thresholds: Vec<f32> = (0..255)
            .map(|k| srgb_to_linear((k as f32 + 0.5) / 255.0))
            .collect();
        let code = |v: f32| thresholds.partition_point(|&t| t <= v) as u8;
        let e = Srgb8Encoder::new();
        let one = 1.0f32.to_bits();
        let mut bits: Vec<u32> = (0..=one).step_by(61).collect();
        for key in (KEY_LO - 2)..=(KEY_HI + 1) {
            let b = key << 16;
            bits.extend([b - 1, b, b + 1]);
        }
        for b in bits {
            let v = f32::from_bits(b);
            assert_eq!(e.encode(v), code(v), "v = {v:e}");
            assert_eq!(e.encode(-v), 0, "v = {:e}", -v);
        }
        for v in [
            f32::NAN,
            -f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::MAX,
            1.0e-40,
        ] {
            let want = if v > 0.0 { code(v) } else { 0 };
            assert_eq!(e.encode(v), want, "v = {v:e}");
        }
    }
}
