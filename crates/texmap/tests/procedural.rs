//! Solid textures and generated texture coordinates, rendered: golden images (PSNR ≥ 40 dB
//! against `tests/golden/`, reviewed by eye), the antialiasing of a far-away solid texture
//! (colour and bump) measured against a supersampled reference, solid textures on the
//! roughness and bump channels, and the u seam of a per-pixel spherical map.

mod common;

use std::sync::Arc;

use glam::{Mat4, Vec2, Vec3, Vec4};
use texmap::camera::{Camera, CameraProjection};
use texmap::geometry::Projection;
use texmap::render::{render, Settings};
use texmap::scene::{
    builtin, Light, Material, Mesh, Procedural, Scene, ShadingModel, SolidChannel, SolidMap,
    TextureSlot,
};
use texmap::texture::procedural::Solid;
use texmap::texture::{ColorSpace, Filter, Sampler, Texture2D, TextureOptions, Wrap};

const MIN_PSNR: f64 = 40.0;

fn lit_scene(
    meshes: Vec<Mesh>,
    materials: Vec<Material>,
    eye: Vec3,
    target: Vec3,
) -> (Scene, Camera) {
    let scene = Scene {
        meshes,
        materials,
        lights: vec![Light::Directional {
            direction: Vec3::new(0.4, 0.8, 0.6).normalize(),
            color: Vec3::ONE,
        }],
        ambient_light: Vec3::ONE,
        background: Vec4::new(0.02, 0.02, 0.03, 1.0),
        ..Scene::default()
    };
    let camera = Camera {
        eye,
        target,
        up: Vec3::Y,
        projection: CameraProjection::Perspective { fov_y_deg: 40.0 },
        near: 0.05,
        far: 100.0,
    };
    (scene, camera)
}

fn solid_material(name: &str, antialias: bool) -> Material {
    let solid = Solid::named(name).unwrap();
    let colors = solid.default_colors();
    Material {
        specular: 0.3,
        shininess: 40.0,
        procedural: Some(Procedural::Solid {
            solid,
            colors,
            antialias,
        }),
        ..Default::default()
    }
}

/// A capped cylinder of radius ½ and height 1 about +y (caps with their own normals).
fn cylinder(segments: usize, material: usize, world_from_object: Mat4) -> Mesh {
    let mut m = Mesh {
        material,
        world_from_object,
        ..Default::default()
    };
    for i in 0..=segments {
        let a = std::f32::consts::TAU * i as f32 / segments as f32;
        let n = Vec3::new(a.cos(), 0.0, -a.sin());
        for y in [-0.5, 0.5] {
            m.positions.push(n * 0.5 + Vec3::Y * y);
            m.normals.push(n);
        }
    }
    for i in 0..segments as u32 {
        let b = 2 * i;
        m.indices.extend([b, b + 2, b + 1, b + 1, b + 2, b + 3]);
    }
    for (y, n) in [(0.5f32, Vec3::Y), (-0.5, Vec3::NEG_Y)] {
        let centre = m.positions.len() as u32;
        m.positions.push(Vec3::Y * y);
        m.normals.push(n);
        for i in 0..=segments {
            let a = std::f32::consts::TAU * i as f32 / segments as f32;
            m.positions
                .push(Vec3::new(0.5 * a.cos(), y, -0.5 * a.sin()));
            m.normals.push(n);
        }
        for i in 0..segments as u32 {
            let (a, b) = (centre + 1 + i, centre + 2 + i);
            if y > 0.0 {
                m.indices.extend([centre, a, b]);
            } else {
                m.indices.extend([centre, b, a]);
            }
        }
    }
    m.uvs = vec![Vec2::ZERO; m.positions.len()];
    m
}

/// A 256×128 orientation texture: hue along u, brightness bands along v, a dark grid every
/// eighth, and a white disc at (0.25, 0.25) so mirroring shows.
fn grid_texture() -> Arc<Texture2D> {
    let (w, h) = (256u32, 128u32);
    Arc::new(
        Texture2D::from_fn(w, h, TextureOptions::default(), |x, y| {
            let (u, v) = ((x as f32 + 0.5) / w as f32, (y as f32 + 0.5) / h as f32);
            let hue = u * 6.0;
            let rgb = Vec3::new(
                (hue - 3.0).abs() - 1.0,
                2.0 - (hue - 2.0).abs(),
                2.0 - (hue - 4.0).abs(),
            )
            .clamp(Vec3::ZERO, Vec3::ONE);
            let band = 0.35 + 0.65 * (1.0 - v);
            let grid = (x % (w / 8) < 2) || (y % (h / 8) < 2);
            let disc = (Vec2::new(u, v) - Vec2::splat(0.25)).length() < 0.06;
            let c = if disc {
                Vec3::ONE
            } else if grid {
                Vec3::splat(0.02)
            } else {
                rgb * band
            };
            c.extend(1.0)
        })
        .unwrap(),
    )
}

fn projected(projection: Projection) -> Material {
    Material {
        procedural: Some(Procedural::Projected {
            slot: TextureSlot::new(grid_texture(), Sampler::new(Filter::aniso(8), Wrap::Repeat)),
            projection,
        }),
        ..Default::default()
    }
}

fn rgb8(scene: &Scene, camera: &Camera, w: u32, h: u32, ssaa: u32) -> Vec<u8> {
    let settings = Settings::new(w, h).with_ssaa(ssaa);
    render(scene, camera, &settings).unwrap().to_srgb8()
}

#[test]
fn marble_sphere_and_wood_cube() {
    let sphere = builtin::uv_sphere(96, 49, 0);
    let mut sphere = sphere;
    sphere.world_from_object =
        Mat4::from_translation(Vec3::new(-0.7, 0.0, 0.0)) * Mat4::from_scale(Vec3::splat(0.6));
    let cube = builtin::cube(
        1,
        Mat4::from_translation(Vec3::new(0.75, 0.0, 0.0)) * Mat4::from_rotation_y(0.6),
    );
    let (scene, camera) = lit_scene(
        vec![sphere, cube],
        vec![solid_material("marble", true), solid_material("wood", true)],
        Vec3::new(0.0, 1.2, 3.6),
        Vec3::ZERO,
    );
    let img = rgb8(&scene, &camera, 320, 200, 1);
    common::assert_golden("solid_marble_wood", 320, 200, &img, MIN_PSNR);
}

#[test]
fn solid_pattern_stays_with_the_object() {
    // Moving the object and the camera together leaves the image unchanged.
    let make = |offset: Vec3| {
        let cube = builtin::cube(
            0,
            Mat4::from_translation(offset) * Mat4::from_rotation_y(0.5),
        );
        let (scene, mut camera) = lit_scene(
            vec![cube],
            vec![solid_material("granite", true)],
            Vec3::new(0.0, 1.5, 2.5),
            Vec3::ZERO,
        );
        camera.eye += offset;
        camera.target += offset;
        let mut scene = scene;
        scene.lights = vec![];
        rgb8(&scene, &camera, 96, 64, 1)
    };
    let a = make(Vec3::ZERO);
    let b = make(Vec3::new(3.0, -1.0, 2.0));
    let c = texmap::metrics::compare_rgb8(&a, &b, 96, 64, None);
    assert!(c.psnr_db > 45.0, "{}", c.psnr_db);
}

/// A large marble floor receding to the horizon.
fn marble_floor(antialias: bool) -> (Scene, Camera) {
    let floor = builtin::cube(
        0,
        Mat4::from_translation(Vec3::new(0.0, -0.5, -45.0))
            * Mat4::from_scale(Vec3::new(40.0, 1.0, 100.0)),
    );
    let mut m = solid_material("checker3d", antialias);
    m.specular = 0.0;
    if let Some(Procedural::Solid { solid, .. }) = &mut m.procedural {
        *solid = Solid::Checker3D { size: 0.004 };
    }
    let (mut scene, mut camera) = lit_scene(
        vec![floor],
        vec![m],
        Vec3::new(0.0, 1.0, 4.0),
        Vec3::new(0.0, 0.0, -20.0),
    );
    scene.ambient_light = Vec3::ONE;
    camera.projection = CameraProjection::Perspective { fov_y_deg: 60.0 };
    (scene, camera)
}

#[test]
fn antialiased_solid_texture_does_not_shimmer() {
    // Reference: the unfiltered pattern supersampled 8×8. The filtered image must be much
    // closer to it than the unfiltered one at one sample per pixel.
    let (w, h) = (192, 108);
    let (scene_ref, camera) = marble_floor(false);
    let reference = rgb8(&scene_ref, &camera, w, h, 8);
    let aliased = rgb8(&scene_ref, &camera, w, h, 1);
    let (scene_aa, _) = marble_floor(true);
    let filtered = rgb8(&scene_aa, &camera, w, h, 1);
    let p_aliased =
        texmap::metrics::compare_rgb8(&reference, &aliased, w as usize, h as usize, None).psnr_db;
    let p_filtered =
        texmap::metrics::compare_rgb8(&reference, &filtered, w as usize, h as usize, None).psnr_db;
    eprintln!("far checker3d vs 8x8 supersampled: unfiltered {p_aliased:.2} dB, filtered {p_filtered:.2} dB");
    assert!(
        p_filtered > p_aliased + 3.0,
        "filtered {p_filtered:.2} dB, unfiltered {p_aliased:.2} dB"
    );
    // Side by side, for the eye: unfiltered | filtered.
    let mut both = Vec::with_capacity((2 * w * h * 3) as usize);
    for y in 0..h as usize {
        let row = w as usize * 3;
        both.extend_from_slice(&aliased[y * row..(y + 1) * row]);
        both.extend_from_slice(&filtered[y * row..(y + 1) * row]);
    }
    common::assert_golden("solid_antialias_off_on", 2 * w, h, &both, MIN_PSNR);
}

fn solid_map(name: &str, channel: SolidChannel, antialias: bool) -> SolidMap {
    SolidMap {
        solid: Solid::named(name).unwrap(),
        channel,
        antialias,
    }
}

#[test]
fn solid_roughness_and_bump_on_lit_spheres() {
    // Left: marble on the roughness channel of a metallic-roughness copper (veins 0.75, the
    // rest 0.12): polished metal with matte veins; the veins spread the lights' reflection
    // over the sphere, the polished metal keeps it in sharp highlights (and reflects only
    // the dim ambient light elsewhere). Middle: marble on the bump
    // channel of a dielectric (veins become grooves). Right: a Phong material with both,
    // granite roughness (as an exponent) and marble bumps, and its own marble colour.
    let place = |x: f32| {
        Mat4::from_translation(Vec3::new(x, 0.0, 0.0)) * Mat4::from_scale(Vec3::splat(0.6))
    };
    let meshes: Vec<Mesh> = (0..3)
        .map(|i| {
            let mut s = builtin::uv_sphere(128, 65, i);
            s.world_from_object = place(1.35 * (i as f32 - 1.0));
            s
        })
        .collect();
    let pbr = Material {
        model: ShadingModel::MetallicRoughness,
        base_color: Vec4::new(0.25, 0.27, 0.32, 1.0),
        roughness: 0.4,
        ..Default::default()
    };
    let rough = Material {
        solid_maps: vec![solid_map(
            "marble",
            SolidChannel::Roughness {
                range: [0.75, 0.12],
            },
            true,
        )],
        base_color: Vec4::new(0.95, 0.64, 0.54, 1.0),
        metallic: 1.0,
        ..pbr.clone()
    };
    let bumpy = Material {
        solid_maps: vec![solid_map(
            "marble",
            SolidChannel::Bump { scale: 0.02 },
            true,
        )],
        base_color: Vec4::new(0.5, 0.45, 0.4, 1.0),
        ..pbr
    };
    let mut both = solid_material("marble", true);
    both.specular = 0.5;
    both.solid_maps = vec![
        solid_map(
            "granite",
            SolidChannel::Roughness { range: [0.25, 0.6] },
            true,
        ),
        solid_map("marble", SolidChannel::Bump { scale: 0.02 }, true),
    ];
    let (mut scene, mut camera) = lit_scene(
        meshes,
        vec![rough, bumpy, both],
        Vec3::new(0.0, 0.6, 4.3),
        Vec3::ZERO,
    );
    // Each sphere fills most of its third of the image.
    camera.projection = CameraProjection::Perspective { fov_y_deg: 20.0 };
    scene.lights[0] = Light::Directional {
        direction: Vec3::new(0.4, 0.8, 0.6),
        color: Vec3::splat(0.8),
    };
    scene.lights.push(Light::Point {
        position: Vec3::new(-1.0, 1.5, 3.0),
        color: Vec3::splat(4.0),
        range: None,
    });
    let (w, h) = (480, 180);
    let img = rgb8(&scene, &camera, w, h, 1);
    if std::env::var_os("TEXMAP_DEBUG_IMAGES").is_some() {
        image::RgbImage::from_raw(w, h, img.clone())
            .unwrap()
            .save("/tmp/shade/spheres.png")
            .unwrap();
    }

    // Each channel changes the image where it should: without the maps the spheres differ.
    let mut plain = scene.clone();
    for m in &mut plain.materials {
        m.solid_maps.clear();
    }
    let flat = rgb8(&plain, &camera, w, h, 1);
    for (i, (x0, x1)) in [(0, 160), (160, 320), (320, 480)].into_iter().enumerate() {
        let changed = (0..h as usize)
            .flat_map(|y| (x0..x1).map(move |x| (y * w as usize + x) * 3))
            .filter(|&k| (0..3).any(|c| img[k + c].abs_diff(flat[k + c]) > 8))
            .count();
        assert!(
            changed > 500,
            "sphere {i}: only {changed} pixels changed by its maps"
        );
    }
    common::assert_golden("solid_roughness_bump_spheres", w, h, &img, MIN_PSNR);
}

/// A floor with a fine cloudy bump (ten octaves, the coarsest about 2 units across, the
/// finest 0.004), receding to the horizon: the top face of a cube of side 100, so the object
/// space is the world's scaled by 1/100.
fn bumpy_floor(antialias: bool) -> (Scene, Camera) {
    let floor = builtin::cube(
        0,
        Mat4::from_translation(Vec3::new(0.0, -50.5, -45.0)) * Mat4::from_scale(Vec3::splat(100.0)),
    );
    let m = Material {
        model: ShadingModel::MetallicRoughness,
        base_color: Vec4::new(0.6, 0.6, 0.6, 1.0),
        roughness: 0.35,
        solid_maps: vec![SolidMap {
            solid: Solid::Clouds {
                scale: 50.0,
                octaves: 10.0,
            },
            // 0.4 world units of height per unit of value.
            channel: SolidChannel::Bump { scale: 0.004 },
            antialias,
        }],
        ..Default::default()
    };
    let (scene, mut camera) = lit_scene(
        vec![floor],
        vec![m],
        Vec3::new(0.0, 1.0, 4.0),
        Vec3::new(0.0, 0.0, -20.0),
    );
    camera.projection = CameraProjection::Perspective { fov_y_deg: 60.0 };
    (scene, camera)
}

#[test]
fn antialiased_solid_bump_does_not_sparkle() {
    // As for colour: against the unfiltered bump supersampled 8×8, the filtered bump at one
    // sample per pixel is closer than the unfiltered one.
    let (w, h) = (192, 108);
    let (scene_ref, camera) = bumpy_floor(false);
    let reference = rgb8(&scene_ref, &camera, w, h, 8);
    let aliased = rgb8(&scene_ref, &camera, w, h, 1);
    let (scene_aa, _) = bumpy_floor(true);
    let filtered = rgb8(&scene_aa, &camera, w, h, 1);
    let psnr = |img: &[u8]| {
        texmap::metrics::compare_rgb8(&reference, img, w as usize, h as usize, None).psnr_db
    };
    let (p_aliased, p_filtered) = (psnr(&aliased), psnr(&filtered));
    if std::env::var_os("TEXMAP_DEBUG_IMAGES").is_some() {
        for (name, img) in [
            ("ref", &reference),
            ("aliased", &aliased),
            ("filtered", &filtered),
        ] {
            image::RgbImage::from_raw(w, h, img.to_vec())
                .unwrap()
                .save(format!("/tmp/shade/floor_{name}.png"))
                .unwrap();
        }
    }
    eprintln!(
        "far bump vs 8x8 supersampled: unfiltered {p_aliased:.2} dB, filtered {p_filtered:.2} dB"
    );
    // Dropping octaves removes the sparkle but not the darkening the unresolved slopes cause
    // on average (the reference keeps it), hence a smaller margin than for colour.
    assert!(
        p_filtered > p_aliased + 1.5,
        "filtered {p_filtered:.2} dB, unfiltered {p_aliased:.2} dB"
    );
}

#[test]
fn projections_on_cylinder_sphere_and_cube() {
    let place = |x: f32| Mat4::from_translation(Vec3::new(x, 0.0, 0.0));
    let mut sphere = builtin::uv_sphere(96, 49, 1);
    sphere.world_from_object = place(0.0) * Mat4::from_scale(Vec3::splat(0.5));
    // Object-space positions on the unit sphere map the same whatever the radius.
    let meshes = vec![
        cylinder(64, 0, place(-1.3) * Mat4::from_rotation_y(-0.4)),
        sphere,
        builtin::cube(
            2,
            place(1.3) * Mat4::from_rotation_y(0.5) * Mat4::from_rotation_x(0.3),
        ),
    ];
    let materials = vec![
        projected(Projection::Cylindrical),
        projected(Projection::Spherical),
        projected(Projection::Cube),
    ];
    let (scene, camera) = lit_scene(meshes, materials, Vec3::new(0.0, 1.0, 4.2), Vec3::ZERO);
    let img = rgb8(&scene, &camera, 360, 160, 1);
    common::assert_golden("projections_cylinder_sphere_cube", 360, 160, &img, MIN_PSNR);
}

#[test]
fn spherical_seam_has_no_blurred_line() {
    // Look straight at the seam (+x) of a sphere with a black-and-white checker of large
    // squares, projected per pixel, trilinear. A footprint that wrapped through the seam would
    // read the coarsest level (mid grey) along the seam's column.
    let checker = Arc::new(
        Texture2D::from_fn(64, 64, TextureOptions::default(), |x, y| {
            Vec4::splat(((x / 16 + y / 16) % 2) as f32)
        })
        .unwrap(),
    );
    let material = Material {
        unlit: true,
        procedural: Some(Procedural::Projected {
            slot: TextureSlot::new(checker, Sampler::new(Filter::TRILINEAR, Wrap::Repeat)),
            projection: Projection::Spherical,
        }),
        ..Default::default()
    };
    let sphere = builtin::uv_sphere(64, 33, 0);
    let (scene, camera) = lit_scene(
        vec![sphere],
        vec![material],
        Vec3::new(3.0, 0.0, 0.0),
        Vec3::ZERO,
    );
    let (w, h) = (128u32, 128u32);
    let img = rgb8(&scene, &camera, w, h, 1);
    // The seam projects onto the image's middle column; look at the sphere's middle half.
    let grey = (h / 4..3 * h / 4)
        .filter(|&y| {
            let i = ((y * w + w / 2) * 3) as usize;
            (60..200).contains(&img[i])
        })
        .count();
    assert!(grey <= 6, "{grey} grey pixels on the seam column");
    common::assert_golden("spherical_seam", w, h, &img, MIN_PSNR);
}

#[test]
fn texture_colour_space_is_declared() {
    // The same bytes read as sRGB and as linear data differ (50% grey: 0.214 vs 0.5).
    let bytes: Vec<u8> = [128u8, 128, 128, 255].repeat(16);
    let srgb = Texture2D::from_rgba8(4, 4, ColorSpace::Srgb, &bytes).unwrap();
    let lin = Texture2D::from_rgba8(4, 4, ColorSpace::Linear, &bytes).unwrap();
    assert!((srgb.texel(0, 0, 0).x - 0.2158).abs() < 1e-3);
    assert!((lin.texel(0, 0, 0).x - 0.502).abs() < 1e-3);
}

#[test]
fn scene_file_with_procedural_and_projected_materials() {
    // scenes/procedural.toml: every solid pattern kind, a cylindrical photo and the
    // bounding-sphere projection on a complex mesh (the glTF Duck). Its photo and duck come
    // from the shared corpus.
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    if !root.join("../shared/assets/gltf/Duck").is_dir() {
        eprintln!("SKIPPED: the asset corpus ../shared/assets is absent");
        return;
    }
    let loaded =
        texmap::scene::load(&root.join("scenes/procedural.toml"), &Default::default()).unwrap();
    let camera = loaded.scene.camera.unwrap();
    let img = rgb8(&loaded.scene, &camera, 320, 180, 1);
    common::assert_golden("scene_procedural", 320, 180, &img, MIN_PSNR);
}

#[test]
fn scene_file_rejects_bad_procedural_settings() {
    let dir = std::env::temp_dir().join(format!("texmap-proc-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let cases = [
        ("procedural = { pattern = \"lava\" }", "lava"),
        (
            "projected = { projection = \"conical\", texture = { file = \"x.png\" } }",
            "conical",
        ),
        ("procedural = { pattern = \"wood\", grain = 3 }", "grain"),
        ("solid_texture = { size = 8 }", "either"),
        ("solid_texture = { bake = \"lava\" }", "lava"),
        (
            "solid_texture = { bake = \"marble\", min = [0, 0, 0], max = [1, 0, 1] }",
            "box",
        ),
        ("solid_texture = { bake = \"marble\", size = 0 }", "size"),
        (
            "solid_texture = { bake = \"wood\", filter = \"ewa\" }",
            "ewa",
        ),
        ("solid_texture = { file = \"missing.nii\" }", "missing.nii"),
        (
            "procedural = { pattern = \"wood\" }\nsolid_texture = { bake = \"wood\" }",
            "one of",
        ),
    ];
    for (i, (line, needle)) in cases.iter().enumerate() {
        let path = dir.join(format!("bad{i}.toml"));
        std::fs::write(&path, format!("[materials.m]\n{line}\n")).unwrap();
        let e = texmap::scene::load(&path, &Default::default())
            .unwrap_err()
            .to_string();
        assert!(e.contains(needle), "{e}");
    }
}

/// A 3D texture as a solid texture: marble baked into a 128³ `Texture3D` over the sphere's
/// object box ([-1, 1]³) and read back trilinearly (mipmapped) renders like the analytic
/// marble: 28.7 dB PSNR between the two (the baked veins are a little softer), asserted above
/// 26 dB. Golden: analytic (left) and 3D texture (right), reviewed by eye.
#[test]
fn a_baked_3d_texture_stands_in_for_the_solid_texture() {
    let solid = Solid::named("marble").unwrap();
    let colors = solid.default_colors();
    let baked = solid
        .bake(128, glam::DVec3::splat(-1.0), glam::DVec3::splat(1.0))
        .unwrap();
    assert_eq!(baked.dims(), [128; 3]);
    let textured = Material {
        specular: 0.3,
        shininess: 40.0,
        procedural: Some(Procedural::Texture3D {
            texture: Arc::new(baked),
            sampler: Sampler::new(Filter::TRILINEAR, Wrap::ClampToEdge),
            min: Vec3::splat(-1.0),
            max: Vec3::ONE,
            colors,
        }),
        ..Default::default()
    };
    let (w, h) = (200u32, 200u32);
    let image = |material: Material| {
        let (scene, camera) = lit_scene(
            vec![builtin::uv_sphere(96, 49, 0)],
            vec![material],
            Vec3::new(0.0, 0.8, 2.8),
            Vec3::ZERO,
        );
        rgb8(&scene, &camera, w, h, 1)
    };
    let analytic = image(solid_material("marble", true));
    let from_3d = image(textured);
    let c = texmap::metrics::compare_rgb8(&analytic, &from_3d, w as usize, h as usize, None);
    assert!(
        c.psnr_db > 26.0,
        "3D texture vs analytic: {:.2} dB",
        c.psnr_db
    );
    let mut both = Vec::with_capacity(analytic.len() * 2);
    for y in 0..h as usize {
        let row = y * w as usize * 3..(y + 1) * w as usize * 3;
        both.extend_from_slice(&analytic[row.clone()]);
        both.extend_from_slice(&from_3d[row]);
    }
    common::assert_golden("solid_texture3d", 2 * w, h, &both, MIN_PSNR);
}

#[test]
fn scene_file_with_a_3d_solid_texture() {
    // scenes/solid_texture3d.toml needs no files: its 3D textures are baked from patterns.
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let loaded = texmap::scene::load(
        &root.join("scenes/solid_texture3d.toml"),
        &Default::default(),
    )
    .unwrap();
    assert!(loaded
        .scene
        .materials
        .iter()
        .any(|m| matches!(m.procedural, Some(Procedural::Texture3D { .. }))));
    let camera = loaded.scene.camera.unwrap();
    let img = rgb8(&loaded.scene, &camera, 320, 180, 1);
    common::assert_golden("scene_solid_texture3d", 320, 180, &img, MIN_PSNR);
}

#[test]
fn a_scan_is_a_solid_texture_too() {
    // The repository's small synthetic scan (scenes/volumes/cell.nrrd) carved by a sphere:
    // its value range maps to the two colours, so the surface is not one colour.
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let scan = root.join("scenes/volumes/cell.nrrd");
    let dir = std::env::temp_dir().join(format!("texmap-scan-solid-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("scan.toml");
    std::fs::write(
        &path,
        format!(
            "[materials.scan]\nsolid_texture = {{ file = {:?}, colors = [[0, 0, 0], [1, 1, 1]], \
             min = [-0.6, -0.6, -0.6], max = [0.6, 0.6, 0.6], wrap = \"clamp\" }}\n\
             [[meshes]]\nprimitive = \"sphere\"\nradius = 0.35\nmaterial = \"scan\"\n",
            scan.display().to_string()
        ),
    )
    .unwrap();
    let loaded = texmap::scene::load(&path, &Default::default()).unwrap();
    let Some(Procedural::Texture3D { texture, .. }) = &loaded.scene.materials[0].procedural else {
        panic!("not a 3D texture");
    };
    assert_eq!(texture.dims(), [48, 48, 40]);
    let mut scene = loaded.scene;
    scene.lights.clear();
    scene.ambient_light = Vec3::splat(5.0); // K_A 0.2 × 5: the unlit colour
    let camera = scene.framing_camera(40.0);
    let img = rgb8(&scene, &camera, 64, 64, 1);
    let lit: Vec<u8> = img.chunks(3).map(|p| p[0]).filter(|&r| r > 0).collect();
    let (lo, hi) = (lit.iter().min().unwrap(), lit.iter().max().unwrap());
    assert!(
        hi - lo > 8,
        "the scan's values vary across the surface: {lo}..{hi}"
    );
}
