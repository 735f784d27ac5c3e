use glam::Vec2;

use super::*;
use crate::texture::compressed::{decode_level_f32, decode_level_rgba8};
use crate::texture::{sample, Filter, Footprint, MagFilter, MinFilter, Sampler, Wrap};

/// Pseudo-random bytes (a fixed LCG, so every run tests the same blocks).
fn bytes(n: usize, seed: u64) -> Vec<u8> {
    let mut s = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
    (0..n)
        .map(|_| {
            s = s
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (s >> 56) as u8
        })
        .collect()
}

/// A full chain of random blocks for a `w`×`h` texture.
fn chain(format: BlockFormat, w: u32, h: u32, seed: u64) -> Vec<Vec<u8>> {
    (0..mip::level_count(w, h))
        .map(|i| {
            let (lw, lh) = ((w >> i).max(1), (h >> i).max(1));
            bytes(format.level_bytes(lw, lh) as usize, seed + i as u64)
        })
        .collect()
}

/// The same texels decoded up front and held natively, the reference the blocks must match.
fn decoded(format: BlockFormat, w: u32, h: u32, levels: &[Vec<u8>], cs: ColorSpace) -> Texture2D {
    let stored = texel_format(format);
    let texels: Vec<Vec<u8>> = levels
        .iter()
        .enumerate()
        .map(|(i, data)| {
            let (lw, lh) = ((w >> i).max(1), (h >> i).max(1));
            match stored {
                Format::Rgba8 => decode_level_rgba8(format, data, lw, lh).unwrap(),
                Format::Rgba16F => decode_level_f32(format, data, lw, lh)
                    .unwrap()
                    .into_iter()
                    .flat_map(|v| crate::texture::f32_to_f16(v).to_le_bytes())
                    .collect(),
                _ => decode_level_f32(format, data, lw, lh)
                    .unwrap()
                    .into_iter()
                    .flat_map(f32::to_le_bytes)
                    .collect(),
            }
        })
        .collect();
    let slices: Vec<&[u8]> = texels.iter().map(Vec::as_slice).collect();
    let options = TextureOptions::default().with_storage(Storage::Native);
    Texture2D::from_texel_levels(w, h, stored, cs, &slices, options).unwrap()
}

fn compressed(
    format: BlockFormat,
    w: u32,
    h: u32,
    levels: &[Vec<u8>],
    cs: ColorSpace,
) -> Texture2D {
    let slices: Vec<&[u8]> = levels.iter().map(Vec::as_slice).collect();
    let options = TextureOptions::default().with_storage(Storage::Compressed);
    Texture2D::from_blocks(w, h, format, cs, &slices, options, false).unwrap()
}

#[test]
fn every_texel_of_every_level_equals_the_decoded_storage() {
    // 37×23: edge blocks cut on both axes, levels down to 1×1.
    let (w, h) = (37, 23);
    for (k, format) in BlockFormat::ALL.into_iter().enumerate() {
        let levels = chain(format, w, h, 10 * k as u64);
        let a = compressed(format, w, h, &levels, ColorSpace::Srgb);
        let b = decoded(format, w, h, &levels, ColorSpace::Srgb);
        assert_eq!(a.block_format(), Some(format));
        assert_eq!(a.storage(), Storage::Compressed);
        assert_eq!(a.storage_format(), b.storage_format(), "{format:?}");
        assert_eq!(a.levels().len(), b.levels().len());
        for l in 0..a.levels().len() {
            let (x, y) = (a.decode_level(l), b.decode_level(l));
            for (i, (p, q)) in x.iter().zip(&y).enumerate() {
                // The same decoder and tables: equal, NaN-free formats bit for bit.
                assert!(
                    p == q || (p.is_nan() && q.is_nan()),
                    "{format:?} level {l} texel {i}: {p} vs {q}"
                );
            }
        }
    }
}

#[test]
fn every_filter_reads_the_same_values() {
    let (w, h) = (64, 48);
    let filters = [
        Filter::Gl {
            mag: MagFilter::Linear,
            min: MinFilter::LinearMipmapLinear,
        },
        Filter::Gl {
            mag: MagFilter::Nearest,
            min: MinFilter::NearestMipmapNearest,
        },
        Filter::aniso(8),
        Filter::Ewa {
            max_eccentricity: 16.0,
        },
        Filter::SummedArea,
    ];
    for format in [BlockFormat::Bc1, BlockFormat::Bc3, BlockFormat::Bc7] {
        let levels = chain(format, w, h, 99);
        let a = compressed(format, w, h, &levels, ColorSpace::Srgb);
        let b = decoded(format, w, h, &levels, ColorSpace::Srgb);
        for filter in filters {
            for wrap in [Wrap::Repeat, Wrap::MirroredRepeat, Wrap::ClampToEdge] {
                let s = Sampler::new(filter, wrap);
                for k in 0..200 {
                    let t = k as f32 * 0.173;
                    let fp = Footprint::new(
                        Vec2::new(t.sin() * 1.7, t.cos() * 1.3 + 0.2),
                        Vec2::new(0.002 + 0.03 * (t * 0.7).sin().abs(), 0.001),
                        Vec2::new(0.0005, 0.004 + 0.02 * (t * 1.3).cos().abs()),
                    );
                    let (p, q) = (sample(&a, &s, &fp), sample(&b, &s, &fp));
                    assert!(
                        (p - q).abs().max_element() < 1e-6,
                        "{format:?} {filter:?} {wrap:?} #{k}: {p} vs {q}"
                    );
                }
            }
        }
    }
}

#[test]
fn one_level_builds_the_chain_as_texels() {
    let (w, h) = (40, 20);
    let format = BlockFormat::Bc7;
    let level0 = bytes(format.level_bytes(w, h) as usize, 5);
    let options = TextureOptions::default().with_storage(Storage::Compressed);
    let a =
        Texture2D::from_blocks(w, h, format, ColorSpace::Srgb, &[&level0], options, false).unwrap();
    assert_eq!(a.levels().len(), mip::level_count(w, h));
    // Level 0 is the blocks (1 byte a texel for BC7, whole blocks), the rest 8-bit texels.
    assert_eq!(a.levels()[0].data.len(), format.level_bytes(w, h) as usize);
    assert!(a.levels()[1..].iter().all(|l| l.block_id.is_none()));
    let b = decoded(
        format,
        w,
        h,
        std::slice::from_ref(&level0),
        ColorSpace::Srgb,
    );
    for l in 0..a.levels().len() {
        let err = a
            .decode_level(l)
            .iter()
            .zip(b.decode_level(l))
            .map(|(p, q)| (*p - q).abs().max_element())
            .fold(0.0, f32::max);
        assert!(err < 1e-6, "level {l}: {err}");
    }
    let no_mips = options.with_mipmaps(false);
    let c =
        Texture2D::from_blocks(w, h, format, ColorSpace::Srgb, &[&level0], no_mips, false).unwrap();
    assert_eq!(c.levels().len(), 1);
}

#[test]
fn compressed_memory_is_the_blocks() {
    let (w, h) = (256, 256);
    let levels = chain(BlockFormat::Bc1, w, h, 1);
    let a = compressed(BlockFormat::Bc1, w, h, &levels, ColorSpace::Srgb);
    let blocks: usize = levels.iter().map(Vec::len).sum();
    assert_eq!(a.texel_bytes(), blocks);
    // Half a byte a texel at level 0, against 4 native and 8 decoded.
    assert_eq!(a.levels()[0].data.len(), (w * h / 2) as usize);
}

#[test]
fn opaque_reads_alpha_one() {
    let (w, h) = (8, 8);
    let levels = chain(BlockFormat::Bc3, w, h, 3);
    let slices: Vec<&[u8]> = levels.iter().map(Vec::as_slice).collect();
    let options = TextureOptions::default().with_storage(Storage::Compressed);
    let t = Texture2D::from_blocks(
        w,
        h,
        BlockFormat::Bc3,
        ColorSpace::Srgb,
        &slices,
        options,
        true,
    )
    .unwrap();
    assert!(t.decode_level(0).iter().all(|c| c.w == 1.0));
    let translucent = compressed(BlockFormat::Bc3, w, h, &levels, ColorSpace::Srgb);
    assert!(translucent.decode_level(0).iter().any(|c| c.w < 1.0));
}

#[test]
fn textures_sharing_a_thread_never_read_each_others_blocks() {
    // Two textures of one size whose blocks land in the same slots, read interleaved, and a
    // third made after the first is dropped (it may reuse its memory): each reads its own.
    let (w, h) = (32, 32);
    let la = chain(BlockFormat::Bc1, w, h, 11);
    let lb = chain(BlockFormat::Bc1, w, h, 12);
    let a = compressed(BlockFormat::Bc1, w, h, &la, ColorSpace::Linear);
    let b = compressed(BlockFormat::Bc1, w, h, &lb, ColorSpace::Linear);
    let ra = decoded(BlockFormat::Bc1, w, h, &la, ColorSpace::Linear);
    let rb = decoded(BlockFormat::Bc1, w, h, &lb, ColorSpace::Linear);
    for round in 0..2 {
        for y in 0..h {
            for x in 0..w {
                assert_eq!(
                    a.texel(0, x, y),
                    ra.texel(0, x, y),
                    "a ({x},{y}) round {round}"
                );
                assert_eq!(
                    b.texel(0, x, y),
                    rb.texel(0, x, y),
                    "b ({x},{y}) round {round}"
                );
            }
        }
    }
    drop(a);
    let c = compressed(BlockFormat::Bc1, w, h, &lb, ColorSpace::Linear);
    assert_eq!(c.decode_level(0), rb.decode_level(0));
}

#[test]
fn threads_read_the_same_values() {
    let (w, h) = (128, 128);
    let levels = chain(BlockFormat::Bc7, w, h, 21);
    let a = compressed(BlockFormat::Bc7, w, h, &levels, ColorSpace::Srgb);
    let expected = a.decode_level(0);
    std::thread::scope(|s| {
        for _ in 0..3 {
            s.spawn(|| assert_eq!(a.decode_level(0), expected));
        }
    });
}

#[test]
fn wrong_sizes_are_errors() {
    let options = TextureOptions::default().with_storage(Storage::Compressed);
    let make = |w, h, levels: &[&[u8]]| {
        Texture2D::from_blocks(
            w,
            h,
            BlockFormat::Bc1,
            ColorSpace::Srgb,
            levels,
            options,
            false,
        )
    };
    assert!(make(0, 4, &[&[]]).is_err());
    assert!(make(4, 4, &[&[0; 7]]).is_err());
    assert!(make(4, 4, &[]).is_err());
    // Two levels of an 8×8 chain of four.
    assert!(make(8, 8, &[&[0; 32], &[0; 8]]).is_err());
    assert!(make(5, 5, &[&[0; 32]]).is_ok());
}

#[test]
fn storage_names_round_trip() {
    for (name, s) in Storage::NAMES {
        assert_eq!(Storage::from_name(name), Some(s));
        assert_eq!(s.name(), name);
    }
    assert_eq!(Storage::from_name("bc1"), None);
}
