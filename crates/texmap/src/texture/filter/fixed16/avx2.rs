//! Two sets of taps at once in AVX2 lanes: [`super::sse2::taps`] of two points (eight
//! pixels' indices and weights) — two probes of a quad (anisotropic filtering, `ewa`: the
//! same levels at several points of one axis), or two quads of a trilinear batch on one pair
//! of levels. The same operations lane for lane as the SSE2 taps, so the same indices and
//! weights; the texels are then gathered probe by probe or quad by quad, two pixels to a
//! 256-bit vector (`avx2/gather.rs`).
//! Each probe's or quad's chain of dependent steps (coordinates, indices, weights) runs
//! beside its neighbour's. Nearest reads of the 8-bit storage decode a quad's four texels
//! here too ([`nearest_rgba8`]: the level's table gathered, two texels a vector).
//!
//! Runs where [`crate::cpu::level`] is x86-64-v3 (the callers check): the entry points
//! ([`probe_quad`], [`quad_pairs`], [`nearest_rgba8`]) are compiled for it, whatever copy
//! calls them.

use std::arch::x86_64::{
    __m128, __m128i, __m256i, _mm256_add_epi32, _mm256_and_si256, _mm256_castsi128_si256,
    _mm256_mul_ps, _mm256_mullo_epi32, _mm256_or_si256, _mm256_permutevar8x32_epi32,
    _mm256_set1_epi32, _mm256_set1_ps, _mm256_set_m128, _mm256_setr_epi32, _mm256_slli_epi32,
    _mm256_srli_epi32, _mm_add_ps, _mm_and_ps, _mm_castsi128_ps, _mm_cmpgt_epi32, _mm_cvtepi32_ps,
    _mm_cvttps_epi32, _mm_loadu_si128, _mm_movemask_ps, _mm_mul_ps, _mm_or_ps, _mm_set1_ps,
    _mm_setzero_si128, _mm_shuffle_epi32, _mm_sub_epi32,
};

use std::mem::MaybeUninit;

use glam::{Vec2, Vec4};

use super::prefetch::PREFETCH_BYTES;
use super::sse2::{self, Taps};
use super::{Probe, Texels, LEVEL_QUADS, MAX_PROBES, ONE};
use crate::texture::storage::LevelRef;
use crate::texture::{MipChoice, QuadCoords, Sampler};

mod gather;
mod taps;
use gather::{finish, gather, gather_shared, gather_weighted, weights, zero};
use taps::{dims, halves, nearest_axis, taps2, taps2_levels, taps_in};

/// A level's width and height ([`size`]), tiled texels and tiles per row (as
/// `tiled_texels` gives them): the parts of a level the probed reads use, copied where they
/// are held (a quad's read copied the whole level view before, 96 bytes a level).
pub(super) type Level<'a> = ((i32, i32), &'a [u8], u32);

/// A level's view, tiled texels and tiles per row, for the reads that also take the SSE2
/// path's ([`quad_pairs`]' odd last quad).
type LevelView<'a> = (&'a LevelRef<'a>, &'a [u8], u32);

/// Level `lv`'s width and height, as [`Level`] and [`taps2`] take them.
#[inline(always)]
pub(super) fn size(lv: &LevelRef) -> (i32, i32) {
    (lv.w, lv.h)
}

/// [`sse2::probes_on`] in AVX2 lanes, the whole quad: first the taps of every pair of
/// probes, both probes' taps on a level computed at once ([`level_taps2`]), then each
/// probe's texels gathered as the SSE2 loop gathers them (a probe whose weight on a level is
/// 0 not read there); an odd last probe takes its two levels' taps at once
/// ([`taps2_levels`]), or, read on one level, that level's taps by `taps2` (its second half
/// unused); the sums finished as [`sse2::finish`] finishes them. The same values. `levels`
/// are the first level and the second (`None` without a blend); `fa` the first level's
/// share of a probe's weight.
///
/// The two phases, rather than one loop reading each pair as soon as its taps were made:
/// the loop held the taps' constants and the sums at once and spilled them (306
/// instructions a pair); in two, `ewa`'s 1080p plane takes 0.89× the time, `aniso5-area`'s
/// 0.91× (docs/performance.md, "The 13:30 session's steps").
///
/// # Safety
/// The CPU must have x86-64-v3 ([`crate::cpu::level`]).
#[allow(clippy::too_many_arguments)]
#[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,movbe")]
pub(super) unsafe fn probe_quad(
    levels: (Level, Option<Level>),
    texels: Texels,
    s: &Sampler,
    fa: f32,
    uv: (Vec4, Vec4),
    step: Vec2,
    probes: &[Probe],
    mask: u8,
) -> [Vec4; 4] {
    // SAFETY: the CPU has x86-64-v3 (this function's contract).
    unsafe { probe_quad_inlined(levels, texels, s, fa, uv, step, probes, mask) }
}

/// [`probe_quad`], inlined into its caller: for the x86-64-v3 copy of a batch
/// (`ProbeReader`), where its intrinsics inline too and a quad pays no call (as a call per
/// quad it cost the 1080p plane's `aniso5-area` frame 2.8 % more instructions, 462.1 against
/// 449.5 M).
///
/// # Safety
/// The CPU must have x86-64-v3 ([`crate::cpu::level`]).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub(super) unsafe fn probe_quad_inlined(
    levels: (Level, Option<Level>),
    texels: Texels,
    s: &Sampler,
    fa: f32,
    (u, v): (Vec4, Vec4),
    step: Vec2,
    probes: &[Probe],
    mask: u8,
) -> [Vec4; 4] {
    // First every pair's taps on its levels (a level a pair weights 0 skipped), then the
    // texels read: each phase holds fewer values at once than one loop over both did.
    let (first, second) = levels;
    let mut taps = [const { MaybeUninit::<[Taps; 2]>::uninit() }; MAX_PROBES];
    // Bits 0 and 1: the first level's points read; 2 and 3: the second's.
    let mut reads = [0u8; MAX_PROBES / 2];
    let pairs = probes.len() / 2;
    for (i, pq) in probes.chunks_exact(2).enumerate() {
        let (p, q) = (pq[0], pq[1]);
        // Both probes' weights on the first level at once (`sse2::probe_first_weight`'s
        // rounding in two lanes), and what they leave the second.
        // SAFETY: `pq` is 16 contiguous bytes of `repr(C)` probes, weights in lanes 1 and
        // 3; the CPU has AVX2 (this function's contract).
        let (wa, wb) = unsafe {
            let w = _mm_shuffle_epi32::<0b11_01_11_01>(_mm_loadu_si128(pq.as_ptr().cast()));
            let wa = round_away(_mm_mul_ps(_mm_cvtepi32_ps(w), _mm_set1_ps(fa)));
            (wa, _mm_sub_epi32(w, wa))
        };
        let pu = [u + Vec4::splat(step.x * p.t), u + Vec4::splat(step.x * q.t)];
        let pv = [v + Vec4::splat(step.y * p.t), v + Vec4::splat(step.y * q.t)];
        // Each level spelled out (as a loop over the two, its iterator's bookkeeping cost
        // a tenth of the read's instructions).
        // SAFETY: the CPU has AVX2 (this function's contract).
        unsafe {
            let a = level_taps2(first, s, (pu, pv), wa, &mut taps[2 * i]);
            let b = match second {
                Some(second) => level_taps2(second, s, (pu, pv), wb, &mut taps[2 * i + 1]),
                None => 0,
            };
            reads[i] = a | b << 2;
        }
    }
    // An odd last probe's taps: its two levels' at once, or one level's (the other half
    // unused), with the texels each half reads.
    let lone = match probes[2 * pairs..] {
        [p] => {
            let wa = sse2::probe_first_weight(fa, p.weight);
            let wb = p.weight - wa;
            let (pu, pv) = (
                [u + Vec4::splat(step.x * p.t); 2],
                [v + Vec4::splat(step.y * p.t); 2],
            );
            // SAFETY: the CPU has AVX2 (this function's contract).
            unsafe {
                match second {
                    Some(second) if wa > 0 && wb > 0 => Some((
                        taps2_levels(first, second, s, pu, pv, [wa, wb]),
                        (first.1, Some(second.1)),
                    )),
                    Some((lv, data, tiles_x)) if wb > 0 => {
                        Some((taps2(lv, tiles_x, s, pu, pv, [wb, 0]), (data, None)))
                    }
                    _ if wa > 0 => {
                        let (lv, data, tiles_x) = first;
                        Some((taps2(lv, tiles_x, s, pu, pv, [wa, 0]), (data, None)))
                    }
                    _ => None,
                }
            }
        }
        _ => None,
    };
    // SAFETY: the CPU has AVX2 (this function's contract).
    let mut acc = unsafe { zero() };
    for (i, &read) in reads.iter().enumerate().take(pairs) {
        // SAFETY: the CPU has AVX2; a level's taps were written where its bits are set.
        unsafe {
            if read & 3 != 0 {
                let t = taps[2 * i].assume_init_ref();
                if read & 1 != 0 {
                    gather(first.1, texels, &t[0], &mut acc);
                }
                if read & 2 != 0 {
                    gather(first.1, texels, &t[1], &mut acc);
                }
            }
            if let (Some(second), true) = (second, read & 12 != 0) {
                let t = taps[2 * i + 1].assume_init_ref();
                if read & 4 != 0 {
                    gather(second.1, texels, &t[0], &mut acc);
                }
                if read & 8 != 0 {
                    gather(second.1, texels, &t[1], &mut acc);
                }
            }
        }
    }
    if let Some((taps, (a, b))) = &lone {
        // SAFETY: the CPU has AVX2 (this function's contract).
        unsafe {
            gather(a, texels, &taps[0], &mut acc);
            if let Some(b) = b {
                gather(b, texels, &taps[1], &mut acc);
            }
        }
    }
    // SAFETY: the CPU has AVX2 (this function's contract).
    unsafe { finish(&acc, mask) }
}

/// Bilinear reads of quads on a pair of levels, two quads at a time (`quads.rs`,
/// `trilinear.rs`): both quads' taps on a level computed at once ([`taps2`]), every pair's
/// first, then each quad's texels gathered as [`sse2::linear_weighted_on`] gathers them (a
/// level weighted 0 not read), an odd last quad by `linear_weighted_on`. The same values:
/// `out[i]` for `coords[i]`, `weights[i]` (the first level's and the second's 15-bit
/// weights) and `masks[i]`.
///
/// On a level larger than [`PREFETCH_BYTES`] each quad's lines are asked for as its taps
/// are made ([`super::prefetch::prefetch_corners`]), so that the run's misses overlap
/// rather than wait one pair after another: the 1080p plane's near rows read levels 0 and 1
/// of its 1024² checker (8 and 2 MiB), which no cache near the core holds.
///
/// # Safety
/// The CPU must have x86-64-v3 ([`crate::cpu::level`]); `coords` at most [`LEVEL_QUADS`]
/// long, `weights`, `masks` and `out` at least as long as it (checked).
#[allow(clippy::too_many_arguments)]
#[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,movbe")]
pub(super) unsafe fn quad_pairs(
    first: LevelView,
    second: LevelView,
    texels: Texels,
    s: &Sampler,
    coords: &[QuadCoords],
    weights: &[[i32; 2]],
    masks: &[u8],
    out: &mut [[Vec4; 4]],
) {
    let n = coords.len();
    assert!(n <= LEVEL_QUADS && weights.len() >= n && masks.len() >= n && out.len() >= n);
    let pairs = n / 2;
    let pair_weights = |p: usize| {
        let (w0, w1) = (weights[2 * p], weights[2 * p + 1]);
        ([w0[0], w1[0]], [w0[1], w1[1]])
    };
    // First every pair's taps on both levels (the second skipped where both quads weight
    // it 0), each level's lines asked for as soon as its taps are known where the level is
    // larger than an L1 cache ...
    let (size, far) = (sse2::bpp(texels), first.1.len() > PREFETCH_BYTES);
    let mut taps = [[const { MaybeUninit::<[Taps; 2]>::uninit() }; 2]; LEVEL_QUADS / 2];
    for (p, t) in taps.iter_mut().enumerate().take(pairs) {
        let c = &coords[2 * p..2 * p + 2];
        let (u, v) = ([c[0].u, c[1].u], [c[0].v, c[1].v]);
        let (wa, wb) = pair_weights(p);
        // SAFETY: the CPU has AVX2 (this function's contract).
        let ta = t[0].write(unsafe { taps2(self::size(first.0), first.2, s, u, v, wa) });
        if far {
            super::prefetch::prefetch_corners(first.1, size, &ta[0]);
            super::prefetch::prefetch_corners(first.1, size, &ta[1]);
        }
        if wb[0] > 0 || wb[1] > 0 {
            // SAFETY: as above.
            let tb = t[1].write(unsafe { taps2(self::size(second.0), second.2, s, u, v, wb) });
            if far && second.1.len() > PREFETCH_BYTES {
                super::prefetch::prefetch_corners(second.1, size, &tb[0]);
                super::prefetch::prefetch_corners(second.1, size, &tb[1]);
            }
        }
    }
    // ... then the texels read, pair by pair.
    for (p, t) in taps.iter().enumerate().take(pairs) {
        let i = 2 * p;
        let (wa, wb) = pair_weights(p);
        let mut acc = [zero(); 2];
        // SAFETY: the CPU has AVX2 (this function's contract); the first level's taps were
        // written above, the second's where a weight on it is positive (read only there).
        // Spelled out for the two quads and levels (as a loop it stayed one, its sums kept
        // in memory).
        unsafe {
            if wa[0] > 0 {
                gather(first.1, texels, &t[0].assume_init_ref()[0], &mut acc[0]);
            }
            if wa[1] > 0 {
                gather(first.1, texels, &t[0].assume_init_ref()[1], &mut acc[1]);
            }
            if wb[0] > 0 {
                gather(second.1, texels, &t[1].assume_init_ref()[0], &mut acc[0]);
            }
            if wb[1] > 0 {
                gather(second.1, texels, &t[1].assume_init_ref()[1], &mut acc[1]);
            }
        }
        out[i] = finish(&acc[0], masks[i]);
        out[i + 1] = finish(&acc[1], masks[i + 1]);
    }
    let i = 2 * pairs;
    if i < n {
        let c = &coords[i];
        out[i] = sse2::linear_weighted_on(first, second, texels, s, weights[i], c.u, c.v, masks[i]);
    }
}

/// Two points' taps on one level weighted `w` (lanes 0 and 1), written to `out` where a
/// point's weight is positive: the mask of the points to read (bit `k` for point `k`; 0, and
/// `out` left, when neither is).
///
/// # Safety
/// The CPU must have AVX2 ([`crate::cpu::level`] is x86-64-v3).
#[inline(always)]
unsafe fn level_taps2(
    (lv, _, tiles_x): Level,
    s: &Sampler,
    (u, v): ([Vec4; 2], [Vec4; 2]),
    w: __m128i,
    out: &mut MaybeUninit<[Taps; 2]>,
) -> u8 {
    // SAFETY: the CPU has AVX2 (this function's contract).
    let read = unsafe { _mm_movemask_ps(_mm_castsi128_ps(_mm_cmpgt_epi32(w, zero128()))) & 3 };
    if read != 0 {
        // SAFETY: as above.
        out.write(unsafe {
            let total = _mm256_permutevar8x32_epi32(
                _mm256_castsi128_si256(w),
                _mm256_setr_epi32(0, 0, 0, 0, 1, 1, 1, 1),
            );
            taps_in(&dims(lv, tiles_x), s, u, v, total)
        });
    }
    read as u8
}

/// An all-zero 128-bit vector.
///
/// # Safety
/// The CPU must have SSE2 (every x86_64 has).
#[inline(always)]
unsafe fn zero128() -> __m128i {
    // SAFETY: SSE2 is part of x86_64.
    unsafe { _mm_setzero_si128() }
}

/// `x` rounded half away from zero to integers, as `f32::round` and `as i32` round a value
/// within ±2²³: the bits of `trunc(x + copysign(0.49999997, x))` (the largest float below
/// ½: ½ itself would take 0.49999997 to 1).
///
/// # Safety
/// The CPU must have SSE2 (every x86_64 has).
#[inline(always)]
unsafe fn round_away(x: __m128) -> __m128i {
    // SAFETY: SSE2 is part of x86_64.
    unsafe {
        let sign = _mm_and_ps(x, _mm_set1_ps(-0.0));
        let below_half = _mm_or_ps(sign, _mm_set1_ps(f32::from_bits(0x3eff_ffff)));
        _mm_cvttps_epi32(_mm_add_ps(x, below_half))
    }
}

/// [`super::read_pair_shared`]: two quads' reads of every texture of `shared`, both quads on
/// the same levels, their taps on each level computed at once ([`taps2`]) and each
/// texture's texels gathered quad by quad as [`sse2::linear_quad_shared`] gathers them (a
/// level whose weight is 0 for a quad not read for it). The same values.
///
/// # Safety
/// The CPU must have x86-64-v3 ([`crate::cpu::level`]); both `choices` must name the same
/// levels.
#[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,movbe")]
pub(super) unsafe fn linear_pair_shared(
    shared: &super::Shared,
    s: &Sampler,
    choices: [MipChoice; 2],
    coords: [&QuadCoords; 2],
    masks: [u8; 2],
    out: &mut [[[Vec4; 4]; super::MAX_SHARED]; 2],
) {
    let count = shared.len();
    let texels = shared.texels;
    let wa = choices.map(sse2::first_weight);
    let wb = [0, 1].map(|k| sse2::second_weight(choices[k], wa[k]));
    let (u, v) = ([coords[0].u, coords[1].u], [coords[0].v, coords[1].v]);
    let mut acc = [[zero(); super::MAX_SHARED]; 2];
    let second = choices[0].blend.map(|b| b.level);
    // (Asked at every pair: as a field of `shared`, set once, the lit helmet's two frames
    // took 0.4 M instructions more, not fewer.)
    let in_lanes = texels[..count].iter().all(|t| t.in_lanes());
    for (index, w) in [(Some(choices[0].level), wa), (second, wb)] {
        let Some(index) = index.filter(|_| w[0] > 0 || w[1] > 0) else {
            continue;
        };
        let lv = shared.level(index);
        // SAFETY: the CPU has AVX2 (this function's contract).
        let taps = unsafe { taps2(size(&lv.first), lv.tiles_x, s, u, v, w) };
        for ((t, w), acc) in taps.iter().zip(w).zip(&mut acc) {
            if w <= 0 {
                continue;
            }
            // SAFETY: the CPU has AVX2 (this function's contract).
            let weights = unsafe { weights(t) };
            // Each texture's level is of the first one's size and tiling (checked when the
            // level was looked up), so the first one's indices are in range for every one.
            if in_lanes {
                // SAFETY: as above; every texture's texels are read in lanes (checked).
                unsafe { gather_shared(&lv.data[..count], &texels[..count], t, &weights, acc) };
                continue;
            }
            for ((data, &texels), acc) in lv.data.iter().zip(&texels[..count]).zip(acc.iter_mut()) {
                unsafe { gather_weighted(data, texels, t, &weights, acc) };
            }
        }
    }
    for ((o, acc), &mask) in out.iter_mut().zip(&acc).zip(&masks) {
        for (o, acc) in o.iter_mut().zip(acc).take(count) {
            *o = finish(acc, mask);
        }
    }
}

/// [`sse2::taps`] of quads on one level, each weighted [`ONE`], two quads at a time (an odd
/// last quad by `taps`): written to `out[i]` for `coords[i]`, the same taps; returns them
/// (`out`'s first `coords.len()`). `out` need not be initialized: a batch's taps were 12
/// instructions a quad more when their array was zeroed first (1,536 bytes a batch).
///
/// # Safety
/// The CPU must have x86-64-v3 ([`crate::cpu::level`]); `out` at least as long as `coords`
/// (checked).
#[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,movbe")]
pub(super) unsafe fn level_taps<'o>(
    lv: &LevelRef,
    tiles_x: u32,
    s: &Sampler,
    coords: &[QuadCoords],
    out: &'o mut [MaybeUninit<Taps>],
) -> &'o [Taps] {
    let n = coords.len();
    let out = &mut out[..n];
    let mut pairs = coords.chunks_exact(2);
    for (c, o) in (&mut pairs).zip(out.chunks_exact_mut(2)) {
        let (u, v) = ([c[0].u, c[1].u], [c[0].v, c[1].v]);
        // SAFETY: the CPU has AVX2 (this function's contract).
        let [a, b] = unsafe { taps2(size(lv), tiles_x, s, u, v, [ONE, ONE]) };
        o[0].write(a);
        o[1].write(b);
    }
    if let [c] = pairs.remainder() {
        out[n - 1].write(sse2::taps(lv, tiles_x, s, c.u, c.v, ONE));
    }
    // SAFETY: every one of `out`'s `n` elements was written above (the pairs, then an odd
    // last one), and `MaybeUninit<Taps>` has `Taps`' layout.
    unsafe { std::slice::from_raw_parts(out.as_ptr().cast::<Taps>(), n) }
}

/// Each quad's texels at its `taps` (on one level, whose tiled texels are `data`) gathered
/// two pixels to a 256-bit vector and finished: `out[i]` = `sse2::gather` then
/// `sse2::finish` of `taps[i]` and `masks[i]`, the same values (a bilinear batch on one level,
/// `quads.rs`).
///
/// # Safety
/// The CPU must have x86-64-v3 ([`crate::cpu::level`]); `taps` must index `data` as
/// [`level_taps`] makes them for its level; `masks` and `out` at least as long as `taps`
/// (checked).
#[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,movbe")]
pub(super) unsafe fn gather_quads(
    data: &[u8],
    texels: Texels,
    taps: &[Taps],
    masks: &[u8],
    out: &mut [[Vec4; 4]],
) {
    assert!(masks.len() >= taps.len() && out.len() >= taps.len());
    for ((t, &mask), out) in taps.iter().zip(masks).zip(out) {
        // SAFETY: the CPU has AVX2 (this function's contract), `t` indexes `data` (the
        // caller's).
        unsafe {
            let mut acc = zero();
            gather(data, texels, t, &mut acc);
            *out = finish(&acc, mask);
        }
    }
}

/// [`sse2::nearest_offsets`] of quads on one level, two quads at a time (an odd last quad by
/// `nearest_offsets`): `out[i]` for `coords[i]`, the same indices.
///
/// # Safety
/// The CPU must have x86-64-v3 ([`crate::cpu::level`]); `out` at least as long as `coords`
/// (checked).
#[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,movbe")]
pub(super) unsafe fn level_nearest(
    lv: &LevelRef,
    tiles_x: u32,
    s: &Sampler,
    coords: &[QuadCoords],
    out: &mut [[i32; 4]],
) {
    assert!(out.len() >= coords.len());
    let wide = |a: Vec4, b: Vec4| _mm256_set_m128(b.into(), a.into());
    let three = _mm256_set1_epi32(3);
    let stride = _mm256_set1_epi32(16 * tiles_x as i32);
    let mut pairs = coords.chunks_exact(2);
    for (c, o) in (&mut pairs).zip(out.chunks_exact_mut(2)) {
        // SAFETY: the CPU has AVX2 (this function's contract).
        let (x, y) = unsafe {
            (
                nearest_axis(s.wrap_u, wide(c[0].u, c[1].u), lv.w),
                nearest_axis(s.wrap_v, wide(c[0].v, c[1].v), lv.h),
            )
        };
        // As `nearest_offsets`: column part + row part of the tiled index.
        let col = _mm256_or_si256(
            _mm256_slli_epi32(_mm256_srli_epi32(x, 2), 4),
            _mm256_and_si256(x, three),
        );
        let row = _mm256_add_epi32(
            _mm256_mullo_epi32(_mm256_srli_epi32(y, 2), stride),
            _mm256_slli_epi32(_mm256_and_si256(y, three), 2),
        );
        let [a, b] = halves(_mm256_add_epi32(col, row));
        (o[0], o[1]) = (a, b);
    }
    if let [c] = pairs.remainder() {
        out[coords.len() - 1] = sse2::nearest_offsets(lv, tiles_x, s, c.u, c.v);
    }
}

/// [`sse2::nearest_texels`] of an RGBA8 level ([`Texels::Rgba8`]) for quads of a batch,
/// `out[i]` for `offsets[i]` and `masks[i]`: each quad's four texels gathered at once and
/// decoded in lanes, two texels a vector, with the codec's operations lane for lane (the
/// level's table for the colour, `a · (1/255)` for alpha, the colour times alpha), so the
/// same values as its scalar decode, texel by texel.
///
/// # Safety
/// The CPU must have x86-64-v3 ([`crate::cpu::level`]); every index in `offsets` must be in
/// range for the level (4 bytes a texel), as [`level_nearest`] gives them, pixels outside
/// the mask too.
#[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,movbe")]
pub(super) unsafe fn nearest_rgba8(
    lv: &LevelRef,
    data: &[u8],
    offsets: &[[i32; 4]],
    masks: &[u8],
    out: &mut [[Vec4; 4]],
) {
    use std::arch::x86_64::{
        _mm256_blend_ps, _mm256_castps256_ps128, _mm256_cvtepi32_ps, _mm256_cvtepu8_epi32,
        _mm256_extractf128_ps, _mm256_i32gather_ps, _mm256_permute_ps, _mm_i32gather_epi32,
        _mm_loadu_si128, _mm_unpackhi_epi64,
    };
    let lut = lv.lut();
    assert!(lut.len() >= 256 && masks.len() >= offsets.len() && out.len() >= offsets.len());
    let (texels, table) = (data.as_ptr().cast::<i32>(), lut.as_ptr());
    let scale = _mm256_set1_ps(1.0 / 255.0);
    // Two texels' channels (8 codes as 32-bit lanes) decoded and premultiplied.
    let decode = |codes: __m256i| {
        // SAFETY: the CPU has AVX2 (this function's contract); every code is below 256,
        // the table's length (checked).
        unsafe {
            let colour = _mm256_i32gather_ps::<4>(table, codes);
            let alpha = _mm256_mul_ps(_mm256_cvtepi32_ps(codes), scale);
            let v = _mm256_blend_ps::<0b1000_1000>(colour, alpha);
            let a = _mm256_permute_ps::<0b1111_1111>(v);
            _mm256_blend_ps::<0b1000_1000>(_mm256_mul_ps(v, a), v)
        }
    };
    for ((o, &mask), out) in offsets.iter().zip(masks).zip(out) {
        // SAFETY: as above; the indices are in range (this function's contract).
        let [t0, t1, t2, t3] = unsafe {
            let quad = _mm_i32gather_epi32::<4>(texels, _mm_loadu_si128(o.as_ptr().cast()));
            let first = decode(_mm256_cvtepu8_epi32(quad));
            let last = decode(_mm256_cvtepu8_epi32(_mm_unpackhi_epi64(quad, quad)));
            [
                _mm256_castps256_ps128(first),
                _mm256_extractf128_ps::<1>(first),
                _mm256_castps256_ps128(last),
                _mm256_extractf128_ps::<1>(last),
            ]
        };
        *out = sse2::masked([t0, t1, t2, t3].map(Vec4::from), mask);
    }
}

#[cfg(test)]
mod tests;
