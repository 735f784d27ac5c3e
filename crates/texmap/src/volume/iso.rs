//! Iso mode: the first crossing of the iso-value along a ray, refined by bisection and shaded
//! with the field's gradient there; and [`iso_hit`], the same crossing for any world ray.
//!
//! Rules:
//! - The iso-value is `MarchParams::iso`, else the transfer function's first opaque value,
//!   else the middle of the value range; its colour is the transfer function's there (white
//!   when that is nearly black).
//! - A crossing is the first sample at or above the iso-value; between it and the sample
//!   before, 10 bisections place the hit (to 1/1024 of that interval). A ray that starts
//!   inside (no sample before) hits at its first sample.
//! - Bricks whose largest value lies below the iso-value are skipped; the sample before a
//!   skipped brick stays the lower end of the bisection.

use glam::{Vec3, Vec4};

use super::bricks::BrickWalk;
use super::grid::Volume;
use super::marcher::{Marcher, Traced};
use super::params::{MarchParams, Mode};
use super::rays::{clip_to_box, RaySamples, VoxelRay};
use super::transfer::TransferFunction;
use crate::Result;

/// Where a ray first crosses the iso-value, and the samples it took to find out.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Crossing {
    /// The ray parameter of the crossing, if any.
    pub t: Option<f32>,
    pub samples: u64,
}

/// The iso-surface seen along the ray (`dir`, the world ray's direction, is the light's):
/// its shaded colour, opaque, or nothing.
pub(crate) fn surface(m: &Marcher, s: &RaySamples, dir: Vec3) -> Traced {
    let hit = crossing(m, s);
    match hit.t {
        Some(t) => {
            let q = s.ray.at(t);
            let g = m.gradient(q);
            Traced {
                color: m.shade(m.iso_color, g, dir, q).extend(1.0),
                samples: hit.samples,
            }
        }
        None => Traced {
            color: Vec4::ZERO,
            samples: hit.samples,
        },
    }
}

/// The first crossing of the iso-value (from below) along the ray, if any.
pub(crate) fn crossing(m: &Marcher, s: &RaySamples) -> Crossing {
    let walk = BrickWalk::new(s);
    let mut k = 0u32;
    let mut taken = 0u64;
    let mut t_prev: Option<f32> = None;
    while k < s.count {
        let t = s.t(k);
        let q = s.ray.at(t);
        if let Some(next) = m.empty.skip(&walk, q, k) {
            if t_prev.is_none() {
                t_prev = Some(t);
            }
            k = next;
            continue;
        }
        taken += 1;
        if m.value(q) >= m.iso_q {
            let mut hit = t;
            if let Some(tp) = t_prev {
                // Bisection: value(lo) < iso ≤ value(hi).
                let (mut lo, mut hi) = (tp, t);
                for _ in 0..10 {
                    let mid = 0.5 * (lo + hi);
                    if m.value(s.ray.at(mid)) >= m.iso_q {
                        hi = mid;
                    } else {
                        lo = mid;
                    }
                }
                hit = 0.5 * (lo + hi);
                taken += 10;
            }
            return Crossing {
                t: Some(hit),
                samples: taken,
            };
        }
        t_prev = Some(t);
        k += 1;
    }
    Crossing {
        t: None,
        samples: taken,
    }
}

/// The distance along the world ray `origin + t·dir` (`dir` of unit length) to the
/// isosurface [`Mode::Iso`] would draw (`params.iso`, else the transfer function's first
/// opaque value), without jitter.
///
/// # Errors
/// [`crate::Error::Parameter`] for a bad step or iso-value.
pub fn iso_hit(
    vol: &Volume,
    tf: &TransferFunction,
    origin: Vec3,
    dir: Vec3,
    params: &MarchParams,
) -> Result<Option<f32>> {
    params.check_step()?;
    let p = MarchParams {
        mode: Mode::Iso,
        ..params.clone()
    };
    let m = Marcher::new(vol, tf, &p, None)?;
    let ray = VoxelRay::new(&m.voxel_from_world, origin, dir);
    Ok(clip_to_box(&ray, f32::INFINITY, m.lo, m.hi)
        .and_then(|span| crossing(&m, &RaySamples::new(ray, span, p.step, 0.0)).t))
}
