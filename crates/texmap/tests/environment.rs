//! Environment maps, reflection, refraction and image-based light, rendered: the classic
//! bugs (a line at the equirectangular seam, seams between cube faces, sparkling reflections
//! at grazing angles), the units (a uniform environment is a uniform ambient light of its
//! radiance), determinism, and one golden image per technique (reviewed by eye; PSNR
//! thresholds stated with each).
//!
//! Every environment here is generated: a synthetic panorama (sky, sun, coloured bands, a
//! checker ground), a cube map and a sphere map painted from a function of direction.

mod common;

use std::f32::consts::TAU;
use std::sync::Arc;

use glam::{Mat3, Mat4, Vec3, Vec4};
use texmap::camera::{Camera, CameraProjection};
use texmap::metrics::compare_rgb8;
use texmap::render::{render, Frame, Settings, ShadingMode, TextureOverrides};
use texmap::scene::primitives::Primitive;
use texmap::scene::{Environment, Material, Scene, ShadingModel, TextureSlot};
use texmap::shading::ibl::Background;
use texmap::shading::{MapChannel, MaterialMap};
use texmap::texture::environment::equirect_direction;
use texmap::texture::{CubeFace, EnvironmentMap, Sampler, Texture2D, TextureCube, TextureOptions};

/// Radiance of the synthetic world along a unit direction.
fn world(d: Vec3) -> Vec3 {
    let sun = Vec3::new(0.4, 0.5, 0.77).normalize();
    let mut c = if d.y > 0.0 {
        Vec3::new(0.25, 0.45, 0.9) * (0.4 + 0.6 * d.y)
            + Vec3::new(0.9, 0.8, 0.6) * (1.0 - d.y).powi(8)
    } else {
        let phi = d.x.atan2(-d.z);
        let theta = d.y.clamp(-1.0, 1.0).acos();
        let on = ((4.0 * phi / std::f32::consts::PI).floor()
            + (8.0 * theta / std::f32::consts::PI).floor())
        .rem_euclid(2.0)
            == 0.0;
        if on {
            Vec3::new(0.5, 0.45, 0.4)
        } else {
            Vec3::new(0.08, 0.1, 0.12)
        }
    };
    if d.y.abs() < 0.12 {
        let phi = d.x.atan2(-d.z);
        c = Vec3::new(
            0.5 + 0.5 * (3.0 * phi).sin(),
            0.5 + 0.5 * (3.0 * phi + 2.1).sin(),
            0.5 + 0.5 * (3.0 * phi + 4.2).sin(),
        );
    }
    if d.dot(sun) > 4f32.to_radians().cos() {
        c += Vec3::splat(20.0);
    }
    c
}

/// An equirectangular panorama of `f` (Mitsuba's rows: θ = π·y/(h − 1)).
fn panorama(w: u32, h: u32, f: impl Fn(Vec3) -> Vec3) -> Texture2D {
    Texture2D::from_fn(w, h, TextureOptions::default(), |x, y| {
        let u = (x as f32 + 0.5) / w as f32;
        let v = y as f32 / (h - 1) as f32;
        f(equirect_direction(u, v)).extend(1.0)
    })
    .unwrap()
}

fn env_of(t: Texture2D) -> Environment {
    Environment::new(EnvironmentMap::Equirect(t), "synthetic")
}

/// A camera at `eye` looking at `target`, `fov` degrees.
fn camera(eye: Vec3, target: Vec3, fov: f32) -> Camera {
    Camera {
        eye,
        target,
        up: Vec3::Y,
        projection: CameraProjection::Perspective { fov_y_deg: fov },
        near: 0.05,
        far: 100.0,
    }
}

/// Spheres of radius 1 along x (2.2 apart), one per material, lit by `env` alone.
fn spheres(materials: Vec<Material>, env: Environment, aspect: f32) -> (Scene, Camera) {
    let n = materials.len();
    let meshes = (0..n)
        .map(|i| {
            let mut m = Primitive::Sphere {
                radius: 1.0,
                segments: 128,
                rings: 65,
            }
            .mesh(i);
            let x = (i as f32 - (n as f32 - 1.0) * 0.5) * 2.2;
            m.world_from_object = Mat4::from_translation(Vec3::new(x, 0.0, 0.0));
            m
        })
        .collect();
    let scene = Scene {
        meshes,
        materials,
        environment: Some(env),
        ..Scene::default()
    };
    // Far enough for every sphere to fit the image's width (and at least 3, as Mitsuba's).
    let half_width = 1.1 * (n as f32 - 1.0) + 1.25;
    // A horizontal field of view of 40° at most, so the outer spheres stay round.
    let tan = 20f32.to_radians().tan() / aspect.max(1.0);
    let z = (half_width / (aspect * tan)).max(1.25 / tan).max(3.0);
    let fov = 2.0 * tan.atan().to_degrees();
    (scene, camera(Vec3::new(0.0, 0.0, z), Vec3::ZERO, fov))
}

fn rgb(f: &Frame) -> Vec<u8> {
    f.to_srgb8()
}

fn psnr(a: &Frame, b: &Frame) -> f64 {
    compare_rgb8(&rgb(a), &rgb(b), a.width as usize, a.height as usize, None).psnr_db
}

fn mirror() -> Material {
    Material {
        ambient: 0.0,
        diffuse: 0.0,
        reflection: 1.0,
        roughness: 0.0,
        ..Material::default()
    }
}

fn pbr(base: Vec3, metallic: f32, roughness: f32) -> Material {
    Material {
        model: ShadingModel::MetallicRoughness,
        base_color: base.extend(1.0),
        metallic,
        roughness,
        ..Material::default()
    }
}

#[test]
fn the_equirect_seam_draws_no_line() {
    // Looking at −z, the panorama's seam runs down the middle of the image. Rolling the
    // panorama by half its width and rotating it by 180° puts the same content there with
    // the seam behind the camera: the two images must agree (a seam filtered as a jump of u
    // from 1 to 0 would draw a line of the coarsest mip level).
    let (w, h) = (256, 128);
    let pano = panorama(w, h, smooth);
    let rolled = Texture2D::from_fn(w, h, TextureOptions::default(), |x, y| {
        pano.texel(0, (x + w / 2) % w, y)
    })
    .unwrap();
    let cam = camera(Vec3::ZERO, Vec3::NEG_Z, 60.0);
    let settings = Settings::new(96, 64);
    let scene = |env: Environment| Scene {
        environment: Some(env),
        ..Scene::default()
    };
    let a = render(&scene(env_of(pano)), &cam, &settings).unwrap();
    let b = render(
        &scene(env_of(rolled).with_rotation_deg(180.0)),
        &cam,
        &settings,
    )
    .unwrap();
    let p = psnr(&a, &b);
    assert!(p >= 50.0, "seam: {p:.1} dB between the two placements");
    // And the seam column is no further from its neighbours than they are from theirs.
    let px = |x: usize, y: usize| a.color[y * 96 + x].truncate();
    let (mut at_seam, mut elsewhere) = (0.0f32, 0.0f32);
    for y in 0..64 {
        at_seam = at_seam.max((px(48, y) - px(47, y)).abs().max_element());
        elsewhere = elsewhere.max((px(30, y) - px(29, y)).abs().max_element());
    }
    assert!(
        at_seam <= 2.0 * elsewhere + 1e-3,
        "{at_seam} vs {elsewhere}"
    );
}

/// A cube map whose faces are painted with `f` of the world direction that reads each texel
/// (face images are OpenGL's, read with x mirrored: `texture::environment`'s convention).
fn cube_of(n: u32, f: impl Fn(Vec3) -> Vec3) -> TextureCube {
    let face = |i: usize| {
        Texture2D::from_fn(n, n, TextureOptions::default(), |x, y| {
            let sc = 2.0 * (x as f32 + 0.5) / n as f32 - 1.0;
            let tc = 2.0 * (y as f32 + 0.5) / n as f32 - 1.0;
            let g = CubeFace::ALL[i].direction_through(sc, tc);
            f(Vec3::new(-g.x, g.y, g.z).normalize()).extend(1.0)
        })
        .unwrap()
    };
    TextureCube::new(std::array::from_fn(face)).unwrap()
}

/// A smooth colour of the direction with detail at every face edge and corner.
fn smooth(d: Vec3) -> Vec3 {
    Vec3::new(
        0.5 + 0.4 * (5.0 * d.x + 2.0 * d.y).sin(),
        0.5 + 0.4 * (4.0 * d.y - 3.0 * d.z).sin(),
        0.5 + 0.4 * (6.0 * d.z + d.x).sin(),
    )
}

#[test]
fn cube_faces_meet_without_a_seam() {
    // Looking into a corner of the cube (three faces and their three edges in view), at a size
    // where the reads magnify and, with a wide field of view, minify: the background must
    // follow the painted function everywhere, with no line along an edge.
    let cube = cube_of(32, smooth);
    let scene = Scene {
        environment: Some(Environment::new(
            EnvironmentMap::Cube(Box::new(cube)),
            "cube",
        )),
        ..Scene::default()
    };
    for (size, fov) in [(96u32, 90.0f32), (24, 120.0)] {
        let cam = camera(Vec3::ZERO, Vec3::new(1.0, 1.0, -1.0), fov);
        let f = render(&scene, &cam, &Settings::new(size, size)).unwrap();
        // The analytic image: the function along each pixel's ray.
        let world_from_view = Mat3::from_mat4(cam.view_from_world()).transpose();
        let tan = (0.5 * fov.to_radians()).tan();
        let mut worst = 0.0f32;
        let mut expected = Frame {
            width: size,
            height: size,
            color: texmap::frame::Pixels::zeroed((size * size) as usize),
            ..Frame::default()
        };
        for y in 0..size {
            for x in 0..size {
                let nx = 2.0 * (x as f32 + 0.5) / size as f32 - 1.0;
                let ny = 1.0 - 2.0 * (y as f32 + 0.5) / size as f32;
                let d = (world_from_view * Vec3::new(nx * tan, ny * tan, -1.0)).normalize();
                let want = smooth(d);
                let got = f.color[(y * size + x) as usize].truncate();
                worst = worst.max((got - want).abs().max_element());
                expected.color[(y * size + x) as usize] = want.extend(1.0);
            }
        }
        let p = psnr(&f, &expected);
        assert!(p >= 35.0, "{size}px, fov {fov}: {p:.1} dB");
        assert!(worst < 0.1, "{size}px, fov {fov}: worst {worst}");
    }
}

/// A high-frequency checker panorama: 64 × 32 checks, black and white.
fn checker_panorama() -> Texture2D {
    let (w, h) = (1024, 512);
    Texture2D::from_fn(w, h, TextureOptions::default(), |x, y| {
        let on = (x / 16 + y / 16) % 2 == 0;
        if on {
            Vec4::ONE
        } else {
            Vec4::new(0.0, 0.0, 0.0, 1.0)
        }
    })
    .unwrap()
}

#[test]
fn grazing_reflections_do_not_sparkle() {
    // A rippled mirror floor seen at grazing angles, reflecting a fine checker sky: across a
    // pixel the reflected direction sweeps many checks. Read with its footprint (the
    // directions' change across the quad, the ripples' included) the reflection averages
    // them, close to the supersampled image; point-sampled (the finest level only) it
    // sparkles.
    let n = 256;
    let ripples = Texture2D::from_fn(n, n, TextureOptions::default(), |x, y| {
        let (u, v) = (x as f32 / n as f32, y as f32 / n as f32);
        let h = 0.5 + 0.25 * ((TAU * 4.0 * u).sin() + (TAU * 3.0 * v).sin());
        Vec4::new(h, h, h, 1.0)
    })
    .unwrap();
    let mut slot = TextureSlot::new(Arc::new(ripples), Sampler::default());
    slot.uv_scale = 40.0;
    let floor = Primitive::Plane {
        width: 200.0,
        depth: 200.0,
        divisions: 8,
    }
    .mesh(0);
    let material = Material {
        double_sided: true,
        maps: vec![MaterialMap {
            channel: MapChannel::Bump,
            slot,
            scale: 0.4,
        }],
        ..mirror()
    };
    let scene = Scene {
        meshes: vec![floor],
        materials: vec![material],
        environment: Some(env_of(checker_panorama()).with_background(Background::Color)),
        ..Scene::default()
    };
    let cam = camera(Vec3::new(0.0, 1.0, 0.0), Vec3::new(0.0, 0.0, -50.0), 60.0);
    let (w, h) = (96, 54);
    let reference = render(&scene, &cam, &Settings::new(w, h).with_ssaa(8)).unwrap();
    let filtered = render(&scene, &cam, &Settings::new(w, h)).unwrap();
    let point = render(
        &scene,
        &cam,
        &Settings::new(w, h).with_textures(TextureOverrides::default().with_max_lod(0.0)),
    )
    .unwrap();
    let (pf, pp) = (psnr(&filtered, &reference), psnr(&point, &reference));
    eprintln!("rippled floor: footprint {pf:.1} dB, point-sampled {pp:.1} dB");
    assert!(
        pf >= pp + 3.0,
        "footprint {pf:.1} dB, point-sampled {pp:.1} dB"
    );

    // A distant mirror ball shows the whole sky in a few pixels, its rim at grazing angles.
    let (mut scene, _) = spheres(
        vec![mirror()],
        env_of(checker_panorama()).with_background(Background::None),
        1.0,
    );
    scene.meshes[0].world_from_object = Mat4::from_translation(Vec3::new(0.0, 0.0, -12.0));
    let cam = camera(Vec3::ZERO, Vec3::NEG_Z, 40.0);
    let reference = render(&scene, &cam, &Settings::new(48, 48).with_ssaa(8)).unwrap();
    let filtered = render(&scene, &cam, &Settings::new(48, 48)).unwrap();
    let point = render(
        &scene,
        &cam,
        &Settings::new(48, 48).with_textures(TextureOverrides::default().with_max_lod(0.0)),
    )
    .unwrap();
    let (pf, pp) = (psnr(&filtered, &reference), psnr(&point, &reference));
    eprintln!("distant ball: footprint {pf:.1} dB, point-sampled {pp:.1} dB");
    assert!(
        pf >= pp + 3.0,
        "ball: footprint {pf:.1} dB, point-sampled {pp:.1} dB"
    );
}

#[test]
fn a_uniform_environment_lights_like_a_uniform_ambient_light_of_its_radiance() {
    // Radiance 1 everywhere: a Lambertian Phong sphere with K_A = 1 shows its colour, a white
    // dielectric reflects 1 at every angle (the white furnace), a smooth white metal 1.
    let white = Texture2D::from_fn(64, 32, TextureOptions::default(), |_, _| Vec4::ONE).unwrap();
    let lambert = Material {
        base_color: Vec4::new(0.8, 0.2, 0.2, 1.0),
        ambient: 1.0,
        diffuse: 0.0,
        ..Material::default()
    };
    let (scene, cam) = spheres(
        vec![lambert, pbr(Vec3::ONE, 0.0, 0.5), pbr(Vec3::ONE, 1.0, 0.0)],
        env_of(white).with_background(Background::None),
        3.0,
    );
    let f = render(&scene, &cam, &Settings::new(120, 40)).unwrap();
    // The spheres' centres: x = ±2.2; the image's half-width at their distance.
    let half = cam.eye.z * 20f32.to_radians().tan();
    let at = |x: f32| {
        let px = (60.0 + x / half * 60.0) as u32;
        f.color[(20 * 120 + px) as usize].truncate()
    };
    let close = |a: Vec3, b: Vec3, tol: f32| (a - b).abs().max_element() < tol;
    assert!(
        close(at(-2.2), Vec3::new(0.8, 0.2, 0.2), 5e-3),
        "{}",
        at(-2.2)
    );
    assert!(close(at(0.0), Vec3::ONE, 1e-2), "{}", at(0.0));
    assert!(close(at(2.2), Vec3::ONE, 3e-2), "{}", at(2.2));
    // Where nothing is drawn the background is transparent black.
    assert_eq!(f.color[0], Vec4::ZERO);
}

#[test]
fn environment_frames_do_not_depend_on_the_thread_count() {
    let (scene, cam) = spheres(
        vec![
            mirror(),
            pbr(Vec3::new(1.0, 0.8, 0.4), 1.0, 0.35),
            Material {
                transmission: 1.0,
                ..pbr(Vec3::ONE, 0.0, 0.0)
            },
        ],
        env_of(panorama(256, 128, world)),
        3.0,
    );
    let settings = Settings::new(90, 30).with_msaa(4);
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| render(&scene, &cam, &settings).unwrap())
    };
    assert_eq!(run(1).color, run(3).color);
}

/// Renders `scene` at `w × h` (SSAA 2) and checks it against `tests/golden/{name}.png`.
fn golden(name: &str, scene: &Scene, cam: &Camera, w: u32, h: u32) {
    let f = render(scene, cam, &Settings::new(w, h).with_ssaa(2)).unwrap();
    // The renderer is deterministic; the threshold leaves room for floating-point changes.
    common::assert_golden(name, w, h, &rgb(&f), 40.0);
}

#[test]
fn golden_background_mirror_and_rough_metals() {
    let env = || env_of(panorama(512, 256, world));
    // The background alone, looking up towards the sun over the bands.
    let scene = Scene {
        environment: Some(env()),
        ..Scene::default()
    };
    let cam = camera(Vec3::ZERO, Vec3::new(0.5, 0.3, 1.0), 90.0);
    golden("env_background", &scene, &cam, 160, 90);
    // A mirror, then metals at roughness 0.15, 0.4 and 0.8.
    let (scene, cam) = spheres(
        vec![
            mirror(),
            pbr(Vec3::ONE, 1.0, 0.15),
            pbr(Vec3::new(1.0, 0.78, 0.34), 1.0, 0.4),
            pbr(Vec3::ONE, 1.0, 0.8),
        ],
        env(),
        4.0,
    );
    golden("env_mirror_metals", &scene, &cam, 320, 80);
}

#[test]
fn golden_diffuse_plastic_and_glass() {
    let env = || env_of(panorama(512, 256, world));
    let lambert = Material {
        base_color: Vec4::new(0.8, 0.2, 0.2, 1.0),
        ambient: 1.0,
        diffuse: 0.0,
        ..Material::default()
    };
    let glass = Material {
        transmission: 1.0,
        ..pbr(Vec3::ONE, 0.0, 0.0)
    };
    let phong_glass = Material {
        ambient: 0.0,
        diffuse: 0.0,
        reflection: 1.0,
        transmission: 1.0,
        ior: 1.33,
        roughness: 0.0, // Material::default's is glTF's 1.0: a Phong glass is smooth
        ..Material::default()
    };
    let (scene, cam) = spheres(
        vec![
            lambert,
            pbr(Vec3::new(0.8, 0.2, 0.2), 0.0, 0.5),
            glass,
            phong_glass,
        ],
        env(),
        4.0,
    );
    golden("env_diffuse_plastic_glass", &scene, &cam, 320, 80);
}

#[test]
fn golden_cube_and_sphere_maps() {
    // The same world as a cube map (32² faces) and as a sphere map (128²): background and a
    // mirror sphere each.
    let cube = Environment::new(EnvironmentMap::Cube(Box::new(cube_of(64, world))), "cube");
    let n = 128;
    let sphere_map = Texture2D::from_fn(n, n, TextureOptions::default(), |x, y| {
        // The inverse of OpenGL's sphere map: the mirror ball's normal, then the reflection.
        let s = 2.0 * (x as f32 + 0.5) / n as f32 - 1.0;
        let t = 1.0 - 2.0 * (y as f32 + 0.5) / n as f32;
        let r2 = s * s + t * t;
        if r2 > 1.0 {
            return Vec4::new(0.0, 0.0, 0.0, 1.0);
        }
        let z = (1.0 - r2).sqrt();
        let d = Vec3::new(2.0 * z * s, 2.0 * z * t, 2.0 * z * z - 1.0);
        world(d.normalize()).extend(1.0)
    })
    .unwrap();
    let sphere = Environment::new(EnvironmentMap::Sphere(sphere_map), "sphere map");
    for (name, env) in [("env_cube_map", cube), ("env_sphere_map", sphere)] {
        let (mut scene, _) = spheres(vec![mirror()], env, 1.0);
        scene.meshes[0].world_from_object = Mat4::from_translation(Vec3::new(0.0, -0.3, -2.0));
        let cam = camera(Vec3::ZERO, Vec3::new(0.3, 0.1, -1.0), 90.0);
        golden(name, &scene, &cam, 160, 90);
    }
}

#[test]
fn gouraud_and_flat_take_the_environment_too() {
    // Per vertex and per face the environment lights with the vertex's or face's directions:
    // close to the per-pixel image for the smooth diffuse term.
    let lambert = Material {
        base_color: Vec4::new(0.8, 0.6, 0.2, 1.0),
        ambient: 1.0,
        diffuse: 0.0,
        ..Material::default()
    };
    let (scene, cam) = spheres(
        vec![lambert, pbr(Vec3::ONE, 1.0, 0.6)],
        env_of(panorama(256, 128, world)).with_background(Background::None),
        2.0,
    );
    let settings = Settings::new(96, 48);
    let phong = render(&scene, &cam, &settings).unwrap();
    let gouraud = render(&scene, &cam, &settings.with_shading(ShadingMode::Gouraud)).unwrap();
    let p = psnr(&phong, &gouraud);
    assert!(p >= 30.0, "Gouraud against Phong shading: {p:.1} dB");
    // Without an environment the same scene is lit by its (zero) ambient light only: black.
    let mut dark = scene.clone();
    dark.environment = None;
    let f = render(&dark, &cam, &settings).unwrap();
    assert!(f.color.iter().all(|c| c.truncate().max_element() < 1e-6));
}

/// `KHR_materials_transmission` sees the frame's other surfaces: a clear glass sphere in front
/// of an unlit green board (the left half of the view, behind the sphere) shows the board
/// where it is behind, and the environment, the same bytes as the sphere alone, where it is
/// not.
#[test]
fn transmission_sees_the_surfaces_behind_it() {
    let glass = Material {
        transmission: 1.0,
        ..pbr(Vec3::ONE, 0.0, 0.0)
    };
    let board = Material {
        unlit: true,
        base_color: Vec4::new(0.0, 1.0, 0.0, 1.0),
        ..Material::default()
    };
    let sphere = Primitive::Sphere {
        radius: 1.0,
        segments: 128,
        rings: 65,
    }
    .mesh(0);
    let mut plane = Primitive::Plane {
        width: 4.0,
        depth: 8.0,
        divisions: 1,
    }
    .mesh(1);
    // Facing +z, covering x in [−4, 0], 3 behind the sphere.
    plane.world_from_object = Mat4::from_translation(Vec3::new(-2.0, 0.0, -3.0))
        * Mat4::from_rotation_x(std::f32::consts::FRAC_PI_2);
    let env = || env_of(panorama(256, 128, world));
    let alone = Scene {
        meshes: vec![sphere.clone()],
        materials: vec![glass.clone(), board.clone()],
        environment: Some(env()),
        ..Scene::default()
    };
    let with_board = Scene {
        meshes: vec![sphere, plane],
        materials: vec![glass, board],
        environment: Some(env()),
        ..Scene::default()
    };
    let cam = camera(Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO, 40.0);
    let settings = Settings::new(96, 96);
    let a = render(&alone, &cam, &settings).unwrap();
    let b = render(&with_board, &cam, &settings).unwrap();
    let px = |f: &Frame, x: usize, y: usize| f.color[y * 96 + x];
    // Through the sphere, left of centre: the board (green), not the sky or ground.
    for x in [30, 38, 44] {
        let c = px(&b, x, 48);
        assert!(c.y > 2.0 * c.x && c.y > 2.0 * c.z, "pixel {x}: {c}");
        assert_ne!(c, px(&a, x, 48));
    }
    // Right of centre nothing is behind the glass: the environment, exactly as alone.
    for y in 30..66 {
        for x in 52..66 {
            assert_eq!(px(&b, x, y), px(&a, x, y), "pixel ({x}, {y})");
        }
    }
    // The pass behind the glass shades the whole board, and the frame the glass and the
    // board around it: the counts include both (the frame alone has fewer than the glass
    // plus the board, whose pixels behind the glass are hidden from it).
    let mut no_glass = with_board.clone();
    no_glass.meshes.remove(0);
    let c = render(&no_glass, &cam, &settings).unwrap();
    let board_pixels = c.stats.pixels_shaded;
    assert!(board_pixels > 0);
    assert!(
        b.stats.pixels_shaded >= a.stats.pixels_shaded + board_pixels,
        "glass and board {}, glass alone {}, board alone {board_pixels}",
        b.stats.pixels_shaded,
        a.stats.pixels_shaded
    );
}
