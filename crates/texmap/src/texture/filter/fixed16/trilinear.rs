//! Trilinear batches (`LinearMipmapLinear`, bilinear when magnified): each quad's first
//! level and its two levels' 15-bit weights straight from its λ ([`level_weights4`]), with no
//! [`MipChoice`](crate::texture::MipChoice) made and none converted back to weights; then the quads read in runs that
//! share their first level, two quads at a time where the CPU has AVX2
//! (`avx2::quad_pairs`). A batch whose λ crosses an integer reads each run on its own
//! pair of levels (the general path read such a batch quad by quad).
//!
//! The values are [`super::read_quads`]'s: `level_weights4` is, lane by lane, [`MipChoice::gl`](crate::texture::MipChoice::gl)'s choice
//! for this filter pair followed by `sse2::first_weight` and `sse2::second_weight`, the same
//! operations (tested on every kind of λ below), and each quad's read depends on its levels
//! and weights alone, not on the quad it is paired with.

use glam::Vec4;

use super::super::super::{Sampler, Texture2D};
use super::super::QuadCoords;
#[cfg(target_arch = "x86_64")]
use super::sse2;
use super::{texels_of, LEVEL_QUADS, ONE};

/// Four quads' first levels and weights straight from their λ (one per lane, after the
/// sampler's bias and clamps) on a texture whose last level is `last`: each lane's first
/// level and that level's 15-bit weight (the second level's is `ONE` less it). The scalar
/// rule's operations (`level_weights` in the tests) in lanes, so the same values (tested on
/// every kind of λ below): `l − ⌊l⌋` with ⌊l⌋ the truncation (l > 0), and the weight
/// rounded half away from zero as `f32::round` is compiled, `trunc(y + copysign(0.5⁻, y))`
/// with y ≥ 0; a magnified or NaN lane level 0, weight `ONE`. (Lane by lane it was 27
/// instructions a quad.)
#[cfg(target_arch = "x86_64")]
#[inline(always)]
#[must_use]
pub(in super::super) fn level_weights4(lod: Vec4, last: usize) -> ([i32; 4], [i32; 4]) {
    use std::arch::x86_64::{
        __m128i, _mm_and_si128, _mm_andnot_si128, _mm_castps_si128, _mm_cmpgt_ps, _mm_cvtepi32_ps,
        _mm_cvttps_epi32, _mm_or_si128, _mm_set1_epi32, _mm_setzero_ps,
    };
    // SAFETY: SSE2 is part of x86_64.
    unsafe {
        let minified = _mm_castps_si128(_mm_cmpgt_ps(lod.into(), _mm_setzero_ps()));
        let l = lod.min(Vec4::splat(last as f32));
        // In range (l ∈ (0, last] in the lanes kept): the truncation is the floor.
        let d = _mm_cvttps_epi32(l.into());
        let f = l - Vec4::from(_mm_cvtepi32_ps(d));
        let y = (Vec4::ONE - f) * ONE as f32;
        let wa = _mm_cvttps_epi32((y + Vec4::splat(0.5f32.next_down())).into());
        let keep = |x: __m128i, other: i32| {
            _mm_or_si128(
                _mm_and_si128(minified, x),
                _mm_andnot_si128(minified, _mm_set1_epi32(other)),
            )
        };
        let as_lanes = |x: __m128i| std::mem::transmute::<__m128i, [i32; 4]>(x);
        (as_lanes(keep(d, 0)), as_lanes(keep(wa, ONE)))
    }
}

/// Trilinear reads of a batch (at most [`LEVEL_QUADS`] quads): `out[i]` for `coords[i]`, its
/// λ `lods[i]` (after the sampler's bias and clamps; `lods` padded to a multiple of four,
/// the padding's λ any) and `masks[i]`, the values
/// [`super::read_quads`] gives for the choices [`MipChoice::gl`](crate::texture::MipChoice::gl) makes of those λ with
/// `LinearMipmapLinear` and a bilinear magnification. `false`, and nothing read, when this
/// texture or sampler is not one this path handles.
///
/// # Panics
/// If `masks` or `out` is shorter than `coords`, `lods` shorter than its length rounded up
/// to a multiple of four, or `coords` is longer than [`LEVEL_QUADS`].
#[inline(always)]
pub(in super::super) fn read_trilinear(
    tex: &Texture2D,
    s: &Sampler,
    coords: &[QuadCoords],
    lods: &[f32],
    masks: &[u8],
    out: &mut [[Vec4; 4]],
) -> bool {
    let Some(texels) = texels_of(tex, s) else {
        return false;
    };
    let n = coords.len();
    assert!(n <= LEVEL_QUADS && lods.len() >= n.next_multiple_of(4));
    assert!(masks.len() >= n && out.len() >= n);
    #[cfg(target_arch = "x86_64")]
    {
        let last = tex.levels().len() - 1;
        let mut levels = [0usize; LEVEL_QUADS];
        let mut weights = [[0i32; 2]; LEVEL_QUADS];
        // Four quads' at a time (`lods` is long enough: asserted above).
        for (k, lods) in lods.chunks_exact(4).take(n.div_ceil(4)).enumerate() {
            let (d, wa) = level_weights4(Vec4::from_slice(lods), last);
            for i in 0..4 {
                levels[4 * k + i] = d[i] as usize;
                weights[4 * k + i] = [wa[i], ONE - wa[i]];
            }
        }
        let size = sse2::bpp(texels);
        let lanes = crate::cpu::level() == crate::cpu::Level::V3;
        let mut start = 0;
        while start < n {
            // A run of quads on one first level (most batches are one run).
            let d = levels[start];
            let end = start + levels[start..n].iter().take_while(|&&l| l == d).count();
            let la = tex.level(d);
            let (da, ta) = la.tiled_texels(size);
            // At the last level no quad reads a second one (its weight is 0): the first
            // stands in for it.
            let lb = tex.level((d + 1).min(last));
            let (db, tb) = lb.tiled_texels(size);
            let (first, second) = ((&la, da, ta), (&lb, db, tb));
            let run = start..end;
            if lanes {
                // SAFETY: the CPU has x86-64-v3 (`cpu::level`); the run's slices are of one
                // length.
                unsafe {
                    super::avx2::quad_pairs(
                        first,
                        second,
                        texels,
                        s,
                        &coords[run.clone()],
                        &weights[run.clone()],
                        &masks[run.clone()],
                        &mut out[run],
                    );
                }
            } else {
                for (((c, &w), &mask), o) in coords[run.clone()]
                    .iter()
                    .zip(&weights[run.clone()])
                    .zip(&masks[run.clone()])
                    .zip(&mut out[run])
                {
                    *o = sse2::linear_weighted_on(first, second, texels, s, w, c.u, c.v, mask);
                }
            }
            start = end;
        }
        true
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        let _ = (texels, masks, out);
        false
    }
}

#[cfg(test)]
mod tests {
    use super::super::sse2;
    use super::*;
    use crate::texture::{MagFilter, MinFilter, MipChoice};

    /// The scalar rule [`level_weights4`] follows lane by lane: the first level a trilinear
    /// read takes at λ `lod` (after the sampler's bias and clamps) on a texture whose last level is `last`, and the 15-bit weights of that level and the
    /// next: [`MipChoice::gl`](crate::texture::MipChoice::gl) of `LinearMipmapLinear` with a bilinear magnification, then
    /// `sse2::first_weight` and `sse2::second_weight` of the choice. A magnified quad (λ ≤ 0 or
    /// NaN) reads level 0 alone, a quad at the last level that level alone (second weight 0).
    fn level_weights(lod: f32, last: usize) -> (usize, [i32; 2]) {
        if !(lod > 0.0) {
            return (0, [ONE, 0]);
        }
        let l = lod.min(last as f32);
        let d = l.floor();
        let f = l - d;
        // `first_weight`: f ∈ [0, 1), so its clamp changes nothing; where f = 0 (no blend) the
        // first level takes ONE and the second 0, as `second_weight` gives without a blend.
        // SAFETY: both are finite and in range (no saturating casts' compares): λ > 0 and not
        // NaN, so `l` ∈ (0, last] and `d` an integer in [0, last]; f ∈ [0, 1), so the first
        // weight is in [0, ONE].
        let (d, wa) = unsafe {
            (
                d.to_int_unchecked::<u32>(),
                ((1.0 - f) * ONE as f32).round().to_int_unchecked::<i32>(),
            )
        };
        (d as usize, [wa, ONE - wa])
    }

    /// `level_weights` against the general path's choice and weights, and
    /// `level_weights4` against it, on λ of every kind: magnified, NaN, integers, just above
    /// and below them, the last level and past it, and many values in between.
    #[test]
    fn level_weights_are_the_choices_weights() {
        let mut lods = vec![
            f32::NAN,
            f32::NEG_INFINITY,
            -3.0,
            -0.0,
            0.0,
            f32::MIN_POSITIVE,
            1e-30,
            1e-7,
            0.5,
            f32::INFINITY,
            1000.0,
        ];
        for k in 0..14 {
            let x = k as f32;
            lods.extend([x, x.next_up(), x.next_down(), x + 0.5, x + 0.25, x + 0.75]);
        }
        // Fractions whose first weight lands on or next to a rounding tie.
        for w in [0.5f32, 1.5, 100.5, 16383.5, 32766.5] {
            let f = 1.0 - w / ONE as f32;
            for x in [1.0f32, 2.0, 7.0] {
                let l = x + f;
                lods.extend([l, l.next_up(), l.next_down()]);
            }
        }
        let mut state = 0x2545_f491_4f6c_dd1du64;
        for _ in 0..100_000 {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            lods.push((state >> 40) as f32 / (1u64 << 24) as f32 * 16.0 - 2.0);
        }
        for levels in [1usize, 2, 5, 11] {
            let last = levels - 1;
            for &lod in &lods {
                let choice = MipChoice::gl(
                    lod,
                    levels,
                    MagFilter::Linear,
                    MinFilter::LinearMipmapLinear,
                );
                let wa = sse2::first_weight(choice);
                let expected = (choice.level, [wa, sse2::second_weight(choice, wa)]);
                assert_eq!(
                    level_weights(lod, last),
                    expected,
                    "λ {lod:e}, {levels} levels"
                );
            }
            // Four at a time, each lane at every position among the others.
            #[cfg(target_arch = "x86_64")]
            for shift in 0..4 {
                for four in lods[shift..].chunks_exact(4) {
                    let (d, wa) = level_weights4(Vec4::from_slice(four), last);
                    for i in 0..4 {
                        let (level, w) = level_weights(four[i], last);
                        let lanes = (d[i] as usize, [wa[i], ONE - wa[i]]);
                        assert_eq!(lanes, (level, w), "λ {:e}, {levels} levels", four[i]);
                    }
                }
            }
        }
    }
}
