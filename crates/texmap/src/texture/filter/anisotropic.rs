//! Anisotropic filtering: trilinear taps spread along the footprint's major axis.
//!
//! The footprint's ellipse comes from the derivatives (its axes are the singular vectors of
//! the Jacobian, not just the longer derivative as in the GL extension's sketch). With the
//! major semi-axis σ₁ and minor σ₂ in texels, `N = min(⌈σ₁/σ₂⌉, max_aniso)` taps sit at the
//! centres of N equal segments of the major axis, each a trilinear read at λ = log2(σ₁/N), so
//! together they cover the footprint without gaps; when the ratio exceeds `max_aniso` the level
//! rises and the image blurs instead of aliasing, as the extension specifies.

use glam::Vec2;
use glam::Vec4;

use super::{bilinear, ellipse_axes, texel_derivatives, trilinear_at, Codec};
use crate::texture::{Footprint, MipChoice, Sampler, Texture2D};

pub(crate) fn sample<C: Codec>(
    tex: &Texture2D,
    s: &Sampler,
    fp: &Footprint,
    max_aniso: u32,
) -> Vec4 {
    let (dx, dy) = texel_derivatives(tex, fp);
    let (major_dir, major, minor) = ellipse_axes(dx, dy);
    let max_aniso = max_aniso.clamp(1, 16) as f32;
    let ratio = if minor > 0.0 {
        major / minor
    } else {
        f32::INFINITY
    };
    let n = ratio.ceil().clamp(1.0, max_aniso);
    let lod = s.adjust_lod(crate::texture::footprint::fast_log2(major / n));
    if !(major > 1.0) || !(lod > 0.0) && n == 1.0 {
        // Magnification: the footprint is smaller than a texel.
        return bilinear::<C>(&tex.level(0), s, fp.uv);
    }
    if !major.is_finite() {
        return trilinear_at::<C>(tex, s, fp.uv, lod);
    }
    let size = Vec2::new(tex.width() as f32, tex.height() as f32);
    let axis_uv = major_dir * major / size;
    let taps = n as u32;
    // Every tap reads the same levels: choose them once.
    let choice = MipChoice::trilinear(lod, tex.levels().len());
    let first = tex.level(choice.level);
    let second = choice.blend.map(|b| (tex.level(b.level), b.weight));
    let mut sum = Vec4::ZERO;
    for i in 0..taps {
        let t = (i as f32 + 0.5) / n - 0.5;
        let uv = fp.uv + axis_uv * t;
        let a = bilinear::<C>(&first, s, uv);
        sum += match second {
            Some((lv, weight)) => a.lerp(bilinear::<C>(&lv, s, uv), weight),
            None => a,
        };
    }
    sum / n
}
