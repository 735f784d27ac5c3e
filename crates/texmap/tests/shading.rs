//! Per-pixel surface parameters, rendered: a bump map tilts the normal as the surface it
//! describes would, heights scale with the object, the metallic-roughness texture drives
//! exactly the factors it multiplies (an occlusion map in the same image read once, as a
//! copy read apart gives it), and Gouraud shading of a metallic-roughness material
//! stays close to Phong shading.

use std::sync::Arc;

use glam::{Mat4, Vec3, Vec4};
use texmap::camera::{Camera, CameraProjection};
use texmap::metrics::compare_rgb8;
use texmap::render::{render, Frame, Settings, ShadingMode};
use texmap::scene::primitives::Primitive;
use texmap::scene::{
    builtin, Light, Material, Scene, ShadingModel, SolidChannel, SolidMap, TextureSlot,
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
        ..Scene::default()
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
    let settings = Settings::new(SIZE, SIZE).with_shading(shading);
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
fn an_occlusion_map_in_the_metallic_roughness_image_reads_as_its_own_copy() {
    // An ORM image (occlusion R, roughness G, metalness B) named by both maps is read once;
    // the frame is the one drawn with the occlusion map in a copy of the image, read apart.
    // With and without a base colour texture (read with the maps or not), under trilinear
    // (the shared read) and anisotropic filtering (map by map).
    let rgba: Vec<u8> = (0..32 * 32 * 4)
        .map(|i: u32| match i % 4 {
            3 => 255,
            k => (i.wrapping_mul(37 + k) % 251) as u8,
        })
        .collect();
    let image = || {
        Arc::new(
            Texture2D::from_texels(
                32,
                32,
                texmap::texture::Format::Rgba8,
                texmap::texture::ColorSpace::Linear,
                &rgba,
                TextureOptions::default(),
            )
            .unwrap(),
        )
    };
    let orm = image();
    let base = Arc::new(
        Texture2D::from_fn(32, 32, TextureOptions::default(), |x, y| {
            Vec4::new(x as f32 / 31.0, y as f32 / 31.0, 0.5, 1.0)
        })
        .unwrap(),
    );
    for filter in [Filter::TRILINEAR, Filter::aniso(8)] {
        for textured in [false, true] {
            let sampler = Sampler::new(filter, Wrap::Repeat);
            let map = |channel, tex: &Arc<Texture2D>| MaterialMap {
                channel,
                slot: TextureSlot::new(tex.clone(), sampler),
                scale: 0.7,
            };
            let material = |occlusion: &Arc<Texture2D>| Material {
                model: ShadingModel::MetallicRoughness,
                base_color_texture: textured.then(|| TextureSlot::new(base.clone(), sampler)),
                maps: vec![
                    map(MapChannel::MetallicRoughness, &orm),
                    map(MapChannel::Occlusion, occlusion),
                ],
                ..Default::default()
            };
            let (once, camera) = plane_scene(material(&orm), 1.0);
            let (apart, _) = plane_scene(material(&image()), 1.0);
            let (a, b) = (
                frame(&once, &camera, ShadingMode::Phong),
                frame(&apart, &camera, ShadingMode::Phong),
            );
            assert!(
                a.color == b.color,
                "{filter:?}, base colour texture {textured}"
            );
            // And the occlusion map is read: without it the frame differs.
            let mut none = once.clone();
            none.materials[0].maps.pop();
            let c = frame(&none, &camera, ShadingMode::Phong);
            assert!(a.color != c.color, "{filter:?}");
        }
    }
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

/// A 64² linear RGBA32F texture of one value everywhere.
fn flat_texture(c: Vec4) -> Arc<Texture2D> {
    Arc::new(Texture2D::from_fn(64, 64, TextureOptions::default(), |_, _| c).unwrap())
}

/// A Phong material with one map on `channel` reading `texture`.
fn with_map(mut m: Material, channel: MapChannel, texture: Arc<Texture2D>) -> Material {
    m.maps.push(MaterialMap {
        channel,
        slot: TextureSlot::new(texture, Sampler::new(Filter::TRILINEAR, Wrap::Repeat)),
        scale: 1.0,
    });
    m
}

/// The OBJ channels `map_d`, `map_Ka`, `map_Ks` and `map_Ns` are drawn: opacity discards
/// (alpha test) where it is low, the ambient map replaces the surface colour in the ambient
/// term, the specular map tints the highlight, and the exponent map widens it.
#[test]
fn obj_opacity_ambient_specular_and_exponent_maps_are_drawn() {
    let shiny = Material {
        base_color: Vec4::new(0.2, 0.2, 0.2, 1.0),
        specular: 1.0,
        shininess: 200.0,
        ..Default::default()
    };
    // A light from straight above: the highlight sits at the centre of the view.
    let centre = |m: Material| {
        let (mut scene, camera) = plane_scene(m, 1.0);
        scene.lights = vec![Light::Directional {
            direction: Vec3::Y,
            color: Vec3::ONE,
        }];
        let f = frame(&scene, &camera, ShadingMode::Phong);
        (pixel(&f, SIZE / 2, SIZE / 2), f)
    };
    // Opacity: a map of 0.3 everywhere (its alpha channel) under MASK 0.5 removes the plane.
    let masked = Material {
        alpha_mode: texmap::scene::AlphaMode::Mask(0.5),
        ..shiny.clone()
    };
    let (_, opaque) = centre(with_map(
        masked.clone(),
        MapChannel::Alpha,
        flat_texture(Vec4::splat(0.9)),
    ));
    let (_, cut) = centre(with_map(
        masked,
        MapChannel::Alpha,
        flat_texture(Vec4::splat(0.3)),
    ));
    let lit = |f: &Frame| {
        f.color
            .iter()
            .filter(|c| c.truncate().max_element() > 0.0)
            .count()
    };
    assert!(
        lit(&opaque) > (SIZE * SIZE / 2) as usize,
        "{}",
        lit(&opaque)
    );
    assert_eq!(lit(&cut), 0);

    // Ambient colour: no lights, I_AL = 1, K_A = 0.2: the colour is 0.2·(map) not 0.2·C.
    let ambient_only = |m: Material| {
        let (mut scene, camera) = plane_scene(m, 1.0);
        scene.lights.clear();
        let f = frame(&scene, &camera, ShadingMode::Phong);
        pixel(&f, SIZE / 2, SIZE / 2)
    };
    let plain = ambient_only(shiny.clone());
    let tinted = ambient_only(with_map(
        shiny.clone(),
        MapChannel::Ambient,
        flat_texture(Vec4::new(0.0, 1.0, 0.0, 1.0)),
    ));
    assert!(
        (plain - Vec3::splat(0.04)).abs().max_element() < 1e-3,
        "{plain}"
    );
    assert!(
        (tinted - Vec3::new(0.0, 0.2, 0.0)).abs().max_element() < 1e-3,
        "{tinted}"
    );

    // Specular tint and exponent, seen where the highlight is: compare whole frames.
    let (_, white) = centre(shiny.clone());
    let (_, red) = centre(with_map(
        shiny.clone(),
        MapChannel::Specular,
        flat_texture(Vec4::new(1.0, 0.0, 0.0, 1.0)),
    ));
    let sum = |f: &Frame| f.color.iter().map(|c| c.truncate()).sum::<Vec3>();
    let (sw, sr) = (sum(&white), sum(&red));
    assert!(
        (sr.x - sw.x).abs() < 1e-3 * sw.x,
        "red channel keeps its highlight"
    );
    assert!(sr.y < sw.y - 1.0, "green loses the highlight: {sw} {sr}");
    let (_, wide) = centre(with_map(
        shiny,
        MapChannel::Shininess,
        flat_texture(Vec4::new(0.1, 0.0, 0.0, 1.0)),
    ));
    let bright = |f: &Frame| f.color.iter().filter(|c| c.x > 0.5).count();
    assert!(
        bright(&wide) > 2 * bright(&white).max(1),
        "exponent ×0.1 widens the highlight: {} vs {}",
        bright(&wide),
        bright(&white)
    );
}

/// A flat plane under a directional light, without specular, is lit once per draw (one
/// normal at every vertex): its colours, front and back (double-sided), are those of the
/// per-pixel lighting that a normal one bit off forces, within float rounding.
#[test]
fn a_flat_surface_lit_once_matches_the_per_pixel_lighting() {
    let material = Material {
        base_color_texture: Some(TextureSlot::new(
            flat_texture(Vec4::new(0.5, 0.5, 0.5, 1.0)),
            Sampler::default(),
        )),
        ambient: 0.2,
        diffuse: 0.8,
        specular: 0.0,
        double_sided: true,
        ..Default::default()
    };
    let mut lit = Vec::new();
    for below in [false, true] {
        let (scene, mut camera) = plane_scene(material.clone(), 1.0);
        if below {
            camera.eye = -camera.eye;
        }
        let normals = &scene.meshes[0].normals;
        assert!(normals.len() > 3 && normals.iter().all(|n| *n == normals[0]));
        let mut per_pixel = scene.clone();
        let n = &mut per_pixel.meshes[0].normals[0];
        n.x = f32::from_bits(n.x.to_bits() + 1);
        let a = frame(&scene, &camera, ShadingMode::Phong);
        let b = frame(&per_pixel, &camera, ShadingMode::Phong);
        let worst = a
            .color
            .iter()
            .zip(&b.color)
            .map(|(x, y)| (*x - *y).abs().max_element())
            .fold(0.0f32, f32::max);
        assert!(worst <= 1e-6, "below {below}: {worst}");
        lit.push(pixel(&a, SIZE / 2, SIZE / 2));
    }
    // The top is lit by the light (0.2 + 0.8·N·L), the underside by the ambient term alone.
    let ratio = lit[0].x / lit[1].x;
    let expected = (0.2 + 0.8 * light().y) / 0.2;
    assert!(
        (ratio - expected).abs() < 1e-3 * expected,
        "{ratio} vs {expected}"
    );
}
