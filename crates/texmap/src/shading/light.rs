//! Lights: directional, point and spot lights (`KHR_lights_punctual`'s), what each delivers
//! at a point, and a scene's lights with its ambient light.

use glam::Vec3;

use super::shadow::ShadowMaps;

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

    /// The light with unit directions, or what makes it unusable: a number that is not
    /// finite, a zero direction, a negative colour, a range ≤ 0, or spot angles outside
    /// 0 ≤ inner ≤ outer ≤ 90 degrees. Loaders call it so a bad light is an error naming
    /// the file, not a light that silently lights nothing.
    pub fn checked(&self) -> Result<Light, String> {
        let color = match *self {
            Light::Directional { color, .. }
            | Light::Point { color, .. }
            | Light::Spot { color, .. } => color,
        };
        if !color.is_finite() || color.min_element() < 0.0 {
            return Err(format!("colour × intensity {color} must be finite and ≥ 0"));
        }
        if let Light::Point {
            position, range, ..
        } = *self
        {
            if !position.is_finite() {
                return Err(format!("position {position} is not finite"));
            }
            if let Some(r) = range.filter(|r| !(*r > 0.0 && r.is_finite())) {
                return Err(format!("range {r} must be positive"));
            }
        }
        if let Light::Spot {
            position,
            inner_deg,
            outer_deg,
            ..
        } = *self
        {
            if !position.is_finite() {
                return Err(format!("position {position} is not finite"));
            }
            if !(0.0 <= inner_deg && inner_deg <= outer_deg && outer_deg <= 90.0) {
                return Err(format!(
                    "spot angles inner {inner_deg}° and outer {outer_deg}° must satisfy \
                     0 ≤ inner ≤ outer ≤ 90"
                ));
            }
        }
        self.normalized()
            .filter(|l| match *l {
                Light::Directional { direction, .. } | Light::Spot { direction, .. } => {
                    direction.is_finite()
                }
                Light::Point { .. } => true,
            })
            .ok_or_else(|| "direction must be a finite, non-zero vector".to_string())
    }

    /// The light with its colour times `k` (what reaches a point a fraction `k` of it
    /// reaches).
    #[inline]
    #[must_use]
    pub fn scaled(mut self, k: f32) -> Light {
        match &mut self {
            Light::Directional { color, .. }
            | Light::Point { color, .. }
            | Light::Spot { color, .. } => *color *= k,
        }
        self
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

/// The lights of a scene and its ambient light, for [`super::illuminate`].
#[derive(Clone, Copy, Debug)]
pub struct Lighting<'a> {
    pub lights: &'a [Light],
    /// I_AL.
    pub ambient: Vec3,
    /// The shadow maps of the lights that cast (indexed like `lights`): each light's term is
    /// scaled by [`ShadowMaps::visibility`]. `None`: nothing casts.
    pub shadows: Option<&'a ShadowMaps>,
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
