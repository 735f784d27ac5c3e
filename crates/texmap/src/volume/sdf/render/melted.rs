//! The melted core (melt, core displacement): its distance, sphere-traced with a Lipschitz
//! bound, and the placing of its crossing (bisection, false position).
//!
//! Rules:
//! - Far from the core a step crosses an empty ball of the core's distance lattice
//!   ([`super::warp`]), near it reads the noises themselves, in steps of at least ¼ voxel.
//! - A crossing of the plain field is bisected; the melted core's by false position
//!   (Illinois), whose few reads matter because each reads the noises.

use glam::Vec3;

use super::super::hyper::Hypertexture;
use super::warp;
use super::{Tracer, BISECTIONS};

impl Tracer<'_> {
    /// True when the core surface is not the field's zero set (melted or displaced).
    #[inline(always)]
    pub(super) fn warped(&self) -> bool {
        self.warped
    }

    /// The melt's displacement of world point `p`: the field is read that far up.
    #[inline]
    pub(super) fn sag(&self, h: &Hypertexture, p: Vec3) -> Vec3 {
        if h.melt == 0.0 || h.time == 0.0 {
            return Vec3::ZERO;
        }
        let height = ((p.dot(self.up) - self.base) / self.size).max(0.0);
        // Drips: noise across the up axis, slowly varying along it.
        let n = warp::sag_noise(h, self.up, self.texture_from_world.transform_point3(p));
        self.up * (h.melt * h.time * height * (1.0 + 1.5 * n).max(0.0) * self.size)
    }

    /// The distance to the core surface (melted and displaced), world.
    #[inline]
    pub(super) fn core_distance(&self, p: Vec3) -> f32 {
        let Some(h) = self.hyper else {
            return self
                .field
                .distance(self.field.voxel_from_world.transform_point3(p));
        };
        let pm = p + self.sag(h, p);
        let d = self
            .field
            .distance(self.field.voxel_from_world.transform_point3(pm));
        if h.core_displacement == 0.0 {
            d
        } else {
            d - h.core_displacement * self.shell * self.noise(h, p)
        }
    }

    /// [`Self::core_distance`] where it is near; far from the core, a lower bound of it
    /// without the displacement's noise (`d − displacement`, at most 1/5 below it there),
    /// which sphere tracing may step by just as safely.
    #[inline]
    pub(super) fn core_step_distance(&self, p: Vec3) -> f32 {
        let Some(h) = self.hyper.filter(|h| h.core_displacement != 0.0) else {
            return self.core_distance(p);
        };
        let pm = p + self.sag(h, p);
        let d = self
            .field
            .distance(self.field.voxel_from_world.transform_point3(pm));
        // The noise is in [0, 1]: the displacement is at most this.
        let most = h.core_displacement.max(0.0) * self.shell;
        if h.core_displacement > 0.0 && d - most > 4.0 * most {
            d - most
        } else {
            d - h.core_displacement * self.shell * self.noise(h, p)
        }
    }

    /// The crossing between `lo` (outside) and `hi` (inside) along the ray, to 1/100 voxel,
    /// and the reads it took.
    pub(super) fn bisect(&self, eye: Vec3, dir: Vec3, lo: f32, hi: f32) -> (f32, u32) {
        let (mut lo, mut hi) = (lo, hi);
        let tolerance = 0.01 * self.field.voxel;
        let mut n = 0;
        while n < BISECTIONS && hi - lo > tolerance {
            n += 1;
            let mid = 0.5 * (lo + hi);
            if self.core_distance(eye + dir * mid) <= 0.0 {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        (0.5 * (lo + hi), n)
    }

    /// The crossing between `lo` (outside) and `hi` (inside), each a ray distance and its
    /// core distance, to 1/100 voxel by false position (Illinois: a side kept twice has its
    /// distance halved), and the reads it took.
    pub(super) fn false_position(
        &self,
        eye: Vec3,
        dir: Vec3,
        lo: (f32, f32),
        hi: (f32, f32),
    ) -> (f32, u32) {
        let ((mut lo, mut e_lo), (mut hi, mut e_hi)) = (lo, hi);
        let tolerance = 0.01 * self.field.voxel;
        let mut n = 0;
        let mut kept = 0i8;
        while n < BISECTIONS && hi - lo > tolerance {
            n += 1;
            let w = e_lo - e_hi;
            let guess = if e_lo > 0.0 && w > 0.0 {
                lo + (hi - lo) * (e_lo / w)
            } else {
                0.5 * (lo + hi)
            };
            // Not on an end, so the bracket shrinks by at least half the tolerance.
            let m = guess.clamp(lo + 0.5 * tolerance, hi - 0.5 * tolerance);
            let e = self.core_distance(eye + dir * m);
            if e <= 0.0 {
                (hi, e_hi) = (m, e);
                if kept < 0 {
                    e_lo *= 0.5;
                }
                kept = kept.min(0) - 1;
            } else {
                (lo, e_lo) = (m, e);
                if kept > 0 {
                    e_hi *= 0.5;
                }
                kept = kept.max(0) + 1;
            }
        }
        (0.5 * (lo + hi), n)
    }
}
