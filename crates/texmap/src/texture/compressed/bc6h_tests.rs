//! BC6H against the specification: the bit layout of every mode against the Khronos table of
//! bit interpretations, and hand-made blocks of every mode whose half-float outputs were worked
//! out with the specification's arithmetic (sign extension, transform, unquantize,
//! interpolation, finish_unquantize).

use super::*;

/// Fields as the Khronos tables name them ("R0" … "B3").
fn field(name: &str) -> u8 {
    let c = b"RGB"
        .iter()
        .position(|&x| x == name.as_bytes()[0])
        .unwrap() as u8;
    let e = name.as_bytes()[1] - b'0';
    3 * e + c
}

/// What the Khronos "Interpretation of lower/upper bits for BC6H block modes" tables put at
/// `bit` for most modes; `None` where every mode has its own entry.
fn usual(bit: u32, two_subsets: bool) -> Option<(&'static str, u32)> {
    Some(match bit {
        5..=14 => ("R0", bit - 5),
        15..=24 => ("G0", bit - 15),
        25..=34 => ("B0", bit - 25),
        35..=39 => ("R1", bit - 35),
        45..=49 => ("G1", bit - 45),
        55..=59 => ("B1", bit - 55),
        _ if !two_subsets => match bit {
            40..=44 => ("R1", bit - 35),
            50..=54 => ("G1", bit - 45),
            60..=64 => ("B1", bit - 55),
            _ => return None,
        },
        41..=44 => ("G2", bit - 41),
        51..=54 => ("G3", bit - 51),
        61..=64 => ("B2", bit - 61),
        65..=69 => ("R2", bit - 65),
        71..=75 => ("R3", bit - 71),
        _ => return None,
    })
}

/// A block bit and the field bit it holds.
type Entry = (u32, &'static str, u32);

/// Each mode's departures from [`usual`], transcribed from the same tables.
#[rustfmt::skip]
const DEPARTURES: [(u8, &[Entry]); 14] = [
    (0, &[(2, "G2", 4), (3, "B2", 4), (4, "B3", 4), (40, "G3", 4), (50, "B3", 0), (60, "B3", 1),
          (70, "B3", 2), (76, "B3", 3)]),
    (1, &[(2, "G2", 5), (3, "G3", 4), (4, "G3", 5), (12, "B3", 0), (13, "B3", 1), (14, "B2", 4),
          (22, "B2", 5), (23, "B3", 2), (24, "G2", 4), (32, "B3", 3), (33, "B3", 5), (34, "B3", 4),
          (40, "R1", 5), (50, "G1", 5), (60, "B1", 5), (70, "R2", 5), (76, "R3", 5)]),
    (2, &[(40, "R0", 10), (49, "G0", 10), (50, "B3", 0), (59, "B0", 10), (60, "B3", 1),
          (70, "B3", 2), (76, "B3", 3)]),
    (6, &[(39, "R0", 10), (40, "G3", 4), (50, "G0", 10), (59, "B0", 10), (60, "B3", 1),
          (69, "B3", 0), (70, "B3", 2), (75, "G2", 4), (76, "B3", 3)]),
    (10, &[(39, "R0", 10), (40, "B2", 4), (49, "G0", 10), (50, "B3", 0), (60, "B0", 10),
           (69, "B3", 1), (70, "B3", 2), (75, "B3", 4), (76, "B3", 3)]),
    (14, &[(14, "B2", 4), (24, "G2", 4), (34, "B3", 4), (40, "G3", 4), (50, "B3", 0),
           (60, "B3", 1), (70, "B3", 2), (76, "B3", 3)]),
    (18, &[(13, "G3", 4), (14, "B2", 4), (23, "B3", 2), (24, "G2", 4), (33, "B3", 3),
           (34, "B3", 4), (40, "R1", 5), (50, "B3", 0), (60, "B3", 1), (70, "R2", 5), (76, "R3", 5)]),
    (22, &[(13, "B3", 0), (14, "B2", 4), (23, "G2", 5), (24, "G2", 4), (33, "G3", 5),
           (34, "B3", 4), (40, "G3", 4), (50, "G1", 5), (60, "B3", 1), (70, "B3", 2), (76, "B3", 3)]),
    (26, &[(13, "B3", 1), (14, "B2", 4), (23, "B2", 5), (24, "G2", 4), (33, "B3", 5),
           (34, "B3", 4), (40, "G3", 4), (50, "B3", 0), (60, "B1", 5), (70, "B3", 2), (76, "B3", 3)]),
    (30, &[(11, "G3", 4), (12, "B3", 0), (13, "B3", 1), (14, "B2", 4), (21, "G2", 5),
           (22, "B2", 5), (23, "B3", 2), (24, "G2", 4), (31, "G3", 5), (32, "B3", 3), (33, "B3", 5),
           (34, "B3", 4), (40, "R1", 5), (50, "G1", 5), (60, "B1", 5), (70, "R2", 5), (76, "R3", 5)]),
    (3, &[]),
    (7, &[(44, "R0", 10), (54, "G0", 10), (64, "B0", 10)]),
    (11, &[(43, "R0", 11), (44, "R0", 10), (53, "G0", 11), (54, "G0", 10), (63, "B0", 11),
           (64, "B0", 10)]),
    (15, &[(39, "R0", 15), (40, "R0", 14), (41, "R0", 13), (42, "R0", 12), (43, "R0", 11),
           (44, "R0", 10), (49, "G0", 15), (50, "G0", 14), (51, "G0", 13), (52, "G0", 12),
           (53, "G0", 11), (54, "G0", 10), (59, "B0", 15), (60, "B0", 14), (61, "B0", 13),
           (62, "B0", 12), (63, "B0", 11), (64, "B0", 10)]),
];

#[test]
fn every_endpoint_bit_is_where_the_khronos_table_puts_it() {
    for (number, departures) in DEPARTURES {
        let mode = MODES.iter().find(|m| m.number == number).unwrap();
        let end = if mode.two_subsets { 77 } else { 65 };
        for bit in mode_bits(mode)..end {
            let want = departures
                .iter()
                .find(|d| d.0 == bit)
                .map(|d| (d.1, d.2))
                .or_else(|| usual(bit, mode.two_subsets))
                .unwrap_or_else(|| panic!("mode {number}: no table entry for bit {bit}"));
            let got = endpoint_fields(u128::from(number) | (1u128 << bit), mode);
            let mut expect = [0i32; 12];
            expect[usize::from(field(want.0))] = 1 << want.1;
            assert_eq!(
                got, expect,
                "mode {number}, bit {bit}: want {}^{}",
                want.0, want.1
            );
        }
    }
}

#[test]
fn runs_fill_each_field_once_to_the_mode_precisions() {
    for mode in &MODES {
        let mut seen = [0u32; 12];
        for r in mode.runs {
            let bits = ((1u32 << r.len) - 1) << r.lsb;
            assert_eq!(seen[usize::from(r.field)] & bits, 0, "mode {}", mode.number);
            seen[usize::from(r.field)] |= bits;
        }
        let endpoints = if mode.two_subsets { 4 } else { 2 };
        for (f, s) in seen.iter().enumerate() {
            let (e, c) = (f / 3, f % 3);
            let want = match e {
                0 => mode.endpoint_bits,
                _ if e < endpoints => mode.delta_bits[c],
                _ => 0,
            };
            assert_eq!(*s, (1u32 << want) - 1, "mode {}, field {f}", mode.number);
        }
        let total: u32 = mode.runs.iter().map(|r| u32::from(r.len)).sum();
        let end = if mode.two_subsets { 77 } else { 65 };
        assert_eq!(mode_bits(mode) + total, end, "mode {}", mode.number);
        if !mode.transformed {
            assert_eq!(mode.delta_bits, [mode.endpoint_bits; 3]);
        }
    }
}

/// Appends bits to a block, least significant first.
#[derive(Default)]
struct Writer {
    bits: u128,
    pos: u32,
}

impl Writer {
    fn put(&mut self, v: u32, len: u32) {
        assert!(len == 32 || v >> len == 0, "{v} does not fit {len} bits");
        self.bits |= u128::from(v) << self.pos;
        self.pos += len;
    }
}

/// A hand-made block: stored endpoint fields, partition, indices and the expected halves.
struct Case {
    what: &'static str,
    mode: u8,
    signed: bool,
    fields: [u32; 12],
    partition: usize,
    indices: [u32; 16],
    halves: [[u16; 3]; 16],
}

fn encode(c: &Case) -> [u8; 16] {
    let mode = MODES.iter().find(|m| m.number == c.mode).unwrap();
    let mut w = Writer::default();
    w.put(u32::from(c.mode), mode_bits(mode));
    for r in mode.runs {
        let mut v = (c.fields[usize::from(r.field)] >> r.lsb) & ((1 << r.len) - 1);
        if r.reversed {
            v = v.reverse_bits() >> (32 - u32::from(r.len));
        }
        w.put(v, u32::from(r.len));
    }
    let index_bits = if mode.two_subsets {
        w.put(c.partition as u32, 5);
        3
    } else {
        4
    };
    for (i, &index) in c.indices.iter().enumerate() {
        let anchor = i == 0 || (mode.two_subsets && i == usize::from(ANCHOR2[c.partition]));
        w.put(index, index_bits - u32::from(anchor));
    }
    assert_eq!(w.pos, 128);
    w.bits.to_le_bytes()
}

/// Expected values computed with the specification's arithmetic, step by step (§19.5.13.6–10).
/// For instance, in the first case blue endpoint 512 of 10 bits unquantizes to
/// ((512 << 16) + 0x8000) >> 10 = 32800, and finish_unquantize gives 32800·31 >> 6 = 0x3e0f;
/// red 1023 is the top value, 0xffff, which finishes as 0x7bff (65504); in the signed mode-15
/// case red −1 at weight 64 interpolates to (−64 + 32) >> 6 = −1, which scales to +0.
#[rustfmt::skip]
const CASES: &[Case] = &[
    Case {
        what: "mode 3: 10-bit endpoints, the ends saturate, a ramp of indices",
        mode: 3,
        signed: false,
        fields: [0, 1023, 512, 1023, 0, 511, 0, 0, 0, 0, 0, 0],
        partition: 0,
        indices: [0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15],
        halves: [
            [0x0000, 0x7bff, 0x3e0f], [0x07c0, 0x743f, 0x3e0d], [0x1170, 0x6a8f, 0x3e0b], [0x1930, 0x62cf, 0x3e09],
            [0x20f0, 0x5b0f, 0x3e07], [0x28b0, 0x534f, 0x3e05], [0x3260, 0x499f, 0x3e02], [0x3a20, 0x41df, 0x3e00],
            [0x41df, 0x3a20, 0x3dff], [0x499f, 0x3260, 0x3dfd], [0x534f, 0x28b0, 0x3dfa], [0x5b0f, 0x20f0, 0x3df8],
            [0x62cf, 0x1930, 0x3df6], [0x6a8f, 0x1170, 0x3df4], [0x743f, 0x07c0, 0x3df2], [0x7bff, 0x0000, 0x3df0],
        ],
    },
    Case {
        what: "mode 7: negative deltas and a wrap past 2047",
        mode: 7,
        signed: false,
        fields: [1000, 2047, 5, 256, 255, 506, 0, 0, 0, 0, 0, 0],
        partition: 0,
        indices: [7, 3, 0, 2, 1, 2, 3, 11, 7, 0, 0, 0, 11, 15, 14, 4],
        halves: [
            [0x354f, 0x4918, 0x3a4d], [0x396d, 0x65f0, 0x1973], [0x3c93, 0x7bff, 0x0055], [0x3a65, 0x6cba, 0x11b9],
            [0x3b9b, 0x7536, 0x080f], [0x3a65, 0x6cba, 0x11b9], [0x396d, 0x65f0, 0x1973], [0x3131, 0x2c40, 0x5b26],
            [0x354f, 0x4918, 0x3a4d], [0x3c93, 0x7bff, 0x0055], [0x3c93, 0x7bff, 0x0055], [0x3c93, 0x7bff, 0x0055],
            [0x3131, 0x2c40, 0x5b26], [0x2d13, 0x0f68, 0x7bff], [0x2e0b, 0x1632, 0x7444], [0x3875, 0x5f27, 0x212e],
        ],
    },
    Case {
        what: "mode 11: the reversed high bits of 12-bit endpoints",
        mode: 11,
        signed: false,
        fields: [3413, 2051, 1024, 127, 128, 1, 0, 0, 0, 0, 0, 0],
        partition: 0,
        indices: [1, 5, 3, 0, 15, 7, 2, 14, 2, 2, 1, 8, 2, 9, 15, 11],
        halves: [
            [0x6794, 0x3ddd, 0x1f04], [0x6899, 0x3cd5, 0x1f06], [0x681e, 0x3d51, 0x1f05], [0x6756, 0x3e1b, 0x1f03],
            [0x6b2e, 0x3a3b, 0x1f0b], [0x6924, 0x3c4a, 0x1f07], [0x67e1, 0x3d8f, 0x1f04], [0x6af1, 0x3a79, 0x1f0b],
            [0x67e1, 0x3d8f, 0x1f04], [0x67e1, 0x3d8f, 0x1f04], [0x6794, 0x3ddd, 0x1f04], [0x6961, 0x3c0c, 0x1f08],
            [0x67e1, 0x3d8f, 0x1f04], [0x699f, 0x3bce, 0x1f08], [0x6b2e, 0x3a3b, 0x1f0b], [0x6a29, 0x3b42, 0x1f09],
        ],
    },
    Case {
        what: "mode 15: 16-bit endpoints pass through",
        mode: 15,
        signed: false,
        fields: [43981, 31743, 1, 7, 8, 15, 0, 0, 0, 0, 0, 0],
        partition: 0,
        indices: [0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15],
        halves: [
            [0x5337, 0x3c0f, 0x0000], [0x5337, 0x3c0f, 0x0000], [0x5337, 0x3c0f, 0x0000], [0x5337, 0x3c0e, 0x0000],
            [0x5338, 0x3c0e, 0x0000], [0x5338, 0x3c0e, 0x0000], [0x5338, 0x3c0e, 0x0000], [0x5338, 0x3c0d, 0x0000],
            [0x5339, 0x3c0d, 0x0000], [0x5339, 0x3c0d, 0x0000], [0x5339, 0x3c0d, 0x0000], [0x5339, 0x3c0c, 0x0000],
            [0x533a, 0x3c0c, 0x0000], [0x533a, 0x3c0c, 0x0000], [0x533a, 0x3c0c, 0x0000], [0x533a, 0x3c0b, 0x0000],
        ],
    },
    Case {
        what: "mode 0: partition 13",
        mode: 0,
        signed: false,
        fields: [545, 510, 409, 29, 1, 4, 0, 21, 9, 30, 24, 10],
        partition: 13,
        indices: [0, 1, 7, 2, 1, 3, 2, 0, 5, 1, 2, 4, 7, 0, 6, 2],
        halves: [
            [0x420e, 0x3dd1, 0x3196], [0x4201, 0x3dd5, 0x31a7], [0x41b1, 0x3df0, 0x3212], [0x41f4, 0x3dda, 0x31b9],
            [0x4201, 0x3dd5, 0x31a7], [0x41e7, 0x3dde, 0x31ca], [0x41f4, 0x3dda, 0x31b9], [0x420e, 0x3dd1, 0x3196],
            [0x41e1, 0x3cbf, 0x32c3], [0x4205, 0x3c89, 0x32b1], [0x41fd, 0x3c96, 0x32b6], [0x41ea, 0x3cb2, 0x32bf],
            [0x41d0, 0x3cd9, 0x32cc], [0x420e, 0x3c7c, 0x32ad], [0x41d9, 0x3ccc, 0x32c8], [0x41fd, 0x3c96, 0x32b6],
        ],
    },
    Case {
        what: "mode 1: partition 17",
        mode: 1,
        signed: false,
        fields: [10, 45, 69, 19, 38, 19, 59, 5, 49, 44, 63, 43],
        partition: 17,
        indices: [3, 7, 0, 7, 2, 7, 7, 4, 4, 1, 2, 6, 6, 1, 1, 7],
        halves: [
            [0x11ef, 0x2173, 0x4b17], [0x72cc, 0x2b1c, 0x2efc], [0x0554, 0x30ec, 0x34cc], [0x72cc, 0x2b1c, 0x2efc],
            [0x0f59, 0x24fe, 0x4881], [0x1c94, 0x12e4, 0x55bc], [0x1c94, 0x12e4, 0x55bc], [0x449d, 0x2d8f, 0x316f],
            [0x14d0, 0x1d84, 0x4df8], [0x0cc2, 0x2889, 0x45ea], [0x0f59, 0x24fe, 0x4881], [0x19fd, 0x166e, 0x5325],
            [0x19fd, 0x166e, 0x5325], [0x0cc2, 0x2889, 0x45ea], [0x0cc2, 0x2889, 0x45ea], [0x1c94, 0x12e4, 0x55bc],
        ],
    },
    Case {
        what: "mode 2: partition 18",
        mode: 2,
        signed: false,
        fields: [1543, 1046, 784, 22, 3, 5, 17, 4, 10, 28, 2, 2],
        partition: 18,
        indices: [3, 3, 0, 4, 0, 3, 1, 5, 2, 7, 1, 4, 1, 6, 3, 1],
        halves: [
            [0x5d32, 0x3f70, 0x2fa0], [0x5d32, 0x3f70, 0x2fa0], [0x5d74, 0x3f5c, 0x2f7f], [0x5d1a, 0x3f77, 0x2fac],
            [0x5d74, 0x3f5c, 0x2f7f], [0x5d32, 0x3f70, 0x2fa0], [0x5d5e, 0x3f63, 0x2f8a], [0x5d04, 0x3f7e, 0x2fb7],
            [0x5cbb, 0x3f92, 0x2f45], [0x5cd9, 0x3f8b, 0x2fcd], [0x5d5e, 0x3f63, 0x2f8a], [0x5d1a, 0x3f77, 0x2fac],
            [0x5ca3, 0x3f96, 0x2f34], [0x5d1e, 0x3f80, 0x2f8d], [0x5cd3, 0x3f8d, 0x2f57], [0x5d5e, 0x3f63, 0x2f8a],
        ],
    },
    Case {
        what: "mode 6: partition 0",
        mode: 6,
        signed: false,
        fields: [1624, 797, 1882, 7, 23, 6, 13, 11, 6, 9, 3, 11],
        partition: 0,
        indices: [1, 7, 7, 5, 2, 2, 0, 2, 2, 1, 5, 2, 0, 0, 1, 1],
        halves: [
            [0x626b, 0x3035, 0x7207], [0x62c8, 0x2fbd, 0x7257], [0x61ef, 0x3077, 0x71ad], [0x6200, 0x309a, 0x71dd],
            [0x627a, 0x3022, 0x7214], [0x627a, 0x3022, 0x7214], [0x622d, 0x30f3, 0x7257], [0x621b, 0x30d0, 0x7227],
            [0x627a, 0x3022, 0x7214], [0x626b, 0x3035, 0x7207], [0x6200, 0x309a, 0x71dd], [0x621b, 0x30d0, 0x7227],
            [0x625b, 0x3049, 0x71fa], [0x625b, 0x3049, 0x71fa], [0x6224, 0x30e2, 0x7240], [0x6224, 0x30e2, 0x7240],
        ],
    },
    Case {
        what: "mode 10: partition 31",
        mode: 10,
        signed: false,
        fields: [888, 163, 1772, 12, 10, 13, 12, 8, 19, 13, 10, 9],
        partition: 31,
        indices: [0, 4, 2, 6, 6, 4, 1, 6, 4, 3, 4, 6, 0, 5, 7, 3],
        halves: [
            [0x35cb, 0x09e6, 0x6b51], [0x35a7, 0x09b0, 0x6bc6], [0x3592, 0x0972, 0x6ae8], [0x359b, 0x0984, 0x6bad],
            [0x359b, 0x0984, 0x6bad], [0x35a7, 0x09b0, 0x6bc6], [0x35c3, 0x09d9, 0x6b6e], [0x359b, 0x0984, 0x6bad],
            [0x3596, 0x097c, 0x6b4d], [0x35b1, 0x09bf, 0x6ba7], [0x35a7, 0x09b0, 0x6bc6], [0x359b, 0x0984, 0x6bad],
            [0x358d, 0x096a, 0x6a88], [0x3598, 0x0980, 0x6b7d], [0x358d, 0x0989, 0x6c1b], [0x35b1, 0x09bf, 0x6ba7],
        ],
    },
    Case {
        what: "mode 14: partition 20",
        mode: 14,
        signed: false,
        fields: [502, 169, 389, 19, 0, 4, 30, 25, 19, 27, 30, 11],
        partition: 20,
        indices: [3, 7, 1, 4, 5, 5, 3, 2, 7, 7, 0, 7, 1, 0, 5, 7],
        halves: [
            [0x785e, 0x290d, 0x5ebd], [0x768d, 0x290d, 0x5f4d], [0x791c, 0x2786, 0x5c00], [0x78cb, 0x280e, 0x5e8b],
            [0x776f, 0x290d, 0x5f07], [0x776f, 0x290d, 0x5f07], [0x785e, 0x290d, 0x5ebd], [0x7902, 0x27b2, 0x5cd1],
            [0x768d, 0x290d, 0x5f4d], [0x768d, 0x290d, 0x5f4d], [0x79b3, 0x290d, 0x5e55], [0x768d, 0x290d, 0x5f4d],
            [0x7941, 0x290d, 0x5e77], [0x79b3, 0x290d, 0x5e55], [0x776f, 0x290d, 0x5f07], [0x768d, 0x290d, 0x5f4d],
        ],
    },
    Case {
        what: "mode 18: partition 24",
        mode: 18,
        signed: false,
        fields: [33, 71, 169, 44, 18, 19, 42, 18, 12, 35, 4, 13],
        partition: 24,
        indices: [2, 5, 2, 7, 4, 1, 1, 3, 4, 5, 2, 0, 6, 0, 0, 3],
        halves: [
            [0x0d80, 0x20b9, 0x5054], [0x0943, 0x1dc2, 0x4d93], [0x049d, 0x1e4d, 0x580c], [0x022e, 0x2492, 0x5866],
            [0x0aa0, 0x1eb6, 0x4e76], [0x0edd, 0x21ad, 0x5137], [0x0edd, 0x21ad, 0x5137], [0x0423, 0x1f87, 0x581e],
            [0x0aa0, 0x1eb6, 0x4e76], [0x0943, 0x1dc2, 0x4d93], [0x0d80, 0x20b9, 0x5054], [0x0592, 0x1bda, 0x57ea],
            [0x07e6, 0x1cce, 0x4cb0], [0x103a, 0x22a2, 0x521a], [0x103a, 0x22a2, 0x521a], [0x0c23, 0x1fc5, 0x4f71],
        ],
    },
    Case {
        what: "mode 22: partition 9",
        mode: 22,
        signed: false,
        fields: [79, 160, 181, 27, 8, 19, 16, 62, 14, 22, 10, 1],
        partition: 9,
        indices: [2, 3, 2, 7, 7, 2, 1, 2, 3, 2, 6, 5, 2, 7, 0, 2],
        halves: [
            [0x25d3, 0x4ed5, 0x5624], [0x257c, 0x4f60, 0x5541], [0x1f93, 0x4e68, 0x5cec], [0x21aa, 0x5296, 0x5866],
            [0x2416, 0x519e, 0x519e], [0x1f93, 0x4e68, 0x5cec], [0x1f2a, 0x4d97, 0x5dcf], [0x1f93, 0x4e68, 0x5cec],
            [0x1ffb, 0x4f39, 0x5c09], [0x1f93, 0x4e68, 0x5cec], [0x2141, 0x51c4, 0x5948], [0x20d8, 0x50f3, 0x5a2b],
            [0x1f93, 0x4e68, 0x5cec], [0x21aa, 0x5296, 0x5866], [0x1ec2, 0x4cc6, 0x5eb2], [0x1f93, 0x4e68, 0x5cec],
        ],
    },
    Case {
        what: "mode 26: partition 30",
        mode: 26,
        signed: false,
        fields: [35, 188, 209, 2, 4, 40, 14, 12, 44, 24, 31, 6],
        partition: 30,
        indices: [0, 7, 0, 4, 6, 5, 2, 7, 3, 0, 5, 5, 6, 2, 1, 0],
        halves: [
            [0x1132, 0x5b4e, 0x657a], [0x0d52, 0x5ad2, 0x6862], [0x17fa, 0x611e, 0x5bca], [0x11d0, 0x5d7a, 0x6311],
            [0x1207, 0x5cf8, 0x5b7c], [0x11e4, 0x5cb2, 0x5d1f], [0x1177, 0x5bd9, 0x6235], [0x0d52, 0x5ad2, 0x6862],
            [0x137b, 0x5e75, 0x611a], [0x1132, 0x5b4e, 0x657a], [0x11e4, 0x5cb2, 0x5d1f], [0x11e4, 0x5cb2, 0x5d1f],
            [0x0ed1, 0x5bb4, 0x669c], [0x14fa, 0x5f58, 0x5f54], [0x167a, 0x603b, 0x5d8f], [0x1132, 0x5b4e, 0x657a],
        ],
    },
    Case {
        what: "mode 30: partition 5",
        mode: 30,
        signed: false,
        fields: [27, 25, 18, 16, 32, 6, 59, 46, 47, 36, 50, 52],
        partition: 5,
        indices: [2, 3, 4, 0, 5, 4, 1, 0, 3, 5, 2, 5, 4, 5, 4, 1],
        halves: [
            [0x2f49, 0x3538, 0x1d4e], [0x2c4a, 0x3720, 0x1a09], [0x5984, 0x5e93, 0x61a1], [0x7348, 0x5a18, 0x5c08],
            [0x25f6, 0x3b27, 0x1322], [0x5984, 0x5e93, 0x61a1], [0x6d03, 0x5b2f, 0x5d64], [0x7348, 0x5a18, 0x5c08],
            [0x2c4a, 0x3720, 0x1a09], [0x5340, 0x5faa, 0x62fe], [0x66bf, 0x5c46, 0x5ec1], [0x5340, 0x5faa, 0x62fe],
            [0x5984, 0x5e93, 0x61a1], [0x5340, 0x5faa, 0x62fe], [0x5984, 0x5e93, 0x61a1], [0x6d03, 0x5b2f, 0x5d64],
        ],
    },
    Case {
        what: "signed mode 3: negative endpoints, and 511 and -511 saturate",
        mode: 3,
        signed: true,
        fields: [512, 511, 513, 1023, 0, 100, 0, 0, 0, 0, 0, 0],
        partition: 0,
        indices: [0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15],
        halves: [
            [0xfbff, 0x7bff, 0xfbff], [0xf444, 0x743f, 0xf2b9], [0xea9c, 0x6a8f, 0xe723], [0xe2e2, 0x62cf, 0xdddd],
            [0xdb28, 0x5b0f, 0xd498], [0xd36e, 0x534f, 0xcb52], [0xc9c4, 0x499f, 0xbfbb], [0xc20a, 0x41df, 0xb676],
            [0xba51, 0x3a20, 0xad31], [0xb297, 0x3260, 0xa3ec], [0xa8ee, 0x28b0, 0x9855], [0xa133, 0x20f0, 0x8f0f],
            [0x9979, 0x1930, 0x85ca], [0x91bf, 0x1170, 0x037b], [0x8817, 0x07c0, 0x0f11], [0x805d, 0x0000, 0x1857],
        ],
    },
    Case {
        what: "signed mode 15: -32768 is -inf, and -1 scales to +0",
        mode: 15,
        signed: true,
        fields: [0, 32768, 32767, 15, 0, 15, 0, 0, 0, 0, 0, 0],
        partition: 0,
        indices: [0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15],
        halves: [
            [0x0000, 0xfc00, 0x7bff], [0x0000, 0xfc00, 0x7bff], [0x0000, 0xfc00, 0x7bff], [0x0000, 0xfc00, 0x7bff],
            [0x0000, 0xfc00, 0x7bff], [0x0000, 0xfc00, 0x7bff], [0x0000, 0xfc00, 0x7bff], [0x0000, 0xfc00, 0x7bff],
            [0x0000, 0xfc00, 0x7bfe], [0x0000, 0xfc00, 0x7bfe], [0x0000, 0xfc00, 0x7bfe], [0x0000, 0xfc00, 0x7bfe],
            [0x0000, 0xfc00, 0x7bfe], [0x0000, 0xfc00, 0x7bfe], [0x0000, 0xfc00, 0x7bfe], [0x0000, 0xfc00, 0x7bfe],
        ],
    },
    Case {
        what: "signed mode 11: deltas from a negative base",
        mode: 11,
        signed: true,
        fields: [2048, 4095, 1000, 127, 128, 156, 0, 0, 0, 0, 0, 0],
        partition: 0,
        indices: [7, 5, 0, 13, 7, 6, 14, 8, 5, 11, 13, 15, 15, 15, 14, 11],
        halves: [
            [0xf868, 0x83b9, 0x39bd], [0xf97b, 0x82a2, 0x3a97], [0xfbff, 0x8017, 0x3c93], [0xf56a, 0x86c0, 0x375f],
            [0xf868, 0x83b9, 0x39bd], [0xf8e2, 0x833d, 0x3a1e], [0xf4d1, 0x875b, 0x36e6], [0xf7ed, 0x8435, 0x395c],
            [0xf97b, 0x82a2, 0x3a97], [0xf65f, 0x85c8, 0x3821], [0xf56a, 0x86c0, 0x375f], [0xf457, 0x87d7, 0x3685],
            [0xf457, 0x87d7, 0x3685], [0xf457, 0x87d7, 0x3685], [0xf4d1, 0x875b, 0x36e6], [0xf65f, 0x85c8, 0x3821],
        ],
    },
    Case {
        what: "signed mode 1: 7-bit base, 6-bit deltas",
        mode: 1,
        signed: true,
        fields: [26, 102, 32, 13, 60, 62, 12, 16, 32, 30, 9, 42],
        partition: 3,
        indices: [3, 4, 5, 6, 3, 7, 7, 5, 7, 1, 7, 1, 1, 3, 2, 2],
        halves: [
            [0x3df8, 0xb69d, 0x3d55], [0x41e7, 0xb7d3, 0x3cba], [0x4572, 0xb8ea, 0x3c2f], [0x6890, 0x9fff, 0x117b],
            [0x3df8, 0xb69d, 0x3d55], [0x4c88, 0xbb18, 0x3b18], [0x6d78, 0xa1e8, 0x1458], [0x63a9, 0x9e17, 0x0e9f],
            [0x4c88, 0xbb18, 0x3b18], [0x36e2, 0xb46f, 0x3e6c], [0x6d78, 0xa1e8, 0x1458], [0x4f7f, 0x9640, 0x02dc],
            [0x36e2, 0xb46f, 0x3e6c], [0x594e, 0x9a10, 0x0895], [0x5467, 0x9828, 0x05b8], [0x5467, 0x9828, 0x05b8],
        ],
    },
    Case {
        what: "signed mode 30: untransformed 6-bit endpoints, all sign-extended",
        mode: 30,
        signed: true,
        fields: [32, 31, 63, 5, 44, 17, 33, 0, 30, 1, 62, 3],
        partition: 11,
        indices: [1, 6, 4, 3, 4, 0, 2, 5, 1, 0, 0, 4, 6, 5, 5, 2],
        halves: [
            [0xe78f, 0x5f63, 0x048a], [0x00e0, 0xb2d4, 0x3975], [0xa7fd, 0x0663, 0x24c0], [0xbeb1, 0x262b, 0x193f],
            [0xa7fd, 0x0663, 0x24c0], [0xfbff, 0x7bff, 0x85d0], [0xd320, 0x42c7, 0x0ee5], [0x938e, 0x9638, 0x2f1b],
            [0xe78f, 0x5f63, 0x048a], [0xfbff, 0x7bff, 0x85d0], [0xfbff, 0x7bff, 0x85d0], [0xb0f3, 0x8599, 0x39b3],
            [0x00e0, 0xb2d4, 0x3975], [0x9eb2, 0x86f6, 0x2afd], [0x9eb2, 0x86f6, 0x2afd], [0xd77c, 0x82b9, 0x58c3],
        ],
    },
    Case {
        what: "signed mode 0",
        mode: 0,
        signed: true,
        fields: [888, 340, 769, 25, 0, 18, 18, 20, 15, 9, 12, 28],
        partition: 26,
        indices: [3, 6, 2, 4, 6, 6, 4, 7, 5, 3, 4, 2, 2, 6, 2, 0],
        halves: [
            [0xa1c6, 0x5277, 0xbf4f], [0x9fa9, 0x548d, 0xbe33], [0xa2e1, 0x5131, 0xbb8a], [0xa209, 0x5277, 0xbfd6],
            [0xa283, 0x5277, 0xc0ca], [0x9fa9, 0x548d, 0xbe33], [0xa13a, 0x52eb, 0xbce8], [0xa2c1, 0x5277, 0xc145],
            [0xa246, 0x5277, 0xc050], [0xa219, 0x5202, 0xbc2f], [0xa13a, 0x52eb, 0xbce8], [0xa189, 0x5277, 0xbed5],
            [0xa189, 0x5277, 0xbed5], [0x9fa9, 0x548d, 0xbe33], [0xa2e1, 0x5131, 0xbb8a], [0xa10f, 0x5277, 0xbde1],
        ],
    },
];

#[test]
fn hand_made_blocks_of_every_mode_decode_as_the_specification_says() {
    let mut modes_seen = std::collections::BTreeSet::new();
    for c in CASES {
        let block = encode(c);
        let got = decode(&block, c.signed);
        assert_eq!(got, c.halves, "{}", c.what);
        modes_seen.insert(c.mode);
    }
    assert_eq!(modes_seen.len(), 14, "a case for each of the 14 modes");
}

#[test]
fn reserved_modes_decode_to_zero() {
    for number in [19u8, 23, 27, 31] {
        let mut block = [0xa5u8; 16];
        block[0] = (block[0] & !31) | number;
        assert!(mode_of(u128::from_le_bytes(block)).is_none());
        assert_eq!(decode(&block, false), [[0; 3]; 16]);
        assert_eq!(decode(&block, true), [[0; 3]; 16]);
    }
}

#[test]
fn two_bit_modes_ignore_the_bits_above_them() {
    // Low bits 00 and 01 are modes 0 and 1 whatever bits 2–4 hold (they are endpoint bits).
    for low in 0..32u128 {
        let m = mode_of(low).map(|m| m.number);
        match low & 3 {
            0 => assert_eq!(m, Some(0)),
            1 => assert_eq!(m, Some(1)),
            _ if [19, 23, 27, 31].contains(&low) => assert_eq!(m, None),
            _ => assert_eq!(m, Some(low as u8)),
        }
    }
}
