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

use crate::texture::{ColorSpace, Format, Texture3D};

use super::perlin::{
    fbm, fbm_with_gradient, octaves_for_width, turbulence, turbulence_with_gradient,
};

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

    /// [`value`](Self::value) and its gradient ∂value/∂p (object space), with the same
    /// footprint filtering: noise patterns sum the same octaves, periodic ones differentiate
    /// their box-filtered forms. A step (checker and brick edges) has no gradient unfiltered
    /// and a ramp one footprint wide filtered, so a bump from it is a groove about a pixel
    /// wide at any distance. Used for bump mapping from a solid texture.
    #[must_use]
    pub fn value_and_gradient(&self, p: DVec3, extent: DVec3) -> (f64, DVec3) {
        let extent = if extent.is_finite() {
            extent.abs()
        } else {
            DVec3::ZERO
        };
        let width = extent.max_element();
        let (v, g) = match *self {
            Solid::Marble {
                scale,
                frequency,
                amplitude,
                octaves,
            } => {
                let q = p * scale;
                let oct = octaves_for_width(width * scale, octaves, 2.0);
                let (t, dt) = turbulence_with_gradient(q, oct, 2.0, 0.5);
                let phase = frequency * (q.x + amplitude * t);
                let dphase = (DVec3::X + dt * amplitude) * frequency;
                let (s, ds) = filtered_sin_with_derivative(phase, frequency * width * scale);
                let a = 1.0 - s.abs();
                let v = 1.0 - a.powi(3);
                // d/ds of 1 − (1 − |s|)³ = 3(1 − |s|)²·sign(s).
                let dv = 3.0 * a * a * s.signum() * ds;
                (v, dphase * (dv * scale))
            }
            Solid::Wood {
                scale,
                rings,
                noise,
            } => {
                let q = p * scale;
                let oct = octaves_for_width(width * scale * 4.0, 3.0, 2.0);
                let (n, dn) = fbm_with_gradient(q * 4.0, oct, 2.0, 0.5);
                let rho = (q.x * q.x + q.z * q.z).sqrt();
                let drho = if rho > 0.0 {
                    DVec3::new(q.x / rho, 0.0, q.z / rho)
                } else {
                    DVec3::ZERO
                };
                // r = ρ + noise·fbm(4q)/4, so ∂r/∂q = ∂ρ/∂q + noise·∇fbm.
                let r = rho + noise * n / 4.0;
                let dr = drho + dn * noise;
                let k = std::f64::consts::TAU * rings;
                let (s, ds) = filtered_sin_with_derivative(k * r, k * width * scale);
                let ring = 0.5 + 0.5 * s;
                (ring * ring, dr * (ring * ds * k * scale))
            }
            Solid::Granite { scale } => {
                let q = p * scale;
                let oct = octaves_for_width(width * scale, 8.0, 2.0);
                let (v, dv) = fbm_with_gradient(q, oct, 2.0, 0.5);
                let spread = 0.05 + 0.5 * (8.0 - oct) / 8.0;
                let (s, ds) = smoothstep_with_derivative(-spread, spread, v);
                (s, dv * (ds * scale))
            }
            Solid::Clouds { scale, octaves } => {
                let q = p * scale;
                let oct = octaves_for_width(width * scale, octaves, 2.0);
                let (n, dn) = fbm_with_gradient(q, oct, 2.0, 0.5);
                let v = 0.5 + 0.6 * n;
                let g = if (0.0..=1.0).contains(&v) {
                    dn * (0.6 * scale)
                } else {
                    DVec3::ZERO
                };
                (v, g)
            }
            Solid::Checker3D { size } => {
                let w = extent / size;
                let t = p / size;
                let (sx, dx) = (
                    filtered_square(t.x, w.x),
                    filtered_square_derivative(t.x, w.x),
                );
                let (sy, dy) = (
                    filtered_square(t.y, w.y),
                    filtered_square_derivative(t.y, w.y),
                );
                let (sz, dz) = (
                    filtered_square(t.z, w.z),
                    filtered_square_derivative(t.z, w.z),
                );
                let g = DVec3::new(dx * sy * sz, sx * dy * sz, sx * sy * dz) * (0.5 / size);
                (0.5 + 0.5 * sx * sy * sz, g)
            }
            Solid::Bricks {
                width: bw,
                height: bh,
                mortar,
            } => {
                let row = (p.y / bh).floor();
                let x = p.x / bw + if row.rem_euclid(2.0) == 1.0 { 0.5 } else { 0.0 };
                let y = p.y / bh;
                let (mx, my) = (mortar * bh / bw, mortar);
                let (wx, wy) = (extent.x / bw, extent.y / bh);
                let (px, py) = (filtered_pulse(x, wx, mx), filtered_pulse(y, wy, my));
                let (dpx, dpy) = (
                    filtered_pulse_derivative(x, wx, mx),
                    filtered_pulse_derivative(y, wy, my),
                );
                (px * py, DVec3::new(dpx * py / bw, px * dpy / bh, 0.0))
            }
        };
        // As `value`: the clamp only removes rounding; outside it the value is flat.
        if (0.0..=1.0).contains(&v) {
            (v, g)
        } else {
            (v.clamp(0.0, 1.0), DVec3::ZERO)
        }
    }

    /// Linear RGB at `p` with the two-colour ramp `colors`.
    #[must_use]
    pub fn color(&self, p: DVec3, extent: DVec3, colors: [Vec3; 2]) -> Vec3 {
        colors[0].lerp(colors[1], self.value(p, extent) as f32)
    }

    /// The pattern's values over the box `[min, max]` baked into a `size³` 16-bit 3D texture
    /// (R channel, full mip chain): voxel `i` holds the value at the box point of texture
    /// coordinate `(i + ½)/size`, box-filtered over one voxel (the pattern's own
    /// antialiasing), so the texture can stand in for the pattern as a solid texture.
    ///
    /// # Errors
    /// A size outside 1..=512 or a box with a non-positive or non-finite side.
    pub fn bake(&self, size: u32, min: DVec3, max: DVec3) -> crate::Result<Texture3D> {
        let side = max - min;
        if !(1..=512).contains(&size) || !side.is_finite() || !side.cmpgt(DVec3::ZERO).all() {
            return Err(crate::Error::parameter(format!(
                "solid texture bake: size {size} must be within 1..=512 and the box {min}..{max} non-empty"
            )));
        }
        let voxel = side / f64::from(size);
        let n = size as usize;
        let mut bytes = Vec::with_capacity(n * n * n * 2);
        for z in 0..n {
            for y in 0..n {
                for x in 0..n {
                    let p = min + (DVec3::new(x as f64, y as f64, z as f64) + 0.5) * voxel;
                    let v = (self.value(p, voxel).clamp(0.0, 1.0) * 65535.0).round() as u16;
                    bytes.extend_from_slice(&v.to_le_bytes());
                }
            }
        }
        Texture3D::from_texels([size; 3], Format::R16, ColorSpace::Linear, &bytes, true)
    }
}

fn smoothstep(a: f64, b: f64, x: f64) -> f64 {
    let t = ((x - a) / (b - a)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// [`smoothstep`] and its derivative in `x`.
fn smoothstep_with_derivative(a: f64, b: f64, x: f64) -> (f64, f64) {
    let t = (x - a) / (b - a);
    if !(0.0..=1.0).contains(&t) {
        return (t.clamp(0.0, 1.0), 0.0);
    }
    (t * t * (3.0 - 2.0 * t), 6.0 * t * (1.0 - t) / (b - a))
}

/// [`filtered_sin`] and its derivative in `phase` (the sinc factor is constant in it).
fn filtered_sin_with_derivative(phase: f64, a: f64) -> (f64, f64) {
    let h = 0.5 * a;
    let sinc = if h < 1e-6 { 1.0 } else { h.sin() / h };
    (phase.sin() * sinc, phase.cos() * sinc)
}

/// d/dt of [`filtered_square`]: the difference of the square wave at the box's ends over its
/// width; zero unfiltered (a step has no derivative to draw).
fn filtered_square_derivative(t: f64, w: f64) -> f64 {
    if w < 1e-9 {
        return 0.0;
    }
    let square = |t: f64| if t.rem_euclid(2.0) < 1.0 { 1.0 } else { -1.0 };
    (square(t + 0.5 * w) - square(t - 0.5 * w)) / w
}

/// d/dt of [`filtered_pulse`], likewise.
fn filtered_pulse_derivative(t: f64, w: f64, m: f64) -> f64 {
    if w < 1e-9 {
        return 0.0;
    }
    let inside = |t: f64| {
        let f = t - t.floor();
        (f >= 0.5 * m && f < 1.0 - 0.5 * m) as u8 as f64
    };
    (inside(t + 0.5 * w) - inside(t - 0.5 * w)) / w
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
    fn gradient_matches_the_value_and_its_finite_differences() {
        let h = 1e-6;
        for name in ALL {
            let s = Solid::named(name).unwrap();
            // Unfiltered and two footprints (the steps of checker and bricks only have a
            // gradient when filtered).
            for extent in [DVec3::ZERO, DVec3::new(0.02, 0.03, 0.01), DVec3::splat(0.2)] {
                let mut checked = 0;
                for i in 0..200 {
                    let t = i as f64;
                    let p = DVec3::new(
                        (t * 0.6180339) % 3.0 - 1.5,
                        (t * 0.41421) % 2.0 - 1.0,
                        (t * 0.7320508) % 2.5 - 1.2,
                    );
                    let (v, g) = s.value_and_gradient(p, extent);
                    assert!((v - s.value(p, extent)).abs() < 1e-12, "{name} at {p}");
                    let fd = DVec3::new(
                        s.value(p + DVec3::X * h, extent) - s.value(p - DVec3::X * h, extent),
                        s.value(p + DVec3::Y * h, extent) - s.value(p - DVec3::Y * h, extent),
                        s.value(p + DVec3::Z * h, extent) - s.value(p - DVec3::Z * h, extent),
                    ) / (2.0 * h);
                    // Skip the few points within h of a kink or step (|n|, |sin|, edges),
                    // where the central difference jumps.
                    let fd_fwd = DVec3::new(
                        s.value(p + DVec3::X * h, extent) - v,
                        s.value(p + DVec3::Y * h, extent) - v,
                        s.value(p + DVec3::Z * h, extent) - v,
                    ) / h;
                    if (fd - fd_fwd).abs().max_element() > 1e-3 * (1.0 + fd.abs().max_element()) {
                        continue;
                    }
                    checked += 1;
                    assert!(
                        (g - fd).abs().max_element() < 1e-4 * (1.0 + fd.abs().max_element()),
                        "{name} at {p} extent {extent}: {g} vs {fd}"
                    );
                }
                assert!(checked > 150, "{name}: only {checked} smooth points");
            }
        }
        // The gradient is not trivially zero: noise slopes almost everywhere, a filtered
        // checker across its edges.
        let s = Solid::named("clouds").unwrap();
        let slopes = (0..50)
            .filter(|&i| {
                let p = DVec3::new(i as f64 * 0.013, 0.2, 0.1);
                s.value_and_gradient(p, DVec3::ZERO).1.length() > 0.5
            })
            .count();
        assert!(slopes > 40, "{slopes}");
        let s = Solid::named("checker3d").unwrap();
        let across = s.value_and_gradient(DVec3::new(0.25, 0.1, 0.1), DVec3::splat(0.02));
        // On the face x = 0.25 (size 0.25), a box 0.02 wide: the ±1 wave falls by 2 over
        // 0.08 periods, so ∂value/∂x = ½·(−2/0.08)/0.25 = −50.
        assert!((across.1.x + 50.0).abs() < 1e-6, "{across:?}");
    }

    #[test]
    fn checker_on_a_boundary_plane_is_not_blurred_across_it() {
        let s = Solid::named("checker3d").unwrap();
        // On z = 0 (a cube boundary) with a footprint only in x and y: still black or white.
        let v = s.value(DVec3::new(0.1, 0.1, 0.0), DVec3::new(0.01, 0.01, 0.0));
        assert!(!(0.01..=0.99).contains(&v), "{v}");
    }
}
