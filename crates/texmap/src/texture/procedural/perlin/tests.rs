//! Tests of Perlin's noise: the reference values, gradients, octaves, bias and gain, and
//! the f32 and four-lane versions against the f64 reference.

use super::*;
use proptest::prelude::*;

#[test]
fn four_lanes_of_noise_have_the_scalar_noise_bits() {
    use glam::Vec4;
    let mut state = 0x9e37_79b9_u32;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 17;
        state ^= state << 5;
        state
    };
    let specials = [
        0.0,
        -0.0,
        1.0,
        -1.0,
        255.0,
        256.0,
        -256.5,
        1e-8,
        -1e-8,
        3e9,
        -3e9,
        1e30,
        f32::NAN,
        f32::INFINITY,
        f32::NEG_INFINITY,
        0.999_999_94,
    ];
    for i in 0..20_000 {
        let mut coord = || {
            let r = next();
            if i % 7 == 0 {
                specials[(r % specials.len() as u32) as usize]
            } else {
                (r as f32 / u32::MAX as f32 - 0.5) * 600.0
            }
        };
        let pts: [[f32; 3]; 4] = std::array::from_fn(|_| [coord(), coord(), coord()]);
        let lanes = noise3f_x4(
            Vec4::from_array(pts.map(|q| q[0])),
            Vec4::from_array(pts.map(|q| q[1])),
            Vec4::from_array(pts.map(|q| q[2])),
        );
        for (l, q) in pts.iter().enumerate() {
            let s = noise3f(q[0], q[1], q[2]);
            let v = lanes.to_array()[l];
            assert!(
                s.to_bits() == v.to_bits() || (s.is_nan() && v.is_nan()),
                "{q:?}: {s} vs {v}"
            );
        }
    }
}

#[test]
fn cached_cells_give_the_four_lanes_bits() {
    use glam::Vec4;
    let mut state = 0x2545_f491_u32;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 17;
        state ^= state << 5;
        (state as f32 / u32::MAX as f32 - 0.5) * 2.0
    };
    let mut cells = CellsX4::EMPTY;
    let mut hits = 0;
    // A walk of small steps (most stay in their cells) with jumps (new cells), one lane
    // at a time leaving its cell too; and a NaN point, which is never a hit.
    let mut pts = [
        [0.3f32, -1.7, 2.2],
        [5.1, 0.2, -3.3],
        [-7.9, 4.4, 0.01],
        [0.0, -0.0, 9.5],
    ];
    for i in 0..20_000 {
        let step = if i % 97 == 0 { 40.0 } else { 0.05 };
        let lane = i % 4;
        for q in &mut pts[lane] {
            *q += step * next();
        }
        if i == 5_000 {
            pts[2][1] = f32::NAN;
        }
        if i == 5_001 {
            pts[2][1] = 1.5;
        }
        let (x, y, z) = (
            Vec4::from_array(pts.map(|q| q[0])),
            Vec4::from_array(pts.map(|q| q[1])),
            Vec4::from_array(pts.map(|q| q[2])),
        );
        let before = cells.floors;
        let cached = noise3f_x4_cached(x, y, z, &mut cells);
        hits += usize::from(before == cells.floors);
        let plain = noise3f_x4(x, y, z);
        for l in 0..4 {
            let (c, p) = (cached.to_array()[l], plain.to_array()[l]);
            assert!(
                c.to_bits() == p.to_bits() || (c.is_nan() && p.is_nan()),
                "step {i} lane {l}: {c} vs {p}"
            );
        }
    }
    // The walk does reuse its cells (and is not all misses).
    assert!(hits > 10_000, "{hits} hits");
}

#[test]
fn the_f32_gradient_table_is_the_reference_gradient() {
    for h in 0..16 {
        assert_eq!(
            GRADIENTS_F32[h].map(f64::from),
            gradient(h).to_array(),
            "hash {h}"
        );
    }
}

#[test]
fn noise_stays_within_its_bound() {
    // Dense in a few cells (the extremes sit inside cells, near their centres).
    let mut most = 0.0f32;
    for c in 0..4 {
        for i in 0..32 {
            for j in 0..32 {
                for k in 0..32 {
                    let f = |n: i32| n as f32 / 32.0;
                    let (x, y, z) = (f(i) + c as f32 * 37.0, f(j) + c as f32, f(k) - 5.0);
                    most = most.max(noise3f(x, y, z).abs());
                }
            }
        }
    }
    assert!(most < NOISE_BOUND, "{most}");
    assert!(most > 0.5, "the scan reached {most} only");
}

proptest! {
    #[test]
    fn noise_is_bounded_anywhere(x in -300.0f32..300.0, y in -300.0f32..300.0, z in -300.0f32..300.0) {
        prop_assert!(noise3f(x, y, z).abs() < NOISE_BOUND);
    }
}

#[test]
fn f32_noise_matches_f64_noise() {
    let mut s = 7u32;
    for _ in 0..2000 {
        let mut r = || {
            s = s.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (s >> 8) as f32 / (1u32 << 24) as f32 * 300.0 - 150.0
        };
        let (x, y, z) = (r(), r(), r());
        let a = noise3f(x, y, z);
        let b = noise3(f64::from(x), f64::from(y), f64::from(z));
        assert!(
            (f64::from(a) - b).abs() < 1e-5,
            "({x}, {y}, {z}): {a} vs {b}"
        );
        let q = glam::Vec3::new(x, y, z);
        let t = octaves3f(q, 3.5, 2.0, 0.5, true);
        let u = turbulence(q.as_dvec3(), 3.5, 2.0, 0.5);
        assert!((f64::from(t) - u).abs() < 1e-4, "{t} vs {u}");
    }
}

/// The reference implementation, transcribed literally (nested lerps of `grad` calls).
fn reference(x: f64, y: f64, z: f64) -> f64 {
    fn grad(hash: usize, x: f64, y: f64, z: f64) -> f64 {
        let h = hash & 15;
        let u = if h < 8 { x } else { y };
        let v = if h < 4 {
            y
        } else if h == 12 || h == 14 {
            x
        } else {
            z
        };
        (if h & 1 == 0 { u } else { -u }) + (if h & 2 == 0 { v } else { -v })
    }
    let lerp = |t: f64, a: f64, b: f64| a + t * (b - a);
    let (xi, yi, zi) = (
        (x.floor() as i64 & 255) as usize,
        (y.floor() as i64 & 255) as usize,
        (z.floor() as i64 & 255) as usize,
    );
    let (x, y, z) = (x - x.floor(), y - y.floor(), z - z.floor());
    let (u, v, w) = (fade(x), fade(y), fade(z));
    let a = p(xi) + yi;
    let (aa, ab) = (p(a) + zi, p(a + 1) + zi);
    let b = p(xi + 1) + yi;
    let (ba, bb) = (p(b) + zi, p(b + 1) + zi);
    lerp(
        w,
        lerp(
            v,
            lerp(u, grad(p(aa), x, y, z), grad(p(ba), x - 1.0, y, z)),
            lerp(
                u,
                grad(p(ab), x, y - 1.0, z),
                grad(p(bb), x - 1.0, y - 1.0, z),
            ),
        ),
        lerp(
            v,
            lerp(
                u,
                grad(p(aa + 1), x, y, z - 1.0),
                grad(p(ba + 1), x - 1.0, y, z - 1.0),
            ),
            lerp(
                u,
                grad(p(ab + 1), x, y - 1.0, z - 1.0),
                grad(p(bb + 1), x - 1.0, y - 1.0, z - 1.0),
            ),
        ),
    )
}

#[test]
#[allow(clippy::approx_constant)] // 3.14 is the published test point, not π
fn published_value() {
    assert!((noise3(3.14, 42.0, 7.0) - 0.136_919_958_784_000_12).abs() < 1e-12);
}

#[test]
fn matches_the_reference_transcription() {
    let pts = [
        (0.5, 0.5, 0.5),
        (1.25, -3.75, 12.5),
        (-7.1, 0.3, 255.9),
        (100.01, 200.02, -300.03),
        (0.999, 0.001, 0.5),
        (-0.5, -0.5, -0.5),
    ];
    for (x, y, z) in pts {
        assert!(
            (noise3(x, y, z) - reference(x, y, z)).abs() < 1e-12,
            "({x},{y},{z})"
        );
    }
}

#[test]
fn bias_and_gain_fixed_points() {
    assert!((bias(0.3, 0.5) - 0.3).abs() < 1e-12);
    assert!((bias(0.5, 0.77) - 0.77).abs() < 1e-12);
    assert!((gain(0.5, 0.3) - 0.3).abs() < 1e-12);
    assert!((gain(0.8, 0.5) - 0.5).abs() < 1e-12);
    assert!(gain(0.8, 0.25) < 0.25 && gain(0.8, 0.75) > 0.75);
}

#[test]
fn fbm_octave_fades_continuously() {
    let p = DVec3::new(0.3, 1.7, -2.2);
    let a = fbm(p, 3.0, 2.0, 0.5);
    let b = fbm(p, 3.0 + 1e-9, 2.0, 0.5);
    assert!((a - b).abs() < 1e-8);
    assert!((turbulence(p, 1.0, 2.0, 0.5) - noise3(0.3, 1.7, -2.2).abs()).abs() < 1e-15);
}

#[test]
fn octave_sums_with_gradient_match_the_plain_sums_and_finite_differences() {
    let h = 1e-6;
    for i in 0..60 {
        let t = i as f64;
        let p = DVec3::new(t * 0.37 - 9.0, t * 0.113 + 0.2, -t * 0.291);
        for (octaves, absolute) in [(1.0, false), (3.6, false), (5.0, true), (2.25, true)] {
            type Plain = fn(DVec3, f64, f64, f64) -> f64;
            type With = fn(DVec3, f64, f64, f64) -> (f64, DVec3);
            let (plain, with): (Plain, With) = if absolute {
                (turbulence, turbulence_with_gradient)
            } else {
                (fbm, fbm_with_gradient)
            };
            let (v, g) = with(p, octaves, 2.0, 0.5);
            assert!(
                (v - plain(p, octaves, 2.0, 0.5)).abs() < 1e-12,
                "{p} {octaves}"
            );
            let fd = DVec3::new(
                plain(p + DVec3::X * h, octaves, 2.0, 0.5)
                    - plain(p - DVec3::X * h, octaves, 2.0, 0.5),
                plain(p + DVec3::Y * h, octaves, 2.0, 0.5)
                    - plain(p - DVec3::Y * h, octaves, 2.0, 0.5),
                plain(p + DVec3::Z * h, octaves, 2.0, 0.5)
                    - plain(p - DVec3::Z * h, octaves, 2.0, 0.5),
            ) / (2.0 * h);
            assert!(
                (g - fd).abs().max_element() < 1e-4 * (1.0 + fd.abs().max_element()),
                "{p} {octaves} {absolute}: {g} vs {fd}"
            );
        }
    }
}

proptest! {
    #[test]
    fn zero_at_lattice_points(x in -300i32..300, y in -300i32..300, z in -300i32..300) {
        prop_assert_eq!(noise3(x as f64, y as f64, z as f64), 0.0);
    }

    #[test]
    fn stays_within_bounds(x in -1e3f64..1e3, y in -1e3f64..1e3, z in -1e3f64..1e3) {
        prop_assert!(noise3(x, y, z).abs() <= 1.1);
        prop_assert!((noise3(x, y, z) - reference(x, y, z)).abs() < 1e-12);
    }

    #[test]
    fn gradient_matches_finite_differences(x in -50f64..50.0, y in -50f64..50.0, z in -50f64..50.0) {
        let (_, g) = noise3_with_gradient(x, y, z);
        let h = 1e-6;
        let fd = DVec3::new(
            (noise3(x + h, y, z) - noise3(x - h, y, z)) / (2.0 * h),
            (noise3(x, y + h, z) - noise3(x, y - h, z)) / (2.0 * h),
            (noise3(x, y, z + h) - noise3(x, y, z - h)) / (2.0 * h),
        );
        prop_assert!((g - fd).abs().max_element() < 1e-5, "{:?} vs {:?}", g, fd);
    }
}
