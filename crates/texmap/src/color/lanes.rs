//! The 8-bit sRGB encodings of whole rows in AVX2 lanes: [`super::encode_srgb8`] and
//! [`super::encode_srgba8`] eight pixels at a time, two pixels' channels in each vector.
//!
//! Each channel is encoded as [`super::Srgb8Encoder::encode`] encodes it, from the same
//! table: the float's top 16 bits choose a slot, two gathers read the slot's threshold and
//! starting code, one comparison finishes the code; the same float operations for the
//! straight alpha (a division, a `min`, the alpha's rounding), none fused. So the codes are
//! the scalar encoder's, value for value (tested on every threshold's neighbours, the slots'
//! edges, specials and random bit patterns). The scalar encoder spent most of its time on
//! the table read each channel waits for; here eight reads are in flight at once.
//!
//! Only where [`crate::cpu::level`] is x86-64-v3 (the callers check).

use std::arch::x86_64::{
    __m256, __m256i, _mm256_add_epi32, _mm256_add_ps, _mm256_and_si256, _mm256_blend_epi32,
    _mm256_castps_si256, _mm256_castsi256_si128, _mm256_cmp_ps, _mm256_cvttps_epi32, _mm256_div_ps,
    _mm256_extracti128_si256, _mm256_i32gather_epi32, _mm256_i32gather_ps, _mm256_loadu_ps,
    _mm256_max_epu32, _mm256_max_ps, _mm256_min_epu32, _mm256_min_ps, _mm256_mul_ps,
    _mm256_packus_epi16, _mm256_packus_epi32, _mm256_permute_ps, _mm256_permutevar8x32_epi32,
    _mm256_set1_epi32, _mm256_set1_ps, _mm256_setr_epi32, _mm256_setr_epi8, _mm256_setzero_ps,
    _mm256_shuffle_epi8, _mm256_srli_epi32, _mm256_storeu_si256, _mm256_sub_epi32,
    _mm_storel_epi64, _mm_storeu_si128, _CMP_GE_OQ, _CMP_GT_OQ,
};

use glam::Vec4;

use super::{Srgb8Encoder, KEY_LO, SLOTS};

/// [`super::encode_srgb8`] of the first pixels of `color`, eight at a time: returns how many
/// it encoded (the rest, fewer than eight, are the caller's).
///
/// # Safety
/// The CPU must have x86-64-v3 ([`crate::cpu::level`]); `out` must hold three bytes a pixel
/// of `color` (the caller asserts it).
#[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,movbe")]
pub(super) unsafe fn srgb8(e: Srgb8Encoder, color: &[Vec4], out: &mut [u8]) -> usize {
    assert!(out.len() >= 3 * color.len());
    let blocks = color.len() / 8;
    // SAFETY: AVX2 (this function's contract); each block reads eight pixels of `color` and
    // writes 24 bytes of `out`, within both (`blocks` whole blocks, `out` three bytes a pixel).
    unsafe {
        // Each 128-bit half's four RGBA pixels to its first 12 bytes, then the two halves'
        // 12 bytes side by side.
        let rgb = _mm256_setr_epi8(
            0, 1, 2, 4, 5, 6, 8, 9, 10, 12, 13, 14, -1, -1, -1, -1, //
            0, 1, 2, 4, 5, 6, 8, 9, 10, 12, 13, 14, -1, -1, -1, -1,
        );
        let join = _mm256_setr_epi32(0, 1, 2, 4, 5, 6, 3, 7);
        for b in 0..blocks {
            let p = color.as_ptr().add(8 * b).cast::<f32>();
            let codes = std::array::from_fn(|k| codes(e, _mm256_loadu_ps(p.add(8 * k))));
            let bytes = _mm256_permutevar8x32_epi32(_mm256_shuffle_epi8(pack(codes), rgb), join);
            let o = out.as_mut_ptr().add(24 * b);
            _mm_storeu_si128(o.cast(), _mm256_castsi256_si128(bytes));
            _mm_storel_epi64(o.add(16).cast(), _mm256_extracti128_si256::<1>(bytes));
        }
    }
    8 * blocks
}

/// [`super::encode_srgba8`] of the first pixels of `color`, eight at a time: returns how many
/// it encoded.
///
/// # Safety
/// The CPU must have x86-64-v3 ([`crate::cpu::level`]); `out` must hold four bytes a pixel of
/// `color` (the caller asserts it).
#[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,movbe")]
pub(super) unsafe fn srgba8(e: Srgb8Encoder, color: &[Vec4], out: &mut [u8]) -> usize {
    assert!(out.len() >= 4 * color.len());
    let blocks = color.len() / 8;
    // SAFETY: as in `srgb8`, 32 bytes of `out` a block.
    unsafe {
        let (zero, one) = (_mm256_setzero_ps(), _mm256_set1_ps(1.0));
        let straight = |v: __m256| {
            // Each pixel's alpha in its four lanes.
            let a = _mm256_permute_ps::<0xff>(v);
            let colour = codes(e, _mm256_div_ps(v, _mm256_min_ps(a, one)));
            // `linear_to_unorm8`: the clamped alpha times 255 plus ½, truncated.
            let clamped = _mm256_min_ps(_mm256_max_ps(a, zero), one);
            let alpha = _mm256_cvttps_epi32(_mm256_add_ps(
                _mm256_mul_ps(clamped, _mm256_set1_ps(255.0)),
                _mm256_set1_ps(0.5),
            ));
            let covered = _mm256_castps_si256(_mm256_cmp_ps::<_CMP_GT_OQ>(a, zero));
            _mm256_and_si256(_mm256_blend_epi32::<0b1000_1000>(colour, alpha), covered)
        };
        for b in 0..blocks {
            let p = color.as_ptr().add(8 * b).cast::<f32>();
            let codes = std::array::from_fn(|k| straight(_mm256_loadu_ps(p.add(8 * k))));
            _mm256_storeu_si256(out.as_mut_ptr().add(32 * b).cast(), pack(codes));
        }
    }
    8 * blocks
}

/// The codes of eight values (each in 0..=255, as `i32`): [`Srgb8Encoder::encode`] lane by
/// lane.
///
/// # Safety
/// The CPU must have AVX2.
#[inline(always)]
unsafe fn codes(e: Srgb8Encoder, v: __m256) -> __m256i {
    let slots = e.table.slots.as_ptr();
    // SAFETY: AVX2 (the caller's contract); every slot index is below `SLOTS` (clamped), so
    // both gathers read inside the table (8-byte slots: the threshold, then the code).
    unsafe {
        let key = _mm256_srli_epi32::<16>(_mm256_castps_si256(v));
        // `(key + 1).saturating_sub(KEY_LO).min(SLOTS − 1)`, unsigned.
        let lo = _mm256_set1_epi32(KEY_LO as i32);
        let above_lo = _mm256_max_epu32(_mm256_add_epi32(key, _mm256_set1_epi32(1)), lo);
        let slot = _mm256_min_epu32(
            _mm256_sub_epi32(above_lo, lo),
            _mm256_set1_epi32(SLOTS as i32 - 1),
        );
        let threshold = _mm256_i32gather_ps::<8>(slots.cast::<f32>(), slot);
        let start = _mm256_i32gather_epi32::<8>(slots.cast::<i32>().add(1), slot);
        // `start + (v ≥ threshold)`: false for a NaN threshold (a slot without one).
        let at_or_above = _mm256_castps_si256(_mm256_cmp_ps::<_CMP_GE_OQ>(v, threshold));
        let code = _mm256_sub_epi32(start, at_or_above);
        // NaN, zero and negative values: 0.
        let positive = _mm256_castps_si256(_mm256_cmp_ps::<_CMP_GT_OQ>(v, _mm256_setzero_ps()));
        _mm256_and_si256(code, positive)
    }
}

/// Four vectors of two pixels' codes (pixels 0–1, 2–3, 4–5, 6–7) as the eight pixels' RGBA
/// bytes in order.
///
/// # Safety
/// The CPU must have AVX2.
#[inline(always)]
unsafe fn pack(codes: [__m256i; 4]) -> __m256i {
    // SAFETY: the caller's contract.
    unsafe {
        // The packs work within each 128-bit half: the halves hold pixels 0, 2, 4, 6 and
        // 1, 3, 5, 7, a pixel a 32-bit lane; the permutation puts them in order.
        let bytes = _mm256_packus_epi16(
            _mm256_packus_epi32(codes[0], codes[1]),
            _mm256_packus_epi32(codes[2], codes[3]),
        );
        _mm256_permutevar8x32_epi32(bytes, _mm256_setr_epi32(0, 4, 1, 5, 2, 6, 3, 7))
    }
}

#[cfg(test)]
mod tests {
    use super::super::{encode_srgb8, encode_srgba8, straight8};
    use super::*;

    /// Values the encoder must get right: every threshold and its neighbours, the slots'
    /// edges, the specials, and random bit patterns and colours.
    fn values() -> Vec<f32> {
        let mut v = vec![
            0.0,
            -0.0,
            1.0,
            -1.0,
            1.0e-40,
            f32::MIN_POSITIVE,
            f32::MAX,
            f32::NAN,
            -f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
        ];
        for k in 0..255 {
            let t = super::super::srgb_to_linear((k as f32 + 0.5) / 255.0).to_bits();
            v.extend([t - 1, t, t + 1].map(f32::from_bits));
        }
        for key in (KEY_LO - 2)..=(KEY_LO + SLOTS as u32) {
            let b = key << 16;
            v.extend([b - 1, b, b + 1].map(f32::from_bits));
        }
        let mut r = crate::xorshift(0x51f1_5eed);
        v.extend((0..20_000).map(|_| f32::from_bits(r())));
        v.extend((0..20_000).map(|_| r() as f32 / u32::MAX as f32 * 1.2));
        v
    }

    #[test]
    fn the_lanes_encode_as_the_scalar_encoder() {
        if !crate::cpu::available(crate::cpu::Level::V3) {
            eprintln!("skipped: this CPU has no x86-64-v3 (AVX2), where the lanes run");
            return;
        }
        let values = values();
        let e = Srgb8Encoder::new();
        // Pixels of every value in every channel, alpha included: the values rotated.
        let n = values.len();
        let pixels: Vec<Vec4> = (0..n)
            .map(|i| Vec4::from_array(std::array::from_fn(|k| values[(i + k * 7919) % n])))
            .collect();
        // Whole blocks and tails, from every start in a block.
        for (start, len) in [(0, n), (3, 8), (1, 15), (5, 0), (7, 17)] {
            let px = &pixels[start..start + len];
            let mut rgb = vec![0; 3 * len];
            // SAFETY: the CPU has x86-64-v3 (checked above).
            let done = unsafe { srgb8(e, px, &mut rgb) };
            assert_eq!(done, len / 8 * 8);
            let mut rgba = vec![0; 4 * len];
            // SAFETY: as above.
            assert_eq!(unsafe { srgba8(e, px, &mut rgba) }, done);
            for (i, c) in px[..done].iter().enumerate() {
                let want = [e.encode(c.x), e.encode(c.y), e.encode(c.z)];
                assert_eq!(rgb[3 * i..3 * i + 3], want, "pixel {c:?}");
                assert_eq!(rgba[4 * i..4 * i + 4], straight8(e, *c), "pixel {c:?}");
            }
            // The dispatched functions: the lanes and the scalar tail together.
            let (mut all3, mut all4) = (vec![0; 3 * len], vec![0; 4 * len]);
            encode_srgb8(px, &mut all3);
            encode_srgba8(px, &mut all4);
            for (i, c) in px.iter().enumerate() {
                assert_eq!(
                    all3[3 * i..3 * i + 3],
                    [e.encode(c.x), e.encode(c.y), e.encode(c.z)]
                );
                assert_eq!(all4[4 * i..4 * i + 4], straight8(e, *c), "pixel {c:?}");
            }
        }
    }
}
