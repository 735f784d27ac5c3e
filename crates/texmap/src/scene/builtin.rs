//! Built-in scenes, generated in code: the peers' plane and sphere, and a showcase.
//!
//! `plane` and `sphere` follow `../shared/peers` exactly (geometry, uv, camera, lighting
//! `tex·(0.2 + 0.8·max(N·L, 0))` with `L = normalize(0.3, 0.8, 0.5)`), so their images can be
//! compared with `gl_render.py`'s pixel for pixel.

use std::sync::{Arc, OnceLock};

use glam::{Mat4, Quat, Vec2, Vec3, Vec4};

use super::{Light, Material, Mesh, Procedural, Scene, TextureSlot};
use crate::camera::{Camera, CameraProjection};
use crate::shading::ibl::Environment;
use crate::shading::shadow::{ShadowParams, Shadows};
use crate::shading::AlphaMode;
use crate::texture::environment::{equirect_direction, EnvironmentMap};
use crate::texture::procedural::Solid;
use crate::texture::{
    ColorSpace, Filter, Sampler, Texture2D, TextureOptions, TextureTransform, Wrap,
};
use crate::{Error, Result};

/// The peers' light direction (towards the light, world space), before normalizing.
pub const PEER_LIGHT: Vec3 = Vec3::new(0.3, 0.8, 0.5);

/// The peers' checker image: 1024×1024 RGB, 8×8-texel squares, (235, 235, 235) where the
/// square index sum is even (texel (0, 0)), else (40, 60, 150); as RGBA8 bytes, alpha 255.
#[must_use]
pub fn checker_rgba8() -> Vec<u8> {
    const N: usize = 1024;
    let mut out = Vec::with_capacity(N * N * 4);
    for y in 0..N {
        for x in 0..N {
            let c = if ((x / 8) + (y / 8)) % 2 == 0 {
                [235, 235, 235, 255]
            } else {
                [40, 60, 150, 255]
            };
            out.extend_from_slice(&c);
        }
    }
    out
}

/// The checker as an sRGB texture with its mip chain (built once per process).
#[must_use]
pub fn checker_texture() -> Arc<Texture2D> {
    static TEX: OnceLock<Arc<Texture2D>> = OnceLock::new();
    TEX.get_or_init(|| {
        // 1024² RGBA8 with the right byte count cannot fail.
        let tex = Texture2D::from_rgba8(1024, 1024, ColorSpace::Srgb, &checker_rgba8())
            .unwrap_or_else(|e| unreachable!("checker texture: {e}"));
        Arc::new(tex)
    })
    .clone()
}

fn peer_material(texture: Arc<Texture2D>, sampler: Sampler) -> Material {
    Material {
        base_color_texture: Some(TextureSlot::new(texture, sampler)),
        ambient: 0.2,
        diffuse: 0.8,
        specular: 0.0,
        double_sided: true,
        ..Default::default()
    }
}

fn peer_lighting(scene: &mut Scene) {
    scene.lights = vec![Light::Directional {
        direction: PEER_LIGHT.normalize(),
        color: Vec3::ONE,
    }];
    scene.ambient_light = Vec3::ONE;
    scene.background = Vec4::new(0.0, 0.0, 0.0, 1.0);
}

/// A square at y = 0, x and z in [−half, half], normal +y, `u = (x + half)/(2·half)`,
/// `v = (z + half)/(2·half)`: two counter-clockwise (seen from +y) triangles.
fn ground(half: f32, material: usize) -> Mesh {
    let positions = vec![
        Vec3::new(-half, 0.0, -half),
        Vec3::new(half, 0.0, -half),
        Vec3::new(half, 0.0, half),
        Vec3::new(-half, 0.0, half),
    ];
    let uvs = positions
        .iter()
        .map(|p| Vec2::new((p.x + half) / (2.0 * half), (p.z + half) / (2.0 * half)))
        .collect();
    Mesh {
        normals: vec![Vec3::Y; 4],
        positions,
        uvs,
        indices: vec![0, 3, 2, 0, 2, 1],
        material,
        world_from_object: Mat4::IDENTITY,
        ..Default::default()
    }
}

/// The peers' ground plane (grazing-angle test): two triangles at y = 0, x, z ∈ [−100, 100],
/// `u = (x+100)/200·S`, `v = (z+100)/200·S` with `S = uv_scale` (the peers' default is 64,
/// held as the scene's [`Scene::uv_scale`], so `--uv-scale` sets the repeat count as in
/// `gl_render.py`);
/// camera at (0, 1, 0) looking at (0, 0, −50), fov 60°, near 0.05, far 1000.
///
/// `texture` defaults to the peers' checker ([`checker_texture`]).
#[must_use]
pub fn plane(texture: Option<Arc<Texture2D>>, uv_scale: f32, sampler: Sampler) -> Scene {
    let texture = texture.unwrap_or_else(checker_texture);
    let mut scene = Scene {
        meshes: vec![ground(100.0, 0)],
        materials: vec![peer_material(texture, sampler)],
        uv_scale,
        camera: Some(Camera {
            eye: Vec3::new(0.0, 1.0, 0.0),
            target: Vec3::new(0.0, 0.0, -50.0),
            up: Vec3::Y,
            projection: CameraProjection::Perspective { fov_y_deg: 60.0 },
            near: 0.05,
            far: 1000.0,
        }),
        ..Default::default()
    };
    peer_lighting(&mut scene);
    scene
}

/// `make_data.py`'s `uv_sphere`: unit radius, `rings` latitude lines including the poles,
/// `slices + 1` vertices per ring (the seam duplicated), position = normal =
/// (sin θ cos φ, cos θ, −sin θ sin φ), uv = (φ/2π, θ/π), degenerate pole triangles dropped.
#[must_use]
pub fn uv_sphere(slices: usize, rings: usize, material: usize) -> Mesh {
    let slices = slices.max(3);
    let rings = rings.max(3);
    let linspace = |stop: f64, num: usize, i: usize| {
        if i + 1 == num {
            stop
        } else {
            i as f64 * (stop / (num - 1) as f64)
        }
    };
    let w = slices + 1;
    let mut pos64 = Vec::with_capacity(rings * w);
    let mut uvs = Vec::with_capacity(rings * w);
    for i in 0..rings {
        let th = linspace(std::f64::consts::PI, rings, i);
        for k in 0..w {
            let ph = linspace(2.0 * std::f64::consts::PI, w, k);
            pos64.push(glam::DVec3::new(
                th.sin() * ph.cos(),
                th.cos(),
                -th.sin() * ph.sin(),
            ));
            uvs.push(Vec2::new(
                (ph / (2.0 * std::f64::consts::PI)) as f32,
                (th / std::f64::consts::PI) as f32,
            ));
        }
    }
    let mut indices = Vec::with_capacity((rings - 1) * slices * 6);
    for i in 0..rings - 1 {
        for k in 0..slices {
            let a = i * w + k;
            let b = a + w;
            for t in [[a, b, a + 1], [a + 1, b, b + 1]] {
                let area = (pos64[t[1]] - pos64[t[0]])
                    .cross(pos64[t[2]] - pos64[t[0]])
                    .length();
                if area > 1e-12 {
                    indices.extend(t.map(|x| x as u32));
                }
            }
        }
    }
    let positions: Vec<Vec3> = pos64.iter().map(|p| p.as_vec3()).collect();
    Mesh {
        normals: positions.clone(),
        positions,
        uvs,
        indices,
        material,
        world_from_object: Mat4::IDENTITY,
        ..Default::default()
    }
}

/// Slices and rings for about `triangles` triangles with the peers' proportions
/// (`rings ≈ slices·251/400`; 199,200 → 400 × 251).
#[must_use]
pub fn sphere_resolution(triangles: usize) -> (usize, usize) {
    // triangles = 2·s·(rings − 2) with rings = 0.6275·s.
    let k = 251.0 / 400.0;
    let t = triangles as f64;
    let s = (4.0 + (16.0 + 8.0 * k * t).sqrt()) / (4.0 * k);
    let slices = (s.round() as usize).max(3);
    let rings = ((slices as f64 * k).round() as usize).max(3);
    (slices, rings)
}

/// The peers' textured UV sphere with about `triangles` triangles (the peers' 400 × 251 =
/// 199,200 for 199,200), lit like the plane, framed by [`Scene::framing_camera`] at 60°.
///
/// `texture` defaults to the checker.
#[must_use]
pub fn sphere(triangles: usize, texture: Option<Arc<Texture2D>>, sampler: Sampler) -> Scene {
    let (slices, rings) = sphere_resolution(triangles);
    let texture = texture.unwrap_or_else(checker_texture);
    let mut scene = Scene {
        meshes: vec![uv_sphere(slices, rings, 0)],
        materials: vec![peer_material(texture, sampler)],
        ..Default::default()
    };
    peer_lighting(&mut scene);
    scene.camera = Some(scene.framing_camera(60.0));
    scene
}

/// An axis-aligned cube of side 1 centred at the origin: 24 vertices, each face with its own
/// normal and uv in [0, 1].
#[must_use]
pub fn cube(material: usize, world_from_object: Mat4) -> Mesh {
    let faces = [
        (Vec3::X, Vec3::NEG_Z, Vec3::Y),
        (Vec3::NEG_X, Vec3::Z, Vec3::Y),
        (Vec3::Y, Vec3::X, Vec3::NEG_Z),
        (Vec3::NEG_Y, Vec3::X, Vec3::Z),
        (Vec3::Z, Vec3::X, Vec3::Y),
        (Vec3::NEG_Z, Vec3::NEG_X, Vec3::Y),
    ];
    let mut m = Mesh {
        material,
        world_from_object,
        ..Default::default()
    };
    for (n, right, up) in faces {
        let base = m.positions.len() as u32;
        for (du, dv) in [(-0.5f32, -0.5f32), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)] {
            m.positions.push(n * 0.5 + right * du + up * dv);
            m.normals.push(n);
            m.uvs.push(Vec2::new(du + 0.5, 0.5 - dv));
        }
        m.indices
            .extend([base, base + 1, base + 2, base, base + 2, base + 3]);
    }
    m
}

fn procedural(size: u32, f: impl Fn(f32, f32) -> [u8; 4]) -> Arc<Texture2D> {
    let mut bytes = Vec::with_capacity((size * size * 4) as usize);
    for y in 0..size {
        for x in 0..size {
            let (u, v) = (
                (x as f32 + 0.5) / size as f32,
                (y as f32 + 0.5) / size as f32,
            );
            bytes.extend_from_slice(&f(u, v));
        }
    }
    let tex = Texture2D::from_rgba8(size, size, ColorSpace::Srgb, &bytes)
        .unwrap_or_else(|e| unreachable!("procedural texture: {e}"));
    Arc::new(tex)
}

fn mix(a: [f32; 3], b: [f32; 3], t: f32) -> [u8; 4] {
    let c = |i: usize| ((a[i] + (b[i] - a[i]) * t.clamp(0.0, 1.0)) * 255.0 + 0.5) as u8;
    [c(0), c(1), c(2), 255]
}

/// Bricks with mortar lines, 4 × 8 per image, odd rows offset by half a brick.
fn brick_texture() -> Arc<Texture2D> {
    procedural(256, |u, v| {
        let row = (v * 8.0).floor();
        let bu = u * 4.0 + if row as i32 % 2 == 1 { 0.5 } else { 0.0 };
        let (fu, fv) = (bu.fract(), (v * 8.0).fract());
        let mortar = fu < 0.05 || fv < 0.1;
        if mortar {
            [200, 195, 185, 255]
        } else {
            let shade = 0.8 + 0.2 * ((bu.floor() * 7.3 + row * 3.1).sin() * 0.5 + 0.5);
            mix(
                [0.0, 0.0, 0.0],
                [0.70 * shade, 0.28 * shade, 0.18 * shade],
                1.0,
            )
        }
    })
}

/// The demo's sky, an equirectangular panorama made here (256×128, linear radiance): a
/// gradient from a pale horizon to a blue zenith, a warm glow and a small bright sun disc
/// towards `sun`, and a dim ground below the horizon. Made once; its prefiltered forms are
/// shared by every copy (they live behind the `Environment`'s `Arc`).
fn demo_sky(sun: Vec3) -> Environment {
    static SKY: OnceLock<Environment> = OnceLock::new();
    SKY.get_or_init(|| {
        let (w, h) = (256, 128);
        // Rows are v = y/(h − 1), columns texel centres (the equirect convention).
        let panorama = Texture2D::from_fn(w, h, TextureOptions::default(), |x, y| {
            let u = (x as f32 + 0.5) / w as f32;
            let v = y as f32 / (h - 1) as f32;
            let d = equirect_direction(u, v);
            let c = if d.y >= 0.0 {
                let towards = d.dot(sun).max(0.0);
                let disc = if towards > 0.9994 { 60.0 } else { 0.0 };
                Vec3::new(0.78, 0.85, 0.95).lerp(Vec3::new(0.2, 0.4, 0.85), d.y.sqrt())
                    + Vec3::new(1.0, 0.85, 0.6) * (0.8 * towards.powi(48) + disc)
            } else {
                Vec3::new(0.3, 0.28, 0.25) * (1.0 + 0.5 * d.y)
            };
            c.extend(1.0)
        })
        .unwrap_or_else(|e| unreachable!("demo sky: {e}"));
        Environment::new(EnvironmentMap::Equirect(panorama), "builtin:demo sky")
    })
    .clone()
}

/// A showcase: a checker floor receding to the horizon (anisotropic filtering), a sphere carved
/// from a block of solid marble (an antialiased procedural texture) that mirrors a little of
/// the sky, a brick cube and a translucent panel, lit by a directional and a point light with
/// Phong specular highlights, both casting shadows, and by the sky around them (image-based
/// light, the background).
#[must_use]
pub fn demo() -> Scene {
    // The floor recedes to the horizon: 8× anisotropic filtering keeps it sharp without moiré.
    let sampler = Sampler::new(Filter::aniso(8), Wrap::Repeat);
    let floor = Material {
        base_color_texture: Some(TextureSlot {
            texture: checker_texture(),
            sampler,
            transform: TextureTransform::default(),
            uv_scale: 16.0,
            tex_coord: 0,
            virtual_texture: None,
        }),
        ambient: 0.3,
        diffuse: 0.7,
        specular: 0.2,
        shininess: 16.0,
        double_sided: true,
        ..Default::default()
    };
    let marble_solid = Solid::named("marble").unwrap_or(Solid::Checker3D { size: 0.25 });
    let marble = Material {
        procedural: Some(Procedural::Solid {
            colors: marble_solid.default_colors(),
            solid: marble_solid,
            antialias: true,
        }),
        ambient: 0.25,
        diffuse: 0.75,
        specular: 0.6,
        shininess: 60.0,
        reflection: 0.12,
        ..Default::default()
    };
    let bricks = Material {
        base_color_texture: Some(TextureSlot::new(brick_texture(), sampler)),
        ambient: 0.25,
        diffuse: 0.8,
        specular: 0.15,
        shininess: 8.0,
        ..Default::default()
    };
    let glass = Material {
        base_color: Vec4::new(0.3, 0.7, 1.0, 0.35),
        ambient: 0.4,
        diffuse: 0.6,
        specular: 0.8,
        shininess: 80.0,
        double_sided: true,
        alpha_mode: AlphaMode::Blend,
        ..Default::default()
    };
    let mut ball = uv_sphere(96, 61, 1);
    ball.world_from_object = Mat4::from_translation(Vec3::new(-1.4, 1.0, 0.0));
    let block = cube(
        2,
        Mat4::from_scale_rotation_translation(
            Vec3::splat(1.4),
            Quat::from_rotation_y(0.5),
            Vec3::new(1.5, 0.7, -0.3),
        ),
    );
    let sun = Vec3::new(-0.4, 0.8, 0.45).normalize();
    let mut panel = ground(0.8, 3);
    panel.world_from_object = Mat4::from_translation(Vec3::new(0.2, 0.9, 1.6))
        * Mat4::from_rotation_x(std::f32::consts::FRAC_PI_2);
    Scene {
        meshes: vec![ground(400.0, 0), ball, block, panel],
        materials: vec![floor, marble, bricks, glass],
        lights: vec![
            Light::Directional {
                direction: sun,
                color: Vec3::splat(0.7),
            },
            Light::Point {
                position: Vec3::new(1.0, 3.0, 2.5),
                color: Vec3::new(1.0, 0.85, 0.6) * 8.0,
                range: Some(40.0),
            },
        ],
        ambient_light: Vec3::new(0.6, 0.7, 0.9),
        background: Vec4::new(0.35, 0.55, 0.85, 1.0),
        camera: Some(Camera {
            eye: Vec3::new(0.0, 2.0, 6.5),
            target: Vec3::new(0.0, 0.8, 0.0),
            up: Vec3::Y,
            projection: CameraProjection::Perspective { fov_y_deg: 50.0 },
            near: 0.05,
            far: 1000.0,
        }),
        uv_scale: 1.0,
        // Both lights cast: the sun's map is fitted to where shadows can fall (the objects
        // over the floor), the point light's is a cube of six around it.
        shadows: Shadows::casting(vec![0, 1])
            .with_params(ShadowParams::default().with_map_size(1024)),
        environment: Some(demo_sky(sun)),
        projectors: Vec::new(),
    }
}

/// The solid-texture showcase (`builtin:marble`): a sphere and a cube carved from marble, a
/// wood block, on a granite floor — each pattern evaluated in its object's space and
/// antialiased by the pixel footprint, so the far floor settles to its mean instead of
/// shimmering.
#[must_use]
pub fn marble() -> Scene {
    let solid = |name: &str, specular: f32| {
        let solid = Solid::named(name).unwrap_or(Solid::Checker3D { size: 0.25 });
        Material {
            procedural: Some(Procedural::Solid {
                colors: solid.default_colors(),
                solid,
                antialias: true,
            }),
            ambient: 0.25,
            diffuse: 0.75,
            specular,
            shininess: 50.0,
            ..Default::default()
        }
    };
    let mut ball = uv_sphere(128, 65, 0);
    ball.world_from_object = Mat4::from_translation(Vec3::new(-1.3, 1.0, 0.0));
    let block = cube(
        0,
        Mat4::from_translation(Vec3::new(0.4, 0.6, -0.6)) * Mat4::from_scale(Vec3::splat(1.2)),
    );
    let wood = cube(
        1,
        Mat4::from_scale_rotation_translation(
            Vec3::new(1.6, 0.5, 0.8),
            Quat::from_rotation_y(-0.4),
            Vec3::new(1.8, 0.25, 0.9),
        ),
    );
    // Solid textures live in object space: the floor is modelled at full size (not a scaled
    // unit square), so its granite grains keep their size.
    let floor = ground(200.0, 2);
    Scene {
        meshes: vec![floor, ball, block, wood],
        materials: vec![
            solid("marble", 0.6),
            solid("wood", 0.2),
            solid("granite", 0.1),
        ],
        lights: vec![
            Light::Directional {
                direction: Vec3::new(-0.4, 0.8, 0.45).normalize(),
                color: Vec3::splat(0.8),
            },
            Light::Point {
                position: Vec3::new(1.0, 3.0, 2.5),
                color: Vec3::new(1.0, 0.9, 0.75) * 6.0,
                range: Some(40.0),
            },
        ],
        ambient_light: Vec3::new(0.6, 0.65, 0.75),
        background: Vec4::new(0.3, 0.35, 0.45, 1.0),
        camera: Some(Camera {
            eye: Vec3::new(0.0, 2.2, 6.0),
            target: Vec3::new(0.2, 0.7, 0.0),
            up: Vec3::Y,
            projection: CameraProjection::Perspective { fov_y_deg: 50.0 },
            near: 0.05,
            far: 1000.0,
        }),
        uv_scale: 1.0,
        shadows: Default::default(),
        environment: None,
        projectors: Vec::new(),
    }
}

/// The built-in scenes, by the names the command line gives them (`builtin:demo`, …).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Builtin {
    /// [`demo`].
    Demo,
    /// [`plane`] with the checker, 64 repeats, trilinear.
    Plane,
    /// [`sphere`] with the checker (199,200 triangles unless told), trilinear.
    Sphere,
    /// [`marble`].
    Marble,
}

impl Builtin {
    pub const ALL: [Builtin; 4] = [
        Builtin::Demo,
        Builtin::Plane,
        Builtin::Sphere,
        Builtin::Marble,
    ];

    /// `builtin:demo`, `builtin:plane`, `builtin:sphere` or `builtin:marble`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Builtin::Demo => "builtin:demo",
            Builtin::Plane => "builtin:plane",
            Builtin::Sphere => "builtin:sphere",
            Builtin::Marble => "builtin:marble",
        }
    }

    /// The scene called `name`, or an error listing the names for any other `builtin:…`;
    /// `None` when `name` does not start with `builtin:` (a file, then).
    ///
    /// # Errors
    /// [`Error::Parameter`] for an unknown built-in name.
    pub fn parse(name: &str) -> Result<Option<Builtin>> {
        if !name.starts_with("builtin:") {
            return Ok(None);
        }
        Builtin::ALL
            .into_iter()
            .find(|b| b.name() == name)
            .map(Some)
            .ok_or_else(|| {
                let names: Vec<&str> = Builtin::ALL.iter().map(|b| b.name()).collect();
                Error::parameter(format!(
                    "{name}: unknown built-in scene ({})",
                    names.join(", ")
                ))
            })
    }

    /// True for the scene made with a triangle count ([`Builtin::Sphere`]).
    #[must_use]
    pub fn takes_triangles(self) -> bool {
        self == Builtin::Sphere
    }

    /// The scene; `triangles` (8..=50,000,000) sets the sphere's count, and `texture` is the
    /// image the plane and the sphere wear instead of the checker (which is then never
    /// built). The other scenes ignore `texture`: [`Scene::set_base_color_texture`] gives any
    /// scene an image.
    ///
    /// # Errors
    /// [`Error::Parameter`] for a triangle count out of range, or given to a scene that takes
    /// none.
    pub fn build(self, triangles: Option<usize>, texture: Option<Arc<Texture2D>>) -> Result<Scene> {
        if let Some(n) = triangles {
            if !self.takes_triangles() {
                return Err(Error::parameter(format!(
                    "a triangle count applies to builtin:sphere, not {}",
                    self.name()
                )));
            }
            if !(8..=50_000_000).contains(&n) {
                return Err(Error::parameter(format!(
                    "triangle count {n} is outside 8..=50000000"
                )));
            }
        }
        Ok(match self {
            Builtin::Demo => demo(),
            Builtin::Plane => plane(texture, 64.0, Sampler::default()),
            Builtin::Sphere => sphere(triangles.unwrap_or(199_200), texture, Sampler::default()),
            Builtin::Marble => marble(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_sphere_is_400_by_251_with_199200_triangles() {
        assert_eq!(sphere_resolution(199_200), (400, 251));
        let m = uv_sphere(400, 251, 0);
        assert_eq!(m.triangle_count(), 199_200);
        assert_eq!(m.positions.len(), 251 * 401);
    }

    #[test]
    fn checker_matches_the_peers_png() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../../shared/peers/data/checker.png");
        let Ok(img) = image::open(&path) else {
            eprintln!("skipped: {} not found", path.display());
            return;
        };
        let rgb = img.to_rgb8();
        assert_eq!(rgb.dimensions(), (1024, 1024));
        let ours: Vec<u8> = checker_rgba8()
            .chunks_exact(4)
            .flat_map(|c| [c[0], c[1], c[2]])
            .collect();
        assert!(
            ours == rgb.as_raw().as_slice(),
            "checker differs from {}",
            path.display()
        );
    }

    #[test]
    fn ground_and_cube_face_outwards() {
        for m in [ground(1.0, 0), cube(0, Mat4::IDENTITY)] {
            for t in m.indices.chunks_exact(3) {
                let p = [t[0], t[1], t[2]].map(|i| m.positions[i as usize]);
                let n = (p[1] - p[0]).cross(p[2] - p[0]);
                assert!(n.dot(m.normals[t[0] as usize]) > 0.0);
            }
        }
    }
}
