//! glTF 2.0's metallic-roughness BRDF (the specification's Appendix B).
//!
//! For unit `N`, `V`, `L` and `H = normalize(L + V)`:
//!
//! ```text
//! c_diff = lerp(base.rgb, 0, metallic)         f0 = lerp(0.04, base.rgb, metallic)
//! α = roughness²                                F  = f0 + (1 − f0)(1 − V·H)⁵   (Schlick)
//! D = α² / (π((N·H)²(α² − 1) + 1)²)             (Trowbridge-Reitz / GGX)
//! Vis = ½ / (N·L·√((N·V)²(1 − α²) + α²) + N·V·√((N·L)²(1 − α²) + α²))
//!                                               (Smith, height-correlated: G / 4(N·L)(N·V))
//! f = (1 − F)·c_diff/π + F·D·Vis
//! ```
//!
//! Light units: texmap's lights are in the units of the Phong model, where a light of colour
//! 1 lights a white Lambertian surface facing it to 1. Outgoing radiance is therefore
//! `π·f·(N·L)·I_i`, so a rough white dielectric and a Phong material with K_D = 1 agree.
//! Physical intensities (glTF's lux and candela) are divided by π when loaded.
//!
//! Ambient light `I_AL` is a uniform environment: it reflects the BRDF's directional albedo,
//! `K_A·I_AL·occlusion·(c_diff·(1 − E) + E)` with `E = f0·A + B` the albedo of the specular
//! lobe (a table integrated once, see [`specular_albedo`]). Under a white environment a white
//! dielectric reflects exactly 1 (the white furnace), and a metal reflects its `f0` times
//! the lobe's single-scattering albedo (below 1 for rough metals, as the BRDF loses the
//! energy of multiple scattering).
//!
//! [`metallic_roughness`] returns `(D, S)` with `I = C·D + S` like the Phong model, `C` being
//! the base colour: the diffuse part is linear in `C`, the specular part (through `f0`) is
//! computed from the base colour the [`Surface`] carries.

use std::f32::consts::PI;

use glam::{Vec2, Vec3};

#[cfg(test)]
use super::albedo::integration::integrate_specular_albedo;
use super::albedo::{albedo_table, ALBEDO_N};
use super::lobes::{coat_share, fresnel_f90, sheen_scaling};
use super::{Lighting, Surface, Viewer};

/// The smallest roughness used: α = roughness² ≥ 0.002, so a perfect mirror keeps a finite,
/// visible highlight from a point light.
pub const MIN_ROUGHNESS: f32 = 0.045;

/// f0 of dielectrics (index of refraction 1.5).
pub const DIELECTRIC_F0: f32 = 0.04;

/// The GGX normal distribution D(N·H) for α (= roughness²).
#[inline]
#[must_use]
pub fn distribution(n_dot_h: f32, alpha: f32) -> f32 {
    let a2 = alpha * alpha;
    let t = n_dot_h * n_dot_h * (a2 - 1.0) + 1.0;
    a2 / (PI * t * t)
}

/// The height-correlated Smith visibility `G / (4·N·L·N·V)` for α.
#[inline]
#[must_use]
pub fn visibility(n_dot_l: f32, n_dot_v: f32, alpha: f32) -> f32 {
    let a2 = alpha * alpha;
    let gv = n_dot_l * (n_dot_v * n_dot_v * (1.0 - a2) + a2).sqrt();
    let gl = n_dot_v * (n_dot_l * n_dot_l * (1.0 - a2) + a2).sqrt();
    let sum = gv + gl;
    if sum > 0.0 {
        0.5 / sum
    } else {
        0.0
    }
}

/// Schlick's Fresnel: `f0 + (1 − f0)(1 − cos θ)⁵`.
#[inline]
#[must_use]
pub fn fresnel(f0: Vec3, cos_theta: f32) -> Vec3 {
    let m = (1.0 - cos_theta).clamp(0.0, 1.0);
    let m2 = m * m;
    f0 + (Vec3::ONE - f0) * (m2 * m2 * m)
}

/// α from a roughness, with [`MIN_ROUGHNESS`] applied.
#[inline]
#[must_use]
pub fn alpha(roughness: f32) -> f32 {
    let r = if roughness.is_finite() {
        roughness.clamp(MIN_ROUGHNESS, 1.0)
    } else {
        1.0
    };
    r * r
}

/// What every light and the ambient or environment term of the metallic-roughness model
/// share at one surface point: the lobe's reflectances, its α and the view direction.
#[derive(Clone, Copy, Debug)]
pub struct MrLobe {
    pub metallic: f32,
    /// KHR_materials_specular's f0 and f90 (f90 = 1 without it: Schlick exactly), the
    /// metal's base colour blended in.
    pub f0: Vec3,
    pub f90: f32,
    /// GGX α (roughness², clamped).
    pub a: f32,
    /// Unit direction towards the viewer.
    pub v: Vec3,
    /// N·V, kept just above 0 (normal-mapped normals can face away from the viewer).
    pub n_dot_v: f32,
}

impl MrLobe {
    /// The lobe of surface `s` seen by `viewer`.
    #[inline(always)]
    #[must_use]
    pub fn new(s: &Surface, viewer: Viewer) -> Self {
        let metallic = s.metallic.clamp(0.0, 1.0);
        let (f0_d, f90_d) = s.lobes.dielectric(super::ibl::dielectric_f0(s.ior));
        let v = viewer.towards(s.position);
        MrLobe {
            metallic,
            f0: f0_d.lerp(s.base_color, metallic),
            f90: f90_d + (1.0 - f90_d) * metallic,
            a: alpha(s.roughness),
            v,
            n_dot_v: s.normal.dot(v).max(1e-4),
        }
    }

    /// The directional albedo of the specular lobe, `E = f0·A + B·f90` (see
    /// [`specular_albedo`]).
    #[inline(always)]
    #[must_use]
    pub fn albedo(&self) -> Vec3 {
        let e = specular_albedo(self.n_dot_v, self.a.sqrt());
        self.f0 * e.x + Vec3::splat(e.y * self.f90)
    }
}

/// The factors `(D, S)` of the metallic-roughness model at surface `s` seen by `viewer`, with
/// `I = C·D + S` (see the module docs). Includes the ambient term and `s.emissive`.
#[inline(never)]
#[must_use]
pub fn metallic_roughness(s: &Surface, lighting: &Lighting, viewer: Viewer) -> (Vec3, Vec3) {
    let lobe = MrLobe::new(s, viewer);
    let ambient = lighting.ambient * (s.ambient * s.occlusion);
    let start = if ambient == Vec3::ZERO {
        // No ambient light (the environment lights instead): the lobe's albedo is not needed.
        (Vec3::ZERO, s.emissive)
    } else {
        let e = lobe.albedo();
        (
            ambient * (1.0 - lobe.metallic) * (Vec3::ONE - e),
            s.emissive + ambient * e,
        )
    };
    let (d, sp) = lights(s, lighting, &lobe, start);
    if s.lobes.layered() {
        return layered(s, lighting, lobe.v, lobe.n_dot_v, (d, sp));
    }
    (d, sp)
}

/// `start` plus every light's diffuse and specular terms of the metallic-roughness `lobe` at
/// `s` (shadows included; not the clearcoat and sheen layers).
#[inline(always)]
#[must_use]
pub fn lights(
    s: &Surface,
    lighting: &Lighting,
    lobe: &MrLobe,
    (mut d, mut sp): (Vec3, Vec3),
) -> (Vec3, Vec3) {
    let (n, v, a) = (s.normal, lobe.v, lobe.a);
    let diffuse_weight = 1.0 - lobe.metallic;
    for (i, light) in lighting.lights.iter().enumerate() {
        let Some((l, mut intensity)) = light.incidence(s.position) else {
            continue;
        };
        let n_dot_l = n.dot(l);
        if n_dot_l <= 0.0 {
            continue;
        }
        if let Some(shadows) = lighting.shadows {
            intensity *= shadows.visibility(i, s.position, n, l);
        }
        let h = (l + v).normalize_or_zero();
        let f = fresnel_f90(lobe.f0, lobe.f90, v.dot(h));
        let n_dot_h = n.dot(h).max(0.0);
        d += intensity * (Vec3::ONE - f) * (diffuse_weight * n_dot_l);
        let spec = PI * distribution(n_dot_h, a) * visibility(n_dot_l, lobe.n_dot_v, a) * n_dot_l;
        sp += intensity * f * spec;
    }
    (d, sp)
}

/// The clearcoat and sheen over the base factors `(d, sp)` (emission included in `sp`), for
/// the lights and the uniform ambient light ([`super::lobes`]' module docs).
#[inline(never)]
fn layered(
    s: &Surface,
    lighting: &Lighting,
    v: Vec3,
    n_dot_v: f32,
    (d, sp): (Vec3, Vec3),
) -> (Vec3, Vec3) {
    let l = &s.lobes;
    let n = s.normal;
    let nc = if s.clearcoat_normal == Vec3::ZERO {
        n
    } else {
        s.clearcoat_normal
    };
    let nc_dot_v = nc.dot(v).max(1e-4);
    let coat = coat_share(l.clearcoat, nc_dot_v);
    let a_coat = alpha(l.clearcoat_roughness);
    let sheen = l.sheen_color != Vec3::ZERO;
    let k = sheen_scaling(l.sheen_color, l.sheen_roughness, n_dot_v);
    // The sheen scales the base, not its emission; the coat covers all three.
    let (mut sheen_sp, mut coat_sp) = (Vec3::ZERO, Vec3::ZERO);
    let ambient = lighting.ambient * (s.ambient * s.occlusion);
    if ambient != Vec3::ZERO {
        if sheen {
            sheen_sp += ambient * l.sheen_color * super::sheen::albedo(n_dot_v, l.sheen_roughness);
        }
        if l.clearcoat > 0.0 {
            let e = specular_albedo(nc_dot_v, a_coat.sqrt());
            coat_sp += ambient * (l.clearcoat * (DIELECTRIC_F0 * e.x + e.y));
        }
    }
    for (i, light) in lighting.lights.iter().enumerate() {
        let Some((dir, mut intensity)) = light.incidence(s.position) else {
            continue;
        };
        if n.dot(dir) <= 0.0 && nc.dot(dir) <= 0.0 {
            continue;
        }
        if let Some(shadows) = lighting.shadows {
            intensity *= shadows.visibility(i, s.position, n, dir);
        }
        if sheen {
            sheen_sp +=
                intensity * l.sheen_color * super::sheen::lobe(n, v, dir, l.sheen_roughness);
        }
        let nc_dot_l = nc.dot(dir);
        if l.clearcoat > 0.0 && nc_dot_l > 0.0 {
            let h = (dir + v).normalize_or_zero();
            let f = fresnel(Vec3::splat(DIELECTRIC_F0), v.dot(h)).x;
            let spec = PI
                * distribution(nc.dot(h).max(0.0), a_coat)
                * visibility(nc_dot_l, nc_dot_v, a_coat)
                * nc_dot_l;
            coat_sp += intensity * (l.clearcoat * f * spec);
        }
    }
    let under_coat = (sp - s.emissive) * k + s.emissive + sheen_sp;
    let under = 1.0 - coat;
    (d * (k * under), under_coat * under + coat_sp)
}

/// The directional albedo of the specular lobe for a white environment, split as
/// `E = f0·A + B` and returned as `(A, B)`, at `n_dot_v` and `roughness` (bilinear in a
/// 32 × 32 table over √(N·V) and roughness — dense near grazing, where it changes fastest
/// — integrated ahead and committed: `shading/albedo.rs`).
#[must_use]
pub fn specular_albedo(n_dot_v: f32, roughness: f32) -> Vec2 {
    const N: usize = ALBEDO_N;
    let table = albedo_table();
    let x = n_dot_v.clamp(0.0, 1.0).sqrt() * (N - 1) as f32;
    let y = roughness.clamp(0.0, 1.0) * (N - 1) as f32;
    let (i, j) = ((x as usize).min(N - 2), (y as usize).min(N - 2));
    let (fx, fy) = (x - i as f32, y - j as f32);
    let at = |i: usize, j: usize| table[j * N + i];
    let top = at(i, j).lerp(at(i + 1, j), fx);
    let bottom = at(i, j + 1).lerp(at(i + 1, j + 1), fx);
    top.lerp(bottom, fy)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shading::{Light, Material, ShadingModel};

    fn surface(base: f32, metallic: f32, roughness: f32, n: Vec3) -> Surface {
        let m = Material {
            model: ShadingModel::MetallicRoughness,
            base_color: glam::Vec4::new(base, base, base, 1.0),
            metallic,
            roughness,
            ambient: 1.0,
            ..Default::default()
        };
        Surface::new(&m, Vec3::ZERO, n)
    }

    fn sun(towards: Vec3) -> [Light; 1] {
        [Light::Directional {
            direction: towards.normalize(),
            color: Vec3::ONE,
        }]
    }

    fn lit(lights: &[Light], ambient: f32) -> Lighting<'_> {
        Lighting {
            lights,
            ambient: Vec3::splat(ambient),
            shadows: None,
        }
    }

    /// The lit value of a grey surface: C·D + S.
    fn value(s: &Surface, lighting: &Lighting, eye: Vec3) -> Vec3 {
        let (d, sp) = metallic_roughness(s, lighting, Viewer::Point(eye));
        s.base_color * d + sp
    }

    #[test]
    fn matches_hand_computed_values() {
        // Light and viewer along N, roughness ½ (α = ¼): D = 1/(πα²), Vis = ¼, F = f0 = 0.04;
        // π·F·D·Vis = 0.04·16·¼ = 0.16, and the diffuse factor is 1 − F = 0.96.
        let s = surface(0.5, 0.0, 0.5, Vec3::Z);
        let light = sun(Vec3::Z);
        let (d, sp) = metallic_roughness(&s, &lit(&light, 0.0), Viewer::Point(Vec3::Z * 3.0));
        assert!((d - Vec3::splat(0.96)).abs().max_element() < 1e-5, "{d}");
        assert!((sp - Vec3::splat(0.16)).abs().max_element() < 1e-5, "{sp}");
        assert!((value(&s, &lit(&light, 0.0), Vec3::Z * 3.0).x - 0.64).abs() < 1e-5);
        // Light 60° off the normal, viewer on it: H at 30°; by hand, D = 0.2257267,
        // Vis = 0.4785319, F = 0.0400414, so S = π·F·D·Vis·½ = 0.0067940, D = (1 − F)·½.
        let light = sun(Vec3::new(60f32.to_radians().sin(), 0.0, 0.5));
        let (d, sp) = metallic_roughness(&s, &lit(&light, 0.0), Viewer::Point(Vec3::Z));
        assert!((d.x - 0.4799793).abs() < 1e-5, "{d}");
        assert!((sp.x - 0.0067940).abs() < 1e-6, "{sp}");
    }

    #[test]
    fn metals_have_no_diffuse_and_tint_their_highlight() {
        let mut s = surface(1.0, 1.0, 0.4, Vec3::Z);
        s.base_color = Vec3::new(1.0, 0.5, 0.1);
        let light = sun(Vec3::new(0.3, 0.0, 1.0));
        let (d, sp) = metallic_roughness(
            &s,
            &lit(&light, 1.0),
            Viewer::Point(Vec3::new(-0.3, 0.0, 1.0)),
        );
        assert_eq!(d, Vec3::ZERO);
        // f0 is the base colour: the highlight keeps its hue.
        assert!(sp.x > sp.y && sp.y > sp.z && sp.z > 0.0, "{sp}");
        let (r, g) = (sp.y / sp.x, sp.z / sp.x);
        assert!((r - 0.5).abs() < 0.05 && (g - 0.1).abs() < 0.05, "{sp}");
    }

    #[test]
    fn smooth_surfaces_have_sharp_bright_highlights_rough_ones_wide_dim_ones() {
        // Light 30° off the normal; the mirror direction 30° the other way.
        let (sin, cos) = (0.5, 0.75f32.sqrt());
        let light = sun(Vec3::new(sin, 0.0, cos));
        let l = lit(&light, 0.0);
        let mirror = Vec3::new(-sin, 0.0, cos);
        let spec = |roughness: f32, eye: Vec3| {
            metallic_roughness(
                &surface(0.5, 0.0, roughness, Vec3::Z),
                &l,
                Viewer::Point(eye),
            )
            .1
            .x
        };
        let (smooth_peak, rough_peak) = (spec(0.1, mirror), spec(1.0, mirror));
        assert!(
            smooth_peak > 1000.0 * rough_peak,
            "{smooth_peak} {rough_peak}"
        );
        // 30° off the mirror direction (the viewer on the normal) the smooth lobe has all but
        // gone; the rough one has barely changed.
        let (smooth_off, rough_off) = (spec(0.1, Vec3::Z), spec(1.0, Vec3::Z));
        assert!(rough_off > 10.0 * smooth_off, "{smooth_off} {rough_off}");
        assert!(rough_off > 0.5 * rough_peak, "{rough_off} {rough_peak}");
    }

    #[test]
    fn white_furnace_under_ambient_light() {
        // A uniform white environment: a white dielectric reflects exactly 1 at any angle
        // and roughness; a white metal reflects the lobe's albedo, at most 1, nearly 1 when
        // smooth, less when rough (single scattering loses the energy of the bounces between
        // microfacets: about half at roughness 1).
        let l = lit(&[], 1.0);
        for roughness in [0.0, 0.2, 0.5, 0.8, 1.0] {
            for angle in [0.0f32, 30.0, 60.0, 85.0] {
                let eye = Vec3::new(angle.to_radians().sin(), 0.0, angle.to_radians().cos());
                let dielectric = value(&surface(1.0, 0.0, roughness, Vec3::Z), &l, eye);
                assert!(
                    (dielectric - Vec3::ONE).abs().max_element() < 1e-5,
                    "{dielectric}"
                );
                let metal = value(&surface(1.0, 1.0, roughness, Vec3::Z), &l, eye).x;
                // 1 − ln 2 = 0.307 at roughness 1 and normal incidence (see below).
                let lower = if roughness == 1.0 { 0.3 } else { 0.4 };
                assert!(
                    metal <= 1.0 + 1e-3 && metal > lower,
                    "{roughness} {angle}: {metal}"
                );
                if roughness <= 0.2 && angle < 70.0 {
                    assert!(metal > 0.95, "{roughness} {angle}: {metal}");
                }
            }
        }
        // Occlusion darkens the ambient term, and only it.
        let mut s = surface(1.0, 0.0, 0.5, Vec3::Z);
        s.occlusion = 0.25;
        assert!((value(&s, &l, Vec3::Z).x - 0.25).abs() < 1e-5);
    }

    #[test]
    fn reflected_energy_stays_below_the_incident_energy() {
        // R(l) = ∫ f(l, v)(N·V) dω_v ≤ 1, integrated over the hemisphere of viewers with
        // f = (C·D + S)/(π·N·L) for a light of intensity 1. The specification's dielectric
        // weights the diffuse lobe by 1 − F per direction, not by the specular lobe's albedo,
        // so a white one exceeds 1 by up to half a percent with the light within 45° of the
        // normal (the bound here is 1.005) and by 15% at 75°; metals stay below 1.
        for (metallic, roughness) in [(0.0, 0.3), (0.0, 1.0), (1.0, 0.3), (1.0, 0.7), (1.0, 1.0)] {
            for light_angle in [0.0f32, 45.0, 75.0] {
                if metallic == 0.0 && light_angle > 45.0 {
                    // See above: 1.15 at 75° (roughness 0.3).
                    continue;
                }
                let l = Vec3::new(
                    light_angle.to_radians().sin(),
                    0.0,
                    light_angle.to_radians().cos(),
                );
                let light = sun(l);
                let lighting = lit(&light, 0.0);
                let s = surface(1.0, metallic, roughness, Vec3::Z);
                let (nt, np) = (400, 200);
                let mut sum = 0.0f64;
                for i in 0..nt {
                    let theta = (i as f32 + 0.5) / nt as f32 * std::f32::consts::FRAC_PI_2;
                    for k in 0..np {
                        let phi = (k as f32 + 0.5) / np as f32 * std::f32::consts::TAU;
                        let v = Vec3::new(
                            theta.sin() * phi.cos(),
                            theta.sin() * phi.sin(),
                            theta.cos(),
                        );
                        let f = value(&s, &lighting, v).x / (PI * l.z);
                        let d_omega = theta.sin()
                            * (std::f32::consts::FRAC_PI_2 / nt as f32)
                            * (std::f32::consts::TAU / np as f32);
                        sum += f64::from(f * v.z * d_omega);
                    }
                }
                let lower = if roughness == 1.0 { 0.25 } else { 0.4 };
                assert!(
                    sum < 1.005 && sum > lower,
                    "metallic {metallic} roughness {roughness} light {light_angle}°: {sum}"
                );
            }
        }
    }

    #[test]
    fn albedo_table_matches_a_direct_integration_and_is_bounded() {
        // Off the grid points; the estimator is noisiest at grazing angles (2% there).
        for (nv, r, tolerance) in [
            (0.9f32, 0.33f32, 0.005),
            (0.31, 0.71, 0.005),
            (0.07, 0.5, 0.025),
            (1.0, 0.045, 0.005),
        ] {
            let table = specular_albedo(nv, r);
            let direct = integrate_specular_albedo(nv, alpha(r), 65536);
            let error = (table - direct).abs().max_element();
            assert!(error < tolerance, "{nv} {r}: {table} {direct}");
        }
        // At roughness 1 (D = 1/π) and normal incidence the integral is 1 − ln 2 by hand.
        let e = specular_albedo(1.0, 1.0);
        assert!((e.x + e.y - (1.0 - 2f32.ln())).abs() < 1e-3, "{e}");
        for i in 0..=20 {
            for j in 0..=20 {
                let e = specular_albedo(i as f32 / 20.0, j as f32 / 20.0);
                assert!(e.x >= 0.0 && e.y >= 0.0 && e.x + e.y <= 1.0 + 1e-6, "{e}");
            }
        }
        // A mirror at normal incidence reflects all of it (F = f0 there, so B ≈ 0).
        let e = specular_albedo(1.0, 0.0);
        assert!(e.x > 0.97 && e.y < 0.01, "{e}");
    }

    fn with_lobes(mut s: Surface, lobes: crate::shading::lobes::Lobes) -> Surface {
        s.lobes = lobes;
        s
    }

    #[test]
    fn default_extensions_are_todays_model_exactly() {
        // Specular factor 1, colour 1, ior 1.5, no coat, no sheen (each given explicitly):
        // the same bits as the plain model, lights and ambient light together.
        use crate::shading::lobes::Lobes;
        let light = sun(Vec3::new(0.4, 0.1, 1.0));
        let l = lit(&light, 0.7);
        let explicit = Lobes {
            specular: 1.0,
            specular_color: Vec3::ONE,
            clearcoat: 0.0,
            clearcoat_roughness: 0.3,
            sheen_color: Vec3::ZERO,
            sheen_roughness: 0.6,
            ..Default::default()
        };
        for (metallic, roughness) in [(0.0, 0.5), (1.0, 0.3), (0.4, 0.9)] {
            let mut base = surface(0.6, metallic, roughness, Vec3::Z);
            base.ior = 1.5;
            base.emissive = Vec3::new(0.1, 0.0, 0.2);
            let eye = Viewer::Point(Vec3::new(-0.5, 0.2, 2.0));
            let plain = metallic_roughness(&base, &l, eye);
            let ext = metallic_roughness(&with_lobes(base, explicit), &l, eye);
            assert_eq!(plain, ext, "metallic {metallic} roughness {roughness}");
        }
        // The hand-computed values of the plain model still hold.
        let s = with_lobes(surface(0.5, 0.0, 0.5, Vec3::Z), explicit);
        let (d, sp) = metallic_roughness(&s, &lit(&sun(Vec3::Z), 0.0), Viewer::Point(Vec3::Z));
        assert!((d - Vec3::splat(0.96)).abs().max_element() < 1e-5, "{d}");
        assert!((sp - Vec3::splat(0.16)).abs().max_element() < 1e-5, "{sp}");
    }

    #[test]
    fn specular_factor_and_colour_scale_the_dielectric_lobe() {
        use crate::shading::lobes::Lobes;
        let light = sun(Vec3::Z);
        let l = lit(&light, 0.0);
        let eye = Viewer::Point(Vec3::Z);
        let base = surface(0.5, 0.0, 0.5, Vec3::Z);
        let (_, plain) = metallic_roughness(&base, &l, eye);
        let half = Lobes {
            specular: 0.5,
            ..Default::default()
        };
        let (d, sp) = metallic_roughness(&with_lobes(base, half), &l, eye);
        // At normal incidence F = w·f0: half the highlight, more diffuse.
        assert!(
            (sp - plain * 0.5).abs().max_element() < 1e-6,
            "{sp} {plain}"
        );
        assert!((d.x - (1.0 - 0.02)).abs() < 1e-5, "{d}");
        let red = Lobes {
            specular_color: Vec3::new(1.0, 0.0, 0.0),
            ..Default::default()
        };
        let (_, sp) = metallic_roughness(&with_lobes(base, red), &l, eye);
        assert!(sp.x > 0.1 && sp.y == 0.0 && sp.z == 0.0, "{sp}");
    }

    #[test]
    fn coat_and_sheen_keep_the_white_furnace_bounded() {
        // A uniform white environment on a white dielectric: 1 without layers; a coat or a
        // sheen takes its share and gives back at most what it took (single scattering: less
        // for a rough coat at grazing views, 0.81 at 75° and roughness 0.7).
        use crate::shading::lobes::Lobes;
        let l = lit(&[], 1.0);
        for angle in [0.0f32, 40.0, 75.0] {
            let eye = Vec3::new(angle.to_radians().sin(), 0.0, angle.to_radians().cos());
            for r in [0.0f32, 0.3, 0.7, 1.0] {
                for lobes in [
                    Lobes {
                        clearcoat: 1.0,
                        clearcoat_roughness: r,
                        ..Default::default()
                    },
                    Lobes {
                        sheen_color: Vec3::ONE,
                        sheen_roughness: r,
                        ..Default::default()
                    },
                    Lobes {
                        clearcoat: 1.0,
                        clearcoat_roughness: r,
                        sheen_color: Vec3::ONE,
                        sheen_roughness: r,
                        ..Default::default()
                    },
                ] {
                    let s = with_lobes(surface(1.0, 0.0, 0.5, Vec3::Z), lobes);
                    let v = value(&s, &l, eye).x;
                    let lower = if angle > 60.0 { 0.75 } else { 0.9 };
                    assert!(
                        v <= 1.0 + 1e-3 && v > lower,
                        "{angle}° r {r} {lobes:?}: {v}"
                    );
                }
            }
        }
    }

    #[test]
    fn a_coat_adds_a_sharp_highlight_of_its_own_and_dims_what_is_beneath() {
        use crate::shading::lobes::Lobes;
        let (sin, cos) = (0.5, 0.75f32.sqrt());
        let light = sun(Vec3::new(sin, 0.0, cos));
        let l = lit(&light, 0.0);
        let mirror = Viewer::Point(Vec3::new(-sin, 0.0, cos));
        let mut base = surface(0.5, 0.0, 1.0, Vec3::Z);
        base.emissive = Vec3::splat(0.5);
        let coat = with_lobes(
            base,
            Lobes {
                clearcoat: 1.0,
                clearcoat_roughness: 0.1,
                ..Default::default()
            },
        );
        let (d0, s0) = metallic_roughness(&base, &l, mirror);
        let (d1, s1) = metallic_roughness(&coat, &l, mirror);
        assert!(d1.x < d0.x, "{d0} {d1}");
        assert!(s1.x > 5.0 * s0.x, "the coat's mirror highlight: {s0} {s1}");
        // Seen along the normal, away from the highlight, the coat only dims (its share,
        // 4%, emission included).
        let (d2, s2) = metallic_roughness(&coat, &l, Viewer::Point(Vec3::Z));
        let (d3, s3) = metallic_roughness(&base, &l, Viewer::Point(Vec3::Z));
        assert!((d2.x / d3.x - 0.96).abs() < 1e-3, "{d2} {d3}");
        assert!(s2.x < s3.x + 1e-3, "{s2} {s3}");
    }

    #[test]
    fn sheen_brightens_grazing_views_more_than_head_on() {
        // Under a uniform light a dark base gains `E·(1 − its own albedo)`, and the sheen's
        // albedo E grows towards grazing views.
        use crate::shading::lobes::Lobes;
        let l = lit(&[], 1.0);
        let base = surface(0.2, 0.0, 1.0, Vec3::Z);
        let sheen = with_lobes(
            base,
            Lobes {
                sheen_color: Vec3::ONE,
                sheen_roughness: 0.5,
                ..Default::default()
            },
        );
        let gain = |eye: Vec3| value(&sheen, &l, eye).x - value(&base, &l, eye).x;
        let head_on = gain(Vec3::Z);
        let grazing = gain(Vec3::new(0.0, -0.95, 0.3));
        assert!(grazing > head_on && head_on > 0.0, "{head_on} {grazing}");
    }
}
