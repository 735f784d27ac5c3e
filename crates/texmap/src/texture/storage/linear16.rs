//! Writing the default storage of 8-bit colour ([`Format::Rgba16Premultiplied`]) fast: its
//! texels encoded a row at a time (for [`Texture2D::fill_rows`]), and the first two levels of
//! a chain made together in strips ([`Texture2D::first_two_levels`]), so that level 1 is never
//! held whole in floats.
//!
//! Loading DamagedHelmet (one thread), each 2048² sRGB map spent 22 ms storing level 0 texel
//! by texel and 27–30 ms building its chain, 12 ms of it reducing level 0 into a 16 MiB
//! float copy of level 1 (every page of it faulted in, written once and read once) and 9 ms
//! storing that. The values are the general paths' (`fill.rs`, `mip.rs`), bit for bit
//! (tested).

use glam::Vec4;
use rayon::prelude::*;

use super::fill::place_row;
use super::{mip, Bands, Level, Texture2D};
use crate::texture::format::Format;

impl Texture2D {
    /// Levels 1 and 2 of a `w`×`h` base of unorm values whose texel `(x, y)` is `read(x, y)`
    /// (both sides multiples of four; stored as [`Format::Rgba16Premultiplied`]): level 1
    /// stored, level 2 as floats (row-major) for the rest of the chain. Each band of four
    /// level-1 rows is made from eight base rows ([`mip::halve_row`]), stored and halved
    /// into two rows of level 2 while it is in the cache, bands in parallel; the values are
    /// those of [`mip::for_each_level`] (every texel a function of its 2×2 above).
    pub(super) fn first_two_levels(
        &self,
        w: u32,
        h: u32,
        read: impl Fn(u32, u32) -> Vec4 + Sync,
    ) -> (Level, Vec<Vec4>) {
        debug_assert!(w.is_multiple_of(4) && h.is_multiple_of(4));
        debug_assert_eq!(self.stored, Format::Rgba16Premultiplied);
        let (w1, h1, w2, h2) = (w / 2, h / 2, w / 4, h / 4);
        let Bands { tiles_x, band, len } = Bands::of(self.layout, w1, h1);
        let mut data = vec![0u8; len * 8];
        let mut level2 = vec![Vec4::ZERO; (w2 * h2) as usize];
        let (layout, w1s) = (self.layout, w1 as usize);
        data.par_chunks_mut(band * 8)
            .zip(level2.par_chunks_mut(2 * w2 as usize))
            .enumerate()
            .for_each(|(b, (chunk, two))| {
                let rows = (h1 as usize - 4 * b).min(4);
                let mut floats = vec![Vec4::ZERO; 4 * w1s];
                let mut texels = vec![0u8; 8 * w1s];
                for (r, out) in floats.chunks_exact_mut(w1s).take(rows).enumerate() {
                    mip::halve_row(2 * (4 * b + r) as u32, &read, out);
                    premultiplied16_row(out, &mut texels);
                    place_row(layout, chunk, r, 8, &texels);
                }
                for (r, out) in two.chunks_exact_mut(w2 as usize).enumerate() {
                    let level1 = |x: u32, y: u32| floats[y as usize * w1s + x as usize];
                    mip::halve_row(2 * r as u32, level1, out);
                }
            });
        let level1 = Level {
            width: w1,
            height: h1,
            tiles_x,
            data,
            block_id: None,
        };
        (level1, level2)
    }
}

/// [`premultiplied16`] of each texel of `row` into `out` (eight bytes a texel).
pub(super) fn premultiplied16_row(row: &[Vec4], out: &mut [u8]) {
    for (o, &t) in out.chunks_exact_mut(8).zip(row) {
        o.copy_from_slice(&premultiplied16(t));
    }
}

/// A linear premultiplied texel as [`Format::Rgba16Premultiplied`] holds it
/// (`Format::encode`'s arm for that format of the unpremultiplied texel, inlined: the same
/// values): the colour divided by alpha and multiplied by the clamped alpha again, each
/// channel clamped and rounded to 16 bits. An opaque texel is kept as it is (dividing and
/// multiplying by 1 change nothing).
#[inline(always)]
fn premultiplied16(t: Vec4) -> [u8; 8] {
    let p = if t.w == 1.0 {
        t
    } else {
        let c = mip::unpremultiply(t);
        let a = c.w.clamp(0.0, 1.0);
        (c.truncate() * a).extend(a)
    };
    let q = p
        .to_array()
        .map(|v| (v.clamp(0.0, 1.0) * 65535.0 + 0.5) as u16);
    let packed =
        u64::from(q[0]) | u64::from(q[1]) << 16 | u64::from(q[2]) << 32 | u64::from(q[3]) << 48;
    packed.to_le_bytes()
}
