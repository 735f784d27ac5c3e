//! The melt's warp on lattices: the two noises that move the core surface (the sag's drips
//! and the core displacement) tabulated per frame over the field's box and read
//! trilinearly, so a sphere-tracing step far from the melted core reads the field once and
//! two lattices instead of evaluating four octaves of noise.
//!
//! Rules:
//! - Each lattice is a [`NoiseCache`] (texture space, filled on first read, a value a
//!   function of its index only: the image is the same at any thread count): the sag's
//!   noise at [`SAG_POINTS_PER_CELL`] points per cell of its finest octave along each axis
//!   (the sag multiplies its error by up to the object's size), the displacement's at
//!   `POINTS_PER_CELL`. The sag's height factor and clamp stay exact.
//! - The lattices are only a bound to step by: the core distance they give, less
//!   [`Warp::margin`] (the most their noises can be off, times what scales them), is a lower
//!   bound of the true one. Where it falls below the margin (near the core), the tracer
//!   evaluates the noises; the crossing, its refinement and the normal always do, so the
//!   surface is the one the noises give, not the lattices'.
//! - The noise errors are measured (200,000 random points, two octaves of fBm, largest
//!   difference between the trilinear lattice read and the noise): 0.087 at 4 points per
//!   cell, 0.024 at 8; the margins use 0.1 and 0.03 (in the fBm's own units).

use glam::{Mat4, Vec3};

use super::super::hyper::Hypertexture;
use super::super::noise_cache::{NoiseCache, POINTS_PER_CELL};
use crate::texture::procedural::perlin::octaves3f;

/// Octaves of the sag's drip noise.
const SAG_OCTAVES: f32 = 2.0;
/// Lattice points per cell of the sag noise's finest octave, along each axis.
const SAG_POINTS_PER_CELL: f32 = 8.0;
/// The most the sag noise read from its lattice is off (measured 0.024).
const SAG_NOISE_ERROR: f32 = 0.03;
/// The most an fBm read from a `POINTS_PER_CELL` lattice is off (measured 0.087).
const NOISE_ERROR: f32 = 0.1;

/// The melt's noises on lattices over a field's box.
pub(super) struct Warp {
    /// The sag's drip noise ([`sag_noise`]).
    sag: Option<NoiseCache>,
    /// The core displacement's noise (the hypertexture's `N`).
    displacement: Option<NoiseCache>,
    /// The most a core distance through the lattices is off, world.
    pub(super) margin: f32,
}

impl Warp {
    /// The lattices for `h` over the world box `[lo, hi]` (`texture_from_world` its texture
    /// space, `size` the object's size, `top` the box's height along the up in sizes): the
    /// sag's when `h` melts, the displacement's when it displaces the core.
    pub(super) fn new(
        h: &Hypertexture,
        texture_from_world: &Mat4,
        lo: Vec3,
        hi: Vec3,
        size: f32,
        top: f32,
    ) -> Warp {
        let (tlo, thi) = (
            texture_from_world.transform_point3(lo),
            texture_from_world.transform_point3(hi),
        );
        let finest = |octaves: f32| 2f32.powi(octaves.clamp(1.0, 32.0).ceil() as i32 - 1);
        let melts = h.melt != 0.0 && h.time != 0.0;
        let sag = melts.then(|| {
            let density = SAG_POINTS_PER_CELL * h.frequency * 0.5 * finest(SAG_OCTAVES);
            NoiseCache::new(tlo, thi, density)
        });
        let displacement = (h.core_displacement != 0.0).then(|| {
            let density = POINTS_PER_CELL * h.frequency * finest(h.octaves) * h.stretch.max(1.0);
            NoiseCache::new(tlo, thi, density)
        });
        // The sag is melt·time·height·max(1 + 1.5 n, 0)·size; the displacement
        // core_displacement·T·N with N = offset + scale·fBm (scale at most 1.2).
        let sag_margin = if melts {
            (h.melt * h.time).abs() * top.max(0.0) * 1.5 * SAG_NOISE_ERROR * size
        } else {
            0.0
        };
        let shell = h.thickness * size;
        let displacement_margin = h.core_displacement * shell * 1.2 * NOISE_ERROR;
        Warp {
            sag: sag.flatten(),
            displacement: displacement.flatten(),
            margin: sag_margin + displacement_margin,
        }
    }

    /// The sag's drip noise at texture point `t` (lattice, or direct outside it).
    #[inline(always)]
    pub(super) fn sag_noise(&self, h: &Hypertexture, up: Vec3, t: Vec3) -> f32 {
        let exact = |t: Vec3| sag_noise(h, up, t);
        self.sag
            .as_ref()
            .and_then(|c| c.read(t, exact))
            .unwrap_or_else(|| exact(t))
    }

    /// The displacement's noise at texture point `t`, `exact` evaluating it (lattice, or
    /// direct outside it).
    #[inline(always)]
    pub(super) fn displacement_noise(&self, t: Vec3, exact: impl Fn(Vec3) -> f32) -> f32 {
        match self.displacement.as_ref().and_then(|c| c.read(t, &exact)) {
            Some(n) => n,
            None => exact(t),
        }
    }
}

/// The sag's drip noise at texture point `t`: fBm across the `up` axis, slowly varying
/// along it.
#[inline(always)]
pub(super) fn sag_noise(h: &Hypertexture, up: Vec3, t: Vec3) -> f32 {
    let x = t * (h.frequency * 0.5);
    let along = x.dot(up);
    octaves3f(x - up * (along * 0.9), SAG_OCTAVES, 2.0, 0.5, false)
}
