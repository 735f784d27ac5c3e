//! glTF cameras → [`Camera`]: the node's world transform gives the eye, the view direction
//! (its −Z) and up (its +Y). The image's aspect always sets the horizontal extent — a
//! perspective camera keeps `yfov`, an orthographic one `ymag` as its half-height, and a
//! file's `aspectRatio` / `xmag` are not used — so nothing is stretched. A perspective
//! camera without `zfar` gets a far plane enclosing the scene once every mesh is placed.

use glam::{Mat4, Vec3};

use crate::camera::{Camera, CameraProjection};
use crate::scene::Scene;

/// A camera as the file gives it, before the scene is known.
#[derive(Clone, Copy, Debug)]
pub(super) struct FileCamera {
    /// `far` is infinite when the file gives no `zfar`.
    pub(super) camera: Camera,
    pub(super) zfar: Option<f32>,
}

/// The camera of a node whose world matrix is `world`.
pub(super) fn camera(cam: &gltf::Camera, world: Mat4) -> FileCamera {
    let eye = world.transform_point3(Vec3::ZERO);
    let fwd = world.transform_vector3(-Vec3::Z).normalize_or(-Vec3::Z);
    let up = world.transform_vector3(Vec3::Y).normalize_or(Vec3::Y);
    let (projection, near, zfar) = match cam.projection() {
        gltf::camera::Projection::Perspective(p) => (
            CameraProjection::Perspective {
                fov_y_deg: p.yfov().to_degrees(),
            },
            p.znear(),
            p.zfar(),
        ),
        gltf::camera::Projection::Orthographic(o) => (
            CameraProjection::Orthographic {
                half_height: o.ymag().abs(),
            },
            o.znear(),
            Some(o.zfar()),
        ),
    };
    FileCamera {
        camera: Camera {
            eye,
            target: eye + fwd,
            up,
            projection,
            near,
            far: zfar.unwrap_or(f32::INFINITY),
        },
        zfar,
    }
}

/// The file's cameras with their far planes: `zfar`, or for cameras without one a plane
/// enclosing `scene` (the distance to its bounding box's centre plus twice the box's
/// half-diagonal, at least 1000 × near); always above near.
pub(super) fn finish_cameras(cameras: &[FileCamera], scene: &Scene) -> Vec<Camera> {
    let (lo, hi) = scene.bounds();
    let (c, r) = ((lo + hi) * 0.5, (hi - lo).length() * 0.5);
    cameras
        .iter()
        .map(|FileCamera { camera: cam, zfar }| {
            let far = zfar.unwrap_or_else(|| (cam.eye.distance(c) + 2.0 * r).max(cam.near * 1e3));
            Camera {
                far: far.max(cam.near * 1.0001),
                ..*cam
            }
        })
        .collect()
}
