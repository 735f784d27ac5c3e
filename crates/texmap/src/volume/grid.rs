//! [`Volume`]: a scalar field on a grid, its values kept as 16-bit levels over the value range
//! in two copies, its placement in the world, and the tables built from it on first use.
//!
//! Rules:
//! - Values are stored as 16-bit levels over `[min, max]` (`value = min + level·step`): exact
//!   for 8-bit data and for integers spanning at most 65,535; otherwise 1/65,535 of the range,
//!   finer than the 4,096-entry transfer tables.
//! - Two copies of the levels: an `R16` [`Texture3D`] (what the texture engine and the slice
//!   method read) and a plain `u16` array (what the marcher reads, see `cell`). The engine's
//!   `sample_3d` dispatches on the texel format and the wrap mode and computes a level of
//!   detail per read, several times the cost of the plain read (`examples/volume_sampling.rs`
//!   times both), which the marcher cannot afford per sample; a test holds the two reads
//!   equal.
//! - The brick min/max table and the per-voxel normals are built on first use and kept; a new
//!   placement drops the normals (they are world-space) but not the bricks (they are levels).

use glam::{Mat4, Vec3, Vec4};

use super::bricks::Bricks;
use super::cell::trilinear;
use super::framing::vtk_camera_for_bounds;
use super::normals::voxel_normals;
use super::patient::PatientAxes;
use super::scalar_type::ScalarType;
use crate::texture::{ColorSpace, Format, Texture3D};
use crate::{Error, Result};

/// A scalar volume: a 3D texture of values, its grid and its placement in the world.
#[derive(Clone, Debug)]
pub struct Volume {
    dims: [u32; 3],
    spacing: Vec3,
    world_from_voxel: Mat4,
    range: (f32, f32),
    /// Value of quantized level q: `range.0 + q·value_step`.
    value_step: f32,
    /// The values as a 3D texture (`R16`, linear: q/65535), read through the texture engine.
    texture: Texture3D,
    /// The same 16-bit levels, x fastest: the marcher's fast path (see `cell`).
    quant: Vec<u16>,
    /// Min/max per brick for empty-space skipping, built on first use.
    bricks: std::sync::OnceLock<Bricks>,
    /// Per-voxel world-space normals for shading, built on first use.
    normals: std::sync::OnceLock<Vec<[i8; 4]>>,
    /// The file's voxel type, when a loader made the volume.
    scalar_type: Option<ScalarType>,
    /// Which way the patient faces, when the file states an anatomical frame.
    patient: Option<PatientAxes>,
}

impl Volume {
    /// A volume from `dims[0]·dims[1]·dims[2]` values, x fastest, placed by
    /// `world_from_voxel` (whose column lengths are the voxel spacing).
    ///
    /// # Errors
    /// [`Error::Parameter`] when a side is zero, the value count differs from the grid, the
    /// transform is singular or not finite, or a value is NaN or infinite.
    pub fn from_scalars(dims: [u32; 3], world_from_voxel: Mat4, scalars: Vec<f32>) -> Result<Self> {
        if dims.contains(&0) {
            return Err(Error::parameter(format!(
                "volume size {dims:?} has a zero side"
            )));
        }
        let count = dims.iter().map(|&d| d as usize).product::<usize>();
        if scalars.len() != count {
            return Err(Error::parameter(format!(
                "volume {dims:?} needs {count} values, got {}",
                scalars.len()
            )));
        }
        if !world_from_voxel.is_finite() || world_from_voxel.determinant().abs() < 1e-12 {
            return Err(Error::parameter(
                "volume transform (world from voxel) is singular or not finite",
            ));
        }
        if let Some(i) = scalars.iter().position(|v| !v.is_finite()) {
            let x = i % dims[0] as usize;
            let y = (i / dims[0] as usize) % dims[1] as usize;
            let z = i / (dims[0] as usize * dims[1] as usize);
            return Err(Error::parameter(format!(
                "volume has a non-finite value ({}) at voxel ({x}, {y}, {z})",
                scalars[i]
            )));
        }
        let (mut lo, mut hi) = (f32::INFINITY, f32::NEG_INFINITY);
        for &v in &scalars {
            lo = lo.min(v);
            hi = hi.max(v);
        }
        // 16-bit levels over [lo, hi]: exact for 8-bit data and for integers spanning at most
        // 65,535; otherwise 1/65,535 of the range (finer than the 4,096-entry tables).
        let value_step = (hi - lo) / 65535.0;
        let inv = if hi > lo {
            65535.0 / (f64::from(hi) - f64::from(lo))
        } else {
            0.0
        };
        let quant: Vec<u16> = scalars
            .iter()
            .map(|&v| {
                ((f64::from(v) - f64::from(lo)) * inv)
                    .round()
                    .clamp(0.0, 65535.0) as u16
            })
            .collect();
        drop(scalars);
        let bytes: Vec<u8> = quant.iter().flat_map(|v| v.to_le_bytes()).collect();
        let texture = Texture3D::from_texels(dims, Format::R16, ColorSpace::Linear, &bytes, false)?;
        let spacing = Vec3::new(
            world_from_voxel.x_axis.truncate().length(),
            world_from_voxel.y_axis.truncate().length(),
            world_from_voxel.z_axis.truncate().length(),
        );
        Ok(Volume {
            dims,
            spacing,
            world_from_voxel,
            range: (lo, hi),
            value_step,
            texture,
            quant,
            bricks: std::sync::OnceLock::new(),
            normals: std::sync::OnceLock::new(),
            scalar_type: None,
            patient: None,
        })
    }

    /// Grid size (voxels per axis).
    #[must_use]
    pub fn dims(&self) -> [u32; 3] {
        self.dims
    }
    /// Voxel spacing in world units.
    #[must_use]
    pub fn spacing(&self) -> Vec3 {
        self.spacing
    }
    /// Voxel index (vertex-centred) → world.
    #[must_use]
    pub fn world_from_voxel(&self) -> Mat4 {
        self.world_from_voxel
    }
    /// Smallest and largest value.
    #[must_use]
    pub fn range(&self) -> (f32, f32) {
        self.range
    }
    /// The voxel type of the file the volume was read from (`None` when built from values).
    #[must_use]
    pub fn scalar_type(&self) -> Option<ScalarType> {
        self.scalar_type
    }
    /// Records the voxel type of the source data (for listings; the values are unchanged).
    pub fn set_scalar_type(&mut self, ty: ScalarType) {
        self.scalar_type = Some(ty);
    }
    /// Records which way the patient faces (a loader does, from the file's frame).
    pub fn set_patient_axes(&mut self, axes: Option<PatientAxes>) {
        self.patient = axes;
    }
    /// The patient's front and top as world directions under the current placement, when
    /// the file stated an anatomical frame.
    #[must_use]
    pub fn patient_front_and_top(&self) -> Option<(Vec3, Vec3)> {
        self.patient.map(|p| p.world(self.world_from_voxel))
    }
    /// The values as a 3D texture (`R16`, linear: level/65535; texel centres at the voxels).
    #[must_use]
    pub fn texture(&self) -> &Texture3D {
        &self.texture
    }
    /// The 16-bit levels, x fastest (value = `range().0 + level·value_step()`).
    #[must_use]
    pub fn quantized(&self) -> &[u16] {
        &self.quant
    }
    /// The value of one 16-bit level.
    #[must_use]
    pub fn value_step(&self) -> f32 {
        self.value_step
    }
    /// The value of (fractional) level `q`.
    #[inline]
    #[must_use]
    pub fn value_of(&self, q: f32) -> f32 {
        self.range.0 + q * self.value_step
    }
    /// The value of voxel `(x, y, z)` (in range), as stored (16-bit levels).
    #[must_use]
    pub fn voxel(&self, x: u32, y: u32, z: u32) -> f32 {
        let [nx, ny, _] = self.dims;
        self.value_of(f32::from(self.quant[((z * ny + y) * nx + x) as usize]))
    }
    /// Min/max of each 8³-cell brick (built on first use, then kept).
    #[must_use]
    pub fn bricks(&self) -> &Bricks {
        self.bricks
            .get_or_init(|| Bricks::new(&self.quant, self.dims))
    }
    /// Per-voxel unit normals in world space ×127 (built on first use, then kept).
    #[must_use]
    pub fn normals(&self) -> &Vec<[i8; 4]> {
        self.normals
            .get_or_init(|| voxel_normals(&self.quant, self.dims, self.world_from_voxel))
    }
    /// Replaces the placement (e.g. to ignore a file's orientation, as VTK does).
    pub fn set_world_from_voxel(&mut self, m: Mat4) -> Result<()> {
        if !m.is_finite() || m.determinant().abs() < 1e-12 {
            return Err(Error::parameter(
                "volume transform is singular or not finite",
            ));
        }
        self.world_from_voxel = m;
        self.normals = std::sync::OnceLock::new();
        self.spacing = Vec3::new(
            m.x_axis.truncate().length(),
            m.y_axis.truncate().length(),
            m.z_axis.truncate().length(),
        );
        Ok(())
    }

    /// The eight corners of the volume's box in world space.
    #[must_use]
    pub fn world_corners(&self) -> [Vec3; 8] {
        let n = Vec3::from_array(self.dims.map(|d| (d - 1) as f32));
        self.world_corners_of((Vec3::ZERO, n))
    }

    /// The eight corners of the voxel-space box `lo..hi` in world space.
    #[must_use]
    pub fn world_corners_of(&self, (lo, hi): (Vec3, Vec3)) -> [Vec3; 8] {
        std::array::from_fn(|i| {
            let c = Vec3::new(
                if i & 1 != 0 { hi.x } else { lo.x },
                if i & 2 != 0 { hi.y } else { lo.y },
                if i & 4 != 0 { hi.z } else { lo.z },
            );
            self.world_from_voxel.transform_point3(c)
        })
    }

    /// World-space axis-aligned bounds of the box (min, max).
    #[must_use]
    pub fn world_bounds(&self) -> (Vec3, Vec3) {
        let c = self.world_corners();
        let lo = c.iter().fold(Vec3::splat(f32::INFINITY), |a, &b| a.min(b));
        let hi = c
            .iter()
            .fold(Vec3::splat(f32::NEG_INFINITY), |a, &b| a.max(b));
        (lo, hi)
    }

    /// The camera `vtk_volume.py` starts from, framing this volume's box (see
    /// [`vtk_camera_for_bounds`]).
    #[must_use]
    pub fn vtk_camera(&self, dolly: f32, azimuth_deg: f32) -> crate::camera::Camera {
        let (lo, hi) = self.world_bounds();
        vtk_camera_for_bounds(lo, hi, dolly, azimuth_deg)
    }

    /// Trilinear value at a point in voxel space (vertex-centred; clamped to the box), read
    /// from the plain copy.
    #[inline]
    #[must_use]
    pub fn value_at(&self, p: Vec3) -> f32 {
        self.value_of(trilinear(&self.quant, self.dims, p))
    }

    /// Trilinear value at a point in voxel space read through the texture engine
    /// ([`crate::texture::sample_3d`], clamp to edge): the reference the fast path is tested
    /// against.
    #[must_use]
    pub fn value_at_engine(&self, p: Vec3) -> f32 {
        use crate::texture::{sample_3d, Filter, Footprint3, Sampler, Wrap};
        let n = Vec3::from_array(self.dims.map(|d| d as f32));
        let uvw = (p + 0.5) / n;
        let s = Sampler::new(Filter::BILINEAR, Wrap::ClampToEdge);
        let c: Vec4 = sample_3d(&self.texture, &s, &Footprint3::point(uvw));
        self.value_of(c.x * 65535.0)
    }

    /// [`Self::value_at_engine`] as a fractional 16-bit level.
    #[must_use]
    pub fn level_at_engine(&self, p: Vec3) -> f32 {
        (self.value_at_engine(p) - self.range.0) / self.value_step.max(f32::MIN_POSITIVE)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ramp(n: u32) -> Volume {
        let mut v = Vec::new();
        for z in 0..n {
            for y in 0..n {
                for x in 0..n {
                    v.push((x * x + 3 * y + 7 * z) as f32);
                }
            }
        }
        Volume::from_scalars([n; 3], Mat4::IDENTITY, v).expect("valid")
    }

    #[test]
    fn fast_trilinear_matches_texture_engine() {
        let vol = ramp(9);
        let mut s = 12345u32;
        for _ in 0..500 {
            let mut r = || {
                s = s.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                (s >> 8) as f32 / (1u32 << 24) as f32 * 8.0
            };
            let p = Vec3::new(r(), r(), r());
            let (a, b) = (vol.value_at(p), vol.value_at_engine(p));
            assert!((a - b).abs() < 1e-3 * b.abs().max(1.0), "{p}: {a} vs {b}");
        }
    }

    #[test]
    fn nan_is_rejected_with_its_voxel() {
        let mut v = vec![0.0; 8];
        v[5] = f32::NAN;
        let e = Volume::from_scalars([2, 2, 2], Mat4::IDENTITY, v).unwrap_err();
        assert!(e.to_string().contains("(1, 0, 1)"), "{e}");
    }

    #[test]
    fn vtk_camera_matches_vtk_volume_json() {
        // vtk_volume.py on vol256 (256³, spacing 1) reports position y = −405.779 143 6.
        let vol = Volume::from_scalars([256, 256, 256], Mat4::IDENTITY, vec![0.0; 256 * 256 * 256])
            .expect("valid");
        let c = vol.vtk_camera(1.6, 0.0);
        assert!(
            (c.eye - Vec3::new(127.5, -405.779_14, 127.5)).length() < 1e-3,
            "{}",
            c.eye
        );
    }
}
