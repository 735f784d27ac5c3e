//! The unshaded composite loop ([`super::composite::cells`] without shading) with eight
//! samples of a ray in AVX2 lanes: their positions, cells, the four voxel pairs of each cell
//! (one gather each), the trilinear blend and the transfer table's index, then the eight
//! table entries composited in order.
//!
//! Rules:
//! - The same samples, the same operations in the same order per lane (a multiply and an add
//!   are never fused), the same table entries composited one by one with the same early
//!   stop: the colour and the sample count are the bits of the scalar loop (tested). The
//!   scalar loop stays, for CPUs without AVX2 and `TEXMAP_CPU=baseline`.
//! - A batch starts at a sample to be taken and runs on over the next seven, across brick
//!   edges; in the composite each sample asks the empty-brick cursor as the scalar loop does
//!   (a compare inside the brick last found non-empty, [`BrickCursor::until`]), and a skip
//!   out of the batch starts the next one past it. Lanes past the ray's end read clamped
//!   cells and are dropped.
//! - A gather reads a voxel and its neighbour along x as one 32-bit word, so the grid must
//!   be at least two voxels on every axis and its voxel count below 2³¹ (every index a
//!   signed 32-bit lane); [`LaneGrid::new`] says `None` otherwise, and the scalar loop runs.

use glam::Vec4;

use super::bricks::BrickCursor;
use super::cell::voxel_count;
use super::marcher::{Marcher, Traced};
use super::rays::RaySamples;

/// The grid's constants for the lanes, prepared once per frame.
#[derive(Clone, Copy, Debug)]
pub(crate) struct LaneGrid {
    /// `n − 1` per axis, the far corner of the box.
    far: [f32; 3],
    /// `n − 2` per axis, the last cell's lowest corner.
    last: [i32; 3],
    /// Voxels per row and per slice.
    nx: i32,
    ny: i32,
    slice: i32,
}

impl LaneGrid {
    /// The lanes' grid for `m`'s frame, or `None` when the CPU lacks AVX2 (or the build is
    /// not x86-64), `TEXMAP_CPU=baseline` says so, or the grid does not fit the lanes (a side
    /// of one voxel, 2³¹ voxels or more, or data short of the grid).
    pub fn new(m: &Marcher) -> Option<Self> {
        if !cfg!(target_arch = "x86_64") || crate::cpu::level() != crate::cpu::Level::V3 {
            return None;
        }
        let [nx, ny, nz] = m.dims;
        let count = voxel_count(m.dims);
        if nx < 2 || ny < 2 || nz < 2 || count >= 1 << 31 || m.data.len() < count {
            return None;
        }
        Some(LaneGrid {
            far: [(nx - 1) as f32, (ny - 1) as f32, (nz - 1) as f32],
            last: [(nx - 2) as i32, (ny - 2) as i32, (nz - 2) as i32],
            nx: nx as i32,
            ny: ny as i32,
            slice: (nx * ny) as i32,
        })
    }
}

/// The unshaded composite of the samples `s` of one ray, as
/// [`super::composite::cells`]`::<false>` gives it.
pub(crate) fn cells(m: &Marcher, grid: &LaneGrid, s: &RaySamples) -> Traced {
    #[cfg(target_arch = "x86_64")]
    {
        // SAFETY: a `LaneGrid` exists only when the CPU has every feature `cells_v3`
        // enables (`cpu::level` is V3) and the grid fits the lanes (`LaneGrid::new`).
        unsafe { cells_v3(m, grid, s) }
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        let _ = grid;
        super::composite::cells::<false>(m, s, glam::Vec3::ZERO, &[])
    }
}

/// One ray's constants, eight copies each, and its grid's.
#[cfg(target_arch = "x86_64")]
pub(super) struct RayLanes {
    origin: [std::arch::x86_64::__m256; 3],
    dir: [std::arch::x86_64::__m256; 3],
    t0: std::arch::x86_64::__m256,
    step: std::arch::x86_64::__m256,
    jitter: std::arch::x86_64::__m256,
    far: [std::arch::x86_64::__m256; 3],
    last: [std::arch::x86_64::__m256i; 3],
    nx: std::arch::x86_64::__m256i,
    ny: std::arch::x86_64::__m256i,
    /// Index steps to the pairs of the next row, slice, and both.
    pub rows: [std::arch::x86_64::__m256i; 3],
    q_to_index: std::arch::x86_64::__m256,
    top: std::arch::x86_64::__m256i,
    /// The levels, read as 32-bit words at 16-bit offsets.
    base: *const i32,
}

#[cfg(target_arch = "x86_64")]
impl RayLanes {
    /// The lanes of the samples `s` of `m`'s frame on `grid`.
    ///
    /// # Safety
    /// The CPU has AVX2.
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,movbe")]
    pub unsafe fn new(m: &Marcher, grid: &LaneGrid, s: &RaySamples) -> Self {
        use std::arch::x86_64::*;
        let (o, d) = (s.ray.origin, s.ray.dir);
        let (sy, sz) = (grid.nx, grid.slice);
        RayLanes {
            origin: [o.x, o.y, o.z].map(|c| _mm256_set1_ps(c)),
            dir: [d.x, d.y, d.z].map(|c| _mm256_set1_ps(c)),
            t0: _mm256_set1_ps(s.t0),
            step: _mm256_set1_ps(s.step),
            jitter: _mm256_set1_ps(s.jitter),
            far: grid.far.map(|c| _mm256_set1_ps(c)),
            last: grid.last.map(|c| _mm256_set1_epi32(c)),
            nx: _mm256_set1_epi32(grid.nx),
            ny: _mm256_set1_epi32(grid.ny),
            rows: [sy, sz, sy + sz].map(|c| _mm256_set1_epi32(c)),
            q_to_index: _mm256_set1_ps(m.q_to_index()),
            // The table is never empty (`TransferLut` has at least one entry).
            top: _mm256_set1_epi32(m.table_premultiplied().len().saturating_sub(1) as i32),
            base: m.data.as_ptr().cast::<i32>(),
        }
    }

    /// The table entries of samples `k` to `k + 7`, as
    /// [`Marcher::classify_premultiplied`] indexes them. Not inlined: the caller's loop
    /// then keeps its running colour and opacity in registers, and these constants are read
    /// from memory here.
    ///
    /// # Safety
    /// The CPU has AVX2, and `self` was made by [`RayLanes::new`] for a grid from
    /// [`LaneGrid::new`].
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,movbe")]
    #[inline(never)]
    unsafe fn entries(&self, k: u32) -> [u32; 8] {
        use std::arch::x86_64::*;
        let (index, f) = self.locate(k);
        let entry = self.entry(index, f);
        let mut entries = [0u32; 8];
        _mm256_storeu_si256(entries.as_mut_ptr().cast(), entry);
        entries
    }

    /// The cells of samples `k` to `k + 7`: each cell's lowest corner as a voxel index and
    /// the samples' fractions in it, as [`super::cell::Locator::locate`] gives them.
    ///
    /// # Safety
    /// As [`Self::entries`].
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,movbe")]
    #[inline]
    pub unsafe fn locate(
        &self,
        k: u32,
    ) -> (std::arch::x86_64::__m256i, [std::arch::x86_64::__m256; 3]) {
        use std::arch::x86_64::*;
        // Positions: `t0 + (k + jitter)·step`, then `origin + dir·t` per axis.
        let lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
        let kf = _mm256_cvtepi32_ps(_mm256_add_epi32(_mm256_set1_epi32(k as i32), lane));
        let t = _mm256_add_ps(
            self.t0,
            _mm256_mul_ps(_mm256_add_ps(kf, self.jitter), self.step),
        );
        // Clamped to the box (`max` first: a NaN lane becomes 0), the cell's lowest corner
        // and the fraction, as `Locator::locate`.
        let mut i = [_mm256_setzero_si256(); 3];
        let mut f = [_mm256_setzero_ps(); 3];
        for a in 0..3 {
            let p = _mm256_add_ps(self.origin[a], _mm256_mul_ps(self.dir[a], t));
            let v = _mm256_min_ps(_mm256_max_ps(p, _mm256_setzero_ps()), self.far[a]);
            i[a] = _mm256_min_epi32(_mm256_cvttps_epi32(v), self.last[a]);
            f[a] = _mm256_sub_ps(v, _mm256_cvtepi32_ps(i[a]));
        }
        let index = _mm256_add_epi32(
            _mm256_mullo_epi32(
                _mm256_add_epi32(_mm256_mullo_epi32(i[2], self.ny), i[1]),
                self.nx,
            ),
            i[0],
        );
        (index, f)
    }

    /// The transfer table's entries (the index [`Marcher::classify`] takes) of the samples
    /// at fractions `f` of the cells at `index` ([`Self::locate`]).
    ///
    /// # Safety
    /// As [`Self::entries`], `index` and `f` from [`Self::locate`].
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,movbe")]
    #[inline]
    pub unsafe fn entry(
        &self,
        index: std::arch::x86_64::__m256i,
        f: [std::arch::x86_64::__m256; 3],
    ) -> std::arch::x86_64::__m256i {
        use std::arch::x86_64::*;
        // The four pairs along x: [c000 c100], [c010 c110], [c001 c101], [c011 c111].
        // SAFETY: every index is a cell's lowest corner (clamped above), so the pair's far
        // voxel, index + sy + sz + 1, is a voxel of the grid, which the data holds.
        let pair = |at: __m256i| {
            let g = _mm256_i32gather_epi32::<2>(self.base, at);
            let lo = _mm256_cvtepi32_ps(_mm256_and_si256(g, _mm256_set1_epi32(0xffff)));
            let hi = _mm256_cvtepi32_ps(_mm256_srli_epi32::<16>(g));
            // `c0 + (c1 − c0)·x`, as `XPairs::blend`.
            _mm256_add_ps(lo, _mm256_mul_ps(_mm256_sub_ps(hi, lo), f[0]))
        };
        let x00 = pair(index);
        let x10 = pair(_mm256_add_epi32(index, self.rows[0]));
        let x01 = pair(_mm256_add_epi32(index, self.rows[1]));
        let x11 = pair(_mm256_add_epi32(index, self.rows[2]));
        let y0 = _mm256_add_ps(x00, _mm256_mul_ps(_mm256_sub_ps(x10, x00), f[1]));
        let y1 = _mm256_add_ps(x01, _mm256_mul_ps(_mm256_sub_ps(x11, x01), f[1]));
        let level = _mm256_add_ps(y0, _mm256_mul_ps(_mm256_sub_ps(y1, y0), f[2]));
        // The table's index, as `Marcher::classify_premultiplied`: levels are at least 0,
        // so the signed conversion is the unsigned one.
        _mm256_min_epu32(
            _mm256_cvttps_epi32(_mm256_add_ps(
                _mm256_mul_ps(level, self.q_to_index),
                _mm256_set1_ps(0.5),
            )),
            self.top,
        )
    }
}

/// Composites the table's `entries` in order onto the colour `acc` and its opacity `w`
/// (the bits of `acc.w`), stopping once the opacity reaches `stop`: the new colour and
/// opacity, and the position of the entry it stopped at. Not inlined, so the running colour
/// and opacity stay in registers (inlined, the caller's many constants pushed them to the
/// stack: a store and a load in every step of the chain).
///
/// # Safety
/// The CPU has AVX2, and every entry indexes `table`.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,movbe")]
#[inline(never)]
unsafe fn composite(
    table: &[Vec4],
    entries: &[u32],
    mut acc: Vec4,
    mut w: f32,
    stop: f32,
) -> (Vec4, f32, Option<usize>) {
    for (j, &e) in entries.iter().enumerate() {
        // SAFETY: every entry indexes the table (`RayLanes::entries`).
        let c = *table.get_unchecked(e as usize);
        // `acc += c·(1 − acc.w)`, the opacity's chain from sample to sample in a scalar:
        // no shuffle or broadcast on it.
        let x = 1.0 - w;
        acc += c * x;
        w += c.w * x;
        if w >= stop {
            return (acc, w, Some(j));
        }
    }
    (acc, w, None)
}

/// [`cells`] in AVX2 lanes.
///
/// # Safety
/// The CPU has AVX2 and FMA, and `grid` was made by [`LaneGrid::new`] for `m`.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,movbe")]
unsafe fn cells_v3(m: &Marcher, grid: &LaneGrid, s: &RaySamples) -> Traced {
    let table = m.table_premultiplied();
    let stop = m.p.early_termination;
    let lanes = RayLanes::new(m, grid, s);
    let (color, _, samples) = march(
        m,
        s,
        // SAFETY: as this function's (the lanes were made for `grid`).
        |k| unsafe { lanes.entries(k) },
        // SAFETY: every entry indexes the table (`RayLanes::entries`).
        |entries, run, acc, w| unsafe { composite(table, &entries[run], acc, w, stop) },
    );
    Traced { color, samples }
}

/// The brick walk the lanes' loops share: the samples of `s` in batches of eight made by
/// `batch(k)` (samples `k` to `k + 7`), each batch's samples composited in order by
/// `composite(batch, lanes, colour, opacity)` in runs the empty-brick cursor has found
/// non-empty, asking it at each run's end as the scalar loop does at every sample; a skip out
/// of the batch starts the next one past it. `composite` gives the new colour and opacity,
/// and where the opacity reached the ray's stop, the sample it stopped at (counted from the
/// run's first). Gives the colour, the opacity and the samples taken.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
pub(super) fn march<B>(
    m: &Marcher,
    s: &RaySamples,
    batch: impl Fn(u32) -> B,
    composite: impl Fn(&B, std::ops::Range<usize>, Vec4, f32) -> (Vec4, f32, Option<usize>),
) -> (Vec4, f32, u64) {
    let (mut acc, mut w) = (Vec4::ZERO, 0.0f32);
    let mut taken = 0u64;
    let mut bricks = BrickCursor::new(s, &m.empty);
    let mut k = 0u32;
    'ray: while k < s.count {
        if let Some(next) = bricks.skip(s.at(k), k) {
            k = next;
            continue;
        }
        let lanes = batch(k);
        let n = (s.count - k).min(8);
        let mut j = 0;
        while j < n {
            let kj = k + j;
            if kj >= bricks.until() {
                if let Some(next) = bricks.skip(s.at(kj), kj) {
                    if next >= k + n {
                        k = next;
                        continue 'ray;
                    }
                    j = next - k;
                    continue;
                }
            }
            let end = n.min(bricks.until() - k);
            let (color, opacity, stopped) = composite(&lanes, j as usize..end as usize, acc, w);
            (acc, w) = (color, opacity);
            if let Some(at) = stopped {
                taken += at as u64 + 1;
                break 'ray;
            }
            taken += u64::from(end - j);
            j = end;
        }
        k += n;
    }
    (acc, w, taken)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::volume::params::MarchParams;
    use crate::volume::rays::{clip_to_box, VoxelRay};
    use crate::volume::{TransferFunction, Volume};
    use glam::Vec3;

    #[test]
    fn lanes_give_the_bits_and_samples_of_the_scalar_loop() {
        if !crate::cpu::available(crate::cpu::Level::V3) {
            eprintln!("skipped: this CPU has no AVX2 (the lanes never run here)");
            return;
        }
        let mut r = crate::xorshift(0x9e37_79b9);
        // Smooth blobs with noise, some empty corners: both skipped and taken bricks.
        let dims = [37u32, 29, 23];
        let values: Vec<f32> = (0..voxel_count(dims))
            .map(|i| {
                let (x, y, z) = (
                    (i % 37) as f32,
                    ((i / 37) % 29) as f32,
                    (i / (37 * 29)) as f32,
                );
                let blob =
                    (-((x - 20.0).powi(2) + (y - 12.0).powi(2) + (z - 11.0).powi(2)) / 60.0).exp();
                240.0 * blob + (r() % 16) as f32
            })
            .collect();
        let vol = Volume::from_scalars(dims, glam::Mat4::IDENTITY, values).unwrap();
        let tf = TransferFunction::preset("synth").unwrap();
        for (step, stop) in [(0.5, 0.99), (0.37, 0.95), (1.3, 1.0)] {
            let params = MarchParams {
                step,
                early_termination: stop,
                ..MarchParams::default()
            };
            let m = Marcher::new(&vol, &tf, &params, None).unwrap();
            let Some(grid) = LaneGrid::new(&m) else {
                eprintln!("skipped: TEXMAP_CPU=baseline (the lanes never run)");
                return;
            };
            for _ in 0..400 {
                let f = |v: u32| (v % 10_000) as f32 / 10_000.0;
                let o = Vec3::new(f(r()), f(r()), f(r())) * 80.0 - 20.0;
                let target = Vec3::new(f(r()) * 36.0, f(r()) * 28.0, f(r()) * 22.0);
                let ray = VoxelRay {
                    origin: o,
                    dir: (target - o).normalize(),
                };
                let Some(span) = clip_to_box(&ray, f32::INFINITY, m.lo, m.hi) else {
                    continue;
                };
                let jitter = f(r());
                let samples = RaySamples::by_reciprocal(ray, span, step, jitter);
                let lanes = cells(&m, &grid, &samples);
                let scalar = crate::volume::composite::cells::<false>(&m, &samples, o, &[]);
                assert_eq!(lanes.samples, scalar.samples, "{ray:?}");
                assert_eq!(
                    lanes.color.to_array().map(f32::to_bits),
                    scalar.color.to_array().map(f32::to_bits),
                    "{ray:?}"
                );
            }
        }
    }
}
