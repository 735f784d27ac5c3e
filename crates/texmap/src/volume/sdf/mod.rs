//! Signed distance fields: 3D grids of the distance to a surface, negative inside, in world
//! units (Miller & Jones 2005, `../shared/references/001_*.txt`, §3: a distance field is the
//! volume representation that texturing and hypertexturing of a volumetric object read).
//!
//! Three sources, one result type ([`Field`]):
//! - triangle meshes ([`mesh_field`]): the exact distance to the nearest triangle through a
//!   bounding volume hierarchy (`bvh`), the sign from the generalized winding number,
//!   evaluated by Barill et al.'s fast hierarchical approximation (`winding`), so that small
//!   holes and badly oriented triangles do not flip it; rows of voxels in parallel (`mesh`);
//! - thresholded scans ([`mask_field`]): the exact Euclidean distance transform of
//!   Felzenszwalb & Huttenlocher, linear in the voxel count, with anisotropic spacing (`edt`);
//! - analytic primitives and their CSG ([`Shape`], `analytic`).
//!
//! And drawn (Miller & Jones §5–6): [`render_distance_field`] sphere-traces the surface
//! (`render`, reading the field through `reader`), colours it with a solid texture and bumps
//! it ([`SurfaceLook`], `look`), and marches a [`Hypertexture`] (`hyper`) in a shell around
//! it: fur, fire, smoke, melt.
//!
//! Conventions:
//! - A field's voxels are points, as everywhere in [`crate::volume`]: voxel `(i, j, k)` holds
//!   the distance at `origin + (i, j, k)·spacing` (its centre). The grid of
//!   [`FieldGrid::around_box`] is the one `../shared/peers/sdf_ref.py mesh` uses: the box grown
//!   by `pad ×` its largest side on every face, `res` cubic cells along the largest side,
//!   `ceil(extent / h)` along the others, centres at `corner + (i + ½)·h`.
//! - Values are `f32`, x fastest; a field is written as NIfTI-1 or NRRD (`write`) and reads
//!   back through [`crate::volume::load`] with its spacing and placement.
//! - The same inputs give the same bytes whatever the thread count: every row of voxels is
//!   computed by one thread from the same data in the same order.

mod analytic;
mod bvh;
mod cast;
mod edt;
pub mod hyper;
mod look;
mod mesh;
mod noise_cache;
mod reader;
mod render;
mod smooth;
mod winding;
mod write;

use glam::{DMat4, DVec3, Mat4};

pub use analytic::{shape_field, Shape};
pub use cast::FieldCaster;
pub use edt::{distance_transform_sq, mask_field, Mask};
pub use hyper::{Hypertexture, NoiseKind};
pub use look::SurfaceLook;
pub use mesh::{mesh_field, MeshFieldStats, Triangles};
pub use render::{render_distance_field, render_distance_field_shadowed};
pub use smooth::{smooth_field, SCAN_SMOOTHING};
pub use write::{write_nifti, write_nrrd, FieldFormat};

use crate::{Error, Result};

/// A regular grid of sample points: `dims` voxels, voxel `(i, j, k)` at
/// `world_from_voxel · (i, j, k, 1)`, whose first three columns are orthogonal (a scan's axes
/// may be rotated or flipped; a mesh's grid is axis-aligned).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FieldGrid {
    /// Voxels per axis.
    pub dims: [u32; 3],
    /// Voxel indices → world points (the centre of each voxel).
    pub world_from_voxel: DMat4,
}

impl FieldGrid {
    /// An axis-aligned grid: voxel `(i, j, k)` at `origin + (i, j, k)·spacing`.
    #[must_use]
    pub fn axis_aligned(dims: [u32; 3], origin: DVec3, spacing: DVec3) -> FieldGrid {
        let mut m = DMat4::from_scale(spacing);
        m.w_axis = origin.extend(1.0);
        FieldGrid {
            dims,
            world_from_voxel: m,
        }
    }

    /// The grid of `sdf_ref.py mesh` around the box `[lo, hi]`: grown by `pad ×` its largest
    /// side on every face; `res` voxels of side `h = largest grown side / res` along it and
    /// `ceil(grown side / h)` (at least 1) along the others; voxel centres at
    /// `grown lo + (i + ½)·h`. Computed in `f64` in the script's order of operations.
    ///
    /// # Errors
    /// [`Error::Parameter`] for `res` = 0, a negative or non-finite `pad`, an empty or
    /// non-finite box, or a side above 65,535 voxels.
    pub fn around_box(lo: DVec3, hi: DVec3, res: u32, pad: f64) -> Result<FieldGrid> {
        if res == 0 {
            return Err(Error::parameter("--res must be at least 1"));
        }
        if !(pad.is_finite() && pad >= 0.0) {
            return Err(Error::parameter(format!(
                "--pad {pad} must be a finite number ≥ 0"
            )));
        }
        if !(lo.is_finite() && hi.is_finite() && lo.cmple(hi).all()) {
            return Err(Error::parameter("the bounding box is empty or not finite"));
        }
        let side = (hi - lo).max_element();
        let (lo, hi) = (lo - pad * side, hi + pad * side);
        let ext = hi - lo;
        let h = ext.max_element() / f64::from(res);
        if !(h > 0.0 && h.is_finite()) {
            return Err(Error::parameter(
                "the bounding box has no extent (a single point)",
            ));
        }
        let mut dims = [1u32; 3];
        for (a, d) in dims.iter_mut().enumerate() {
            let n = (ext[a] / h).ceil();
            if n > 65_535.0 {
                return Err(Error::parameter(format!(
                    "the grid would have {n} voxels along axis {a} (at most 65,535)"
                )));
            }
            *d = (n as u32).max(1);
        }
        Ok(FieldGrid::axis_aligned(dims, lo + 0.5 * h, DVec3::splat(h)))
    }

    /// The number of voxels.
    #[must_use]
    pub fn voxel_count(&self) -> u64 {
        self.dims.iter().map(|&d| u64::from(d)).product()
    }

    /// The distance between voxel centres along each axis (the columns' lengths).
    #[must_use]
    pub fn spacing(&self) -> DVec3 {
        let m = &self.world_from_voxel;
        DVec3::new(
            m.x_axis.truncate().length(),
            m.y_axis.truncate().length(),
            m.z_axis.truncate().length(),
        )
    }

    /// Voxel `(i, j, k)`'s centre.
    #[must_use]
    pub fn point(&self, i: u32, j: u32, k: u32) -> DVec3 {
        self.world_from_voxel
            .transform_point3(DVec3::new(f64::from(i), f64::from(j), f64::from(k)))
    }

    /// [`Self::world_from_voxel`] in `f32`, as volumes keep it.
    #[must_use]
    pub fn world_from_voxel_f32(&self) -> Mat4 {
        self.world_from_voxel.as_mat4()
    }
}

/// A signed distance field: one `f32` per voxel of its grid, x fastest, negative inside.
#[derive(Clone, Debug, PartialEq)]
pub struct Field {
    /// Where the values are.
    pub grid: FieldGrid,
    /// `grid.voxel_count()` distances, x fastest.
    pub values: Vec<f32>,
}

impl Field {
    /// The value at voxel `(i, j, k)`.
    ///
    /// # Panics
    /// When the voxel is outside the grid.
    #[must_use]
    pub fn at(&self, i: u32, j: u32, k: u32) -> f32 {
        let [nx, ny, _] = self.grid.dims;
        self.values[i as usize + nx as usize * (j as usize + ny as usize * k as usize)]
    }

    /// The smallest and largest values.
    #[must_use]
    pub fn range(&self) -> (f32, f32) {
        self.values
            .iter()
            .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), &v| {
                (lo.min(v), hi.max(v))
            })
    }

    /// The field as a [`Volume`](crate::volume::Volume) (16-bit levels over its range), to
    /// render it.
    ///
    /// # Errors
    /// As [`Volume::from_scalars`](crate::volume::Volume::from_scalars).
    pub fn to_volume(&self) -> Result<crate::volume::Volume> {
        crate::volume::Volume::from_scalars(
            self.grid.dims,
            self.grid.world_from_voxel_f32(),
            self.values.clone(),
        )
    }
}

#[cfg(test)]
mod tests;
