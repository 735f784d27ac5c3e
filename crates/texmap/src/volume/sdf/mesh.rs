//! A triangle mesh's signed distance field: at every voxel the exact distance to the nearest
//! triangle (`bvh`), negative where the winding number (`winding`) says inside.
//!
//! Two facts about distance fields cut the work (each exact for a closed mesh):
//! - the distance is 1-Lipschitz, so along a row the previous voxel's nearest triangle is
//!   within `d + h` of the next voxel: its distance is the query's first bound, and most of
//!   the tree is pruned at once;
//! - no surface passes through the ball of radius `|d|` around a voxel, and the winding
//!   number of a closed mesh is constant off the surface, so a later voxel of the row inside
//!   that ball has the same sign and needs no winding number. Near a hole the winding number
//!   varies off the surface; the sign is reused only from a voxel whose winding number was
//!   clearly inside or outside (at least [`CLEAR`] from ½), and every voxel near the surface
//!   (closer than a voxel) is evaluated.
//!
//! Rows of voxels (along x) run in parallel (rayon); a row is computed by one thread alone,
//! so the field is the same whatever the thread count.

use std::time::Instant;

use glam::{Vec3, Vec3A};
use rayon::prelude::*;

use super::bvh::{tri_dist2, Bvh, Tri};
use super::winding::Winding;
use super::{Field, FieldGrid};
use crate::{Error, Result};

/// A reused sign needs the evaluated winding number at least this far from ½.
const CLEAR: f32 = 0.25;

/// World-space triangles, the input of [`mesh_field`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Triangles {
    tris: Vec<[Vec3; 3]>,
}

impl Triangles {
    /// No triangles.
    #[must_use]
    pub fn new() -> Self {
        Triangles::default()
    }

    /// Adds a triangle (counter-clockwise seen from outside); one with a non-finite corner is
    /// skipped.
    pub fn push(&mut self, tri: [Vec3; 3]) {
        if tri.iter().all(|v| v.is_finite()) {
            self.tris.push(tri);
        }
    }

    /// The triangles.
    #[must_use]
    pub fn as_slice(&self) -> &[[Vec3; 3]] {
        &self.tris
    }

    /// How many.
    #[must_use]
    pub fn len(&self) -> usize {
        self.tris.len()
    }

    /// True with no triangles.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.tris.is_empty()
    }

    /// The bounding box of the corners (in `f64`), `None` when empty.
    #[must_use]
    pub fn bounds(&self) -> Option<(glam::DVec3, glam::DVec3)> {
        let mut it = self.tris.iter().flatten();
        let first = it.next()?.as_dvec3();
        Some(it.fold((first, first), |(lo, hi), v| {
            (lo.min(v.as_dvec3()), hi.max(v.as_dvec3()))
        }))
    }
}

impl FromIterator<[Vec3; 3]> for Triangles {
    fn from_iter<I: IntoIterator<Item = [Vec3; 3]>>(iter: I) -> Self {
        let mut t = Triangles::new();
        for tri in iter {
            t.push(tri);
        }
        t
    }
}

/// What building a mesh field cost.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MeshFieldStats {
    /// Building the tree and its dipoles, ms.
    pub tree_ms: f64,
    /// Filling the grid, ms.
    pub fill_ms: f64,
    /// Voxels whose winding number was evaluated (the others reused a sign).
    pub winding_evaluations: u64,
}

/// The signed distance field of `tris` on `grid` (see the module docs).
///
/// # Errors
/// [`Error::Parameter`] when there are no triangles.
pub fn mesh_field(tris: &Triangles, grid: &FieldGrid) -> Result<(Field, MeshFieldStats)> {
    if tris.is_empty() {
        return Err(Error::parameter("the mesh has no triangles"));
    }
    let t0 = Instant::now();
    let list: Vec<Tri> = tris
        .tris
        .iter()
        .map(|&[a, b, c]| Tri {
            a: a.into(),
            b: b.into(),
            c: c.into(),
        })
        .collect();
    let bvh = Bvh::build(&list);
    let winding = Winding::new(&bvh);
    let tree_ms = t0.elapsed().as_secs_f64() * 1e3;

    let t1 = Instant::now();
    let [nx, ny, nz] = grid.dims.map(|d| d as usize);
    let mut values = vec![0.0f32; nx * ny * nz];
    let step = grid.world_from_voxel.x_axis.truncate().as_vec3();
    let evaluations: u64 = values
        .par_chunks_mut(nx)
        .enumerate()
        .map(|(row, out)| {
            let (j, k) = ((row % ny) as u32, (row / ny) as u32);
            let start = grid.point(0, j, k);
            fill_row(&bvh, &winding, start, step, out)
        })
        .sum();
    let fill_ms = t1.elapsed().as_secs_f64() * 1e3;
    Ok((
        Field {
            grid: *grid,
            values,
        },
        MeshFieldStats {
            tree_ms,
            fill_ms,
            winding_evaluations: evaluations,
        },
    ))
}

/// One row of voxels from `start` in steps of `step`; returns the winding numbers evaluated.
fn fill_row(bvh: &Bvh, winding: &Winding, start: glam::DVec3, step: Vec3, out: &mut [f32]) -> u64 {
    let mut guess = (f32::INFINITY, 0u32);
    // The last voxel whose sign was evaluated: its point, squared distance, and inside.
    let mut signed: Option<(Vec3A, f32, bool)> = None;
    let mut evaluations = 0;
    for (i, v) in out.iter_mut().enumerate() {
        let p = Vec3A::from((start + step.as_dvec3() * i as f64).as_vec3());
        if guess.0.is_finite() {
            guess.0 = tri_dist2(p, &bvh.tris[guess.1 as usize]);
        }
        let (d2, tri) = bvh.closest(p, guess);
        guess = (d2, tri);
        let inside = match signed {
            Some((q, r2, inside)) if (p - q).length_squared() < r2 => inside,
            _ => {
                evaluations += 1;
                let w = winding.at(bvh, p);
                let inside = w >= 0.5;
                // Only a clear answer, at a voxel with room around it, is passed on.
                signed = if (w - 0.5).abs() >= CLEAR {
                    Some((p, d2, inside))
                } else {
                    None
                };
                inside
            }
        };
        let d = d2.sqrt();
        *v = if inside { -d } else { d };
    }
    evaluations
}
