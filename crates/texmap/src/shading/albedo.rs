//! The directional albedo of the GGX specular lobe for a white environment, `E = f0·A + B`,
//! as the table [`super::pbr::specular_albedo`] reads: 32 × 32 cells over √(N·V) and
//! roughness, each an importance-sampled estimate over 2048 points of a low-discrepancy set.
//!
//! The table is integrated ahead and committed (`albedo_table.bin`: `(A, B)` per cell, row
//! by row, little-endian `f32`): integrating it took a metallic-roughness scene's first
//! frame about 120 M instructions (a 1080p DamagedHelmet's first frame 53–55 ms against
//! 23 ms for the next), and a committed table is the same on every machine (the integration
//! calls the platform's `sin` and `cos`). The test below integrates it again and compares;
//! `TEXMAP_BLESS_ALBEDO=1 cargo test -p texmap --lib albedo` writes the file anew after a
//! change to the integration.

use std::sync::OnceLock;

use glam::Vec2;

/// The side of the table.
pub(super) const ALBEDO_N: usize = 32;

/// The committed table's bytes.
const TABLE: &[u8; ALBEDO_N * ALBEDO_N * 8] = include_bytes!("albedo_table.bin");

/// The table, `(A, B)` at `[j·N + i]` for `√(N·V) = i/(N − 1)` and roughness `j/(N − 1)`.
pub(super) fn albedo_table() -> &'static [Vec2] {
    static CELLS: OnceLock<Vec<Vec2>> = OnceLock::new();
    CELLS.get_or_init(|| {
        let f = |b: &[u8]| f32::from_le_bytes([b[0], b[1], b[2], b[3]]);
        TABLE
            .chunks_exact(8)
            .map(|c| Vec2::new(f(&c[..4]), f(&c[4..])))
            .collect()
    })
}

/// The integration the table was made by (the tests run it again).
#[cfg(test)]
pub(super) mod integration {
    use std::f32::consts::PI;

    use glam::{Vec2, Vec3};

    use super::super::pbr::{visibility, MIN_ROUGHNESS};
    use super::ALBEDO_N;

    /// The table [`albedo_table`] holds, integrated: `(A, B)` at `[j·N + i]` for
    /// `√(N·V) = i/(N − 1)` and roughness `j/(N − 1)`, each cell's estimate over 2048 samples
    /// (rows in parallel, each cell on its own: the same table at any thread count; the sample
    /// set's azimuths shared by every cell).
    pub(super) fn integrate_table() -> Vec<Vec2> {
        const N: usize = ALBEDO_N;
        use rayon::prelude::*;
        let azimuths = azimuths(2048);
        let rows: Vec<Vec<Vec2>> = (0..N)
            .into_par_iter()
            .map(|j| {
                let r = (j as f32 / (N - 1) as f32).max(MIN_ROUGHNESS);
                (0..N)
                    .map(|i| {
                        let sqrt_nv = i as f32 / (N - 1) as f32;
                        let nv = (sqrt_nv * sqrt_nv).max(1e-3);
                        let e = integrate_with(nv, r * r, &azimuths);
                        // The true albedo is at most 1; near grazing the estimate's noise is
                        // not.
                        e / (e.x + e.y).max(1.0)
                    })
                    .collect()
            })
            .collect();
        rows.concat()
    }

    /// `(A, B)` by importance-sampling the GGX distribution of half vectors with `samples`
    /// points of a 2D low-discrepancy set: for `H` with density `D·(N·H)`, the estimator of
    /// `∫ F·D·Vis·(N·L) dω_L` is `F·Vis·(N·L)·4(V·H)/(N·H)`, and `F = f0·(1 − m) + m` with
    /// `m = (1 − V·H)⁵` splits it into `A` (the `1 − m` part) and `B` (the `m` part).
    pub(in crate::shading) fn integrate_specular_albedo(
        n_dot_v: f32,
        alpha: f32,
        samples: u32,
    ) -> Vec2 {
        integrate_with(n_dot_v, alpha, &azimuths(samples))
    }

    /// `(cos φ, sin φ)` of each of `samples` points' azimuth, `φ = 2π·radical_inverse(k)`.
    fn azimuths(samples: u32) -> Vec<(f32, f32)> {
        (0..samples)
            .map(|k| {
                let phi = 2.0 * PI * radical_inverse_base2(k);
                (phi.cos(), phi.sin())
            })
            .collect()
    }

    /// The estimate of `integrate_specular_albedo` (the tests' form) over the sample set whose
    /// azimuths are `azimuths`: `(A, B)` by importance-sampling the GGX distribution of half
    /// vectors (the estimator `F·Vis·(N·L)·4(V·H)/(N·H)`, split by `m = (1 − V·H)⁵`).
    fn integrate_with(n_dot_v: f32, alpha: f32, azimuths: &[(f32, f32)]) -> Vec2 {
        let samples = azimuths.len() as u32;
        let v = Vec3::new((1.0 - n_dot_v * n_dot_v).max(0.0).sqrt(), 0.0, n_dot_v);
        let a2 = alpha * alpha;
        let mut sum = glam::DVec2::ZERO;
        for (k, &(cos_phi, sin_phi)) in azimuths.iter().enumerate() {
            let u1 = (k as f32 + 0.5) / samples as f32;
            // Invert the GGX CDF of cos θ_h; φ uniform.
            let cos_h = ((1.0 - u1) / (1.0 + (a2 - 1.0) * u1)).sqrt();
            let sin_h = (1.0 - cos_h * cos_h).max(0.0).sqrt();
            let h = Vec3::new(sin_h * cos_phi, sin_h * sin_phi, cos_h);
            let v_dot_h = v.dot(h);
            let l = h * (2.0 * v_dot_h) - v;
            let n_dot_l = l.z;
            if n_dot_l <= 0.0 || v_dot_h <= 0.0 {
                continue;
            }
            let w = visibility(n_dot_l, n_dot_v, alpha) * n_dot_l * 4.0 * v_dot_h / cos_h;
            let m = (1.0 - v_dot_h).powi(5);
            sum += glam::DVec2::new(f64::from(w * (1.0 - m)), f64::from(w * m));
        }
        (sum / f64::from(samples)).as_vec2()
    }

    /// The base-2 radical inverse of `k` (van der Corput): its bits mirrored about the point.
    fn radical_inverse_base2(k: u32) -> f32 {
        (f64::from(k.reverse_bits()) / 4_294_967_296.0) as f32
    }
}

#[cfg(test)]
mod tests {
    use super::integration::integrate_table;
    use super::*;

    #[test]
    fn the_committed_albedo_table_is_the_integration() {
        let cells = integrate_table();
        if std::env::var_os("TEXMAP_BLESS_ALBEDO").is_some() {
            let bytes: Vec<u8> = cells
                .iter()
                .flat_map(|c| [c.x.to_le_bytes(), c.y.to_le_bytes()].concat())
                .collect();
            let path = concat!(env!("CARGO_MANIFEST_DIR"), "/src/shading/albedo_table.bin");
            std::fs::write(path, bytes).unwrap();
        }
        // Within a few ulps of the integration (another platform's `sin` and `cos` may round
        // its azimuths differently).
        for (k, (&t, c)) in albedo_table().iter().zip(&cells).enumerate() {
            assert!((t - *c).abs().max_element() <= 1e-6, "cell {k}: {t} vs {c}");
        }
        assert_eq!(albedo_table().len(), ALBEDO_N * ALBEDO_N);
    }
}
