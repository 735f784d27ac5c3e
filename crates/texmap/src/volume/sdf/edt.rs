//! A scan's signed distance field: the exact Euclidean distance transform of a thresholded
//! volume, in time linear in the voxel count.
//!
//! Felzenszwalb & Huttenlocher, "Distance Transforms of Sampled Functions" (Theory of
//! Computing 8, 2012): the squared distance transform is separable,
//! `D(x, y, z) = min over x' of (sx²(x − x')² + min over y' of (sy²(y − y')² + min over z' …))`,
//! and each one-dimensional pass `f(q) = min_p (w²(q − p)² + g(p))` is the lower envelope of
//! parabolas rooted at the samples, found in one sweep and read back in another. Spacing
//! enters as the weight `w` of each axis's pass, so anisotropic voxels are exact.
//!
//! The signed field follows `sdf_ref.py mask`: an outside voxel holds +(the distance from its
//! centre to the nearest inside voxel's centre), an inside voxel −(the distance to the nearest
//! outside one); nothing is subtracted, so no value lies in (−h, h) but 0 never occurs.
//!
//! Lines of each pass run in parallel (rayon); each line is one thread's work, so results do
//! not depend on the thread count.

use rayon::prelude::*;

use super::{Field, FieldGrid};
use crate::{Error, Result};

/// Which voxels are inside: one flag per voxel, x fastest.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Mask {
    /// Voxels per axis.
    pub dims: [u32; 3],
    /// `dims[0]·dims[1]·dims[2]` flags, x fastest.
    pub inside: Vec<bool>,
}

impl Mask {
    /// The voxels whose value is at least `threshold` (the rule of `sdf_ref.py mask`).
    #[must_use]
    pub fn threshold(dims: [u32; 3], values: &[f32], threshold: f64) -> Mask {
        Mask {
            dims,
            inside: values.iter().map(|&v| f64::from(v) >= threshold).collect(),
        }
    }
}

/// The squared distance (world units²) from every voxel to the nearest voxel whose flag in
/// `feature` is true, with voxel spacing `spacing`; `f64::INFINITY` everywhere when no flag
/// is set.
///
/// # Panics
/// When `feature` does not hold one flag per voxel of `dims`.
#[must_use]
pub fn distance_transform_sq(dims: [u32; 3], spacing: [f64; 3], feature: &[bool]) -> Vec<f64> {
    let [nx, ny, nz] = dims.map(|d| d as usize);
    assert_eq!(feature.len(), nx * ny * nz, "one flag per voxel");
    let mut g: Vec<f64> = feature
        .iter()
        .map(|&f| if f { 0.0 } else { f64::INFINITY })
        .collect();
    let w2 = spacing.map(|s| s * s);
    let longest = nx.max(ny).max(nz);
    // x: contiguous lines.
    g.par_chunks_mut(nx).for_each_init(
        || Scratch::new(longest),
        |s, line| {
            s.input[..nx].copy_from_slice(line);
            s.transform(nx, w2[0]);
            line.copy_from_slice(&s.output[..nx]);
        },
    );
    // y: strided within each z slab.
    g.par_chunks_mut(nx * ny).for_each_init(
        || Scratch::new(longest),
        |s, slab| {
            for x in 0..nx {
                for y in 0..ny {
                    s.input[y] = slab[x + nx * y];
                }
                s.transform(ny, w2[1]);
                for y in 0..ny {
                    slab[x + nx * y] = s.output[y];
                }
            }
        },
    );
    // z: strided across slabs; each y-plane's lines are one task, gathered and scattered.
    if nz > 1 {
        let planes: Vec<Vec<f64>> = (0..ny)
            .into_par_iter()
            .map_init(
                || Scratch::new(longest),
                |s, y| {
                    let mut plane = vec![0.0; nx * nz];
                    for x in 0..nx {
                        for z in 0..nz {
                            s.input[z] = g[x + nx * (y + ny * z)];
                        }
                        s.transform(nz, w2[2]);
                        plane[x * nz..(x + 1) * nz].copy_from_slice(&s.output[..nz]);
                    }
                    plane
                },
            )
            .collect();
        for (y, plane) in planes.iter().enumerate() {
            for x in 0..nx {
                for z in 0..nz {
                    g[x + nx * (y + ny * z)] = plane[x * nz + z];
                }
            }
        }
    }
    g
}

/// The buffers of one-dimensional transforms.
struct Scratch {
    input: Vec<f64>,
    output: Vec<f64>,
    /// Roots of the envelope's parabolas.
    roots: Vec<usize>,
    /// Boundaries between them (`bounds[k]`..`bounds[k+1]` belongs to `roots[k]`).
    bounds: Vec<f64>,
}

impl Scratch {
    fn new(n: usize) -> Scratch {
        Scratch {
            input: vec![0.0; n],
            output: vec![0.0; n],
            roots: vec![0; n],
            bounds: vec![0.0; n + 1],
        }
    }

    /// `output[q] = min_p (w2·(q − p)² + input[p])` for the first `n` samples; infinite
    /// samples root no parabola.
    fn transform(&mut self, n: usize, w2: f64) {
        let (f, v, z) = (&self.input, &mut self.roots, &mut self.bounds);
        let Some(first) = f[..n].iter().position(|x| x.is_finite()) else {
            self.output[..n].fill(f64::INFINITY);
            return;
        };
        let mut k = 0usize;
        v[0] = first;
        z[0] = f64::NEG_INFINITY;
        z[1] = f64::INFINITY;
        for q in first + 1..n {
            if !f[q].is_finite() {
                continue;
            }
            let fq = f[q] + w2 * (q * q) as f64;
            loop {
                let p = v[k];
                let s = (fq - (f[p] + w2 * (p * p) as f64)) / (2.0 * w2 * (q - p) as f64);
                if s <= z[k] {
                    // Parabola k is hidden (k > 0 here: z[0] is −∞).
                    k -= 1;
                } else {
                    k += 1;
                    v[k] = q;
                    z[k] = s;
                    z[k + 1] = f64::INFINITY;
                    break;
                }
            }
        }
        let mut k = 0;
        for q in 0..n {
            while z[k + 1] < q as f64 {
                k += 1;
            }
            let d = q as f64 - v[k] as f64;
            self.output[q] = w2 * d * d + f[v[k]];
        }
    }
}

/// The signed distance field of `mask` on `grid` (see the module docs).
///
/// # Errors
/// [`Error::Parameter`] when the mask and grid differ in size, or when no voxel is inside or
/// none outside (the field would be infinite).
pub fn mask_field(mask: &Mask, grid: &FieldGrid) -> Result<Field> {
    if mask.dims != grid.dims || mask.inside.len() as u64 != grid.voxel_count() {
        return Err(Error::parameter(format!(
            "a mask of {:?} on a grid of {:?}",
            mask.dims, grid.dims
        )));
    }
    let inside = mask.inside.iter().filter(|&&b| b).count();
    if inside == 0 || inside == mask.inside.len() {
        return Err(Error::parameter(format!(
            "{} of {} voxels are inside: a distance field needs both sides",
            inside,
            mask.inside.len()
        )));
    }
    let sp = grid.spacing().to_array();
    let to_inside = distance_transform_sq(mask.dims, sp, &mask.inside);
    let outside: Vec<bool> = mask.inside.iter().map(|&b| !b).collect();
    let to_outside = distance_transform_sq(mask.dims, sp, &outside);
    let values = mask
        .inside
        .par_iter()
        .zip(to_inside.par_iter().zip(to_outside.par_iter()))
        .map(|(&ins, (&di, &dout))| {
            if ins {
                -(dout.sqrt() as f32)
            } else {
                di.sqrt() as f32
            }
        })
        .collect();
    Ok(Field {
        grid: *grid,
        values,
    })
}
