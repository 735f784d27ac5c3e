//! Choosing a frame's camera: the scene's own, or one that frames what is drawn, with the
//! user's overrides laid over it — the rule the command line follows, so a library user
//! frames a scene exactly as `texmap render` does.
//!
//! - A scene's own camera is used unless [`CameraRequest::auto`] or a view is asked for.
//! - Without one, the automatic framing ([`CameraRequest::default`]): meshes alone are seen
//!   in a three-quarter view (from the front, [`THREE_QUARTER_AZIMUTH_DEG`] to the right and
//!   [`THREE_QUARTER_ELEVATION_DEG`] above, +y up) in a 60° view; with volumes, the eye faces
//!   the patient when a scan states its anatomical frame (the face toward the camera, the
//!   head up: [`crate::volume::Volume::patient_front_and_top`]), otherwise it looks along +y
//!   with z up as VTK does, in a 30° view. Either way the bounding sphere of the meshes and
//!   of what the volumes show ([`SceneVolume::visible_world_bounds`]: the bricks their
//!   transfer functions make visible) fills the frame with a 10% margin on the tighter side
//!   for the request's aspect ratio, and near and far enclose everything.
//! - [`CameraRequest::auto`] (`--auto-camera`) frames as the peer scripts do, so their images
//!   line up: meshes as `gl_render.py` ([`Scene::framing_camera`]: from +z, the bounding
//!   sphere at 1.1 radii in a 60° view, or the requested field of view); with volumes as
//!   `vtk_volume.py` ([`vtk_camera_for_bounds`] over every mesh and volume, turned by the
//!   azimuth and moved in by the dolly, default 1.6).
//! - A [`StandardView`] (`--view`) replaces both: the eye on an axis (or the diagonal) of
//!   the bounding box of everything drawn, the bounding sphere in frame, near and far
//!   enclosing it.
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

/// A standard view of the whole scene (`--view`): the eye on one axis of the bounding box's
/// centre (or on its diagonal for `Iso`), far enough for the bounding sphere to fill the
/// frame with a 10% margin, whatever camera the scene has.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StandardView {
    /// From +z (the glTF front), +y up.
    Front,
    /// From −z.
    Back,
    /// From −x.
    Left,
    /// From +x.
    Right,
    /// From +y, −z up (the front at the image's bottom).
    Top,
    /// From −y, +z up.
    Bottom,
    /// From (1, 1, 1): above, to the right and in front, +y up.
    Iso,
}

impl StandardView {
    /// Every view with its name, in the order the command line lists them.
    pub const NAMES: [(&'static str, StandardView); 7] = [
        ("front", StandardView::Front),
        ("back", StandardView::Back),
        ("left", StandardView::Left),
        ("right", StandardView::Right),
        ("top", StandardView::Top),
        ("bottom", StandardView::Bottom),
        ("iso", StandardView::Iso),
    ];

    /// The unit direction from the target to the eye, and the up vector.
    #[must_use]
    pub fn direction_and_up(self) -> (Vec3, Vec3) {
        match self {
            StandardView::Front => (Vec3::Z, Vec3::Y),
            StandardView::Back => (-Vec3::Z, Vec3::Y),
            StandardView::Left => (-Vec3::X, Vec3::Y),
            StandardView::Right => (Vec3::X, Vec3::Y),
            StandardView::Top => (Vec3::Y, -Vec3::Z),
            StandardView::Bottom => (-Vec3::Y, Vec3::Z),
            StandardView::Iso => (Vec3::ONE.normalize(), Vec3::Y),
        }
    }
}

/// The automatic three-quarter view of meshes: degrees the eye turns from +z toward +x.
pub const THREE_QUARTER_AZIMUTH_DEG: f32 = 35.0;
/// The automatic three-quarter view of meshes: degrees the eye rises above the centre.
pub const THREE_QUARTER_ELEVATION_DEG: f32 = 25.0;

/// What the user asks of the camera (the command line's `--eye`, `--target`, `--up`, `--fov`,
/// `--ortho`, `--auto-camera`, `--dolly`, `--azimuth`, `--view`).
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct CameraRequest {
    pub eye: Option<Vec3>,
    pub target: Option<Vec3>,
    pub up: Option<Vec3>,
    pub projection: ProjectionRequest,
    /// Ignore the scene's own camera and frame what is drawn as the peer scripts do.
    pub auto: bool,
    /// Volume framing: the distance divisor after framing the bounding sphere
    /// (`vtk_volume.py`'s `--dolly`; `None` is 1.6 in the peers' framing, 1 in the automatic
    /// one).
    pub dolly: Option<f32>,
    /// Volume framing: degrees the eye turns about the view-up (`--azimuth`, default 0).
    pub azimuth_deg: f32,
    /// The image's width over its height, which the automatic framing and the standard views
    /// fit the scene into (`None`: 4:3).
    pub aspect: Option<f32>,
    /// A standard view of everything drawn, in place of the scene's camera and the
    /// automatic framing (`--view`).
    pub view: Option<StandardView>,
}

impl Default for CameraRequest {
    fn default() -> Self {
        CameraRequest {
            eye: None,
            target: None,
            up: None,
            projection: ProjectionRequest::Keep,
            auto: false,
            dolly: None,
            azimuth_deg: 0.0,
            aspect: None,
            view: None,
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
    pub fn with_view(mut self, view: StandardView) -> Self {
        self.view = Some(view);
        self
    }
    #[must_use]
    pub fn with_volume_framing(mut self, dolly: Option<f32>, azimuth_deg: f32) -> Self {
        (self.dolly, self.azimuth_deg) = (dolly, azimuth_deg);
        self
    }
    /// The image's width over its height (`width / height`).
    #[must_use]
    pub fn with_aspect(mut self, aspect: f32) -> Self {
        self.aspect = Some(aspect);
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
    let own = scene
        .camera
        .filter(|_| !request.auto && request.view.is_none());
    let with_volumes = own.is_none() && !volumes.is_empty();
    let requested_fov = match request.projection {
        ProjectionRequest::Perspective { fov_y_deg } => Some(fov_y_deg),
        _ => None,
    };
    let fov = requested_fov.unwrap_or(60.0);
    let aspect = request
        .aspect
        .filter(|a| a.is_finite() && *a > 0.0)
        .unwrap_or(4.0 / 3.0);
    let anything = !scene.meshes.is_empty() || !volumes.is_empty();
    let automatic = own.is_none() && !request.auto && request.view.is_none() && anything;
    let (lo, hi) = bounds(scene, volumes);
    // What the automatic framing and the standard views fit: the meshes and what the
    // volumes show (the peers' framings fit the volumes' whole boxes, as VTK does).
    let fitted = if automatic || request.view.is_some() {
        visible_bounds(scene, volumes)
    } else {
        (lo, hi)
    };
    let base = match own {
        Some(c) => c,
        None if request.view.is_some() && anything => standard_view(
            request.view.unwrap_or(StandardView::Front),
            fitted.0,
            fitted.1,
            fov,
            aspect,
        ),
        None if automatic => automatic_camera(scene, volumes, request, requested_fov, aspect),
        None if with_volumes => {
            vtk_camera_for_bounds(lo, hi, request.dolly.unwrap_or(1.6), request.azimuth_deg)
        }
        None => scene.framing_camera(fov),
    };
    let radius = ((hi - lo) * 0.5).length().max(1e-3);
    let projection = match request.projection {
        ProjectionRequest::Keep => base.projection,
        ProjectionRequest::Perspective { fov_y_deg } => CameraProjection::Perspective { fov_y_deg },
        ProjectionRequest::Orthographic {
            height: Some(height),
        } => CameraProjection::Orthographic {
            half_height: 0.5 * height,
        },
        // The bounding sphere with a 10% margin, in both directions.
        ProjectionRequest::Orthographic { height: None }
            if (request.view.is_some() || automatic) && anything =>
        {
            let r = if automatic && volumes.is_empty() {
                scene.bounding_sphere().1
            } else {
                ((fitted.1 - fitted.0) * 0.5).length().max(1e-3)
            };
            CameraProjection::Orthographic {
                half_height: 1.1 * r / aspect.min(1.0) / request.dolly.unwrap_or(1.0),
            }
        }
        // VTK's parallel scale: the bounding radius over the dolly.
        ProjectionRequest::Orthographic { height: None } if with_volumes => {
            CameraProjection::Orthographic {
                half_height: radius / request.dolly.unwrap_or(1.6),
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
    // as a framing of volumes or the automatic one always does (a chosen camera's planes were
    // fitted to its own eye).
    let moved = request.eye.is_some() || request.target.is_some() || request.view.is_some();
    Ok(if anything && (with_volumes || automatic || moved) {
        enclose(camera, lo, hi)
    } else {
        camera
    })
}

/// The automatic framing (see the module docs): a three-quarter view of meshes, or the view
/// that faces a scan's patient (VTK's along +y when no scan states its frame); the bounding
/// sphere fitted to `fov_y_deg` (60° for meshes, 30° with volumes) and `aspect` with a 10%
/// margin, moved in by the dolly and turned by the azimuth. Near and far are fitted by the
/// caller.
fn automatic_camera(
    scene: &Scene,
    volumes: &[SceneVolume],
    request: &CameraRequest,
    fov_y_deg: Option<f32>,
    aspect: f32,
) -> Camera {
    let (centre, radius, toward_eye, up, fov) = if volumes.is_empty() {
        let (c, r) = scene.bounding_sphere();
        let (az, el) = (
            THREE_QUARTER_AZIMUTH_DEG.to_radians(),
            THREE_QUARTER_ELEVATION_DEG.to_radians(),
        );
        let dir = Vec3::new(az.sin() * el.cos(), el.sin(), az.cos() * el.cos());
        (c, r, dir, Vec3::Y, fov_y_deg.unwrap_or(60.0))
    } else {
        let (lo, hi) = visible_bounds(scene, volumes);
        let facing = volumes
            .iter()
            .find_map(|v| v.volume.patient_front_and_top())
            .filter(|(a, s)| a.length() > 0.5 && s.length() > 0.5);
        let (dir, up) = facing.unwrap_or((-Vec3::Y, Vec3::Z));
        let r = ((hi - lo) * 0.5).length().max(1e-3);
        ((lo + hi) * 0.5, r, dir, up, fov_y_deg.unwrap_or(30.0))
    };
    let distance = fit_distance(radius, fov, aspect) / request.dolly.unwrap_or(1.0);
    Camera {
        eye: centre + toward_eye * distance,
        target: centre,
        up,
        projection: CameraProjection::Perspective { fov_y_deg: fov },
        near: 0.1,
        far: 1.0,
    }
    .orbit(request.azimuth_deg.to_radians())
}

/// The distance at which a sphere of `radius` fills a perspective view of `fov_y_deg` and
/// `aspect` with a 10% margin on the tighter side.
fn fit_distance(radius: f32, fov_y_deg: f32, aspect: f32) -> f32 {
    let half_v = fov_y_deg.clamp(1.0, 179.0).to_radians() * 0.5;
    let half_h = (half_v.tan() * aspect).atan();
    1.1 * radius.max(1e-3) / half_v.min(half_h).sin()
}

/// World bounds of the meshes and volumes together (a unit box about the origin when there
/// is nothing).
fn bounds(scene: &Scene, volumes: &[SceneVolume]) -> (Vec3, Vec3) {
    bounds_of(scene, volumes, |v| v.volume.world_bounds())
}

/// World bounds of the meshes and of what the volumes show
/// ([`SceneVolume::visible_world_bounds`]): what the automatic framing and the standard views
/// fit.
fn visible_bounds(scene: &Scene, volumes: &[SceneVolume]) -> (Vec3, Vec3) {
    bounds_of(scene, volumes, SceneVolume::visible_world_bounds)
}

fn bounds_of(
    scene: &Scene,
    volumes: &[SceneVolume],
    volume_bounds: impl Fn(&SceneVolume) -> (Vec3, Vec3),
) -> (Vec3, Vec3) {
    let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    if !scene.meshes.is_empty() {
        let (a, b) = scene.bounds();
        lo = lo.min(a);
        hi = hi.max(b);
    }
    for v in volumes {
        let (a, b) = volume_bounds(v);
        lo = lo.min(a);
        hi = hi.max(b);
    }
    if lo.cmple(hi).all() {
        (lo, hi)
    } else {
        (-Vec3::ONE, Vec3::ONE)
    }
}

/// The camera of `view` over the box `lo..hi`: aimed at its centre from the view's direction,
/// at the distance where its bounding sphere (the box's half-diagonal) fills a `fov_y_deg`
/// view of `aspect` with a 10% margin (near and far are fitted by the caller).
fn standard_view(view: StandardView, lo: Vec3, hi: Vec3, fov_y_deg: f32, aspect: f32) -> Camera {
    let (dir, up) = view.direction_and_up();
    let centre = (lo + hi) * 0.5;
    let radius = ((hi - lo) * 0.5).length().max(1e-3);
    Camera {
        eye: centre + dir * fit_distance(radius, fov_y_deg, aspect),
        target: centre,
        up,
        projection: CameraProjection::Perspective { fov_y_deg },
        near: 0.1,
        far: 1.0,
    }
}

/// `camera` with near and far around the box `lo..hi` (its bounding sphere), wherever the
/// eye was moved: what [`choose_camera`] does to a moved eye, and what an interactive
/// camera does after each move.
#[must_use]
pub fn enclose(camera: Camera, lo: Vec3, hi: Vec3) -> Camera {
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
    fn standard_views_look_at_the_centre_from_their_side_and_see_everything() {
        let scene = builtin::sphere(200, None, Default::default());
        let (lo, hi) = scene.bounds();
        let (c, r) = ((lo + hi) * 0.5, ((hi - lo) * 0.5).length());
        for (name, view) in StandardView::NAMES {
            let req = CameraRequest::default().with_view(view);
            let cam = choose_camera(&scene, &[], &req).unwrap();
            let (dir, up) = view.direction_and_up();
            let seen = (cam.eye - cam.target).normalize();
            assert!((seen - dir).length() < 1e-5, "{name}: {seen}");
            assert!((cam.target - c).length() < 1e-5, "{name}");
            assert_eq!(cam.up, up, "{name}");
            let d = cam.eye.distance(c);
            // The bounding sphere fits the 60° view, and lies between near and far.
            assert!(r / d <= (30f32).to_radians().sin() + 1e-5, "{name}: {d}");
            assert!(cam.near <= d - r && cam.far >= d + r, "{name}: {cam:?}");
        }
        // A view replaces the scene's own camera too.
        let demo = builtin::demo();
        let top = choose_camera(
            &demo,
            &[],
            &CameraRequest::default().with_view(StandardView::Top),
        );
        assert!(top.unwrap().eye.y > demo.camera.unwrap().eye.y);
    }

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
        // The peers' framing keeps its own planes.
        let peer = choose_camera(&scene, &[], &CameraRequest::default().with_auto(true));
        assert_eq!(peer.unwrap(), scene.framing_camera(60.0));
    }
}
