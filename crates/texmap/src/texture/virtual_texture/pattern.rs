//! The procedural source of the virtual-texture scene: a quadtree of colour with grid lines,
//! detail at every scale, and every level's texels exact box averages of level 0's.
//!
//! Colour is a random Haar cascade: level `k`'s texel is its parent's plus a zero-sum
//! offset over the four children (the three 2×2 Haar wavelets, each with a hashed weight in
//! ±[`AMPLITUDE`]), so the mean of any aligned `2ˡ` block of level 0 is its level-`l`
//! ancestor: a texel of any level is the sum along its path from the root, `O(levels)`
//! hashes, with no need to visit the texels below it. Grid lines (one texel wide every 16,
//! 2 every 128, 4 every 1,024, 8 every 8,192) darken the colour; a line's coverage of an
//! aligned block has a closed form, so they too are exact at every level.

use glam::{Vec3, Vec4};

use super::source::PageSource;

/// The weight bound of each Haar wavelet at every level (linear light).
pub const AMPLITUDE: f32 = 0.03;
/// The colour at the root (linear).
const BASE: Vec3 = Vec3::new(0.42, 0.36, 0.28);
/// Grid families: spacing 2^s texels, width 2^w, how much they darken.
const GRIDS: [(u32, u32, f32); 4] = [(4, 0, 0.07), (7, 1, 0.1), (10, 2, 0.13), (13, 3, 0.16)];

/// The quadtree pattern on a `2^side_log2` square.
#[derive(Clone, Copy, Debug)]
pub struct QuadtreePattern {
    side_log2: u32,
    seed: u64,
}

impl QuadtreePattern {
    /// The pattern on a `2^side_log2` square; `seed` chooses its colours.
    #[must_use]
    pub fn new(side_log2: u32, seed: u64) -> Self {
        QuadtreePattern { side_log2, seed }
    }
}

/// SplitMix64's finalizer: a well-mixed 64 bits from a key.
fn mix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// The share of an aligned block of `2^level` texels starting at texel `x0` that a family of
/// lines `2^w` wide every `2^s` covers along one axis.
fn line_coverage(x0: u32, level: u32, s: u32, w: u32) -> f32 {
    let period = 1u32 << s;
    if level > s {
        (1u32 << w) as f32 / period as f32
    } else if level > w {
        if x0.is_multiple_of(period) {
            (1u32 << w) as f32 / (1u32 << level) as f32
        } else {
            0.0
        }
    } else if x0 % period < (1 << w) {
        1.0
    } else {
        0.0
    }
}

impl QuadtreePattern {
    /// The offset child `(x, y)` of level `parent − 1` adds to its parent's colour.
    #[inline]
    fn offset(&self, parent: u32, x: u32, y: u32) -> Vec3 {
        let (px, py) = (x >> 1, y >> 1);
        let hx = if x & 1 == 0 { 1.0 } else { -1.0 };
        let hy = if y & 1 == 0 { 1.0 } else { -1.0 };
        let key = self.seed ^ (u64::from(parent) << 58) ^ (u64::from(py) << 29) ^ u64::from(px);
        let h = mix(key.wrapping_add(0x9e37_79b9_7f4a_7c15));
        let weight = |k: u32| ((h >> (7 * k)) & 127) as f32 / 63.5 - 1.0;
        let basis = [hx, hy, hx * hy];
        let channel = |ch: u32| -> f32 {
            (0..3)
                .map(|b| weight(3 * ch + b) * basis[b as usize])
                .sum::<f32>()
        };
        Vec3::new(channel(0), channel(1), channel(2)) * AMPLITUDE
    }

    /// How much the grid lines darken texel `x` (along one axis) of level `level`, per
    /// family.
    fn lines(level: u32, x: u32) -> [f32; GRIDS.len()] {
        GRIDS.map(|(s, w, _)| line_coverage(x << level, level, s, w))
    }

    /// The colour with the lines of coverages `cx`, `cy` taken off.
    #[inline]
    fn with_lines(mut c: Vec3, cx: &[f32; GRIDS.len()], cy: &[f32; GRIDS.len()]) -> Vec4 {
        for (k, (_, _, depth)) in GRIDS.iter().enumerate() {
            c -= Vec3::splat(depth * (cx[k] + cy[k] - cx[k] * cy[k]));
        }
        c.extend(1.0)
    }
}

impl PageSource for QuadtreePattern {
    fn describe(&self) -> String {
        format!(
            "procedural quadtree (Haar cascade of colour, grid lines every 16/128/1024/8192 texels), seed {}",
            self.seed
        )
    }

    fn texel(&self, level: u32, x: u32, y: u32) -> Vec4 {
        let mut c = BASE;
        // From the root down to this texel: each step adds the zero-sum offset of the child
        // the path takes.
        for parent in (level + 1..=self.side_log2).rev() {
            let shift = parent - level - 1;
            c += self.offset(parent, x >> shift, y >> shift);
        }
        Self::with_lines(c, &Self::lines(level, x), &Self::lines(level, y))
    }

    /// The grid `xs × ys` level by level from the root: each level's texels from their
    /// parents', one offset each, so a page costs about 4/3 of an offset a texel instead of
    /// one per level above it. The sums run in [`PageSource::texel`]'s order: the same bits.
    fn fill(&self, level: u32, xs: &[u32], ys: &[u32], out: &mut [Vec4]) {
        // The distinct indices of every level from this one to the root, sorted.
        let chain = |v: &[u32]| -> Vec<Vec<u32>> {
            let mut first = v.to_vec();
            first.sort_unstable();
            first.dedup();
            let mut all = vec![first];
            for _ in level..self.side_log2 {
                let mut up: Vec<u32> = all
                    .last()
                    .map_or(Vec::new(), |l| l.iter().map(|x| x >> 1).collect());
                up.dedup();
                all.push(up);
            }
            all
        };
        let (cx, cy) = (chain(xs), chain(ys));
        let top = (self.side_log2 - level) as usize;
        let mut grid = vec![BASE; cx[top].len() * cy[top].len()];
        for k in (0..top).rev() {
            let parent = level + k as u32 + 1;
            let (px, py) = (&cx[k + 1], &cy[k + 1]);
            let at = |p: &[u32], v: u32| p.binary_search(&(v >> 1)).unwrap_or(0);
            let ix: Vec<usize> = cx[k].iter().map(|&x| at(px, x)).collect();
            let mut next = Vec::with_capacity(cx[k].len() * cy[k].len());
            for &y in &cy[k] {
                let row = at(py, y) * px.len();
                for (&x, &i) in cx[k].iter().zip(&ix) {
                    next.push(grid[row + i] + self.offset(parent, x, y));
                }
            }
            grid = next;
        }
        let lines_x: Vec<_> = cx[0].iter().map(|&x| Self::lines(level, x)).collect();
        let lines_y: Vec<_> = cy[0].iter().map(|&y| Self::lines(level, y)).collect();
        let ix: Vec<usize> = xs
            .iter()
            .map(|x| cx[0].binary_search(x).unwrap_or(0))
            .collect();
        for (row, &y) in out.chunks_exact_mut(xs.len()).zip(ys) {
            let j = cy[0].binary_search(&y).unwrap_or(0);
            for (o, &i) in row.iter_mut().zip(&ix) {
                *o = Self::with_lines(grid[j * cx[0].len() + i], &lines_x[i], &lines_y[j]);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The mean of level 0's texels under a texel of level `l`.
    fn block_mean(p: &QuadtreePattern, level: u32, x: u32, y: u32) -> Vec4 {
        let n = 1u32 << level;
        let mut sum = Vec4::ZERO;
        for j in 0..n {
            for i in 0..n {
                sum += p.texel(0, (x << level) + i, (y << level) + j);
            }
        }
        sum / (n * n) as f32
    }

    #[test]
    fn every_level_is_the_box_average_of_level_zero() {
        let p = QuadtreePattern::new(9, 7);
        for level in 1..=9 {
            let side = 512 >> level;
            for (x, y) in [
                (0, 0),
                (side - 1, 0),
                (side / 2, side / 3),
                (side - 1, side - 1),
            ] {
                let (got, want) = (p.texel(level, x, y), block_mean(&p, level, x, y));
                assert!(
                    (got - want).abs().max_element() < 2e-5,
                    "level {level} ({x}, {y}): {got} vs {want}"
                );
            }
        }
    }

    #[test]
    fn a_filled_grid_equals_its_texels_bit_for_bit() {
        let p = QuadtreePattern::new(12, 4);
        // Wrapped indices, as a page's border at the texture's edge takes them.
        let xs: Vec<u32> = (4092..4096).chain(0..9).collect();
        let ys: Vec<u32> = (1000..1013).collect();
        for level in [0, 3] {
            let n = 4096 >> level;
            let (xs, ys): (Vec<u32>, Vec<u32>) = (
                xs.iter().map(|&x| x % n).collect(),
                ys.iter().map(|&y| y % n).collect(),
            );
            let mut out = vec![Vec4::ZERO; xs.len() * ys.len()];
            p.fill(level, &xs, &ys, &mut out);
            for (j, &y) in ys.iter().enumerate() {
                for (i, &x) in xs.iter().enumerate() {
                    assert_eq!(out[j * xs.len() + i], p.texel(level, x, y), "({x}, {y})");
                }
            }
        }
    }

    #[test]
    fn lines_cover_what_they_should() {
        // One-texel lines every 16: texel 0 on, 1 off; a 4-texel block at 0 a quarter.
        assert_eq!(line_coverage(0, 0, 4, 0), 1.0);
        assert_eq!(line_coverage(1, 0, 4, 0), 0.0);
        assert_eq!(line_coverage(0, 2, 4, 0), 0.25);
        assert_eq!(line_coverage(4, 2, 4, 0), 0.0);
        assert_eq!(line_coverage(0, 6, 4, 0), 1.0 / 16.0);
    }

    #[test]
    fn the_colour_has_detail_at_the_finest_level() {
        let p = QuadtreePattern::new(16, 1);
        let (a, b) = (p.texel(0, 40_001, 7), p.texel(0, 40_002, 7));
        assert!((a - b).abs().max_element() > 1e-3);
    }
}
