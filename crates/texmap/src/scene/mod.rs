//! Scenes: meshes, materials, lights and a camera — plain data the renderer consumes.
//!
//! Conventions: right-handed world, the camera looks from `eye` towards `target` (down its
//! own −Z), `up` is projected to the image's upward direction. Triangles are counter-clockwise
//! when seen from their front side (after `world_from_object`; a mirroring transform flips the
//! winding back). Texture coordinates follow glTF (v down the image rows).

// `!(x > y)` is deliberate: it is true for NaN, which must be rejected too.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod builtin;
pub mod gltf;
pub mod load;
pub mod obj;
pub mod primitives;
pub mod tangents;
pub mod toml;
mod toml_volume;

/// Writes `body` to file `name` in this test process's scratch directory for loader `kind`
/// (`texmap-{kind}-{pid}` under the system's temporary directory) and returns its path.
#[cfg(test)]
pub(crate) fn test_file(kind: &str, name: &str, body: impl AsRef<[u8]>) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("texmap-{kind}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(name);
    std::fs::write(&p, body).unwrap();
    p
}

pub use load::{load, AssetInfo, LoadOptions, Loaded, TextureInfo};

use glam::{Mat4, Vec2, Vec3, Vec4};

pub use crate::shading::{
    AlphaMode, Light, Material, Procedural, ShadingModel, SolidChannel, SolidMap, TextureSlot,
    Viewer,
};
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
    /// rays start there, see `volume::raymarch::camera_ray`).
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

/// An indexed triangle mesh. Optional attributes are empty or have one entry per position.
#[derive(Clone, Debug, Default)]
pub struct Mesh {
    pub positions: Vec<Vec3>,
    /// Unit vertex normals; empty means faceted (the geometric normal of each triangle).
    pub normals: Vec<Vec3>,
    /// Texture coordinates (set 0); empty means (0, 0).
    pub uvs: Vec<Vec2>,
    /// A second texture coordinate set (not used by the base colour yet).
    pub uvs1: Vec<Vec2>,
    /// Vertex colours, linear RGBA, straight alpha; empty means white.
    pub colors: Vec<Vec4>,
    /// Tangents (xyz) and handedness (w), for normal maps (not used yet).
    pub tangents: Vec<Vec4>,
    /// Three indices per triangle.
    pub indices: Vec<u32>,
    /// Index into `Scene::materials`.
    pub material: usize,
    pub world_from_object: Mat4,
}

impl Mesh {
    /// The centre of the object-space bounding box of the positions (the origin when there
    /// are none): the default centre of a bounding-sphere projection.
    #[must_use]
    pub fn object_center(&self) -> Vec3 {
        let (lo, hi) = self.positions.iter().fold(
            (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
            |(lo, hi), &p| (lo.min(p), hi.max(p)),
        );
        if lo.cmple(hi).all() {
            (lo + hi) * 0.5
        } else {
            Vec3::ZERO
        }
    }

    /// Number of triangles (`indices.len() / 3`).
    #[must_use]
    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }
}

/// Everything a frame shows.
#[derive(Clone, Debug, Default)]
pub struct Scene {
    pub meshes: Vec<Mesh>,
    pub materials: Vec<Material>,
    pub lights: Vec<Light>,
    /// I_AL: the ambient light.
    pub ambient_light: Vec3,
    /// Linear RGBA, straight alpha; the colour where nothing is drawn.
    pub background: Vec4,
    /// The scene's own camera, if it has one.
    pub camera: Option<Camera>,
}

impl Scene {
    /// World-space bounding box of every vertex (min, max); `(0, 0)` for an empty scene.
    #[must_use]
    pub fn bounds(&self) -> (Vec3, Vec3) {
        let mut lo = Vec3::splat(f32::INFINITY);
        let mut hi = Vec3::splat(f32::NEG_INFINITY);
        for p in self.world_positions() {
            lo = lo.min(p);
            hi = hi.max(p);
        }
        if lo.x > hi.x {
            (Vec3::ZERO, Vec3::ZERO)
        } else {
            (lo, hi)
        }
    }

    /// Total number of triangles.
    #[must_use]
    pub fn triangle_count(&self) -> usize {
        self.meshes.iter().map(Mesh::triangle_count).sum()
    }

    /// The peers' mesh camera: target at the bounding-box centre `c`, eye at
    /// `c + (0, 0, 1.1·r / sin(fov/2))` with `r` the largest vertex distance from `c`, and
    /// near/far enclosing the scene on the whole turntable orbit.
    #[must_use]
    pub fn framing_camera(&self, fov_y_deg: f32) -> Camera {
        let (c, r) = self.bounding_sphere();
        let half = (fov_y_deg.to_radians() * 0.5).sin();
        let eye = c + Vec3::new(0.0, 0.0, 1.1 * r / half);
        let d = eye.distance(c);
        Camera {
            eye,
            target: c,
            up: Vec3::Y,
            projection: CameraProjection::Perspective { fov_y_deg },
            near: (d - 1.5 * r).max(1e-3 * d),
            far: d + 1.5 * r,
        }
    }

    /// The orthographic counterpart of [`Scene::framing_camera`]: the same pose and range as
    /// at 60°, and a half-height of `1.1·r`, so the bounding sphere fills the image's height
    /// with the same margin.
    #[must_use]
    pub fn framing_camera_orthographic(&self) -> Camera {
        let (_, r) = self.bounding_sphere();
        Camera {
            projection: CameraProjection::Orthographic {
                half_height: 1.1 * r,
            },
            ..self.framing_camera(60.0)
        }
    }

    /// The bounding-box centre and the largest vertex distance from it (1 for an empty or
    /// point-like scene).
    fn bounding_sphere(&self) -> (Vec3, f32) {
        let (lo, hi) = self.bounds();
        let c = (lo + hi) * 0.5;
        let r = self
            .world_positions()
            .map(|p| p.distance(c))
            .fold(0.0f32, f32::max);
        (c, if r > 0.0 { r } else { 1.0 })
    }

    fn world_positions(&self) -> impl Iterator<Item = Vec3> + '_ {
        self.meshes.iter().flat_map(|m| {
            let identity = m.world_from_object == Mat4::IDENTITY;
            m.positions.iter().map(move |&p| {
                if identity {
                    p
                } else {
                    m.world_from_object.transform_point3(p)
                }
            })
        })
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
    fn framing_camera_follows_the_peers_rule() {
        let scene = builtin::sphere(2000, None, Default::default());
        let cam = scene.framing_camera(60.0);
        assert!(cam.target.length() < 1e-5);
        assert!((cam.eye.z - 2.2).abs() < 1e-4, "{}", cam.eye);
        assert!((cam.near - 0.7).abs() < 1e-4 && (cam.far - 3.7).abs() < 1e-4);
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
