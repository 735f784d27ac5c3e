//! Double-sided materials seen from behind: every shading mode lights the back face with the
//! flipped normal, so a light on the viewer's side lights it and a light on the far side
//! leaves it dark (ambient only).

use std::sync::Arc;

use glam::{Vec2, Vec3, Vec4};
use texmap::camera::{Camera, CameraProjection};
use texmap::geometry::Projection;
use texmap::render::{render, Settings, ShadingMode};
use texmap::scene::{Light, Material, Mesh, Procedural, Scene, TextureSlot};
use texmap::texture::{ColorSpace, Sampler, Texture2D};

/// A 2×2 square in the plane z = 0, counter-clockwise seen from +z (its front), with vertex
/// normals +z.
fn square() -> Mesh {
    Mesh {
        positions: vec![
            Vec3::new(-1.0, -1.0, 0.0),
            Vec3::new(1.0, -1.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(-1.0, 1.0, 0.0),
        ],
        normals: vec![Vec3::Z; 4],
        uvs: vec![Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::Y],
        indices: vec![0, 1, 2, 0, 2, 3],
        ..Mesh::default()
    }
}

fn scene(mesh: Mesh, material: Material, light_towards: Vec3) -> Scene {
    Scene {
        meshes: vec![mesh],
        materials: vec![material],
        lights: vec![Light::Directional {
            direction: light_towards,
            color: Vec3::ONE,
        }],
        ambient_light: Vec3::ONE,
        ..Scene::default()
    }
}

/// Looking at the square's back: from z = −3 towards +z.
fn behind() -> Camera {
    Camera {
        eye: Vec3::new(0.0, 0.0, -3.0),
        target: Vec3::ZERO,
        up: Vec3::Y,
        projection: CameraProjection::Perspective { fov_y_deg: 60.0 },
        near: 0.1,
        far: 10.0,
    }
}

fn centre(scene: &Scene, shading: ShadingMode) -> Vec4 {
    let s = Settings::new(32, 32).with_shading(shading);
    render(scene, &behind(), &s).unwrap().color[16 * 32 + 16]
}

#[test]
fn back_faces_are_lit_from_their_own_side_in_every_shading_mode() {
    let double = Material {
        double_sided: true,
        ..Material::default()
    };
    for shading in [ShadingMode::Flat, ShadingMode::Gouraud, ShadingMode::Phong] {
        // Light on the viewer's side (towards −z): K_A + K_D = 0.2 + 0.8.
        let lit = centre(&scene(square(), double.clone(), -Vec3::Z), shading);
        assert!((lit.x - 1.0).abs() < 1e-4, "{shading:?} lit: {lit}");
        // Light on the front side only: ambient.
        let dark = centre(&scene(square(), double.clone(), Vec3::Z), shading);
        assert!((dark.x - 0.2).abs() < 1e-4, "{shading:?} dark: {dark}");
    }
    // Single-sided materials keep their own normal on both sides (as Phong always did).
    let single = Material::default();
    for shading in [ShadingMode::Gouraud, ShadingMode::Phong] {
        let c = centre(&scene(square(), single.clone(), Vec3::Z), shading);
        assert!((c.x - 1.0).abs() < 1e-4, "{shading:?}: {c}");
    }
}

#[test]
fn a_back_face_looks_like_the_front_of_its_mirror_twin_with_every_varying() {
    // The largest Gouraud draw: vertex colours, a second uv set read by the base colour, a
    // projected texture (object position and normal), specular, double-sided.
    let white = Arc::new(Texture2D::from_rgba8(1, 1, ColorSpace::Srgb, &[255; 4]).unwrap());
    let mut slot = TextureSlot::new(white.clone(), Sampler::default());
    slot.tex_coord = 1;
    let material = Material {
        double_sided: true,
        specular: 0.5,
        shininess: 4.0,
        base_color_texture: Some(slot),
        procedural: Some(Procedural::Projected {
            slot: TextureSlot::new(white, Sampler::default()),
            projection: Projection::Spherical,
        }),
        ..Material::default()
    };
    let mut mesh = square();
    mesh.colors = vec![Vec4::ONE; 4];
    mesh.uvs1 = mesh.uvs.clone();
    // The twin: the same square facing the camera (winding reversed, normals flipped).
    let mut twin = mesh.clone();
    twin.indices = vec![0, 2, 1, 0, 3, 2];
    twin.normals = vec![-Vec3::Z; 4];
    // A point light on the viewer's side, off the axis: diffuse and specular vary.
    let lights = vec![Light::Point {
        position: Vec3::new(0.8, 0.5, -1.5),
        color: Vec3::splat(3.0),
        range: None,
    }];
    let frame = |mesh: &Mesh, shading| {
        let mut sc = scene(mesh.clone(), material.clone(), Vec3::Z);
        sc.lights = lights.clone();
        let s = Settings::new(48, 48).with_shading(shading);
        render(&sc, &behind(), &s).unwrap().color
    };
    for shading in [ShadingMode::Gouraud, ShadingMode::Phong, ShadingMode::Flat] {
        let back = frame(&mesh, shading);
        let front = frame(&twin, shading);
        let worst = back
            .iter()
            .zip(&front)
            .map(|(a, b)| (*a - *b).abs().max_element())
            .fold(0.0f32, f32::max);
        assert!(worst < 1e-4, "{shading:?}: differs by {worst}");
        // The light reaches the surface: brighter than ambient (0.2) somewhere, and unevenly.
        let xs: Vec<f32> = back.iter().filter(|c| c.w > 0.0).map(|c| c.x).collect();
        let hi = xs.iter().copied().fold(0.0f32, f32::max);
        let lo = xs.iter().copied().fold(f32::INFINITY, f32::min);
        assert!(hi > 0.5 && hi - lo > 0.05, "{shading:?}: {lo} .. {hi}");
    }
}
