//! The AVX2 gathers of [`super`]: each pixel's four bilinear taps of one level, two pixels
//! to a 256-bit vector, summed into its accumulator with their 15-bit weights — the 16-bit
//! storage's texels and opaque 8-bit ones with linear codes; other storages by the SSE2
//! gather. The same sums as `sse2::gather` (integer multiply-adds, in any order), held two
//! pixels to a vector ([`Sums`]) and finished as `sse2::finish` finishes them ([`finish`]).

use std::arch::x86_64::{
    __m128i, __m256i, _mm256_add_epi32, _mm256_and_ps, _mm256_castsi128_si256, _mm256_castsi256_ps,
    _mm256_cvtepi32_ps, _mm256_loadu_si256, _mm256_madd_epi16, _mm256_max_ps, _mm256_mul_ps,
    _mm256_permutevar8x32_epi32, _mm256_set1_ps, _mm256_set_m128i, _mm256_setr_epi32,
    _mm256_setzero_ps, _mm256_setzero_si256, _mm256_srli_epi16, _mm256_unpacklo_epi8,
    _mm_cvtsi32_si128, _mm_loadl_epi64, _mm_loadu_si128, _mm_setzero_si128, _mm_unpacklo_epi16,
    _mm_unpacklo_epi8,
};

use glam::Vec4;

use super::super::sse2::{self, Taps};
use super::super::{Texels, ONE};

/// A quad's 32-bit sums, two pixels to a vector: pixel `2k` in the low half of `[k]`, pixel
/// `2k + 1` in its high half (`sse2`'s four accumulators, paired).
pub(in super::super) type Sums = [__m256i; 2];

/// Sums of zero.
///
/// # Safety
/// The CPU must have AVX2.
#[inline(always)]
pub(in super::super) unsafe fn zero() -> Sums {
    // SAFETY: the CPU has AVX2 (the caller's contract).
    unsafe { [_mm256_setzero_si256(); 2] }
}

/// A pair of pixels' lanes kept by [`finish`], by the pair's two mask bits (the first pixel's
/// the low bit): all ones where a pixel is kept. (Built from the bits lane by lane, the
/// masks were 16 instructions a quad, 2.7 % of the bilinear plane's.)
static PAIR_LANES: [[i32; 8]; 4] = [
    [0; 8],
    [-1, -1, -1, -1, 0, 0, 0, 0],
    [0, 0, 0, 0, -1, -1, -1, -1],
    [-1; 8],
];

/// [`sse2::finish`] of the paired sums: the same values (pixels outside `mask` zero).
///
/// # Safety
/// The CPU must have AVX2.
#[inline(always)]
pub(in super::super) unsafe fn finish(acc: &Sums, mask: u8) -> [Vec4; 4] {
    // SAFETY: the CPU has AVX2 (the caller's contract).
    unsafe {
        let scale = _mm256_set1_ps(1.0 / (ONE as f32 * ONE as f32));
        let pair = |k: usize| {
            let kept = &PAIR_LANES[usize::from(mask >> (2 * k)) & 3];
            let lanes = _mm256_loadu_si256(kept.as_ptr().cast());
            // A tap whose rounded weight came out −1 can leave a sum a hair below zero.
            let sum = _mm256_mul_ps(_mm256_cvtepi32_ps(acc[k]), scale);
            let sum = _mm256_max_ps(sum, _mm256_setzero_ps());
            std::mem::transmute::<_, [Vec4; 2]>(_mm256_and_ps(sum, _mm256_castsi256_ps(lanes)))
        };
        let ([p0, p1], [p2, p3]) = (pair(0), pair(1));
        [p0, p1, p2, p3]
    }
}

/// [`sse2::gather`]: the 16-bit storage's texels, and opaque RGBA8 texels with linear codes
/// (data maps), two pixels to a 256-bit vector (each pixel's top pair in one half, its bottom
/// pair in the other, as the SSE2 loop interleaves them; one shift and one multiply-add for
/// two pixels' pairs), other storages by `sse2::gather`. The same sums: each pixel's four
/// products added into its accumulator.
///
/// # Safety
/// The CPU must have AVX2 ([`crate::cpu::level`] is x86-64-v3).
#[inline(always)]
pub(in super::super) unsafe fn gather(data: &[u8], texels: Texels, t: &Taps, acc: &mut Sums) {
    // Its own match, not `gather_weighted(.., &weights(t), ..)`: that made the 1080p plane's
    // frame 1.2 % more instructions (bilinear), aniso6's 1.4 %.
    match texels {
        // SAFETY: the CPU has AVX2 (this function's contract).
        Texels::Linear16 => unsafe { gather16(data, t, &weights(t), acc) },
        // SAFETY: as above (opaque linear codes: data maps).
        Texels::Rgba8(r) if r.opaque_linear() => unsafe { gather8(data, t, &weights(t), acc) },
        // SAFETY: the CPU has AVX2 (this function's contract).
        _ => unsafe {
            let mut part = [_mm_setzero_si128(); 4];
            sse2::gather(data, texels, t, &mut part);
            acc[0] = _mm256_add_epi32(acc[0], _mm256_set_m128i(part[1], part[0]));
            acc[1] = _mm256_add_epi32(acc[1], _mm256_set_m128i(part[3], part[2]));
        },
    }
}

/// A tap set's packed weights as [`gather_pairs`] multiplies them: `[j / 2][0]` the top
/// pair's and `[j / 2][1]` the bottom pair's of pixels `j` and `j + 1` (each pixel's in its
/// half). Made once where several textures are read through the same taps
/// ([`gather_weighted`]).
pub(in super::super) type Weights = [[__m256i; 2]; 2];

/// The [`Weights`] of taps `t`.
///
/// # Safety
/// The CPU must have AVX2.
#[inline(always)]
pub(in super::super) unsafe fn weights(t: &Taps) -> Weights {
    // SAFETY: the CPU has AVX2 (this function's contract).
    unsafe {
        let top = _mm256_castsi128_si256(_mm_loadu_si128(t.top.as_ptr().cast()));
        let bottom = _mm256_castsi128_si256(_mm_loadu_si128(t.bottom.as_ptr().cast()));
        // Written out: as `array::map` the closure was left as a call (in every gather).
        let pair = |j: i32| {
            let lanes = _mm256_setr_epi32(j, j, j, j, j + 1, j + 1, j + 1, j + 1);
            [
                _mm256_permutevar8x32_epi32(top, lanes),
                _mm256_permutevar8x32_epi32(bottom, lanes),
            ]
        };
        [pair(0), pair(2)]
    }
}

/// [`gather`] with the taps' [`Weights`] made beforehand (`w` = `weights(t)`): the same sums.
/// The shared reads gather every texture through one level's taps, so they make the weights
/// once (8 instructions a texture a quad fewer).
///
/// # Safety
/// As [`gather`]; `w` must be `weights(t)`.
#[inline(always)]
pub(in super::super) unsafe fn gather_weighted(
    data: &[u8],
    texels: Texels,
    t: &Taps,
    w: &Weights,
    acc: &mut Sums,
) {
    match texels {
        // SAFETY: the CPU has AVX2 (this function's contract).
        Texels::Linear16 => unsafe { gather16(data, t, w, acc) },
        // SAFETY: as above (opaque linear codes: data maps).
        Texels::Rgba8(r) if r.opaque_linear() => unsafe { gather8(data, t, w, acc) },
        // SAFETY: the CPU has AVX2 (this function's contract).
        _ => unsafe { gather(data, texels, t, acc) },
    }
}

/// [`gather_weighted`] of several textures through the same taps `t` (`data[k]`'s texels,
/// of kind `texels[k]`, summed into `acc[k]`), each pixel pair's eight offsets loaded once
/// for every texture: texture by texture, the offsets were loaded again for each (half of
/// a texture's loads). The same products, each texture's added in the same order, so the
/// same sums.
///
/// # Safety
/// The CPU must have AVX2; every `texels[k]` must be read in lanes (`Texels::in_lanes`),
/// and `t`'s offsets must index texels of every `data[k]` (a level of the size they were
/// made for, as `sse2::taps` makes them); `w` = `weights(t)`.
#[inline(always)]
pub(in super::super) unsafe fn gather_shared(
    data: &[&[u8]],
    texels: &[Texels],
    t: &Taps,
    w: &Weights,
    acc: &mut [Sums],
) {
    // SAFETY: the CPU has AVX2 (this function's contract); each load reads one texel (8
    // bytes of the 16-bit storage, 4 of the 8-bit one) at an offset `t` makes for this
    // level, which every `data[k]` holds (the caller's).
    unsafe {
        for j in [0, 2] {
            let at = |k: usize, p: usize| t.offsets[k][p];
            // Pixels `j` and `j + 1`: taps 0 and 1 (the top pair), then taps 2 and 3.
            let o = [
                [at(0, j), at(1, j), at(0, j + 1), at(1, j + 1)],
                [at(2, j), at(3, j), at(2, j + 1), at(3, j + 1)],
            ];
            let [top, bottom] = w[j / 2];
            for ((d, &texels), acc) in data.iter().zip(texels).zip(acc.iter_mut()) {
                let base = d.as_ptr();
                // As `gather_pairs` makes a pair, through `gather16`'s and `gather8`'s halves.
                let pairs = if matches!(texels, Texels::Linear16) {
                    o.map(|[a, b, c, e]| {
                        let v = _mm256_set_m128i(half16(base, c, e), half16(base, a, b));
                        _mm256_srli_epi16::<1>(v)
                    })
                } else {
                    o.map(|[a, b, c, e]| {
                        let v = _mm256_set_m128i(half8(base, c, e), half8(base, a, b));
                        _mm256_srli_epi16::<1>(widen8(v))
                    })
                };
                let sum = _mm256_add_epi32(
                    _mm256_madd_epi16(pairs[0], top),
                    _mm256_madd_epi16(pairs[1], bottom),
                );
                acc[j / 2] = _mm256_add_epi32(acc[j / 2], sum);
            }
        }
    }
}

/// [`gather`] of the 16-bit storage.
///
/// # Safety
/// The CPU must have AVX2; `t`'s offsets index 8-byte texels of `data` (as `sse2::taps`
/// makes them); `w` = `weights(t)`.
#[inline(always)]
unsafe fn gather16(data: &[u8], t: &Taps, w: &Weights, acc: &mut Sums) {
    let base = data.as_ptr();
    // SAFETY (the loads): each reads one 8-byte texel at an index below `data.len() / 8`
    // (the offsets' level has this size, see `sse2::taps`); the CPU has AVX2.
    unsafe {
        gather_pairs(t, w, acc, |o0, o1| half16(base, o0, o1), |v| v);
    }
}

/// Two 8-byte texels of the 16-bit storage at `base` (indices `o0`, `o1`), their channels
/// interleaved in 128 bits: one pixel's pair of taps ([`gather16`], [`gather_shared`]).
///
/// # Safety
/// The CPU must have AVX2; both indices must be texels of the level at `base`.
#[inline(always)]
unsafe fn half16(base: *const u8, o0: i32, o1: i32) -> __m128i {
    // SAFETY: this function's contract.
    unsafe {
        let q = |i: i32| _mm_loadl_epi64(base.add(i as usize * 8).cast());
        _mm_unpacklo_epi16(q(o0), q(o1))
    }
}

/// [`gather`] of opaque RGBA8 texels with linear codes: `sse2::gather`'s bytes interleaved
/// (r0 r1 g0 g1 …), two pixels' to a vector, then each byte doubled (`c · 257` in 16 bits)
/// for both at once. The same 15-bit values, so the same sums.
///
/// # Safety
/// The CPU must have AVX2; `t`'s offsets index 4-byte texels of `data`; `w` = `weights(t)`.
#[inline(always)]
unsafe fn gather8(data: &[u8], t: &Taps, w: &Weights, acc: &mut Sums) {
    let base = data.as_ptr();
    // SAFETY (the loads): each reads one 4-byte texel at an index below `data.len() / 4`
    // (the offsets' level has this size, see `sse2::taps`); the CPU has AVX2.
    unsafe {
        gather_pairs(t, w, acc, |o0, o1| half8(base, o0, o1), |v| widen8(v));
    }
}

/// Two opaque RGBA8 texels at `base` (indices `o0`, `o1`), their bytes interleaved
/// (r0 r1 g0 g1 …) in the low 64 bits: one pixel's pair of taps before [`widen8`].
///
/// # Safety
/// The CPU must have AVX2; both indices must be texels of the level at `base`.
#[inline(always)]
unsafe fn half8(base: *const u8, o0: i32, o1: i32) -> __m128i {
    // SAFETY: this function's contract.
    unsafe {
        let q = |i: i32| _mm_cvtsi32_si128(base.add(i as usize * 4).cast::<i32>().read_unaligned());
        _mm_unpacklo_epi8(q(o0), q(o1))
    }
}

/// Two pixels' [`half8`] pairs of taps, each byte doubled to 16 bits (`c · 257`).
///
/// # Safety
/// The CPU must have AVX2.
#[inline(always)]
unsafe fn widen8(v: __m256i) -> __m256i {
    // SAFETY: this function's contract.
    unsafe { _mm256_unpacklo_epi8(v, v) }
}

/// The gathers' sums: for pixels `j` and `j + 1` at once, each pixel's two pairs of taps
/// (`pair` interleaves two taps' channels in the low 8 or 16 bytes; `widen` makes both
/// pixels' 16-bit values) taken to 15 bits and multiplied by their packed weights `w`, each
/// pixel's four products added into its sums.
///
/// # Safety
/// The CPU must have AVX2; `pair` must only read within its texels' level.
#[inline(always)]
unsafe fn gather_pairs(
    t: &Taps,
    w: &Weights,
    acc: &mut Sums,
    pair: impl Fn(i32, i32) -> __m128i,
    widen: impl Fn(__m256i) -> __m256i,
) {
    // SAFETY: the CPU has AVX2 (this function's contract).
    unsafe {
        for j in [0, 2] {
            // Taps `k0` and `k1` of pixels `j` and `j + 1`, interleaved, as 15 bits.
            let pair = |k0: usize, k1: usize| {
                let o = (&t.offsets[k0], &t.offsets[k1]);
                let lo = pair(o.0[j], o.1[j]);
                let hi = pair(o.0[j + 1], o.1[j + 1]);
                _mm256_srli_epi16::<1>(widen(_mm256_set_m128i(hi, lo)))
            };
            let [top, bottom] = w[j / 2];
            let sum = _mm256_add_epi32(
                _mm256_madd_epi16(pair(0, 1), top),
                _mm256_madd_epi16(pair(2, 3), bottom),
            );
            acc[j / 2] = _mm256_add_epi32(acc[j / 2], sum);
        }
    }
}
