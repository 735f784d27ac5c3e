//! Bin: primitives → per-tile lists, once per frame.
//!
//! The target is cut into [`TILE`]×[`TILE`] pixel tiles; each primitive is listed in every
//! tile its bounding box touches, in draw order. The lists are stored compactly (counts,
//! prefix sums, one index array), so binning allocates a few vectors per frame, not one per
//! tile. Runs of primitives are binned in parallel into their own places of those lists, so
//! the lists are the serial pass's. Tiles are then rasterized independently, each in draw
//! order.

use rayon::prelude::*;

use super::Prim;

/// Tile side in pixels (even, so 2×2 quads never straddle tiles).
pub const TILE: u32 = 64;

/// A tile's pixel rectangle, `x0..x1` × `y0..y1` (exclusive ends).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TileRect {
    pub x0: u32,
    pub y0: u32,
    pub x1: u32,
    pub y1: u32,
}

/// The per-tile primitive lists.
#[derive(Clone, Debug)]
pub struct Bins {
    pub width: u32,
    pub height: u32,
    pub tiles_x: u32,
    pub tiles_y: u32,
    /// `offsets[t]..offsets[t + 1]` indexes `prims` for tile `t`.
    offsets: Vec<u32>,
    prims: Vec<u32>,
}

impl Bins {
    /// Number of tiles.
    #[must_use]
    pub fn tile_count(&self) -> usize {
        (self.tiles_x * self.tiles_y) as usize
    }

    /// The primitives of tile `t`, in draw order.
    #[must_use]
    pub fn tile_prims(&self, t: usize) -> &[u32] {
        &self.prims[self.offsets[t] as usize..self.offsets[t + 1] as usize]
    }

    /// The pixels of tile `t` (row-major tile order).
    #[must_use]
    pub fn tile_rect(&self, t: usize) -> TileRect {
        let tx = t as u32 % self.tiles_x;
        let ty = t as u32 / self.tiles_x;
        TileRect {
            x0: tx * TILE,
            y0: ty * TILE,
            x1: ((tx + 1) * TILE).min(self.width),
            y1: ((ty + 1) * TILE).min(self.height),
        }
    }
}

/// Primitives binned by one task of [`bin_prims`]: a run of `order` this long is counted and
/// placed by one task (fewer and the counting arrays cost more than the work they share).
const BIN_CHUNK: usize = 16384;

/// Bins `prims` (visited in `order`) for a `width × height` target.
///
/// In parallel (rayon's current pool), with the same lists as one pass in order: `order` is cut
/// into runs; each run counts its primitives per tile, the counts give every run its place
/// in every tile's list (the runs in order), and each run writes its primitives there.
#[must_use]
pub fn bin_prims(prims: &[Prim], order: &[u32], width: u32, height: u32) -> Bins {
    let tiles_x = width.div_ceil(TILE);
    let tiles_y = height.div_ceil(TILE);
    let n = (tiles_x * tiles_y) as usize;
    let range = |p: &Prim| {
        let s = TILE.trailing_zeros();
        (
            (p.bbox[0] as u32) >> s,
            (p.bbox[1] as u32) >> s,
            (p.bbox[2] as u32) >> s,
            (p.bbox[3] as u32) >> s,
        )
    };
    let runs: Vec<&[u32]> = order.chunks(BIN_CHUNK).collect();
    let counts: Vec<Vec<u32>> = runs
        .par_iter()
        .map(|run| {
            let mut counts = vec![0u32; n];
            for &i in *run {
                let (x0, y0, x1, y1) = range(&prims[i as usize]);
                for ty in y0..=y1 {
                    for tx in x0..=x1 {
                        counts[(ty * tiles_x + tx) as usize] += 1;
                    }
                }
            }
            counts
        })
        .collect();
    let mut offsets = vec![0u32; n + 1];
    let mut sum = 0u32;
    for t in 0..n {
        offsets[t] = sum;
        sum += counts.iter().map(|c| c[t]).sum::<u32>();
    }
    offsets[n] = sum;
    // Each run's piece of each tile's list: tile by tile, the runs in order.
    let mut list = vec![0u32; sum as usize];
    let mut pieces: Vec<Vec<&mut [u32]>> = runs.iter().map(|_| Vec::with_capacity(n)).collect();
    let mut rest = &mut list[..];
    for t in 0..n {
        for (k, c) in counts.iter().enumerate() {
            let (piece, tail) = std::mem::take(&mut rest).split_at_mut(c[t] as usize);
            pieces[k].push(piece);
            rest = tail;
        }
    }
    runs.par_iter()
        .zip(pieces.into_par_iter())
        .for_each(|(run, mut pieces)| {
            let mut cursor = vec![0u32; n];
            for &i in *run {
                let (x0, y0, x1, y1) = range(&prims[i as usize]);
                for ty in y0..=y1 {
                    for tx in x0..=x1 {
                        let t = (ty * tiles_x + tx) as usize;
                        pieces[t][cursor[t] as usize] = i;
                        cursor[t] += 1;
                    }
                }
            }
        });
    Bins {
        width,
        height,
        tiles_x,
        tiles_y,
        offsets,
        prims: list,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn prim(bbox: [i32; 4]) -> Prim {
        Prim {
            v: [0; 3],
            call: 0,
            bbox,
            sort_depth: 0.0,
            front_facing: true,
            affine: false,
        }
    }

    #[test]
    fn runs_binned_in_parallel_make_the_lists_of_one_pass_in_order() {
        // More primitives than one run, scattered bounding boxes, a shuffled order.
        let mut s = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = |m: u32| {
            s = s.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
            ((s >> 33) as u32) % m
        };
        let (w, h) = (700, 300);
        let prims: Vec<Prim> = (0..3 * BIN_CHUNK + 17)
            .map(|_| {
                let (x, y) = (next(w) as i32, next(h) as i32);
                let (dx, dy) = (next(150) as i32, next(90) as i32);
                prim([x, y, (x + dx).min(w as i32 - 1), (y + dy).min(h as i32 - 1)])
            })
            .collect();
        let mut order: Vec<u32> = (0..prims.len() as u32).collect();
        for i in (1..order.len()).rev() {
            order.swap(i, next(i as u32 + 1) as usize);
        }
        let bins = bin_prims(&prims, &order, w, h);
        for t in 0..bins.tile_count() {
            let r = bins.tile_rect(t);
            let want: Vec<u32> = order
                .iter()
                .copied()
                .filter(|&i| {
                    let b = prims[i as usize].bbox;
                    b[0] < r.x1 as i32
                        && b[2] >= r.x0 as i32
                        && b[1] < r.y1 as i32
                        && b[3] >= r.y0 as i32
                })
                .collect();
            assert_eq!(bins.tile_prims(t), &want[..], "tile {t}");
        }
    }

    #[test]
    fn prims_land_in_every_touched_tile_in_order() {
        let prims = [prim([0, 0, 70, 10]), prim([65, 65, 65, 65])];
        let bins = bin_prims(&prims, &[1, 0], 130, 100);
        assert_eq!((bins.tiles_x, bins.tiles_y), (3, 2));
        assert_eq!(bins.tile_prims(0), &[0]);
        assert_eq!(bins.tile_prims(1), &[0]);
        assert_eq!(bins.tile_prims(4), &[1]);
        assert!(bins.tile_prims(2).is_empty());
        assert_eq!(
            bins.tile_rect(5),
            TileRect {
                x0: 128,
                y0: 64,
                x1: 130,
                y1: 100
            }
        );
    }
}
