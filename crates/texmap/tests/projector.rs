//! Slide projectors (projective textures): the light a projector delivers against the
//! closed form, the slide's orientation, nothing behind the projector or outside its
//! frustum, occlusion by its own depth map, every shading mode, the same image whatever the
//! thread count, and the golden image of `scenes/projector.toml` (PSNR ≥ [`MIN_PSNR`] dB
//! against `tests/golden/projector.png`, reviewed by eye).

mod common;

use std::path::Path;
use std::sync::Arc;

use glam::{Mat4, Vec2, Vec3, Vec4};
use texmap::camera::{Camera, CameraProjection};
use texmap::render::{render, Settings, ShadingMode, ShadowOverrides};
use texmap::scene::{Material, Mesh, Projector, Scene, TextureSlot};
use texmap::texture::{Filter, Sampler, Texture2D, TextureOptions, Wrap};

const MIN_PSNR: f64 = 40.0;
const SIZE: u32 = 64;

/// A `2·half` square in the object's z = 0 plane, facing +z.
fn wall(half: f32, at: Vec3) -> Mesh {
    Mesh {
        positions: vec![
            Vec3::new(-half, -half, 0.0),
            Vec3::new(half, -half, 0.0),
            Vec3::new(half, half, 0.0),
            Vec3::new(-half, half, 0.0),
        ],
        normals: vec![Vec3::Z; 4],
        uvs: vec![Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::Y],
        indices: vec![0, 1, 2, 0, 2, 3],
        world_from_object: Mat4::from_translation(at),
        ..Default::default()
    }
}

/// The slide: top-left red, top-right green, bottom-left blue, bottom-right white.
fn quadrants() -> Arc<Texture2D> {
    let t = Texture2D::from_fn(4, 4, TextureOptions::default(), |x, y| {
        match (x < 2, y < 2) {
            (true, true) => Vec4::new(1.0, 0.0, 0.0, 1.0),
            (false, true) => Vec4::new(0.0, 1.0, 0.0, 1.0),
            (true, false) => Vec4::new(0.0, 0.0, 1.0, 1.0),
            (false, false) => Vec4::ONE,
        }
    });
    Arc::new(t.unwrap())
}

/// A projector at `position` aiming at `target`, 40° square, no falloff, light 1.
fn projector(position: Vec3, target: Vec3) -> Projector {
    let sampler = Sampler::new(Filter::NEAREST, Wrap::ClampToBorder);
    Projector {
        position,
        target,
        up: Vec3::Y,
        fov_deg: 40.0,
        aspect: 1.0,
        slide: TextureSlot::new(quadrants(), sampler),
        color: Vec3::ONE,
        falloff: false,
        shadows: false,
    }
}

/// White Lambertian meshes lit by the projectors only (no lights, no ambient light).
fn scene(meshes: Vec<Mesh>, projectors: Vec<Projector>) -> Scene {
    Scene {
        meshes,
        materials: vec![Material {
            base_color: Vec4::ONE,
            ambient: 0.0,
            diffuse: 1.0,
            specular: 0.0,
            ..Default::default()
        }],
        projectors,
        background: Vec4::new(0.0, 0.0, 0.0, 1.0),
        ..Default::default()
    }
}

/// Looking at the z = 0 wall from +z, orthographic, 4 units high: pixel (i, j) sees the
/// world point (−2 + (i + ½)/16, 2 − (j + ½)/16, 0).
fn front_camera() -> Camera {
    Camera {
        eye: Vec3::new(0.0, 0.0, 6.0),
        target: Vec3::ZERO,
        up: Vec3::Y,
        projection: CameraProjection::Orthographic { half_height: 2.0 },
        near: 0.1,
        far: 20.0,
    }
}

/// The linear colour the frame holds at world point (x, y) of the wall.
fn at(frame: &texmap::render::Frame, x: f32, y: f32) -> Vec3 {
    let i = ((x + 2.0) * 16.0).floor() as u32;
    let j = ((2.0 - y) * 16.0).floor() as u32;
    frame.color[(j * SIZE + i) as usize].truncate()
}

/// The centre of the pixel [`at`] reads for world point (x, y).
fn centre(x: f32, y: f32) -> Vec3 {
    let i = ((x + 2.0) * 16.0).floor();
    let j = ((2.0 - y) * 16.0).floor();
    Vec3::new(-2.0 + (i + 0.5) / 16.0, 2.0 - (j + 0.5) / 16.0, 0.0)
}

fn draw(s: &Scene, settings: &Settings) -> texmap::render::Frame {
    render(s, &front_camera(), settings).unwrap()
}

#[test]
fn the_light_is_the_slide_times_n_dot_l_and_its_top_left_is_up_left() {
    let p = projector(Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO);
    let s = scene(vec![wall(2.0, Vec3::ZERO)], vec![p.clone()]);
    let f = draw(&s, &Settings::new(SIZE, SIZE));
    for (x, y, slide) in [
        (-0.5, 0.5, Vec3::X),
        (0.5, 0.5, Vec3::Y),
        (-0.5, -0.5, Vec3::Z),
        (0.5, -0.5, Vec3::ONE),
    ] {
        let q = centre(x, y);
        let n_dot_l = (p.position - q).normalize().z;
        let got = at(&f, x, y);
        let want = slide * n_dot_l;
        assert!(
            (got - want).abs().max_element() < 1e-3,
            "({x}, {y}): {got} != {want}"
        );
    }
}

#[test]
fn with_falloff_the_light_is_inverse_square() {
    let mut p = projector(Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO);
    p.falloff = true;
    p.color = Vec3::splat(16.0);
    let s = scene(vec![wall(2.0, Vec3::ZERO)], vec![p.clone()]);
    let f = draw(&s, &Settings::new(SIZE, SIZE));
    let q = centre(0.5, -0.5);
    let to = p.position - q;
    let want = 16.0 * to.normalize().z / to.length_squared();
    let got = at(&f, 0.5, -0.5);
    assert!(
        (got - Vec3::splat(want)).abs().max_element() < 1e-3,
        "{got} {want}"
    );
}

#[test]
fn nothing_outside_the_frustum_and_its_edge_at_half_the_fov() {
    let p = projector(Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO);
    let s = scene(vec![wall(2.0, Vec3::ZERO)], vec![p]);
    let f = draw(&s, &Settings::new(SIZE, SIZE));
    let edge = 4.0 * 20f32.to_radians().tan(); // 1.456
    assert!(at(&f, edge - 0.1, 0.2).max_element() > 0.1);
    assert!(at(&f, 0.2, edge - 0.1).max_element() > 0.1);
    for (x, y) in [(edge + 0.1, 0.2), (0.2, -edge - 0.1), (1.9, 1.9)] {
        assert_eq!(at(&f, x, y), Vec3::ZERO, "({x}, {y})");
    }
}

#[test]
fn nothing_behind_the_projector() {
    // Aimed away from the wall: every wall point is behind it (its w < 0), though each
    // faces the projector (N·L > 0).
    let p = projector(Vec3::new(0.0, 0.0, 2.0), Vec3::new(0.0, 0.0, 4.0));
    let s = scene(vec![wall(2.0, Vec3::ZERO)], vec![p]);
    let f = draw(&s, &Settings::new(SIZE, SIZE));
    assert!(f.color.iter().all(|c| c.truncate() == Vec3::ZERO));
}

#[test]
fn its_depth_map_stops_the_slide_at_the_first_surface() {
    // A small card at z = 2 between the projector and the wall, off the axis: its shadow
    // falls on the wall around x = 1.0–1.46, beside the card as the camera sees it.
    let mut p = projector(Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO);
    p.shadows = true;
    let s = scene(
        vec![wall(2.0, Vec3::ZERO), wall(0.3, Vec3::new(0.5, 0.0, 2.0))],
        vec![p],
    );
    let lit = |cast: Option<bool>| {
        let mut o = ShadowOverrides::default();
        o.cast = cast;
        draw(&s, &Settings::new(SIZE, SIZE).with_shadows(o))
    };
    let (on, off) = (lit(None), lit(Some(false)));
    let shadowed = (1.2, -0.1);
    assert_eq!(at(&on, shadowed.0, shadowed.1), Vec3::ZERO);
    assert!(at(&off, shadowed.0, shadowed.1).max_element() > 0.5);
    // The card itself and the wall outside its shadow are lit either way.
    for (x, y) in [(0.5, 0.1), (-0.5, -0.5)] {
        let (a, b) = (at(&on, x, y), at(&off, x, y));
        assert!(
            a.max_element() > 0.3 && (a - b).abs().max_element() < 1e-3,
            "({x},{y})"
        );
    }
}

#[test]
fn every_shading_mode_lights_with_the_projector() {
    let p = projector(Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO);
    let s = scene(vec![wall(2.0, Vec3::ZERO)], vec![p]);
    let phong = draw(&s, &Settings::new(SIZE, SIZE));
    for mode in [ShadingMode::Gouraud, ShadingMode::Flat] {
        let f = draw(&s, &Settings::new(SIZE, SIZE).with_shading(mode));
        // A flat wall: the same light in every mode.
        for (x, y) in [(-0.5, 0.5), (0.5, -0.5), (1.3, 0.0)] {
            let (a, b) = (at(&phong, x, y), at(&f, x, y));
            assert!(
                (a - b).abs().max_element() < 1e-3,
                "{mode:?} ({x},{y}): {a} {b}"
            );
        }
    }
}

fn repo() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
}

fn projector_scene(w: u32, h: u32) -> Vec<u8> {
    let loaded =
        texmap::scene::load(&repo().join("scenes/projector.toml"), &Default::default()).unwrap();
    render(
        &loaded.scene,
        &loaded.scene.camera.unwrap(),
        &Settings::new(w, h),
    )
    .unwrap()
    .to_srgb8()
}

#[test]
fn golden_projector_scene() {
    let (w, h) = (256, 144);
    common::assert_golden("projector", w, h, &projector_scene(w, h), MIN_PSNR);
}

#[test]
fn the_same_image_whatever_the_thread_count() {
    let pool = |n| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap()
    };
    let one = pool(1).install(|| projector_scene(160, 90));
    let three = pool(3).install(|| projector_scene(160, 90));
    assert!(one == three, "1 and 3 threads differ");
}
