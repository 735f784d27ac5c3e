//! Property tests of the block decoders and the level decoders: no input panics, the 8-bit and
//! `f32` outputs agree as the module docs say, levels have their size and their texels are
//! the blocks' texels with the ones past the edge dropped.

use proptest::prelude::*;

use super::*;

const ALL: [BlockFormat; 10] = BlockFormat::ALL;

fn both(format: BlockFormat, block: &[u8]) -> ([[u8; 4]; 16], [[f32; 4]; 16]) {
    let mut rgba8 = [[0u8; 4]; 16];
    let mut f = [[0f32; 4]; 16];
    decode_block_rgba8(format, block, &mut rgba8);
    decode_block_f32(format, block, &mut f);
    (rgba8, f)
}

/// Blocks of a few bytes' worth of randomness, so whole levels stay cheap to make.
fn noise(len: usize, seed: u64) -> Vec<u8> {
    let mut s = seed | 1;
    (0..len)
        .map(|_| {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 32) as u8
        })
        .collect()
}

proptest! {
    #[test]
    fn any_block_decodes_without_panicking(bytes in prop::array::uniform16(any::<u8>())) {
        for format in ALL {
            let (_, f) = both(format, &bytes[..format.block_bytes()]);
            prop_assert!(f.iter().flatten().all(|v| !v.is_nan()), "{}", format.name());
        }
    }

    #[test]
    fn bc1_with_color0_above_color1_is_opaque(mut bytes in prop::array::uniform8(any::<u8>())) {
        let (c0, c1) = (u16::from_le_bytes([bytes[0], bytes[1]]), u16::from_le_bytes([bytes[2], bytes[3]]));
        if c0 < c1 {
            bytes.swap(0, 2);
            bytes.swap(1, 3);
        } else if c0 == c1 {
            bytes[0] = bytes[0].wrapping_add(1);
            if bytes[0] == 0 {
                bytes[1] = bytes[1].wrapping_add(1);
            }
            prop_assume!(u16::from_le_bytes([bytes[0], bytes[1]]) > c1);
        }
        let (rgba8, f) = both(BlockFormat::Bc1, &bytes);
        prop_assert!(rgba8.iter().all(|t| t[3] == 255));
        prop_assert!(f.iter().all(|t| t[3] == 1.0));
    }

    #[test]
    fn unorm8_formats_f32_is_the_bytes_over_255(bytes in prop::array::uniform16(any::<u8>())) {
        for format in [BlockFormat::Bc1, BlockFormat::Bc2, BlockFormat::Bc3, BlockFormat::Bc7] {
            let (rgba8, f) = both(format, &bytes[..format.block_bytes()]);
            for (b, v) in rgba8.iter().zip(&f) {
                // BC3's alpha is the interpolated channel (the next test); the rest are UNORM8.
                let channels = if format == BlockFormat::Bc3 { 3 } else { 4 };
                for c in 0..channels {
                    prop_assert_eq!(v[c], f32::from(b[c]) / 255.0, "{}", format.name());
                }
            }
        }
    }

    #[test]
    fn interpolated_channels_are_the_truncated_bytes_of_the_f32(
        bytes in prop::array::uniform16(any::<u8>())
    ) {
        for format in [BlockFormat::Bc3, BlockFormat::Bc4, BlockFormat::Bc5] {
            let (rgba8, f) = both(format, &bytes[..format.block_bytes()]);
            let channels: &[usize] = match format {
                BlockFormat::Bc3 => &[3],
                BlockFormat::Bc4 => &[0],
                _ => &[0, 1],
            };
            for (b, v) in rgba8.iter().zip(&f) {
                for &c in channels {
                    // A seventh or fifth is never within 1e-4 below an integer: the margin only
                    // absorbs the f32 division's error at exact values.
                    prop_assert_eq!(f32::from(b[c]), (v[c] * 255.0 + 1e-4).floor(), "{}", format.name());
                    prop_assert!((0.0..=1.0).contains(&v[c]));
                }
                if format != BlockFormat::Bc3 {
                    prop_assert_eq!((b[2], b[3], v[2], v[3]), (0, 255, 0.0, 1.0));
                }
                if format == BlockFormat::Bc4 {
                    prop_assert_eq!((b[1], v[1]), (0, 0.0));
                }
            }
        }
    }

    #[test]
    fn signed_channels_are_the_nearest_snorm8_of_the_f32(
        bytes in prop::array::uniform16(any::<u8>())
    ) {
        for format in [BlockFormat::Bc4Signed, BlockFormat::Bc5Signed] {
            let (rgba8, f) = both(format, &bytes[..format.block_bytes()]);
            let g = format == BlockFormat::Bc5Signed;
            for (b, v) in rgba8.iter().zip(&f) {
                for c in if g { 0..2 } else { 0..1 } {
                    prop_assert_eq!(f32::from(b[c] as i8), (v[c] * 127.0).round());
                    prop_assert!((-1.0..=1.0).contains(&v[c]));
                    prop_assert!(b[c] != 0x80, "−128 never comes out");
                }
                prop_assert_eq!((b[2], b[3], v[2], v[3]), (0, 127, 0.0, 1.0));
            }
        }
    }

    #[test]
    fn bc6h_bytes_are_the_clamped_floats(bytes in prop::array::uniform16(any::<u8>())) {
        for format in [BlockFormat::Bc6hUnsigned, BlockFormat::Bc6hSigned] {
            let (rgba8, f) = both(format, &bytes);
            for (b, v) in rgba8.iter().zip(&f) {
                for c in 0..3 {
                    prop_assert_eq!(f32::from(b[c]), (v[c].clamp(0.0, 1.0) * 255.0).round());
                }
                prop_assert_eq!((b[3], v[3]), (255, 1.0));
                if format == BlockFormat::Bc6hUnsigned {
                    // Unsigned halves are never negative, nor above 65504.
                    prop_assert!(v[..3].iter().all(|x| (0.0..=65504.0).contains(x)));
                }
            }
        }
    }

    #[test]
    fn a_level_is_its_blocks_with_the_edges_dropped(
        width in 1u32..19,
        height in 1u32..19,
        seed in any::<u64>(),
        which in 0usize..10,
    ) {
        let format = ALL[which];
        let data = noise(format.level_bytes(width, height) as usize, seed);
        let rgba8 = decode_level_rgba8(format, &data, width, height).unwrap();
        let f = decode_level_f32(format, &data, width, height).unwrap();
        prop_assert_eq!(rgba8.len(), (width * height * 4) as usize);
        prop_assert_eq!(f.len(), rgba8.len());
        let blocks_x = width.div_ceil(4) as usize;
        let bb = format.block_bytes();
        for y in 0..height as usize {
            for x in 0..width as usize {
                let b = (y / 4) * blocks_x + x / 4;
                let (texels, ftexels) = both(format, &data[b * bb..(b + 1) * bb]);
                let t = (y % 4) * 4 + x % 4;
                let at = (y * width as usize + x) * 4;
                prop_assert_eq!(&rgba8[at..at + 4], &texels[t][..]);
                prop_assert_eq!(&f[at..at + 4], &ftexels[t][..]);
            }
        }
    }
}

#[test]
fn levels_of_the_usual_odd_shapes_have_their_size() {
    for (w, h) in [(1, 1), (3, 5), (747, 600), (373, 300), (2, 1), (0, 7)] {
        for format in [
            BlockFormat::Bc1,
            BlockFormat::Bc3,
            BlockFormat::Bc6hSigned,
            BlockFormat::Bc7,
        ] {
            let data = noise(format.level_bytes(w, h) as usize, u64::from(w * 31 + h));
            let rgba8 = decode_level_rgba8(format, &data, w, h).unwrap();
            assert_eq!(
                rgba8.len(),
                (w * h * 4) as usize,
                "{} {w}x{h}",
                format.name()
            );
            let f = decode_level_f32(format, &data, w, h).unwrap();
            assert_eq!(f.len(), (w * h * 4) as usize);
        }
    }
    assert_eq!(BlockFormat::Bc1.level_bytes(747, 600), 187 * 150 * 8);
    assert_eq!(BlockFormat::Bc7.level_bytes(1, 1), 16);
}

#[test]
fn a_wrong_length_is_refused_naming_the_format_and_sizes() {
    let err = decode_level_rgba8(BlockFormat::Bc1, &[0; 7], 4, 4)
        .unwrap_err()
        .to_string();
    assert_eq!(err, "BC1 level 4x4 needs 8 bytes, got 7");
    let err = decode_level_f32(BlockFormat::Bc7, &[0; 32], 4, 4)
        .unwrap_err()
        .to_string();
    assert_eq!(err, "BC7 level 4x4 needs 16 bytes, got 32");
}

#[test]
fn huge_sizes_are_refused_before_any_allocation() {
    // Decoding these would need exabytes: the length check refuses them first.
    for format in ALL {
        assert!(decode_level_rgba8(format, &[], u32::MAX, u32::MAX).is_err());
        assert!(decode_level_f32(format, &[0; 16], u32::MAX, 1 << 20).is_err());
    }
    assert_eq!(BlockFormat::Bc7.level_bytes(u32::MAX, u32::MAX), u64::MAX);
}

#[test]
fn block_formats_route_their_channels() {
    // BC4: (R, 0, 0, 1); BC5: (R, G, 0, 1); both halves are channel blocks.
    let red = [200u8, 10, 0, 0, 0, 0, 0, 0]; // code 0 everywhere: 200
    let green = [5u8, 99, 0b0100_1001, 0x92, 0x24, 0x49, 0x92, 0x24]; // code 1: 99
    let (b4, f4) = both(BlockFormat::Bc4, &red);
    assert!(b4.iter().all(|t| *t == [200, 0, 0, 255]));
    assert!(f4.iter().all(|t| *t == [200.0 / 255.0, 0.0, 0.0, 1.0]));
    let bc5 = [red, green].concat();
    let (b5, _) = both(BlockFormat::Bc5, &bc5);
    assert!(b5.iter().all(|t| *t == [200, 99, 0, 255]));
    let (s5, fs5) = both(BlockFormat::Bc5Signed, &bc5);
    // 200 is −56 and 99 is 99 as signed bytes.
    assert!(s5.iter().all(|t| *t == [200, 99, 0, 127]));
    assert!(fs5
        .iter()
        .all(|t| *t == [-56.0 / 127.0, 99.0 / 127.0, 0.0, 1.0]));
    // BC2: explicit alpha over a four-colour block; BC3: interpolated alpha.
    let mut bc2 = [0u8; 16];
    bc2[0] = 0x0f; // texel 0: 15 → 255, texel 1: 0
    bc2[8..10].copy_from_slice(&0xffffu16.to_le_bytes());
    let (t, _) = both(BlockFormat::Bc2, &bc2);
    assert_eq!((t[0], t[1]), ([255, 255, 255, 255], [255, 255, 255, 0]));
    let mut bc3 = bc2;
    bc3[..8].copy_from_slice(&red);
    let (t, f) = both(BlockFormat::Bc3, &bc3);
    assert!(t.iter().all(|t| *t == [255, 255, 255, 200]));
    assert_eq!(f[0], [1.0, 1.0, 1.0, 200.0 / 255.0]);
}

#[test]
fn bc6h_values_reach_both_outputs() {
    // Mode 3 (10-bit endpoints), red 1023 → 65504 at weight 0, green 512, blue 0, indices 0.
    let fields: u128 = 3 | (1023 << 5) | (512 << 15);
    let block = fields.to_le_bytes();
    let (b, f) = both(BlockFormat::Bc6hUnsigned, &block);
    assert_eq!(f[0], [65504.0, f16_to_f32(0x3e0f), 0.0, 1.0]);
    assert_eq!(b[0], [255, 255, 0, 255]);
    assert!(f.iter().all(|t| *t == f[0]));
}
