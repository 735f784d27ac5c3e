//! Solid textures: colour (or any scalar channel) as a function of the object-space position,
//! so an object looks carved from a block of marble or wood and the pattern stays put when the
//! object moves.
//!
//! Every pattern is antialiased by the footprint `width` (the size, in object units, of the
//! pixel's footprint on the surface): fBm-based patterns drop the octaves finer than the
//! footprint (the last one fading out), periodic ones use their exact box-filtered form —
//! sin(φ)·sinc for marble veins and wood rings, the integral of the square wave for checkers
//! and bricks — so a far-away object converges to its mean colour instead of shimmering.

use glam::{DVec3, Vec3};

use super::perlin::{fbm, octaves_for_width, turbulence};

/// A solid (3D) or 2D procedural pattern, evaluated to a value in [0, 1] and a colour ramp.
#[derive(Clone, Debug, PartialEq)]
pub enum Solid {
    /// Veins: ½ + ½·sin(frequency·(x + amplitude·turbulence(p))).
    Marble {
        scale: f64,
        frequency: f64,
        amplitude: f64,
        octaves: f64,
    },
    /// Rings about the object's y axis, perturbed by noise.
    Wood { scale: f64, rings: f64, noise: f64 },
    /// Speckled stone: thresholded high-frequency fBm.
    Granite { scale: f64 },
    /// Soft fBm.
    Clouds { scale: f64, octaves: f64 },
    /// Alternating cubes of side `size`.
    Checker3D { size: f64 },
    /// Running-bond bricks in the object's xy plane (`brick` = width, height; `mortar` = joint
    /// width as a fraction of the brick height). 0 = mortar, 1 = brick.
    Bricks {
        width: f64,
        height: f64,
        mortar: f64,
    },
}

impl Solid {
    /// Parses a pattern name with default parameters: `marble`, `wood`, `granite`, `clouds`,
    /// `checker3d`, `bricks`.
    #[must_use]
    pub fn named(name: &str) -> Option<Solid> {
        Some(match name {
            "marble" => Solid::Marble {
                scale: 2.0,
                frequency: 3.0,
                amplitude: 1.2,
                octaves: 6.0,
            },
            "wood" => Solid::Wood {
                scale: 1.0,
                rings: 12.0,
                noise: 0.6,
            },
            "granite" => Solid::Granite { scale: 24.0 },
            "clouds" => Solid::Clouds {
                scale: 2.0,
                octaves: 8.0,
            },
            "checker3d" => Solid::Checker3D { size: 0.25 },
            "bricks" => Solid::Bricks {
                width: 0.5,
                height: 0.2,
                mortar: 0.12,
            },
            _ => return None,
        })
    }

    /// The default two colours (linear RGB) of the named pattern: value 0 → first, 1 → second.
    #[must_use]
    pub fn default_colors(&self) -> [Vec3; 2] {
        match self {
            Solid::Marble { .. } => [Vec3::new(0.08, 0.08, 0.12), Vec3::new(0.85, 0.84, 0.80)],
            Solid::Wood { .. } => [Vec3::new(0.20, 0.09, 0.03), Vec3::new(0.55, 0.30, 0.12)],
            Solid::Granite { .. } => [Vec3::new(0.05, 0.05, 0.05), Vec3::new(0.60, 0.55, 0.52)],
            Solid::Clouds { .. } => [Vec3::new(0.15, 0.30, 0.75), Vec3::new(1.0, 1.0, 1.0)],
            Solid::Checker3D { .. } => [Vec3::new(0.05, 0.05, 0.05), Vec3::new(0.9, 0.9, 0.9)],
            Solid::Bricks { .. } => [Vec3::new(0.55, 0.55, 0.52), Vec3::new(0.45, 0.12, 0.06)],
        }
    }

    /// The pattern's value in [0, 1] at `p`, box-filtered over a footprint whose extent along
    /// each object axis is `extent` (for a surface point, |∂P/∂x| + |∂P/∂y| per component; zero
    /// evaluates the pattern unfiltered, all octaves). Periodic patterns filter per axis, so a
    /// surface lying along a checker boundary is not blurred across it; noise patterns use the
    /// largest extent.
    #[must_use]
    pub fn value(&self, p: DVec3, extent: DVec3) -> f64 {
        let extent = if extent.is_finite() {
            extent.abs()
        } else {
            DVec3::ZERO
        };
        let width = extent.max_element();
        let v = match *self {
            Solid::Marble {
                scale,
                frequency,
                amplitude,
                octaves,
            } => {
                let q = p * scale;
                let oct = octaves_for_width(width * scale, octaves, 2.0);
                let phase = frequency * (q.x + amplitude * turbulence(q, oct, 2.0, 0.5));
                // Thin dark veins in a light stone: |sin| near 0 is a vein; 1 − (1 − |s|)^4
                // applied to the filtered wave keeps the mean right as the filter flattens it.
                let s = filtered_sin(phase, frequency * width * scale);
                1.0 - (1.0 - s.abs()).powi(3)
            }
            Solid::Wood {
                scale,
                rings,
                noise,
            } => {
                let q = p * scale;
                let oct = octaves_for_width(width * scale * 4.0, 3.0, 2.0);
                let r = (q.x * q.x + q.z * q.z).sqrt() + noise * fbm(q * 4.0, oct, 2.0, 0.5) / 4.0;
                let ring = 0.5
                    + 0.5
                        * filtered_sin(
                            std::f64::consts::TAU * rings * r,
                            std::f64::consts::TAU * rings * width * scale,
                        );
                ring * ring
            }
            Solid::Granite { scale } => {
                let q = p * scale;
                let oct = octaves_for_width(width * scale, 8.0, 2.0);
                let v = fbm(q, oct, 2.0, 0.5);
                // Full detail: a sharp threshold; the missing octaves widen it to their spread.
                let spread = 0.05 + 0.5 * (8.0 - oct) / 8.0;
                smoothstep(-spread, spread, v)
            }
            Solid::Clouds { scale, octaves } => {
                let q = p * scale;
                let oct = octaves_for_width(width * scale, octaves, 2.0);
                (0.5 + 0.6 * fbm(q, oct, 2.0, 0.5)).clamp(0.0, 1.0)
            }
            Solid::Checker3D { size } => {
                let w = extent / size;
                let s = filtered_square(p.x / size, w.x)
                    * filtered_square(p.y / size, w.y)
                    * filtered_square(p.z / size, w.z);
                0.5 + 0.5 * s
            }
            Solid::Bricks {
                width: bw,
                height: bh,
                mortar,
            } => {
                let row = (p.y / bh).floor();
                let x = p.x / bw + if row.rem_euclid(2.0) == 1.0 { 0.5 } else { 0.0 };
                let y = p.y / bh;
                // Mortar fraction per axis: the joint is the same width in both directions.
                let (mx, my) = (mortar * bh / bw, mortar);
                filtered_pulse(x, extent.x / bw, mx) * filtered_pulse(y, extent.y / bh, my)
            }
        };
        // Rounding in the filtered forms can stray by an ulp.
        v.clamp(0.0, 1.0)
    }

    /// Linear RGB at `p` with the two-colour ramp `colors`.
    #[must_use]
    pub fn color(&self, p: DVec3, extent: DVec3, colors: [Vec3; 2]) -> Vec3 {
        colors[0].lerp(colors[1], self.value(p, extent) as f32)
    }
}

fn smoothstep(a: f64, b: f64, x: f64) -> f64 {
    let t = ((x - a) / (b - a)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// sin averaged over a phase interval `a` wide centred on `phase`: sin(φ)·sin(a/2)/(a/2).
fn filtered_sin(phase: f64, a: f64) -> f64 {
    let h = 0.5 * a;
    let sinc = if h < 1e-6 { 1.0 } else { h.sin() / h };
    phase.sin() * sinc
}

/// The ±1 square wave of period 2 (+1 on [0, 1)) averaged over `[t − w/2, t + w/2]`.
fn filtered_square(t: f64, w: f64) -> f64 {
    if w < 1e-9 {
        return if t.rem_euclid(2.0) < 1.0 { 1.0 } else { -1.0 };
    }
    // Its integral is a triangle wave: F(t) = t for t mod 2 in [0, 1], 2 − t in [1, 2].
    let integral = |t: f64| {
        let m = t.rem_euclid(2.0);
        if m <= 1.0 {
            m
        } else {
            2.0 - m
        }
    };
    (integral(t + 0.5 * w) - integral(t - 0.5 * w)) / w
}

/// The unit-period pulse that is 1 except within `m/2` of the integers (the mortar), averaged
/// over `[t − w/2, t + w/2]`.
fn filtered_pulse(t: f64, w: f64, m: f64) -> f64 {
    let inside = |t: f64| {
        let f = t - t.floor();
        (f >= 0.5 * m && f < 1.0 - 0.5 * m) as u8 as f64
    };
    if w < 1e-9 {
        return inside(t);
    }
    let integral = |t: f64| {
        let f = t - t.floor();
        t.floor() * (1.0 - m) + (f - 0.5 * m).clamp(0.0, 1.0 - m)
    };
    (integral(t + 0.5 * w) - integral(t - 0.5 * w)) / w
}

#[cfg(test)]
mod tests {
    use super::*;

    const ALL: [&str; 6] = ["marble", "wood", "granite", "clouds", "checker3d", "bricks"];

    #[test]
    fn values_stay_in_unit_range() {
        for name in ALL {
            let s = Solid::named(name).unwrap();
            for i in 0..500 {
                let p = DVec3::new(
                    i as f64 * 0.137 - 30.0,
                    (i * 7 % 13) as f64 * 0.31,
                    -(i as f64) * 0.071,
                );
                for w in [0.0, 0.01, 0.3, 10.0].map(DVec3::splat) {
                    let v = s.value(p, w);
                    assert!((0.0..=1.0).contains(&v), "{name} at {p} width {w}: {v}");
                }
            }
        }
    }

    /// Mean and variance of a pattern over a block, at footprint width `w`.
    fn stats(s: &Solid, w: DVec3) -> (f64, f64) {
        let n = 4000;
        let vals: Vec<f64> = (0..n)
            .map(|i| {
                let t = i as f64;
                s.value(
                    DVec3::new(t * 0.6180339 % 7.0, t * 0.41421 % 5.0, t * 0.7320508 % 3.0),
                    w,
                )
            })
            .collect();
        let mean = vals.iter().sum::<f64>() / n as f64;
        (
            mean,
            vals.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n as f64,
        )
    }

    #[test]
    fn large_footprints_converge_to_a_constant() {
        // Far away (a footprint much wider than the pattern), the variance across the block
        // collapses: no shimmer. Unfiltered, the same points vary a lot.
        for name in ["marble", "checker3d", "bricks", "wood"] {
            let s = Solid::named(name).unwrap();
            let (_, var_sharp) = stats(&s, DVec3::ZERO);
            let (_, var_far) = stats(&s, DVec3::splat(50.0));
            assert!(var_sharp > 0.02, "{name}: {var_sharp}");
            assert!(
                var_far < 0.1 * var_sharp,
                "{name}: {var_far} vs {var_sharp}"
            );
        }
    }

    #[test]
    fn filtered_checker_matches_brute_force() {
        for &(t, w) in &[(0.3, 0.5), (1.7, 2.3), (-0.4, 0.9), (5.05, 0.1)] {
            let n = 20000;
            let brute: f64 = (0..n)
                .map(|i| filtered_square(t - w / 2.0 + w * (i as f64 + 0.5) / n as f64, 0.0))
                .sum::<f64>()
                / n as f64;
            assert!((filtered_square(t, w) - brute).abs() < 1e-3, "{t} {w}");
            let b2: f64 = (0..n)
                .map(|i| filtered_pulse(t - w / 2.0 + w * (i as f64 + 0.5) / n as f64, 0.0, 0.2))
                .sum::<f64>()
                / n as f64;
            assert!((filtered_pulse(t, w, 0.2) - b2).abs() < 1e-3, "{t} {w}");
        }
    }

    #[test]
    fn the_pattern_is_fixed_to_the_position() {
        let s = Solid::named("marble").unwrap();
        let p = DVec3::new(0.3, 0.2, 0.1);
        assert_eq!(s.value(p, DVec3::ZERO), s.value(p, DVec3::ZERO));
        assert_ne!(
            s.value(p, DVec3::ZERO),
            s.value(p + DVec3::X * 0.05, DVec3::ZERO)
        );
    }

    #[test]
    fn checker_on_a_boundary_plane_is_not_blurred_across_it() {
        let s = Solid::named("checker3d").unwrap();
        // On z = 0 (a cube boundary) with a footprint only in x and y: still black or white.
        let v = s.value(DVec3::new(0.1, 0.1, 0.0), DVec3::new(0.01, 0.01, 0.0));
        assert!(!(0.01..=0.99).contains(&v), "{v}");
    }
}
