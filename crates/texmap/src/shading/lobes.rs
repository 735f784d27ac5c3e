//! glTF's material extensions over the metallic-roughness model ([`super::pbr`]), as their
//! specifications say, in texmap's `I = C·D + S` form:
//!
//! - `KHR_materials_specular`: the dielectric Fresnel is `F = w·f0' + (w − w·f0')(1 − V·H)⁵`
//!   with `f0' = min(f0(ior)·specular_colour, 1)` and `w` the specular factor, mixed with
//!   the metal's `F = base + (1 − base)(1 − V·H)⁵` by `metallic` (Schlick with an f90,
//!   [`fresnel_f90`]). At factor 1, colour 1 it is today's model bit for bit.
//! - `KHR_materials_clearcoat`: a second GGX lobe (its own roughness and normal, f0 = 0.04)
//!   over everything beneath, emission included: `f = base·(1 − c·Fc(N_c·V)) + c·Fc·D·Vis`.
//! - `KHR_materials_sheen`: the Charlie lobe ([`super::sheen`]) over the base, which it
//!   scales by `1 − max(sheen_colour)·E(N·V)` (the specification's albedo scaling; for a
//!   light, the smaller of that and the same at N·L).
//! - `KHR_materials_volume`: light transmitted through the thickness `t` (object units
//!   times the mesh's scale) is attenuated by Beer–Lambert, `attenuation_colour^(t/d)`.
//!
//! Under an environment, each lobe reads the prefiltered environment as the base's specular
//! lobe does (split sum): the clearcoat along its own reflected direction at its roughness;
//! the sheen reads the environment prefiltered by its Charlie lobe (the glTF sample viewer's
//! method, [`super::ibl`]) along the reflected direction at its roughness, times its albedo
//! `E`.

use glam::Vec3;

/// The extension parameters of a material (and, after its maps, of a pixel's surface). The
/// default is the plain metallic-roughness model.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lobes {
    /// `KHR_materials_specular`'s `specularFactor` (× its texture's alpha): the weight of the
    /// dielectric's specular lobe.
    pub specular: f32,
    /// `specularColorFactor` (× its texture), linear: tints the dielectric's f0.
    pub specular_color: Vec3,
    /// `KHR_materials_clearcoat`: the coat's weight (0 = none).
    pub clearcoat: f32,
    /// The coat's roughness.
    pub clearcoat_roughness: f32,
    /// `KHR_materials_sheen`: the sheen colour, linear (0 = no sheen).
    pub sheen_color: Vec3,
    /// The sheen roughness.
    pub sheen_roughness: f32,
    /// `KHR_materials_volume`: the thickness in object units (0 = thin-walled).
    pub thickness: f32,
    /// The colour white light reaches after `attenuation_distance`, linear.
    pub attenuation_color: Vec3,
    /// The distance (world units) over which light is attenuated to `attenuation_color`;
    /// infinite = no attenuation.
    pub attenuation_distance: f32,
}

impl Default for Lobes {
    fn default() -> Self {
        Lobes {
            specular: 1.0,
            specular_color: Vec3::ONE,
            clearcoat: 0.0,
            clearcoat_roughness: 0.0,
            sheen_color: Vec3::ZERO,
            sheen_roughness: 0.0,
            thickness: 0.0,
            attenuation_color: Vec3::ONE,
            attenuation_distance: f32::INFINITY,
        }
    }
}

impl Lobes {
    /// True when a coat or a sheen lies over the base (the layering of the module docs).
    #[inline]
    #[must_use]
    pub fn layered(&self) -> bool {
        self.clearcoat > 0.0 || self.sheen_color != Vec3::ZERO
    }

    /// The dielectric's `(f0, f90)` for index of refraction `ior`: `(w·min(f0(ior)·colour,
    /// 1), w)` with `w` the specular factor.
    #[inline]
    #[must_use]
    pub fn dielectric(&self, f0_ior: f32) -> (Vec3, f32) {
        let w = self.specular;
        ((self.specular_color * f0_ior).min(Vec3::ONE) * w, w)
    }

    /// Beer–Lambert transmittance through `distance` world units of the volume:
    /// `attenuation_color^(distance/attenuation_distance)` (1 without a volume).
    #[inline]
    #[must_use]
    pub fn transmittance(&self, distance: f32) -> Vec3 {
        if !(self.attenuation_distance.is_finite() && self.attenuation_distance > 0.0)
            || distance <= 0.0
        {
            return Vec3::ONE;
        }
        let k = distance / self.attenuation_distance;
        Vec3::new(
            self.attenuation_color.x.max(0.0).powf(k),
            self.attenuation_color.y.max(0.0).powf(k),
            self.attenuation_color.z.max(0.0).powf(k),
        )
    }
}

/// Schlick's Fresnel with a grazing value: `f0 + (f90 − f0)(1 − cos θ)⁵`.
#[inline]
#[must_use]
pub fn fresnel_f90(f0: Vec3, f90: f32, cos_theta: f32) -> Vec3 {
    let m = (1.0 - cos_theta).clamp(0.0, 1.0);
    let m2 = m * m;
    f0 + (Vec3::splat(f90) - f0) * (m2 * m2 * m)
}

/// The clearcoat's Fresnel at the viewer, `0.04 + 0.96(1 − N_c·V)⁵`, times the coat's weight:
/// the share of the light the coat takes from everything beneath.
#[inline]
#[must_use]
pub fn coat_share(clearcoat: f32, nc_dot_v: f32) -> f32 {
    if clearcoat <= 0.0 {
        return 0.0;
    }
    clearcoat * fresnel_f90(Vec3::splat(super::pbr::DIELECTRIC_F0), 1.0, nc_dot_v).x
}

/// The factor by which a sheen of `color` and roughness `r` scales the base beneath it,
/// seen at `n_dot_v`: `1 − max(colour)·E(N·V, r)`.
#[inline]
#[must_use]
pub fn sheen_scaling(color: Vec3, r: f32, n_dot_v: f32) -> f32 {
    let m = color.max_element();
    if m <= 0.0 {
        return 1.0;
    }
    1.0 - m * super::sheen::albedo(n_dot_v, r)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_specular_is_todays_fresnel_bit_for_bit() {
        let l = Lobes::default();
        for f0_ior in [0.04f32, 0.02, 0.1] {
            let (f0, f90) = l.dielectric(f0_ior);
            assert_eq!(f0, Vec3::splat(f0_ior));
            for base in [Vec3::new(0.9, 0.5, 0.1), Vec3::ONE] {
                for metallic in [0.0f32, 0.3, 1.0] {
                    let f0m = f0.lerp(base, metallic);
                    let f90m = f90 + (1.0 - f90) * metallic;
                    for c in [0.0f32, 0.2, 0.7, 1.0] {
                        assert_eq!(
                            fresnel_f90(f0m, f90m, c),
                            super::super::pbr::fresnel(f0m, c)
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn beer_lambert_reaches_the_colour_at_the_distance() {
        let l = Lobes {
            attenuation_color: Vec3::new(0.5, 0.25, 1.0),
            attenuation_distance: 2.0,
            ..Default::default()
        };
        assert!(
            (l.transmittance(2.0) - l.attenuation_color)
                .abs()
                .max_element()
                < 1e-6
        );
        assert!(
            (l.transmittance(4.0) - Vec3::new(0.25, 0.0625, 1.0))
                .abs()
                .max_element()
                < 1e-6
        );
        assert_eq!(l.transmittance(0.0), Vec3::ONE);
        assert_eq!(Lobes::default().transmittance(10.0), Vec3::ONE);
    }

    #[test]
    fn coat_and_sheen_shares_vanish_at_zero() {
        assert_eq!(coat_share(0.0, 0.3), 0.0);
        assert!((coat_share(1.0, 1.0) - 0.04).abs() < 1e-6);
        assert_eq!(sheen_scaling(Vec3::ZERO, 0.5, 0.5), 1.0);
        let s = sheen_scaling(Vec3::ONE, 0.5, 0.5);
        assert!(s > 0.0 && s < 1.0, "{s}");
    }
}
