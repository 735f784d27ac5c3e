//! The field's normals for shading: per-voxel normals built once per volume, their trilinear
//! interpolation at a sample, and central differences of the interpolated field.
//!
//! Rules:
//! - Per-voxel normals are central differences of the 16-bit levels (one-sided on the box's
//!   faces) taken to world space through the inverse transpose of `world_from_voxel`,
//!   normalised and stored ×127 as `[i8; 4]` (the fourth is 0); zero where the field is flat.
//! - Eight interpolated normals that disagree (or are zero) give a short vector: below half
//!   length a sample has no normal and gets ambient light only, as VTK's shading tables give
//!   a zero normal.
//! - Shading interpolates the per-voxel normals rather than taking central differences of the
//!   interpolated field, which costs six extra trilinear reads per sample; those differences
//!   ([`central_difference`]) remain where the gradient's magnitude matters (gradient
//!   opacity) and for iso-surface hits (one per ray).

use glam::{Mat3, Mat4, Vec3, Vec4};
use rayon::prelude::*;

use super::cell::interpolate;

/// Per-voxel unit normals in world space ×127 of the 16-bit `levels` of a `dims` grid (x
/// fastest) placed by `world_from_voxel`; zero where the field is flat.
#[must_use]
pub(crate) fn voxel_normals(
    levels: &[u16],
    dims: [u32; 3],
    world_from_voxel: Mat4,
) -> Vec<[i8; 4]> {
    let (nx, ny, nz) = (dims[0] as usize, dims[1] as usize, dims[2] as usize);
    let m = Mat3::from_mat4(world_from_voxel.inverse()).transpose();
    let slabs: Vec<Vec<[i8; 4]>> = (0..nz)
        .into_par_iter()
        .map(|z| {
            let mut out = Vec::with_capacity(nx * ny);
            let at = |x: usize, y: usize, z: usize| f32::from(levels[(z * ny + y) * nx + x]);
            for y in 0..ny {
                for x in 0..nx {
                    let diff = |lo: usize, hi: usize, f: &dyn Fn(usize) -> f32| {
                        if hi > lo {
                            (f(hi) - f(lo)) / (hi - lo) as f32
                        } else {
                            0.0
                        }
                    };
                    let gx = diff(x.saturating_sub(1), (x + 1).min(nx - 1), &|i| at(i, y, z));
                    let gy = diff(y.saturating_sub(1), (y + 1).min(ny - 1), &|j| at(x, j, z));
                    let gz = diff(z.saturating_sub(1), (z + 1).min(nz - 1), &|k| at(x, y, k));
                    let g = m * Vec3::new(gx, gy, gz);
                    let len = g.length();
                    out.push(if len > 0.0 {
                        let n = g / len * 127.0;
                        [n.x.round() as i8, n.y.round() as i8, n.z.round() as i8, 0]
                    } else {
                        [0; 4]
                    });
                }
            }
            out
        })
        .collect();
    slabs.concat()
}

/// A stored normal (×127) as a vector, for blending.
#[inline(always)]
pub(crate) fn normal_of(n: [i8; 4]) -> Vec3 {
    Vec3::new(f32::from(n[0]), f32::from(n[1]), f32::from(n[2]))
}

/// A stored normal (×127) in four lanes, for blending in lanes: the values of [`normal_of`]
/// (the fourth lane, the stored 0, is never read back). With SSE4.1 (this crate's x86-64 build) one load, sign extension and
/// conversion.
#[inline(always)]
pub(crate) fn normal_lanes(n: [i8; 4]) -> Vec4 {
    #[cfg(all(target_arch = "x86_64", target_feature = "sse4.1"))]
    {
        use std::arch::x86_64::{_mm_cvtepi32_ps, _mm_cvtepi8_epi32, _mm_cvtsi32_si128};
        let bits = i32::from_ne_bytes(n.map(|b| b as u8));
        // SAFETY: SSE4.1 is enabled for this build.
        Vec4::from(unsafe { _mm_cvtepi32_ps(_mm_cvtepi8_epi32(_mm_cvtsi32_si128(bits))) })
    }
    #[cfg(not(all(target_arch = "x86_64", target_feature = "sse4.1")))]
    {
        normal_of(n).extend(f32::from(n[3]))
    }
}

/// [`direction_or_zero`] of a normal blended in lanes ([`normal_lanes`]; the fourth lane is
/// ignored): the same bits.
#[inline(always)]
pub(crate) fn direction_or_zero_lanes(n127: Vec4) -> Vec3 {
    let v = (n127 * (1.0 / 127.0)).truncate();
    if v.length_squared() < 0.25 * 0.25 {
        Vec3::ZERO
    } else {
        v
    }
}

/// An interpolated normal (×127) as a direction: below half length the neighbours disagree
/// (or are flat), so there is none.
#[inline(always)]
pub(crate) fn direction_or_zero(n127: Vec3) -> Vec3 {
    let v = n127 * (1.0 / 127.0);
    if v.length_squared() < 0.25 * 0.25 {
        Vec3::ZERO
    } else {
        v
    }
}

/// Trilinear interpolation of per-voxel normals at voxel-space `p` (clamped): a direction
/// whose length falls below ½ where the normals disagree or are zero.
#[inline(always)]
pub(crate) fn trilinear_normal(normals: &[[i8; 4]], dims: [u32; 3], p: Vec3) -> Vec3 {
    interpolate(normals, dims, p, normal_of).map_or(Vec3::ZERO, direction_or_zero)
}

/// Half the differences of `value` one voxel either way along x, y and z around
/// voxel-space `q`: the field's gradient in voxel units (per voxel) at `q`.
#[inline(always)]
pub(crate) fn central_difference(value: impl Fn(Vec3) -> f32, q: Vec3) -> Vec3 {
    Vec3::new(
        value(q + Vec3::X) - value(q - Vec3::X),
        value(q + Vec3::Y) - value(q - Vec3::Y),
        value(q + Vec3::Z) - value(q - Vec3::Z),
    ) * 0.5
}
