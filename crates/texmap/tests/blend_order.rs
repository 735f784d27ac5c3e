//! The order of blended surfaces, as `../shared/peers/gl_render.py` (and the Khronos sample
//! viewer) draw them: blended meshes after the opaque ones, back to front by the view depth of
//! each mesh's centroid, and each mesh's triangles in index order.
//!
//! Unlit, half-transparent colours over a black background, seen by an orthographic camera
//! (coverage is then the xy projection): "over" is not commutative, so the centre pixel tells
//! the order: red over blue is (0.5, 0, 0.25), blue over red (0.25, 0, 0.5).

use glam::{Vec3, Vec4};
use texmap::camera::{Camera, CameraProjection};
use texmap::render::{render, Settings, Visibility};
use texmap::scene::{AlphaMode, Material, Mesh, Scene};

const RED: Vec4 = Vec4::new(1.0, 0.0, 0.0, 0.5);
const BLUE: Vec4 = Vec4::new(0.0, 0.0, 1.0, 0.5);
const RED_OVER_BLUE: Vec4 = Vec4::new(0.5, 0.0, 0.25, 0.75);
const BLUE_OVER_RED: Vec4 = Vec4::new(0.25, 0.0, 0.5, 0.75);

fn blended(color: Vec4) -> Material {
    Material {
        base_color: color,
        unlit: true,
        double_sided: true,
        alpha_mode: AlphaMode::Blend,
        ..Material::default()
    }
}

fn triangle(p: [Vec3; 3], material: usize) -> Mesh {
    Mesh {
        positions: p.to_vec(),
        indices: vec![0, 1, 2],
        material,
        ..Mesh::default()
    }
}

fn centre(scene: &Scene, visibility: Visibility) -> Vec4 {
    let cam = Camera {
        eye: Vec3::new(0.0, 0.0, 10.0),
        target: Vec3::ZERO,
        up: Vec3::Y,
        projection: CameraProjection::Orthographic { half_height: 5.0 },
        near: 0.0,
        far: 30.0,
    };
    let s = Settings::new(32, 32).with_visibility(visibility);
    render(scene, &cam, &s).unwrap().color[16 * 32 + 16]
}

fn assert_close(got: Vec4, want: Vec4, what: &str) {
    assert!(
        (got - want).abs().max_element() < 1e-5,
        "{what}: {got}, expected {want}"
    );
}

#[test]
fn blended_meshes_are_sorted_by_their_centroid_not_their_farthest_vertex() {
    // Red: a triangle tilted away, one corner far behind (z = −8) but its centroid near
    // (z = −0.67). Blue: flat at z = −1. Sorted by farthest vertex red would come first;
    // sorted by centroid blue is farther, so red is blended over it.
    let red = triangle(
        [
            Vec3::new(-3.0, -3.0, 3.0),
            Vec3::new(3.0, -3.0, 3.0),
            Vec3::new(0.0, 4.0, -8.0),
        ],
        0,
    );
    let blue = triangle(
        [
            Vec3::new(-1.0, -1.0, -1.0),
            Vec3::new(1.0, -1.0, -1.0),
            Vec3::new(0.0, 1.0, -1.0),
        ],
        1,
    );
    for meshes in [vec![red.clone(), blue.clone()], vec![blue, red]] {
        let scene = Scene {
            meshes,
            materials: vec![blended(RED), blended(BLUE)],
            ..Scene::default()
        };
        assert_close(
            centre(&scene, Visibility::ZBuffer),
            RED_OVER_BLUE,
            "centroid order",
        );
        // The painter's algorithm still sorts triangles by their farthest vertex.
        assert_close(
            centre(&scene, Visibility::DepthSort),
            BLUE_OVER_RED,
            "painter's order",
        );
    }
}

#[test]
fn a_blended_mesh_draws_its_triangles_in_index_order_and_ties_keep_scene_order() {
    // One mesh, two triangles through the centre: the near red one first in the index list,
    // the far blue one second. As on a GPU, blue is blended over red.
    let near = [
        Vec3::new(-2.0, -2.0, 2.0),
        Vec3::new(2.0, -2.0, 2.0),
        Vec3::new(0.0, 2.0, 2.0),
    ];
    let far = near.map(|p| p - Vec3::Z * 4.0);
    let mut mesh = triangle(near, 0);
    mesh.positions.extend(far);
    mesh.indices = vec![0, 1, 2, 3, 4, 5];
    mesh.colors = [RED; 3].into_iter().chain([BLUE; 3]).collect();
    let white = Vec4::new(1.0, 1.0, 1.0, 1.0);
    let scene = Scene {
        meshes: vec![mesh],
        materials: vec![blended(white)],
        ..Scene::default()
    };
    assert_close(
        centre(&scene, Visibility::ZBuffer),
        BLUE_OVER_RED,
        "index order",
    );
    // Two meshes with the same centroid depth: drawn in scene order, the second over the first.
    let a = triangle(near, 0);
    let b = triangle(near, 1);
    let scene = Scene {
        meshes: vec![a, b],
        materials: vec![blended(RED), blended(BLUE)],
        ..Scene::default()
    };
    assert_close(
        centre(&scene, Visibility::ZBuffer),
        BLUE_OVER_RED,
        "scene order",
    );
}
