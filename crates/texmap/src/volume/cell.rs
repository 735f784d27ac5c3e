//! Trilinear reads of a voxel grid (values x fastest, voxels at the integer points): the cell
//! a point falls in, its eight corners and their blend.
//!
//! Rules:
//! - Points are clamped to the box `[0, n − 1]`. On a one-voxel axis the stride is 0, so every
//!   corner read stays inside the grid and the blend along that axis changes nothing.
//! - Corners are read without bounds checks: [`Cell::locate`] checks that the data holds the
//!   whole grid, and the largest index a cell names, `index + sx + sy + sz`, is then one of its
//!   voxels. Checked reads cost eight compares and branches per sample in the marcher's inner
//!   loop.
//! - One blend order for every caller (x, then y, then z): the marcher's cached cells, the
//!   plain reads and the normals give the same bits at the same point.
//! - The marcher's loop does the same arithmetic in lanes ([`Locator`] for the cell and its
//!   fraction, [`XPairs`] for the blend; SSE4.1, this crate's x86-64 build, else the plain
//!   code): per lane the same operations in the same order, so the same bits (tested).

use glam::{Vec3, Vec4, Vec4Swizzles};

/// The trilinear cell of a voxel-space point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Cell {
    /// Index of the lowest corner, x fastest.
    pub index: usize,
    /// Index steps to the next voxel along x, y and z (0 on a one-voxel axis).
    pub strides: [usize; 3],
    /// Position inside the cell, each component in `[0, 1]`.
    pub frac: Vec3,
}

impl Cell {
    /// The cell of voxel-space `p` in a `dims` grid, `p` clamped to the box (a NaN
    /// coordinate to 0). `None` when a side is zero or `len`, the data's length, is short of
    /// the grid's voxel count.
    #[inline(always)]
    pub fn locate(dims: [u32; 3], p: Vec3, len: usize) -> Option<Cell> {
        let [nx, ny, nz] = dims;
        if nx == 0 || ny == 0 || nz == 0 || len < voxel_count(dims) {
            return None;
        }
        // `max` then `min`: a clamp that also takes NaN to 0, so every coordinate is a finite
        // value in [0, n − 1] and converts without the saturating cast's checks (a few
        // instructions per axis at every sample of the marcher).
        let x = p.x.max(0.0).min((nx - 1) as f32);
        let y = p.y.max(0.0).min((ny - 1) as f32);
        let z = p.z.max(0.0).min((nz - 1) as f32);
        // SAFETY: x, y, z are finite, at least 0 and below 2³², as `to_int_unchecked` needs.
        let (ix, iy, iz) = unsafe {
            (
                x.to_int_unchecked::<u32>().min(nx.saturating_sub(2)),
                y.to_int_unchecked::<u32>().min(ny.saturating_sub(2)),
                z.to_int_unchecked::<u32>().min(nz.saturating_sub(2)),
            )
        };
        Some(Cell {
            index: (iz as usize * ny as usize + iy as usize) * nx as usize + ix as usize,
            strides: Self::strides(dims),
            frac: Vec3::new(x - ix as f32, y - iy as f32, z - iz as f32),
        })
    }

    /// The index steps to the next voxel along x, y and z in a `dims` grid (0 on a one-voxel
    /// axis), the same for every cell.
    #[inline(always)]
    pub fn strides(dims: [u32; 3]) -> [usize; 3] {
        let [nx, ny, nz] = dims;
        [
            usize::from(nx > 1),
            if ny > 1 { nx as usize } else { 0 },
            if nz > 1 { nx as usize * ny as usize } else { 0 },
        ]
    }

    /// The cell's eight voxels of `data`, each through `convert`, in [`blend_cell`]'s order:
    /// c000, c100, c010, c110, c001, c101, c011, c111.
    ///
    /// # Safety
    /// `data` holds at least the voxel count of the grid the cell was located in (what
    /// [`Cell::locate`] checks when given `data.len()`).
    #[inline(always)]
    pub unsafe fn corners<T: Copy, V>(&self, data: &[T], convert: impl Fn(T) -> V) -> [V; 8] {
        let (i, [sx, sy, sz]) = (self.index, self.strides);
        // SAFETY: `locate` keeps ix ≤ nx − 2 when sx = 1 (else sx = 0), likewise y and z, so
        // the largest index, i + sx + sy + sz, is a voxel of the grid, which `data` holds.
        let g = |k: usize| convert(unsafe { *data.get_unchecked(k) });
        [
            g(i),
            g(i + sx),
            g(i + sy),
            g(i + sx + sy),
            g(i + sz),
            g(i + sx + sz),
            g(i + sy + sz),
            g(i + sx + sy + sz),
        ]
    }
}

/// [`Cell::locate`] for many points of one grid: the grid's bounds and strides computed once,
/// and with SSE4.1 (this crate's x86-64 build) the three axes in lanes — the clamp, the
/// truncation, the last cell's bound and the fraction each one instruction for all three.
/// The same cell and fraction as [`Cell::locate`] (tested).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Locator {
    dims: [u32; 3],
    /// `n − 1` per axis as floats (the box's far corner), the fourth lane 0.
    far: Vec4,
    /// `n − 2` per axis (0 on a one-voxel axis): the last cell's lowest corner.
    last: [u32; 3],
    strides: [usize; 3],
    /// Every side below 2³¹ voxels: a clamped coordinate converts to `i32` in a lane.
    #[cfg_attr(
        not(all(target_arch = "x86_64", target_feature = "sse4.1")),
        allow(dead_code)
    )]
    lanes: bool,
}

impl Locator {
    /// The locator of a `dims` grid, a zero side counted as one voxel (its callers read no
    /// voxel of a grid with a zero side).
    #[must_use]
    pub fn new(dims: [u32; 3]) -> Self {
        let dims = dims.map(|n| n.max(1));
        let [nx, ny, nz] = dims;
        Locator {
            dims,
            far: Vec4::new((nx - 1) as f32, (ny - 1) as f32, (nz - 1) as f32, 0.0),
            last: dims.map(|n| n.saturating_sub(2)),
            strides: Cell::strides(dims),
            lanes: dims.iter().all(|&n| n < 1 << 31),
        }
    }

    /// `p` clamped to the box in lanes and its cell's lowest corner (voxel coordinates), the
    /// fourth lane 0.
    ///
    /// # Safety
    /// SSE4.1 must be enabled (this build's target) and `self.lanes` true. `max` returns its
    /// second operand (0) for a NaN lane, as `f32::max` does, so every lane is in
    /// [0, n − 1] below 2³¹ and converts exactly as `to_int_unchecked::<u32>`; `n − 2 < 2³¹`
    /// too, so the signed minimum is the unsigned one.
    #[cfg(all(target_arch = "x86_64", target_feature = "sse4.1"))]
    #[inline(always)]
    unsafe fn clamp_lanes(
        &self,
        p: Vec3,
    ) -> (std::arch::x86_64::__m128, std::arch::x86_64::__m128i) {
        use std::arch::x86_64::{
            _mm_cvttps_epi32, _mm_max_ps, _mm_min_epi32, _mm_min_ps, _mm_setr_epi32, _mm_setzero_ps,
        };
        let [lx, ly, lz] = self.last;
        let v = _mm_min_ps(
            _mm_max_ps(p.extend(0.0).into(), _mm_setzero_ps()),
            self.far.into(),
        );
        let i = _mm_min_epi32(
            _mm_cvttps_epi32(v),
            _mm_setr_epi32(lx as i32, ly as i32, lz as i32, 0),
        );
        (v, i)
    }

    /// The lowest corner of the cell of voxel-space `p` (voxel coordinates), as
    /// [`Cell::locate`] names it.
    #[inline(always)]
    pub fn corner(&self, p: Vec3) -> [u32; 3] {
        #[cfg(all(target_arch = "x86_64", target_feature = "sse4.1"))]
        if self.lanes {
            // SAFETY: SSE4.1 is enabled for this build and the lanes are in range (`lanes`).
            let i = unsafe {
                std::mem::transmute::<std::arch::x86_64::__m128i, [u32; 4]>(self.clamp_lanes(p).1)
            };
            return [i[0], i[1], i[2]];
        }
        let [nx, ny, nz] = self.dims;
        let axis =
            |v: f32, n: u32| (v.max(0.0).min((n - 1) as f32) as u32).min(n.saturating_sub(2));
        [axis(p.x, nx), axis(p.y, ny), axis(p.z, nz)]
    }

    /// The cell of voxel-space `p`, as [`Cell::locate`] (without its length check).
    #[inline(always)]
    pub fn locate(&self, p: Vec3) -> Cell {
        #[cfg(all(target_arch = "x86_64", target_feature = "sse4.1"))]
        if self.lanes {
            use std::arch::x86_64::{_mm_cvtepi32_ps, _mm_sub_ps};
            // SAFETY: SSE4.1 is enabled for this build and the lanes are in range (`lanes`).
            let (i, frac) = unsafe {
                let (v, i) = self.clamp_lanes(p);
                let frac = Vec4::from(_mm_sub_ps(v, _mm_cvtepi32_ps(i)));
                (
                    std::mem::transmute::<std::arch::x86_64::__m128i, [u32; 4]>(i),
                    frac,
                )
            };
            let [nx, ny, _] = self.dims;
            return Cell {
                index: (i[2] as usize * ny as usize + i[1] as usize) * nx as usize + i[0] as usize,
                strides: self.strides,
                frac: frac.truncate(),
            };
        }
        Cell::locate(self.dims, p, usize::MAX).unwrap_or(Cell {
            index: 0,
            strides: self.strides,
            frac: Vec3::ZERO,
        })
    }
}

/// The number of voxels of a `dims` grid.
#[inline(always)]
pub(crate) fn voxel_count(dims: [u32; 3]) -> usize {
    dims.iter().map(|&d| d as usize).product()
}

/// A value a cell's corners can be blended in (scalars and vectors, each with its own lerp).
pub(crate) trait CellValue: Copy {
    fn mix(self, other: Self, t: f32) -> Self;
}

impl CellValue for f32 {
    #[inline(always)]
    fn mix(self, other: f32, t: f32) -> f32 {
        self + (other - self) * t
    }
}

impl CellValue for Vec3 {
    #[inline(always)]
    fn mix(self, other: Vec3, t: f32) -> Vec3 {
        self.lerp(other, t)
    }
}

/// Vectors in four lanes: the lanes blend as [`Vec3`]'s components do (glam's `lerp` is
/// `a·(1 − t) + b·t` for both), one instruction per operation for all lanes.
impl CellValue for Vec4 {
    #[inline(always)]
    fn mix(self, other: Vec4, t: f32) -> Vec4 {
        self.lerp(other, t)
    }
}

/// Trilinear blend of a cell's corners ([`Cell::corners`]) at fractions `f` (x first, then
/// y, then z).
#[inline(always)]
pub(crate) fn blend_cell<T: CellValue>(c: &[T; 8], f: Vec3) -> T {
    let c00 = c[0].mix(c[1], f.x);
    let c10 = c[2].mix(c[3], f.x);
    let c01 = c[4].mix(c[5], f.x);
    let c11 = c[6].mix(c[7], f.x);
    c00.mix(c10, f.y).mix(c01.mix(c11, f.y), f.z)
}

/// A cell's eight scalar corners kept for blending in lanes: the low ends of its four x-pairs
/// `[c000, c010, c001, c011]` and the steps to their high ends (`c100 − c000`, …), so a blend
/// ([`XPairs::blend`]) is [`blend_cell`]'s arithmetic, the same bits, the x step of all four
/// pairs in one multiply-add and the y step of both halves in another.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct XPairs {
    lo: Vec4,
    dx: Vec4,
}

impl XPairs {
    /// The pairs of corners in [`Cell::corners`]'s order.
    #[inline(always)]
    pub fn new(c: [f32; 8]) -> Self {
        let lo = Vec4::new(c[0], c[2], c[4], c[6]);
        XPairs {
            lo,
            dx: Vec4::new(c[1], c[3], c[5], c[7]) - lo,
        }
    }

    /// The pairs from their low ends (`[c000, c010, c001, c011]`) and high ends along x.
    #[inline(always)]
    pub fn from_ends(lo: Vec4, hi: Vec4) -> Self {
        XPairs { lo, dx: hi - lo }
    }

    /// The four steps along x (`c100 − c000`, …), which an in-cell gradient reuses.
    #[inline(always)]
    pub fn dx(&self) -> Vec4 {
        self.dx
    }

    /// The trilinear blend at fractions `f`: [`blend_cell`] of the same corners.
    #[inline(always)]
    pub fn blend(&self, f: Vec3) -> f32 {
        self.blend_steps(f).2
    }

    /// [`Self::blend`] with its intermediate blends: along x `[c00, c10, c01, c11]`, along y
    /// `(c0, c1)` (z = 0 and 1), and the value.
    #[inline(always)]
    pub fn blend_steps(&self, f: Vec3) -> (Vec4, (f32, f32), f32) {
        // [c00, c10, c01, c11]: `c0 + (c1 − c0)·x` per pair, as `f32::mix`.
        let x = self.lo + self.dx * f.x;
        // [c00, c01] towards [c10, c11] along y, then the two along z.
        let (a, b) = (x.xzxz(), x.ywyw());
        let y = a + (b - a) * f.y;
        (x, (y.x, y.y), y.x + (y.y - y.x) * f.z)
    }
}

/// A cell's eight voxels (in [`blend_cell`]'s order) and the point's position inside it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Corners<V> {
    pub values: [V; 8],
    pub frac: Vec3,
}

/// The corners of the cell of voxel-space `p` (clamped to the box) in `data` (x fastest,
/// `dims`), each voxel read through `convert`; `None` when `data` is short of the grid.
#[inline(always)]
pub(crate) fn corners_at<T: Copy, V>(
    data: &[T],
    dims: [u32; 3],
    p: Vec3,
    convert: impl Fn(T) -> V,
) -> Option<Corners<V>> {
    let cell = Cell::locate(dims, p, data.len())?;
    Some(Corners {
        // SAFETY: `locate` was given `data.len()` and checked it.
        values: unsafe { cell.corners(data, convert) },
        frac: cell.frac,
    })
}

/// Trilinear interpolation of `data` (x fastest, `dims`) at voxel-space `p`, clamped to the
/// box, each voxel read through `convert`; `None` when `data` is short of the grid.
#[inline(always)]
pub(crate) fn interpolate<T: Copy, V: CellValue>(
    data: &[T],
    dims: [u32; 3],
    p: Vec3,
    convert: impl Fn(T) -> V,
) -> Option<V> {
    corners_at(data, dims, p, convert).map(|c| blend_cell(&c.values, c.frac))
}

/// The trilinear 16-bit level (fractional) of `data` (x fastest, `dims`) at voxel-space `p`,
/// clamped to the box; 0 when `data` is short of the grid.
#[inline(always)]
pub(crate) fn trilinear(data: &[u16], dims: [u32; 3], p: Vec3) -> f32 {
    interpolate(data, dims, p, f32::from).unwrap_or(0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_locator_finds_cell_locates_cells() {
        let mut s = 7u32;
        let mut r = move || {
            s = s.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (s >> 8) as f32 / (1u32 << 24) as f32
        };
        for dims in [[9, 5, 3], [1, 4, 6], [2, 1, 1], [1, 1, 1], [300, 2, 70]] {
            let grid = Locator::new(dims);
            let n = Vec3::from_array(dims.map(|d| d as f32));
            let mut points: Vec<Vec3> = (0..2000)
                .map(|_| (Vec3::new(r(), r(), r()) * 1.4 - 0.2) * n)
                .collect();
            // Corners, faces, beyond the box, NaN and infinities.
            points.extend([
                Vec3::ZERO,
                n - 1.0,
                n,
                Vec3::splat(-1.0),
                Vec3::new(f32::NAN, 0.5, f32::INFINITY),
                Vec3::new(f32::NEG_INFINITY, f32::NAN, 1e30),
            ]);
            for p in points {
                let want = Cell::locate(dims, p, usize::MAX).expect("no zero side");
                let got = grid.locate(p);
                assert_eq!(got.index, want.index, "{dims:?} {p}");
                assert_eq!(got.strides, want.strides, "{dims:?} {p}");
                assert_eq!(got.frac, want.frac, "{dims:?} {p}");
                let [x, y, z] = grid.corner(p);
                let [nx, ny, _] = dims.map(|d| d as usize);
                assert_eq!((z as usize * ny + y as usize) * nx + x as usize, want.index);
            }
        }
    }
}
