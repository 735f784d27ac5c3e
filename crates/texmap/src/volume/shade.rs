//! Blinn-Phong for volume samples, shared by the ray marcher and the slices: a white
//! headlight (VTK's default, `vtk_volume.py`'s images) or the scene's lights.
//!
//! Rules:
//! - The normal is the field's gradient (any length; below 1e-6 the sample gets the ambient
//!   term only, as VTK's shading tables give a zero normal).
//! - Headlight: light and eye both along the view direction, two-sided, `c·(k_a + k_d·|N·V|)
//!   + k_s·|N·V|^p` (VTK's `vtkFixedPointVolumeRayCastMapper` with its default light).
//! - Scene lights ([`Light`], world space, at the sample's world position): the gradient's
//!   sign is arbitrary, so the normal is turned to face the viewer, then each light adds
//!   `S·I·(k_d·c·max(N·L, 0) + k_s·max(N·H, 0)^p)` with `H = normalize(L + V)`; the ambient
//!   term is `k_a·c`. Turning the normal towards the viewer (not `|N·L|`) keeps a side lit
//!   from +x bright and the far side dark; for the headlight (L = V) both are the same.

use glam::Vec3;

use crate::shading::Light;

/// How a volume sample reflects light: Blinn-Phong coefficients (`k_a`, `k_d`, `k_s` and the
/// specular power `p` of the rules above), VTK's `vtkVolumeProperty` values in
/// `vtk_volume.py` by default, for the headlight or the scene's lights
/// ([`MarchParams::lights`](super::params::MarchParams::lights)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Reflectance {
    pub ambient: f32,
    pub diffuse: f32,
    pub specular: f32,
    pub power: f32,
}

impl Default for Reflectance {
    fn default() -> Self {
        Reflectance {
            ambient: 0.2,
            diffuse: 0.7,
            specular: 0.2,
            power: 10.0,
        }
    }
}

/// How a volume sample is lit.
#[derive(Clone, Debug)]
pub(crate) struct VolumeLights {
    k: Reflectance,
    /// Scene lights with unit directions; empty: the headlight.
    lights: Vec<Light>,
    /// Each light's index in the list it was made from (the scene's, which shadow maps use).
    index: Vec<usize>,
    /// The specular power when it is a whole number in `0..=64` (then raised by squaring).
    whole_power: Option<u32>,
}

impl VolumeLights {
    /// `lights` empty means the headlight; lights that cannot shine (a zero direction) are
    /// dropped.
    pub fn new(k: Reflectance, lights: &[Light]) -> Self {
        let (index, lights) = lights
            .iter()
            .enumerate()
            .filter_map(|(i, l)| Some((i, l.normalized()?)))
            .unzip();
        let p = k.power;
        let whole_power = (p == p.round() && (0.0..=64.0).contains(&p)).then_some(p as u32);
        VolumeLights {
            k,
            lights,
            index,
            whole_power,
        }
    }

    /// The coefficients and the whole specular power when the headlight shades with a
    /// power raised by squaring (the loops in lanes take only that case).
    pub fn headlight_by_squaring(&self) -> Option<(Reflectance, u32)> {
        match self.whole_power {
            Some(n) if self.lights.is_empty() => Some((self.k, n)),
            _ => None,
        }
    }

    /// `x^power`, by multiplications when the power is a small integer (powf costs more than
    /// the rest of the shading).
    #[inline(always)]
    fn spec_pow(&self, x: f32) -> f32 {
        match self.whole_power {
            // VTK's power and the default: the loop unrolled to four multiplications.
            Some(10) => powi_by_squaring(x, 10),
            Some(n) => powi_by_squaring(x, n),
            None => x.powf(self.k.power),
        }
    }

    /// The shaded colour of `c` with gradient `g`, seen along `ray` (unit, from the eye into
    /// the scene), at the world position `world()` (evaluated for scene lights only).
    #[inline(always)]
    pub fn shade(&self, c: Vec3, g: Vec3, ray: Vec3, world: impl FnOnce() -> Vec3) -> Vec3 {
        self.shade_shadowed(c, g, ray, world, |_, _, _, _| 1.0)
    }

    /// [`Self::shade`] with each scene light's diffuse and specular terms scaled by
    /// `visible(i, p, n, l)`: the fraction of light `i` (its index in the list given to
    /// [`Self::new`]) reaching world point `p` with normal `n` (facing the viewer), `l`
    /// towards the light, asked only where `n·l > 0`.
    #[inline(always)]
    pub fn shade_shadowed(
        &self,
        c: Vec3,
        g: Vec3,
        ray: Vec3,
        world: impl FnOnce() -> Vec3,
        visible: impl Fn(usize, Vec3, Vec3, Vec3) -> f32,
    ) -> Vec3 {
        let k = &self.k;
        let len = g.length();
        if len <= 1e-6 {
            return c * k.ambient;
        }
        if self.lights.is_empty() {
            let ndl = (g.dot(ray) / len).abs();
            return c * (k.ambient + k.diffuse * ndl)
                + Vec3::splat(k.specular * self.spec_pow(ndl));
        }
        // Facing the viewer: N·V ≥ 0 with V = −ray.
        let n = if g.dot(ray) > 0.0 { -g / len } else { g / len };
        let v = -ray;
        let p = world();
        let (mut diffuse, mut specular) = (Vec3::ZERO, Vec3::ZERO);
        for (light, &i) in self.lights.iter().zip(&self.index) {
            let Some((l, intensity)) = light.incidence(p) else {
                continue;
            };
            let ndl = n.dot(l);
            if ndl <= 0.0 {
                continue;
            }
            let s = visible(i, p, n, l);
            if s <= 0.0 {
                continue;
            }
            let intensity = intensity * s;
            diffuse += intensity * ndl;
            let ndh = (l + v).try_normalize().map_or(0.0, |h| n.dot(h).max(0.0));
            specular += intensity * self.spec_pow(ndh);
        }
        c * (k.ambient + diffuse * k.diffuse) + specular * k.specular
    }
}

/// `x^n` by repeated squaring: the multiplications of `f32::powi`'s library routine
/// (compiler-builtins' `__powisf2`, a call per sample) in its order, so the same bits, inline.
#[inline(always)]
fn powi_by_squaring(x: f32, n: u32) -> f32 {
    let (mut base, mut n) = (x, n);
    let mut acc = if n & 1 != 0 { x } else { 1.0 };
    loop {
        n >>= 1;
        if n == 0 {
            return acc;
        }
        base *= base;
        if n & 1 != 0 {
            acc *= base;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn powers_by_squaring_are_powi_bits() {
        // `black_box`: a constant power would let the compiler expand `powi` itself.
        for n in 0..=64u32 {
            let e = std::hint::black_box(n as i32);
            for i in 0..=1000 {
                let x = i as f32 / 1000.0 * 1.25;
                assert_eq!(
                    powi_by_squaring(x, n).to_bits(),
                    x.powi(e).to_bits(),
                    "{x}^{n}"
                );
            }
        }
    }

    #[test]
    fn headlight_is_two_sided_and_scene_light_is_not() {
        let k = Reflectance::default();
        let c = Vec3::ONE;
        let ray = Vec3::Y;
        let head = VolumeLights::new(k, &[]);
        // A gradient facing the eye and one facing away shade alike under the headlight.
        let a = head.shade(c, -Vec3::Y, ray, || Vec3::ZERO);
        let b = head.shade(c, Vec3::Y, ray, || Vec3::ZERO);
        assert_eq!(a, b);
        assert!((a.x - (0.2 + 0.7 + 0.2)).abs() < 1e-6, "{a}");
        // A light from +x: a normal towards +x (either gradient sign, seen from −y … here the
        // gradient is ⟂ to the ray) is lit, one towards −x gets the ambient term only.
        let lit = VolumeLights::new(
            k,
            &[Light::Directional {
                direction: Vec3::X * 3.0,
                color: Vec3::ONE,
            }],
        );
        let g_plus = Vec3::new(1.0, -0.5, 0.0);
        let g_minus = Vec3::new(-1.0, -0.5, 0.0);
        let plus = lit.shade(c, g_plus, ray, || Vec3::ZERO);
        let minus = lit.shade(c, g_minus, ray, || Vec3::ZERO);
        assert!(plus.x > 0.6, "{plus}");
        assert!((minus.x - 0.2).abs() < 1e-6, "{minus}");
        // The sign of the gradient does not matter: it is turned towards the viewer.
        assert_eq!(lit.shade(c, -g_plus, ray, || Vec3::ZERO), plus);
        // Zero gradient: ambient only.
        assert_eq!(lit.shade(c, Vec3::ZERO, ray, || Vec3::ZERO), c * 0.2);
    }

    #[test]
    fn point_light_uses_the_sample_position() {
        let lit = VolumeLights::new(
            Reflectance::default(),
            &[Light::Point {
                position: Vec3::new(10.0, 0.0, 0.0),
                color: Vec3::splat(100.0),
                range: None,
            }],
        );
        let g = Vec3::new(1.0, -1.0, 0.0);
        let near = lit.shade(Vec3::ONE, g, Vec3::Y, || Vec3::new(5.0, 0.0, 0.0));
        let far = lit.shade(Vec3::ONE, g, Vec3::Y, || Vec3::new(-5.0, 0.0, 0.0));
        assert!(near.x > far.x + 0.5, "{near} vs {far}");
    }
}
