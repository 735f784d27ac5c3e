//! The melted core (melt, core displacement): its distance, sphere-traced with a Lipschitz
//! bound, and the placing of its crossing (bisection, false position).
//!
//! Rules:
//! - Far from the core a step crosses an empty ball of the core's distance lattice
//!   ([`super::warp`]), near it reads the noises themselves, in steps of at least ¼ voxel.
//! - A crossing of the plain field is bisected; the melted core's by false position
//!   (Illinois), whose few reads matter because each reads the noises.

use glam::{Vec3, Vec3A, Vec4};

use super::super::super::rays::{clip_to_box, VoxelRay};
use super::super::hyper::{Hypertexture, NoiseKind};
use super::warp::{self, Warp};
use super::{Tracer, BISECTIONS, MAX_STEPS, WARPED_STEP};
use std::cell::RefCell;

use crate::texture::procedural::perlin::{noise3f_x4, noise3f_x4_cached, CellsX4};

thread_local! {
    /// The noise cells of this thread's last melted-core distance with the preset's two
    /// octaves: the next one (the ray's next step, a normal's neighbour) is most often in
    /// the same cells and reuses their gradients ([`noise3f_x4_cached`]: the same bits).
    static CELLS: RefCell<CellsX4> = const { RefCell::new(CellsX4::EMPTY) };
}

/// One ray of the melted core's march ([`Tracer::march_melted`]) between its steps.
struct MeltedRay {
    eye: Vec3,
    dir: Vec3,
    eye_a: Vec3A,
    dir_a: Vec3A,
    /// The ray in voxel space: `origin + voxel_dir·t`.
    origin: Vec3A,
    voxel_dir: Vec3A,
    t: f32,
    /// The span's end.
    t1: f32,
    t_prev: Option<f32>,
    /// The core distance at `t_prev` (a ball's lower bound after a far step).
    e_prev: Option<f32>,
    at_end: bool,
    steps: u32,
    done: bool,
    acc: Vec4,
    reads: u64,
    hit_t: f32,
}

impl Tracer<'_> {
    /// [`Tracer::march`] for the melted core alone (no material, or a depth-only trace): far
    /// from it through the empty balls of `warp`, near it by its own distance, its crossing
    /// by false position. The generic march's operations on this path, in the same order
    /// (the same bits), in a loop of its own without the material's branches.
    #[inline(never)]
    pub(super) fn march_melted(
        &self,
        warp: &Warp,
        eye: Vec3,
        dir: Vec3,
        t_max: f32,
    ) -> (Vec4, u64, f32) {
        let mut r = self.melted_ray(eye, dir, t_max);
        while !r.done {
            self.melted_step(warp, &mut r);
        }
        (r.acc, r.reads, r.hit_t)
    }

    /// [`Self::march_melted`] of two rays, a step of each in turn: their chains of dependent
    /// steps are independent, so the processor overlaps them. Each ray takes the same
    /// operations as alone (the same bits).
    #[inline(never)]
    pub(super) fn march_melted_pair(
        &self,
        warp: &Warp,
        rays: [(Vec3, Vec3, f32); 2],
    ) -> [(Vec4, u64, f32); 2] {
        let [(e0, d0, m0), (e1, d1, m1)] = rays;
        let (mut a, mut b) = (self.melted_ray(e0, d0, m0), self.melted_ray(e1, d1, m1));
        while !a.done && !b.done {
            self.melted_step(warp, &mut a);
            self.melted_step(warp, &mut b);
        }
        while !a.done {
            self.melted_step(warp, &mut a);
        }
        while !b.done {
            self.melted_step(warp, &mut b);
        }
        [(a.acc, a.reads, a.hit_t), (b.acc, b.reads, b.hit_t)]
    }

    /// A melted-core ray from `eye` along the unit `dir`, stopped at `t_max`, before its
    /// first step (done when it misses the box).
    #[inline(always)]
    fn melted_ray(&self, eye: Vec3, dir: Vec3, t_max: f32) -> MeltedRay {
        let ray = VoxelRay::new(&self.field.voxel_from_world, eye, dir);
        let core = self.hyper.is_none_or(|h| h.core);
        let span = clip_to_box(&ray, t_max, Vec3::ZERO, self.field.hi)
            .filter(|_| core || !self.depth_only);
        MeltedRay {
            eye,
            dir,
            // The ray's points in lanes (per axis the same operations: the same bits).
            eye_a: eye.into(),
            dir_a: dir.into(),
            origin: ray.origin.into(),
            voxel_dir: ray.dir.into(),
            t: span.map_or(0.0, |s| s.t0),
            t1: span.map_or(0.0, |s| s.t1),
            t_prev: None,
            e_prev: None,
            at_end: false,
            steps: 0,
            done: span.is_none(),
            acc: Vec4::ZERO,
            reads: 0,
            hit_t: f32::INFINITY,
        }
    }

    /// One step of a melted-core ray (the generic march's loop body on this path).
    #[inline(always)]
    fn melted_step(&self, warp: &Warp, r: &mut MeltedRay) {
        if r.steps == MAX_STEPS {
            r.done = true;
            return;
        }
        r.steps += 1;
        if r.t > r.t1 {
            // The last sample sits on the span's end, as in the generic march.
            if r.at_end || r.t_prev.is_none_or(|tp| tp >= r.t1) {
                r.done = true;
                return;
            }
            r.t = r.t1;
            r.at_end = true;
        }
        let t = r.t;
        let q = r.origin + r.voxel_dir * t;
        let p = r.eye_a + r.dir_a * t;
        let warped_step = self.field.voxel * WARPED_STEP;
        if let Some(b) = warp.ball_step(p, q, r.dir_a, warped_step, self.lipschitz, |c| {
            self.core_distance(c)
        }) {
            r.t_prev = Some(t);
            r.e_prev = Some(b.lower);
            r.t += b.advance;
            return;
        }
        let e = self.core_step_distance(p.into());
        r.reads += 1;
        if e <= 0.0 {
            let (hit, acc, n) = self.core_crossing(r.eye, r.dir, (r.t_prev, r.e_prev), (t, e));
            (r.hit_t, r.acc) = (hit, acc);
            r.reads += n;
            r.done = true;
            return;
        }
        r.t_prev = Some(t);
        r.e_prev = Some(e);
        r.t += (e * 0.9 / self.lipschitz).max(warped_step);
    }

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
        // Drips: noise across the up axis, slowly varying along it.
        let n = warp::sag_noise(h, self.up, self.texture_from_world.transform_point3(p));
        self.sag_from_noise(h, p, n)
    }

    /// The sag at `p` whose drip noise is `n`.
    #[inline(always)]
    fn sag_from_noise(&self, h: &Hypertexture, p: Vec3, n: f32) -> Vec3 {
        let height = ((p.dot(self.up) - self.base) / self.size).max(0.0);
        self.up * (h.melt * h.time * height * (1.0 + 1.5 * n).max(0.0) * self.size)
    }

    /// The distance to the core surface (melted and displaced), world.
    #[inline]
    pub(super) fn core_distance(&self, p: Vec3) -> f32 {
        let Some(h) = self.hyper.filter(|_| self.warped) else {
            return self
                .field
                .distance(self.field.voxel_from_world.transform_point3(p));
        };
        let (sag, n) = self.sag_and_noise(h, p, h.core_displacement != 0.0);
        let pm = p + sag;
        let d = self
            .field
            .distance(self.field.voxel_from_world.transform_point3(pm));
        if h.core_displacement == 0.0 {
            d
        } else {
            d - h.core_displacement * self.shell * n
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
        // The displacement's noise comes with the sag's in the same lanes (nearly free).
        let (sag, n) = self.sag_and_noise(h, p, true);
        let pm = p + sag;
        let d = self
            .field
            .distance(self.field.voxel_from_world.transform_point3(pm));
        // The noise is in [0, 1]: the displacement is at most this.
        let most = h.core_displacement.max(0.0) * self.shell;
        if h.core_displacement > 0.0 && d - most > 4.0 * most {
            d - most
        } else {
            d - h.core_displacement * self.shell * n
        }
    }

    /// [`Self::sag`] at `p` and, when `with_noise`, [`Self::noise`] there (else 0): their
    /// octaves of `noise3f` evaluated four at a time ([`noise3f_x4`]), each summed in the
    /// scalar functions' order, so both are the same bits as theirs.
    #[inline]
    pub(super) fn sag_and_noise(&self, h: &Hypertexture, p: Vec3, with_noise: bool) -> (Vec3, f32) {
        const MOST: usize = 8;
        let t = self.texture_from_world.transform_point3(p);
        let sagging = h.melt != 0.0 && h.time != 0.0;
        if sagging && with_noise {
            if let Some(w1) = two_octaves(h.octaves) {
                return self.sag_and_two_octaves(h, p, t, w1);
            }
        }
        let mut pts = [Vec3::ZERO; MOST];
        let mut n = 0;
        if sagging {
            let (a, b) = warp::sag_points(h, self.up, t);
            pts[0] = a;
            pts[1] = b;
            n = 2;
        }
        // The noise's octaves as `noise_above_texture` takes them (no floor: all of them).
        let octaves = h.octaves.clamp(0.0, 32.0);
        let whole = octaves.floor() as u32;
        let mut weights = [0.0f32; MOST];
        let first = n;
        if with_noise {
            let x = t * h.frequency;
            let up = self.up;
            let x = x + up * (x.dot(up) * (h.stretch - 1.0) - h.rise * h.time);
            let (mut amp, mut freq) = (1.0f32, 1.0f32);
            let mut i = 0;
            loop {
                let weight = if i < whole {
                    amp
                } else {
                    (octaves - whole as f32) * amp
                };
                if weight == 0.0 {
                    break;
                }
                if n == MOST {
                    // More octaves than lanes set aside: the scalar functions.
                    return (self.sag(h, p), self.noise(h, p));
                }
                pts[n] = x * freq;
                weights[n] = weight;
                n += 1;
                amp *= 0.5;
                freq *= 2.0;
                if i == whole {
                    break;
                }
                i += 1;
            }
        }
        let mut values = [0.0f32; MOST];
        for k in (0..n).step_by(4) {
            let lane =
                |c: fn(&Vec3) -> f32| Vec4::from_array(std::array::from_fn(|j| c(&pts[k + j])));
            let v = noise3f_x4(lane(|q| q.x), lane(|q| q.y), lane(|q| q.z));
            values[k..k + 4].copy_from_slice(&v.to_array());
        }
        let sag = if sagging {
            let mut sum = 0.0f32;
            sum += values[0];
            sum += 0.5 * values[1];
            self.sag_from_noise(h, p, sum)
        } else {
            Vec3::ZERO
        };
        if !with_noise {
            return (sag, 0.0);
        }
        let absolute = h.noise == NoiseKind::Turbulence;
        let (offset, scale) = if absolute { (0.0, 1.2) } else { (0.5, 0.7) };
        let mut sum = 0.0f32;
        for k in first..n {
            let v = values[k];
            sum += weights[k] * if absolute { v.abs() } else { v };
        }
        (sag, (offset + scale * sum).clamp(0.0, 1.0))
    }

    /// [`Self::sag_and_noise`] when sagging with a noise of two octaves (the melt preset's):
    /// the four octaves in one [`noise3f_x4_cached`] call straight from their points (the
    /// thread's last cells reused), each sum in the same order (the same bits). `t` is `p` in texture space, `w1` the second noise
    /// octave's weight.
    #[inline(always)]
    fn sag_and_two_octaves(&self, h: &Hypertexture, p: Vec3, t: Vec3, w1: f32) -> (Vec3, f32) {
        let (s0, s1) = warp::sag_points(h, self.up, t);
        let x = t * h.frequency;
        let up = self.up;
        let x = x + up * (x.dot(up) * (h.stretch - 1.0) - h.rise * h.time);
        // The octaves at frequency 1 and 2, as the general loop's `x * freq`.
        let (o0, o1) = (x * 1.0, x * 2.0);
        let v = CELLS.with(|cells| {
            noise3f_x4_cached(
                Vec4::new(s0.x, s1.x, o0.x, o1.x),
                Vec4::new(s0.y, s1.y, o0.y, o1.y),
                Vec4::new(s0.z, s1.z, o0.z, o1.z),
                &mut cells.borrow_mut(),
            )
        });
        let mut sag = 0.0f32;
        sag += v.x;
        sag += 0.5 * v.y;
        let sag = self.sag_from_noise(h, p, sag);
        let absolute = h.noise == NoiseKind::Turbulence;
        let (offset, scale) = if absolute { (0.0, 1.2) } else { (0.5, 0.7) };
        let term = |v: f32| if absolute { v.abs() } else { v };
        let mut sum = 0.0f32;
        sum += 1.0 * term(v.z);
        sum += w1 * term(v.w);
        (sag, (offset + scale * sum).clamp(0.0, 1.0))
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

/// The second octave's weight when `octaves` (as the noise loops clamp and take it) gives
/// exactly two octaves (weights 1 and this), else `None`.
#[inline(always)]
fn two_octaves(octaves: f32) -> Option<f32> {
    let octaves = octaves.clamp(0.0, 32.0);
    let whole = octaves.floor();
    let frac = octaves - whole;
    if whole == 2.0 && frac == 0.0 {
        Some(0.5)
    } else if whole == 1.0 && frac > 0.0 {
        Some(frac * 0.5)
    } else {
        None
    }
}
