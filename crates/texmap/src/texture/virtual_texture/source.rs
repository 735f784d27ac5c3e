//! Where pages come from: a [`PageSource`] gives any texel of any level, and [`build_page`]
//! cuts one page (with its border, wrapped as the texture wraps) into a small [`Texture2D`]
//! the existing filters read.

use glam::Vec4;

use super::layout::{PageKey, PageLayout, PAGE_BORDER};
use crate::texture::{ColorSpace, Format, Texture2D, TextureOptions, Wrap};
use crate::Result;

/// A texture too large to hold, read a page at a time.
///
/// Level `l`'s texel `(x, y)` must be the box average of the `2ˡ × 2ˡ` texels of level 0 it
/// covers (what [`Texture2D`]'s mip chain holds for a power-of-two side), so a virtual read
/// equals the read of the same texture held whole.
pub trait PageSource: Send + Sync + std::fmt::Debug {
    /// One line for `texmap info`: what the texels are.
    fn describe(&self) -> String;
    /// Linear, premultiplied texel `(x, y)` of level `level` (both in range).
    fn texel(&self, level: u32, x: u32, y: u32) -> Vec4;

    /// The texels of level `level` at every `(xs[i], ys[j])` (in range), row by row into
    /// `out` (`xs.len() · ys.len()` long). A source that shares work between neighbours
    /// overrides it; the default reads [`PageSource::texel`] one by one.
    fn fill(&self, level: u32, xs: &[u32], ys: &[u32], out: &mut [Vec4]) {
        for (row, &y) in out.chunks_exact_mut(xs.len().max(1)).zip(ys) {
            for (o, &x) in row.iter_mut().zip(xs) {
                *o = self.texel(level, x, y);
            }
        }
    }
}

/// Texel index `i` of a level of `n` texels, wrapped as `wrap` says (repeat or clamp).
fn wrap_index(wrap: Wrap, i: i64, n: u32) -> u32 {
    match wrap {
        Wrap::Repeat => i.rem_euclid(i64::from(n)) as u32,
        _ => i.clamp(0, i64::from(n) - 1) as u32,
    }
}

/// Page `key` of `source`: the level's texels it covers and a border of [`PAGE_BORDER`] on
/// each side, RGBA16F, one level (no mip chain: the page table holds the levels).
pub(super) fn build_page(
    source: &dyn PageSource,
    layout: &PageLayout,
    key: PageKey,
    wraps: (Wrap, Wrap),
) -> Result<Texture2D> {
    let n = layout.level_side(key.level);
    let span = layout.span(key.level);
    let side = span + 2 * PAGE_BORDER;
    let origin = |p: u32| i64::from(p * span) - i64::from(PAGE_BORDER);
    let (ox, oy) = (origin(key.x), origin(key.y));
    let xs: Vec<u32> = (0..side)
        .map(|i| wrap_index(wraps.0, ox + i64::from(i), n))
        .collect();
    let ys: Vec<u32> = (0..side)
        .map(|i| wrap_index(wraps.1, oy + i64::from(i), n))
        .collect();
    let mut texels = vec![Vec4::ZERO; (side * side) as usize];
    source.fill(key.level, &xs, &ys, &mut texels);
    let mut bytes = vec![0u8; (side * side) as usize * 8];
    for (c, texel) in texels.iter().zip(bytes.chunks_exact_mut(8)) {
        let straight = if c.w > 0.0 {
            (c.truncate() / c.w).extend(c.w)
        } else {
            Vec4::ZERO
        };
        Format::Rgba16F.encode(straight, ColorSpace::Linear, texel);
    }
    Texture2D::from_texels(
        side,
        side,
        Format::Rgba16F,
        ColorSpace::Linear,
        &bytes,
        TextureOptions::default().with_mipmaps(false),
    )
}
