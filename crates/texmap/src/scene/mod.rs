//! Scenes: meshes, materials, lights and a camera — plain data the renderer consumes.
//!
//! Conventions: right-handed world, the camera looks from `eye` towards `target` (down its
//! own −Z), `up` is projected to the image's upward direction. Triangles are counter-clockwise
//! when seen from their front side (after `world_from_object`; a mirroring transform flips the
//! winding back). Texture coordinates follow glTF (v down the image rows); each loader
//! converts its format's convention once, at load.
//!
//! Loading: [`load()`] picks the loader by the file's extension (`format`) — [`gltf`],
//! [`obj`] or [`toml`] — and each returns a [`Loaded`]. The loaders share, without importing
//! one another, what loading takes and gives (`asset`: [`LoadOptions`], [`Loaded`],
//! [`AssetInfo`]), the file rules (`files`: bounded reads, the folder rule, `data:` URIs) and
//! the texture cache (`texture_cache`); a TOML scene calls the glTF and OBJ loaders for its
//! model files, never the dispatcher, so no two files depend on each other.

mod asset;
pub mod builtin;
pub mod displace;
mod files;
mod format;
pub mod gltf;
pub mod load;
pub mod obj;
pub mod primitives;
pub mod tangents;
mod texture_cache;
pub mod toml;

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

pub use asset::{AssetInfo, LoadOptions, Loaded, TextureInfo};
pub use load::load;

use std::sync::Arc;

use glam::{Mat4, Vec2, Vec3, Vec4};

use crate::camera::{Camera, CameraProjection};
pub use crate::shading::ibl::Environment;
pub use crate::shading::shadow::Shadows;
pub use crate::shading::{
    AlphaMode, Light, Material, Procedural, Projector, ShadingModel, SolidChannel, SolidMap,
    TextureSlot, Viewer,
};
use crate::texture::{Sampler, Texture2D, VirtualTexture};

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
#[derive(Clone, Debug)]
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
    /// Multiplies every texture's coordinates (after each slot's own transform and scale):
    /// 1 for every loaded scene; the peers' plane uses it for its repeat count (64 by
    /// default), and the command line's `--uv-scale` sets it.
    pub uv_scale: f32,
    /// Which lights cast shadows, and how their maps are made and read (none by default).
    pub shadows: Shadows,
    /// The light from every direction, if any: drawn behind the surfaces, lighting them in
    /// place of `ambient_light` and seen in their reflections and refractions
    /// ([`crate::shading::ibl`]).
    pub environment: Option<Environment>,
    /// Slide projectors: lights whose colour passes through an image
    /// ([`crate::shading::Projector`]).
    pub projectors: Vec<Projector>,
}

impl Default for Scene {
    /// Nothing to draw: no meshes, lights or camera, no ambient light, a transparent black
    /// background, texture coordinates as they are, no shadows.
    fn default() -> Self {
        Scene {
            meshes: Vec::new(),
            materials: Vec::new(),
            lights: Vec::new(),
            ambient_light: Vec3::ZERO,
            background: Vec4::ZERO,
            camera: None,
            uv_scale: 1.0,
            shadows: Shadows::default(),
            environment: None,
            projectors: Vec::new(),
        }
    }
}

impl Scene {
    /// Every triangle of every mesh in world space (each mesh's `world_from_object`
    /// applied), in mesh and index order: the input of a mesh distance field
    /// ([`crate::volume::sdf::mesh_field`]). Triangles with an index out of range or a
    /// non-finite corner are left out.
    #[must_use]
    pub fn world_triangles(&self) -> crate::volume::sdf::Triangles {
        let mut out = crate::volume::sdf::Triangles::new();
        for mesh in &self.meshes {
            let m = mesh.world_from_object;
            for t in mesh.indices.chunks_exact(3) {
                let corner = |i: u32| {
                    mesh.positions
                        .get(i as usize)
                        .map(|&p| m.transform_point3(p))
                };
                if let (Some(a), Some(b), Some(c)) = (corner(t[0]), corner(t[1]), corner(t[2])) {
                    out.push([a, b, c]);
                }
            }
        }
        out
    }

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

    /// The samplers of every image texture a mesh's material reads (base colour, maps, layers,
    /// projected images, 3D textures; the projectors' slides when there is a mesh to light),
    /// in scene order.
    #[must_use]
    pub fn texture_samplers(&self) -> Vec<Sampler> {
        let mut out = Vec::new();
        for m in &self.meshes {
            let Some(mat) = self.materials.get(m.material) else {
                continue;
            };
            out.extend(mat.base_color_texture.iter().map(|s| s.sampler));
            out.extend(mat.maps.iter().map(|m| m.slot.sampler));
            out.extend(mat.layers.iter().map(|l| l.slot.sampler));
            match &mat.procedural {
                Some(Procedural::Projected { slot, .. }) => out.push(slot.sampler),
                Some(Procedural::Texture3D { sampler, .. }) => out.push(*sampler),
                _ => {}
            }
        }
        if !self.meshes.is_empty() {
            out.extend(self.projectors.iter().map(|p| p.slide.sampler));
        }
        out
    }

    /// The virtual textures the meshes' materials read, each once (in scene order), with
    /// the samplers that read them.
    #[must_use]
    pub fn virtual_textures(&self) -> Vec<(Arc<VirtualTexture>, Vec<Sampler>)> {
        let mut out: Vec<(Arc<VirtualTexture>, Vec<Sampler>)> = Vec::new();
        for m in &self.meshes {
            let Some(slot) = self
                .materials
                .get(m.material)
                .and_then(|mat| mat.base_color_texture.as_ref())
            else {
                continue;
            };
            let Some(vt) = &slot.virtual_texture else {
                continue;
            };
            match out.iter_mut().find(|(v, _)| Arc::ptr_eq(v, vt)) {
                Some((_, samplers)) => samplers.push(slot.sampler),
                None => out.push((vt.clone(), vec![slot.sampler])),
            }
        }
        out
    }

    /// Makes `texture` the base-colour image of every material without a procedural colour
    /// (replacing the image of those that have one, keeping their sampler and transform;
    /// the others get a default slot). Returns how many materials drawn by a mesh take it.
    pub fn set_base_color_texture(&mut self, texture: Arc<Texture2D>) -> usize {
        for m in &mut self.materials {
            if m.procedural.is_some() {
                continue;
            }
            match &mut m.base_color_texture {
                Some(slot) => {
                    slot.texture = texture.clone();
                    slot.virtual_texture = None;
                }
                None => {
                    m.base_color_texture =
                        Some(TextureSlot::new(texture.clone(), Sampler::default()))
                }
            }
        }
        let used: std::collections::BTreeSet<usize> =
            self.meshes.iter().map(|m| m.material).collect();
        used.into_iter()
            .filter(|&i| {
                self.materials
                    .get(i)
                    .is_some_and(|m| m.procedural.is_none())
            })
            .count()
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
    pub(crate) fn bounding_sphere(&self) -> (Vec3, f32) {
        let (lo, hi) = self.bounds();
        let c = (lo + hi) * 0.5;
        let r = self
            .world_positions()
            .map(|p| p.distance(c))
            .fold(0.0f32, f32::max);
        (c, if r > 0.0 { r } else { 1.0 })
    }

    /// The finite world positions of every mesh (a non-finite one frames nothing).
    fn world_positions(&self) -> impl Iterator<Item = Vec3> + '_ {
        self.meshes.iter().flat_map(|m| {
            let identity = m.world_from_object == Mat4::IDENTITY;
            m.positions
                .iter()
                .map(move |&p| {
                    if identity {
                        p
                    } else {
                        m.world_from_object.transform_point3(p)
                    }
                })
                .filter(|p| p.is_finite())
        })
    }

    /// Removes every triangle with a vertex whose world position is not finite (NaN, ±∞, or
    /// a transform that overflows it) or whose index is out of range; returns how many went.
    /// Loaders call it, so such faces are dropped with a warning rather than silently.
    pub fn drop_unusable_triangles(&mut self) -> usize {
        let mut dropped = 0;
        for m in &mut self.meshes {
            let world: Vec<bool> = m
                .positions
                .iter()
                .map(|&p| m.world_from_object.transform_point3(p).is_finite())
                .collect();
            let ok = |i: u32| world.get(i as usize).copied().unwrap_or(false);
            let before = m.indices.len() / 3;
            let kept: Vec<u32> = m
                .indices
                .chunks_exact(3)
                .filter(|t| t.iter().all(|&i| ok(i)))
                .flatten()
                .copied()
                .collect();
            dropped += before - kept.len() / 3;
            m.indices = kept;
        }
        dropped
    }

    /// Whether some triangle has a non-zero area in world space (a zero scale or a mesh of
    /// coincident vertices draws nothing). Stops at the first one found.
    #[must_use]
    pub fn any_triangle_has_area(&self) -> bool {
        self.meshes.iter().any(|m| {
            let p = |i: u32| {
                m.positions
                    .get(i as usize)
                    .map(|&p| m.world_from_object.transform_point3(p))
            };
            m.indices
                .chunks_exact(3)
                .any(|t| match (p(t[0]), p(t[1]), p(t[2])) {
                    (Some(a), Some(b), Some(c)) => (b - a).cross(c - a).length_squared() > 0.0,
                    _ => false,
                })
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn framing_camera_follows_the_peers_rule() {
        let scene = builtin::sphere(2000, None, Default::default());
        let cam = scene.framing_camera(60.0);
        assert!(cam.target.length() < 1e-5);
        assert!((cam.eye.z - 2.2).abs() < 1e-4, "{}", cam.eye);
        assert!((cam.near - 0.7).abs() < 1e-4 && (cam.far - 3.7).abs() < 1e-4);
    }
}
