//! Shading: materials, lights and the illumination models — Phong (here) and glTF's
//! metallic-roughness BRDF ([`pbr`]), chosen per material by [`ShadingModel`].
//!
//! The fragment stage builds a [`Surface`] per pixel — the material's parameters after its
//! maps (normal, bump, metallic-roughness, occlusion, emissive, solid textures) — and hands
//! it to [`illuminate`]; Gouraud and flat shading build it per vertex or per face from the
//! material alone.
//!
//! The Phong rule, for a surface point with unit normal `N`, unit direction to the viewer `V`, and
//! for each light `i` the unit direction `L_i` towards it and the reflection
//! `R_i = 2(N·L_i)N − L_i`:
//!
//! ```text
//! I = I_E + K_A·C·I_AL + Σ_i (K_D·C·max(N·L_i, 0) + K_S·max(V·R_i, 0)^n)·S_i·I_i
//! ```
//!
//! `C` is the surface colour (base colour × texture × vertex colour): the texture modulates
//! the ambient and diffuse terms, never the specular one. The specular term is only added where
//! `N·L_i > 0`. `S_i` is the light's attenuation: 1 for directional lights, inverse square
//! distance (windowed by `range` as in `KHR_lights_punctual`) for point lights, and the same
//! times a smooth cone falloff for spot lights; for a light that casts shadows, times the
//! fraction of it its shadow maps let through ([`shadow`], [`Lighting::shadows`]).
//!
//! [`illuminate`] returns the two factors `(D, S)` such that `I = C·D + S`, so Gouraud and flat
//! shading can compute them per vertex or per face and the texture is still applied per pixel.
//! Occlusion `O` scales the ambient term: `K_A·O·C·I_AL`.
//!
//! Files: `material.rs` (what a surface is made of), `light.rs` (lights and what they deliver
//! at a point), this file (the per-pixel [`Surface`], Phong, [`combine`]), [`pbr`] (the
//! metallic-roughness BRDF), [`lobes`] and [`sheen`] (glTF's specular, clearcoat, sheen and
//! volume extensions over it), [`lanes`] (Phong for a quad's four pixels at once), [`mr_lanes`] (the
//! metallic-roughness model likewise), [`bump`]
//! (tilting normals by height gradients), [`shadow`] (shadow-map lookups and filters) and
//! `viewer.rs` (where the viewer is), [`layers`] (texture layers: OpenGL's texture
//! environment) and [`toon`] (ramp-shaded diffuse, outlines).

mod albedo;
pub mod bump;
pub mod ibl;
pub mod lanes;
pub mod layers;
mod light;
pub mod lobes;
mod material;
pub mod mr_lanes;
pub mod pbr;
mod projector;
pub mod relief;
pub mod shadow;
pub mod sheen;
pub mod toon;
mod viewer;
pub(crate) mod wide;

use glam::{Vec3, Vec4};

pub use light::{Light, Lighting};
pub use material::{
    AlphaMode, MapChannel, Material, MaterialMap, Procedural, ShadingModel, SolidChannel, SolidMap,
    TextureSlot,
};
pub use projector::{Projector, ProjectorView};
pub use viewer::Viewer;

/// What the illumination models read at one surface point: the material's parameters after
/// its maps, the position and the normal. The fragment stage makes one per pixel from a
/// per-draw copy of [`Surface::new`] (no allocation, no material clone).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Surface {
    /// World position (read by point and spot lights and by specular terms).
    pub position: Vec3,
    /// Unit world normal (after normal and bump maps; towards the viewer on double-sided
    /// back faces).
    pub normal: Vec3,
    /// Linear RGB, straight alpha: the colour `C` (which [`combine`] applies through
    /// `I = C·D + S`), read by the metallic-roughness model for the `f0` of metals.
    pub base_color: Vec3,
    /// K_A.
    pub ambient: f32,
    /// K_D.
    pub diffuse: f32,
    /// K_S.
    pub specular: f32,
    /// The Phong exponent n.
    pub shininess: f32,
    pub metallic: f32,
    pub roughness: f32,
    /// Ambient occlusion: 1 = none, 0 = no ambient light reaches the point.
    pub occlusion: f32,
    /// I_E.
    pub emissive: Vec3,
    /// Tint of the Phong specular term (OBJ `map_Ks`; white otherwise).
    pub specular_color: Vec3,
    /// The ambient term's own colour (OBJ `map_Ka`): when set, the ambient light reflects
    /// `K_A·O·I_AL·ambient_color` instead of modulating the surface colour `C`.
    pub ambient_color: Option<Vec3>,
    /// Index of refraction (dielectric f0 and refraction; 1.5 by default).
    pub ior: f32,
    /// glTF's extension lobes after their maps ([`lobes`]); the thickness in world units.
    pub lobes: lobes::Lobes,
    /// The clearcoat's unit world normal (its own normal map's, else the geometric normal
    /// before the base's normal map); zero: the surface normal.
    pub clearcoat_normal: Vec3,
}

impl Surface {
    /// The material's own parameters (no maps) at `position` with unit `normal`; the base
    /// colour is the material's factor.
    #[must_use]
    pub fn new(m: &Material, position: Vec3, normal: Vec3) -> Self {
        Surface {
            position,
            normal,
            base_color: m.base_color.truncate(),
            ambient: m.ambient,
            diffuse: m.diffuse,
            specular: m.specular,
            shininess: m.shininess,
            metallic: m.metallic,
            roughness: m.roughness,
            occlusion: 1.0,
            emissive: m.emissive,
            specular_color: Vec3::ONE,
            ambient_color: None,
            ior: m.ior,
            lobes: m.lobes,
            clearcoat_normal: Vec3::ZERO,
        }
    }
}

/// The Phong exponent equivalent to a roughness: `n = 2/α² − 2` with α = roughness² (the
/// usual Beckmann–Blinn correspondence), at least 1.
#[inline]
#[must_use]
pub fn shininess_from_roughness(roughness: f32) -> f32 {
    let a = pbr::alpha(roughness);
    (2.0 / (a * a) - 2.0).max(1.0)
}

/// The factors `(D, S)` of `model` at surface point `s`, seen by `viewer`: the lit colour is
/// `C·D + S` (see the module docs and [`pbr`]).
#[inline(always)]
#[must_use]
pub fn illuminate(
    model: ShadingModel,
    s: &Surface,
    lighting: &Lighting,
    viewer: Viewer,
) -> (Vec3, Vec3) {
    match model {
        ShadingModel::Phong => phong(s, lighting, viewer),
        ShadingModel::MetallicRoughness => pbr::metallic_roughness(s, lighting, viewer),
    }
}

/// The Phong factors `(D, S)` (the module docs' rule).
#[inline(always)]
#[must_use]
pub fn phong(s: &Surface, lighting: &Lighting, viewer: Viewer) -> (Vec3, Vec3) {
    let (p, n) = (s.position, s.normal);
    let ambient = lighting.ambient * (s.ambient * s.occlusion);
    let (mut d, mut sp) = match s.ambient_color {
        None => (ambient, s.emissive),
        Some(a) => (Vec3::ZERO, s.emissive + ambient * a),
    };
    let specular = s.specular > 0.0;
    let v = if specular {
        viewer.towards(p)
    } else {
        Vec3::ZERO
    };
    for (i, light) in lighting.lights.iter().enumerate() {
        let Some((l, mut intensity)) = light.incidence(p) else {
            continue;
        };
        let n_dot_l = n.dot(l);
        if n_dot_l <= 0.0 {
            continue;
        }
        if let Some(shadows) = lighting.shadows {
            intensity *= shadows.visibility(i, p, n, l);
        }
        d += intensity * (s.diffuse * n_dot_l);
        if specular {
            let r = n * (2.0 * n_dot_l) - l;
            let r_dot_v = r.dot(v);
            if r_dot_v > 0.0 {
                sp += intensity * s.specular_color * (s.specular * r_dot_v.powf(s.shininess));
            }
        }
    }
    (d, sp)
}

/// Combines a premultiplied surface colour `c` with the Phong factors and the material's
/// alpha mode: returns premultiplied RGBA, or `None` when an alpha-tested fragment is
/// discarded.
#[inline]
#[must_use]
pub fn combine(alpha_mode: AlphaMode, c: Vec4, d: Vec3, s: Vec3) -> Option<Vec4> {
    let a = c.w;
    match alpha_mode {
        AlphaMode::Blend => {
            let rgb = c.truncate() * d + s * a;
            Some(rgb.extend(a))
        }
        AlphaMode::Opaque | AlphaMode::Mask(_) => {
            if let AlphaMode::Mask(cutoff) = alpha_mode {
                if !(a >= cutoff) {
                    return None;
                }
            }
            let straight = if a > 0.0 && a != 1.0 {
                c.truncate() / a
            } else {
                c.truncate()
            };
            Some((straight * d + s).extend(1.0))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lighting(lights: &[Light]) -> Lighting<'_> {
        Lighting {
            lights,
            ambient: Vec3::ONE,
            shadows: None,
        }
    }

    #[test]
    fn peers_plane_factor_is_0_8465() {
        let light = [Light::Directional {
            direction: Vec3::new(0.3, 0.8, 0.5),
            color: Vec3::ONE,
        }];
        let surface = Surface::new(&Material::default(), Vec3::ZERO, Vec3::Y);
        let (d, s) = illuminate(
            ShadingModel::Phong,
            &surface,
            &lighting(&light),
            Viewer::Point(Vec3::Y),
        );
        assert!((d - Vec3::splat(0.84650)).abs().max_element() < 1e-5, "{d}");
        assert_eq!(s, Vec3::ZERO);
    }

    #[test]
    fn specular_peaks_on_the_mirror_direction() {
        let m = Material {
            specular: 1.0,
            shininess: 10.0,
            ..Default::default()
        };
        let light = [Light::Directional {
            direction: Vec3::new(1.0, 1.0, 0.0),
            color: Vec3::ONE,
        }];
        let l = lighting(&light);
        let s = Surface::new(&m, Vec3::ZERO, Vec3::Y);
        let eye = |x: f32| Viewer::Point(Vec3::new(x, 1.0, 0.0));
        let (_, on) = illuminate(ShadingModel::Phong, &s, &l, eye(-1.0));
        let (_, off) = illuminate(ShadingModel::Phong, &s, &l, eye(1.0));
        assert!((on.x - 1.0).abs() < 1e-5 && off.x < 1e-3, "{on} {off}");
        // An orthographic viewer along the mirror direction sees the peak at every point.
        let ortho = Viewer::Direction(Vec3::new(-1.0, 1.0, 0.0).normalize());
        for p in [Vec3::ZERO, Vec3::new(5.0, 0.0, -3.0)] {
            let (_, s) = illuminate(
                ShadingModel::Phong,
                &Surface::new(&m, p, Vec3::Y),
                &l,
                ortho,
            );
            assert!((s.x - 1.0).abs() < 1e-5, "{p} {s}");
        }
    }

    #[test]
    fn point_light_is_inverse_square_and_spot_has_a_cone() {
        let p = Light::Point {
            position: Vec3::new(0.0, 2.0, 0.0),
            color: Vec3::ONE,
            range: None,
        };
        let (l, i) = p.incidence(Vec3::ZERO).unwrap();
        assert!((l - Vec3::Y).length() < 1e-6 && (i.x - 0.25).abs() < 1e-6);
        let spot = Light::Spot {
            position: Vec3::new(0.0, 1.0, 0.0),
            direction: -Vec3::Y,
            color: Vec3::ONE,
            inner_deg: 10.0,
            outer_deg: 20.0,
        };
        assert!(spot.incidence(Vec3::ZERO).is_some());
        assert!(spot.incidence(Vec3::new(1.0, 0.0, 0.0)).is_none());
    }

    #[test]
    fn mask_discards_below_cutoff_and_blend_premultiplies() {
        let c = Vec4::new(0.25, 0.25, 0.25, 0.5);
        assert!(combine(AlphaMode::Mask(0.6), c, Vec3::ONE, Vec3::ZERO).is_none());
        let o = combine(AlphaMode::Mask(0.4), c, Vec3::ONE, Vec3::ZERO).unwrap();
        assert_eq!(o, Vec4::new(0.5, 0.5, 0.5, 1.0));
        let b = combine(AlphaMode::Blend, c, Vec3::ONE, Vec3::ZERO).unwrap();
        assert_eq!(b, c);
    }
}
