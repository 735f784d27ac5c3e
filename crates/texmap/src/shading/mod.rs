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
//! times a smooth cone falloff for spot lights.
//!
//! [`illuminate`] returns the two factors `(D, S)` such that `I = C·D + S`, so Gouraud and flat
//! shading can compute them per vertex or per face and the texture is still applied per pixel.
//! Occlusion `O` scales the ambient term: `K_A·O·C·I_AL`.

pub mod bump;
pub mod lanes;
pub mod pbr;
mod viewer;

use std::sync::Arc;

use glam::{Vec3, Vec4};

use crate::geometry::Projection;
use crate::texture::procedural::Solid;
use crate::texture::{Sampler, Texture2D, Texture3D, TextureTransform};

pub use viewer::Viewer;

/// A texture bound to a material: the image, how it is read, and the uv transform.
///
/// The uv used for sampling is `transform.apply(uv) · uv_scale`.
#[derive(Clone, Debug)]
pub struct TextureSlot {
    pub texture: Arc<Texture2D>,
    pub sampler: Sampler,
    pub transform: TextureTransform,
    pub uv_scale: f32,
    /// Which texture coordinate set the slot reads: 0 (`Mesh::uvs`) or 1 (`Mesh::uvs1`).
    pub tex_coord: u32,
}

impl TextureSlot {
    /// A slot with the identity transform and a uv scale of 1.
    #[must_use]
    pub fn new(texture: Arc<Texture2D>, sampler: Sampler) -> Self {
        TextureSlot {
            texture,
            sampler,
            transform: TextureTransform::default(),
            uv_scale: 1.0,
            tex_coord: 0,
        }
    }
}

/// A colour computed from the surface point rather than read through the mesh's UVs. It
/// multiplies the base colour (and the base-colour texture, if any), like a texture.
#[derive(Clone, Debug)]
pub enum Procedural {
    /// A solid texture evaluated at the object-space position: the object looks carved from
    /// the block, and the pattern moves with it. With `antialias`, the pattern is box-filtered
    /// over the pixel's footprint (|∂P/∂x| + |∂P/∂y|); without, it is point-sampled.
    Solid {
        solid: Solid,
        /// Linear RGB for pattern values 0 and 1.
        colors: [Vec3; 2],
        antialias: bool,
    },
    /// An image texture whose coordinates a projection generates per pixel from the
    /// object-space position (and normal, for cube faces and cylinder caps), with analytic
    /// derivatives for the footprint — no seam where u wraps. A bounding-sphere projection
    /// whose centre is not finite (NaN) is centred on each mesh's bounding box.
    Projected {
        slot: TextureSlot,
        projection: Projection,
    },
    /// A 3D texture (the texture engine's [`Texture3D`]) as a solid texture: the object-space
    /// box `[min, max]` maps onto the texture's unit cube, `uvw = (P − min)/(max − min)`, read
    /// through `sampler` over the pixel's footprint (∂uvw/∂x, ∂uvw/∂y from the position's
    /// derivatives: trilinear with mip levels, as [`crate::texture::sample_3d`]). The red
    /// channel (a scan's value, a baked pattern) is mapped through `colors` (0 → first,
    /// 1 → second); the ramp is linear, so filtering the values equals filtering the colours.
    Texture3D {
        texture: Arc<Texture3D>,
        sampler: Sampler,
        min: Vec3,
        max: Vec3,
        colors: [Vec3; 2],
    },
}

/// How a material's alpha is used (glTF's `alphaMode`).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub enum AlphaMode {
    /// Alpha is ignored and written as 1.
    #[default]
    Opaque,
    /// Fragments with alpha below the cutoff are discarded; the others are opaque.
    Mask(f32),
    /// Premultiplied "over" blending, drawn after every opaque surface, back to front.
    Blend,
}

/// Which reflection model lights a material.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum ShadingModel {
    /// The Phong model of the module docs: K_A, K_D, K_S and the exponent n.
    #[default]
    Phong,
    /// glTF's metallic-roughness BRDF ([`pbr`]): base colour, metallic and roughness (K_A
    /// still scales the ambient term; K_D, K_S and n are not used).
    MetallicRoughness,
}

/// A solid texture feeding a material channel other than the colour, evaluated at the
/// object-space position like [`Procedural::Solid`], with the same footprint filtering.
#[derive(Clone, Debug, PartialEq)]
pub struct SolidMap {
    pub solid: Solid,
    pub channel: SolidChannel,
    /// Filter the pattern (and its gradient) over the pixel's footprint.
    pub antialias: bool,
}

/// What a [`SolidMap`] feeds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SolidChannel {
    /// Roughness = `range[0] + (range[1] − range[0])·value`, replacing the factor. Phong
    /// materials take it as the exponent `n = 2/α² − 2` (α = roughness², at least 1).
    Roughness { range: [f32; 2] },
    /// A height field `scale·value` in object units: the normal is tilted by the pattern's
    /// analytic gradient projected onto the surface.
    Bump { scale: f32 },
}

/// A surface's appearance: Phong coefficients, base colour and its texture.
#[derive(Clone, Debug)]
pub struct Material {
    /// The reflection model (Phong by default; glTF materials are metallic-roughness).
    pub model: ShadingModel,
    /// Linear RGBA, straight (not premultiplied) alpha.
    pub base_color: Vec4,
    pub base_color_texture: Option<TextureSlot>,
    /// K_A: the fraction of the ambient light reflected.
    pub ambient: f32,
    /// K_D: the diffuse reflection coefficient.
    pub diffuse: f32,
    /// K_S: the specular reflection coefficient.
    pub specular: f32,
    /// n: the Phong exponent.
    pub shininess: f32,
    /// I_E: linear light emitted by the surface.
    pub emissive: Vec3,
    /// When true, the colour is the surface colour `C` and lights are ignored.
    pub unlit: bool,
    /// When false, back faces may be culled (see `render::CullMode`); when true their normal
    /// is flipped towards the viewer before lighting.
    pub double_sided: bool,
    pub alpha_mode: AlphaMode,
    /// A procedural colour (solid texture or projected image), multiplying the base colour.
    pub procedural: Option<Procedural>,
    /// glTF's metallic factor (0 = dielectric), for metallic-roughness shading.
    pub metallic: f32,
    /// glTF's roughness factor (α = roughness²).
    pub roughness: f32,
    /// Texture maps other than the base colour (normal, occlusion, emissive, …), each with
    /// its channel and scale. The renderer reads the channels it implements.
    pub maps: Vec<MaterialMap>,
    /// Solid textures on channels other than the colour (roughness, bump height).
    pub solid_maps: Vec<SolidMap>,
}

/// What a [`MaterialMap`] feeds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MapChannel {
    /// glTF metallic (B) and roughness (G), linear.
    MetallicRoughness,
    /// Tangent-space normal map, linear; `scale` scales its x and y.
    Normal,
    /// Ambient occlusion (R), linear; `scale` is the strength.
    Occlusion,
    /// Emissive colour, sRGB; multiplies `Material::emissive`.
    Emissive,
    /// OBJ `map_Ka`: ambient colour, sRGB.
    Ambient,
    /// OBJ `map_Ks`: specular colour, sRGB.
    Specular,
    /// OBJ `map_Ns`: specular exponent (R), linear.
    Shininess,
    /// OBJ `map_d`: opacity (R, or alpha when present), linear.
    Alpha,
    /// OBJ `bump`/`map_bump`: a height field, linear; `scale` is `-bm`.
    Bump,
}

impl MapChannel {
    /// The lower-case name used in scene files and by `texmap info`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            MapChannel::MetallicRoughness => "metallic_roughness",
            MapChannel::Normal => "normal",
            MapChannel::Occlusion => "occlusion",
            MapChannel::Emissive => "emissive",
            MapChannel::Ambient => "ambient",
            MapChannel::Specular => "specular",
            MapChannel::Shininess => "shininess",
            MapChannel::Alpha => "alpha",
            MapChannel::Bump => "bump",
        }
    }

    /// True for channels that hold colour (decoded from sRGB); the others hold linear data.
    #[must_use]
    pub fn is_color(self) -> bool {
        matches!(
            self,
            MapChannel::Emissive | MapChannel::Ambient | MapChannel::Specular
        )
    }
}

/// A texture map of a material other than the base colour.
#[derive(Clone, Debug)]
pub struct MaterialMap {
    pub channel: MapChannel,
    pub slot: TextureSlot,
    /// Normal scale, occlusion strength or bump multiplier (1 otherwise).
    pub scale: f32,
}

impl Material {
    /// The first map feeding `channel`, if any.
    #[must_use]
    pub fn map(&self, channel: MapChannel) -> Option<&MaterialMap> {
        self.maps.iter().find(|m| m.channel == channel)
    }

    /// The first solid texture on the roughness channel and its range, if any.
    #[must_use]
    pub fn solid_roughness(&self) -> Option<(&SolidMap, [f32; 2])> {
        self.solid_maps.iter().find_map(|m| match m.channel {
            SolidChannel::Roughness { range } => Some((m, range)),
            SolidChannel::Bump { .. } => None,
        })
    }

    /// The first solid texture on the bump channel and its scale, if any.
    #[must_use]
    pub fn solid_bump(&self) -> Option<(&SolidMap, f32)> {
        self.solid_maps.iter().find_map(|m| match m.channel {
            SolidChannel::Bump { scale } => Some((m, scale)),
            SolidChannel::Roughness { .. } => None,
        })
    }
}

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

impl Default for Material {
    /// White, K_A 0.2, K_D 0.8, no specular, opaque, single-sided.
    fn default() -> Self {
        Material {
            base_color: Vec4::ONE,
            base_color_texture: None,
            ambient: 0.2,
            diffuse: 0.8,
            specular: 0.0,
            shininess: 32.0,
            emissive: Vec3::ZERO,
            unlit: false,
            double_sided: false,
            alpha_mode: AlphaMode::Opaque,
            procedural: None,
            metallic: 0.0,
            roughness: 1.0,
            maps: Vec::new(),
            solid_maps: Vec::new(),
            model: ShadingModel::Phong,
        }
    }
}

/// A light source. Colours are linear and may exceed 1 (they are intensities).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Light {
    /// Parallel light; `direction` points *towards* the light.
    Directional { direction: Vec3, color: Vec3 },
    /// Light from a point, attenuated by the inverse square distance; beyond `range` (if any)
    /// it is zero, with `KHR_lights_punctual`'s smooth window.
    Point {
        position: Vec3,
        color: Vec3,
        range: Option<f32>,
    },
    /// A point light restricted to a cone around `direction` (pointing *away* from the light):
    /// full inside `inner_deg`, zero outside `outer_deg`, smooth in between.
    Spot {
        position: Vec3,
        direction: Vec3,
        color: Vec3,
        inner_deg: f32,
        outer_deg: f32,
    },
}

impl Light {
    /// The light with unit direction vectors, or `None` when a direction is zero or not
    /// finite.
    #[must_use]
    pub fn normalized(&self) -> Option<Light> {
        let mut l = *self;
        match &mut l {
            Light::Directional { direction, .. } | Light::Spot { direction, .. } => {
                *direction = direction.try_normalize()?;
            }
            Light::Point { .. } => {}
        }
        Some(l)
    }

    /// The light's direction `L` (unit, towards the light) and `S·I` at world point `p`, or
    /// `None` when it does not reach `p`.
    #[inline(always)]
    #[must_use]
    pub fn incidence(&self, p: Vec3) -> Option<(Vec3, Vec3)> {
        match *self {
            Light::Directional { direction, color } => {
                // Already unit length after `normalized` (the cheap common case).
                let len2 = direction.length_squared();
                if (len2 - 1.0).abs() < 1e-6 {
                    Some((direction, color))
                } else {
                    Some((direction.try_normalize()?, color))
                }
            }
            Light::Point {
                position,
                color,
                range,
            } => {
                let (l, s) = point_falloff(position - p, range)?;
                Some((l, color * s))
            }
            Light::Spot {
                position,
                direction,
                color,
                inner_deg,
                outer_deg,
            } => {
                let (l, s) = point_falloff(position - p, None)?;
                let axis = direction.try_normalize()?;
                let cos_outer = outer_deg.to_radians().cos();
                let cos_inner = inner_deg.to_radians().cos();
                let scale = 1.0 / (cos_inner - cos_outer).max(1e-3);
                let cone = ((-l).dot(axis) - cos_outer) * scale;
                let cone = cone.clamp(0.0, 1.0);
                if cone <= 0.0 {
                    return None;
                }
                Some((l, color * (s * cone * cone)))
            }
        }
    }
}

#[inline]
fn point_falloff(to_light: Vec3, range: Option<f32>) -> Option<(Vec3, f32)> {
    let d2 = to_light.length_squared();
    if !(d2 > 0.0) || !d2.is_finite() {
        return None;
    }
    let d = d2.sqrt();
    let mut s = 1.0 / d2;
    if let Some(r) = range {
        if r > 0.0 {
            let x = (d / r).powi(4);
            let w = (1.0 - x).clamp(0.0, 1.0);
            s *= w * w;
        }
    }
    if s <= 0.0 {
        return None;
    }
    Some((to_light / d, s))
}

/// The lights of a scene and its ambient light, for [`illuminate`].
#[derive(Clone, Copy, Debug)]
pub struct Lighting<'a> {
    pub lights: &'a [Light],
    /// I_AL.
    pub ambient: Vec3,
}

impl Lighting<'_> {
    /// True when some light depends on the surface position (point and spot lights).
    #[must_use]
    pub fn needs_position(&self) -> bool {
        self.lights
            .iter()
            .any(|l| !matches!(l, Light::Directional { .. }))
    }
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
    for light in lighting.lights {
        let Some((l, intensity)) = light.incidence(p) else {
            continue;
        };
        let n_dot_l = n.dot(l);
        if n_dot_l <= 0.0 {
            continue;
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
