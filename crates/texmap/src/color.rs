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

/// Encodes a linear value to an 8-bit sRGB code (round to nearest).
#[must_use]
pub fn linear_to_srgb8(c: f32) -> u8 {
    (linear_to_srgb(c) * 255.0 + 0.5) as u8
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
    fn srgb_known_values() {
        assert!((srgb_to_linear(0.5) - 0.214_041).abs() < 1e-5);
        assert_eq!(srgb_to_linear(0.0), 0.0);
        assert!((srgb_to_linear(1.0) - 1.0).abs() < 1e-6);
    }
}
