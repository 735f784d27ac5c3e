//! The viewer's camera: orbit about the target, pan across the view, zoom towards the
//! target, and reset to the view `texmap render` would use.
//!
//! Rules: orbiting turns the eye about the camera's `up` through the target (yaw) and about
//! the camera's right axis (pitch), keeping the distance, and stops a degree short of the
//! poles so the view never looks along `up`; panning moves eye and target together so the
//! point under the cursor at the target's depth follows the cursor; zooming scales the
//! eye's distance (perspective) or the visible height (orthographic). After every move the
//! near and far planes are refitted around the scene's bounds (the library's
//! `framing::enclose`, the rule `--eye` follows); the initial view is kept exactly, so a
//! reset gives back `texmap render`'s camera bit for bit.

use glam::{Quat, Vec3};
use texmap::camera::{Camera, CameraProjection};
use texmap::render::framing::enclose;

/// Radians the camera turns per pixel dragged.
pub const ORBIT_PER_PX: f32 = 0.01;
/// Radians an arrow key turns the camera.
pub const ORBIT_PER_KEY: f32 = 0.08;
/// The distance (or visible height) factor of one wheel notch or `+` press (zooming in).
pub const ZOOM_STEP: f32 = 0.9;

/// The closest the orbit comes to either pole, in radians.
const POLE_MARGIN: f32 = 0.017_453_3;

/// `cam` turned about its target: `yaw` about `up`, `pitch` towards `up` (positive raises
/// the eye), the distance kept.
#[must_use]
pub fn orbit(cam: &Camera, yaw: f32, pitch: f32) -> Camera {
    let up = cam.up.normalize();
    let offset = cam.eye - cam.target;
    let dist = offset.length();
    let dir = offset / dist;
    let polar = up.dot(dir).clamp(-1.0, 1.0).acos();
    let wanted = (polar - pitch).clamp(POLE_MARGIN, std::f32::consts::PI - POLE_MARGIN);
    let right = up
        .cross(dir)
        .try_normalize()
        .unwrap_or_else(|| up.any_orthonormal_vector());
    // Rotating `dir` about `right` by a positive angle moves it away from `up`.
    let pitched = Quat::from_axis_angle(right, wanted - polar) * dir;
    let turned = Quat::from_axis_angle(up, yaw) * pitched;
    Camera {
        eye: cam.target + turned * dist,
        ..*cam
    }
}

/// World units a pixel spans at the target's depth, in a view `height_px` pixels high.
#[must_use]
pub fn units_per_pixel(cam: &Camera, height_px: u32) -> f32 {
    let half = match cam.projection {
        CameraProjection::Perspective { fov_y_deg } => {
            (cam.eye - cam.target).length() * (0.5 * fov_y_deg.to_radians()).tan()
        }
        CameraProjection::Orthographic { half_height } => half_height,
    };
    2.0 * half / height_px.max(1) as f32
}

/// `cam` moved across the view so the scene follows a drag of `(dx, dy)` pixels (x right,
/// y down) in a view `height_px` high.
#[must_use]
pub fn pan(cam: &Camera, dx: f32, dy: f32, height_px: u32) -> Camera {
    let s = units_per_pixel(cam, height_px);
    let forward = cam.forward();
    let right = forward.cross(cam.up).normalize();
    let up = right.cross(forward);
    let delta = (-right * dx + up * dy) * s;
    Camera {
        eye: cam.eye + delta,
        target: cam.target + delta,
        ..*cam
    }
}

/// `cam` with its distance to the target (perspective) or its visible height
/// (orthographic) multiplied by `factor` (below 1 zooms in), kept within a sane range.
#[must_use]
pub fn zoom(cam: &Camera, factor: f32) -> Camera {
    match cam.projection {
        CameraProjection::Perspective { .. } => {
            let offset = cam.eye - cam.target;
            let dist = (offset.length() * factor).clamp(1e-4, 1e7);
            Camera {
                eye: cam.target + offset.normalize() * dist,
                ..*cam
            }
        }
        CameraProjection::Orthographic { half_height } => Camera {
            projection: CameraProjection::Orthographic {
                half_height: (half_height * factor).clamp(1e-5, 1e7),
            },
            ..*cam
        },
    }
}

/// The interactive camera: the initial view and where the user has moved it.
#[derive(Clone, Copy, Debug)]
pub struct ViewCamera {
    initial: Camera,
    current: Camera,
    /// The scene's bounds, which near and far enclose after a move (none: an environment
    /// alone, whose planes do not matter).
    bounds: Option<(Vec3, Vec3)>,
}

impl ViewCamera {
    /// Starts at `initial` (the render's camera).
    #[must_use]
    pub fn new(initial: Camera, bounds: Option<(Vec3, Vec3)>) -> Self {
        ViewCamera {
            initial,
            current: initial,
            bounds,
        }
    }

    /// The camera to render with.
    #[must_use]
    pub fn current(&self) -> Camera {
        self.current
    }

    /// Back to the initial view.
    pub fn reset(&mut self) {
        self.current = self.initial;
    }

    fn set(&mut self, cam: Camera) {
        if cam.validate().is_err() {
            return;
        }
        self.current = match self.bounds {
            Some((lo, hi)) => enclose(cam, lo, hi),
            None => cam,
        };
    }

    /// Orbits by `yaw` and `pitch` radians (see [`orbit`]).
    pub fn orbit(&mut self, yaw: f32, pitch: f32) {
        self.set(orbit(&self.current, yaw, pitch));
    }

    /// Pans by a drag of `(dx, dy)` pixels (see [`pan`]).
    pub fn pan(&mut self, dx: f32, dy: f32, height_px: u32) {
        self.set(pan(&self.current, dx, dy, height_px));
    }

    /// Zooms by `factor` (see [`zoom`]).
    pub fn zoom(&mut self, factor: f32) {
        self.set(zoom(&self.current, factor));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn camera(eye: Vec3, ortho: bool) -> Camera {
        Camera {
            eye,
            target: Vec3::new(0.5, -0.25, 1.0),
            up: Vec3::Y,
            projection: if ortho {
                CameraProjection::Orthographic { half_height: 2.0 }
            } else {
                CameraProjection::Perspective { fov_y_deg: 50.0 }
            },
            near: 0.1,
            far: 100.0,
        }
    }

    /// Pixel position of `p` in a `w × h` view of `cam`.
    fn project(cam: &Camera, p: Vec3, w: u32, h: u32) -> (f32, f32) {
        let clip = cam.clip_from_view(w as f32 / h as f32) * cam.view_from_world();
        let c = clip * p.extend(1.0);
        let (x, y) = (c.x / c.w, c.y / c.w);
        ((x + 1.0) * 0.5 * w as f32, (1.0 - y) * 0.5 * h as f32)
    }

    fn eyes() -> impl Strategy<Value = Vec3> {
        (-5.0f32..5.0, -5.0f32..5.0, -5.0f32..5.0)
            .prop_map(|(x, y, z)| Vec3::new(x, y, z))
            .prop_filter("away from the target and off the up axis", |e| {
                let d = *e - Vec3::new(0.5, -0.25, 1.0);
                d.length() > 0.5 && d.normalize().dot(Vec3::Y).abs() < 0.99
            })
    }

    proptest! {
        #[test]
        fn orbit_keeps_the_target_and_distance_and_never_reaches_a_pole(
            eye in eyes(), yaw in -7.0f32..7.0, pitch in -4.0f32..4.0,
        ) {
            let cam = camera(eye, false);
            let moved = orbit(&cam, yaw, pitch);
            prop_assert_eq!(moved.target, cam.target);
            let (d0, d1) = ((cam.eye - cam.target).length(), (moved.eye - moved.target).length());
            prop_assert!((d0 - d1).abs() < 1e-3 * d0, "{} {}", d0, d1);
            let cos = moved.forward().dot(Vec3::Y).abs();
            prop_assert!(cos < POLE_MARGIN.cos() + 1e-4, "{}", cos);
            prop_assert!(moved.validate().is_ok());
        }

        #[test]
        fn a_yaw_and_its_opposite_come_back(eye in eyes(), yaw in -3.0f32..3.0) {
            let cam = camera(eye, false);
            let back = orbit(&orbit(&cam, yaw, 0.0), -yaw, 0.0);
            prop_assert!((back.eye - cam.eye).length() < 1e-3, "{} {}", back.eye, cam.eye);
        }

        #[test]
        fn panning_moves_the_target_under_the_cursor(
            eye in eyes(), dx in -200.0f32..200.0, dy in -200.0f32..200.0, ortho: bool,
        ) {
            let (w, h) = (640, 360);
            let cam = camera(eye, ortho);
            let before = project(&cam, cam.target, w, h);
            let moved = pan(&cam, dx, dy, h);
            prop_assert!((moved.forward() - cam.forward()).length() < 1e-4);
            let after = project(&moved, cam.target, w, h);
            prop_assert!((after.0 - before.0 - dx).abs() < 0.05, "{:?} {:?}", before, after);
            prop_assert!((after.1 - before.1 - dy).abs() < 0.05, "{:?} {:?}", before, after);
        }

        #[test]
        fn zoom_scales_the_distance_and_its_inverse_undoes_it(
            eye in eyes(), factor in 0.2f32..5.0, ortho: bool,
        ) {
            let cam = camera(eye, ortho);
            let z = zoom(&cam, factor);
            prop_assert_eq!(z.target, cam.target);
            match (cam.projection, z.projection) {
                (
                    CameraProjection::Orthographic { half_height: a },
                    CameraProjection::Orthographic { half_height: b },
                ) => prop_assert!((b - a * factor).abs() < 1e-4 * a),
                _ => {
                    let (d0, d1) = ((cam.eye - cam.target).length(), (z.eye - z.target).length());
                    prop_assert!((d1 - d0 * factor).abs() < 1e-3 * d0);
                    prop_assert!((z.forward() - cam.forward()).length() < 1e-4);
                }
            }
            let back = zoom(&z, 1.0 / factor);
            prop_assert!((back.eye - cam.eye).length() < 1e-3);
        }
    }

    #[test]
    fn moves_refit_the_planes_and_reset_restores_the_initial_camera_exactly() {
        let cam = camera(Vec3::new(0.0, 1.0, 8.0), false);
        let (lo, hi) = (Vec3::splat(-1.0), Vec3::splat(1.0));
        let mut view = ViewCamera::new(cam, Some((lo, hi)));
        view.zoom(3.0);
        let c = view.current();
        let d = c.eye.length();
        let r = 3f32.sqrt();
        assert!(c.near <= d - r && c.far >= d + r, "{c:?}");
        view.orbit(0.3, 0.2);
        view.pan(10.0, -4.0, 360);
        view.reset();
        let back = view.current();
        assert_eq!(
            (back.eye, back.target, back.near, back.far),
            (cam.eye, cam.target, cam.near, cam.far)
        );
    }

    #[test]
    fn a_move_into_an_invalid_camera_is_ignored() {
        let cam = camera(Vec3::new(0.0, 1.0, 8.0), false);
        let mut view = ViewCamera::new(cam, None);
        view.zoom(f32::NAN);
        assert_eq!(view.current().eye, cam.eye);
    }
}
