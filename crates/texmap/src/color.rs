//! Colour: sRGB transfer functions and the lookup tables texel decoding uses.
//!
//! All shading and filtering happen in linear light with `f32` components; sRGB is decoded
//! when a texel is read and encoded once, when an image is written.

use std::sync::OnceLock;

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

/// Encodes a linear value to an 8-bit sRGB code (round to nearest in the encoded space).
///
/// A binary search over the 255 linear values where the code changes (eight comparisons), in
/// place of a `powf` per channel — which took a fifth of the instructions of loading a 1024²
/// texture, in building its mip chain.
#[must_use]
pub fn linear_to_srgb8(c: f32) -> u8 {
    static THRESHOLDS: OnceLock<[f32; 255]> = OnceLock::new();
    let t = THRESHOLDS
        .get_or_init(|| std::array::from_fn(|k| srgb_to_linear((k as f32 + 0.5) / 255.0)));
    if c.is_nan() {
        return 0;
    }
    t.partition_point(|&x| x <= c) as u8
}

/// Encodes a linear value to an 8-bit code without a transfer function (round to nearest).
#[must_use]
pub fn linear_to_unorm8(c: f32) -> u8 {
    (c.clamp(0.0, 1.0) * 255.0 + 0.5) as u8
}

fn table<const N: usize>(srgb: bool) -> Box<[f32]> {
    let max = (N - 1) as f32;
    (0..N)
        .map(|i| {
            let c = i as f32 / max;
            if srgb {
                srgb_to_linear(c)
            } else {
                c
            }
        })
        .collect()
}

/// Decoding table for 8-bit codes: `lut8(true)[code]` is the linear value of an sRGB code.
pub fn lut8(srgb: bool) -> &'static [f32] {
    static LIN: OnceLock<Box<[f32]>> = OnceLock::new();
    static SRGB: OnceLock<Box<[f32]>> = OnceLock::new();
    if srgb {
        SRGB.get_or_init(|| table::<256>(true))
    } else {
        LIN.get_or_init(|| table::<256>(false))
    }
}

/// Decoding table for 16-bit codes, as [`lut8`].
pub fn lut16(srgb: bool) -> &'static [f32] {
    static LIN: OnceLock<Box<[f32]>> = OnceLock::new();
    static SRGB: OnceLock<Box<[f32]>> = OnceLock::new();
    if srgb {
        SRGB.get_or_init(|| table::<65536>(true))
    } else {
        LIN.get_or_init(|| table::<65536>(false))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_round_trips_every_8bit_code() {
        for i in 0..=255u8 {
            let lin = lut8(true)[i as usize];
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
}
