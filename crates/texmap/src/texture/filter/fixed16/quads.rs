//! One texture's reads on the fixed-point path: a quad ([`read_quad`]) and a batch of quads
//! ([`read_quads`], what [`super::super::sample_quads_lanes`] asks for).
//!
//! The batch checks once that the texture and sampler are ones this path serves, and keeps
//! the view of the level its nearest reads take while consecutive quads stay on it (most
//! do: a whole batch of a plane reads level 0): a quad pays its texel addresses and loads,
//! not the storage's bookkeeping.

use glam::Vec4;

use super::super::super::{MipChoice, Sampler, TexelFilter, Texture2D};
use super::super::QuadCoords;
#[cfg(target_arch = "x86_64")]
use super::sse2;
use super::{texels_of, Texels};

/// A quad's reads at `(u, v)` (one pixel per lane, pixels whose `mask` bit is clear left
/// zero) on the levels `choice` names: bilinear in fixed point for [`TexelFilter::Linear`],
/// else nearest — the same texels and values as the float path's `nearest` (its wrap of an
/// index that rounds up to the size, its index 0 for NaN), with the index arithmetic in
/// lanes. `None` when this texture or sampler is not one this path handles.
#[inline]
pub(in super::super) fn read_quad(
    tex: &Texture2D,
    s: &Sampler,
    choice: MipChoice,
    u: Vec4,
    v: Vec4,
    mask: u8,
) -> Option<[Vec4; 4]> {
    let texels = texels_of(tex, s)?;
    #[cfg(target_arch = "x86_64")]
    {
        Some(read_with(tex, texels, s, choice, u, v, mask))
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        let _ = (texels, choice, u, v, mask);
        None
    }
}

/// [`read_quad`] of each quad of a batch: `out[i]` for `coords[i]`, `choices[i]` and
/// `masks[i]`, the same values quad for quad. `false`, and nothing read, when this texture or
/// sampler is not one this path handles.
///
/// # Panics
/// If `choices`, `masks` or `out` is shorter than `coords`.
#[inline(always)]
pub(in super::super) fn read_quads(
    tex: &Texture2D,
    s: &Sampler,
    coords: &[QuadCoords],
    choices: &[MipChoice],
    masks: &[u8],
    out: &mut [[Vec4; 4]],
) -> bool {
    let Some(texels) = texels_of(tex, s) else {
        return false;
    };
    assert!(choices.len() >= coords.len() && masks.len() >= coords.len());
    assert!(out.len() >= coords.len());
    #[cfg(target_arch = "x86_64")]
    {
        if linear_on_one_pair(tex, texels, s, coords, choices, masks, out) {
            return true;
        }
        // The level the last nearest read took, and its view.
        let mut view = None;
        for (((c, &choice), &mask), o) in coords.iter().zip(choices).zip(masks).zip(out) {
            if choice.texels == TexelFilter::Nearest && choice.blend.is_none() {
                let lv = match view {
                    Some((level, lv)) if level == choice.level => lv,
                    _ => {
                        let lv = tex.level(choice.level);
                        view = Some((choice.level, lv));
                        lv
                    }
                };
                *o = sse2::nearest_level(lv, texels, s, c.u, c.v, mask);
            } else {
                *o = read_with(tex, texels, s, choice, c.u, c.v, mask);
            }
        }
        true
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        let _ = (texels, coords, choices, masks, out);
        false
    }
}

/// [`read_quads`] of a batch (at most [`LEVEL_QUADS`] quads) whose quads all read bilinear
/// texels on the same level, or the same pair of levels: the two levels' views and storage
/// checks once for the batch, not per quad. The same values; `false`, and nothing read,
/// for any other batch. (Trilinear batches take `trilinear.rs`'s path.)
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn linear_on_one_pair(
    tex: &Texture2D,
    texels: Texels,
    s: &Sampler,
    coords: &[QuadCoords],
    choices: &[MipChoice],
    masks: &[u8],
    out: &mut [[Vec4; 4]],
) -> bool {
    let pair = |c: &MipChoice| (c.texels, c.level, c.blend.map(|b| b.level));
    let Some(first) = choices.first() else {
        return true;
    };
    let (texel_filter, a, b) = pair(first);
    let n = coords.len();
    assert!(n <= LEVEL_QUADS);
    if texel_filter != TexelFilter::Linear || choices[..n].iter().any(|c| pair(c) != pair(first)) {
        return false;
    }
    let size = sse2::bpp(texels);
    let la = tex.level(a);
    let (da, ta) = la.tiled_texels(size);
    // Without a blend the second level is never read: the first stands in for it.
    let lb = tex.level(b.unwrap_or(a));
    let (db, tb) = lb.tiled_texels(size);
    if crate::cpu::level() == crate::cpu::Level::V3 {
        // Each quad's two weights (`read_quads` takes a chunk of at most LEVEL_QUADS).
        let mut weights = [[0; 2]; LEVEL_QUADS];
        for (w, &choice) in weights.iter_mut().zip(&choices[..n]) {
            let wa = sse2::first_weight(choice);
            *w = [wa, sse2::second_weight(choice, wa)];
        }
        // SAFETY: the CPU has x86-64-v3 (`cpu::level`).
        unsafe {
            super::avx2::quad_pairs(
                (&la, da, ta),
                (&lb, db, tb),
                texels,
                s,
                coords,
                &weights[..n],
                masks,
                out,
            );
        }
        return true;
    }
    for (((c, &choice), &mask), o) in coords.iter().zip(choices).zip(masks).zip(out) {
        *o = sse2::linear_quad_on(
            (&la, da, ta),
            (&lb, db, tb),
            texels,
            s,
            choice,
            c.u,
            c.v,
            mask,
        );
    }
    true
}

/// The most quads [`read_level_quads`] takes at a time.
pub(in super::super) const LEVEL_QUADS: usize = 16;

/// [`read_quads`] of a batch (at most [`LEVEL_QUADS`] quads) whose quads all read level
/// `choice.level` with no blend (a filter pair whose choice λ cannot change,
/// [`MipChoice::fixed`]), with the prefetch of the quads whose bit is set in `far`
/// ([`super::prefetch_quads`]): the level's view and storage are checked once, and each
/// quad's texel indices (and bilinear weights) computed once, for its prefetch and its read.
/// The same values as [`read_quads`]; `false`, and nothing read, when this texture or sampler
/// is not one this path handles.
///
/// # Panics
/// If `masks` or `out` is shorter than `coords`, `coords` is longer than [`LEVEL_QUADS`],
/// or `choice` blends two levels.
#[inline(always)]
pub(in super::super) fn read_level_quads(
    tex: &Texture2D,
    s: &Sampler,
    choice: MipChoice,
    coords: &[QuadCoords],
    masks: &[u8],
    far: u32,
    out: &mut [[Vec4; 4]],
) -> bool {
    let Some(texels) = texels_of(tex, s) else {
        return false;
    };
    let n = coords.len();
    assert!(masks.len() >= n && out.len() >= n && n <= LEVEL_QUADS && choice.blend.is_none());
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::_mm_setzero_si128;
        let lv = tex.level(choice.level);
        let size = sse2::bpp(texels);
        let (data, tiles_x) = lv.tiled_texels(size);
        // Quad i's texels at `offsets` (lanes of its pixels) asked for when it is far.
        let prefetch = |i: usize, offsets: &[&[i32; 4]]| {
            if far & (1 << i) != 0 {
                super::prefetch::prefetch_lanes(data, size, offsets, masks[i]);
            }
        };
        let lanes = crate::cpu::level() == crate::cpu::Level::V3;
        if choice.texels == TexelFilter::Nearest {
            let mut offsets = [[0; 4]; LEVEL_QUADS];
            if lanes {
                // Two quads' indices at once (the same indices).
                // SAFETY: the CPU has x86-64-v3 (`cpu::level`).
                unsafe { super::avx2::level_nearest(&lv, tiles_x, s, coords, &mut offsets) };
                // (Nearest batches ask for none, `far` 0: the walk over the quads was 8
                // instructions a quad, 1.7 % of the nearest plane's.)
                if far != 0 {
                    for (i, o) in offsets.iter().enumerate().take(n) {
                        prefetch(i, &[o]);
                    }
                }
            } else {
                for (i, (c, o)) in coords.iter().zip(&mut offsets).enumerate() {
                    *o = sse2::nearest_offsets(&lv, tiles_x, s, c.u, c.v);
                    prefetch(i, &[o]);
                }
            }
            if lanes && matches!(texels, Texels::Rgba8(_)) {
                // SAFETY: the CPU has x86-64-v3 (`cpu::level`); `level_nearest` gave indices
                // in range for the level `data` holds.
                unsafe {
                    super::avx2::nearest_rgba8(&lv, data, &offsets[..n], &masks[..n], out);
                }
                return true;
            }
            for ((o, &mask), out) in offsets.iter().zip(masks).zip(out).take(n) {
                // SAFETY: `nearest_offsets` gave indices in range for the level `data` holds.
                *out = unsafe { sse2::nearest_texels(&lv, data, texels, *o, mask) };
            }
        } else {
            // `linear_quad` on one level: its taps weighted ONE in all, summed, finished.
            if lanes {
                // Two quads' taps at once (the same taps), into an array not zeroed first.
                let mut taps = [const { std::mem::MaybeUninit::uninit() }; LEVEL_QUADS];
                // SAFETY: the CPU has x86-64-v3 (`cpu::level`).
                let taps = unsafe { super::avx2::level_taps(&lv, tiles_x, s, coords, &mut taps) };
                for (i, t) in taps.iter().enumerate() {
                    prefetch(i, &[&t.offsets[0], &t.offsets[3]]);
                }
                // Two pixels to a 256-bit vector (the same sums).
                // SAFETY: the CPU has x86-64-v3 (`cpu::level`); the taps index `data`, the
                // level they were made for.
                unsafe { super::avx2::gather_quads(data, texels, taps, masks, out) };
                return true;
            }
            let mut taps = [sse2::Taps::default(); LEVEL_QUADS];
            for (i, (c, t)) in coords.iter().zip(&mut taps).enumerate() {
                *t = sse2::taps(&lv, tiles_x, s, c.u, c.v, super::ONE);
                prefetch(i, &[&t.offsets[0], &t.offsets[3]]);
            }
            for ((t, &mask), out) in taps.iter().zip(masks).zip(out).take(n) {
                // SAFETY: SSE2 is part of x86_64.
                let mut acc = [unsafe { _mm_setzero_si128() }; 4];
                sse2::gather(data, texels, t, &mut acc);
                *out = sse2::finish(&acc, mask);
            }
        }
        true
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        let _ = (texels, coords, choice, masks, far, out);
        false
    }
}

/// [`read_quad`] once the texture's texels are known to be served (`texels`).
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn read_with(
    tex: &Texture2D,
    texels: Texels,
    s: &Sampler,
    choice: MipChoice,
    u: Vec4,
    v: Vec4,
    mask: u8,
) -> [Vec4; 4] {
    if choice.texels == TexelFilter::Linear {
        return sse2::linear_quad(tex, texels, s, choice, u, v, mask);
    }
    let a = sse2::nearest_level(tex.level(choice.level), texels, s, u, v, mask);
    match choice.blend {
        Some(b) => {
            let (f, b) = (
                b.weight,
                sse2::nearest_level(tex.level(b.level), texels, s, u, v, mask),
            );
            std::array::from_fn(|j| a[j].lerp(b[j], f))
        }
        None => a,
    }
}
