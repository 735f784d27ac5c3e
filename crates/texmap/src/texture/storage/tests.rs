use super::*;

#[test]
fn linear16_storage_holds_the_native_texels_within_its_precision() {
    let (w, h) = (13u32, 7u32);
    let rgba: Vec<u8> = (0..w * h * 4).map(|i| (i * 7 % 251) as u8).collect();
    let make = |storage, format: Format, bytes: &[u8]| {
        let options = TextureOptions::default().with_storage(storage);
        Texture2D::from_texels(w, h, format, ColorSpace::Srgb, bytes, options).unwrap()
    };
    let rgb: Vec<u8> = rgba
        .chunks_exact(4)
        .flat_map(|c| [c[0], c[1], c[2]])
        .collect();
    for (format, bytes) in [(Format::Rgba8, &rgba), (Format::Rgb8, &rgb)] {
        let native = make(Storage::Native, format, bytes);
        let fast = make(Storage::Linear16, format, bytes);
        assert_eq!(native.storage_format(), format);
        assert_eq!(fast.storage_format(), Format::Rgba16Premultiplied);
        assert_eq!(
            (fast.format(), fast.color_space()),
            (format, ColorSpace::Srgb)
        );
        let texels = native.texel_bytes() / format.bytes_per_texel();
        assert_eq!(fast.texel_bytes(), texels * 8);
        // Level 0 holds the same values to 16-bit precision; the mip levels differ by the
        // native format's 8-bit sRGB rounding of each level.
        let (a, b) = (native.decode_level(0), fast.decode_level(0));
        let err = a
            .iter()
            .zip(&b)
            .map(|(x, y)| (*x - *y).abs().max_element())
            .fold(0.0, f32::max);
        assert!(err < 1e-5, "{format:?} level 0: {err}");
        for l in 1..native.levels().len() {
            let (a, b) = (native.decode_level(l), fast.decode_level(l));
            let err = a
                .iter()
                .zip(&b)
                .map(|(x, y)| (*x - *y).abs().max_element())
                .fold(0.0, f32::max);
            assert!(err < 0.02, "{format:?} level {l}: {err}");
        }
    }
}

#[test]
fn tiled_and_row_major_hold_the_same_texels() {
    let (w, h) = (13u32, 7u32);
    let rgba: Vec<u8> = (0..w * h * 4).map(|i| (i * 7 % 251) as u8).collect();
    let opts = |layout| TextureOptions::default().with_layout(layout);
    let a = Texture2D::from_texels(
        w,
        h,
        Format::Rgba8,
        ColorSpace::Srgb,
        &rgba,
        opts(Layout::Tiled4x4),
    )
    .unwrap();
    let b = Texture2D::from_texels(
        w,
        h,
        Format::Rgba8,
        ColorSpace::Srgb,
        &rgba,
        opts(Layout::RowMajor),
    )
    .unwrap();
    assert_eq!(a.levels().len(), b.levels().len());
    for l in 0..a.levels().len() {
        assert_eq!(a.decode_level(l), b.decode_level(l), "level {l}");
    }
}

#[test]
fn wrong_byte_count_is_an_error() {
    let r = Texture2D::from_rgba8(4, 4, ColorSpace::Srgb, &[0; 10]);
    assert!(r.is_err());
    assert!(Texture2D::from_rgba8(0, 4, ColorSpace::Srgb, &[]).is_err());
}

/// Every level's bytes of a texture built from `bytes` in a pool of `threads` threads.
fn level_bytes(
    threads: usize,
    format: Format,
    storage: Storage,
    layout: Layout,
    (w, h): (u32, u32),
    bytes: &[u8],
) -> Vec<Vec<u8>> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    let options = TextureOptions::default()
        .with_storage(storage)
        .with_layout(layout);
    let tex = pool
        .install(|| Texture2D::from_texels(w, h, format, ColorSpace::Srgb, bytes, options))
        .unwrap();
    tex.levels().iter().map(|l| l.data.clone()).collect()
}

#[test]
fn levels_are_the_same_bytes_whatever_the_thread_count() {
    // Odd sides (three-tap boxes), partial tiles, alpha: every path of the parallel build.
    let (w, h) = (67u32, 45u32);
    let rgba: Vec<u8> = (0..w * h * 4).map(|i| (i * 37 % 253) as u8).collect();
    for storage in [Storage::Linear16, Storage::Native, Storage::Rgba8] {
        for layout in [Layout::Tiled4x4, Layout::RowMajor] {
            let one = level_bytes(1, Format::Rgba8, storage, layout, (w, h), &rgba);
            let three = level_bytes(3, Format::Rgba8, storage, layout, (w, h), &rgba);
            assert_eq!(one.len(), mip::level_count(w, h));
            assert!(one == three, "{storage:?} {layout:?}");
        }
    }
}

#[test]
fn opaque_rgb8_table_gives_the_float_conversion_bytes() {
    // RGB8 goes to 16-bit linear through a 256-entry table, RGBA8 through the float decode
    // and encode: with alpha 255 everywhere both must store the same bytes, chain included.
    let (w, h) = (32u32, 19u32);
    let rgb: Vec<u8> = (0..w * h * 3).map(|i| (i * 11 % 256) as u8).collect();
    let rgba: Vec<u8> = rgb
        .chunks_exact(3)
        .flat_map(|c| [c[0], c[1], c[2], 255])
        .collect();
    let size = (w, h);
    let (storage, layout) = (Storage::Linear16, Layout::Tiled4x4);
    let a = level_bytes(2, Format::Rgb8, storage, layout, size, &rgb);
    let b = level_bytes(2, Format::Rgba8, storage, layout, size, &rgba);
    assert!(a == b);
}

#[test]
fn rgba8_storage_keeps_the_codes_and_builds_its_chain_in_linear_light() {
    // Odd sides (three-tap boxes), alpha: level 0 holds the given codes (RGB8 with alpha 255),
    // and each mip level is the one above averaged in linear light, premultiplied, and
    // rounded to 8 bits: within the 8-bit steps of the default storage's chain, built from
    // 16-bit levels.
    let (w, h) = (37u32, 22u32);
    let rgba: Vec<u8> = (0..w * h * 4).map(|i| (i * 37 % 253) as u8).collect();
    let rgb: Vec<u8> = rgba
        .chunks_exact(4)
        .flat_map(|c| [c[0], c[1], c[2]])
        .collect();
    for cs in [ColorSpace::Srgb, ColorSpace::Linear] {
        for (format, bytes) in [(Format::Rgba8, &rgba), (Format::Rgb8, &rgb)] {
            let make = |storage| {
                let options = TextureOptions::default().with_storage(storage);
                Texture2D::from_texels(w, h, format, cs, bytes, options).unwrap()
            };
            let (eight, native, wide) = (
                make(Storage::Rgba8),
                make(Storage::Native),
                make(Storage::Linear16),
            );
            assert_eq!(eight.storage(), Storage::Rgba8);
            assert_eq!(eight.storage_format(), Format::Rgba8);
            assert_eq!((eight.format(), eight.color_space()), (format, cs));
            assert_eq!(eight.levels().len(), native.levels().len());
            if cs == ColorSpace::Linear {
                // The default storage keeps linear data in its 8 bits: the same texture.
                assert_eq!(wide.storage(), Storage::Rgba8);
                assert_eq!(wide.texel_bytes(), eight.texel_bytes());
                for l in 0..eight.levels().len() {
                    assert_eq!(eight.decode_level(l), wide.decode_level(l), "level {l}");
                }
                continue;
            }
            assert_eq!(eight.texel_bytes(), wide.texel_bytes() / 2);
            assert_eq!(
                eight.decode_level(0),
                native.decode_level(0),
                "{cs:?} {format:?}"
            );
            for l in 1..eight.levels().len() {
                let (a, b) = (eight.decode_level(l), wide.decode_level(l));
                let err = a
                    .iter()
                    .zip(&b)
                    .map(|(x, y)| (*x - *y).abs().max_element())
                    .fold(0.0, f32::max);
                assert!(err < 0.02, "{cs:?} {format:?} level {l}: {err}");
            }
        }
    }
}

#[test]
fn rgba8_storage_level_is_the_encoded_average_of_the_one_above() {
    // 2:1 on both sides: each texel the four above it decoded, averaged premultiplied,
    // unpremultiplied and encoded (sRGB colour, linear alpha); translucent and opaque.
    let (w, h) = (8u32, 6u32);
    for (opaque, cs) in [
        (false, ColorSpace::Srgb),
        (true, ColorSpace::Srgb),
        (true, ColorSpace::Linear),
    ] {
        let rgba: Vec<u8> = (0..w * h * 4)
            .map(|i| {
                if opaque && i % 4 == 3 {
                    255
                } else {
                    (i * 53 % 256) as u8
                }
            })
            .collect();
        let options = TextureOptions::default().with_storage(Storage::Rgba8);
        let tex = Texture2D::from_texels(w, h, Format::Rgba8, cs, &rgba, options).unwrap();
        let (top, next) = (tex.decode_level(0), tex.decode_level(1));
        for y in 0..h / 2 {
            for x in 0..w / 2 {
                let at = |dx: u32, dy: u32| top[((2 * y + dy) * w + 2 * x + dx) as usize];
                let mean = (at(0, 0) * 0.5 + at(1, 0) * 0.5) * 0.5
                    + (at(0, 1) * 0.5 + at(1, 1) * 0.5) * 0.5;
                let mut want = [0u8; 4];
                Format::Rgba8.encode(mip::unpremultiply(mean), cs, &mut want);
                let mut got = [0u8; 4];
                let c = next[(y * (w / 2) + x) as usize];
                Format::Rgba8.encode(mip::unpremultiply(c), cs, &mut got);
                // Opaque levels are halved in integers (16-bit linear sums): at most a code off.
                for (g, e) in got.iter().zip(want) {
                    assert!(g.abs_diff(e) <= 1, "({x}, {y}): {got:?} vs {want:?}");
                }
            }
        }
    }
}

/// The default storage of 8-bit sRGB colour takes faster paths (`linear16.rs`: level 0 by
/// rows, levels 1 and 2 in strips, `mip::halve_row` for even sides): every level must hold
/// the bytes of the general paths — each texel decoded, the chain reduced with its weights
/// (`mip::for_each_level` without the unorm shortcut), each level encoded by
/// `Format::encode`.
#[test]
fn the_linear16_chain_is_the_general_paths_bit_for_bit() {
    use crate::texture::format::{Codec, CodecRgb8, CodecRgba8};
    let mut r = crate::xorshift(0x16c4_a1f5);
    // Multiples of four (levels 1 and 2 in strips, whole and partial bands), even sides
    // only, odd sides, and a side reaching 1 before the other.
    for (w, h) in [
        (8, 8),
        (12, 20),
        (16, 4),
        (4, 12),
        (24, 8),
        (40, 36),
        (6, 10),
        (13, 7),
        (32, 2),
    ] {
        for format in [Format::Rgb8, Format::Rgba8] {
            let bpp = format.bytes_per_texel();
            // Alpha 0, 255 and between; every texel random.
            let bytes: Vec<u8> = (0..w * h * bpp as u32)
                .map(|i| match (i as usize % bpp == 3, r() % 4) {
                    (true, 0) => 0,
                    (true, 1) => 255,
                    _ => r() as u8,
                })
                .collect();
            let lut = crate::color::lut8(ColorSpace::Srgb);
            let decode = |x: u32, y: u32| {
                let t = &bytes[(y * w + x) as usize * bpp..][..bpp];
                match format {
                    Format::Rgb8 => CodecRgb8::decode_premultiplied(t, lut),
                    _ => CodecRgba8::decode_premultiplied(t, lut),
                }
            };
            let encode = |c: Vec4| {
                let mut out = [0u8; 8];
                Format::Rgba16Premultiplied.encode(
                    mip::unpremultiply(c),
                    ColorSpace::Srgb,
                    &mut out,
                );
                out
            };
            let mut want = vec![(
                w,
                h,
                (0..w * h)
                    .map(|i| encode(decode(i % w, i / w)))
                    .collect::<Vec<_>>(),
            )];
            mip::for_each_level(w, h, false, decode, |lw, lh, t| {
                want.push((lw, lh, t.iter().map(|&c| encode(c)).collect()));
            });
            for layout in [Layout::Tiled4x4, Layout::RowMajor] {
                let options = TextureOptions::default()
                    .with_storage(Storage::Linear16)
                    .with_layout(layout);
                let tex = Texture2D::from_texels(w, h, format, ColorSpace::Srgb, &bytes, options)
                    .unwrap();
                assert_eq!(tex.storage_format(), Format::Rgba16Premultiplied);
                assert_eq!(tex.levels.len(), want.len());
                for (l, (level, (lw, lh, texels))) in tex.levels.iter().zip(&want).enumerate() {
                    assert_eq!((level.width, level.height), (*lw, *lh));
                    for (i, t) in texels.iter().enumerate() {
                        let (x, y) = (i as u32 % lw, i as u32 / lw);
                        let at = texel_index(layout, level.tiles_x, *lw, x, y) * 8;
                        assert_eq!(
                            &level.data[at..at + 8],
                            t,
                            "{w}x{h} {format:?} {layout:?} level {l} texel ({x}, {y})"
                        );
                    }
                }
            }
        }
    }
}
