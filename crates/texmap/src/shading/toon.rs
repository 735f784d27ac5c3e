//! Toon (cel) shading: each light's diffuse term through a 1D ramp texture, a hard-edged
//! specular highlight, and an optional outline.
//!
//! For each light `i` (direction `L_i`, delivered intensity `S_i·I_i`, shadows included) the
//! diffuse term is `K_D·ramp((N·L_i + 1)/2)·S_i·I_i`: the ramp is indexed half-Lambert, so
//! its left half colours the side turned away from the light and its right half the lit
//! side. The ramp is a texture read through the sampling engine at `(u, 0.5)` with a zero
//! footprint (a lookup table: level 0, the sampler's magnification filter; the coordinate
//! depends on the normal, not on the surface's parameterisation, so it has no uv footprint).
//! Its red, green and blue scale the light's colour. The specular term is Phong's lobe
//! thresholded: `K_S·S_i·I_i` where `(R_i·V)^n ≥ ½` and `N·L_i > 0`, else nothing. Ambient,
//! emission and occlusion are Phong's.
//!
//! The outline is drawn on the surface where it turns away from the viewer: where
//! `|N·V| < w·fwidth(|N·V|)` (`fwidth` = |∂/∂x| + |∂/∂y| over the 2×2 quad, `w` the width in
//! pixels), the pixel takes the outline colour, faded over the last pixel for antialiasing.
//! Its lines are about `w` pixels wide at silhouettes, whatever the distance; creases that
//! do not turn from the viewer are not outlined.

use std::sync::Arc;

use glam::{Vec2, Vec3, Vec4};

use super::{Lighting, Surface, Viewer};
use crate::texture::{sample, Filter, Footprint, Sampler, Texture2D, TextureOptions, Wrap};

/// A toon material's ramp and outline.
#[derive(Clone, Debug)]
pub struct Toon {
    /// The 1D ramp (its middle row is read).
    pub ramp: Arc<Texture2D>,
    pub sampler: Sampler,
    /// "bands N" or the ramp image's file, for `texmap info`.
    pub source: Arc<str>,
    pub outline: Option<Outline>,
}

/// The toon outline: its colour and width.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Outline {
    /// Linear RGB.
    pub color: Vec3,
    /// Pixels.
    pub width: f32,
}

impl Toon {
    /// A built-in ramp of `bands` steps (at least 2): step k of n is `k/(n − 1)`, read
    /// nearest, so the light falls off in hard bands.
    ///
    /// # Panics
    /// Never for `bands` ≥ 1 (a one-texel ramp is a valid texture).
    #[must_use]
    pub fn bands(bands: u32, outline: Option<Outline>) -> Self {
        let n = bands.max(2);
        let ramp = Texture2D::from_fn(
            n,
            1,
            TextureOptions::default().with_mipmaps(false),
            |x, _| {
                let v = x as f32 / (n - 1) as f32;
                Vec4::new(v, v, v, 1.0)
            },
        )
        .expect("a ramp of at least two texels");
        Toon {
            ramp: Arc::new(ramp),
            sampler: ramp_sampler(Filter::NEAREST),
            source: format!("bands {n}").into(),
            outline,
        }
    }

    /// The ramp at `u` in [0, 1] (linear RGB).
    #[inline]
    #[must_use]
    pub fn ramp_at(&self, u: f32) -> Vec3 {
        let fp = Footprint::new(Vec2::new(u.clamp(0.0, 1.0), 0.5), Vec2::ZERO, Vec2::ZERO);
        let t = sample(&self.ramp, &self.sampler, &fp);
        if t.w > 0.0 && t.w != 1.0 {
            t.truncate() / t.w
        } else {
            t.truncate()
        }
    }
}

/// A ramp's sampler: `filter`, clamped to the edge on both axes (a ramp does not repeat).
#[must_use]
pub fn ramp_sampler(filter: Filter) -> Sampler {
    Sampler {
        wrap_u: Wrap::ClampToEdge,
        wrap_v: Wrap::ClampToEdge,
        filter,
        ..Sampler::default()
    }
}

/// The toon factors `(D, S)` of surface `s` (the lit colour is `C·D + S`, as
/// [`super::illuminate`]'s).
#[must_use]
pub fn toon(s: &Surface, toon: &Toon, lighting: &Lighting, viewer: Viewer) -> (Vec3, Vec3) {
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
        if let Some(shadows) = lighting.shadows {
            if n_dot_l > 0.0 {
                intensity *= shadows.visibility(i, p, n, l);
            }
        }
        d += intensity * toon.ramp_at(0.5 * (n_dot_l + 1.0)) * s.diffuse;
        if specular && n_dot_l > 0.0 {
            let r = n * (2.0 * n_dot_l) - l;
            let r_dot_v = r.dot(v);
            if r_dot_v > 0.0 && r_dot_v.powf(s.shininess) >= 0.5 {
                sp += intensity * s.specular_color * s.specular;
            }
        }
    }
    (d, sp)
}

/// The outline's weight at the quad's four pixels (1 = outline colour, 0 = the surface),
/// from `|N·V|` at each (helpers included, for the differences).
#[must_use]
pub fn outline_weights(n_dot_v: [f32; 4], width: f32) -> [f32; 4] {
    let a = n_dot_v.map(f32::abs);
    let fwidth = (a[1] - a[0]).abs() + (a[2] - a[0]).abs();
    a.map(|x| {
        if fwidth <= 0.0 {
            return 0.0;
        }
        // Full colour up to width − 1 pixels from the silhouette, fading over the last one.
        let pixels = x / fwidth;
        (width - pixels).clamp(0.0, 1.0)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shading::{Light, Material};

    #[test]
    fn bands_are_hard_steps_over_half_lambert() {
        let t = Toon::bands(3, None);
        // Three texels over [0, 1]: 0, ½, 1.
        assert_eq!(t.ramp_at(0.1), Vec3::ZERO);
        assert!((t.ramp_at(0.5) - Vec3::splat(0.5)).abs().max_element() < 1e-6);
        assert!((t.ramp_at(0.9) - Vec3::ONE).abs().max_element() < 1e-6);
        let light = [Light::Directional {
            direction: Vec3::Y,
            color: Vec3::ONE,
        }];
        let lighting = Lighting {
            lights: &light,
            ambient: Vec3::ZERO,
            shadows: None,
        };
        let m = Material {
            diffuse: 1.0,
            ..Material::default()
        };
        let at = |n: Vec3| {
            let s = Surface::new(&m, Vec3::ZERO, n.normalize());
            toon(&s, &t, &lighting, Viewer::Point(Vec3::Y)).0.x
        };
        // N·L = 1 and 0.5 are in the top band; 0 in the middle; −1 in the bottom.
        assert_eq!(at(Vec3::Y), 1.0);
        assert_eq!(at(Vec3::new(3f32.sqrt(), 1.0, 0.0)), 1.0);
        assert_eq!(at(Vec3::X), 0.5);
        assert_eq!(at(-Vec3::Y), 0.0);
    }

    #[test]
    fn outline_covers_width_pixels_at_the_silhouette() {
        // |N·V| falls by 0.1 a pixel: 0 at the silhouette.
        let w = outline_weights([0.0, 0.1, 0.1, 0.2], 2.0);
        assert_eq!(w[0], 1.0);
        // 0.1/(0.1 + 0.1) = 0.5 pixel in: still full colour.
        assert_eq!(w[1], 1.0);
        // Far inside: none.
        let far = outline_weights([0.8, 0.9, 0.9, 1.0], 2.0);
        assert_eq!(far, [0.0; 4]);
        // A flat quad (no change) is never outlined.
        assert_eq!(outline_weights([0.0; 4], 2.0), [0.0; 4]);
    }
}
