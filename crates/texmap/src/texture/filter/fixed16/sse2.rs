//! The SSE2 side of [`super`]: texel indices and 15-bit weights in lanes, the loads and
//! multiply-adds of a quad's taps, the nearest reads, and the per-storage texel loaders (the
//! 16-bit default, 8-bit RGBA sRGB or linear, opaque or not).

use std::arch::x86_64::{
    __m128i, _mm_add_epi32, _mm_and_si128, _mm_andnot_si128, _mm_cmpeq_epi32, _mm_cvtepi32_ps,
    _mm_cvtps_epi32, _mm_cvtsi32_si128, _mm_cvtsi64_si128, _mm_cvttps_epi32, _mm_insert_epi16,
    _mm_loadl_epi64, _mm_madd_epi16, _mm_or_si128, _mm_set1_epi32, _mm_set_epi16,
    _mm_setzero_si128, _mm_slli_epi32, _mm_srli_epi16, _mm_srli_epi32, _mm_sub_epi32,
    _mm_unpacklo_epi16, _mm_unpacklo_epi8,
};

use glam::Vec4;

use super::{Texels, ONE};
use crate::texture::format::CodecRgba8;
use crate::texture::storage::LevelRef;
use crate::texture::{MipChoice, Sampler, Texture2D, Wrap};

// Inlined into the quad read: as a call (which the compiler chose once the level choice
// became a `MipChoice`) it cost the trilinear quad path measurably more instructions.
#[inline(always)]
pub(super) fn linear_quad(
    tex: &Texture2D,
    texels: Texels,
    s: &Sampler,
    choice: MipChoice,
    u: Vec4,
    v: Vec4,
    mask: u8,
) -> [Vec4; 4] {
    // SAFETY: SSE2 is part of x86_64.
    let mut acc = [unsafe { _mm_setzero_si128() }; 4];
    let a = choice.level;
    let second = choice.blend.map(|b| b.level);
    let wa = first_weight(choice);
    if wa > 0 {
        accumulate(&tex.level(a), texels, s, u, v, wa, &mut acc);
    }
    if let Some(b) = second.filter(|_| wa < ONE) {
        accumulate(&tex.level(b), texels, s, u, v, ONE - wa, &mut acc);
    }
    finish(&acc, mask)
}

/// The weight of `choice`'s first level in 15 bits (the second level's is `ONE` minus
/// it): `(1 − f)·ONE` rounded, `f` the blend's weight (0 without a blend; NaN gives 0).
#[inline(always)]
pub(super) fn first_weight(choice: MipChoice) -> i32 {
    let f = choice.blend.map_or(0.0, |b| b.weight);
    ((1.0 - f.clamp(0.0, 1.0)) * ONE as f32).round() as i32
}

/// A probe's 15-bit weight on the first level: `fa·weight` rounded, `fa` in [0, 1] (the
/// first level's share) and `weight` within ±ONE (a probe's weight, `weights::fixed`),
/// without the saturating cast's compares and branches (the value is finite and in range).
#[inline(always)]
pub(super) fn probe_first_weight(fa: f32, weight: i32) -> i32 {
    let x = fa * weight as f32;
    debug_assert!((-ONE as f32..=ONE as f32).contains(&x));
    // SAFETY: `x` is finite and within ±ONE (asserted in debug builds): `fa` in [0, 1] and
    // `weight` within ±ONE, as the callers give them.
    unsafe { x.round().to_int_unchecked::<i32>() }
}

/// The weight of `choice`'s second level in 15 bits, its first level's being `wa`: what
/// `ONE` leaves where the read blends two levels, else 0 (the second level not read).
#[inline(always)]
pub(super) fn second_weight(choice: MipChoice, wa: i32) -> i32 {
    if choice.blend.is_some() && wa < ONE {
        ONE - wa
    } else {
        0
    }
}

/// [`linear_quad`] on levels whose views, tiled texels and tiles per row are given (as
/// `tiled_texels` gives them): `first` for `choice.level`, `second` for its blend's level
/// (read only when `choice` blends). The same values.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(super) fn linear_quad_on(
    first: (&LevelRef, &[u8], u32),
    second: (&LevelRef, &[u8], u32),
    texels: Texels,
    s: &Sampler,
    choice: MipChoice,
    u: Vec4,
    v: Vec4,
    mask: u8,
) -> [Vec4; 4] {
    let wa = first_weight(choice);
    let weights = [wa, second_weight(choice, wa)];
    linear_weighted_on(first, second, texels, s, weights, u, v, mask)
}

/// [`linear_quad_on`] with the two levels' 15-bit weights given (`weights[0]` the first
/// level's, `weights[1]` the second's; a level weighted 0 is not read). The same values as
/// `linear_quad_on` of a choice whose [`first_weight`] and [`second_weight`] they are.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(super) fn linear_weighted_on(
    first: (&LevelRef, &[u8], u32),
    second: (&LevelRef, &[u8], u32),
    texels: Texels,
    s: &Sampler,
    weights: [i32; 2],
    u: Vec4,
    v: Vec4,
    mask: u8,
) -> [Vec4; 4] {
    // SAFETY: SSE2 is part of x86_64.
    let mut acc = [unsafe { _mm_setzero_si128() }; 4];
    if weights[0] > 0 {
        accumulate_on(first, texels, s, u, v, weights[0], &mut acc);
    }
    if weights[1] > 0 {
        accumulate_on(second, texels, s, u, v, weights[1], &mut acc);
    }
    finish(&acc, mask)
}

/// The reads from a quad's 32-bit sums (pixels outside `mask` zero).
#[inline(always)]
pub(super) fn finish(acc: &[__m128i; 4], mask: u8) -> [Vec4; 4] {
    let scale = 1.0 / (ONE as f32 * ONE as f32);
    std::array::from_fn(|j| {
        if mask & (1 << j) == 0 {
            return Vec4::ZERO;
        }
        // SAFETY: SSE2 is part of x86_64.
        let sum = Vec4::from(unsafe { _mm_cvtepi32_ps(acc[j]) });
        // A tap whose rounded weight came out −1 can leave a sum a hair below zero.
        (sum * scale).max(Vec4::ZERO)
    })
}

/// [`super::read_quad_shared`]: [`linear_quad`] of each texture of `shared` (how each
/// one's texels enter the sums is `shared`'s), the taps' addresses and weights computed once
/// per level for all of them.
#[inline(always)]
pub(super) fn linear_quad_shared(
    shared: &super::Shared,
    s: &Sampler,
    choice: MipChoice,
    u: Vec4,
    v: Vec4,
    mask: u8,
    out: &mut [[Vec4; 4]],
) {
    // SAFETY: SSE2 is part of x86_64.
    let mut acc = [[unsafe { _mm_setzero_si128() }; 4]; super::MAX_SHARED];
    let second = choice.blend.map(|b| b.level);
    let wa = first_weight(choice);
    let count = shared.len();
    let texels = shared.texels;
    let level = |index: usize, weight: i32, acc: &mut [[__m128i; 4]]| {
        let lv = shared.level(index);
        let t = taps(&lv.first, lv.tiles_x, s, u, v, weight);
        // Each texture's level is of the first one's size and tiling (checked when the
        // level was looked up), so the first one's indices are in range for every one.
        for ((data, &texels), acc) in lv.data.iter().zip(&texels[..count]).zip(acc.iter_mut()) {
            gather(data, texels, &t, acc);
        }
    };
    if wa > 0 {
        level(choice.level, wa, &mut acc);
    }
    if let Some(b) = second.filter(|_| wa < ONE) {
        level(b, ONE - wa, &mut acc);
    }
    for (o, acc) in out.iter_mut().zip(&acc).take(count) {
        *o = finish(acc, mask);
    }
}

/// The first level's share (in [0, 1]) of a probe's weight under `choice`: `1 − f`, `f` the
/// blend's weight (0 without a blend; a NaN weight gives the first level nothing, as the
/// saturating cast of [`first_weight`] does).
#[inline(always)]
pub(super) fn first_share(choice: MipChoice) -> f32 {
    let f = choice.blend.map_or(0.0, |b| b.weight);
    let fa = 1.0 - f.clamp(0.0, 1.0);
    if fa.is_nan() {
        0.0
    } else {
        fa
    }
}

/// A level's view, tiled texels and tiles per row (as `tiled_texels` gives them).
pub(super) type Level<'a> = (LevelRef<'a>, &'a [u8], u32);

/// `tex`'s level `index` as [`probes_on`] reads it.
#[inline(always)]
pub(super) fn level_of<'t>(tex: &'t Texture2D, texels: Texels, index: usize) -> Level<'t> {
    let lv = tex.level(index);
    let (data, tiles_x) = lv.tiled_texels(bpp(texels));
    (lv, data, tiles_x)
}

/// [`super::read_probes`] on the levels of `choice`, looked up: `first` for `choice.level`,
/// `second` for its blend's level (`None` without a blend). Every probe's taps summed into
/// one 32-bit accumulator per pixel, the 15-bit weights of all of them summing to exactly
/// `ONE` (as the probes' do).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(super) fn probes_on(
    first: &Level,
    second: Option<&Level>,
    texels: Texels,
    s: &Sampler,
    choice: MipChoice,
    (u, v): (Vec4, Vec4),
    step: glam::Vec2,
    probes: &[super::Probe],
    mask: u8,
) -> [Vec4; 4] {
    let fa = first_share(choice);
    if crate::cpu::level() == crate::cpu::Level::V3 {
        // The whole quad in AVX2 lanes (the same values).
        // SAFETY: the CPU has x86-64-v3 (`cpu::level`).
        return unsafe {
            super::avx2::probe_quad(
                (
                    (super::avx2::size(&first.0), first.1, first.2),
                    second.map(|(lv, data, tiles_x)| (super::avx2::size(lv), *data, *tiles_x)),
                ),
                texels,
                s,
                fa,
                (u, v),
                step,
                probes,
                mask,
            )
        };
    }
    probes_sse2(first, second, texels, s, fa, (u, v), step, probes, mask)
}

/// [`probes_on`]'s SSE2 loop, probe by probe (`fa` the first level's share of each probe's
/// weight, `first_share(choice)`): what the AVX2 read must equal, bit for bit.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(super) fn probes_sse2(
    first: &Level,
    second: Option<&Level>,
    texels: Texels,
    s: &Sampler,
    fa: f32,
    (u, v): (Vec4, Vec4),
    step: glam::Vec2,
    probes: &[super::Probe],
    mask: u8,
) -> [Vec4; 4] {
    // SAFETY: SSE2 is part of x86_64.
    let mut acc = [unsafe { _mm_setzero_si128() }; 4];
    for &super::Probe { t, weight } in probes {
        let wa = probe_first_weight(fa, weight);
        let (pu, pv) = (u + Vec4::splat(step.x * t), v + Vec4::splat(step.y * t));
        if wa > 0 {
            let (lv, data, tiles_x) = first;
            accumulate_on((lv, data, *tiles_x), texels, s, pu, pv, wa, &mut acc);
        }
        if let Some((lv, data, tiles_x)) = second.filter(|_| wa < weight) {
            accumulate_on(
                (lv, data, *tiles_x),
                texels,
                s,
                pu,
                pv,
                weight - wa,
                &mut acc,
            );
        }
    }
    finish(&acc, mask)
}

/// The tiled texel indices of the nearest texels to `(u, v)` on `lv` (one lane per pixel).
#[inline(always)]
pub(super) fn nearest_offsets(
    lv: &LevelRef,
    tiles_x: u32,
    s: &Sampler,
    u: Vec4,
    v: Vec4,
) -> [i32; 4] {
    let (x, y) = (
        nearest_axis(s.wrap_u, u, lv.w),
        nearest_axis(s.wrap_v, v, lv.h),
    );
    // SAFETY: SSE2 is part of x86_64 (SSE4.1 where `times` uses it); both indices are in
    // range, so the texel index is below tiles_x·tiles_y·16 (see `taps`).
    unsafe {
        let three = _mm_set1_epi32(3);
        let col = _mm_or_si128(
            _mm_slli_epi32(_mm_srli_epi32(x, 2), 4),
            _mm_and_si128(x, three),
        );
        let row = _mm_add_epi32(
            times(_mm_srli_epi32(y, 2), 16 * tiles_x as i32),
            _mm_slli_epi32(_mm_and_si128(y, three), 2),
        );
        lanes(_mm_add_epi32(col, row))
    }
}

/// The nearest texels to `(u, v)` on `lv` (pixels outside `mask` zero).
#[inline(always)]
pub(super) fn nearest_level(
    lv: LevelRef,
    texels: Texels,
    s: &Sampler,
    u: Vec4,
    v: Vec4,
    mask: u8,
) -> [Vec4; 4] {
    let (data, tiles_x) = lv.tiled_texels(bpp(texels));
    let offsets = nearest_offsets(&lv, tiles_x, s, u, v);
    // SAFETY: `nearest_offsets` gives indices in range for the level `data` holds.
    unsafe { nearest_texels(&lv, data, texels, offsets, mask) }
}

/// The texels at tiled indices `offsets` of level `lv`, whose tiled texels (held as
/// `texels` says) are `data` (its `tiled_texels`), decoded (pixels outside `mask` zero).
///
/// # Safety
/// Every index must be in range for the level, as [`nearest_offsets`] gives them.
#[inline(always)]
pub(super) unsafe fn nearest_texels(
    lv: &LevelRef,
    data: &[u8],
    texels: Texels,
    offsets: [i32; 4],
    mask: u8,
) -> [Vec4; 4] {
    let base = data.as_ptr();
    if let Texels::Rgba8(_) = texels {
        return std::array::from_fn(|j| {
            if mask & (1 << j) == 0 {
                return Vec4::ZERO;
            }
            // The float path's decode of the texel (the codec's, through the level's
            // table): the same values.
            lv.texel_at::<CodecRgba8>(offsets[j] as usize)
        });
    }
    // Every lane's texel is loaded (the indices are in range for helper pixels too), with
    // no branch per pixel; the decode is the codec's (`decode_rgba16`): zero-extend,
    // convert, scale.
    let load = |j: usize| {
        // SAFETY: SSE2 is part of x86_64; the index is in range (the caller's), and the
        // load reads the texel's 8 bytes.
        unsafe {
            let q = _mm_loadl_epi64(base.add(offsets[j] as usize * 8).cast());
            let f = _mm_cvtepi32_ps(_mm_unpacklo_epi16(q, _mm_setzero_si128()));
            Vec4::from(f) * (1.0 / 65535.0)
        }
    };
    masked([load(0), load(1), load(2), load(3)], mask)
}

/// A quad's four texels with the pixels outside `mask` zero.
#[inline(always)]
pub(super) fn masked(texel: [Vec4; 4], mask: u8) -> [Vec4; 4] {
    if mask == 0b1111 {
        return texel;
    }
    std::array::from_fn(|j| {
        if mask & (1 << j) == 0 {
            Vec4::ZERO
        } else {
            texel[j]
        }
    })
}

/// The nearest texel's index on an axis of `n` texels at `t` (one lane per pixel), in
/// `[0, n − 1]`: the float path's rule (`nearest`, `Wrap::index`) lane-wise.
#[inline(always)]
fn nearest_axis(wrap: Wrap, t: Vec4, n: i32) -> __m128i {
    let nf = n as f32;
    // SAFETY: SSE2 is part of x86_64.
    unsafe {
        if wrap == Wrap::Repeat {
            // ⌊(t − ⌊t⌋)·n⌋ ∈ [0, n]: n (by rounding) wraps to 0, as a NaN lane (i32::MIN
            // from the conversion) reads 0.
            let i = _mm_cvttps_epi32(floor4((t - floor4(t)) * nf).into());
            let wrapped = _mm_or_si128(
                _mm_cmpeq_epi32(i, _mm_set1_epi32(n)),
                _mm_cmpeq_epi32(i, _mm_set1_epi32(i32::MIN)),
            );
            min_u32(_mm_andnot_si128(wrapped, i), _mm_set1_epi32(n - 1))
        } else {
            // `max` first: it returns its second operand (0) for a NaN lane.
            let i = floor4(t * nf).max(Vec4::ZERO).min(Vec4::splat(nf - 1.0));
            _mm_cvttps_epi32(i.into())
        }
    }
}

/// The four lanes of `v`.
#[inline(always)]
fn lanes(v: __m128i) -> [i32; 4] {
    // SAFETY: same size, every bit pattern valid for both.
    unsafe { std::mem::transmute::<__m128i, [i32; 4]>(v) }
}

/// `v · k` per lane (the low 32 bits): one `pmulld` with SSE4.1.
#[inline(always)]
fn times(v: __m128i, k: i32) -> __m128i {
    #[cfg(target_feature = "sse4.1")]
    {
        // SAFETY: SSE4.1 is enabled for this build.
        unsafe { std::arch::x86_64::_mm_mullo_epi32(v, _mm_set1_epi32(k)) }
    }
    #[cfg(not(target_feature = "sse4.1"))]
    {
        let l = lanes(v).map(|x| x.wrapping_mul(k));
        // SAFETY: same size, every bit pattern valid for both.
        unsafe { std::mem::transmute::<[i32; 4], __m128i>(l) }
    }
}

/// `⌊v⌋` per lane: one `roundps` with SSE4.1 (x86-64-v2, this crate's build), else
/// glam's emulation.
#[inline(always)]
fn floor4(v: Vec4) -> Vec4 {
    #[cfg(target_feature = "sse4.1")]
    {
        // SAFETY: SSE4.1 is enabled for this build.
        Vec4::from(unsafe { std::arch::x86_64::_mm_floor_ps(v.into()) })
    }
    #[cfg(not(target_feature = "sse4.1"))]
    {
        v.floor()
    }
}

/// The texel positions a bilinear read at `t` (one lane per pixel) takes on an axis of `n`
/// texels: the two indices, both in `[0, n − 1]` whatever `t` is (NaN reads index 0 when
/// clamping, `n − 1` when repeating), and the second one's weight in `[0, 1]`.
#[inline(always)]
fn axis(wrap: Wrap, t: Vec4, n: i32) -> (__m128i, __m128i, Vec4) {
    let nf = n as f32;
    let p = if wrap == Wrap::Repeat {
        (t - floor4(t)) * nf - 0.5
    } else {
        t * nf - 0.5
    };
    let i = floor4(p);
    // p − ⌊p⌋ of a finite p lies in [0, 1] as rounded, so no upper clamp; `max` returns its
    // second operand (0) for a NaN lane (an infinite or NaN p).
    let frac = (p - i).max(Vec4::ZERO);
    // SAFETY: SSE2 is part of x86_64.
    unsafe {
        if wrap == Wrap::Repeat {
            // t − ⌊t⌋ ∈ [0, 1] puts i in [−1, n − 1] (a NaN lane converts to i32::MIN): as
            // unsigned, the minimum with n − 1 wraps −1 to n − 1 and keeps the rest; i + 1
            // wraps n to 0 by a compare.
            let last = _mm_set1_epi32(n - 1);
            let lo = _mm_cvttps_epi32(i.into());
            let hi = _mm_add_epi32(lo, _mm_set1_epi32(1));
            let hi = _mm_andnot_si128(_mm_cmpeq_epi32(hi, _mm_set1_epi32(n)), hi);
            (min_u32(lo, last), min_u32(hi, last), frac)
        } else {
            // `max` first: it returns its second operand (0) for a NaN lane.
            let clamp = |x: Vec4| x.max(Vec4::ZERO).min(Vec4::splat(nf - 1.0));
            (
                _mm_cvttps_epi32(clamp(i).into()),
                _mm_cvttps_epi32(clamp(i + 1.0).into()),
                frac,
            )
        }
    }
}

/// The unsigned minimum per lane: one `pminud` with SSE4.1.
#[inline(always)]
fn min_u32(a: __m128i, b: __m128i) -> __m128i {
    #[cfg(target_feature = "sse4.1")]
    {
        // SAFETY: SSE4.1 is enabled for this build.
        unsafe { std::arch::x86_64::_mm_min_epu32(a, b) }
    }
    #[cfg(not(target_feature = "sse4.1"))]
    {
        let (a, b) = (lanes(a), lanes(b));
        let m: [i32; 4] = std::array::from_fn(|k| (a[k] as u32).min(b[k] as u32) as i32);
        // SAFETY: same size, every bit pattern valid for both.
        unsafe { std::mem::transmute::<[i32; 4], __m128i>(m) }
    }
}

/// Adds level `lv`'s bilinear taps, weighted `level_weight / ONE` in all, into `acc`.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn accumulate(
    lv: &LevelRef,
    texels: Texels,
    s: &Sampler,
    u: Vec4,
    v: Vec4,
    level_weight: i32,
    acc: &mut [__m128i; 4],
) {
    let (data, tiles_x) = lv.tiled_texels(bpp(texels));
    accumulate_on((lv, data, tiles_x), texels, s, u, v, level_weight, acc);
}

/// [`accumulate`] on a level whose tiled texels and tiles per row are given.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn accumulate_on(
    (lv, data, tiles_x): (&LevelRef, &[u8], u32),
    texels: Texels,
    s: &Sampler,
    u: Vec4,
    v: Vec4,
    level_weight: i32,
    acc: &mut [__m128i; 4],
) {
    let t = taps(lv, tiles_x, s, u, v, level_weight);
    gather(data, texels, &t, acc);
}

pub(super) use super::bpp;

/// A quad's bilinear taps on one level: each pixel's four texel indices and its
/// 15-bit weights, packed in pairs (top row, bottom row).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct Taps {
    pub(super) offsets: [[i32; 4]; 4],
    pub(super) top: [i32; 4],
    pub(super) bottom: [i32; 4],
}

/// Level `lv`'s bilinear taps at `(u, v)`, weighted `level_weight / ONE` in all
/// (`tiles_x` from its `tiled_texels`).
#[inline(always)]
pub(super) fn taps(
    lv: &LevelRef,
    tiles_x: u32,
    s: &Sampler,
    u: Vec4,
    v: Vec4,
    level_weight: i32,
) -> Taps {
    sized_taps((lv.w, lv.h), tiles_x, s, u, v, level_weight)
}

/// [`taps`] of a level of `(width, height)`.
#[inline(always)]
pub(super) fn sized_taps(
    (w, h): (i32, i32),
    tiles_x: u32,
    s: &Sampler,
    u: Vec4,
    v: Vec4,
    level_weight: i32,
) -> Taps {
    let (xa, xb, fx) = axis(s.wrap_u, u, w);
    let (ya, yb, fy) = axis(s.wrap_v, v, h);
    let lw = level_weight as f32;
    let (gx, gy) = (Vec4::ONE - fx, Vec4::ONE - fy);
    // SAFETY: SSE2 is part of x86_64.
    unsafe {
        // Tiled index = column part + row part: ((x >> 2) << 4 | x & 3) + (y >> 2)·16·tiles_x
        // + (y & 3) << 2. Both indices of each axis are in range, so every texel index is
        // below tiles_x·tiles_y·16, which `tiled_texels` checked the data holds.
        let three = _mm_set1_epi32(3);
        let col = |x| {
            _mm_or_si128(
                _mm_slli_epi32(_mm_srli_epi32(x, 2), 4),
                _mm_and_si128(x, three),
            )
        };
        let stride = 16 * tiles_x as i32;
        let row = |y| {
            let tile_row = times(_mm_srli_epi32(y, 2), stride);
            _mm_add_epi32(tile_row, _mm_slli_epi32(_mm_and_si128(y, three), 2))
        };
        let (ca, cb, ra, rb) = (col(xa), col(xb), row(ya), row(yb));
        let offsets = [
            lanes(_mm_add_epi32(ca, ra)),
            lanes(_mm_add_epi32(cb, ra)),
            lanes(_mm_add_epi32(ca, rb)),
            lanes(_mm_add_epi32(cb, rb)),
        ];
        // Weights in 15 bits, the last one what the others leave.
        let round = |w: Vec4| _mm_cvtps_epi32((w * lw).into());
        let w00 = round(gx * gy);
        let w10 = round(fx * gy);
        let w01 = round(gx * fy);
        let w11 = _mm_sub_epi32(
            _mm_sub_epi32(_mm_sub_epi32(_mm_set1_epi32(level_weight), w00), w10),
            w01,
        );
        let low = _mm_set1_epi32(0xffff);
        let pack = |a: __m128i, b: __m128i| {
            let packed = _mm_or_si128(_mm_and_si128(a, low), _mm_slli_epi32(b, 16));
            lanes(packed)
        };
        Taps {
            offsets,
            top: pack(w00, w10),
            bottom: pack(w01, w11),
        }
    }
}

/// Adds the taps `t` of a level whose tiled texels (held as `texels` says) are `data`
/// into `acc`, every pixel's (those outside the quad's mask too: [`finish`] drops them);
/// `data` must be a level of the size the taps were computed for (its `tiled_texels`).
#[inline(always)]
pub(super) fn gather(data: &[u8], texels: Texels, t: &Taps, acc: &mut [__m128i; 4]) {
    let base = data.as_ptr();
    // SAFETY (every loader): SSE2 is part of x86_64; each load reads one texel at an
    // index below `data.len() / bpp` (the offsets' level has this size, see `taps`).
    match texels {
        Texels::Linear16 => gather_with(t, acc, |i0, i1| unsafe {
            let q = |i: usize| _mm_loadl_epi64(base.add(i * 8).cast());
            _mm_srli_epi16(_mm_unpacklo_epi16(q(i0), q(i1)), 1)
        }),
        Texels::Rgba8(r) => match (r.srgb15, r.opaque) {
            // Each code's 15-bit value inserted straight at its interleaved place, alpha
            // 255 (32767 in 15 bits) already there.
            (Some(table), true) => gather_with(t, acc, |i0, i1| unsafe {
                let (p0, p1) = (base.add(i0 * 4), base.add(i1 * 4));
                let c = |p: *const u8, k: usize| i32::from(table[usize::from(*p.add(k))]);
                let v = _mm_set_epi16(0x7fff, 0x7fff, 0, 0, 0, 0, 0, 0);
                let v = _mm_insert_epi16::<0>(v, c(p0, 0));
                let v = _mm_insert_epi16::<1>(v, c(p1, 0));
                let v = _mm_insert_epi16::<2>(v, c(p0, 1));
                let v = _mm_insert_epi16::<3>(v, c(p1, 1));
                let v = _mm_insert_epi16::<4>(v, c(p0, 2));
                _mm_insert_epi16::<5>(v, c(p1, 2))
            }),
            // Bytes interleaved (r0 r1 g0 g1 …), then each doubled: `c · 257` in 16 bits,
            // already in the interleaved order.
            (None, true) => gather_with(t, acc, |i0, i1| unsafe {
                let q = |i: usize| _mm_cvtsi32_si128(read8(base, i) as i32);
                let b = _mm_unpacklo_epi8(q(i0), q(i1));
                _mm_srli_epi16(_mm_unpacklo_epi8(b, b), 1)
            }),
            (_, false) => gather_with(t, acc, |i0, i1| unsafe {
                let q = |i: usize| {
                    let c = read8(base, i);
                    let q = match r.srgb {
                        Some(table) => srgb8(c, table),
                        None => linear8(c),
                    };
                    _mm_cvtsi64_si128(premultiply(q) as i64)
                };
                _mm_srli_epi16(_mm_unpacklo_epi16(q(i0), q(i1)), 1)
            }),
        },
    }
}

/// The 4-byte texel at index `i` of `base`, as a little-endian word.
///
/// # Safety
/// `base` must hold at least `4·(i + 1)` bytes.
#[inline(always)]
unsafe fn read8(base: *const u8, i: usize) -> u32 {
    // SAFETY: the caller's.
    u32::from_le(unsafe { base.add(i * 4).cast::<u32>().read_unaligned() })
}

/// An RGBA8 texel (`r` in the low byte) with sRGB colour, as four 16-bit linear channels
/// (`r` in the low 16 bits): colour through `table`, alpha `a · 257`.
#[inline(always)]
fn srgb8(c: u32, table: &[u16; 256]) -> u64 {
    u64::from(table[(c & 0xff) as usize])
        | u64::from(table[(c >> 8 & 0xff) as usize]) << 16
        | u64::from(table[(c >> 16 & 0xff) as usize]) << 32
        | u64::from((c >> 24) * 257) << 48
}

/// An RGBA8 texel of linear channels as four 16-bit ones (each `c · 257`).
#[inline(always)]
fn linear8(c: u32) -> u64 {
    let c = u64::from(c);
    let spread = (c & 0xff) | (c & 0xff00) << 8 | (c & 0xff_0000) << 16 | (c & 0xff00_0000) << 24;
    spread * 257
}

/// Four 16-bit straight-alpha channels (alpha the top one) with the colour times alpha,
/// rounded.
#[inline(always)]
fn premultiply(q: u64) -> u64 {
    let a = q >> 48;
    let times = |k: u32| ((q >> (16 * k) & 0xffff) * a + 32767) / 65535;
    times(0) | times(1) << 16 | times(2) << 32 | a << 48
}

/// [`gather`] with each pair of taps' texels (their indices given) loaded by `pair` as
/// 15-bit linear premultiplied channels, interleaved (r0 r1 g0 g1 b0 b1 a0 a1). Every
/// pixel's taps are summed, with no branch per pixel: their indices are in range for helper
/// pixels too, and the sums of pixels outside a quad's mask are dropped when finished.
#[inline(always)]
fn gather_with(t: &Taps, acc: &mut [__m128i; 4], pair: impl Fn(usize, usize) -> __m128i) {
    for j in 0..4 {
        // SAFETY: SSE2 is part of x86_64.
        unsafe {
            // Two taps' channels interleaved, as 15 bits, times their packed weights: one
            // multiply-add gives both taps' sum per channel.
            let pair = |k0: usize, k1: usize, w: i32| {
                let t = pair(t.offsets[k0][j] as usize, t.offsets[k1][j] as usize);
                _mm_madd_epi16(t, _mm_set1_epi32(w))
            };
            let sum = _mm_add_epi32(pair(0, 1, t.top[j]), pair(2, 3, t.bottom[j]));
            acc[j] = _mm_add_epi32(acc[j], sum);
        }
    }
}
