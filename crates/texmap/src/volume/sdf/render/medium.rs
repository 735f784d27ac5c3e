//! The hypertexture's material inside the shell: its noise, density and colour at a
//! sample.
//!
//! Rules:
//! - The density (Perlin & Hoffert): the height `d / T` in the shell against the noise's
//!   reach `A · N`, over the softness, shaped by bias and gain (tabulated).
//! - The octaves stop early once the sum so far and a bound on the rest show the noise
//!   cannot reach the sample's height: no material there, whatever the finer octaves.
//! - Where the frame's noise lattice covers the sample, the noise is read from it.

use glam::{Vec3, Vec3A};

use super::super::hyper::{Hypertexture, NoiseKind};
use super::kind::{self, flag};
use super::{Tracer, SHAPE_LUT};
use crate::texture::procedural::perlin::{noise3f, NOISE_BOUND};

impl Tracer<'_> {
    /// The hypertexture's noise at world point `p`, in `[0, 1]`.
    #[inline(always)]
    pub(super) fn noise(&self, h: &Hypertexture, p: Vec3) -> f32 {
        self.noise_above(h, p, f32::NEG_INFINITY).unwrap_or(0.0)
    }

    /// [`Self::noise`] when it may exceed `floor`; `None` once the octaves summed so far and
    /// a bound on the rest (each octave's weight × [`NOISE_BOUND`]) show it cannot. The sum
    /// is `octaves3f`'s, term by term in the same order, so a value returned is the same.
    #[inline(always)]
    fn noise_above(&self, h: &Hypertexture, p: Vec3, floor: f32) -> Option<f32> {
        self.noise_above_texture(h, self.texture_from_world.transform_point3(p), floor)
    }

    /// [`Self::noise_above`] at texture-space point `t`.
    #[inline(always)]
    pub(super) fn noise_above_texture(&self, h: &Hypertexture, t: Vec3, floor: f32) -> Option<f32> {
        let x = t * h.frequency;
        let up = self.up;
        let x = x + up * (x.dot(up) * (h.stretch - 1.0) - h.rise * h.time);
        let absolute = h.noise == NoiseKind::Turbulence;
        let (offset, scale) = if absolute { (0.0, 1.2) } else { (0.5, 0.7) };
        // N = offset + scale · S ≤ floor  ⇔  S ≤ (floor − offset) / scale.
        let s_floor = (floor - offset) / scale;
        let octaves = h.octaves.clamp(0.0, 32.0);
        let whole = octaves.floor() as u32;
        let (mut sum, mut amp, mut freq) = (0.0f32, 1.0f32, 1.0f32);
        let mut rest = self.noise_weight * NOISE_BOUND;
        // `0..=whole` by hand: the inclusive range's end flag costs more than the octave.
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
            let q = x * freq;
            let n = noise3f(q.x, q.y, q.z);
            sum += weight * if absolute { n.abs() } else { n };
            amp *= 0.5;
            freq *= 2.0;
            rest -= weight * NOISE_BOUND;
            if sum + rest < s_floor {
                return None;
            }
            if i == whole {
                break;
            }
            i += 1;
        }
        Some((offset + scale * sum).clamp(0.0, 1.0))
    }

    /// The density at world point `p` with field distance `d` and gradient `g`, in `[0, 1]`,
    /// its ramp value `u` and its entry in the tables (`shape`, `alpha`). `lat`, when given,
    /// is `p` in the noise lattice's coordinates (a ray's, [`Tracer::lattice_ray`]).
    #[inline(always)]
    fn density<const K: u8>(
        &self,
        h: &Hypertexture,
        p: Vec3,
        d: f32,
        g: impl Fn() -> Vec3,
        lat: Option<Vec3A>,
    ) -> (f32, f32, usize) {
        // A plain march ([`kind::PLAIN`]) has material and no melt.
        let plain = K & kind::PLAIN != 0;
        if !plain && (h.amplitude == 0.0 || h.opacity == 0.0) {
            return (0.0, 0.0, 0);
        }
        let d = if !plain && h.melt != 0.0 {
            let pm = p + self.sag(h, p);
            self.field
                .distance(self.field.voxel_from_world.transform_point3(pm))
        } else {
            d
        };
        let height = d / self.shell;
        if height >= h.amplitude {
            return (0.0, 0.0, 0);
        }
        let at = if flag::<K>(kind::STRANDS, h.strands) {
            p - g().try_normalize().unwrap_or(Vec3::ZERO) * d
        } else {
            p
        };
        // The frame's lattice of the noise where there is one; otherwise the noise itself,
        // and no material where it cannot reach this height (its finer octaves skipped).
        let lattice = if flag::<K>(kind::LATTICE, true) {
            self.noise_cache.as_ref()
        } else {
            None
        };
        // (Without strands `at` is `p`, so a ray's lattice coordinates are `at`'s.)
        let cached = lattice.and_then(|c| {
            let q = match lat.filter(|_| !flag::<K>(kind::STRANDS, h.strands)) {
                Some(q) => q,
                None => c.lattice_point(self.texture_from_world.transform_point3(at)),
            };
            c.read_lattice(q, |t| {
                self.noise_above_texture(h, t, f32::NEG_INFINITY)
                    .unwrap_or(0.0)
            })
        });
        let n = match cached {
            Some(n) => n,
            None => match self.noise_above(h, at, height.max(0.0) / h.amplitude) {
                Some(n) => n,
                None => return (0.0, 0.0, 0),
            },
        };
        // The sign first (softness > 0): most samples stop here, before the division.
        let reach = h.amplitude * n - height.max(0.0);
        if reach <= 0.0 {
            return (0.0, 0.0, 0);
        }
        let u = reach / h.softness;
        if u <= 0.0 {
            return (0.0, 0.0, 0);
        }
        // SAFETY: `u > 0` or NaN here, and `min` gives 1 for NaN: the product is in
        // `(0, SHAPE_LUT]`, which needs none of `as`'s saturation.
        let i = unsafe { (u.min(1.0) * SHAPE_LUT as f32).to_int_unchecked::<usize>() };
        (self.shape[i], u.min(1.0), i)
    }

    /// The material at one sample: its colour, opacity over the step, and the reads taken
    /// (`lat` as [`Self::density`]'s).
    pub(super) fn material<const K: u8>(
        &self,
        h: &Hypertexture,
        p: Vec3,
        d: f32,
        g: impl Fn() -> Vec3,
        dir: Vec3,
        lat: Option<Vec3A>,
    ) -> (Vec3, f32, u64) {
        // The gradient read once, where the strands or the lighting first need it.
        let memo = std::cell::Cell::new(None::<Vec3>);
        let g = || match memo.get() {
            Some(v) => v,
            None => {
                let v = g();
                memo.set(Some(v));
                v
            }
        };
        let (dens, u, i) = self.density::<K>(h, p, d, g, lat);
        if dens <= 0.0 {
            return (Vec3::ZERO, 0.0, 0);
        }
        let a = self.alpha[i];
        let ramp = h.outer.lerp(h.inner, u);
        if flag::<K>(kind::GLOW, h.emission > 0.0) {
            return (ramp * h.emission, a, 0);
        }
        let lit = self.lit(ramp, g(), dir, p);
        if K & kind::PLAIN != 0 || !(h.shadows && self.has_lights) {
            return (lit, a, 0);
        }
        // Self-shadowing: the material between the sample and the first light.
        let Some((l, _)) = self
            .light_list
            .iter()
            .find_map(|li| li.normalized().and_then(|li| li.incidence(p)))
        else {
            return (lit, a, 0);
        };
        let steps = 4;
        let ds = (h.amplitude * self.shell).max(self.step) / steps as f32;
        let mut tau = 0.0;
        for k in 1..=steps {
            let ps = p + l * (ds * k as f32);
            let qs = self.field.voxel_from_world.transform_point3(ps);
            let (dd, gg) = self.field.distance_and_gradient(qs);
            if dd <= 0.0 {
                tau = f32::INFINITY;
                break;
            }
            tau += h.opacity * self.density::<K>(h, ps, dd, || gg, None).0 * ds / self.shell;
        }
        let ambient = ramp * 0.2;
        (
            ambient + (lit - ambient).max(Vec3::ZERO) * (-tau).exp(),
            a,
            steps,
        )
    }
}
