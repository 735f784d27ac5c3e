//! `[[lights]]` → [`Light`]: `color × intensity` is the light's colour, in the Phong model's
//! units (a light of 1 lights a white surface facing it with K_D = 1 to 1). A file without
//! lights gets the peers' directional light from (0.3, 0.8, 0.5), colour 1, for its surfaces.
//! Lights with `shadows = true` cast, with the `[shadows]` table's parameters ([`shadows`]).

use glam::Vec3;

use super::spec::{LightSpec, ShadowsSpec};
use crate::shading::shadow::{ShadowFilter, ShadowParams, Shadows};
use crate::shading::Light;

/// The light a `[[lights]]` entry describes.
pub(super) fn light(l: &LightSpec) -> Light {
    match *l {
        LightSpec::Directional {
            direction,
            color,
            intensity,
            ..
        } => Light::Directional {
            direction: Vec3::from(direction),
            color: Vec3::from(color) * intensity,
        },
        LightSpec::Point {
            position,
            color,
            intensity,
            range,
            ..
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
            ..
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

/// Which lights cast (`shadows = true`) and the `[shadows]` table's parameters over the
/// defaults. A `[shadows]` table without a casting light is an error (it would never be read).
pub(super) fn shadows(
    table: Option<&ShadowsSpec>,
    lights: &[LightSpec],
) -> std::result::Result<Shadows, String> {
    let casting: Vec<usize> = (0..lights.len()).filter(|&i| lights[i].casts()).collect();
    let Some(t) = table else {
        return Ok(Shadows::casting(casting));
    };
    if casting.is_empty() {
        return Err(
            "shadows: no light casts (set shadows = true on a [[lights]] entry)".to_string(),
        );
    }
    let mut p = ShadowParams::default();
    if let Some(n) = t.map_size {
        p.map_size = n;
    }
    if let Some(f) = &t.filter {
        p.filter = ShadowFilter::parse(f).map_err(|e| format!("shadows: filter \"{f}\": {e}"))?;
    }
    for (v, to) in [
        (t.bias, &mut p.bias),
        (t.slope_bias, &mut p.slope_bias),
        (t.normal_offset, &mut p.normal_offset),
        (t.light_angle, &mut p.light_angle),
        (t.light_radius, &mut p.light_radius),
    ] {
        if let Some(v) = v {
            *to = v;
        }
    }
    p.validate().map_err(|e| format!("shadows: {e}"))?;
    Ok(Shadows::casting(casting).with_params(p))
}
