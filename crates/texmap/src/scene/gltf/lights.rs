//! Lighting of glTF scenes: `KHR_lights_punctual` lights, the ambient light, and the light
//! a file without lights gets.
//!
//! glTF has no ambient light, and its models are shown in image-based light, which texmap
//! does not have; a uniform environment stands in for it. `I_AL` is 1.5, so with every
//! loader's K_A = 0.2 the environment is 0.3: enough for metals, which reflect nothing else
//! but their highlights, to show their colour, little enough for the light to model the
//! shapes. Without lights in the file, the peer's direction (0.3, 0.8, 0.5) is used with
//! colour 0.7, so a rough white dielectric facing it reflects 0.3 + 0.7·(1 − F) ≈ 0.97, as
//! the peer's 0.2 + 0.8 reaches 1 (chosen by eye against the models' screenshots among
//! environment/light splits 0.2/1, 0.3/0.7, 0.5/0.5 and 0.8/0.5).
//!
//! `KHR_lights_punctual` intensities (lux for directional lights, candela for point and
//! spot lights) are divided by π: texmap's light units are those of the Phong model (see
//! `shading::pbr`), so a file's lights give the image the glTF sample viewer gives without
//! exposure or tone mapping. A light shines down its node's −Z.

use glam::{Mat4, Vec3};

use crate::shading::Light;

/// `I_AL` of glTF scenes (module docs).
pub(super) const AMBIENT_LIGHT: f32 = 1.5;

/// The colour of the default directional light of glTF scenes without lights.
const DEFAULT_SUN: f32 = 0.7;

/// The light of a node whose world matrix is `world`.
pub(super) fn light(light: &gltf::khr_lights_punctual::Light, world: Mat4) -> Light {
    // Lux and candela to texmap's units (module docs).
    let color = Vec3::from(light.color()) * (light.intensity() / std::f32::consts::PI);
    let position = world.transform_point3(Vec3::ZERO);
    let dir = world.transform_vector3(-Vec3::Z).normalize_or(-Vec3::Z);
    match light.kind() {
        gltf::khr_lights_punctual::Kind::Directional => Light::Directional {
            direction: -dir,
            color,
        },
        gltf::khr_lights_punctual::Kind::Point => Light::Point {
            position,
            color,
            range: light.range(),
        },
        gltf::khr_lights_punctual::Kind::Spot {
            inner_cone_angle,
            outer_cone_angle,
        } => Light::Spot {
            position,
            direction: dir,
            color,
            inner_deg: inner_cone_angle.to_degrees(),
            outer_deg: outer_cone_angle.to_degrees(),
        },
    }
}

/// The light of a file without lights (module docs).
pub(super) fn default_light() -> Light {
    Light::Directional {
        direction: Vec3::new(0.3, 0.8, 0.5).normalize(),
        color: Vec3::splat(DEFAULT_SUN),
    }
}
