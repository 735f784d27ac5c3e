//! The covered quads a tile's depth pre-pass finds, kept for its shading pass.
//!
//! The pre-pass (`raster.rs`) walks every pre-passed primitive's quads once: it tests the
//! edges, takes the nearest depth per pixel, and keeps each covered quad here (its place in
//! the tile, its covered pixels, its four depths), primitive after primitive in draw order.
//! The shading pass then reads a primitive's quads back instead of walking its coverage again
//! (edge setup, the bounding box's empty quads, the edge tests): with the 199,200-triangle
//! sphere, whose triangles cover a few pixels each, the walk cost as much as the pre-pass.
//! The quads and their depths are the walk's own, so the image is the same.

use std::cell::RefCell;

/// One covered quad of a pre-passed primitive: top-left pixel `(lx, ly)` in the tile, the
/// pixels whose centre the primitive covers (bit `j`: pixel `(lx + (j & 1), ly + (j >> 1))`),
/// and the primitive's depth at the four pixel centres.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct CoveredQuad {
    pub zp: [f32; 4],
    pub lx: u8,
    pub ly: u8,
    pub mask: u8,
}

/// A tile's covered quads, grouped by primitive in the order the pre-pass visited them.
#[derive(Default)]
pub(super) struct Covered {
    quads: Vec<CoveredQuad>,
    /// Where each primitive's quads start in `quads`.
    starts: Vec<u32>,
    /// The next primitive [`Covered::next_prim`] hands out.
    cursor: usize,
}

impl Covered {
    /// Empties the lists for a new tile.
    pub(super) fn clear(&mut self) {
        self.quads.clear();
        self.starts.clear();
        self.cursor = 0;
    }

    /// Starts the next primitive's quads (call once per pre-passed primitive, covered or not).
    #[inline]
    pub(super) fn begin_prim(&mut self) {
        self.starts.push(self.quads.len() as u32);
    }

    /// Keeps a covered quad of the current primitive.
    #[inline(always)]
    pub(super) fn push(&mut self, quad: CoveredQuad) {
        self.quads.push(quad);
    }

    /// The quads of the next primitive, in the order [`Covered::begin_prim`] started them.
    ///
    /// # Panics
    /// When every started primitive has been handed out.
    #[inline]
    pub(super) fn next_prim(&mut self) -> &[CoveredQuad] {
        let k = self.cursor;
        self.cursor += 1;
        let start = self.starts[k] as usize;
        let end = self
            .starts
            .get(k + 1)
            .map_or(self.quads.len(), |&e| e as usize);
        &self.quads[start..end]
    }
}

thread_local! {
    /// One list per thread, reused tile after tile (no allocation once it has grown).
    static COVERED: RefCell<Covered> = RefCell::new(Covered::default());
}

/// Runs `f` with this thread's list, cleared.
pub(super) fn with_covered<R>(f: impl FnOnce(&mut Covered) -> R) -> R {
    COVERED.with(|c| {
        let mut c = c.borrow_mut();
        c.clear();
        f(&mut c)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pipeline::{
        draw, ClipVertex, DrawCall, DrawState, FragmentShader, Interpolation, Quad, Target,
        MAX_VARYINGS,
    };
    use glam::Vec4;

    /// Writes the first three varyings and the draw (from 1); draw 2 discards a pattern of
    /// pixels.
    struct Varyings;
    impl FragmentShader for Varyings {
        fn shade(&self, draw: u32, q: &Quad, out: &mut [Vec4; 4]) -> u8 {
            let mut kept = q.mask;
            for (j, o) in out.iter_mut().enumerate() {
                let p = q.pixel(j);
                *o = Vec4::new(p[0], p[1], p[2], draw as f32 + 1.0);
                if draw == 2 && (q.x + j as u32).is_multiple_of(3) {
                    kept &= !(1 << j);
                }
            }
            kept
        }
    }

    /// A grid of small triangles over the target: `z` and `w` vary across it, the varyings
    /// are the position in normalized device coordinates.
    fn grid(n: usize, z: impl Fn(f32, f32) -> f32, w: impl Fn(f32, f32) -> f32) -> Vec<ClipVertex> {
        let mut out = Vec::new();
        let at = |i: usize, j: usize| {
            let (x, y) = (
                i as f32 / n as f32 * 2.0 - 1.0,
                j as f32 / n as f32 * 2.0 - 1.0,
            );
            let w = w(x, y);
            let mut varyings = [0.0; MAX_VARYINGS];
            varyings[..3].copy_from_slice(&[x, y, z(x, y)]);
            ClipVertex {
                clip: Vec4::new(x * w, y * w, z(x, y) * w, w),
                varyings,
            }
        };
        for i in 0..n {
            for j in 0..n {
                let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
                out.extend([a, b, c, a, c, d]);
            }
        }
        out
    }

    #[test]
    fn kept_quads_shade_what_walking_again_would() {
        // Three overlapping layers of small triangles (tilted against each other, so each
        // hides the others in places), a discarding draw between them, over several tiles.
        let draws = [
            grid(37, |x, _| 0.2 + 0.3 * x, |x, y| 1.0 + 0.2 * (x + y)),
            grid(29, |_, y| 0.1 - 0.4 * y, |_, _| 1.0),
            grid(23, |x, y| 0.1 * x * y, |x, _| 1.5 - 0.3 * x),
            grid(41, |x, y| 0.3 * (y - x), |_, y| 1.0 + 0.1 * y),
        ];
        let indices: Vec<u32> = (0..draws.iter().map(Vec::len).max().unwrap() as u32).collect();
        let target = Target {
            width: 150,
            height: 97,
            samples: 1,
            clear_color: Vec4::ZERO,
            interpolation: Interpolation::Perspective,
            depth_sort: false,
        };
        let run = |pre: bool| {
            let calls: Vec<DrawCall> = draws
                .iter()
                .enumerate()
                .map(|(k, v)| DrawCall {
                    vertices: v,
                    indices: &indices[..v.len()],
                    state: DrawState {
                        varyings: 3,
                        keeps_all: pre && k != 2,
                        ..Default::default()
                    },
                })
                .collect();
            draw(&calls, &Varyings, &target)
        };
        let bits = |c: &[Vec4]| {
            c.iter()
                .flat_map(|v| v.to_array().map(f32::to_bits))
                .collect::<Vec<_>>()
        };
        let ((with, with_stats), (without, without_stats)) = (run(true), run(false));
        assert_eq!(bits(&with), bits(&without));
        assert!(with_stats.pixels_shaded < without_stats.pixels_shaded);
        // Every layer shows somewhere.
        for k in 1..=4 {
            assert!(with.iter().any(|c| c.w == k as f32), "layer {k}");
        }
    }

    fn quad(lx: u8) -> CoveredQuad {
        CoveredQuad {
            zp: [0.5; 4],
            lx,
            ly: 0,
            mask: 0b1111,
        }
    }

    #[test]
    fn primitives_get_back_their_own_quads_in_order_empty_ones_included() {
        with_covered(|c| {
            c.begin_prim();
            c.push(quad(0));
            c.push(quad(2));
            c.begin_prim();
            c.begin_prim();
            c.push(quad(4));
            assert_eq!(c.next_prim(), &[quad(0), quad(2)]);
            assert!(c.next_prim().is_empty());
            assert_eq!(c.next_prim(), &[quad(4)]);
        });
        // The next tile starts empty.
        with_covered(|c| {
            c.begin_prim();
            assert!(c.next_prim().is_empty());
        });
    }
}
