//! BC7 against the specification: a hand-made block of every mode (expected texels from the
//! Khronos decoding rules, and the same as the reference decoder gives), every partition of the
//! 2- and 3-subset modes with their anchors, and the reserved mode.

use super::*;

/// Blocks of every mode, with rotations and both index selections, and their texels.
/// E.g. in the mode 6 block texel 5 has index 5 (weight 21) between endpoints
/// (255, 1, 129, 255) and (0, 254, 128, 0): red ((64 − 21)·255 + 32) >> 6 = 171,
/// green (43·1 + 21·254 + 32) >> 6 = 84, blue (43·129 + 21·128 + 32) >> 6 = 129.
/// What a case shows, its block and its texels.
type Case = (&'static str, [u8; 16], [[u8; 4]; 16]);

#[rustfmt::skip]
const CASES: &[Case] = &[
    (
        "mode 0: three subsets, 4-bit colour and a P-bit per endpoint, partition 7",
        [0xef, 0x61, 0x38, 0x10, 0x3e, 0x4d, 0xe8, 0x90, 0x87, 0xa4, 0xb4, 0xdb, 0xc2, 0x27, 0x10, 0x57],
        [
            [183, 75, 126, 255], [72, 180, 129, 255], [116, 132, 140, 255], [116, 132, 140, 255],
            [147, 109, 127, 255], [219, 42, 124, 255], [139, 123, 115, 255], [198, 99, 49, 255],
            [33, 39, 62, 255], [51, 45, 59, 255], [57, 156, 206, 255], [139, 123, 115, 255],
            [16, 33, 66, 255], [140, 74, 41, 255], [97, 140, 162, 255], [77, 148, 184, 255],
        ],
    ),
    (
        "mode 1: two subsets, 6-bit colour and shared P-bits, partition 35",
        [0x8e, 0x3f, 0xa0, 0xa0, 0xc0, 0x4f, 0xc9, 0xe0, 0xe7, 0xf1, 0xad, 0x36, 0xe1, 0xdb, 0x92, 0x3d],
        [
            [148, 109, 129, 255], [184, 73, 130, 255], [127, 167, 207, 255], [127, 167, 207, 255],
            [219, 38, 130, 255], [219, 38, 130, 255], [110, 150, 190, 255], [161, 201, 241, 255],
            [57, 97, 137, 255], [91, 131, 171, 255], [148, 109, 129, 255], [219, 38, 130, 255],
            [57, 97, 137, 255], [91, 131, 171, 255], [2, 255, 126, 255], [219, 38, 130, 255],
        ],
    ),
    (
        "mode 2: three subsets, 5-bit colour, no P-bits, partition 63",
        [0xfc, 0x3f, 0x00, 0x1f, 0x12, 0xf0, 0xc1, 0x47, 0x08, 0x80, 0x0f, 0x08, 0x94, 0x18, 0x8e, 0x5c],
        [
            [255, 0, 0, 255], [84, 84, 171, 255], [171, 171, 84, 255], [0, 0, 255, 255],
            [132, 66, 33, 255], [0, 255, 0, 255], [0, 0, 255, 255], [0, 0, 255, 255],
            [100, 66, 65, 255], [33, 66, 132, 255], [255, 0, 0, 255], [171, 171, 84, 255],
            [132, 66, 33, 255], [33, 66, 132, 255], [100, 66, 65, 255], [171, 84, 0, 255],
        ],
    ),
    (
        "mode 3: two subsets, 7-bit colour and a P-bit per endpoint, partition 17",
        [0x18, 0xfd, 0x01, 0xe4, 0x4c, 0xc0, 0x2f, 0x93, 0x01, 0x7f, 0x19, 0x72, 0xde, 0xc0, 0x38, 0xce],
        [
            [171, 85, 128, 255], [51, 101, 201, 255], [200, 100, 50, 255], [51, 101, 201, 255],
            [255, 3, 129, 255], [255, 3, 129, 255], [255, 3, 129, 255], [51, 101, 201, 255],
            [255, 3, 129, 255], [84, 170, 127, 255], [0, 252, 126, 255], [255, 3, 129, 255],
            [84, 170, 127, 255], [0, 252, 126, 255], [255, 3, 129, 255], [0, 252, 126, 255],
        ],
    ),
    (
        "mode 4: separate 6-bit alpha, 3-bit colour indices (selector 1), rotation 2",
        [0xd0, 0x1f, 0x28, 0x0a, 0xfe, 0x0f, 0x48, 0xd8, 0xe1, 0x20, 0x8e, 0x1f, 0x8d, 0x8b, 0x24, 0x60],
        [
            [147, 255, 108, 117], [219, 171, 36, 94], [36, 84, 219, 153], [0, 255, 255, 165],
            [219, 255, 36, 94], [183, 0, 72, 105], [147, 84, 108, 117], [108, 0, 147, 130],
            [147, 255, 108, 117], [219, 255, 36, 94], [183, 0, 72, 105], [183, 171, 72, 105],
            [183, 255, 72, 105], [255, 255, 0, 82], [255, 171, 0, 82], [147, 255, 108, 117],
        ],
    ),
    (
        "mode 4: 2-bit colour indices (selector 0), no rotation",
        [0x10, 0xc1, 0x8b, 0x3e, 0x78, 0xc1, 0x7f, 0x79, 0xf5, 0x18, 0x10, 0x92, 0xc5, 0x8a, 0xf9, 0x7b],
        [
            [86, 89, 92, 20], [247, 239, 231, 83], [247, 239, 231, 20], [169, 166, 163, 51],
            [8, 16, 24, 51], [247, 239, 231, 114], [247, 239, 231, 51], [169, 166, 163, 212],
            [169, 166, 163, 83], [169, 166, 163, 51], [247, 239, 231, 212], [86, 89, 92, 149],
            [8, 16, 24, 243], [247, 239, 231, 243], [8, 16, 24, 212], [8, 16, 24, 114],
        ],
    ),
    (
        "mode 5: 7-bit colour, 8-bit alpha, rotation 1",
        [0x60, 0x7f, 0x00, 0x10, 0x08, 0xf8, 0xff, 0x47, 0x54, 0x34, 0xfd, 0x5d, 0x52, 0x12, 0x90, 0xc9],
        [
            [177, 129, 84, 171], [255, 129, 171, 84], [177, 129, 171, 84], [177, 129, 0, 255],
            [95, 129, 171, 84], [255, 129, 171, 84], [177, 129, 84, 171], [255, 129, 171, 84],
            [255, 129, 171, 84], [255, 129, 255, 0], [177, 129, 255, 0], [95, 129, 255, 0],
            [177, 129, 171, 84], [95, 129, 255, 0], [255, 129, 171, 84], [17, 129, 0, 255],
        ],
    ),
    (
        "mode 5: rotation 3",
        [0xe0, 0x05, 0x2d, 0x79, 0x80, 0xe7, 0x01, 0x20, 0x13, 0x87, 0x7b, 0x06, 0x86, 0x06, 0x4c, 0xa7],
        [
            [10, 201, 66, 241], [125, 70, 66, 160], [10, 201, 0, 241], [125, 70, 134, 160],
            [181, 6, 134, 120], [10, 201, 66, 241], [10, 201, 0, 241], [181, 6, 0, 120],
            [66, 137, 0, 201], [181, 6, 200, 120], [181, 6, 0, 120], [10, 201, 66, 241],
            [181, 6, 200, 120], [10, 201, 66, 241], [10, 201, 134, 241], [10, 201, 134, 241],
        ],
    ),
    (
        "mode 6: one subset, RGBA 7-bit with P-bits, 4-bit indices",
        [0xc0, 0x3f, 0x00, 0xf0, 0x07, 0x02, 0xff, 0x80, 0x10, 0x32, 0x54, 0x76, 0x98, 0xba, 0xdc, 0xfe],
        [
            [255, 1, 129, 255], [239, 17, 129, 239], [219, 37, 129, 219], [203, 52, 129, 203],
            [187, 68, 129, 187], [171, 84, 129, 171], [151, 104, 129, 151], [135, 120, 129, 135],
            [120, 135, 128, 120], [104, 151, 128, 104], [84, 171, 128, 84], [68, 187, 128, 68],
            [52, 203, 128, 52], [36, 218, 128, 36], [16, 238, 128, 16], [0, 254, 128, 0],
        ],
    ),
    (
        "mode 7: two subsets, RGBA 5-bit with P-bits, partition 0",
        [0x80, 0xc0, 0x07, 0x87, 0x83, 0xef, 0xc6, 0x83, 0x35, 0x7d, 0xa0, 0xa8, 0xad, 0xbf, 0x49, 0xbd],
        [
            [170, 84, 125, 170], [170, 84, 125, 170], [115, 86, 141, 110], [227, 24, 73, 162],
            [4, 255, 134, 4], [4, 255, 134, 4], [115, 86, 141, 110], [227, 24, 73, 162],
            [251, 0, 121, 251], [170, 84, 125, 170], [172, 55, 106, 137], [172, 55, 106, 137],
            [85, 171, 130, 85], [4, 255, 134, 4], [115, 86, 141, 110], [115, 86, 141, 110],
        ],
    ),
];

#[test]
fn a_block_of_every_mode_decodes_as_the_specification_says() {
    let mut modes = [false; 8];
    for (what, block, want) in CASES {
        let mut got = [[0; 4]; 16];
        decode(block, &mut got);
        assert_eq!(&got, want, "{what}");
        modes[block[0].trailing_zeros() as usize] = true;
    }
    assert_eq!(modes, [true; 8]);
}

#[test]
fn a_block_without_a_mode_decodes_to_zero() {
    let mut block = [0xffu8; 16];
    block[0] = 0;
    let mut got = [[7; 4]; 16];
    decode(&block, &mut got);
    assert_eq!(got, [[0; 4]; 16]);
}

#[test]
fn endpoints_widen_by_replicating_their_top_bits() {
    assert_eq!(widen(0b10101, 5), 0b1010_1101);
    assert_eq!(widen(0b11_1111, 6), 255);
    assert_eq!(widen(0b100_0000, 7), 0b1000_0001);
    assert_eq!(widen(0x5a, 8), 0x5a);
}

#[test]
fn anchors_belong_to_their_subsets() {
    for p in 0..64 {
        assert_eq!(PARTITION2[p][0], 0);
        assert_eq!(PARTITION2[p][usize::from(ANCHOR2[p])], 1);
        assert_eq!(PARTITION3[p][0], 0);
        assert_eq!(PARTITION3[p][usize::from(ANCHOR3[0][p])], 1);
        assert_eq!(PARTITION3[p][usize::from(ANCHOR3[1][p])], 2);
    }
}

/// The fields of a block, before packing.
struct Fields {
    mode: usize,
    partition: u32,
    colour: [[u32; 3]; 6],
    pbits: [u32; 6],
    indices: [u32; 16],
}

/// The specification's field order: mode, partition, colour (R of every endpoint, then G, then
/// B), P-bits, indices (anchors one bit fewer). Only the colour-only modes and mode 7 (whose
/// alpha is left at 0).
fn pack(f: &Fields) -> [u8; 16] {
    let m = &MODES[f.mode];
    let mut bits = 0u128;
    let mut pos = 0;
    let mut put = |v: u32, len: u32| {
        assert!(v >> len == 0);
        bits |= u128::from(v) << pos;
        pos += len;
    };
    put(1 << f.mode, f.mode as u32 + 1);
    put(f.partition, m.partition_bits);
    let n = 2 * m.subsets;
    for c in 0..3 {
        for e in &f.colour[..n] {
            put(e[c], m.colour_bits);
        }
    }
    for _ in 0..n {
        put(0, m.alpha_bits);
    }
    let pbits = if m.endpoint_pbits {
        n
    } else if m.shared_pbits {
        m.subsets
    } else {
        0
    };
    for &p in &f.pbits[..pbits] {
        put(p, 1);
    }
    for (i, &index) in f.indices.iter().enumerate() {
        let (_, anchor) = subset_and_anchor(m.subsets, f.partition as usize, i);
        put(index, m.index_bits - u32::from(anchor));
    }
    assert_eq!(pos, 128);
    bits.to_le_bytes()
}

#[test]
fn every_partition_of_the_subset_modes_and_its_anchors() {
    for mode in [0usize, 1, 2, 3, 7] {
        let m = &MODES[mode];
        for partition in 0..1u32 << m.partition_bits {
            // Red runs 0 → max in every subset, so it shows the index; blue tells the subset.
            let top = (1 << m.colour_bits) - 1;
            let mut colour = [[0u32; 3]; 6];
            for s in 0..m.subsets {
                let blue = (s as u32 + 1) * top / 4;
                colour[2 * s] = [0, top / 2, blue];
                colour[2 * s + 1] = [top, top / 2, blue];
            }
            let pbits = [0, 1, 0, 1, 0, 1];
            // Indices that differ texel to texel; anchors get one bit fewer.
            let indices: [u32; 16] = std::array::from_fn(|i| {
                let (_, anchor) = subset_and_anchor(m.subsets, partition as usize, i);
                let range = 1 << (m.index_bits - u32::from(anchor));
                (i as u32 * 5 + partition) % range
            });
            let f = Fields {
                mode,
                partition,
                colour,
                pbits,
                indices,
            };
            let mut got = [[0; 4]; 16];
            decode(&pack(&f), &mut got);

            // The expected texels, straight from the rules.
            let shared = m.shared_pbits;
            let prec = m.colour_bits + u32::from(m.endpoint_pbits || shared);
            let end = |e: usize| -> [u16; 3] {
                let p = if shared { pbits[e / 2] } else { pbits[e] };
                let v = |c: usize| {
                    if m.endpoint_pbits || shared {
                        (colour[e][c] << 1) | p
                    } else {
                        colour[e][c]
                    }
                };
                [widen(v(0), prec), widen(v(1), prec), widen(v(2), prec)]
            };
            for i in 0..16 {
                let s = match m.subsets {
                    2 => usize::from(PARTITION2[partition as usize][i]),
                    _ => usize::from(PARTITION3[partition as usize][i]),
                };
                let w = weights(m.index_bits)[indices[i] as usize];
                let (a, b) = (end(2 * s), end(2 * s + 1));
                let want: [u8; 3] =
                    std::array::from_fn(|c| (((64 - w) * a[c] + w * b[c] + 32) >> 6) as u8);
                assert_eq!(
                    got[i][..3],
                    want,
                    "mode {mode}, partition {partition}, texel {i}"
                );
                // Mode 7's alpha endpoints are 0 with their P-bits: 0 or 4 after widening.
                let alpha = if mode == 7 {
                    let (pa, pb) = (widen(pbits[2 * s], 6), widen(pbits[2 * s + 1], 6));
                    (((64 - w) * pa + w * pb + 32) >> 6) as u8
                } else {
                    255
                };
                assert_eq!(got[i][3], alpha);
            }
        }
    }
}
