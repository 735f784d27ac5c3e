//! Reading a distance field stored as a [`Volume`]: the trilinear distance at a voxel-space
//! point, its gradient inside the cell (for per-sample work) and by central differences (for
//! shading), and the world-space conversions both need.
//!
//! Rules:
//! - The field is the volume's plain 16-bit copy read trilinearly (`cell`), the marcher's
//!   read: a field's range over 65,535 levels is far below a voxel (spot at 128: 3·10⁻⁵ of a
//!   voxel).
//! - Gradients are taken in voxel space and carried to world space by the transpose of
//!   `voxel_from_world`'s linear part (the chain rule), so anisotropic and rotated grids
//!   shade right.

use glam::{Mat3, Mat4, Vec3, Vec4};

use super::super::cell::{voxel_count, XPairs};
use super::super::grid::Volume;

/// The most voxels along an axis a field's reads take: `cell` truncates voxel coordinates,
/// exact floats up to 2^24, to `i32`.
pub(crate) const MAX_AXIS: u32 = 1 << 24;

/// Refuses a field with an axis over [`MAX_AXIS`] voxels, which [`FieldReader`] would read as
/// empty (a frame with nothing drawn).
///
/// # Errors
/// [`crate::Error::Parameter`] naming the axis.
pub(crate) fn check_axes(vol: &Volume) -> crate::Result<()> {
    match vol
        .dims()
        .iter()
        .zip(["x", "y", "z"])
        .find(|(&d, _)| d > MAX_AXIS)
    {
        Some((d, axis)) => Err(crate::Error::parameter(format!(
            "distance field: {d} voxels along {axis}, over the {MAX_AXIS} a field's reads take"
        ))),
        None => Ok(()),
    }
}

/// A distance field's reads, with the transforms of its grid.
#[derive(Clone, Copy, Debug)]
pub(crate) struct FieldReader<'a> {
    vol: &'a Volume,
    /// The field's 16-bit levels (x fastest); empty when short of the grid (reads give 0).
    levels: &'a [u16],
    /// Voxels per row and per slice.
    nx: usize,
    nxy: usize,
    /// The highest voxel coordinate along each axis (`dims − 1`).
    top: Vec3,
    /// The highest cell corner along each axis (`dims − 2`, 0 on a one-voxel axis).
    last_cell: [u32; 3],
    /// Index steps to the next voxel along x, y and z (0 on a one-voxel axis).
    strides: [usize; 3],
    pub voxel_from_world: Mat4,
    /// Voxel-space gradient → world-space gradient.
    pub grad_to_world: Mat3,
    /// The box's far corner in voxel space (`dims − 1`).
    pub hi: Vec3,
    /// The smallest voxel side, world units.
    pub voxel: f32,
}

impl<'a> FieldReader<'a> {
    pub fn new(vol: &'a Volume) -> Self {
        let voxel_from_world = vol.world_from_voxel().inverse();
        let dims = vol.dims();
        let [nx, ny, nz] = dims;
        // (An axis of more than MAX_AXIS voxels is read as short of data; the renders refuse
        // such a field first, `check_axes`.)
        let whole = nx > 0
            && ny > 0
            && nz > 0
            && dims.iter().all(|&d| d <= MAX_AXIS)
            && vol.quantized().len() >= voxel_count(dims);
        FieldReader {
            vol,
            levels: if whole { vol.quantized() } else { &[] },
            nx: nx as usize,
            nxy: nx as usize * ny as usize,
            top: Vec3::from_array(dims.map(|d| d.saturating_sub(1) as f32)),
            last_cell: dims.map(|d| d.saturating_sub(2)),
            strides: [
                usize::from(nx > 1),
                if ny > 1 { nx as usize } else { 0 },
                if nz > 1 { nx as usize * ny as usize } else { 0 },
            ],
            voxel_from_world,
            grad_to_world: Mat3::from_mat4(voxel_from_world).transpose(),
            hi: Vec3::from_array(vol.dims().map(|d| (d - 1) as f32)),
            voxel: vol.spacing().min_element(),
        }
    }

    /// The cell of voxel-space `q` (clamped to the box): its eight levels in
    /// [`super::super::cell::blend_cell`]'s order and `q`'s place inside it; `None` when
    /// the data is short of the grid. The same cell, corners and fractions as
    /// [`super::super::cell::Cell::locate`] (so the same bits as `Volume::value_at`), with
    /// the grid's checks and strides made once in [`FieldReader::new`].
    #[inline(always)]
    fn cell(&self, q: Vec3) -> Option<FieldCell> {
        if self.levels.is_empty() {
            return None;
        }
        // `max` before `min`: a NaN coordinate becomes 0, so every value is in [0, top].
        let x = q.x.max(0.0).min(self.top.x);
        let y = q.y.max(0.0).min(self.top.y);
        let z = q.z.max(0.0).min(self.top.z);
        let [lx, ly, lz] = self.last_cell;
        // SAFETY: finite and in [0, top] (above), `top` at most 2^24 (checked in `new`), which
        // `i32` holds: the truncation needs none of `as`'s saturation, and the signed one is
        // a single instruction in lanes (the same value as the unsigned).
        let whole = |v: f32| unsafe { v.to_int_unchecked::<i32>() } as u32;
        let (ix, iy, iz) = (whole(x).min(lx), whole(y).min(ly), whole(z).min(lz));
        let i = iz as usize * self.nxy + iy as usize * self.nx + ix as usize;
        let f = Vec3::new(x - ix as f32, y - iy as f32, z - iz as f32);
        let (lo, hi) = self.corners(i);
        Some(FieldCell {
            pairs: XPairs::from_ends(lo, hi),
            f,
        })
    }

    /// The eight levels of the cell whose first corner is level `i` (at most `dims − 2`
    /// along an axis of stride > 0), as [`FieldCell`]'s `lo` and `hi`: in lanes where x's
    /// stride is 1, else one by one.
    #[inline(always)]
    fn corners(&self, i: usize) -> (Vec4, Vec4) {
        #[cfg(target_arch = "x86_64")]
        if self.strides[0] == 1 {
            let [_, sy, sz] = self.strides;
            // SAFETY: as `corners_scalar`'s; with x's stride 1 each pair is two neighbours.
            return unsafe { pairs_sse2(self.levels, i, sy, sz) };
        }
        self.corners_scalar(i)
    }

    /// [`Self::corners`] one level at a time.
    #[inline(always)]
    fn corners_scalar(&self, i: usize) -> (Vec4, Vec4) {
        let [sx, sy, sz] = self.strides;
        let data = self.levels;
        // SAFETY: the cell's corner is at most `dims − 2` along an axis of stride > 0 (else 0),
        // so the largest index, i + sx + sy + sz, is a voxel of the grid, which `levels`
        // holds (checked in `new`).
        let g = |k: usize| f32::from(unsafe { *data.get_unchecked(k) });
        (
            Vec4::new(g(i), g(i + sy), g(i + sz), g(i + sy + sz)),
            Vec4::new(
                g(i + sx),
                g(i + sx + sy),
                g(i + sx + sz),
                g(i + sx + sy + sz),
            ),
        )
    }

    /// The trilinear distance at voxel-space `q` (clamped to the box), world units.
    #[inline(always)]
    pub fn distance(&self, q: Vec3) -> f32 {
        self.vol
            .value_of(self.cell(q).map_or(0.0, |c| c.blend().level))
    }

    /// The trilinear distance at `q` and its gradient inside `q`'s cell, world space (one
    /// cell read).
    #[inline(always)]
    pub fn distance_and_gradient(&self, q: Vec3) -> (f32, Vec3) {
        let (d, g) = self.distance_and_lazy_gradient(q);
        (d, g.gradient())
    }

    /// [`Self::distance_and_gradient`] with the gradient left for later: read it from the
    /// returned value only where it is needed (the same bits).
    #[inline(always)]
    pub fn distance_and_lazy_gradient(&self, q: Vec3) -> (f32, LazyGradient<'_>) {
        match self.cell(q) {
            None => (
                0.0,
                LazyGradient {
                    reader: self,
                    blend: None,
                },
            ),
            Some(c) => {
                let b = c.blend();
                (
                    self.vol.value_of(b.level),
                    LazyGradient {
                        reader: self,
                        blend: Some(b),
                    },
                )
            }
        }
    }

    /// The world-space gradient of `e` (a function of voxel-space points) at `q` by central
    /// differences half a voxel either side: the shading normal (outward, any length).
    #[inline]
    pub fn central_gradient(&self, q: Vec3, e: impl Fn(Vec3) -> f32) -> Vec3 {
        let h = 0.5;
        let g = Vec3::new(
            e(q + Vec3::X * h) - e(q - Vec3::X * h),
            e(q + Vec3::Y * h) - e(q - Vec3::Y * h),
            e(q + Vec3::Z * h) - e(q - Vec3::Z * h),
        ) / (2.0 * h);
        self.grad_to_world * g
    }
}

/// A cell's eight levels as x-pairs (blended in lanes, [`XPairs`]) and a point's place
/// inside it.
#[derive(Clone, Copy, Debug)]
struct FieldCell {
    pairs: XPairs,
    f: Vec3,
}

/// The eight levels of the cell whose first corner is level `i` (`sy`, `sz` the strides;
/// x's is 1), as [`FieldCell`]'s `lo` and `hi`: four 32-bit loads, each two neighbours
/// along x, split and converted in lanes (exact: levels are below 2^24).
///
/// # Safety
/// `i + 1 + sy + sz` must index `levels`.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn pairs_sse2(levels: &[u16], i: usize, sy: usize, sz: usize) -> (Vec4, Vec4) {
    use std::arch::x86_64::{
        _mm_and_si128, _mm_cvtepi32_ps, _mm_set1_epi32, _mm_set_epi32, _mm_srli_epi32,
    };
    let base = levels.as_ptr();
    // SAFETY: the caller's bound covers the last pair; unaligned loads of two levels.
    let pair = |k: usize| unsafe { base.add(k).cast::<u32>().read_unaligned() } as i32;
    let v = _mm_set_epi32(pair(i + sy + sz), pair(i + sz), pair(i + sy), pair(i));
    let lo = _mm_cvtepi32_ps(_mm_and_si128(v, _mm_set1_epi32(0xffff)));
    let hi = _mm_cvtepi32_ps(_mm_srli_epi32::<16>(v));
    (Vec4::from(lo), Vec4::from(hi))
}

/// A cell's trilinear blend, x then y then z, with what its gradient reuses.
#[derive(Clone, Copy, Debug)]
struct Blend {
    cell: FieldCell,
    /// The blends along x: x00, x10, x01, x11.
    x: Vec4,
    y0: f32,
    y1: f32,
    level: f32,
}

impl FieldCell {
    #[inline(always)]
    fn blend(self) -> Blend {
        let (x, (y0, y1), level) = self.pairs.blend_steps(self.f);
        Blend {
            cell: self,
            x,
            y0,
            y1,
            level,
        }
    }
}

/// The gradient of a field read, computed when asked ([`FieldReader::distance_and_lazy_gradient`]).
#[derive(Clone, Copy, Debug)]
pub(crate) struct LazyGradient<'r> {
    reader: &'r FieldReader<'r>,
    blend: Option<Blend>,
}

impl<'r> LazyGradient<'r> {
    /// No gradient (zero when asked).
    #[inline(always)]
    pub fn zero(reader: &'r FieldReader<'r>) -> Self {
        LazyGradient {
            reader,
            blend: None,
        }
    }

    /// The gradient inside the cell, world space (zero where the read had no cell).
    #[inline(always)]
    pub fn gradient(&self) -> Vec3 {
        let Some(b) = self.blend else {
            return Vec3::ZERO;
        };
        let (d, x) = (b.cell.pairs.dx(), b.x);
        let f = b.cell.f;
        let (gy, gz) = (1.0 - f.y, 1.0 - f.z);
        let dx = gz * (gy * d.x + f.y * d.y) + f.z * (gy * d.z + f.y * d.w);
        let dy = gz * (x.y - x.x) + f.z * (x.w - x.z);
        let dz = b.y1 - b.y0;
        let g = Vec3::new(dx, dy, dz) * self.reader.vol.value_step();
        self.reader.grad_to_world * g
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cell_corners_in_lanes_equal_the_scalar_ones() {
        let dims = [7u32, 5, 4];
        let n = (dims[0] * dims[1] * dims[2]) as usize;
        // Scattered levels over the whole 16-bit range.
        let values: Vec<f32> = (0..n)
            .map(|k| ((k as u32).wrapping_mul(2_654_435_761) >> 16) as f32)
            .collect();
        let vol = Volume::from_scalars(dims, Mat4::IDENTITY, values).expect("volume");
        let r = FieldReader::new(&vol);
        assert_eq!(r.strides[0], 1);
        for z in 0..dims[2] - 1 {
            for y in 0..dims[1] - 1 {
                for x in 0..dims[0] - 1 {
                    let i = (z * dims[0] * dims[1] + y * dims[0] + x) as usize;
                    let (a, b) = (r.corners(i), r.corners_scalar(i));
                    assert_eq!(a.0.to_array(), b.0.to_array(), "cell {x} {y} {z}");
                    assert_eq!(a.1.to_array(), b.1.to_array(), "cell {x} {y} {z}");
                }
            }
        }
    }
}
