//! The AVX2 taps and decodes against the SSE2 ones they must equal, bit for bit.

use super::super::sse2::taps;
use super::*;
use crate::color::ColorSpace;
use crate::texture::{Filter, Texture2D, Wrap};

/// Two probes' taps on one level ([`taps2`]), and one point's taps on two levels
/// ([`taps2_levels`]: each level with the next, a trilinear read's pair, and the last with
/// the first), are the SSE2 taps of each, on random points in and off the texture.
#[test]
fn paired_taps_are_the_sse2_taps_of_each() {
    if !crate::cpu::available(crate::cpu::Level::V3) {
        eprintln!("skipped: this CPU has no x86-64-v3 (AVX2), where the paired taps run");
        return;
    }
    let mut r = crate::xorshift(0x2545_f491);
    let mut next = move || r() as f32 / u32::MAX as f32;
    let (mut compared, mut levels_compared) = (0, 0);
    for (w, h) in [(64, 64), (40, 24), (1, 1), (256, 8)] {
        let tex =
            Texture2D::from_rgba8(w, h, ColorSpace::Srgb, &vec![90; (w * h * 4) as usize]).unwrap();
        let count = tex.levels().len();
        for index in 0..count {
            let lv = tex.level(index);
            let (data, tiles_x) = lv.tiled_texels(8);
            let other = tex.level((index + 1) % count);
            let (other_data, other_tiles) = other.tiled_texels(8);
            for wrap in [Wrap::Repeat, Wrap::ClampToEdge] {
                let s = Sampler::new(Filter::BILINEAR, wrap);
                for _ in 0..200 {
                    let mut lanes =
                        || Vec4::new(next(), next(), next(), next()) * 6.0 - Vec4::splat(2.5);
                    let (u, v) = ([lanes(), lanes()], [lanes(), lanes()]);
                    let weight = [(next() * 32767.0) as i32, (next() * 32767.0) as i32];
                    let case = format!("{w}x{h} level {index} {wrap:?}");
                    // SAFETY: the CPU has x86-64-v3 (checked above).
                    let two = unsafe { taps2(size(&lv), tiles_x, &s, u, v, weight) };
                    for k in 0..2 {
                        let one = taps(&lv, tiles_x, &s, u[k], v[k], weight[k]);
                        assert_eq!(two[k], one, "{case} probe {k}");
                        compared += 1;
                    }
                    let (a, b) = (
                        (size(&lv), data, tiles_x),
                        (size(&other), other_data, other_tiles),
                    );
                    // SAFETY: as above.
                    let two = unsafe { taps2_levels(a, b, &s, u, v, weight) };
                    let one = [
                        taps(&lv, tiles_x, &s, u[0], v[0], weight[0]),
                        taps(&other, other_tiles, &s, u[1], v[1], weight[1]),
                    ];
                    assert_eq!(two, one, "{case} with the next level");
                    levels_compared += 1;
                }
            }
        }
    }
    assert!(compared > 1000 && levels_compared > 500);
}

#[test]
fn rgba8_nearest_texels_in_lanes_are_the_scalar_decode() {
    use crate::texture::{Format, Storage, TextureOptions};
    if !crate::cpu::available(crate::cpu::Level::V3) {
        eprintln!("skipped: this CPU has no x86-64-v3 (AVX2), where RGBA8 texels decode in lanes");
        return;
    }
    let mut r = crate::xorshift(0x5bd1_e995);
    let (w, h) = (37u32, 22u32);
    // Every code, translucent texels among them (the premultiplied decode), sRGB and
    // linear colour (the level's two tables).
    let bytes: Vec<u8> = (0..w * h * 4).map(|_| r() as u8).collect();
    let mut compared = 0;
    for cs in [ColorSpace::Srgb, ColorSpace::Linear] {
        let options = TextureOptions::default().with_storage(Storage::Rgba8);
        let tex = Texture2D::from_texels(w, h, Format::Rgba8, cs, &bytes, options).unwrap();
        assert!(tex.rgba8_texels().is_some(), "{cs:?}: held as RGBA8");
        for index in 0..tex.levels().len() {
            let lv = tex.level(index);
            let (data, _) = lv.tiled_texels(4);
            let count = (data.len() / 4) as u32;
            let mut offsets = [[0; 4]; 16];
            for o in offsets.iter_mut().flatten() {
                *o = (r() % count) as i32;
            }
            let masks: Vec<u8> = (0..16)
                .map(|i| [0b1111, 0b0110, 0, 0b1001][i % 4])
                .collect();
            let mut out = [[Vec4::splat(7.0); 4]; 16];
            // SAFETY: the CPU has x86-64-v3 (checked above); the indices are below the
            // level's texel count.
            unsafe { nearest_rgba8(&lv, data, &offsets, &masks, &mut out) };
            for ((o, &mask), got) in offsets.iter().zip(&masks).zip(&out) {
                for j in 0..4 {
                    let want = if mask & (1 << j) == 0 {
                        Vec4::ZERO
                    } else {
                        lv.texel_at::<crate::texture::format::CodecRgba8>(o[j] as usize)
                    };
                    assert_eq!(
                        got[j].to_array().map(f32::to_bits),
                        want.to_array().map(f32::to_bits),
                        "{cs:?} level {index}"
                    );
                    compared += 1;
                }
            }
        }
    }
    assert!(compared >= 128);
}

#[test]
fn a_levels_quads_two_at_a_time_take_the_sse2_taps_and_indices() {
    if !crate::cpu::available(crate::cpu::Level::V3) {
        eprintln!("skipped: this CPU has no x86-64-v3 (AVX2), where quads pair");
        return;
    }
    let mut r = crate::xorshift(0x9e37_79b9);
    let mut next = move || r() as f32 / u32::MAX as f32;
    let tex = Texture2D::from_rgba8(48, 80, ColorSpace::Srgb, &[50; 48 * 80 * 4]).unwrap();
    for index in 0..tex.levels().len() {
        let lv = tex.level(index);
        let (_, tiles_x) = lv.tiled_texels(8);
        for wrap in [Wrap::Repeat, Wrap::ClampToEdge] {
            let s = Sampler::new(Filter::BILINEAR, wrap);
            // Odd and even counts: the last quad of an odd batch is read alone.
            for n in [1, 2, 7, 16] {
                let mut lanes = || Vec4::new(next(), next(), next(), next()) * 5.0 - 2.0;
                let mut coords = [QuadCoords::default(); 16];
                for c in &mut coords[..n] {
                    (c.u, c.v) = (lanes(), lanes());
                }
                coords[0].u.x = f32::NAN;
                let coords = &coords[..n];
                let mut offsets = [[0; 4]; 16];
                let mut out = [const { std::mem::MaybeUninit::uninit() }; 16];
                // SAFETY: the CPU has x86-64-v3 (checked above).
                let paired = unsafe {
                    level_nearest(&lv, tiles_x, &s, coords, &mut offsets);
                    level_taps(&lv, tiles_x, &s, coords, &mut out)
                };
                assert_eq!(paired.len(), n);
                for (i, c) in coords.iter().enumerate() {
                    let case = format!("level {index} {wrap:?} quad {i} of {n}");
                    assert_eq!(paired[i], taps(&lv, tiles_x, &s, c.u, c.v, ONE), "{case}");
                    let near = sse2::nearest_offsets(&lv, tiles_x, &s, c.u, c.v);
                    assert_eq!(offsets[i], near, "{case}");
                }
            }
        }
    }
}

#[test]
fn a_nan_coordinate_takes_the_sse2_indices() {
    if !crate::cpu::available(crate::cpu::Level::V3) {
        eprintln!("skipped: this CPU has no x86-64-v3 (AVX2)");
        return;
    }
    let tex = Texture2D::from_rgba8(16, 16, ColorSpace::Srgb, &[7; 16 * 16 * 4]).unwrap();
    let lv = tex.level(0);
    let (_, tiles_x) = lv.tiled_texels(8);
    let odd = Vec4::new(f32::NAN, f32::INFINITY, -f32::INFINITY, 1e30);
    for wrap in [Wrap::Repeat, Wrap::ClampToEdge] {
        let s = Sampler::new(Filter::BILINEAR, wrap);
        let (u, v) = ([odd, Vec4::splat(0.3)], [Vec4::splat(0.7), odd]);
        // SAFETY: the CPU has x86-64-v3 (checked above).
        let two = unsafe { taps2(size(&lv), tiles_x, &s, u, v, [32767, 100]) };
        for k in 0..2 {
            assert_eq!(two[k], taps(&lv, tiles_x, &s, u[k], v[k], [32767, 100][k]));
        }
    }
}

/// [`quad_pairs`] is each quad's [`sse2::linear_weighted_on`], bit for bit: on a first level
/// larger than [`PREFETCH_BYTES`] (its lines asked for before the reads) and on smaller
/// ones, runs of every length up to [`LEVEL_QUADS`], levels weighted 0 for one quad of a
/// pair or for both, and partial masks.
#[test]
fn quad_pairs_are_each_quads_sse2_read() {
    if !crate::cpu::available(crate::cpu::Level::V3) {
        eprintln!("skipped: this CPU has no x86-64-v3 (AVX2), where quads pair");
        return;
    }
    let (tex, mut next) = noise(0x51ed_270b, 160, 128);
    assert!(tex.level(0).tiled_texels(8).0.len() > PREFETCH_BYTES);
    assert!(tex.level(1).tiled_texels(8).0.len() <= PREFETCH_BYTES);
    let mut compared = 0;
    for first in 0..3 {
        let (la, lb) = (tex.level(first), tex.level(first + 1));
        let ((da, ta), (db, tb)) = (la.tiled_texels(8), lb.tiled_texels(8));
        for wrap in [Wrap::Repeat, Wrap::ClampToEdge] {
            let s = Sampler::new(Filter::TRILINEAR, wrap);
            for n in 1..=LEVEL_QUADS {
                let mut coords = [QuadCoords::default(); LEVEL_QUADS];
                let mut weights = [[0; 2]; LEVEL_QUADS];
                let mut masks = [0u8; LEVEL_QUADS];
                for i in 0..n {
                    let mut lanes = || Vec4::new(next(), next(), next(), next()) * 3.0 - 1.0;
                    (coords[i].u, coords[i].v) = (lanes(), lanes());
                    let wa = match (next() * 4.0) as u32 {
                        0 => 0,
                        1 => ONE,
                        _ => (next() * ONE as f32) as i32,
                    };
                    weights[i] = [wa, ONE - wa];
                    masks[i] = 1 + (next() * 15.0) as u8;
                }
                let mut out = [[Vec4::splat(-1.0); 4]; LEVEL_QUADS];
                let (a, b) = ((&la, da, ta), (&lb, db, tb));
                // SAFETY: the CPU has x86-64-v3 (checked above); the slices are of length n.
                unsafe {
                    quad_pairs(
                        a,
                        b,
                        Texels::Linear16,
                        &s,
                        &coords[..n],
                        &weights[..n],
                        &masks[..n],
                        &mut out[..n],
                    );
                }
                for i in 0..n {
                    let c = &coords[i];
                    let want = sse2::linear_weighted_on(
                        a,
                        b,
                        Texels::Linear16,
                        &s,
                        weights[i],
                        c.u,
                        c.v,
                        masks[i],
                    );
                    assert_eq!(out[i], want, "level {first} {wrap:?} quad {i} of {n}");
                    compared += 1;
                }
            }
        }
    }
    assert!(compared >= 800);
}

/// A quad's probes in AVX2 lanes ([`probe_quad`]: every pair's taps first, then the texels,
/// an odd last probe on one level or two) are the SSE2 loop's ([`sse2::probes_sse2`]), bit
/// for bit: every count of anisotropic filtering's and `ewa`'s probe sets, one level or two,
/// the first level's share 0, 1 or between, both wraps, partial masks.
#[test]
fn probe_quads_are_the_sse2_probes() {
    if !crate::cpu::available(crate::cpu::Level::V3) {
        eprintln!("skipped: this CPU has no x86-64-v3 (AVX2), where probes pair");
        return;
    }
    let (tex, mut next) = noise(0x7f4a_7c15, 96, 80);
    let sets = [
        crate::texture::filter::anisotropic::probe_sets(),
        crate::texture::filter::ewa_probes::probe_sets(),
    ];
    let mut compared = 0;
    for first in 0..3 {
        let a = sse2::level_of(&tex, Texels::Linear16, first);
        let b = sse2::level_of(&tex, Texels::Linear16, first + 1);
        for wrap in [Wrap::Repeat, Wrap::ClampToEdge] {
            let s = Sampler::new(Filter::TRILINEAR, wrap);
            for (set, count) in sets
                .iter()
                .flat_map(|s| (1..=MAX_PROBES).map(move |n| (s, n)))
            {
                let probes = set.get(count);
                for blend in 0..4 {
                    let (second, fa) = match blend {
                        0 => (None, 1.0),
                        1 => (Some(&b), 0.0),
                        2 => (Some(&b), 1.0),
                        _ => (Some(&b), next()),
                    };
                    let mut lanes = || Vec4::new(next(), next(), next(), next()) * 3.0 - 1.0;
                    let uv = (lanes(), lanes());
                    let step = glam::Vec2::new(next() - 0.5, next() - 0.5) * 0.2;
                    let mask = 1 + (next() * 15.0) as u8;
                    let texels = Texels::Linear16;
                    // SAFETY: the CPU has x86-64-v3 (checked above).
                    let lanes = unsafe {
                        let levels = (part(&a), second.map(|b| part(b)));
                        probe_quad(levels, texels, &s, fa, uv, step, probes, mask)
                    };
                    let want =
                        sse2::probes_sse2(&a, second, texels, &s, fa, uv, step, probes, mask);
                    let case = format!("level {first} {wrap:?} {count} probes, blend {blend}");
                    assert_eq!(lanes, want, "{case}");
                    compared += 1;
                }
            }
        }
    }
    assert_eq!(compared, 3 * 2 * 2 * MAX_PROBES * 4);
}

/// A level's parts as the AVX2 probed reads take them ([`Level`]).
fn part<'a>((lv, data, tiles_x): &sse2::Level<'a>) -> Level<'a> {
    (size(lv), data, *tiles_x)
}

/// A `w`×`h` texture of random texels (on the default 16-bit storage), and the generator
/// that made them, going on as uniform floats in [0, 1].
fn noise(seed: u32, w: u32, h: u32) -> (Texture2D, impl FnMut() -> f32) {
    let mut r = crate::xorshift(seed);
    let rgba: Vec<u8> = (0..w * h * 4).map(|_| r() as u8).collect();
    let tex = Texture2D::from_rgba8(w, h, ColorSpace::Srgb, &rgba).unwrap();
    (tex, move || r() as f32 / u32::MAX as f32)
}
