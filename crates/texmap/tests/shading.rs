//! Per-pixel surface parameters, rendered: a bump map tilts the normal as the surface it
//! describes would, heights scale with the object, the metallic-roughness texture drives
//! exactly the factors it multiplies, and Gouraud shading of a metallic-roughness material
//! stays close to Phong shading.

use std::sync::Arc;

use glam::{Mat4, Vec3, Vec4};
use texmap::metrics::compare_rgb8;
use texmap::render::{render, Frame, Settings, ShadingMode};
use texmap::scene::primitives::Primitive;
use texmap::scene::{
    builtin, Camera, CameraProjection, Light, Material, Scene, ShadingModel, SolidChannel,
    SolidMap, TextureSlot,
};
use texmap::shading::{MapChannel, MaterialMap};
use texmap::texture::procedural::Solid;
use texmap::texture::{Filter, Sampler, Texture2D, TextureOptions, Wrap};

const SIZE: u32 = 96;

/// The peers' light: directional from (0.3, 0.8, 0.5), colour 1, I_AL = 1.
fn light() -> Vec3 {
    Vec3::new(0.3, 0.8, 0.5).normalize()
}

/// A 2 × 2 plane at y = 0 (u = x/2 + ½, v = z/2 + ½) seen from straight above.
fn plane_scene(material: Material, scale: f32) -> (Scene, Camera) {
    let mut plane = Primitive::Plane {
        width: 2.0,
        depth: 2.0,
        divisions: 4,
    }
    .mesh(0);
    plane.world_from_object = Mat4::from_scale(Vec3::splat(scale));
    let scene = Scene {
        meshes: vec![plane],
        materials: vec![material],
        lights: vec![Light::Directional {
            direction: light(),
            color: Vec3::ONE,
        }],
        ambient_light: Vec3::ONE,
        background: Vec4::new(0.0, 0.0, 0.0, 1.0),
        camera: None,
    };
    let camera = Camera {
        eye: Vec3::new(0.0, 2.0 * scale, 0.0),
        target: Vec3::ZERO,
        up: Vec3::NEG_Z,
        projection: CameraProjection::Perspective { fov_y_deg: 40.0 },
        near: 0.05 * scale,
        far: 100.0 * scale,
    };
    (scene, camera)
}

fn frame(scene: &Scene, camera: &Camera, shading: ShadingMode) -> Frame {
    let settings = Settings {
        width: SIZE,
        height: SIZE,
        shading,
        ..Default::default()
    };
    render(scene, camera, &settings).unwrap()
}

fn pixel(f: &Frame, x: u32, y: u32) -> Vec3 {
    f.color[(y * f.width + x) as usize].truncate()
}

/// A linear height texture h = (u + 2v)/3 (float texels, so the ramp is exact).
fn ramp() -> Arc<Texture2D> {
    let n = 64;
    Arc::new(
        Texture2D::from_fn(n, n, TextureOptions::default(), |x, y| {
            let (u, v) = ((x as f32 + 0.5) / n as f32, (y as f32 + 0.5) / n as f32);
            Vec4::new((u + 2.0 * v) / 3.0, 0.0, 0.0, 1.0)
        })
        .unwrap(),
    )
}

fn bumped(scale: f32) -> Material {
    Material {
        maps: vec![MaterialMap {
            channel: MapChannel::Bump,
            slot: TextureSlot::new(ramp(), Sampler::new(Filter::BILINEAR, Wrap::ClampToEdge)),
            scale,
        }],
        ..Default::default()
    }
}

#[test]
fn a_bump_ramp_shades_like_the_sloped_plane_it_describes() {
    // h = 1.5·(u + 2v)/3 = 0.25·x + 0.5·z + const on the plane, whose surface normal is
    // (−0.25, 1, −0.5)/|…|; Phong's I = K_A + K_D·N·L = 0.2 + 0.8·N·L.
    let (scene, camera) = plane_scene(bumped(1.5), 1.0);
    let f = frame(&scene, &camera, ShadingMode::Phong);
    let n = Vec3::new(-0.25, 1.0, -0.5).normalize();
    let expected = 0.2 + 0.8 * n.dot(light());
    let flat = 0.2 + 0.8 * Vec3::Y.dot(light());
    assert!((expected - flat).abs() > 0.2);
    for (x, y) in [(48, 48), (30, 40), (60, 62), (40, 66)] {
        let c = pixel(&f, x, y);
        assert!(
            (c - Vec3::splat(expected)).abs().max_element() < 2e-3,
            "pixel ({x}, {y}): {c}, expected {expected}"
        );
    }
    // Gouraud and flat shading do not read bump maps.
    let g = frame(&scene, &camera, ShadingMode::Gouraud);
    assert!((pixel(&g, 48, 48).x - flat).abs() < 2e-3);
}

#[test]
fn bump_heights_scale_with_the_object() {
    // Heights are in object units: a plane and its camera scaled together give the same
    // image, for an image bump and for a solid one.
    let solid = Material {
        model: ShadingModel::MetallicRoughness,
        roughness: 0.5,
        solid_maps: vec![SolidMap {
            solid: Solid::named("marble").unwrap(),
            channel: SolidChannel::Bump { scale: 0.05 },
            antialias: true,
        }],
        ..Default::default()
    };
    for material in [bumped(0.6), solid] {
        let images: Vec<Vec<u8>> = [1.0, 3.0]
            .iter()
            .map(|&s| {
                let (scene, camera) = plane_scene(material.clone(), s);
                frame(&scene, &camera, ShadingMode::Phong).to_srgb8()
            })
            .collect();
        let (w, h) = (SIZE as usize, SIZE as usize);
        let c = compare_rgb8(&images[0], &images[1], w, h, None);
        assert!(c.psnr_db > 45.0, "{}", c.psnr_db);
        // And the bump is there: the image differs from the flat plane's.
        let (mut flat, camera) = plane_scene(material.clone(), 1.0);
        flat.materials[0].maps.clear();
        flat.materials[0].solid_maps.clear();
        let f = frame(&flat, &camera, ShadingMode::Phong).to_srgb8();
        assert!(compare_rgb8(&images[0], &f, w, h, None).psnr_db < 35.0);
    }
}

#[test]
fn metallic_roughness_texture_multiplies_the_factors() {
    // Left texel: metallic 1 (B), roughness 0.3 (G); right: metallic 0, roughness 0.8. With
    // factors 1, each half equals a plane whose factors are those values.
    let tex = Arc::new(
        Texture2D::from_fn(2, 1, TextureOptions::default(), |x, _| {
            if x == 0 {
                Vec4::new(0.0, 0.3, 1.0, 1.0)
            } else {
                Vec4::new(0.0, 0.8, 0.0, 1.0)
            }
        })
        .unwrap(),
    );
    let base = Material {
        model: ShadingModel::MetallicRoughness,
        base_color: Vec4::new(0.8, 0.2, 0.1, 1.0),
        ..Default::default()
    };
    let textured = Material {
        metallic: 1.0,
        roughness: 1.0,
        maps: vec![MaterialMap {
            channel: MapChannel::MetallicRoughness,
            slot: TextureSlot::new(tex, Sampler::new(Filter::NEAREST, Wrap::ClampToEdge)),
            scale: 1.0,
        }],
        ..base.clone()
    };
    let (scene, camera) = plane_scene(textured, 1.0);
    let f = frame(&scene, &camera, ShadingMode::Phong);
    for (x, metallic, roughness) in [(30, 1.0, 0.3), (66, 0.0, 0.8)] {
        let plain = Material {
            metallic,
            roughness,
            ..base.clone()
        };
        let (scene, camera) = plane_scene(plain, 1.0);
        let g = frame(&scene, &camera, ShadingMode::Phong);
        for y in [30, 48, 66] {
            let (a, b) = (pixel(&f, x, y), pixel(&g, x, y));
            assert!((a - b).abs().max_element() < 1e-6, "({x}, {y}): {a} vs {b}");
        }
    }
    // The metal half has no diffuse: its red channel is far below the dielectric's.
    assert!(pixel(&f, 30, 48).x < 0.5 * pixel(&f, 66, 48).x);
}

#[test]
fn gouraud_metallic_roughness_stays_close_to_phong() {
    // Per-vertex evaluation with a broad lobe on a fine sphere: close to per-pixel.
    let mut sphere = builtin::uv_sphere(128, 65, 0);
    sphere.world_from_object = Mat4::from_scale(Vec3::splat(0.8));
    let material = Material {
        model: ShadingModel::MetallicRoughness,
        base_color: Vec4::new(0.9, 0.6, 0.2, 1.0),
        metallic: 0.5,
        roughness: 0.8,
        ..Default::default()
    };
    let (mut scene, _) = plane_scene(material, 1.0);
    scene.meshes = vec![sphere];
    let camera = Camera {
        eye: Vec3::new(0.0, 0.5, 3.0),
        target: Vec3::ZERO,
        up: Vec3::Y,
        projection: CameraProjection::Perspective { fov_y_deg: 40.0 },
        near: 0.05,
        far: 100.0,
    };
    let p = frame(&scene, &camera, ShadingMode::Phong).to_srgb8();
    let g = frame(&scene, &camera, ShadingMode::Gouraud).to_srgb8();
    let c = compare_rgb8(&p, &g, SIZE as usize, SIZE as usize, None);
    assert!(c.psnr_db > 35.0, "{}", c.psnr_db);
    assert!(
        c.psnr_db < 80.0,
        "Gouraud should not be identical: {}",
        c.psnr_db
    );
}
