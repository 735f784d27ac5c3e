//! BC6H: RGB half floats, 14 modes (D3D11.3 §19.5.13, the Khronos BPTC chapter).
//!
//! A block is its mode (2 or 5 bits), the endpoint bits scattered in a per-mode order
//! ([`MODES`], transcribed from the Khronos "Block descriptions for BC6H block modes"), for
//! two-subset modes a 5-bit partition (the first 32 of BC7's two-subset table), and the
//! indices (3 bits, or 4 for one subset; anchors one bit fewer). Decoding follows the
//! specification's steps, which hardware must match bit for bit: sign-extend, undo the delta
//! transform (wrapping at the endpoint precision), unquantize, interpolate with BC7's weights,
//! and `finish_unquantize` to the half float's bits. The reserved modes (19, 23, 27, 31)
//! decode to 0 in every channel (alpha, which BC6H does not store, is always 1).

use super::partitions::{ANCHOR2, PARTITION2};

/// Endpoint channel fields: endpoint `e` (0–3, D3D's w, x, y, z), channel `c` (R, G, B) is
/// field `3e + c`.
const R0: u8 = 0;
const G0: u8 = 1;
const B0: u8 = 2;
const R1: u8 = 3;
const G1: u8 = 4;
const B1: u8 = 5;
const R2: u8 = 6;
const G2: u8 = 7;
const B2: u8 = 8;
const R3: u8 = 9;
const G3: u8 = 10;
const B3: u8 = 11;

/// A run of consecutive block bits going into bits `lsb .. lsb + len` of a field, the first
/// block bit into `lsb` (or, `reversed`, into the highest of them).
#[derive(Clone, Copy, Debug)]
struct Run {
    field: u8,
    lsb: u8,
    len: u8,
    reversed: bool,
}

/// The spec's `v^(b+len−1)..b`: block bits in increasing order fill `v` from bit `lsb` up.
const fn run(field: u8, lsb: u8, len: u8) -> Run {
    Run {
        field,
        lsb,
        len,
        reversed: false,
    }
}

/// The spec's `v^lsb..(lsb+len−1)`: the first block bit goes to the highest bit.
const fn rev(field: u8, lsb: u8, len: u8) -> Run {
    Run {
        field,
        lsb,
        len,
        reversed: true,
    }
}

/// One BC6H mode.
#[derive(Debug)]
struct Mode {
    /// The mode number (the low 2 bits, or 5 bits when the low two are ≥ 2).
    number: u8,
    /// Endpoints are stored as deltas from endpoint 0.
    transformed: bool,
    /// Two subsets (a partition follows the endpoints) or one.
    two_subsets: bool,
    /// Bits of each channel of endpoint 0 (the endpoint precision).
    endpoint_bits: u8,
    /// Bits of each channel of the other endpoints (R, G, B); the endpoint precision when the
    /// mode is not transformed.
    delta_bits: [u8; 3],
    /// The endpoint bits, in block order after the mode bits.
    runs: &'static [Run],
}

#[rustfmt::skip]
const MODES: [Mode; 14] = [
    Mode { number: 0, transformed: true, two_subsets: true, endpoint_bits: 10, delta_bits: [5, 5, 5], runs: &[
        run(G2, 4, 1), run(B2, 4, 1), run(B3, 4, 1), run(R0, 0, 10), run(G0, 0, 10), run(B0, 0, 10),
        run(R1, 0, 5), run(G3, 4, 1), run(G2, 0, 4), run(G1, 0, 5), run(B3, 0, 1), run(G3, 0, 4),
        run(B1, 0, 5), run(B3, 1, 1), run(B2, 0, 4), run(R2, 0, 5), run(B3, 2, 1), run(R3, 0, 5),
        run(B3, 3, 1),
    ] },
    Mode { number: 1, transformed: true, two_subsets: true, endpoint_bits: 7, delta_bits: [6, 6, 6], runs: &[
        run(G2, 5, 1), run(G3, 4, 1), run(G3, 5, 1), run(R0, 0, 7), run(B3, 0, 1), run(B3, 1, 1),
        run(B2, 4, 1), run(G0, 0, 7), run(B2, 5, 1), run(B3, 2, 1), run(G2, 4, 1), run(B0, 0, 7),
        run(B3, 3, 1), run(B3, 5, 1), run(B3, 4, 1), run(R1, 0, 6), run(G2, 0, 4), run(G1, 0, 6),
        run(G3, 0, 4), run(B1, 0, 6), run(B2, 0, 4), run(R2, 0, 6), run(R3, 0, 6),
    ] },
    Mode { number: 2, transformed: true, two_subsets: true, endpoint_bits: 11, delta_bits: [5, 4, 4], runs: &[
        run(R0, 0, 10), run(G0, 0, 10), run(B0, 0, 10), run(R1, 0, 5), run(R0, 10, 1), run(G2, 0, 4),
        run(G1, 0, 4), run(G0, 10, 1), run(B3, 0, 1), run(G3, 0, 4), run(B1, 0, 4), run(B0, 10, 1),
        run(B3, 1, 1), run(B2, 0, 4), run(R2, 0, 5), run(B3, 2, 1), run(R3, 0, 5), run(B3, 3, 1),
    ] },
    Mode { number: 6, transformed: true, two_subsets: true, endpoint_bits: 11, delta_bits: [4, 5, 4], runs: &[
        run(R0, 0, 10), run(G0, 0, 10), run(B0, 0, 10), run(R1, 0, 4), run(R0, 10, 1), run(G3, 4, 1),
        run(G2, 0, 4), run(G1, 0, 5), run(G0, 10, 1), run(G3, 0, 4), run(B1, 0, 4), run(B0, 10, 1),
        run(B3, 1, 1), run(B2, 0, 4), run(R2, 0, 4), run(B3, 0, 1), run(B3, 2, 1), run(R3, 0, 4),
        run(G2, 4, 1), run(B3, 3, 1),
    ] },
    Mode { number: 10, transformed: true, two_subsets: true, endpoint_bits: 11, delta_bits: [4, 4, 5], runs: &[
        run(R0, 0, 10), run(G0, 0, 10), run(B0, 0, 10), run(R1, 0, 4), run(R0, 10, 1), run(B2, 4, 1),
        run(G2, 0, 4), run(G1, 0, 4), run(G0, 10, 1), run(B3, 0, 1), run(G3, 0, 4), run(B1, 0, 5),
        run(B0, 10, 1), run(B2, 0, 4), run(R2, 0, 4), run(B3, 1, 1), run(B3, 2, 1), run(R3, 0, 4),
        run(B3, 4, 1), run(B3, 3, 1),
    ] },
    Mode { number: 14, transformed: true, two_subsets: true, endpoint_bits: 9, delta_bits: [5, 5, 5], runs: &[
        run(R0, 0, 9), run(B2, 4, 1), run(G0, 0, 9), run(G2, 4, 1), run(B0, 0, 9), run(B3, 4, 1),
        run(R1, 0, 5), run(G3, 4, 1), run(G2, 0, 4), run(G1, 0, 5), run(B3, 0, 1), run(G3, 0, 4),
        run(B1, 0, 5), run(B3, 1, 1), run(B2, 0, 4), run(R2, 0, 5), run(B3, 2, 1), run(R3, 0, 5),
        run(B3, 3, 1),
    ] },
    Mode { number: 18, transformed: true, two_subsets: true, endpoint_bits: 8, delta_bits: [6, 5, 5], runs: &[
        run(R0, 0, 8), run(G3, 4, 1), run(B2, 4, 1), run(G0, 0, 8), run(B3, 2, 1), run(G2, 4, 1),
        run(B0, 0, 8), run(B3, 3, 1), run(B3, 4, 1), run(R1, 0, 6), run(G2, 0, 4), run(G1, 0, 5),
        run(B3, 0, 1), run(G3, 0, 4), run(B1, 0, 5), run(B3, 1, 1), run(B2, 0, 4), run(R2, 0, 6),
        run(R3, 0, 6),
    ] },
    Mode { number: 22, transformed: true, two_subsets: true, endpoint_bits: 8, delta_bits: [5, 6, 5], runs: &[
        run(R0, 0, 8), run(B3, 0, 1), run(B2, 4, 1), run(G0, 0, 8), run(G2, 5, 1), run(G2, 4, 1),
        run(B0, 0, 8), run(G3, 5, 1), run(B3, 4, 1), run(R1, 0, 5), run(G3, 4, 1), run(G2, 0, 4),
        run(G1, 0, 6), run(G3, 0, 4), run(B1, 0, 5), run(B3, 1, 1), run(B2, 0, 4), run(R2, 0, 5),
        run(B3, 2, 1), run(R3, 0, 5), run(B3, 3, 1),
    ] },
    Mode { number: 26, transformed: true, two_subsets: true, endpoint_bits: 8, delta_bits: [5, 5, 6], runs: &[
        run(R0, 0, 8), run(B3, 1, 1), run(B2, 4, 1), run(G0, 0, 8), run(B2, 5, 1), run(G2, 4, 1),
        run(B0, 0, 8), run(B3, 5, 1), run(B3, 4, 1), run(R1, 0, 5), run(G3, 4, 1), run(G2, 0, 4),
        run(G1, 0, 5), run(B3, 0, 1), run(G3, 0, 4), run(B1, 0, 6), run(B2, 0, 4), run(R2, 0, 5),
        run(B3, 2, 1), run(R3, 0, 5), run(B3, 3, 1),
    ] },
    Mode { number: 30, transformed: false, two_subsets: true, endpoint_bits: 6, delta_bits: [6, 6, 6], runs: &[
        run(R0, 0, 6), run(G3, 4, 1), run(B3, 0, 1), run(B3, 1, 1), run(B2, 4, 1), run(G0, 0, 6),
        run(G2, 5, 1), run(B2, 5, 1), run(B3, 2, 1), run(G2, 4, 1), run(B0, 0, 6), run(G3, 5, 1),
        run(B3, 3, 1), run(B3, 5, 1), run(B3, 4, 1), run(R1, 0, 6), run(G2, 0, 4), run(G1, 0, 6),
        run(G3, 0, 4), run(B1, 0, 6), run(B2, 0, 4), run(R2, 0, 6), run(R3, 0, 6),
    ] },
    Mode { number: 3, transformed: false, two_subsets: false, endpoint_bits: 10, delta_bits: [10, 10, 10], runs: &[
        run(R0, 0, 10), run(G0, 0, 10), run(B0, 0, 10), run(R1, 0, 10), run(G1, 0, 10), run(B1, 0, 10),
    ] },
    Mode { number: 7, transformed: true, two_subsets: false, endpoint_bits: 11, delta_bits: [9, 9, 9], runs: &[
        run(R0, 0, 10), run(G0, 0, 10), run(B0, 0, 10), run(R1, 0, 9), run(R0, 10, 1), run(G1, 0, 9),
        run(G0, 10, 1), run(B1, 0, 9), run(B0, 10, 1),
    ] },
    Mode { number: 11, transformed: true, two_subsets: false, endpoint_bits: 12, delta_bits: [8, 8, 8], runs: &[
        run(R0, 0, 10), run(G0, 0, 10), run(B0, 0, 10), run(R1, 0, 8), rev(R0, 10, 2), run(G1, 0, 8),
        rev(G0, 10, 2), run(B1, 0, 8), rev(B0, 10, 2),
    ] },
    Mode { number: 15, transformed: true, two_subsets: false, endpoint_bits: 16, delta_bits: [4, 4, 4], runs: &[
        run(R0, 0, 10), run(G0, 0, 10), run(B0, 0, 10), run(R1, 0, 4), rev(R0, 10, 6), run(G1, 0, 4),
        rev(G0, 10, 6), run(B1, 0, 4), rev(B0, 10, 6),
    ] },
];

/// The mode a block's low bits name, or `None` for the reserved modes.
fn mode_of(bits: u128) -> Option<&'static Mode> {
    let number = (if (bits & 2) == 0 { bits & 3 } else { bits & 31 }) as u8;
    MODES.iter().find(|m| m.number == number)
}

/// Bit width of a mode number field.
fn mode_bits(mode: &Mode) -> u32 {
    if mode.number < 2 {
        2
    } else {
        5
    }
}

/// `v` (a `bits`-bit two's-complement number) widened to `i32`.
fn sign_extend(v: i32, bits: u8) -> i32 {
    let shift = 32 - u32::from(bits);
    (v << shift) >> shift
}

/// The spec's `unquantize`: an endpoint of `bits` precision to the 16- (or 17-) bit range the
/// interpolation works in.
fn unquantize(comp: i32, bits: u8, signed: bool) -> i32 {
    let bits = i32::from(bits);
    if !signed {
        if bits >= 15 {
            comp
        } else if comp == 0 {
            0
        } else if comp == (1 << bits) - 1 {
            0xffff
        } else {
            ((comp << 16) + 0x8000) >> bits
        }
    } else if bits >= 16 {
        comp
    } else {
        let magnitude = comp.abs();
        let unq = if magnitude == 0 {
            0
        } else if magnitude >= (1 << (bits - 1)) - 1 {
            0x7fff
        } else {
            ((magnitude << 15) + 0x4000) >> (bits - 1)
        };
        if comp < 0 {
            -unq
        } else {
            unq
        }
    }
}

/// The spec's `finish_unquantize`: an interpolated value to the bits of a half float.
fn finish_unquantize(comp: i32, signed: bool) -> u16 {
    if !signed {
        return ((comp * 31) >> 6) as u16;
    }
    // Scale the magnitude by 31/32, then split the sign off (a result of 0 is +0).
    let scaled = if comp < 0 {
        -((-comp * 31) >> 5)
    } else {
        (comp * 31) >> 5
    };
    if scaled < 0 {
        0x8000 | (-scaled) as u16
    } else {
        scaled as u16
    }
}

/// BC6H and BC7's interpolation weights for 3- and 4-bit indices, in 64ths.
const WEIGHTS3: [i32; 8] = [0, 9, 18, 27, 37, 46, 55, 64];
const WEIGHTS4: [i32; 16] = [0, 4, 9, 13, 17, 21, 26, 30, 34, 38, 43, 47, 51, 55, 60, 64];

/// The endpoint fields as stored (before sign extension), gathered from a block's bits.
fn endpoint_fields(bits: u128, mode: &Mode) -> [i32; 12] {
    let mut e = [0i32; 12];
    let mut pos = mode_bits(mode);
    for r in mode.runs {
        let mut v = ((bits >> pos) as u32) & ((1u32 << r.len) - 1);
        if r.reversed {
            v = v.reverse_bits() >> (32 - u32::from(r.len));
        }
        e[usize::from(r.field)] |= (v as i32) << r.lsb;
        pos += u32::from(r.len);
    }
    e
}

/// Decodes a block into 16 texels' RGB half floats (their bits), row-major.
pub(super) fn decode(block: &[u8; 16], signed: bool) -> [[u16; 3]; 16] {
    let bits = u128::from_le_bytes(*block);
    let Some(mode) = mode_of(bits) else {
        return [[0; 3]; 16];
    };
    let read = |pos: u32, len: u8| ((bits >> pos) as u32 & ((1u32 << len) - 1)) as i32;
    let mut e = endpoint_fields(bits, mode);
    // The endpoints end at bit 77 (two subsets, the partition follows) or 65.
    let mut pos = if mode.two_subsets { 77 } else { 65 };
    let endpoints = if mode.two_subsets { 4 } else { 2 };

    // Sign extension, the inverse transform, unquantization.
    let prec = mode.endpoint_bits;
    for c in 0..3 {
        if signed {
            e[c] = sign_extend(e[c], prec);
        }
        for k in 1..endpoints {
            let f = 3 * k + c;
            if signed || mode.transformed {
                e[f] = sign_extend(e[f], mode.delta_bits[c]);
            }
            if mode.transformed {
                e[f] = (e[f] + e[c]) & ((1 << prec) - 1);
                if signed {
                    e[f] = sign_extend(e[f], prec);
                }
            }
        }
    }
    for v in e.iter_mut().take(3 * endpoints) {
        *v = unquantize(*v, prec, signed);
    }

    // The partition and the indices.
    let (partition, index_bits) = if mode.two_subsets {
        let p = read(pos, 5) as usize;
        pos += 5;
        (Some(p), 3u8)
    } else {
        (None, 4u8)
    };
    let mut out = [[0u16; 3]; 16];
    for (i, texel) in out.iter_mut().enumerate() {
        let (subset, anchor) = match partition {
            Some(p) => {
                let s = usize::from(PARTITION2[p][i]);
                (s, i == 0 || i == usize::from(ANCHOR2[p]))
            }
            None => (0, i == 0),
        };
        let len = index_bits - u8::from(anchor);
        let index = read(pos, len) as usize;
        pos += u32::from(len);
        let w = if mode.two_subsets {
            WEIGHTS3[index]
        } else {
            WEIGHTS4[index]
        };
        for (c, half) in texel.iter_mut().enumerate() {
            let a = e[6 * subset + c];
            let b = e[6 * subset + 3 + c];
            *half = finish_unquantize((a * (64 - w) + b * w + 32) >> 6, signed);
        }
    }
    out
}

#[cfg(test)]
#[path = "bc6h_tests.rs"]
mod tests;
