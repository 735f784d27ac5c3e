//! BC7: RGBA, 8 modes (D3D11.3 §19.5.14, the Khronos BPTC chapter), decoded bit-exactly as
//! the specification requires of hardware.
//!
//! A block is its mode (a run of zeros ended by a one, from bit 0), then in this order the
//! partition, rotation and index-selection fields, the colour endpoints (all red, then green,
//! then blue, each subset's two endpoints in turn), the alpha endpoints, the P-bits (one per
//! endpoint, or one per subset shared by both), the primary indices and the secondary ones.
//! Endpoints are widened to 8 bits by replicating their top bits, the palette is
//! `((64 − w)·e0 + w·e1 + 32) >> 6` with the 2-, 3- or 4-bit weight tables, and modes 4 and 5
//! then swap alpha with one colour channel. A block whose low byte is 0 (no mode) decodes to
//! 0 in every channel.

use super::partitions::{ANCHOR2, ANCHOR3, PARTITION2, PARTITION3};

/// One BC7 mode's field widths (the Khronos "Mode-dependent BPTC parameters").
struct Mode {
    subsets: usize,
    partition_bits: u32,
    rotation_bits: u32,
    index_selection_bits: u32,
    colour_bits: u32,
    alpha_bits: u32,
    /// One P-bit per endpoint.
    endpoint_pbits: bool,
    /// One P-bit per subset, shared by its two endpoints.
    shared_pbits: bool,
    index_bits: u32,
    /// Bits of the secondary indices (modes 4 and 5), 0 if none.
    index2_bits: u32,
}

#[rustfmt::skip]
const MODES: [Mode; 8] = [
    Mode { subsets: 3, partition_bits: 4, rotation_bits: 0, index_selection_bits: 0, colour_bits: 4, alpha_bits: 0, endpoint_pbits: true, shared_pbits: false, index_bits: 3, index2_bits: 0 },
    Mode { subsets: 2, partition_bits: 6, rotation_bits: 0, index_selection_bits: 0, colour_bits: 6, alpha_bits: 0, endpoint_pbits: false, shared_pbits: true, index_bits: 3, index2_bits: 0 },
    Mode { subsets: 3, partition_bits: 6, rotation_bits: 0, index_selection_bits: 0, colour_bits: 5, alpha_bits: 0, endpoint_pbits: false, shared_pbits: false, index_bits: 2, index2_bits: 0 },
    Mode { subsets: 2, partition_bits: 6, rotation_bits: 0, index_selection_bits: 0, colour_bits: 7, alpha_bits: 0, endpoint_pbits: true, shared_pbits: false, index_bits: 2, index2_bits: 0 },
    Mode { subsets: 1, partition_bits: 0, rotation_bits: 2, index_selection_bits: 1, colour_bits: 5, alpha_bits: 6, endpoint_pbits: false, shared_pbits: false, index_bits: 2, index2_bits: 3 },
    Mode { subsets: 1, partition_bits: 0, rotation_bits: 2, index_selection_bits: 0, colour_bits: 7, alpha_bits: 8, endpoint_pbits: false, shared_pbits: false, index_bits: 2, index2_bits: 2 },
    Mode { subsets: 1, partition_bits: 0, rotation_bits: 0, index_selection_bits: 0, colour_bits: 7, alpha_bits: 7, endpoint_pbits: true, shared_pbits: false, index_bits: 4, index2_bits: 0 },
    Mode { subsets: 2, partition_bits: 6, rotation_bits: 0, index_selection_bits: 0, colour_bits: 5, alpha_bits: 5, endpoint_pbits: true, shared_pbits: false, index_bits: 2, index2_bits: 0 },
];

/// The interpolation weights in 64ths, by index width (2, 3, 4 bits).
const WEIGHTS2: [u16; 4] = [0, 21, 43, 64];
const WEIGHTS3: [u16; 8] = [0, 9, 18, 27, 37, 46, 55, 64];
const WEIGHTS4: [u16; 16] = [0, 4, 9, 13, 17, 21, 26, 30, 34, 38, 43, 47, 51, 55, 60, 64];

fn weights(bits: u32) -> &'static [u16] {
    match bits {
        2 => &WEIGHTS2,
        3 => &WEIGHTS3,
        _ => &WEIGHTS4,
    }
}

/// Reads consecutive fields from a block, least significant bit first.
struct Reader {
    bits: u128,
    pos: u32,
}

impl Reader {
    fn read(&mut self, len: u32) -> u32 {
        if len == 0 {
            return 0;
        }
        let v = (self.bits >> self.pos) as u32 & ((1u32 << len) - 1);
        self.pos += len;
        v
    }
}

/// A `bits`-bit endpoint channel widened to 8 bits by replicating its top bits.
fn widen(v: u32, bits: u32) -> u16 {
    let v = v << (8 - bits);
    (v | (v >> bits)) as u16
}

/// The subset of texel `i` and whether it is its subset's anchor.
fn subset_and_anchor(subsets: usize, partition: usize, i: usize) -> (usize, bool) {
    match subsets {
        2 => {
            let s = usize::from(PARTITION2[partition][i]);
            (s, i == 0 || i == usize::from(ANCHOR2[partition]))
        }
        3 => {
            let s = usize::from(PARTITION3[partition][i]);
            let anchor = match s {
                0 => i == 0,
                s => i == usize::from(ANCHOR3[s - 1][partition]),
            };
            (s, anchor)
        }
        _ => (0, i == 0),
    }
}

/// Decodes a block into 16 RGBA8 texels, row-major.
pub(super) fn decode(block: &[u8; 16], out: &mut [[u8; 4]; 16]) {
    if block[0] == 0 {
        *out = [[0; 4]; 16];
        return;
    }
    let number = block[0].trailing_zeros();
    let mode = &MODES[number as usize];
    let mut r = Reader {
        bits: u128::from_le_bytes(*block),
        pos: number + 1,
    };
    let partition = r.read(mode.partition_bits) as usize;
    let rotation = r.read(mode.rotation_bits);
    let index_selection = r.read(mode.index_selection_bits);

    // Endpoints: [subset·2 + end][channel], raw, then P-bits, then widened.
    let n = 2 * mode.subsets;
    let mut ep = [[0u32; 4]; 6];
    for c in 0..3 {
        for e in ep.iter_mut().take(n) {
            e[c] = r.read(mode.colour_bits);
        }
    }
    for e in ep.iter_mut().take(n) {
        e[3] = if mode.alpha_bits > 0 {
            r.read(mode.alpha_bits)
        } else {
            0
        };
    }
    let pbit = mode.endpoint_pbits || mode.shared_pbits;
    if mode.endpoint_pbits {
        for e in ep.iter_mut().take(n) {
            let p = r.read(1);
            *e = e.map(|v| (v << 1) | p);
        }
    } else if mode.shared_pbits {
        for pair in ep.chunks_mut(2).take(mode.subsets) {
            let p = r.read(1);
            for e in pair {
                *e = e.map(|v| (v << 1) | p);
            }
        }
    }
    let colour_prec = mode.colour_bits + u32::from(pbit);
    let alpha_prec = mode.alpha_bits + u32::from(pbit);
    let mut wide = [[0u16; 4]; 6];
    for (w, e) in wide.iter_mut().zip(&ep).take(n) {
        for c in 0..3 {
            w[c] = widen(e[c], colour_prec);
        }
        w[3] = if mode.alpha_bits > 0 {
            widen(e[3], alpha_prec)
        } else {
            255
        };
    }

    // Indices: the primary set after the endpoints, the secondary after it.
    let primary_start = r.pos;
    let secondary_start = primary_start + 16 * mode.index_bits - mode.subsets as u32;
    let (mut p1, mut p2) = (primary_start, secondary_start);
    let (w1, w2) = (weights(mode.index_bits), weights(mode.index2_bits));
    for (i, texel) in out.iter_mut().enumerate() {
        let (s, anchor) = subset_and_anchor(mode.subsets, partition, i);
        let len = mode.index_bits - u32::from(anchor);
        r.pos = p1;
        let primary = w1[r.read(len) as usize];
        p1 += len;
        let (colour_w, alpha_w) = if mode.index2_bits > 0 {
            let len2 = mode.index2_bits - u32::from(anchor);
            r.pos = p2;
            let secondary = w2[r.read(len2) as usize];
            p2 += len2;
            if index_selection == 0 {
                (primary, secondary)
            } else {
                (secondary, primary)
            }
        } else {
            (primary, primary)
        };
        let (a, b) = (&wide[2 * s], &wide[2 * s + 1]);
        let lerp = |c: usize, w: u16| (((64 - w) * a[c] + w * b[c] + 32) >> 6) as u8;
        let mut t = [
            lerp(0, colour_w),
            lerp(1, colour_w),
            lerp(2, colour_w),
            lerp(3, alpha_w),
        ];
        match rotation {
            1 => t.swap(0, 3),
            2 => t.swap(1, 3),
            3 => t.swap(2, 3),
            _ => {}
        }
        *texel = t;
    }
}

#[cfg(test)]
#[path = "bc7_tests.rs"]
mod tests;
