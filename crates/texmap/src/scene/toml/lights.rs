//! `[[lights]]` → [`Light`]: `color × intensity` is the light's colour, in the Phong model's
//! units (a light of 1 lights a white surface facing it with K_D = 1 to 1). A file without
//! lights gets the peers' directional light from (0.3, 0.8, 0.5), colour 1, for its surfaces.

use glam::Vec3;

use super::spec::LightSpec;
use crate::shading::Light;

/// The light a `[[lights]]` entry describes.
pub(super) fn light(l: &LightSpec) -> Light {
    match *l {
        LightSpec::Directional {
            direction,
            color,
            intensity,
        } => Light::Directional {
            direction: Vec3::from(direction),
            color: Vec3::from(color) * intensity,
        },
        LightSpec::Point {
            position,
            color,
            intensity,
            range,
        } => Light::Point {
            position: Vec3::from(position),
            color: Vec3::from(color) * intensity,
            range,
        },
        LightSpec::Spot {
            position,
            direction,
            color,
            intensity,
            inner_deg,
            outer_deg,
        } => Light::Spot {
            position: Vec3::from(position),
            direction: Vec3::from(direction),
            color: Vec3::from(color) * intensity,
            inner_deg,
            outer_deg,
        },
    }
}

/// The peers' light, for a file that defines none.
pub(super) fn default_light() -> Light {
    Light::Directional {
        direction: Vec3::new(0.3, 0.8, 0.5).normalize(),
        color: Vec3::ONE,
    }
}
