//! The taps of two points at once in AVX2 lanes ([`taps2`], [`taps2_levels`]: the
//! bilinear indices and 15-bit weights of [`super::super::sse2::taps`], lane for lane), and
//! the per-axis work they share with the nearest reads ([`nearest_axis`]).

use std::arch::x86_64::{
    __m256, __m256i, _mm256_add_epi32, _mm256_add_ps, _mm256_and_si256, _mm256_andnot_si256,
    _mm256_cmpeq_epi32, _mm256_cvtepi32_ps, _mm256_cvtps_epi32, _mm256_cvttps_epi32,
    _mm256_floor_ps, _mm256_max_ps, _mm256_min_epu32, _mm256_min_ps, _mm256_mul_ps,
    _mm256_mullo_epi32, _mm256_or_si256, _mm256_set1_epi32, _mm256_set1_ps, _mm256_set_m128,
    _mm256_set_m128i, _mm256_setzero_ps, _mm256_slli_epi32, _mm256_srli_epi32, _mm256_sub_epi32,
    _mm256_sub_ps, _mm_set1_epi32,
};

use glam::Vec4;

use super::super::sse2::Taps;
use super::Level;
use crate::texture::{Sampler, Wrap};

/// [`super::super::sse2::taps`] of a level of `size` ([`super::size`]) at two points,
/// `(u[k], v[k])` weighted `level_weight[k] / ONE` in all: `[taps(u[0], v[0], w[0]),
/// taps(u[1], v[1], w[1])]`, bit for bit. Inlined into its caller, so that in the hot
/// loops' x86-64-v3 copy ([`crate::cpu`]) its intrinsics inline too (a `#[target_feature]`
/// function cannot be `#[inline(always)]`, and as a call it cost a call per pair).
///
/// # Safety
/// The CPU must have AVX2 ([`crate::cpu::level`] is x86-64-v3).
#[inline(always)]
pub(super) unsafe fn taps2(
    size: (i32, i32),
    tiles_x: u32,
    s: &Sampler,
    u: [Vec4; 2],
    v: [Vec4; 2],
    level_weight: [i32; 2],
) -> [Taps; 2] {
    // SAFETY: the CPU has AVX2 (the caller's contract).
    unsafe { taps_in(&dims(size, tiles_x), s, u, v, totals(level_weight)) }
}

/// A level's width, height (`size`) and 16 × tiles per row, each in all eight lanes, as
/// [`taps_in`] takes them (`tiles_x` from its `tiled_texels`).
///
/// # Safety
/// The CPU must have AVX2.
#[inline(always)]
pub(super) unsafe fn dims((w, h): (i32, i32), tiles_x: u32) -> (__m256i, __m256i, __m256i) {
    // SAFETY: the CPU has AVX2 (the caller's contract).
    unsafe {
        (
            _mm256_set1_epi32(w),
            _mm256_set1_epi32(h),
            _mm256_set1_epi32(16 * tiles_x as i32),
        )
    }
}

/// Each half's 15-bit level weight in its four lanes, as [`taps_in`] takes them.
///
/// # Safety
/// The CPU must have AVX2.
#[inline(always)]
pub(super) unsafe fn totals(level_weight: [i32; 2]) -> __m256i {
    // SAFETY: the CPU has AVX2 (the caller's contract).
    unsafe {
        _mm256_set_m128i(
            _mm_set1_epi32(level_weight[1]),
            _mm_set1_epi32(level_weight[0]),
        )
    }
}

/// [`taps2`] with the two points on two levels: `[taps(a, u[0], v[0], w[0]), taps(b, u[1],
/// v[1], w[1])]` for levels `a` and `b` (each with its tiled texels and tiles per row), bit
/// for bit — a probe's two levels of a trilinear read at once.
///
/// # Safety
/// The CPU must have AVX2 ([`crate::cpu::level`] is x86-64-v3).
#[inline(always)]
pub(super) unsafe fn taps2_levels(
    (a, _, tiles_a): Level,
    (b, _, tiles_b): Level,
    s: &Sampler,
    u: [Vec4; 2],
    v: [Vec4; 2],
    level_weight: [i32; 2],
) -> [Taps; 2] {
    // SAFETY: the CPU has AVX2 (the caller's contract).
    unsafe {
        let halves = |x: i32, y: i32| _mm256_set_m128i(_mm_set1_epi32(y), _mm_set1_epi32(x));
        let dims = (
            halves(a.0, b.0),
            halves(a.1, b.1),
            halves(16 * tiles_a as i32, 16 * tiles_b as i32),
        );
        taps_in(&dims, s, u, v, totals(level_weight))
    }
}

/// [`taps2`]' and [`taps2_levels`]' work: each half's taps on a level of `dims` (width,
/// height, 16 × tiles per row, each as that half's four lanes), weighted `total` in all (that
/// half's 15-bit level weight in its four lanes).
///
/// # Safety
/// The CPU must have AVX2.
#[inline(always)]
pub(super) unsafe fn taps_in(
    &(w, h, stride): &(__m256i, __m256i, __m256i),
    s: &Sampler,
    u: [Vec4; 2],
    v: [Vec4; 2],
    total: __m256i,
) -> [Taps; 2] {
    // SAFETY: the CPU has AVX2 (the caller's contract), all these intrinsics need.
    unsafe {
        let wide = |x: [Vec4; 2]| _mm256_set_m128(x[1].into(), x[0].into());
        let (xa, xb, fx) = axis(s.wrap_u, wide(u), w);
        let (ya, yb, fy) = axis(s.wrap_v, wide(v), h);
        let one = _mm256_set1_ps(1.0);
        let (gx, gy) = (_mm256_sub_ps(one, fx), _mm256_sub_ps(one, fy));
        // Tiled index = column part + row part, as `taps` computes it.
        let three = _mm256_set1_epi32(3);
        let col = |x| {
            _mm256_or_si256(
                _mm256_slli_epi32(_mm256_srli_epi32(x, 2), 4),
                _mm256_and_si256(x, three),
            )
        };
        let row = |y| {
            let tile_row = _mm256_mullo_epi32(_mm256_srli_epi32(y, 2), stride);
            _mm256_add_epi32(tile_row, _mm256_slli_epi32(_mm256_and_si256(y, three), 2))
        };
        let (ca, cb, ra, rb) = (col(xa), col(xb), row(ya), row(yb));
        let offsets = [
            halves(_mm256_add_epi32(ca, ra)),
            halves(_mm256_add_epi32(cb, ra)),
            halves(_mm256_add_epi32(ca, rb)),
            halves(_mm256_add_epi32(cb, rb)),
        ];
        // Weights in 15 bits, the last one what the others leave (per half, its own total).
        let lw = _mm256_cvtepi32_ps(total);
        let round = |w: __m256| _mm256_cvtps_epi32(_mm256_mul_ps(w, lw));
        let w00 = round(_mm256_mul_ps(gx, gy));
        let w10 = round(_mm256_mul_ps(fx, gy));
        let w01 = round(_mm256_mul_ps(gx, fy));
        let w11 = _mm256_sub_epi32(_mm256_sub_epi32(_mm256_sub_epi32(total, w00), w10), w01);
        let low = _mm256_set1_epi32(0xffff);
        let pack = |a: __m256i, b: __m256i| {
            halves(_mm256_or_si256(
                _mm256_and_si256(a, low),
                _mm256_slli_epi32(b, 16),
            ))
        };
        let (top, bottom) = (pack(w00, w10), pack(w01, w11));
        std::array::from_fn(|k| Taps {
            offsets: [offsets[0][k], offsets[1][k], offsets[2][k], offsets[3][k]],
            top: top[k],
            bottom: bottom[k],
        })
    }
}

/// The two halves' lanes.
#[inline(always)]
pub(super) fn halves(v: __m256i) -> [[i32; 4]; 2] {
    // SAFETY: same size, every bit pattern valid for both.
    unsafe { std::mem::transmute::<__m256i, [[i32; 4]; 2]>(v) }
}

/// [`super::sse2`]'s `nearest_axis` in eight lanes: the same operations, in the same order.
///
/// # Safety
/// The CPU must have AVX2.
#[inline(always)]
pub(super) unsafe fn nearest_axis(wrap: Wrap, t: __m256, n: i32) -> __m256i {
    // SAFETY: the CPU has AVX2 (the caller's contract).
    unsafe {
        let nf = _mm256_set1_ps(n as f32);
        if wrap == Wrap::Repeat {
            // ⌊(t − ⌊t⌋)·n⌋ ∈ [0, n]: n wraps to 0, as a NaN lane (i32::MIN) reads 0.
            let frac = _mm256_sub_ps(t, _mm256_floor_ps(t));
            let i = _mm256_cvttps_epi32(_mm256_floor_ps(_mm256_mul_ps(frac, nf)));
            let wrapped = _mm256_or_si256(
                _mm256_cmpeq_epi32(i, _mm256_set1_epi32(n)),
                _mm256_cmpeq_epi32(i, _mm256_set1_epi32(i32::MIN)),
            );
            _mm256_min_epu32(_mm256_andnot_si256(wrapped, i), _mm256_set1_epi32(n - 1))
        } else {
            // `max` first: it returns its second operand (0) for a NaN lane.
            let i = _mm256_floor_ps(_mm256_mul_ps(t, nf));
            let i = _mm256_min_ps(
                _mm256_max_ps(i, _mm256_setzero_ps()),
                _mm256_set1_ps(n as f32 - 1.0),
            );
            _mm256_cvttps_epi32(i)
        }
    }
}

/// [`super::sse2`]'s `axis` in eight lanes, on a level `n` texels long (per lane): the same
/// operations, in the same order.
///
/// # Safety
/// The CPU must have AVX2.
#[inline(always)]
unsafe fn axis(wrap: Wrap, t: __m256, n: __m256i) -> (__m256i, __m256i, __m256) {
    // SAFETY: the CPU has AVX2 (the caller's contract).
    unsafe {
        let nf = _mm256_cvtepi32_ps(n);
        let half = _mm256_set1_ps(0.5);
        let p = if wrap == Wrap::Repeat {
            _mm256_sub_ps(
                _mm256_mul_ps(_mm256_sub_ps(t, _mm256_floor_ps(t)), nf),
                half,
            )
        } else {
            _mm256_sub_ps(_mm256_mul_ps(t, nf), half)
        };
        let i = _mm256_floor_ps(p);
        // As `sse2`'s: in [0, 1] without an upper clamp, 0 for a NaN lane.
        let frac = _mm256_max_ps(_mm256_sub_ps(p, i), _mm256_setzero_ps());
        if wrap == Wrap::Repeat {
            let one = _mm256_set1_epi32(1);
            let last = _mm256_sub_epi32(n, one);
            let lo = _mm256_cvttps_epi32(i);
            let hi = _mm256_add_epi32(lo, one);
            let hi = _mm256_andnot_si256(_mm256_cmpeq_epi32(hi, n), hi);
            (_mm256_min_epu32(lo, last), _mm256_min_epu32(hi, last), frac)
        } else {
            // `max` first: it returns its second operand (0) for a NaN lane.
            let top = _mm256_sub_ps(nf, _mm256_set1_ps(1.0));
            let clamp = |x: __m256| _mm256_min_ps(_mm256_max_ps(x, _mm256_setzero_ps()), top);
            (
                _mm256_cvttps_epi32(clamp(i)),
                _mm256_cvttps_epi32(clamp(_mm256_add_ps(i, _mm256_set1_ps(1.0)))),
                frac,
            )
        }
    }
}
