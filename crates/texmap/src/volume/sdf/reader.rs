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

use glam::{Mat3, Mat4, Vec3};

use super::super::cell::corners_at;
use super::super::grid::Volume;

/// A distance field's reads, with the transforms of its grid.
#[derive(Clone, Copy, Debug)]
pub(crate) struct FieldReader<'a> {
    vol: &'a Volume,
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
        FieldReader {
            vol,
            voxel_from_world,
            grad_to_world: Mat3::from_mat4(voxel_from_world).transpose(),
            hi: Vec3::from_array(vol.dims().map(|d| (d - 1) as f32)),
            voxel: vol.spacing().min_element(),
        }
    }

    /// The trilinear distance at voxel-space `q` (clamped to the box), world units.
    #[inline(always)]
    pub fn distance(&self, q: Vec3) -> f32 {
        self.vol.value_at(q)
    }

    /// The trilinear distance at `q` and its gradient inside `q`'s cell, world space (one
    /// cell read).
    #[inline(always)]
    pub fn distance_and_gradient(&self, q: Vec3) -> (f32, Vec3) {
        let v = self.vol;
        let Some(c) = corners_at(v.quantized(), v.dims(), q, f32::from) else {
            return (0.0, Vec3::ZERO);
        };
        let [c0, c1, c2, c3, c4, c5, c6, c7] = c.values;
        let f = c.frac;
        let (gy, gz) = (1.0 - f.y, 1.0 - f.z);
        let x00 = c0 + (c1 - c0) * f.x;
        let x10 = c2 + (c3 - c2) * f.x;
        let x01 = c4 + (c5 - c4) * f.x;
        let x11 = c6 + (c7 - c6) * f.x;
        let y0 = x00 + (x10 - x00) * f.y;
        let y1 = x01 + (x11 - x01) * f.y;
        let level = y0 + (y1 - y0) * f.z;
        let dx = gz * (gy * (c1 - c0) + f.y * (c3 - c2)) + f.z * (gy * (c5 - c4) + f.y * (c7 - c6));
        let dy = gz * (x10 - x00) + f.z * (x11 - x01);
        let dz = y1 - y0;
        let g = Vec3::new(dx, dy, dz) * v.value_step();
        (v.value_of(level), self.grad_to_world * g)
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
