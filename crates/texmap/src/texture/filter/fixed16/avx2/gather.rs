//! The AVX2 gathers of [`super`]: each pixel's four bilinear taps of one level, two pixels
//! to a 256-bit vector, summed into its accumulator with their 15-bit weights — the 16-bit
//! storage's texels and opaque 8-bit ones with linear codes; other storages by the SSE2
//! gather. The same sums as `sse2::gather` (integer multiply-adds, in any order).

use std::arch::x86_64::{
    __m128i, __m256i, _mm256_add_epi32, _mm256_castsi128_si256, _mm256_castsi256_si128,
    _mm256_extracti128_si256, _mm256_madd_epi16, _mm256_permutevar8x32_epi32, _mm256_set_m128i,
    _mm256_setr_epi32, _mm256_srli_epi16, _mm256_unpacklo_epi8, _mm_add_epi32, _mm_cvtsi32_si128,
    _mm_loadl_epi64, _mm_loadu_si128, _mm_unpacklo_epi16, _mm_unpacklo_epi8,
};

use super::super::sse2::{self, Taps};
use super::super::Texels;

/// [`sse2::gather`]: the 16-bit storage's texels, and opaque RGBA8 texels with linear codes
/// (data maps), two pixels to a 256-bit vector (each pixel's top pair in one half, its bottom
/// pair in the other, as the SSE2 loop interleaves them; one shift and one multiply-add for
/// two pixels' pairs), other storages by `sse2::gather`. The same sums: each pixel's four
/// products added into its accumulator.
///
/// # Safety
/// The CPU must have AVX2 ([`crate::cpu::level`] is x86-64-v3).
#[inline(always)]
pub(super) unsafe fn gather(data: &[u8], texels: Texels, t: &Taps, acc: &mut [__m128i; 4]) {
    match texels {
        // SAFETY: the CPU has AVX2 (this function's contract).
        Texels::Linear16 => unsafe { gather16(data, t, acc) },
        // Opaque linear codes (data maps: normals, metallic-roughness, occlusion).
        Texels::Rgba8(r) if r.srgb15.is_none() && r.opaque => unsafe { gather8(data, t, acc) },
        _ => sse2::gather(data, texels, t, acc),
    }
}

/// [`gather`] of the 16-bit storage.
///
/// # Safety
/// The CPU must have AVX2; `t`'s offsets index 8-byte texels of `data` (as `sse2::taps`
/// makes them).
#[inline(always)]
unsafe fn gather16(data: &[u8], t: &Taps, acc: &mut [__m128i; 4]) {
    let base = data.as_ptr();
    // SAFETY (the loads): each reads one 8-byte texel at an index below `data.len() / 8`
    // (the offsets' level has this size, see `sse2::taps`); the CPU has AVX2.
    unsafe {
        let q = |i: i32| _mm_loadl_epi64(base.add(i as usize * 8).cast());
        gather_pairs(
            t,
            acc,
            |o0: i32, o1: i32| _mm_unpacklo_epi16(q(o0), q(o1)),
            |v| v,
        );
    }
}

/// [`gather`] of opaque RGBA8 texels with linear codes: `sse2::gather`'s bytes interleaved
/// (r0 r1 g0 g1 …), two pixels' to a vector, then each byte doubled (`c · 257` in 16 bits)
/// for both at once. The same 15-bit values, so the same sums.
///
/// # Safety
/// The CPU must have AVX2; `t`'s offsets index 4-byte texels of `data`.
#[inline(always)]
unsafe fn gather8(data: &[u8], t: &Taps, acc: &mut [__m128i; 4]) {
    let base = data.as_ptr();
    // SAFETY (the loads): each reads one 4-byte texel at an index below `data.len() / 4`
    // (the offsets' level has this size, see `sse2::taps`); the CPU has AVX2.
    unsafe {
        let q = |i: i32| _mm_cvtsi32_si128(base.add(i as usize * 4).cast::<i32>().read_unaligned());
        gather_pairs(
            t,
            acc,
            |o0: i32, o1: i32| _mm_unpacklo_epi8(q(o0), q(o1)),
            |v| _mm256_unpacklo_epi8(v, v),
        );
    }
}

/// The gathers' sums: for pixels `j` and `j + 1` at once, each pixel's two pairs of taps
/// (`pair` interleaves two taps' channels in the low 8 or 16 bytes; `widen` makes both
/// pixels' 16-bit values) taken to 15 bits and multiplied by their packed weights, each
/// pixel's four products added into its accumulator.
///
/// # Safety
/// The CPU must have AVX2; `pair` must only read within its texels' level.
#[inline(always)]
unsafe fn gather_pairs(
    t: &Taps,
    acc: &mut [__m128i; 4],
    pair: impl Fn(i32, i32) -> __m128i,
    widen: impl Fn(__m256i) -> __m256i,
) {
    // SAFETY: the CPU has AVX2 (this function's contract).
    unsafe {
        let top = _mm256_castsi128_si256(_mm_loadu_si128(t.top.as_ptr().cast()));
        let bottom = _mm256_castsi128_si256(_mm_loadu_si128(t.bottom.as_ptr().cast()));
        for j in [0, 2] {
            // Taps `k0` and `k1` of pixels `j` and `j + 1`, interleaved, as 15 bits.
            let pair = |k0: usize, k1: usize| {
                let o = (&t.offsets[k0], &t.offsets[k1]);
                let lo = pair(o.0[j], o.1[j]);
                let hi = pair(o.0[j + 1], o.1[j + 1]);
                _mm256_srli_epi16::<1>(widen(_mm256_set_m128i(hi, lo)))
            };
            let lanes = _mm256_setr_epi32(
                j as i32,
                j as i32,
                j as i32,
                j as i32,
                j as i32 + 1,
                j as i32 + 1,
                j as i32 + 1,
                j as i32 + 1,
            );
            let sum = _mm256_add_epi32(
                _mm256_madd_epi16(pair(0, 1), _mm256_permutevar8x32_epi32(top, lanes)),
                _mm256_madd_epi16(pair(2, 3), _mm256_permutevar8x32_epi32(bottom, lanes)),
            );
            acc[j] = _mm_add_epi32(acc[j], _mm256_castsi256_si128(sum));
            acc[j + 1] = _mm_add_epi32(acc[j + 1], _mm256_extracti128_si256::<1>(sum));
        }
    }
}
