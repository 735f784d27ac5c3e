//! Bin: primitives → per-tile lists, once per frame.
//!
//! The target is cut into [`TILE`]×[`TILE`] pixel tiles; each primitive is listed in every
//! tile its bounding box touches, in draw order. The lists are stored compactly (counts,
//! prefix sums, one index array), so binning allocates three vectors per frame, not one per
//! tile. Tiles are then rasterized independently, each in draw order.

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

/// Bins `prims` (visited in `order`) for a `width × height` target.
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
    let mut counts = vec![0u32; n + 1];
    for &i in order {
        let (x0, y0, x1, y1) = range(&prims[i as usize]);
        for ty in y0..=y1 {
            for tx in x0..=x1 {
                counts[(ty * tiles_x + tx) as usize] += 1;
            }
        }
    }
    let mut offsets = vec![0u32; n + 1];
    let mut sum = 0u32;
    for t in 0..n {
        offsets[t] = sum;
        sum += counts[t];
    }
    offsets[n] = sum;
    let mut cursor = offsets.clone();
    let mut list = vec![0u32; sum as usize];
    for &i in order {
        let (x0, y0, x1, y1) = range(&prims[i as usize]);
        for ty in y0..=y1 {
            for tx in x0..=x1 {
                let t = (ty * tiles_x + tx) as usize;
                list[cursor[t] as usize] = i;
                cursor[t] += 1;
            }
        }
    }
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
