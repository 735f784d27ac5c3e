//! A frame's hypertexture noise tabulated on a lattice over the field's box and read
//! trilinearly: the shell march's samples of fire and smoke read 8 stored values instead of
//! evaluating three octaves of noise each (a miss evaluates the noise at the lattice point
//! and stores it).
//!
//! Rules:
//! - The lattice is in texture space (the box centred, its largest side 1), `POINTS_PER_CELL`
//!   points per cell of the finest octave's noise lattice along each axis, so the trilinear
//!   read follows the finest octave closely (measured: ≥ 40 dB against the direct noise on
//!   the presets' images, README's hypertexture section). The points per unit may differ by
//!   axis: the noise squeezed along the screen's up (fire's flames) changes more slowly
//!   along it, and needs fewer points there.
//! - Filled lazily, in parallel: a value is a function of its lattice index alone, so which
//!   thread stores it first (both compute the same bits) does not change the image; the
//!   image is the same whatever the number of threads.
//! - Made per frame (the noise drifts with time); not made when the lattice would exceed
//!   `MAX_POINTS` (then the noise is evaluated directly).

use std::sync::atomic::{AtomicU32, Ordering};

use glam::{Vec3, Vec3A, Vec4};

use super::super::cell::XPairs;

/// Lattice points per cell of the finest noise octave, along each axis.
pub(super) const POINTS_PER_CELL: f32 = 4.0;
/// The largest lattice made (16 MB of values).
const MAX_POINTS: usize = 1 << 22;
/// An empty entry (a NaN no noise value has).
const EMPTY: u32 = u32::MAX;

/// The noise `N ∈ [0, 1]` on a lattice over a box in texture space.
pub(super) struct NoiseCache {
    /// The lattice's first point, texture space.
    origin: Vec3,
    /// Lattice points per texture unit, along each axis.
    density: Vec3,
    /// Points per axis.
    dims: [usize; 3],
    /// The last point's index along each axis (`dims − 1`), as floats.
    last: Vec3,
    /// `f32` bits, [`EMPTY`] until read.
    values: Vec<AtomicU32>,
}

impl NoiseCache {
    /// A lattice over the texture-space box `[lo, hi]` with `density` points per unit along
    /// each axis, or `None` when it would exceed [`MAX_POINTS`].
    pub(super) fn new(lo: Vec3, hi: Vec3, density: Vec3) -> Option<NoiseCache> {
        if !(density.is_finite() && density.cmpgt(Vec3::ZERO).all()) {
            return None;
        }
        let ext = (hi - lo).max(Vec3::ZERO) * density;
        let dims = ext.to_array().map(|e| e.ceil() as usize + 2);
        let n = dims.iter().try_fold(1usize, |a, &d| a.checked_mul(d))?;
        if n > MAX_POINTS {
            return None;
        }
        Some(NoiseCache {
            origin: lo,
            density,
            dims,
            last: Vec3::from_array(dims.map(|d| (d - 1) as f32)),
            values: (0..n).map(|_| AtomicU32::new(EMPTY)).collect(),
        })
    }

    /// The noise at texture point `x` read trilinearly, `noise` evaluating it at lattice
    /// points not yet stored; `None` outside the lattice.
    #[cfg(test)]
    pub(super) fn read(&self, x: Vec3, noise: impl Fn(Vec3) -> f32) -> Option<f32> {
        self.read_lattice(self.lattice_point(x), noise)
    }

    /// Texture point `x` in lattice coordinates (the lattice's points at whole numbers).
    #[inline(always)]
    pub(super) fn lattice_point(&self, x: Vec3) -> Vec3A {
        Vec3A::from((x - self.origin) * self.density)
    }

    /// A texture-space direction `v` in lattice units: a ray's lattice coordinates are
    /// `lattice_point(o) + lattice_vector(v) · t`.
    #[inline(always)]
    pub(super) fn lattice_vector(&self, v: Vec3) -> Vec3A {
        Vec3A::from(v * self.density)
    }

    /// [`Self::read`] at lattice coordinates `qa` ([`Self::lattice_point`]).
    #[inline(always)]
    pub(super) fn read_lattice(&self, qa: Vec3A, noise: impl Fn(Vec3) -> f32) -> Option<f32> {
        let [nx, ny, _] = self.dims;
        // The six bounds in lanes (one mask test; NaN fails as before).
        if !(qa.cmpge(Vec3A::ZERO) & qa.cmplt(Vec3A::from(self.last))).all() {
            return None;
        }
        let q = Vec3::from(qa);
        let c = q.floor();
        let f = q - c;
        // SAFETY: in range and not negative (checked above, NaN failing the checks): the
        // truncations need none of `as`'s saturation.
        let whole = |v: f32| unsafe { v.to_int_unchecked::<u32>() } as usize;
        let (cx, cy, cz) = (whole(c.x), whole(c.y), whole(c.z));
        let base = cx + nx * (cy + ny * cz);
        let (sy, sz) = (nx, nx * ny);
        // Corner k's offset: +1 along x for odd k, +sy for k & 2, +sz for k & 4.
        let corners = &self.values[base..=base + sz + sy + 1];
        // SAFETY: every offset is at most `sz + sy + 1`, the slice's last index.
        let load = |o: usize| unsafe { corners.get_unchecked(o) }.load(Ordering::Relaxed);
        let offsets = [0, 1, sy, sy + 1, sz, sz + 1, sz + sy, sz + sy + 1];
        let mut bits = offsets.map(load);
        // One test for the eight (all stored, after the lattice's first reads), without a
        // branch per corner.
        if bits.iter().fold(false, |any, &b| any | (b == EMPTY)) {
            bits = self.fill_missing([cx, cy, cz], bits, &noise);
        }
        // The pairs straight from the loaded values (an array built in memory and read
        // back in lanes stalls on the store forwarding).
        let v = |k: usize| f32::from_bits(bits[k]);
        let lo = Vec4::new(v(0), v(2), v(4), v(6));
        let hi = Vec4::new(v(1), v(3), v(5), v(7));
        Some(XPairs::from_ends(lo, hi).blend(f))
    }

    /// `bits` (the corners of the cell whose first corner is lattice point `cell`) with the
    /// missing ones evaluated and stored.
    #[cold]
    #[inline(never)]
    fn fill_missing(
        &self,
        cell: [usize; 3],
        mut bits: [u32; 8],
        noise: &impl Fn(Vec3) -> f32,
    ) -> [u32; 8] {
        for (k, b) in bits.iter_mut().enumerate() {
            if *b == EMPTY {
                let corner = [
                    cell[0] + (k & 1),
                    cell[1] + ((k >> 1) & 1),
                    cell[2] + (k >> 2),
                ];
                *b = self.fill(corner, noise).to_bits();
            }
        }
        bits
    }

    /// Evaluates and stores the noise at lattice point `[a, b, c]` (a miss; its index from
    /// its coordinates, not the other way: no integer division).
    #[cold]
    #[inline(never)]
    fn fill(&self, [a, b, c]: [usize; 3], noise: &impl Fn(Vec3) -> f32) -> f32 {
        let [nx, ny, _] = self.dims;
        let p = self.origin + Vec3::new(a as f32, b as f32, c as f32) / self.density;
        let v = noise(p);
        self.values[a + nx * (b + ny * c)].store(v.to_bits(), Ordering::Relaxed);
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lattice_points_read_back_exactly_and_between_them_linearly() {
        let cache =
            NoiseCache::new(Vec3::splat(-0.5), Vec3::splat(0.5), Vec3::splat(8.0)).expect("small");
        let f = |p: Vec3| 0.25 + 0.5 * p.x - 0.125 * p.y + 0.0625 * p.z;
        for p in [
            Vec3::new(-0.5, -0.5, -0.5),
            Vec3::new(0.125, -0.25, 0.375),
            Vec3::new(0.03, 0.41, -0.27),
        ] {
            let v = cache.read(p, f).expect("inside");
            // A linear function is reproduced by trilinear interpolation.
            assert!((v - f(p)).abs() < 1e-5, "{p}: {v} vs {}", f(p));
        }
        assert!(cache.read(Vec3::splat(2.0), f).is_none());
        assert!(cache.read(Vec3::splat(-0.6), f).is_none());
    }

    #[test]
    fn a_lattice_spaced_per_axis_reads_linearly_and_sizes_by_axis() {
        let density = Vec3::new(8.0, 3.5, 8.0);
        let cache = NoiseCache::new(Vec3::splat(-0.5), Vec3::splat(0.5), density).expect("small");
        // ceil(extent · density) + 2 points along each axis.
        assert_eq!(cache.dims, [10, 6, 10]);
        let f = |p: Vec3| 0.25 + 0.5 * p.x - 0.125 * p.y + 0.0625 * p.z;
        for p in [Vec3::new(0.125, -0.3, 0.375), Vec3::new(-0.41, 0.29, 0.03)] {
            let v = cache.read(p, f).expect("inside");
            assert!((v - f(p)).abs() < 1e-5, "{p}: {v} vs {}", f(p));
        }
    }

    #[test]
    fn a_rays_lattice_coordinates_read_as_its_points() {
        let cache = NoiseCache::new(
            Vec3::splat(-0.5),
            Vec3::splat(0.5),
            Vec3::new(8.0, 5.0, 8.0),
        )
        .expect("small");
        let f = |p: Vec3| 0.25 + 0.5 * p.x - 0.125 * p.y + 0.0625 * p.z;
        let (o, v) = (Vec3::new(-0.9, 0.2, -0.7), Vec3::new(0.6, -0.2, 0.5));
        let (lo, lv) = (cache.lattice_point(o), cache.lattice_vector(v));
        for t in [0.8, 1.0, 1.3, 1.7] {
            let by_ray = cache.read_lattice(lo + lv * t, f).expect("inside");
            let by_point = cache.read(o + v * t, f).expect("inside");
            assert!(
                (by_ray - by_point).abs() < 1e-5,
                "t {t}: {by_ray} vs {by_point}"
            );
        }
    }

    #[test]
    fn an_oversized_lattice_is_not_made() {
        assert!(NoiseCache::new(Vec3::ZERO, Vec3::ONE, Vec3::splat(1000.0)).is_none());
        assert!(NoiseCache::new(Vec3::ZERO, Vec3::ONE, Vec3::splat(f32::NAN)).is_none());
    }
}
