//! Prefetching a batch's texels before [`super::read_quad`] reads them.
//!
//! Minified without mipmaps (the OpenGL filters `nearest` and `linear` on level 0),
//! neighbouring pixels read texels far apart: on the 1080p plane's far rows nearly every load
//! misses the caches, and the reads, one quad after another, wait for each quad's misses in
//! turn (perf: 92% of the nearest read's samples on the instruction after its load). Asking
//! for the whole batch's texels first lets the misses overlap. Quads minified by less than two
//! texels a pixel (λ ≤ 1: their texels sit in the lines their neighbours read) are not asked
//! for: for them this would only compute the addresses twice, so only the far quads are
//! prefetched.
//!
//! Mipmapped reads on large levels are the exception, two ways. The trilinear runs of
//! `avx2::quad_pairs` ask for each quad's corners on a level larger than an L1 cache as
//! soon as its taps are made ([`prefetch_corners`]), before any of the run's texels are
//! read: the 1080p plane's near rows read levels 0 and 1 of its 1024² checker (8 and
//! 2 MiB), and with the same instructions the plane took 0.885× the time when `--uv-scale
//! 256` moved its reads two levels up (twelve alternated rounds): the misses of the large
//! levels were a tenth of the frame. The taps were made anyway; the asks are 4 % of the
//! plane's instructions (415.8 against 398.5 M in two frames), and they made its frame
//! 0.955–0.979× as long, the unlit DamagedHelmet's 0.947× (frames with and without them
//! alternated in one process); levels of 64 KiB or less are not asked for. The anisotropic
//! and `ewa` batches ask for each quad's first-level texels between planning a chunk and
//! reading it, through their reader (`ProbeReader::prefetch`, `probed.rs`): `aniso5-area`
//! 0.958×, `ewa` 0.966× (frames with and without, in one process).
//!
//! A material's maps read together ([`prefetch_shared`]) are the other: four or five
//! textures' lines a quad, on levels the frame streams through (DamagedHelmet's 2048² maps
//! at levels 1–2). Each pair of quads' reads is hundreds of instructions, so the next pair's
//! loads lie beyond the out-of-order window and its misses waited after the last pair's
//! (perf: the samples on the instruction after each pixel's first texel load). Asking for
//! every quad's first-level corners in every map before the first read lets them overlap.

use super::super::super::{MipChoice, Sampler, Texture2D};
use super::super::QuadCoords;

/// The size of a level's texels above which mipmapped reads ask for their lines ahead
/// ([`prefetch_corners`], `ProbeReader::prefetch`): more than an L1 data cache holds
/// (32–48 KiB on the machines measured).
pub(super) const PREFETCH_BYTES: usize = 64 << 10;

/// Asks the cache for the texels [`super::read_quad`] will read for each quad `i` of a batch
/// whose bit is set in `far` (`coords[i]`, `choices[i]`, `masks[i]`): on the level chosen,
/// each covered pixel's nearest texel, or the first and last of its bilinear taps. Nothing is
/// read or changed. (Inlined into the batch reads: as a call it kept the baseline's code in
/// their x86-64-v3 copy, `crate::cpu`.)
#[inline(always)]
pub(in super::super) fn prefetch_quads(
    tex: &Texture2D,
    s: &Sampler,
    coords: &[QuadCoords],
    choices: &[MipChoice],
    masks: &[u8],
    far: u32,
) {
    let Some(texels) = super::texels_of(tex, s) else {
        return;
    };
    #[cfg(target_arch = "x86_64")]
    for (i, ((c, &choice), &mask)) in coords.iter().zip(choices).zip(masks).enumerate() {
        if far & (1 << i) != 0 {
            prefetch_quad(tex, texels, s, choice, c.u, c.v, mask);
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = (texels, coords, choices, masks, far);
}

/// [`prefetch_quads`] of one quad.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn prefetch_quad(
    tex: &Texture2D,
    texels: super::Texels,
    s: &Sampler,
    choice: MipChoice,
    u: glam::Vec4,
    v: glam::Vec4,
    mask: u8,
) {
    use super::sse2::{bpp, nearest_offsets, taps};
    let lv = tex.level(choice.level);
    let size = bpp(texels);
    let (data, tiles_x) = lv.tiled_texels(size);
    let (first, last) = if choice.texels == crate::texture::TexelFilter::Linear {
        let t = taps(&lv, tiles_x, s, u, v, super::ONE);
        (t.offsets[0], t.offsets[3])
    } else {
        let o = nearest_offsets(&lv, tiles_x, s, u, v);
        (o, o)
    };
    prefetch_lanes(data, size, &[&first, &last], mask);
}

/// Asks the cache for the texels of `data` (`size` bytes each) at each of `offsets`' lanes
/// whose bit is set in `mask` (a quad's pixels). Nothing is read or changed.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
pub(super) fn prefetch_lanes(data: &[u8], size: usize, offsets: &[&[i32; 4]], mask: u8) {
    use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
    let base = data.as_ptr();
    for j in (0..4).filter(|j| mask & (1 << j) != 0) {
        for o in offsets {
            // SAFETY: SSE is part of x86_64; a prefetch reads nothing (the offsets are in
            // range anyway, as for the reads).
            unsafe {
                _mm_prefetch::<_MM_HINT_T0>(base.wrapping_add(o[j] as usize * size).cast::<i8>());
            }
        }
    }
}

/// Asks the cache for a quad's texels on the first level `choice` names, in every texture of
/// `shared` (read together at `u`, `v`): the four corners of the texels the quad reads there
/// (pixel `k`'s tap `k`: the first tap of the top-left pixel, the top-right one of the
/// top-right pixel, …), which lie in different 4×4 tiles when the quad's texels straddle
/// them. Nothing is read or changed. (Two corners, the first and the last, left the lit
/// DamagedHelmet frame 2 % slower: the median of 30 alternated rounds.)
#[cfg(target_arch = "x86_64")]
#[inline(always)]
pub(in super::super) fn prefetch_shared(
    shared: &super::Shared,
    s: &Sampler,
    choice: MipChoice,
    u: glam::Vec4,
    v: glam::Vec4,
) {
    use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
    if choice.texels != crate::texture::TexelFilter::Linear {
        return;
    }
    let lv = shared.level(choice.level);
    let t = super::sse2::taps(&lv.first, lv.tiles_x, s, u, v, super::ONE);
    let corners = [0, 1, 2, 3].map(|k| t.offsets[k][k] as usize);
    for (data, &texels) in lv.data.iter().zip(&shared.texels).take(shared.count) {
        let size = super::bpp(texels);
        for o in corners {
            // SAFETY: SSE is part of x86_64; a prefetch reads nothing.
            unsafe {
                _mm_prefetch::<_MM_HINT_T0>(data.as_ptr().wrapping_add(o * size).cast::<i8>());
            }
        }
    }
}

/// Asks the cache for the lines of a quad's bilinear taps `t` on a level whose tiled texels
/// (`size` bytes each) are `data`: two opposite corners of its texels (the top-left pixel's
/// first tap, the bottom-right pixel's last). All four corners, as [`prefetch_shared`] asks
/// for them, made the trilinear plane's frame 1.014× this (30 alternated rounds, each
/// run's fastest frame). Nothing is read or changed. (Inlined into `avx2::quad_pairs`,
/// which reads the taps right after.)
#[cfg(target_arch = "x86_64")]
#[inline(always)]
pub(super) fn prefetch_corners(data: &[u8], size: usize, t: &super::sse2::Taps) {
    use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
    for k in [0, 3] {
        let o = t.offsets[k][k] as usize;
        // SAFETY: SSE is part of x86_64; a prefetch reads nothing.
        unsafe {
            _mm_prefetch::<_MM_HINT_T0>(data.as_ptr().wrapping_add(o * size).cast::<i8>());
        }
    }
}
