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
            let shift = parent - level;
            let (px, py) = (x >> shift, y >> shift);
            let hx = if (x >> (shift - 1)) & 1 == 0 {
                1.0
            } else {
                -1.0
            };
            let hy = if (y >> (shift - 1)) & 1 == 0 {
                1.0
            } else {
                -1.0
            };
            let key = self.seed ^ (u64::from(parent) << 58) ^ (u64::from(py) << 29) ^ u64::from(px);
            let h = mix(key.wrapping_add(0x9e37_79b9_7f4a_7c15));
            let weight = |k: u32| ((h >> (7 * k)) & 127) as f32 / 63.5 - 1.0;
            let basis = [hx, hy, hx * hy];
            let channel = |ch: u32| -> f32 {
                (0..3)
                    .map(|b| weight(3 * ch + b) * basis[b as usize])
                    .sum::<f32>()
            };
            c += Vec3::new(channel(0), channel(1), channel(2)) * AMPLITUDE;
        }
        let (x0, y0) = (x << level, y << level);
        for (s, w, depth) in GRIDS {
            let cx = line_coverage(x0, level, s, w);
            let cy = line_coverage(y0, level, s, w);
            c -= Vec3::splat(depth * (cx + cy - cx * cy));
        }
        c.extend(1.0)
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
