//! Volumes: scalar fields on a grid (CT, MRI), classified by transfer functions and rendered
//! by ray marching ([`raymarch`]) or by view-aligned texture slices ([`slice`]).
//!
//! Conventions:
//! - Voxels are points (vertex-centred, as VTK and NIfTI): voxel `(i, j, k)` sits at
//!   `world_from_voxel · (i, j, k, 1)`, and the volume's box in voxel space is
//!   `[0, n − 1]` on each axis. The 3D texture's texel centres `(i + ½)/n` are the same points.
//! - Values are the file's values after its scale and offset (NIfTI `scl_slope`/`scl_inter`):
//!   Hounsfield units for CT. Transfer functions are written in those units.
//! - Lengths (`--step`, the opacity unit distance) are world units, i.e. the file's spacing
//!   units (mm for NIfTI and most NRRD), like VTK's `SampleDistance`.

pub mod load;
pub mod raymarch;
pub mod scene_volume;
mod shade;
pub mod slice;
pub mod transfer;

use glam::{Mat4, Vec3, Vec4};

use crate::texture::{ColorSpace, Format, Texture3D};
use crate::{Error, Result};

pub use load::{load_volume, RawDesc, ScalarType};
pub use raymarch::{iso_hit, raymarch, Classification, Lighting, MarchParams, Mode};
pub use slice::{render_slices, render_slices_until};

pub use scene_volume::{Method, SceneVolume};
pub use transfer::{PreIntegrated, TransferFunction, TransferFunction2D, TransferLut};

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
    /// The same 16-bit levels, x fastest: the marcher's fast path (see `raymarch`).
    quant: Vec<u16>,
    /// Min/max per brick for empty-space skipping, built on first use.
    bricks: std::sync::OnceLock<raymarch::Bricks>,
    /// Per-voxel world-space normals for shading, built on first use.
    normals: std::sync::OnceLock<Vec<[i8; 4]>>,
    /// The file's voxel type, when a loader made the volume.
    scalar_type: Option<ScalarType>,
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
    pub fn bricks(&self) -> &raymarch::Bricks {
        self.bricks.get_or_init(|| raymarch::Bricks::new(self))
    }
    /// Per-voxel unit normals in world space ×127 (built on first use, then kept).
    #[must_use]
    pub fn normals(&self) -> &Vec<[i8; 4]> {
        self.normals.get_or_init(|| raymarch::voxel_normals(self))
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
        std::array::from_fn(|i| {
            let c = Vec3::new(
                if i & 1 != 0 { n.x } else { 0.0 },
                if i & 2 != 0 { n.y } else { 0.0 },
                if i & 4 != 0 { n.z } else { 0.0 },
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

/// The camera `vtk_volume.py` starts from for the world box `lo..hi`: looking along +y with z
/// up at the centre of the box, at `ResetCamera`'s distance (bounding sphere fits a 30° view
/// angle) divided by `dolly` (the script's default is 1.6), then turned by `azimuth_deg` about
/// z (degrees).
#[must_use]
pub fn vtk_camera_for_bounds(
    lo: Vec3,
    hi: Vec3,
    dolly: f32,
    azimuth_deg: f32,
) -> crate::camera::Camera {
    let centre = (lo + hi) * 0.5;
    let radius = {
        let r = ((hi - lo) * 0.5).length();
        if r > 0.0 {
            r
        } else {
            1.0
        }
    };
    let view_angle = 30.0f32;
    let distance = radius / (view_angle.to_radians() * 0.5).sin() / dolly;
    let cam = crate::camera::Camera {
        eye: centre - Vec3::Y * distance,
        target: centre,
        up: Vec3::Z,
        projection: crate::camera::CameraProjection::Perspective {
            fov_y_deg: view_angle,
        },
        near: (distance - radius).max(distance * 1e-3),
        far: distance + radius * 2.0,
    };
    // VTK's Azimuth turns the eye about the view-up through the focal point.
    cam.orbit(azimuth_deg.to_radians())
}

/// The trilinear cell of voxel-space `p`, clamped to the box: the index of its lowest corner,
/// the strides to the next voxel along x, y and z (0 on a one-voxel axis, so every corner read
/// stays inside the grid), and the position inside the cell. `None` when `len`, the data's
/// length, is short of the grid's voxel count.
#[inline(always)]
pub(crate) fn trilinear_cell(
    dims: [u32; 3],
    p: Vec3,
    len: usize,
) -> Option<(usize, [usize; 3], Vec3)> {
    let [nx, ny, nz] = dims;
    if nx == 0 || ny == 0 || nz == 0 || len < nx as usize * ny as usize * nz as usize {
        return None;
    }
    let x = p.x.clamp(0.0, (nx - 1) as f32);
    let y = p.y.clamp(0.0, (ny - 1) as f32);
    let z = p.z.clamp(0.0, (nz - 1) as f32);
    let (ix, iy, iz) = (
        (x as u32).min(nx.saturating_sub(2)),
        (y as u32).min(ny.saturating_sub(2)),
        (z as u32).min(nz.saturating_sub(2)),
    );
    let strides = [
        usize::from(nx > 1),
        if ny > 1 { nx as usize } else { 0 },
        if nz > 1 { nx as usize * ny as usize } else { 0 },
    ];
    let i = (iz as usize * ny as usize + iy as usize) * nx as usize + ix as usize;
    Some((
        i,
        strides,
        Vec3::new(x - ix as f32, y - iy as f32, z - iz as f32),
    ))
}

/// Trilinear interpolation of `data` (x fastest, `dims`) at voxel-space `p`, clamped to the box.
#[inline(always)]
pub(crate) fn trilinear(data: &[u16], dims: [u32; 3], p: Vec3) -> f32 {
    let Some((
        i,
        [sx, sy, sz],
        Vec3 {
            x: fx,
            y: fy,
            z: fz,
        },
    )) = trilinear_cell(dims, p, data.len())
    else {
        return 0.0;
    };
    // SAFETY: `trilinear_cell` keeps ix ≤ nx − 2 when sx = 1 (else sx = 0), likewise y and z,
    // so the largest index, i + sx + sy + sz, is a voxel of the grid, whose nx·ny·nz values
    // `data` holds (it checked the length). Unchecked reads: the bounds checks cost
    // 8 compares and branches per sample in the marcher's inner loop.
    let g = |k: usize| f32::from(unsafe { *data.get_unchecked(k) });
    blend_cell(&cell_corners(i, [sx, sy, sz], g), Vec3::new(fx, fy, fz))
}

/// The eight corners of the cell at voxel index `i` with the given strides, x fastest:
/// c000, c100, c010, c110, c001, c101, c011, c111.
#[inline(always)]
pub(crate) fn cell_corners<T>(
    i: usize,
    [sx, sy, sz]: [usize; 3],
    g: impl Fn(usize) -> T,
) -> [T; 8] {
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

/// Trilinear blend of [`cell_corners`] at fractions `f` (x first, then y, then z).
#[inline(always)]
pub(crate) fn blend_cell<T: CellValue>(c: &[T; 8], f: Vec3) -> T {
    let c00 = c[0].mix(c[1], f.x);
    let c10 = c[2].mix(c[3], f.x);
    let c01 = c[4].mix(c[5], f.x);
    let c11 = c[6].mix(c[7], f.x);
    c00.mix(c10, f.y).mix(c01.mix(c11, f.y), f.z)
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
