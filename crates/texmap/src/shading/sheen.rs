//! The sheen lobe of `KHR_materials_sheen` (the extension's appendix): the "Charlie"
//! distribution of Estevez and Kulla, their visibility term, and the lobe's directional
//! albedo `E(N·V, r)` that scales the base material beneath it.
//!
//! ```text
//! α = r²           D(N·H) = (2 + 1/α)·sin(θ_h)^(1/α) / 2π
//! V = 1 / ((1 + Λ(N·V) + Λ(N·L))·4·N·V·N·L)            (clamped to [0, 1])
//! f_sheen = sheen_colour · D · V
//! base scaled by 1 − max(sheen_colour)·E(N·V, r)       (the albedo scaling)
//! ```
//!
//! `Λ` is the extension's fitted curve. `E` is read from a 16 × 16 table over N·V and r,
//! integrated ahead and committed (`sheen_albedo.bin`, like [`super::pbr::specular_albedo`]'s).

use std::f32::consts::PI;
use std::sync::OnceLock;

use glam::Vec3;

/// The smallest sheen roughness used (α = r² stays above 0), as the specification's viewer.
pub const MIN_SHEEN_ROUGHNESS: f32 = 0.07;

/// The Charlie distribution `D(N·H)` at sheen roughness `r`.
#[inline]
#[must_use]
pub fn distribution(n_dot_h: f32, r: f32) -> f32 {
    let r = r.clamp(MIN_SHEEN_ROUGHNESS, 1.0);
    let inv_alpha = 1.0 / (r * r);
    let sin2 = (1.0 - n_dot_h * n_dot_h).max(0.0);
    (2.0 + inv_alpha) * sin2.powf(0.5 * inv_alpha) / (2.0 * PI)
}

/// The fitted curve `L(x)` of the sheen visibility (the extension's appendix).
fn l(x: f32, r: f32) -> f32 {
    let t = (1.0 - r) * (1.0 - r);
    let mix = |a: f32, b: f32| a + (b - a) * t;
    let (a, b, c, d, e) = (
        mix(21.5473, 25.3245),
        mix(3.82987, 3.32435),
        mix(0.19823, 0.16801),
        mix(-1.97760, -1.27393),
        mix(-4.32054, -4.85967),
    );
    a / (1.0 + b * x.powf(c)) + d * x + e
}

/// `Λ(cos θ)` of the sheen visibility.
fn lambda(cos_theta: f32, r: f32) -> f32 {
    if cos_theta < 0.5 {
        l(cos_theta, r).exp()
    } else {
        (2.0 * l(0.5, r) - l(1.0 - cos_theta, r)).exp()
    }
}

/// The sheen visibility `V(N·L, N·V)` at sheen roughness `r`.
#[inline]
#[must_use]
pub fn visibility(n_dot_l: f32, n_dot_v: f32, r: f32) -> f32 {
    let r = r.clamp(MIN_SHEEN_ROUGHNESS, 1.0);
    let denom = (1.0 + lambda(n_dot_v, r) + lambda(n_dot_l, r)) * 4.0 * n_dot_v * n_dot_l;
    if denom > 0.0 {
        (1.0 / denom).clamp(0.0, 1.0)
    } else {
        0.0
    }
}

/// The sheen BRDF times π·N·L (texmap's light units, see [`super::pbr`]) for a white sheen
/// colour, at unit `n`, `v`, `l`.
#[inline]
#[must_use]
pub fn lobe(n: Vec3, v: Vec3, l: Vec3, r: f32) -> f32 {
    let (n_dot_l, n_dot_v) = (n.dot(l), n.dot(v).max(1e-4));
    if n_dot_l <= 0.0 {
        return 0.0;
    }
    let h = (l + v).normalize_or_zero();
    PI * distribution(n.dot(h).max(0.0), r) * visibility(n_dot_l, n_dot_v, r) * n_dot_l
}

/// The side of [`albedo`]'s table.
const N: usize = 16;

/// The committed table: `E` at `[j·N + i]` for N·V = `i/(N − 1)` and r = `j/(N − 1)`,
/// little-endian `f32` (integrated ahead by [`integrate_table`]: a million evaluations of
/// the lobe with the platform's `sin` and `cos`, once a sheen scene's first frame; the test
/// below integrates it again, `TEXMAP_BLESS_ALBEDO=1` rewrites it).
const TABLE: &[u8; N * N * 4] = include_bytes!("sheen_albedo.bin");

/// The directional albedo `E(N·V, r)` of a white sheen lobe (bilinear in a 16 × 16 table
/// over N·V and r).
#[must_use]
pub fn albedo(n_dot_v: f32, r: f32) -> f32 {
    let table = cells();
    let x = n_dot_v.clamp(0.0, 1.0) * (N - 1) as f32;
    let y = r.clamp(0.0, 1.0) * (N - 1) as f32;
    let (i, j) = ((x as usize).min(N - 2), (y as usize).min(N - 2));
    let (fx, fy) = (x - i as f32, y - j as f32);
    let at = |i: usize, j: usize| table[j * N + i];
    let top = at(i, j) + (at(i + 1, j) - at(i, j)) * fx;
    let bottom = at(i, j + 1) + (at(i + 1, j + 1) - at(i, j + 1)) * fx;
    top + (bottom - top) * fy
}

/// The committed table's cells.
fn cells() -> &'static [f32] {
    static CELLS: OnceLock<Vec<f32>> = OnceLock::new();
    CELLS.get_or_init(|| {
        TABLE
            .chunks_exact(4)
            .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .collect()
    })
}

/// The table [`albedo`] reads, integrated (32 × 128 cells each).
#[cfg(test)]
fn integrate_table() -> Vec<f32> {
    let mut t = Vec::with_capacity(N * N);
    for j in 0..N {
        for i in 0..N {
            let nv = (i as f32 / (N - 1) as f32).max(1e-3);
            let r = j as f32 / (N - 1) as f32;
            t.push(integrate_albedo(nv, r, 32).min(1.0));
        }
    }
    t
}

/// `∫ D·V·(N·L) dω_L` over the hemisphere by the midpoint rule on `n × 4n` cells in
/// (cos θ, φ): the lobe is smooth and broad, so a plain grid converges fast.
#[cfg(test)]
fn integrate_albedo(n_dot_v: f32, r: f32, n: usize) -> f32 {
    let v = Vec3::new((1.0 - n_dot_v * n_dot_v).max(0.0).sqrt(), 0.0, n_dot_v);
    let (nt, np) = (n, 4 * n);
    let mut sum = 0.0f64;
    for i in 0..nt {
        let cos_t = (i as f32 + 0.5) / nt as f32;
        let sin_t = (1.0 - cos_t * cos_t).sqrt();
        for k in 0..np {
            let phi = (k as f32 + 0.5) / np as f32 * std::f32::consts::TAU;
            let l = Vec3::new(sin_t * phi.cos(), sin_t * phi.sin(), cos_t);
            let h = (l + v).normalize_or_zero();
            let f = distribution(h.z.max(0.0), r) * visibility(cos_t, n_dot_v, r) * cos_t;
            sum += f64::from(f);
        }
    }
    // dω = d(cos θ)·dφ.
    (sum * (1.0 / nt as f64) * (std::f64::consts::TAU / np as f64)) as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_distribution_is_normalised() {
        // ∫ D(h)·(N·H) dω_h = 1 over the hemisphere, for every roughness.
        for r in [0.1f32, 0.3, 0.6, 1.0] {
            let n = 2000;
            let mut sum = 0.0f64;
            for i in 0..n {
                let cos_h = (i as f32 + 0.5) / n as f32;
                sum += f64::from(distribution(cos_h, r) * cos_h) / n as f64;
            }
            let integral = sum * std::f64::consts::TAU;
            assert!((integral - 1.0).abs() < 0.01, "r {r}: {integral}");
        }
    }

    #[test]
    fn the_committed_sheen_albedo_table_is_the_integration() {
        let cells = integrate_table();
        if std::env::var_os("TEXMAP_BLESS_ALBEDO").is_some() {
            let bytes: Vec<u8> = cells.iter().flat_map(|c| c.to_le_bytes()).collect();
            let path = concat!(env!("CARGO_MANIFEST_DIR"), "/src/shading/sheen_albedo.bin");
            std::fs::write(path, bytes).unwrap();
        }
        // Within a few ulps (another platform's `sin` and `cos` may round differently).
        assert_eq!(super::cells().len(), cells.len());
        for (k, (t, c)) in super::cells().iter().zip(&cells).enumerate() {
            assert!((t - c).abs() <= 1e-6, "cell {k}: {t} vs {c}");
        }
    }

    #[test]
    fn albedo_is_bounded_grows_with_roughness_and_matches_a_finer_integration() {
        for r in [0.0f32, 0.25, 0.5, 0.75, 1.0] {
            for nv in [0.05f32, 0.3, 0.7, 1.0] {
                let e = albedo(nv, r);
                assert!((0.0..=1.0).contains(&e), "{nv} {r}: {e}");
            }
        }
        assert!(albedo(0.8, 1.0) > albedo(0.8, 0.3));
        for (nv, r) in [(0.5f32, 0.5f32), (0.9, 0.8), (0.2, 0.3)] {
            let fine = integrate_albedo(nv, r, 256);
            assert!((albedo(nv, r) - fine).abs() < 0.01, "{nv} {r}");
        }
    }
}
