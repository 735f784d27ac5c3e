//! The way in of a material's march ([`kind::PLAIN`]): sphere tracing from the field's box
//! to the reach, two neighbouring rays a step each in turn.
//!
//! Rules:
//! - A ray's approach is its march's first sphere-traced steps, the same reads in the same
//!   order: it stops before the first point within the reach (where the march reads again,
//!   with the gradient) or where the march would end, and the march resumes from its state
//!   ([`Start`]). The image is the march's own.
//! - Each step waits on its read (the next point depends on the distance); two rays taking
//!   a step each in turn fill each other's waits.

use glam::{Vec3, Vec4};

use super::super::super::rays::{clip_to_box, pixel_hash, Span, VoxelRay};
use super::{kind, Tracer, MAX_STEPS};

/// A march's state after its approach: where it resumes.
#[derive(Clone, Copy, Debug)]
pub(super) struct Start {
    /// The next point to read.
    pub t: f32,
    /// The last point read and its distance.
    pub t_prev: Option<f32>,
    pub e_prev: Option<f32>,
    /// The next point is the span's end.
    pub at_end: bool,
    /// Reads and steps taken.
    pub reads: u64,
    pub steps: u32,
}

/// One ray's approach.
struct Way {
    ray: VoxelRay,
    span: Span,
    start: Start,
    /// Still stepping.
    live: bool,
    /// The march ends in the approach (nothing within the reach).
    ended: bool,
}

/// Where a ray's approach left it.
pub(super) enum Approached {
    /// The march ends there: no colour, these reads.
    Ended(u64),
    /// The march resumes here.
    At(Start),
}

impl Tracer<'_> {
    /// Pixels `xs` of row `y` traced, their colours pushed onto `color` (`ray(x, y)` the
    /// pixel's `(eye, dir, t_max)`), two neighbours' ways in at a time; returns their reads.
    /// For a tracer of a plain kind, not depth-only.
    pub(super) fn trace_row(
        &self,
        y: u32,
        xs: std::ops::Range<u32>,
        color: &mut Vec<Vec4>,
        ray: impl Fn(u32, u32) -> (Vec3, Vec3, f32),
    ) -> u64 {
        let mut n = 0;
        let mut x = xs.start;
        let jitter = |x: u32| if self.jitter { pixel_hash(x, y) } else { 0.0 };
        while x + 1 < xs.end {
            let rays = [ray(x, y), ray(x + 1, y)];
            let ways = self.approach_pair(rays);
            for (k, (way, (o, d, t_max))) in ways.into_iter().zip(rays).enumerate() {
                let (c, m) = match way {
                    Approached::Ended(m) => (Vec4::ZERO, m),
                    Approached::At(s) => {
                        let r = self.trace_from(o, d, t_max, jitter(x + k as u32), Some(s));
                        (r.0, r.1)
                    }
                };
                color.push(c);
                n += m;
            }
            x += 2;
        }
        if x < xs.end {
            let (o, d, t_max) = ray(x, y);
            let (c, m, _) = self.trace(o, d, t_max, jitter(x));
            color.push(c);
            n += m;
        }
        n
    }

    /// The approaches of rays `(eye, dir, t_max)`, a step of each in turn. For a tracer of
    /// a plain kind ([`kind::PLAIN`]), not depth-only.
    pub(super) fn approach_pair(&self, rays: [(Vec3, Vec3, f32); 2]) -> [Approached; 2] {
        debug_assert!(self.kind & kind::PLAIN != 0 && !self.depth_only);
        let mut ways = rays.map(|(eye, dir, t_max)| {
            let ray = VoxelRay::new(&self.field.voxel_from_world, eye, dir);
            let span = clip_to_box(&ray, t_max, Vec3::ZERO, self.field.hi);
            let start = Start {
                t: span.map_or(0.0, |s| s.t0),
                t_prev: None,
                e_prev: None,
                at_end: false,
                reads: 0,
                steps: 0,
            };
            Way {
                ray,
                span: span.unwrap_or(Span { t0: 0.0, t1: 0.0 }),
                start,
                live: span.is_some(),
                ended: span.is_none(),
            }
        });
        while ways[0].live || ways[1].live {
            for w in &mut ways {
                if w.live {
                    self.approach_step(w);
                }
            }
        }
        ways.map(|w| {
            if w.ended {
                Approached::Ended(w.start.reads)
            } else {
                Approached::At(w.start)
            }
        })
    }

    /// One pass of the march's loop while it sphere-traces (see [`Tracer::march`]): a step
    /// towards the reach, or the way's end.
    #[inline(always)]
    fn approach_step(&self, w: &mut Way) {
        let s = &mut w.start;
        if s.steps >= MAX_STEPS {
            (w.live, w.ended) = (false, true);
            return;
        }
        let mut t = s.t;
        let mut at_end = s.at_end;
        if t > w.span.t1 {
            if at_end || s.t_prev.is_none_or(|tp| tp >= w.span.t1) {
                (w.live, w.ended) = (false, true);
                return;
            }
            t = w.span.t1;
            at_end = true;
        }
        let d = self.field.distance(w.ray.at(t));
        if d > self.reach {
            s.reads += 1;
            s.steps += 1;
            s.t_prev = Some(t);
            s.e_prev = Some(d);
            // As the march: inside a shell, no step shorter than a shell step.
            let least = if self.reach > 0.0 {
                self.step
            } else {
                self.field.voxel * 0.05
            };
            s.t = t + ((d - self.reach) * 0.9).max(least);
            s.at_end = at_end;
        } else {
            // Within the reach: the march takes this point again (its `at_end` as set).
            s.t = t;
            s.at_end = at_end;
            w.live = false;
        }
    }
}
