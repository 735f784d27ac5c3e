//! Cameras: a pose (eye, target, up), a perspective or orthographic projection and a
//! clipping range, and the transforms, rays and viewer they define.
//!
//! Conventions: right-handed world; the camera looks from `eye` towards `target`, down its own
//! −Z; `up` is projected to the image's upward direction; clip space is OpenGL's.

use glam::{Mat4, Vec3};

use crate::shading::Viewer;
use crate::{Error, Result};

/// How a camera maps view space to the image.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CameraProjection {
    /// Rays from the eye; `fov_y_deg` is the vertical field of view in degrees.
    Perspective { fov_y_deg: f32 },
    /// Parallel rays along the view direction; the image shows `half_height` world units
    /// above and below the view axis, and `half_height · aspect` to either side (glTF's
    /// `ymag`; the horizontal extent follows the image's aspect).
    Orthographic { half_height: f32 },
}

impl CameraProjection {
    /// The vertical field of view in degrees, for a perspective projection.
    #[must_use]
    pub fn fov_y_deg(self) -> Option<f32> {
        match self {
            CameraProjection::Perspective { fov_y_deg } => Some(fov_y_deg),
            CameraProjection::Orthographic { .. } => None,
        }
    }

    /// True for an orthographic projection.
    #[must_use]
    pub fn is_orthographic(self) -> bool {
        matches!(self, CameraProjection::Orthographic { .. })
    }
}

/// A camera: a pose (eye, target, up), a projection and the clipping range.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub eye: Vec3,
    pub target: Vec3,
    pub up: Vec3,
    pub projection: CameraProjection,
    /// Distance to the near clipping plane along the view direction (> 0; orthographic
    /// cameras may also use 0).
    pub near: f32,
    /// Distance to the far clipping plane (> near).
    pub far: f32,
}

impl Camera {
    /// The eye rotated about the axis `up` through `target` by `angle_rad`, counter-clockwise
    /// seen from +up (Rodrigues' formula, as `gl_render.py`'s turntable).
    #[must_use]
    pub fn orbit(&self, angle_rad: f32) -> Camera {
        let k = self.up.normalize_or_zero();
        let v = self.eye - self.target;
        let (s, c) = angle_rad.sin_cos();
        let eye = self.target + v * c + k.cross(v) * s + k * k.dot(v) * (1.0 - c);
        Camera { eye, ..*self }
    }

    /// Checks that the camera defines a view: finite values, eye ≠ target, up not parallel
    /// to the view direction, 0 < fov < 180 (perspective) or a half-height > 0
    /// (orthographic), 0 < near < far (0 ≤ near for orthographic).
    pub fn validate(&self) -> Result<()> {
        let finite = self.eye.is_finite()
            && self.target.is_finite()
            && self.up.is_finite()
            && self.near.is_finite()
            && self.far.is_finite();
        if !finite {
            return Err(Error::parameter("camera has a non-finite value"));
        }
        let f = self.target - self.eye;
        if f.length_squared() <= 0.0 {
            return Err(Error::parameter("camera eye and target coincide"));
        }
        if f.normalize().cross(self.up).length_squared() <= 1e-12 {
            return Err(Error::parameter(
                "camera up is parallel to the view direction",
            ));
        }
        match self.projection {
            CameraProjection::Perspective { fov_y_deg } => {
                if !(fov_y_deg > 0.0 && fov_y_deg < 180.0) {
                    return Err(Error::parameter(format!(
                        "camera fov {fov_y_deg} is not in (0, 180) degrees"
                    )));
                }
                if !(self.near > 0.0) {
                    return Err(Error::parameter(format!(
                        "camera near {} must be > 0",
                        self.near
                    )));
                }
            }
            CameraProjection::Orthographic { half_height } => {
                if !(half_height > 0.0 && half_height.is_finite()) {
                    return Err(Error::parameter(format!(
                        "orthographic camera height {} must be > 0 and finite",
                        2.0 * half_height
                    )));
                }
                if !(self.near >= 0.0) {
                    return Err(Error::parameter(format!(
                        "orthographic camera near {} must be ≥ 0",
                        self.near
                    )));
                }
            }
        }
        if !(self.far > self.near) {
            return Err(Error::parameter(format!(
                "camera far {} must be > near {}",
                self.far, self.near
            )));
        }
        Ok(())
    }

    /// World → view (the camera at the origin looking down −Z).
    #[must_use]
    pub fn view_from_world(&self) -> Mat4 {
        Mat4::look_at_rh(self.eye, self.target, self.up)
    }

    /// View → clip, NDC depth in [−1, 1]: OpenGL's perspective projection, or its
    /// orthographic one (`glOrtho(−h·aspect, h·aspect, −h, h, near, far)`, so w = 1).
    #[must_use]
    pub fn clip_from_view(&self, aspect: f32) -> Mat4 {
        match self.projection {
            CameraProjection::Perspective { fov_y_deg } => {
                Mat4::perspective_rh_gl(fov_y_deg.to_radians(), aspect, self.near, self.far)
            }
            CameraProjection::Orthographic { half_height: h } => {
                Mat4::orthographic_rh_gl(-h * aspect, h * aspect, -h, h, self.near, self.far)
            }
        }
    }

    /// The unit view direction, from the eye towards the target.
    #[must_use]
    pub fn forward(&self) -> Vec3 {
        (self.target - self.eye).normalize()
    }

    /// How far along its pixel's ray `p` lies from the ray's origin: the distance from the
    /// eye (perspective), or along the view direction from the eye's plane (orthographic
    /// rays start there, see `volume::camera_ray`).
    #[must_use]
    pub fn ray_distance(&self, p: Vec3) -> f32 {
        match self.projection {
            CameraProjection::Perspective { .. } => p.distance(self.eye),
            CameraProjection::Orthographic { .. } => (p - self.eye).dot(self.forward()),
        }
    }

    /// The viewer of the lighting model: the eye (perspective) or the direction towards the
    /// camera, the same at every point (orthographic).
    #[must_use]
    pub fn viewer(&self) -> Viewer {
        match self.projection {
            CameraProjection::Perspective { .. } => Viewer::Point(self.eye),
            CameraProjection::Orthographic { .. } => Viewer::Direction(-self.forward()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn orbit_is_counter_clockwise_seen_from_up() {
        let cam = Camera {
            eye: Vec3::new(0.0, 0.0, 1.0),
            target: Vec3::ZERO,
            up: Vec3::Y,
            projection: CameraProjection::Perspective { fov_y_deg: 60.0 },
            near: 0.1,
            far: 10.0,
        };
        // Seen from +y (x right, z down on the page), counter-clockwise takes +z to +x.
        let e = cam.orbit(std::f32::consts::FRAC_PI_2).eye;
        assert!((e - Vec3::X).length() < 1e-6, "{e}");
    }

    #[test]
    fn validate_rejects_bad_cameras() {
        let ok = Camera {
            eye: Vec3::Z,
            target: Vec3::ZERO,
            up: Vec3::Y,
            projection: CameraProjection::Perspective { fov_y_deg: 60.0 },
            near: 0.1,
            far: 10.0,
        };
        assert!(ok.validate().is_ok());
        for bad in [
            Camera {
                eye: Vec3::NAN,
                ..ok
            },
            Camera { near: 0.0, ..ok },
            Camera { far: 0.05, ..ok },
            Camera { up: Vec3::Z, ..ok },
            Camera {
                target: Vec3::Z,
                ..ok
            },
            Camera {
                projection: CameraProjection::Perspective { fov_y_deg: 180.0 },
                ..ok
            },
            Camera {
                projection: CameraProjection::Orthographic { half_height: 0.0 },
                ..ok
            },
            Camera {
                projection: CameraProjection::Orthographic { half_height: 1.0 },
                near: -0.1,
                ..ok
            },
        ] {
            assert!(bad.validate().is_err(), "{bad:?}");
        }
    }
}
