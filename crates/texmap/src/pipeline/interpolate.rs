//! Interpolate: attribute planes and their evaluation on 2×2 quads.
//!
//! Every interpolated quantity `f` is a plane in screen space, `f(x, y) = c + f_x·x + f_y·y`,
//! set up in `f64` from the snapped vertex positions and stored in `f32` relative to a tile's
//! first pixel centre (so `x, y < 64` and the `f32` rounding stays below 1e-6 relative).
//! - Perspective-correct: the planes are of `a/w` and `1/w`; per pixel `a = (a/w)/(1/w)`.
//! - Affine: the planes are of `a` itself (screen-linear).
//!
//! Depth is always screen-linear (`z_ndc` is affine in screen space).

use glam::Vec4;

use super::transform::PostVertex;
use super::{MAX_VARYINGS, SUBPIXEL_ONE};

/// A plane `c + dx·x + dy·y` with x, y in pixels from a reference pixel centre.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Plane {
    pub c: f32,
    pub dx: f32,
    pub dy: f32,
}

impl Plane {
    /// The value at pixel offset (x, y) from the reference pixel.
    #[inline(always)]
    #[must_use]
    pub fn at(&self, x: f32, y: f32) -> f32 {
        self.c + self.dx * x + self.dy * y
    }
}

/// The interpolation planes of one triangle, relative to one reference pixel.
#[derive(Clone, Debug)]
pub struct Planes {
    pub n: usize,
    pub perspective: bool,
    /// Window depth.
    pub z: Plane,
    /// 1/w (perspective) — unused when affine.
    pub q: Plane,
    pub a: [Plane; MAX_VARYINGS],
    /// Each plane's steps from a quad's first pixel to the others, `(0, dx, 0, dx)` and
    /// `(0, 0, dy, dy)`: `q`'s, then the varyings'.
    steps: [[Vec4; 2]; MAX_VARYINGS + 1],
}

struct Gradient {
    x0: f64,
    y0: f64,
    x10: f64,
    y10: f64,
    x20: f64,
    y20: f64,
    inv_area: f64,
    rx: f64,
    ry: f64,
}

impl Gradient {
    /// The gradients of triangle `v`, relative to the centre of pixel `(px, py)`.
    #[inline]
    fn new(v: [&PostVertex; 3], px: i32, py: i32) -> Self {
        let s = 1.0 / SUBPIXEL_ONE as f64;
        let p = v.map(|v| (v.sx as f64 * s, v.sy as f64 * s));
        let (x10, y10) = (p[1].0 - p[0].0, p[1].1 - p[0].1);
        let (x20, y20) = (p[2].0 - p[0].0, p[2].1 - p[0].1);
        Gradient {
            x0: p[0].0,
            y0: p[0].1,
            x10,
            y10,
            x20,
            y20,
            inv_area: 1.0 / (x10 * y20 - x20 * y10),
            rx: px as f64 + 0.5,
            ry: py as f64 + 0.5,
        }
    }

    #[inline]
    fn plane(&self, f0: f64, f1: f64, f2: f64) -> Plane {
        let (d1, d2) = (f1 - f0, f2 - f0);
        let dx = (d1 * self.y20 - d2 * self.y10) * self.inv_area;
        let dy = (d2 * self.x10 - d1 * self.x20) * self.inv_area;
        Plane {
            c: (f0 + dx * (self.rx - self.x0) + dy * (self.ry - self.y0)) as f32,
            dx: dx as f32,
            dy: dy as f32,
        }
    }
}

/// `p`'s steps from a quad's first pixel to the others (lane `j` is pixel `j`): `(0, dx, 0,
/// dx)` and `(0, 0, dy, dy)`, added in that order.
fn steps(p: &Plane) -> [Vec4; 2] {
    [
        Vec4::new(0.0, p.dx, 0.0, p.dx),
        Vec4::new(0.0, 0.0, p.dy, p.dy),
    ]
}

/// The window depth plane of triangle `v` relative to the centre of pixel `(px, py)`:
/// [`Planes::set`]'s `z`.
#[inline]
#[must_use]
pub fn depth_plane(v: [&PostVertex; 3], px: i32, py: i32) -> Plane {
    Gradient::new(v, px, py).plane(v[0].z as f64, v[1].z as f64, v[2].z as f64)
}

impl Planes {
    /// Sets up the planes of triangle `v` (any orientation, non-zero area) relative to the
    /// centre of pixel `(px, py)`, for the first `n` varyings.
    #[must_use]
    pub fn new(v: [&PostVertex; 3], n: usize, perspective: bool, px: i32, py: i32) -> Self {
        let mut planes = Planes::empty();
        planes.set(v, n, perspective, px, py);
        planes
    }

    /// Planes of nothing (every plane zero), to be [`Planes::set`].
    #[must_use]
    pub fn empty() -> Self {
        Planes {
            n: 0,
            perspective: true,
            z: Plane::default(),
            q: Plane::default(),
            a: [Plane::default(); MAX_VARYINGS],
            steps: [[Vec4::ZERO; 2]; MAX_VARYINGS + 1],
        }
    }

    /// [`Planes::new`] in place: the planes it would make, the unused varyings' planes
    /// (index `n` on) left as they were (the rasterizer sets up one triangle's planes after
    /// another in one value).
    pub fn set(&mut self, v: [&PostVertex; 3], n: usize, perspective: bool, px: i32, py: i32) {
        let g = Gradient::new(v, px, py);
        let q = v.map(|v| v.inv_w as f64);
        self.n = n;
        self.perspective = perspective;
        self.z = g.plane(v[0].z as f64, v[1].z as f64, v[2].z as f64);
        self.q = g.plane(q[0], q[1], q[2]);
        self.steps[0] = steps(&self.q);
        for i in 0..n.min(MAX_VARYINGS) {
            let f = v.map(|v| v.varyings[i] as f64);
            self.a[i] = if perspective {
                g.plane(f[0] * q[0], f[1] * q[1], f[2] * q[2])
            } else {
                g.plane(f[0], f[1], f[2])
            };
            self.steps[i + 1] = steps(&self.a[i]);
        }
    }

    /// Only the depth plane of [`Planes::set`] (the same bits), for a pass that needs
    /// nothing else; the other planes are left as they were.
    pub fn set_depth(&mut self, v: [&PostVertex; 3], px: i32, py: i32) {
        self.z = depth_plane(v, px, py);
    }

    /// Evaluates the varyings at the four pixel centres of the quad whose top-left pixel is at
    /// offset (x, y) from the reference pixel: pixel `j` (lane `j`) at
    /// `(x + (j & 1), y + (j >> 1))`.
    #[inline]
    pub fn quad(&self, x: f32, y: f32, out: &mut [Vec4; MAX_VARYINGS]) {
        // A uv set alone (textured draws lit once or unlit) with its count known: the loop
        // over a count read at run time was a third of the quad's interpolation.
        if self.n == 2 {
            self.quad_first::<2>(x, y, out);
        } else {
            self.quad_first::<MAX_VARYINGS>(x, y, out);
        }
    }

    /// [`Planes::quad`] of the first `N.min(self.n)` varyings.
    #[inline(always)]
    fn quad_first<const N: usize>(&self, x: f32, y: f32, out: &mut [Vec4; MAX_VARYINGS]) {
        // Lane j adds dx when j & 1, then dy when j >> 1 (pixel 3: (b + dx) + dy).
        let along = |p: &Plane, [sx, sy]: [Vec4; 2]| Vec4::splat(p.at(x, y)) + sx + sy;
        let n = self.n.min(N);
        let (planes, steps) = (&self.a[..n], &self.steps[1..=n]);
        if self.perspective {
            let w = Vec4::ONE / along(&self.q, self.steps[0]).max(Vec4::splat(f32::MIN_POSITIVE));
            for ((o, p), &s) in out.iter_mut().zip(planes).zip(steps) {
                *o = along(p, s) * w;
            }
        } else {
            for ((o, p), &s) in out.iter_mut().zip(planes).zip(steps) {
                *o = along(p, s);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pipeline::Viewport;

    #[test]
    fn the_depth_plane_alone_is_the_full_setups() {
        let vp = Viewport::new(100, 100);
        let mk = |x: f32, y: f32, z: f32, w: f32| {
            PostVertex::new(Vec4::new(x * w, y * w, z * w, w), [0.5; MAX_VARYINGS], &vp)
        };
        let v = [
            mk(-0.7, 0.3, 0.1, 1.0),
            mk(0.37, 0.9, 0.8, 2.5),
            mk(0.1, -0.83, -0.4, 1.7),
        ];
        let full = Planes::new([&v[0], &v[1], &v[2]], 3, true, 64, 0);
        let mut depth = Planes::empty();
        depth.set_depth([&v[0], &v[1], &v[2]], 64, 0);
        assert_eq!(depth.z, full.z);
    }

    #[test]
    fn planes_reproduce_vertex_values() {
        let vp = Viewport::new(100, 100);
        let mk = |x: f32, y: f32, w: f32, a: f32| {
            let mut var = [0.0; MAX_VARYINGS];
            var[0] = a;
            PostVertex::new(Vec4::new(x * w, y * w, 0.0, w), var, &vp)
        };
        // Vertices at pixel centres (ndc chosen so).
        let v = [
            mk(-0.99, 0.99, 1.0, 1.0),
            mk(0.97, 0.99, 3.0, 5.0),
            mk(-0.99, -0.97, 2.0, -2.0),
        ];
        let planes = Planes::new([&v[0], &v[1], &v[2]], 1, true, 0, 0);
        let mut out = [Vec4::ZERO; MAX_VARYINGS];
        planes.quad(0.0, 0.0, &mut out);
        assert!((out[0].x - 1.0).abs() < 1e-4, "{}", out[0].x);
        planes.quad(98.0, 0.0, &mut out);
        assert!((out[0].x - 5.0).abs() < 1e-4, "{}", out[0].x);
        planes.quad(0.0, 98.0, &mut out);
        assert!((out[0].x + 2.0).abs() < 1e-4, "{}", out[0].x);
    }
}
