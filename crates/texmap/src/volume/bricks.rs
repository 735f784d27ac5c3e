//! Empty-space skipping: the box is cut into bricks of 8³ cells, each with the min/max of its
//! voxels, and a ray crosses a brick its classification leaves transparent in one jump.
//!
//! Rules:
//! - Brick `b` covers cells `[8b, 8b + 8)`, i.e. voxels `8b ..= 8b + 8` (neighbours share a
//!   face of voxels), so a trilinear value anywhere in its cells lies within its min/max.
//! - A brick is empty for a frame when its whole value interval is transparent under the
//!   frame's table (composite) or lies below the iso-value (iso); MIP and X-ray skip nothing.
//! - A ray in an empty brick jumps to the first sample position past the brick's box. Sample
//!   positions never move, so skipping changes no pixel (tested). The jump aims 1/1000 of a
//!   step short of the exit, so a sample within rounding of the brick's face is looked at
//!   again (it is still in the brick) rather than passed over.
//! - The composite loops test bricks through a [`BrickCursor`], which looks a brick up once,
//!   at its first sample: the samples before the exit of a brick found non-empty need no test.
//!   (Iso rays test every sample: [`EmptyBricks::skip`].) A cursor that yielded the samples to
//!   take (an iterator owning the sample index) cost the shaded loop more instructions than
//!   this test inside the caller's loop.
//! - The cursor foresees the next brick (across the face the ray leaves by) and computes its
//!   exit from that, checking the sample's own brick beside it: the chain from one brick's
//!   exit to the next is then the brick's faces, not the sample's position, its cell and its
//!   brick (about a hundred cycles of dependent steps). An edge, a corner or a brick thinner
//!   than a step foresees wrong; the exit is then computed again from the sample's brick, so
//!   the samples are those of looking every brick up (tested).

use glam::{BVec4A, Vec3, Vec4};
use rayon::prelude::*;

use super::cell::Locator;
use super::rays::RaySamples;

/// Cells per brick side for empty-space skipping.
pub const BRICK: u32 = 8;

/// Min/max 16-bit level of the voxels of each brick (computed once per volume).
#[derive(Clone, Debug)]
pub struct Bricks {
    pub counts: [u32; 3],
    pub min_max: Vec<(f32, f32)>,
}

impl Bricks {
    /// The bricks of the 16-bit `levels` of a `dims` grid (x fastest): brick `b` covers cells
    /// `[8b, 8b + 8)`, i.e. voxels `8b ..= 8b + 8`.
    #[must_use]
    pub fn new(levels: &[u16], dims: [u32; 3]) -> Self {
        let d = dims;
        let cells = d.map(|n| (n - 1).max(1));
        let counts = cells.map(|c| c.div_ceil(BRICK));
        let data = levels;
        let (nx, ny) = (d[0] as usize, d[1] as usize);
        let slabs: Vec<Vec<(f32, f32)>> = (0..counts[2])
            .into_par_iter()
            .map(|bz| {
                let mut out =
                    vec![(f32::INFINITY, f32::NEG_INFINITY); (counts[0] * counts[1]) as usize];
                let z0 = bz * BRICK;
                let z1 = (z0 + BRICK).min(d[2] - 1);
                for z in z0..=z1 {
                    for y in 0..d[1] {
                        let by_lo = (y.saturating_sub(1) / BRICK).min(counts[1] - 1);
                        let by_hi = (y / BRICK).min(counts[1] - 1);
                        let row = &data[(z as usize * ny + y as usize) * nx..][..nx];
                        for (x, &v) in row.iter().enumerate() {
                            let v = f32::from(v);
                            let x = x as u32;
                            let bx_lo = (x.saturating_sub(1) / BRICK).min(counts[0] - 1);
                            let bx_hi = (x / BRICK).min(counts[0] - 1);
                            for by in by_lo..=by_hi {
                                for bx in bx_lo..=bx_hi {
                                    let m = &mut out[(by * counts[0] + bx) as usize];
                                    m.0 = m.0.min(v);
                                    m.1 = m.1.max(v);
                                }
                            }
                        }
                    }
                }
                out
            })
            .collect();
        Bricks {
            counts,
            min_max: slabs.concat(),
        }
    }
}

/// Which bricks one frame's rays may cross in one jump, under its classification.
#[derive(Clone, Debug)]
pub(crate) struct EmptyBricks {
    empty: Vec<bool>,
    counts: [u32; 3],
    /// The grid's cells.
    grid: Locator,
    /// Whether a brick may be skipped at all; when not ([`Self::none`]), the composite
    /// loops never look a brick up.
    any: bool,
}

/// What a ray does at a sample whose brick it looked up (the procedure [`BrickCursor`]
/// follows, spelled out for its test).
#[cfg(test)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum BrickStep {
    /// The brick is empty: go on at sample `next`, the first past it.
    Skip { next: u32 },
    /// The brick is not empty: take the samples before `until`, the first past it, without
    /// looking again.
    Sample { until: u32 },
}

impl EmptyBricks {
    /// Each brick of `bricks` (of a `dims` grid) marked by `is_empty(min, max)` of its levels.
    #[must_use]
    pub fn new(bricks: &Bricks, dims: [u32; 3], is_empty: impl Fn(f32, f32) -> bool) -> Self {
        EmptyBricks {
            empty: bricks
                .min_max
                .iter()
                .map(|&(lo, hi)| is_empty(lo, hi))
                .collect(),
            counts: bricks.counts,
            grid: Locator::new(dims),
            any: true,
        }
    }

    /// No brick is skipped.
    #[must_use]
    pub fn none(bricks: &Bricks, dims: [u32; 3]) -> Self {
        EmptyBricks {
            any: false,
            ..Self::new(bricks, dims, |_, _| false)
        }
    }

    /// The brick holding the trilinear cell of `q` (clamped as the cell is), as its index and
    /// its brick coordinates.
    #[inline(always)]
    fn brick_of(&self, q: Vec3) -> (usize, [u32; 3]) {
        let c = self.grid.corner(q);
        let b: [u32; 3] = std::array::from_fn(|a| (c[a] / BRICK).min(self.counts[a] - 1));
        (
            ((b[2] * self.counts[1] + b[1]) * self.counts[0] + b[0]) as usize,
            b,
        )
    }

    /// The brick next to `b` across its face on `axis`, the side `walk` leaves by: its
    /// index and coordinates, the index `usize::MAX` when it lies outside the grid or `axis`
    /// is none (3). Without branches: the steps per axis are the walk's.
    #[inline(always)]
    fn neighbour(&self, b: [u32; 3], axis: usize, walk: &BrickWalk) -> (usize, [u32; 3]) {
        let d = walk.brick_step[axis & 3];
        let n = [
            b[0].wrapping_add(d[0]),
            b[1].wrapping_add(d[1]),
            b[2].wrapping_add(d[2]),
        ];
        let [c0, c1, c2] = self.counts;
        let inside = (n[0] < c0) & (n[1] < c1) & (n[2] < c2) & (axis < 3);
        // Wrapping: a brick outside the grid gets `usize::MAX` whatever this gives.
        let index = (n[2].wrapping_mul(c1).wrapping_add(n[1]))
            .wrapping_mul(c0)
            .wrapping_add(n[0]);
        (if inside { index as usize } else { usize::MAX }, n)
    }

    /// At sample `k` (voxel-space `q`) of `walk`'s ray: skip the brick or sample it.
    #[cfg(test)]
    fn step(&self, walk: &BrickWalk, q: Vec3, k: u32) -> BrickStep {
        let (i, b) = self.brick_of(q);
        let past = walk.first_sample_past(b, k);
        if self.empty[i] {
            BrickStep::Skip { next: past }
        } else {
            BrickStep::Sample { until: past }
        }
    }

    /// The sample to go on at when sample `k` (voxel-space `q`) lies in an empty brick;
    /// `None` when its brick is not empty (no exit is computed then).
    #[inline(always)]
    pub fn skip(&self, walk: &BrickWalk, q: Vec3, k: u32) -> Option<u32> {
        let (i, b) = self.brick_of(q);
        self.empty[i].then(|| walk.first_sample_past(b, k))
    }
}

/// A ray's samples as the brick tests need them: the reciprocal direction and step, so an
/// exit costs multiplications only, and per axis which face of a brick the ray leaves by, so
/// the three axes' exits are computed in lanes.
#[derive(Clone, Copy, Debug)]
pub(crate) struct BrickWalk {
    origin: Vec4,
    inv_dir: Vec4,
    /// Per axis, the exit face's offset from a brick's lowest corner: a brick's side where the
    /// ray runs towards +, else 0.
    exit_face: Vec4,
    /// The axes whose reciprocal direction is finite (the others never leave a brick); the
    /// fourth lane is off.
    crosses: BVec4A,
    t0: f32,
    inv_step: f32,
    jitter: f32,
    /// Per exit axis (and a fourth, none) the step to the next brick's coordinates (±1 as
    /// wrapping `u32`).
    brick_step: [[u32; 3]; 4],
}

impl BrickWalk {
    #[inline]
    pub fn new(samples: &RaySamples) -> Self {
        let inv_dir = samples.ray.dir.recip();
        BrickWalk {
            origin: samples.ray.origin.extend(0.0),
            inv_dir: inv_dir.extend(0.0),
            exit_face: Vec4::select(
                inv_dir.extend(0.0).cmpgt(Vec4::ZERO),
                Vec4::splat(BRICK as f32),
                Vec4::ZERO,
            ),
            crosses: BVec4A::new(
                inv_dir.x.is_finite(),
                inv_dir.y.is_finite(),
                inv_dir.z.is_finite(),
                false,
            ),
            t0: samples.t0,
            inv_step: samples.inv_step,
            jitter: samples.jitter,
            brick_step: std::array::from_fn(|axis| {
                std::array::from_fn(|c| match (axis == c, inv_dir[c] > 0.0) {
                    (false, _) => 0,
                    (true, true) => 1,
                    (true, false) => u32::MAX,
                })
            }),
        }
    }

    /// The first sample after `k` past brick `b`'s box (aimed 1/1000 of a step short).
    #[inline(always)]
    fn first_sample_past(&self, b: [u32; 3], k: u32) -> u32 {
        self.exit(b, k).0
    }

    /// [`Self::first_sample_past`], and the axis of the face the ray leaves brick `b` by
    /// (the lowest of several at an edge or corner; 3 when no axis crosses).
    #[inline(always)]
    fn exit(&self, b: [u32; 3], k: u32) -> (u32, usize) {
        let lo = Vec4::new(b[0] as f32, b[1] as f32, b[2] as f32, 0.0) * BRICK as f32;
        // Per axis the exit face's parameter; the nearest of the crossing axes (no lane is
        // NaN there: finite origins, faces and reciprocals).
        let t = Vec4::select(
            self.crosses,
            (lo + self.exit_face - self.origin) * self.inv_dir,
            Vec4::INFINITY,
        );
        let t_exit = t.min_element();
        let past = ((t_exit - self.t0) * self.inv_step - self.jitter - 1e-3).floor() + 1.0;
        let axis = (t.cmpeq(Vec4::splat(t_exit)) & self.crosses).bitmask();
        (
            (past.max(0.0) as u32).max(k + 1),
            (axis | 8).trailing_zeros() as usize,
        )
    }
}

/// Where a ray's walk is among the bricks: the brick tests of one ray's composite loop, each
/// brick looked up once, at the first of its samples.
pub(crate) struct BrickCursor<'a> {
    empty: &'a EmptyBricks,
    walk: BrickWalk,
    /// The first sample not known to lie in a non-empty brick.
    until: u32,
    /// The brick across the exit face of the last one found (its index, `usize::MAX` when
    /// there is none, and its coordinates): where the next sample asked about lies but for
    /// an edge, a corner or a brick thinner than a step.
    next: (usize, [u32; 3]),
}

impl<'a> BrickCursor<'a> {
    /// The cursor for `samples`, crossing the bricks `empty` marks.
    #[inline(always)]
    pub fn new(samples: &RaySamples, empty: &'a EmptyBricks) -> Self {
        BrickCursor {
            empty,
            walk: BrickWalk::new(samples),
            until: if empty.any { 0 } else { u32::MAX },
            next: (usize::MAX, [0; 3]),
        }
    }

    /// The first sample not known to lie in a non-empty brick: after [`Self::skip`] gave
    /// `None` for sample `k`, samples `k` up to this one are all to be taken.
    #[inline(always)]
    pub fn until(&self) -> u32 {
        self.until
    }

    /// The sample to go on at when sample `k` (voxel-space `q`) lies in an empty brick;
    /// `None` when it is to be taken.
    #[inline(always)]
    pub fn skip(&mut self, q: Vec3, k: u32) -> Option<u32> {
        if k < self.until {
            return None;
        }
        // The exit is computed from the brick foreseen, so one brick's exit does not wait on
        // the sample's position and its brick (a long chain of dependent steps); the brick
        // of the sample is checked against it beside that, and when they differ (rarely)
        // the exit is computed again from the sample's own brick: the same results as
        // looking every brick up from its sample.
        let (i, b) = self.next;
        if self.empty.brick_of(q).0 != i {
            return self.enter_located(q, k);
        }
        self.enter(i, b, k)
    }

    /// [`Self::skip`] from sample `k`'s own brick (`q` its position): the first sample of a
    /// ray and a sample not in the brick foreseen.
    #[cold]
    #[inline(never)]
    fn enter_located(&mut self, q: Vec3, k: u32) -> Option<u32> {
        let (i, b) = self.empty.brick_of(q);
        self.enter(i, b, k)
    }

    /// Sample `k` lies in brick `b` (index `i`): skip past it or take its samples, and
    /// foresee the next brick.
    #[inline(always)]
    fn enter(&mut self, i: usize, b: [u32; 3], k: u32) -> Option<u32> {
        let (past, axis) = self.walk.exit(b, k);
        self.next = self.empty.neighbour(b, axis, &self.walk);
        if self.empty.empty[i] {
            Some(past)
        } else {
            self.until = past;
            None
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::volume::rays::{clip_to_box, VoxelRay};

    /// The cursor, which computes each exit from the brick it foresees, asks for the same
    /// samples as looking every brick up from its sample ([`EmptyBricks::step`]).
    #[test]
    fn the_cursor_follows_the_bricks_looked_up_from_each_sample() {
        let mut r = crate::xorshift(0x1234_5678);
        let dims = [50u32, 41, 33];
        let levels: Vec<u16> = (0..dims.iter().product::<u32>())
            .map(|_| r() as u16)
            .collect();
        let bricks = Bricks::new(&levels, dims);
        // About half the bricks empty, at random.
        let empty = EmptyBricks::new(&bricks, dims, |lo, _| (lo as u32).is_multiple_of(2));
        let (lo, hi) = (Vec3::ZERO, Vec3::new(49.0, 40.0, 32.0));
        // Brick lookups the cursor foresaw, and those it had to look up again.
        let (mut foreseen, mut again) = (0, 0);
        for n in 0..2000 {
            let f = |v: u32| (v % 10_000) as f32 / 10_000.0;
            let o = Vec3::new(f(r()), f(r()), f(r())) * 120.0 - 35.0;
            let target = Vec3::new(f(r()), f(r()), f(r())) * hi;
            // Every fifth ray along an axis or a diagonal (exits at edges and corners).
            let dir = match n % 5 {
                0 => Vec3::new(1.0, 1.0, 1.0) * if o.x > 25.0 { -1.0 } else { 1.0 },
                1 => Vec3::new(0.0, 1.0, 0.0),
                _ => target - o,
            }
            .normalize();
            let ray = VoxelRay { origin: o, dir };
            let Some(span) = clip_to_box(&ray, f32::INFINITY, lo, hi) else {
                continue;
            };
            let step = [0.5, 0.25, 3.7, 8.0][n % 4];
            let samples = RaySamples::by_reciprocal(ray, span, step, f(r()));
            let walk = BrickWalk::new(&samples);
            let mut cursor = BrickCursor::new(&samples, &empty);
            let (mut k, mut until) = (0, 0);
            while k < samples.count {
                let q = samples.at(k);
                let expected = if k < until {
                    None
                } else {
                    match empty.step(&walk, q, k) {
                        BrickStep::Skip { next } => Some(next),
                        BrickStep::Sample { until: u } => {
                            until = u;
                            None
                        }
                    }
                };
                let before = cursor.next.0;
                assert_eq!(
                    cursor.skip(q, k),
                    expected,
                    "ray {ray:?} step {step} sample {k}"
                );
                assert_eq!(cursor.until(), until, "ray {ray:?} step {step} sample {k}");
                if k >= until && before != usize::MAX {
                    if before == empty.brick_of(q).0 {
                        foreseen += 1;
                    } else {
                        again += 1;
                    }
                }
                k = expected.unwrap_or(k + 1);
            }
        }
        // Both ways through the cursor were taken.
        assert!(foreseen > 2 * again && again > 100, "{foreseen} {again}");
    }
}
