//! The camera `vtk_volume.py` (the VTK peer) starts from, so that texmap's volume images and
//! the peer's show the same view. It frames a world box, not one volume, so a scene of several
//! volumes and meshes is framed by the same rule.

use glam::Vec3;

/// The camera `vtk_volume.py` starts from for the world box `lo..hi`: looking along +y with z
/// up at the centre of the box, at `ResetCamera`'s distance (bounding sphere fits a 30° view
/// angle) divided by `dolly` (the script's default is 1.6), then turned by `azimuth_deg` about
/// z (degrees).
#[must_use]
pub fn vtk_camera_for_bounds(
    lo: Vec3,
    hi: Vec3,
    dolly: f32,
    azimuth_deg: f32,
) -> crate::camera::Camera {
    let centre = (lo + hi) * 0.5;
    let radius = {
        let r = ((hi - lo) * 0.5).length();
        if r > 0.0 {
            r
        } else {
            1.0
        }
    };
    let view_angle = 30.0f32;
    let distance = radius / (view_angle.to_radians() * 0.5).sin() / dolly;
    let cam = crate::camera::Camera {
        eye: centre - Vec3::Y * distance,
        target: centre,
        up: Vec3::Z,
        projection: crate::camera::CameraProjection::Perspective {
            fov_y_deg: view_angle,
        },
        near: (distance - radius).max(distance * 1e-3),
        far: distance + radius * 2.0,
    };
    // VTK's Azimuth turns the eye about the view-up through the focal point.
    cam.orbit(azimuth_deg.to_radians())
}
