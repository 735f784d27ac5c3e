//! Bump mapping: the normal tilted by the gradient of a height field, one rule for both
//! sources of height — `N' = normalize(N − ∇ₛh)`, where `∇ₛh` is the height's gradient
//! along the surface (its world gradient with the normal component removed). Heights are
//! lengths along the normal (a displacement that is only shaded, never moved).
//!
//! - Image heights (`MapChannel::Bump`): Mikkelsen's screen-space surface gradient ("Bump
//!   Mapping Unparametrized Surfaces on the GPU", 2010), which needs no tangents: from the
//!   screen derivatives of the position `σx = ∂P/∂x`, `σy = ∂P/∂y` and of the height,
//!   `R1 = σy × N`, `R2 = N × σx`, `det = σx·R1`, and
//!   `∇ₛh·det = sign(det)(∂h/∂x·R1 + ∂h/∂y·R2)`, so `N' = normalize(|det|·N − that)`.
//!   The height's screen derivatives come from two extra reads per pixel, one pixel
//!   footprint along x and along y in texture space (see `render`), not from differences
//!   across the 2×2 quad, so the tilt is smooth per pixel when the texture is magnified.
//! - Solid textures: the pattern's analytic gradient ([`Solid::value_and_gradient`]),
//!   taken to world space by the normal matrix, then projected onto the surface.
//!
//! [`Solid::value_and_gradient`]: crate::texture::procedural::Solid::value_and_gradient

use glam::{Vec2, Vec3};

/// The normal `n` (unit) tilted by a height whose screen derivatives are
/// `dh = (∂h/∂x, ∂h/∂y)`, on a surface whose position has screen derivatives `dp_dx`, `dp_dy`
/// (Mikkelsen's surface gradient). Returns `n` unchanged where the derivatives are degenerate.
#[inline]
#[must_use]
pub fn tilt_screen_space(n: Vec3, dp_dx: Vec3, dp_dy: Vec3, dh: Vec2) -> Vec3 {
    let r1 = dp_dy.cross(n);
    let r2 = n.cross(dp_dx);
    let det = dp_dx.dot(r1);
    if !(det.abs() > f32::MIN_POSITIVE) || !det.is_finite() {
        return n;
    }
    let grad = (r1 * dh.x + r2 * dh.y) * det.signum();
    (n * det.abs() - grad).try_normalize().unwrap_or(n)
}

/// The normal `n` (unit) tilted by a height whose world-space gradient is `grad`: the
/// gradient's component along the surface, `grad − (grad·n)n`, is subtracted.
#[inline]
#[must_use]
pub fn tilt_by_gradient(n: Vec3, grad: Vec3) -> Vec3 {
    let along_surface = grad - n * grad.dot(n);
    (n - along_surface).try_normalize().unwrap_or(n)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_ramp_on_a_plane_tilts_the_normal_like_the_sloped_plane() {
        // z = 0 seen from above, 0.01 world units per pixel in x and 0.02 in y (screen y
        // down = world −y here); height h = 0.5·x has ∂h/∂x = 0.5·0.01 per pixel.
        let n = Vec3::Z;
        let (dp_dx, dp_dy) = (Vec3::X * 0.01, Vec3::NEG_Y * 0.02);
        let dh = Vec2::new(0.5 * 0.01, 0.0);
        let tilted = tilt_screen_space(n, dp_dx, dp_dy, dh);
        // The surface z = 0.5·x has the normal (−0.5, 0, 1)/|…|.
        let expected = Vec3::new(-0.5, 0.0, 1.0).normalize();
        assert!((tilted - expected).length() < 1e-5, "{tilted}");
        // The same slope along y (screen y runs along world −y: ∂h/∂y = −0.3·0.02).
        let tilted = tilt_screen_space(n, dp_dx, dp_dy, Vec2::new(0.0, -0.3 * 0.02));
        let expected = Vec3::new(0.0, -0.3, 1.0).normalize();
        assert!((tilted - expected).length() < 1e-5, "{tilted}");
    }

    #[test]
    fn screen_space_and_gradient_tilts_agree_and_ignore_the_normal_component() {
        let n = Vec3::new(0.3, 0.5, 0.8).normalize();
        let t = n.any_orthonormal_vector();
        let b = n.cross(t);
        let (dp_dx, dp_dy) = (t * 0.02 + b * 0.005, b * -0.03 + t * 0.004);
        let grad = t * 0.7 - b * 0.2 + n * 5.0;
        let dh = Vec2::new(grad.dot(dp_dx), grad.dot(dp_dy));
        let a = tilt_screen_space(n, dp_dx, dp_dy, dh);
        let g = tilt_by_gradient(n, grad);
        assert!((a - g).length() < 1e-4, "{a} vs {g}");
        assert!((g - (n - t * 0.7 + b * 0.2).normalize()).length() < 1e-5);
    }

    #[test]
    fn flat_heights_and_degenerate_derivatives_keep_the_normal() {
        let n = Vec3::Y;
        assert_eq!(tilt_screen_space(n, Vec3::X, Vec3::Z, Vec2::ZERO), n);
        assert_eq!(tilt_screen_space(n, Vec3::X, Vec3::X, Vec2::ONE), n);
        assert_eq!(tilt_by_gradient(n, Vec3::Y * 3.0), n);
    }
}
