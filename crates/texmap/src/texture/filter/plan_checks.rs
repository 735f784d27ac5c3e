//! Checks shared by the tests of the filters whose batches plan four quads at a time in
//! lanes (`anisotropic.rs`, `ewa_probes.rs`): each plan made four at a time must be the
//! quad's own, for derivatives of every kind.

use glam::Vec2;

use crate::texture::{QuadCoords, Sampler, Texture2D};

/// Asserts that plans made four at a time (`four`) are each quad's own (`one`), for
/// `derivatives_of_every_kind` under an unbiased and a biased, clamped copy of `sampler`
/// (`Debug` text compared, so that NaN fields compare equal).
pub(super) fn assert_four_plans_are_each_quads<P: std::fmt::Debug>(
    sampler: Sampler,
    four: impl Fn(&Texture2D, &Sampler, &[QuadCoords]) -> [P; 4],
    one: impl Fn(&Texture2D, &Sampler, Vec2, Vec2) -> P,
) {
    let tex = super::tests::noisy(64, 32);
    let coords = derivatives_of_every_kind();
    for (bias, min_lod, max_lod) in [(0.0, -1000.0, 1000.0), (0.6, 0.25, 3.5)] {
        let mut s = sampler;
        (s.lod_bias, s.min_lod, s.max_lod) = (bias, min_lod, max_lod);
        for quads in coords.chunks(4) {
            for (c, plan) in quads.iter().zip(&four(&tex, &s, quads)) {
                let want = one(&tex, &s, c.duv_dx, c.duv_dy);
                let (dx, dy) = (c.duv_dx, c.duv_dy);
                assert_eq!(format!("{plan:?}"), format!("{want:?}"), "{dx:?} {dy:?}");
            }
        }
    }
}

/// Quads' derivatives of every kind, for the plans' tests: zero, tiny, huge, infinite, NaN,
/// round and long footprints, and 20,000 random ones.
fn derivatives_of_every_kind() -> Vec<QuadCoords> {
    let special = [
        0.0,
        -0.0,
        1e-30,
        1e-6,
        0.001,
        0.01,
        0.05,
        0.3,
        1.0,
        1e30,
        f32::INFINITY,
        f32::NAN,
        -0.02,
    ];
    let mut derivs = Vec::new();
    for &p in &special {
        for &q in &special {
            derivs.push((Vec2::new(p, 0.0), Vec2::new(0.0, q)));
            derivs.push((Vec2::new(p, q), Vec2::new(-q, p)));
            derivs.push((Vec2::new(p, q), Vec2::new(p, q)));
        }
    }
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        ((state >> 40) as f32 / (1u64 << 24) as f32 - 0.5) * 0.2
    };
    for _ in 0..20_000 {
        derivs.push((Vec2::new(next(), next()), Vec2::new(next(), next())));
    }
    derivs
        .iter()
        .map(|&(duv_dx, duv_dy)| QuadCoords {
            duv_dx,
            duv_dy,
            ..Default::default()
        })
        .collect()
}
