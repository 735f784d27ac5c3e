//! Choosing a frame's camera: the scene's own, or one that frames what is drawn, with the
//! user's overrides laid over it — the rule the command line follows, so a library user
//! frames a scene exactly as `texmap render` does.
//!
//! - A scene's own camera is used unless [`CameraRequest::auto`] is set.
//! - Without one, meshes alone are framed as the peers frame a mesh
//!   ([`Scene::framing_camera`]: the bounding sphere at 1.1 radii in a 60° view, or the
//!   requested field of view); with volumes, as `vtk_volume.py` frames its box
//!   ([`vtk_camera_for_bounds`] over every mesh and volume, turned by the azimuth and moved in
//!   by the dolly), and the near and far planes then enclose everything wherever the eye was
//!   moved.
//! - `eye`, `target` and `up` replace the pose; a moved eye or target gets near and far
//!   planes that enclose every mesh and volume from the new eye; a field of view makes the projection
//!   perspective, an orthographic request makes it orthographic (its height given, or framing
//!   the bounding sphere with the same margin); otherwise the chosen camera keeps its own.

use glam::Vec3;

use crate::camera::{Camera, CameraProjection};
use crate::scene::Scene;
use crate::volume::{vtk_camera_for_bounds, SceneVolume};
use crate::Result;

/// The projection a [`CameraRequest`] asks for.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub enum ProjectionRequest {
    /// The chosen camera's own projection.
    #[default]
    Keep,
    /// Perspective with this vertical field of view (degrees).
    Perspective { fov_y_deg: f32 },
    /// Orthographic, showing `height` world units vertically, or with `None` the height that
    /// frames the bounding sphere (2.2·r for meshes, VTK's parallel scale over the dolly with
    /// volumes).
    Orthographic { height: Option<f32> },
}

/// What the user asks of the camera (the command line's `--eye`, `--target`, `--up`, `--fov`,
/// `--ortho`, `--auto-camera`, `--dolly`, `--azimuth`).
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct CameraRequest {
    pub eye: Option<Vec3>,
    pub target: Option<Vec3>,
    pub up: Option<Vec3>,
    pub projection: ProjectionRequest,
    /// Ignore the scene's own camera and frame what is drawn.
    pub auto: bool,
    /// Volume framing: the distance divisor after framing the bounding sphere
    /// (`vtk_volume.py`'s `--dolly`, default 1.6).
    pub dolly: f32,
    /// Volume framing: degrees the eye turns about the view-up (`--azimuth`, default 0).
    pub azimuth_deg: f32,
}

impl Default for CameraRequest {
    fn default() -> Self {
        CameraRequest {
            eye: None,
            target: None,
            up: None,
            projection: ProjectionRequest::Keep,
            auto: false,
            dolly: 1.6,
            azimuth_deg: 0.0,
        }
    }
}

impl CameraRequest {
    #[must_use]
    pub fn with_eye(mut self, eye: Vec3) -> Self {
        self.eye = Some(eye);
        self
    }
    #[must_use]
    pub fn with_target(mut self, target: Vec3) -> Self {
        self.target = Some(target);
        self
    }
    #[must_use]
    pub fn with_up(mut self, up: Vec3) -> Self {
        self.up = Some(up);
        self
    }
    #[must_use]
    pub fn with_projection(mut self, projection: ProjectionRequest) -> Self {
        self.projection = projection;
        self
    }
    #[must_use]
    pub fn with_auto(mut self, auto: bool) -> Self {
        self.auto = auto;
        self
    }
    #[must_use]
    pub fn with_volume_framing(mut self, dolly: f32, azimuth_deg: f32) -> Self {
        (self.dolly, self.azimuth_deg) = (dolly, azimuth_deg);
        self
    }
}

/// The camera for `scene` and its `volumes` under `request` (see the module docs).
///
/// ```
/// use texmap::render::framing::{choose_camera, CameraRequest, ProjectionRequest};
/// use texmap::scene::builtin;
/// let scene = builtin::sphere(2000, None, Default::default());
/// let req = CameraRequest::default()
///     .with_auto(true)
///     .with_projection(ProjectionRequest::Perspective { fov_y_deg: 60.0 });
/// let cam = choose_camera(&scene, &[], &req)?;
/// assert!((cam.eye.z - 2.2).abs() < 1e-4);
/// # Ok::<(), texmap::Error>(())
/// ```
///
/// # Errors
/// [`crate::Error::Parameter`] when the result is not a valid camera (eye on the target, up
/// along the view, a bad field of view or height).
pub fn choose_camera(
    scene: &Scene,
    volumes: &[SceneVolume],
    request: &CameraRequest,
) -> Result<Camera> {
    let own = scene.camera.filter(|_| !request.auto);
    let with_volumes = own.is_none() && !volumes.is_empty();
    let fov = match request.projection {
        ProjectionRequest::Perspective { fov_y_deg } => fov_y_deg,
        _ => 60.0,
    };
    let base = match own {
        Some(c) => c,
        None if with_volumes => {
            let (lo, hi) = bounds(scene, volumes);
            vtk_camera_for_bounds(lo, hi, request.dolly, request.azimuth_deg)
        }
        None => scene.framing_camera(fov),
    };
    let projection = match request.projection {
        ProjectionRequest::Keep => base.projection,
        ProjectionRequest::Perspective { fov_y_deg } => CameraProjection::Perspective { fov_y_deg },
        ProjectionRequest::Orthographic {
            height: Some(height),
        } => CameraProjection::Orthographic {
            half_height: 0.5 * height,
        },
        // VTK's parallel scale: the bounding radius over the dolly.
        ProjectionRequest::Orthographic { height: None } if with_volumes => {
            let (lo, hi) = bounds(scene, volumes);
            CameraProjection::Orthographic {
                half_height: ((hi - lo) * 0.5).length().max(1e-3) / request.dolly,
            }
        }
        ProjectionRequest::Orthographic { height: None } => {
            scene.framing_camera_orthographic().projection
        }
    };
    let camera = Camera {
        eye: request.eye.unwrap_or(base.eye),
        target: request.target.unwrap_or(base.target),
        up: request.up.unwrap_or(base.up),
        projection,
        ..base
    };
    camera.validate()?;
    // A pose the user moved keeps everything between near and far from where it now looks,
    // as a volume framing always does (a chosen camera's planes were fitted to its own eye).
    let moved = request.eye.is_some() || request.target.is_some();
    let anything = !scene.meshes.is_empty() || !volumes.is_empty();
    Ok(if anything && (with_volumes || moved) {
        let (lo, hi) = bounds(scene, volumes);
        enclose(camera, lo, hi)
    } else {
        camera
    })
}

/// World bounds of the meshes and volumes together.
fn bounds(scene: &Scene, volumes: &[SceneVolume]) -> (Vec3, Vec3) {
    let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    if !scene.meshes.is_empty() {
        let (a, b) = scene.bounds();
        lo = lo.min(a);
        hi = hi.max(b);
    }
    for v in volumes {
        let (a, b) = v.volume.world_bounds();
        lo = lo.min(a);
        hi = hi.max(b);
    }
    (lo, hi)
}

/// `camera` with near and far around the box `lo..hi`, wherever the eye was moved.
fn enclose(camera: Camera, lo: Vec3, hi: Vec3) -> Camera {
    let centre = (lo + hi) * 0.5;
    let radius = ((hi - lo) * 0.5).length().max(1e-3);
    let dist = (camera.eye - centre).length();
    Camera {
        near: (dist - radius).max(dist * 1e-3).max(1e-4),
        far: dist + radius + 1.0,
        ..camera
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::builtin;

    #[test]
    fn a_moved_eye_gets_planes_that_enclose_the_scene_from_there() {
        let scene = builtin::sphere(200, None, Default::default());
        let (lo, hi) = scene.bounds();
        let (c, r) = ((lo + hi) * 0.5, ((hi - lo) * 0.5).length());
        for eye in [
            Vec3::new(4.0, 3.0, 5.0),
            Vec3::new(40.0, -30.0, 50.0),
            Vec3::new(0.3, 0.2, 1.2),
            Vec3::new(0.0, 0.0, -0.5),
        ] {
            let req = CameraRequest::default()
                .with_eye(eye)
                .with_target(Vec3::ZERO);
            let cam = choose_camera(&scene, &[], &req).unwrap();
            let d = eye.distance(c);
            assert!(
                cam.near > 0.0 && cam.near <= (d - r).max(1e-3 * d),
                "{eye}: {cam:?}"
            );
            assert!(cam.far >= d + r, "{eye}: {cam:?}");
        }
        // Untouched, the automatic framing keeps its own planes.
        let auto = choose_camera(&scene, &[], &CameraRequest::default()).unwrap();
        assert_eq!(auto, scene.framing_camera(60.0));
    }
}
