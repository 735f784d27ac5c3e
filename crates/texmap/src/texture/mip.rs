//! Mip chain building: each level from the one above, in linear light with premultiplied alpha.
//!
//! Level sizes follow OpenGL (`max(1, ⌊n/2⌋)` per axis, down to 1×1). The reduction is an
//! exact-area box filter: a texel of the smaller level averages the region of the larger level
//! it covers, each source texel weighted by the area it shares with that region. On even sides
//! this is the classic 2×2 box; on odd sides a destination texel spans `n/⌊n/2⌋` source texels
//! (three taps with fractional end weights), so texel centres stay aligned and the mean of the
//! image is kept exactly: no half-texel drift on non-power-of-two textures. A box is chosen over
//! wider kernels (Kaiser, Lanczos) because it is what `glGenerateMipmap` computes on even sides,
//! which keeps trilinear comparable with the peers, and because it never rings.

use glam::Vec4;
use rayon::prelude::*;

/// Weights of the source texels covered by destination texel `i` when `src` texels shrink to `dst`.
pub(crate) fn coverage(i: u32, src: u32, dst: u32) -> impl Iterator<Item = (u32, f32)> {
    let scale = src as f64 / dst as f64;
    let (lo, hi) = (i as f64 * scale, (i + 1) as f64 * scale);
    let first = lo.floor() as u32;
    let last = (hi.ceil() as u32).min(src);
    (first..last).filter_map(move |j| {
        let overlap = (hi.min(j as f64 + 1.0) - lo.max(j as f64)) / scale;
        (overlap > 1e-12).then_some((j, overlap as f32))
    })
}

/// Reduces a `w`×`h` level, whose texel `(x, y)` is `read(x, y)`, to the next level's size.
///
/// Each destination row is made in parallel (rayon): for each source row it covers, that row
/// reduced along x (a row pass), then added with its weight (the column pass). The additions
/// come in the same order whatever thread makes the row, so the result is the same bits for
/// any thread count, and no whole-level intermediate is held.
///
/// With `unorm` (every value finite, not negative and far above the subnormals, as unorm
/// texels and their means are) and both sides even, [`halve`] makes the same bits faster.
fn reduce_with(
    w: u32,
    h: u32,
    unorm: bool,
    read: impl Fn(u32, u32) -> Vec4 + Sync,
) -> (u32, u32, Vec<Vec4>) {
    if unorm && w.is_multiple_of(2) && h.is_multiple_of(2) {
        return halve(w, h, read);
    }
    let (nw, nh) = ((w / 2).max(1), (h / 2).max(1));
    let columns: Vec<Vec<(u32, f32)>> = (0..nw).map(|x| coverage(x, w, nw).collect()).collect();
    let mut out = vec![Vec4::ZERO; (nw * nh) as usize];
    out.par_chunks_mut(nw as usize)
        .enumerate()
        .for_each(|(y, row_out)| {
            for (j, wt) in coverage(y as u32, h, nh) {
                for (o, taps) in row_out.iter_mut().zip(&columns) {
                    let r: Vec4 = taps.iter().map(|&(i, wx)| read(i, j) * wx).sum();
                    *o += r * wt;
                }
            }
        });
    (nw, nh, out)
}

/// [`reduce_with`] of a level with both sides even, for values finite, not negative and far
/// above the subnormals: each row by [`halve_row`].
fn halve(w: u32, h: u32, read: impl Fn(u32, u32) -> Vec4 + Sync) -> (u32, u32, Vec<Vec4>) {
    let (nw, nh) = (w / 2, h / 2);
    let mut out = vec![Vec4::ZERO; (nw * nh) as usize];
    out.par_chunks_mut(nw as usize)
        .enumerate()
        .for_each(|(y, row_out)| halve_row(2 * y as u32, &read, row_out));
    (nw, nh, out)
}

/// Row `y / 2` of the next level of a level with both sides even whose texel `(x, y)` is
/// `read(x, y)`, into `out` (the next level's width): each texel `((a + b) + (c + d)) / 4`
/// of the 2×2 above it (`a`, `b` the top row, from row `y`).
///
/// For values finite, not negative and far above the subnormals (unorm texels and their
/// means), the same bits as [`reduce_with`]'s general reduction: that adds `a/2 + b/2` from
/// zero, halves the row sum and adds the bottom row's in the same way; halving such values
/// is exact and commutes with rounding, so its result is `fl(fl(a + b) + fl(c + d)) / 4`
/// too (tested), here with no weights, tap lists or per-tap multiplications.
#[inline]
pub(crate) fn halve_row(y: u32, read: impl Fn(u32, u32) -> Vec4, out: &mut [Vec4]) {
    for (x, o) in (0..).step_by(2).zip(out.iter_mut()) {
        let upper = read(x, y) + read(x + 1, y);
        let lower = read(x, y + 1) + read(x + 1, y + 1);
        *o = (upper + lower) * 0.25;
    }
}

/// Makes every level below a `w`×`h` base whose linear premultiplied texel `(x, y)` is
/// `read(x, y)`, down to 1×1, handing each to `emit` (its width, height and row-major texels)
/// as soon as it is made: the base is never copied to floats, and only the last level made is
/// held. `unorm`: the base's values are those of unorm texels (finite, in [0, 1], not −0),
/// which lets levels with even sides take [`halve`].
pub(crate) fn for_each_level(
    w: u32,
    h: u32,
    unorm: bool,
    read: impl Fn(u32, u32) -> Vec4 + Sync,
    mut emit: impl FnMut(u32, u32, &[Vec4]),
) {
    if w <= 1 && h <= 1 {
        return;
    }
    let (mut cw, mut ch, mut cur) = reduce_with(w, h, unorm, read);
    loop {
        emit(cw, ch, &cur);
        if cw <= 1 && ch <= 1 {
            return;
        }
        let texels = &cur;
        let next = reduce_with(cw, ch, unorm, |x, y| texels[(y * cw + x) as usize]);
        (cw, ch, cur) = next;
    }
}

/// Straight alpha from premultiplied (colour kept where alpha is zero: it is zero too).
#[must_use]
pub(crate) fn unpremultiply(c: Vec4) -> Vec4 {
    if c.w > 0.0 {
        (c.truncate() / c.w).extend(c.w)
    } else {
        Vec4::ZERO
    }
}

/// Number of levels of a full chain for a `w`×`h` base.
#[must_use]
pub fn level_count(w: u32, h: u32) -> usize {
    (32 - w.max(h).max(1).leading_zeros()) as usize
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::texture::{ColorSpace, Format, Texture2D, TextureOptions};

    #[test]
    fn coverage_weights_sum_to_one() {
        for src in 1..40 {
            let dst = (src / 2).max(1);
            for i in 0..dst {
                let s: f32 = coverage(i, src, dst).map(|(_, w)| w).sum();
                assert!((s - 1.0).abs() < 1e-5, "src {src} dst {dst} i {i}: {s}");
            }
        }
    }

    #[test]
    fn odd_side_uses_three_taps_centred() {
        // 5 → 2: texel 0 covers [0, 2.5): weights 0.4, 0.4, 0.2; texel 1 mirrors it, so the
        // destination texel centres sit at 1.25 and 3.75 = (i + 0.5)·5/2, with no drift.
        let w0: Vec<_> = coverage(0, 5, 2).collect();
        let w1: Vec<_> = coverage(1, 5, 2).collect();
        assert_eq!(w0.iter().map(|p| p.0).collect::<Vec<_>>(), [0, 1, 2]);
        assert_eq!(w1.iter().map(|p| p.0).collect::<Vec<_>>(), [2, 3, 4]);
        for (got, want) in w0.iter().zip([0.4, 0.4, 0.2]) {
            assert!((got.1 - want).abs() < 1e-6);
        }
        for (a, b) in w0.iter().zip(w1.iter().rev()) {
            assert!((a.1 - b.1).abs() < 1e-6);
        }
    }

    #[test]
    fn chain_goes_to_one_by_one_with_gl_sizes() {
        let tex = Texture2D::from_fn(37, 10, TextureOptions::default(), |_, _| Vec4::ONE).unwrap();
        let sizes: Vec<_> = tex
            .levels()
            .iter()
            .map(|l| (l.width(), l.height()))
            .collect();
        assert_eq!(sizes, [(37, 10), (18, 5), (9, 2), (4, 1), (2, 1), (1, 1)]);
        assert_eq!(level_count(37, 10), sizes.len());
    }

    #[test]
    fn chain_costs_about_a_third_more() {
        let n = 512u32;
        let rgba = vec![128u8; (n * n * 4) as usize];
        let tex = Texture2D::from_texels(
            n,
            n,
            Format::Rgba8,
            ColorSpace::Srgb,
            &rgba,
            TextureOptions::default(),
        )
        .unwrap();
        let base = (n * n) as f64 * tex.storage_format().bytes_per_texel() as f64;
        let ratio = tex.texel_bytes() as f64 / base;
        assert!((ratio - 4.0 / 3.0).abs() < 0.01, "chain/base = {ratio}");
    }

    #[test]
    fn checkerboard_levels_average_as_expected() {
        // 8×8-texel squares of 0 and 1: levels 1..3 keep the squares (values 0 and 1),
        // level 4 onward mixes them to exactly 0.5 everywhere.
        let tex = Texture2D::from_fn(64, 64, TextureOptions::default(), |x, y| {
            Vec4::splat(((x / 8 + y / 8) % 2) as f32)
        })
        .unwrap();
        for l in 1..tex.levels().len() {
            let texels = tex.decode_level(l);
            let mean: f32 = texels.iter().map(|c| c.x).sum::<f32>() / texels.len() as f32;
            assert!((mean - 0.5).abs() < 1e-6, "level {l} mean {mean}");
            if l <= 3 {
                assert!(texels.iter().all(|c| c.x == 0.0 || c.x == 1.0), "level {l}");
            } else {
                assert!(texels.iter().all(|c| (c.x - 0.5).abs() < 1e-6), "level {l}");
            }
        }
    }

    #[test]
    fn odd_checkerboard_keeps_its_mean() {
        let tex = Texture2D::from_fn(45, 27, TextureOptions::default(), |x, y| {
            Vec4::splat(((x + y) % 2) as f32)
        })
        .unwrap();
        let base = tex.decode_level(0);
        let mean0: f32 = base.iter().map(|c| c.x).sum::<f32>() / base.len() as f32;
        let last = tex.decode_level(tex.levels().len() - 1);
        assert!((last[0].x - mean0).abs() < 1e-4, "{} vs {mean0}", last[0].x);
    }

    #[test]
    fn transparent_texels_do_not_bleed_colour() {
        // Red opaque next to green fully transparent: the average must be pure red, half alpha.
        let tex = Texture2D::from_fn(2, 1, TextureOptions::default(), |x, _| {
            if x == 0 {
                Vec4::new(1.0, 0.0, 0.0, 1.0)
            } else {
                Vec4::new(0.0, 1.0, 0.0, 0.0)
            }
        })
        .unwrap();
        let c = tex.decode_level(1)[0];
        assert!(
            (c - Vec4::new(0.5, 0.0, 0.0, 0.5)).abs().max_element() < 1e-6,
            "{c}"
        );
    }
}
