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
    for storage in [Storage::Linear16, Storage::Native] {
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
