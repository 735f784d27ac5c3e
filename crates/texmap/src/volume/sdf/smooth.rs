//! Smoothing a scan's distance field before its surface is drawn. The exact transform of a
//! thresholded mask measures to voxel centres, so its zero set is a staircase of voxel faces
//! and its gradient shades as terraces. A binomial filter `[1, 2, 1] / 4` along each axis,
//! `passes` times, rounds the steps off (σ = √(passes / 2) voxels) and leaves a distance
//! that is linear across the kernel unchanged (the kernel is symmetric and sums to 1), so
//! the field away from the surface keeps its meaning for sphere tracing.

use super::Field;

/// The passes a scan's field is smoothed by before its surface is drawn (σ ≈ 1.2 voxels).
pub const SCAN_SMOOTHING: u32 = 3;

/// `field` filtered `passes` times by `[1, 2, 1] / 4` along x, y and z (edges clamped).
#[must_use]
pub fn smooth_field(field: &Field, passes: u32) -> Field {
    let [nx, ny, nz] = field.grid.dims.map(|d| d as usize);
    let mut v = field.values.clone();
    let mut tmp = vec![0.0f32; v.len()];
    for _ in 0..passes {
        for (n, stride) in [(nx, 1), (ny, nx), (nz, nx * ny)] {
            if n < 2 {
                continue;
            }
            for (i, out) in tmp.iter_mut().enumerate() {
                let k = (i / stride) % n;
                let lo = if k == 0 { i } else { i - stride };
                let hi = if k + 1 == n { i } else { i + stride };
                *out = 0.25 * v[lo] + 0.5 * v[i] + 0.25 * v[hi];
            }
            std::mem::swap(&mut v, &mut tmp);
        }
    }
    Field {
        grid: field.grid,
        values: v,
    }
}
