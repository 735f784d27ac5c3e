//! Integration tests of the rasterization pipeline and `render`.

mod common;

use common::Uv;

use std::sync::Arc;

use glam::{Mat4, Vec2, Vec3, Vec4};
use texmap::camera::{Camera, CameraProjection};
use texmap::pipeline::{
    self, ClipVertex, CullMode, DrawCall, DrawState, FragmentShader, Interpolation, Quad, Target,
    MAX_VARYINGS,
};
use texmap::render::{render, Frame, Settings, ShadingMode, Visibility};
use texmap::scene::{builtin, AlphaMode, Material, Mesh, Scene};
use texmap::texture::Sampler;

// ---- helpers -------------------------------------------------------------------------------

/// Adds (1, 0, 0, 0) per covered sample: with premultiplied "over" and alpha 0 this counts.
struct Count;
impl FragmentShader for Count {
    fn shade(&self, _: u32, q: &Quad, out: &mut [Vec4; 4]) -> u8 {
        *out = [Vec4::new(1.0, 0.0, 0.0, 0.0); 4];
        q.mask
    }
}

fn clip_vertices(positions: &[Vec3], uvs: &[Vec2], clip_from_world: Mat4) -> Vec<ClipVertex> {
    positions
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let mut var = [0.0; MAX_VARYINGS];
            if let Some(uv) = uvs.get(i) {
                var[0] = uv.x;
                var[1] = uv.y;
            }
            ClipVertex {
                clip: clip_from_world * p.extend(1.0),
                varyings: var,
            }
        })
        .collect()
}

fn target(w: u32, h: u32, samples: u32) -> Target {
    Target {
        width: w,
        height: h,
        samples,
        clear_color: Vec4::ZERO,
        interpolation: Interpolation::Perspective,
        depth_sort: false,
    }
}

fn camera(eye: Vec3, target: Vec3) -> Camera {
    Camera {
        eye,
        target,
        up: Vec3::Y,
        projection: CameraProjection::Perspective { fov_y_deg: 60.0 },
        near: 0.05,
        far: 100.0,
    }
}

fn clip_from_world(cam: &Camera, w: u32, h: u32) -> Mat4 {
    cam.clip_from_view(w as f32 / h as f32) * cam.view_from_world()
}

fn count_hits(
    positions: &[Vec3],
    indices: &[u32],
    cam: &Camera,
    w: u32,
    h: u32,
    samples: u32,
    cull: CullMode,
) -> Vec<f32> {
    let verts = clip_vertices(positions, &[], clip_from_world(cam, w, h));
    let call = DrawCall {
        vertices: &verts,
        indices,
        state: DrawState {
            cull,
            depth_test: false,
            depth_write: false,
            blend: true,
            ..Default::default()
        },
    };
    let (color, _) = pipeline::draw(&[call], &Count, &target(w, h, samples));
    color.iter().map(|c| c.x).collect()
}

fn unlit(color: Vec4) -> Material {
    Material {
        base_color: color,
        unlit: true,
        double_sided: true,
        ..Default::default()
    }
}

fn max_abs_diff(a: &Frame, b: &Frame) -> (f32, usize) {
    let mut worst = 0.0f32;
    let mut differing = 0;
    for (x, y) in a.color.iter().zip(&b.color) {
        let d = (*x - *y).abs().max_element();
        worst = worst.max(d);
        differing += usize::from(d > 1e-6);
    }
    (worst, differing)
}

// ---- coverage ------------------------------------------------------------------------------

#[test]
fn watertight_closed_mesh_inside_covers_every_pixel_once() {
    let (p, idx) = common::icosphere(3);
    // Many triangles cross the camera plane and are clipped at near; with near = 1e-4 the
    // clipped vertices land far outside the guard band, so those planes clip too.
    let cam = camera(Vec3::new(0.13, -0.21, 0.17), Vec3::new(0.9, 0.37, -1.0));
    for near in [0.05, 1e-4] {
        for samples in [1, 4] {
            let cam = Camera { near, ..cam };
            let hits = count_hits(&p, &idx, &cam, 97, 61, samples, CullMode::None);
            let bad = hits.iter().filter(|&&c| c != 1.0).count();
            assert_eq!(
                bad, 0,
                "near {near}, {samples} samples: {bad} pixels not covered once"
            );
        }
    }
}

#[test]
fn watertight_closed_mesh_outside_covers_pixels_zero_or_two_times() {
    let (p, idx) = common::icosphere(3);
    let cam = camera(Vec3::new(0.3, 0.4, 2.4), Vec3::ZERO);
    let hits = count_hits(&p, &idx, &cam, 128, 96, 1, CullMode::None);
    assert!(
        hits.iter().all(|&c| c == 0.0 || c == 2.0),
        "a pixel was hit an odd number of times"
    );
    let covered = hits.iter().filter(|&&c| c == 2.0).count();
    assert!(covered > 128 * 96 / 4, "{covered}");
    // Front faces only: exactly once.
    let front = count_hits(&p, &idx, &cam, 128, 96, 1, CullMode::Back);
    for (a, b) in hits.iter().zip(&front) {
        assert_eq!(*a, 2.0 * b);
    }
}

#[test]
fn camera_inside_a_cube_sees_it_everywhere() {
    let scene = Scene {
        meshes: vec![builtin::cube(0, Mat4::from_scale(Vec3::splat(10.0)))],
        materials: vec![unlit(Vec4::ONE)],
        ..Default::default()
    };
    let cam = Camera {
        eye: Vec3::new(1.0, 2.0, 3.0),
        target: Vec3::new(4.0, 2.5, -1.0),
        ..camera(Vec3::ZERO, Vec3::Z)
    };
    let s = Settings::new(96, 64);
    let f = render(&scene, &cam, &s).unwrap();
    assert!(
        f.color.iter().all(|c| *c == Vec4::ONE),
        "a pixel missed the cube"
    );
    assert!(f.stats.triangles_after_clip >= 4, "{:?}", f.stats);
}

#[test]
fn triangles_behind_the_camera_draw_nothing() {
    let mut scene = Scene {
        meshes: vec![Mesh {
            positions: vec![
                Vec3::new(-5.0, -5.0, 3.0),
                Vec3::new(5.0, -5.0, 3.0),
                Vec3::new(0.0, 5.0, 3.0),
            ],
            indices: vec![0, 1, 2],
            ..Default::default()
        }],
        materials: vec![unlit(Vec4::ONE)],
        ..Default::default()
    };
    scene.meshes[0].world_from_object = Mat4::IDENTITY;
    let cam = camera(Vec3::ZERO, Vec3::new(0.0, 0.0, -1.0));
    let s = Settings::new(64, 48);
    let f = render(&scene, &cam, &s).unwrap();
    assert!(f.color.iter().all(|c| *c == Vec4::ZERO));
    assert_eq!(f.stats.triangles_after_clip, 0);
}

#[test]
fn plane_crossing_the_camera_plane_fills_below_the_horizon_only() {
    let scene = builtin::plane(None, 64.0, Sampler::default());
    let cam = scene.camera.unwrap();
    let (w, h) = (160u32, 90u32);
    let f = render(&scene, &cam, &Settings::new(w, h)).unwrap();
    // The view looks down by atan(1/50): the horizon is that far above the centre row.
    let horizon = h as f32 * 0.5 * (1.0 - (1.0f32 / 50.0).atan().tan() / 30f32.to_radians().tan());
    for y in 0..h {
        for x in 0..w {
            let c = f.color[(y * w + x) as usize];
            if (y as f32) < horizon - 2.0 {
                assert_eq!(c.truncate(), Vec3::ZERO, "sky pixel ({x}, {y}) drawn");
            } else if (y as f32) > horizon + 2.0 {
                assert!(c.max_element() > 0.01, "floor pixel ({x}, {y}) empty");
            }
        }
    }
}

// ---- interpolation -------------------------------------------------------------------------

/// Max uv error in texels of the peers' plane against the analytic ray–plane intersection,
/// over pixels whose ray hits the plane within `max_dist`.
fn plane_uv_error(interpolation: Interpolation, max_dist: f32) -> f32 {
    let (w, h) = (320u32, 180u32);
    let s = 64.0;
    let cam = builtin::plane(None, s, Sampler::default()).camera.unwrap();
    let positions = [
        Vec3::new(-100.0, 0.0, -100.0),
        Vec3::new(100.0, 0.0, -100.0),
        Vec3::new(100.0, 0.0, 100.0),
        Vec3::new(-100.0, 0.0, 100.0),
    ];
    let uvs: Vec<Vec2> = positions
        .iter()
        .map(|p| Vec2::new(p.x + 100.0, p.z + 100.0) / 200.0 * s)
        .collect();
    let verts = clip_vertices(&positions, &uvs, clip_from_world(&cam, w, h));
    let call = DrawCall {
        vertices: &verts,
        indices: &[0, 3, 2, 0, 2, 1],
        state: DrawState {
            varyings: 2,
            ..Default::default()
        },
    };
    let t = Target {
        interpolation,
        ..target(w, h, 1)
    };
    let (color, _) = pipeline::draw(&[call], &Uv, &t);
    // Analytic: the ray through each pixel centre.
    let world_from_view = cam.view_from_world().inverse();
    let tan = (cam.projection.fov_y_deg().unwrap().to_radians() * 0.5).tan();
    let aspect = w as f32 / h as f32;
    let mut worst = 0.0f32;
    for y in 0..h {
        for x in 0..w {
            let ndc = Vec2::new(
                2.0 * (x as f32 + 0.5) / w as f32 - 1.0,
                1.0 - 2.0 * (y as f32 + 0.5) / h as f32,
            );
            let d = world_from_view.transform_vector3(Vec3::new(
                ndc.x * tan * aspect,
                ndc.y * tan,
                -1.0,
            ));
            if d.y >= 0.0 {
                continue;
            }
            let t = -cam.eye.y / d.y;
            let hit = cam.eye + d * t;
            if (hit - cam.eye).length() > max_dist || hit.x.abs() > 100.0 || hit.z.abs() > 100.0 {
                continue;
            }
            let want = Vec2::new(hit.x + 100.0, hit.z + 100.0) / 200.0 * s;
            let got = color[(y * w + x) as usize];
            let err = (Vec2::new(got.x, got.y) - want).length() * 1024.0;
            worst = worst.max(err);
        }
    }
    worst
}

#[test]
fn perspective_correct_uv_matches_ray_plane_intersection() {
    // The error grows with distance as f32 clip coordinates lose precision; within 10 units
    // of the eye a pixel spans up to ~60 texels here.
    let err = plane_uv_error(Interpolation::Perspective, 10.0);
    let far = plane_uv_error(Interpolation::Perspective, 50.0);
    println!("perspective: max uv error {err:.4} texels within 10 units, {far:.3} within 50");
    assert!(err < 0.1, "{err} texels");
}

#[test]
fn affine_interpolation_differs_measurably_and_subdivision_fixes_it() {
    let affine = plane_uv_error(Interpolation::Affine, 10.0);
    let sub = plane_uv_error(Interpolation::Subdivide { max_error_px: 0.25 }, 10.0);
    println!("affine: {affine:.1} texels, subdivide(0.25 px): {sub:.2} texels");
    assert!(affine > 100.0, "{affine}");
    assert!(sub < affine / 20.0, "{sub} vs {affine}");
}

// ---- antialiasing, visibility, blending ----------------------------------------------------

fn white_triangle_scene() -> (Scene, Camera) {
    let scene = Scene {
        meshes: vec![Mesh {
            positions: vec![
                Vec3::new(-1.0, -0.8, 0.0),
                Vec3::new(1.1, -0.5, 0.0),
                Vec3::new(-0.2, 0.9, 0.0),
            ],
            indices: vec![0, 1, 2],
            ..Default::default()
        }],
        materials: vec![unlit(Vec4::ONE)],
        ..Default::default()
    };
    (scene, camera(Vec3::new(0.0, 0.0, 2.5), Vec3::ZERO))
}

#[test]
fn msaa_edge_pixels_get_fractional_coverage() {
    let (scene, cam) = white_triangle_scene();
    for n in [2u32, 4, 8, 16] {
        let f = render(&scene, &cam, &Settings::new(64, 48).with_msaa(n)).unwrap();
        let partial: Vec<f32> = f
            .color
            .iter()
            .map(|c| c.x)
            .filter(|&v| v > 0.0 && v < 1.0)
            .collect();
        assert!(
            !partial.is_empty(),
            "{n}x: no edge pixel with partial coverage"
        );
        for v in partial {
            let k = v * n as f32;
            assert!(
                (k - k.round()).abs() < 1e-4,
                "{n}x: {v} is not a multiple of 1/{n}"
            );
        }
    }
}

#[test]
fn ssaa_resolves_edges_in_linear_light() {
    let (scene, cam) = white_triangle_scene();
    let f = render(&scene, &cam, &Settings::new(64, 48).with_ssaa(3)).unwrap();
    assert!(f.color.iter().any(|c| c.x > 0.0 && c.x < 1.0));
    assert_eq!(f.color.len(), 64 * 48);
}

fn separated_objects() -> (Scene, Camera) {
    let mut near = builtin::cube(1, Mat4::from_translation(Vec3::new(0.4, 0.2, 1.0)));
    near.world_from_object *= Mat4::from_rotation_y(0.6);
    let mut far = builtin::uv_sphere(24, 13, 0);
    far.world_from_object = Mat4::from_translation(Vec3::new(-0.3, 0.0, -2.0));
    let lit = Material {
        specular: 0.5,
        ..Default::default()
    };
    let scene = Scene {
        meshes: vec![near, far],
        materials: vec![
            lit.clone(),
            Material {
                base_color: Vec4::new(1.0, 0.5, 0.2, 1.0),
                ..lit
            },
        ],
        lights: vec![texmap::scene::Light::Directional {
            direction: Vec3::new(0.3, 0.8, 0.5),
            color: Vec3::ONE,
        }],
        ambient_light: Vec3::ONE,
        background: Vec4::new(0.1, 0.1, 0.1, 1.0),
        ..Scene::default()
    };
    (scene, camera(Vec3::new(0.0, 0.5, 4.0), Vec3::ZERO))
}

#[test]
fn depth_sort_agrees_with_the_z_buffer_on_separated_objects() {
    let (scene, cam) = separated_objects();
    let s = Settings::new(96, 64).with_cull(CullMode::Back);
    let z = render(&scene, &cam, &s).unwrap();
    let p = render(&scene, &cam, &s.with_visibility(Visibility::DepthSort)).unwrap();
    let (worst, differing) = max_abs_diff(&z, &p);
    assert_eq!(differing, 0, "max difference {worst}");
}

#[test]
fn blended_surfaces_are_drawn_over_opaque_ones() {
    let mut panel = builtin::cube(1, Mat4::from_translation(Vec3::new(0.0, 0.0, 1.0)));
    panel.world_from_object *= Mat4::from_scale(Vec3::new(3.0, 3.0, 0.1));
    let back = builtin::cube(
        0,
        Mat4::from_scale(Vec3::splat(4.0)) * Mat4::from_translation(Vec3::new(0.0, 0.0, -1.0)),
    );
    // The translucent panel comes first in the scene but must be blended after the wall.
    let scene = Scene {
        meshes: vec![panel, back],
        materials: vec![
            unlit(Vec4::new(1.0, 0.0, 0.0, 1.0)),
            Material {
                alpha_mode: AlphaMode::Blend,
                ..unlit(Vec4::new(0.0, 0.0, 1.0, 0.5))
            },
        ],
        ..Default::default()
    };
    let cam = camera(Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO);
    let f = render(&scene, &cam, &Settings::new(32, 32)).unwrap();
    let c = f.color[16 * 32 + 16];
    // Two panel faces (front and back, both blended): blue over blue over red.
    assert!(
        (c - Vec4::new(0.25, 0.0, 0.75, 1.0)).abs().max_element() < 1e-5,
        "{c}"
    );
}

#[test]
fn shading_modes_all_render_and_agree_on_a_flat_surface() {
    let scene = builtin::plane(None, 8.0, Sampler::default());
    let cam = scene.camera.unwrap();
    let base = Settings::new(64, 36);
    let phong = render(&scene, &cam, &base).unwrap();
    for shading in [ShadingMode::Gouraud, ShadingMode::Flat] {
        let f = render(&scene, &cam, &base.with_shading(shading)).unwrap();
        let (worst, _) = max_abs_diff(&phong, &f);
        assert!(worst < 1e-4, "{shading:?}: {worst}");
    }
}

// ---- determinism and robustness ------------------------------------------------------------

#[test]
fn same_image_whatever_the_thread_count() {
    let scene = builtin::demo();
    let cam = scene.camera.unwrap();
    // One sample (colour streamed from the tile buffer) and MSAA (resolved).
    for msaa in [1, 4] {
        let s = Settings::new(200, 120).with_msaa(msaa);
        let run = |threads| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| render(&scene, &cam, &s)).unwrap()
        };
        let (a, b, c) = (run(1), run(2), run(3));
        assert!(
            a.color == b.color && b.color == c.color,
            "msaa {msaa}: images differ between thread counts"
        );
        assert_eq!(a.stats, b.stats);
    }
}

#[test]
fn bad_settings_and_cameras_are_errors() {
    let scene = builtin::plane(None, 64.0, Sampler::default());
    let cam = scene.camera.unwrap();
    let ok = Settings::new(16, 16);
    assert!(render(&scene, &cam, &ok).is_ok());
    for s in [
        ok.with_size(0, ok.height),
        ok.with_size(ok.width, 20_000),
        ok.with_msaa(3),
        ok.with_ssaa(0),
        ok.with_ssaa(9),
        ok.with_interpolation(Interpolation::Subdivide {
            max_error_px: f32::NAN,
        }),
    ] {
        assert!(render(&scene, &cam, &s).is_err(), "{s:?}");
    }
    for c in [
        Camera {
            eye: Vec3::splat(f32::NAN),
            ..cam
        },
        Camera { near: 0.0, ..cam },
        Camera { near: -1.0, ..cam },
        Camera { far: 0.01, ..cam },
        Camera {
            projection: CameraProjection::Perspective {
                fov_y_deg: f32::INFINITY,
            },
            ..cam
        },
    ] {
        assert!(render(&scene, &c, &ok).is_err(), "{c:?}");
    }
    let mut broken = scene.clone();
    broken.meshes[0].material = 7;
    assert!(render(&broken, &cam, &ok).is_err());
}

#[test]
fn nan_degenerate_and_out_of_range_triangles_are_skipped() {
    let (mut scene, cam) = white_triangle_scene();
    let m = &mut scene.meshes[0];
    m.positions.extend([
        Vec3::NAN,
        Vec3::new(f32::INFINITY, 0.0, 0.0),
        Vec3::new(0.5, 0.5, 0.0),
    ]);
    m.indices
        .extend([3, 1, 2, 0, 4, 2, 0, 0, 1, 5, 5, 5, 0, 1, 99]);
    m.normals = vec![Vec3::Z; 2]; // wrong length: ignored
    m.uvs = vec![Vec2::ZERO; 1];
    m.colors = vec![Vec4::ONE; 6];
    for shading in [ShadingMode::Phong, ShadingMode::Gouraud, ShadingMode::Flat] {
        let f = render(&scene, &cam, &Settings::new(48, 48).with_shading(shading)).unwrap();
        assert_eq!(f.stats.triangles_after_clip, 1, "{shading:?}");
        assert!(f.color.iter().any(|c| c.x > 0.5));
    }
}

#[test]
fn textured_sphere_renders_with_samples_counted() {
    let scene = builtin::sphere(
        2000,
        Some(Arc::new(
            texmap::texture::Texture2D::from_rgba8(
                2,
                2,
                texmap::texture::ColorSpace::Srgb,
                &[255; 16],
            )
            .unwrap(),
        )),
        Sampler::default(),
    );
    let cam = scene.camera.unwrap();
    let f = render(&scene, &cam, &Settings::new(64, 64)).unwrap();
    assert!(f.stats.texture_samples > 0 && f.stats.texture_samples == f.stats.pixels_shaded);
    let centre = f.color[32 * 64 + 32];
    assert!(centre.x > 0.2, "{centre}");
    assert_eq!(f.to_srgb8().len(), 64 * 64 * 3);
}

// ---- timing (run with: cargo test --release -p texmap --test pipeline -- --ignored --nocapture)

fn time_frames(scene: &Scene, s: &Settings, frames: usize) -> (f64, f64) {
    let cam = scene.camera.unwrap();
    let threads = std::env::var("TEXMAP_THREADS")
        .ok()
        .and_then(|t| t.parse().ok())
        .unwrap_or(2);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        let _ = render(scene, &cam, s).unwrap();
        let mut times = Vec::new();
        for k in 0..frames {
            let c = cam.orbit(k as f32 * std::f32::consts::TAU / frames as f32);
            let t = std::time::Instant::now();
            let f = render(scene, &c, s).unwrap();
            times.push(t.elapsed().as_secs_f64() * 1e3);
            std::hint::black_box(f);
        }
        times.sort_by(f64::total_cmp);
        (times[0], times[times.len() / 2])
    })
}

#[test]
#[ignore = "timing; run in release"]
fn timing_1080p_two_threads() {
    let s = Settings::new(1920, 1080);
    let only = std::env::var("TEXMAP_TIMING").unwrap_or_default();
    let threads = std::env::var("TEXMAP_THREADS").unwrap_or_else(|_| "2".into());
    let want = |name: &str| only.is_empty() || only.contains(name);
    let plane = builtin::plane(None, 64.0, Sampler::default());
    let (min, med) = if want("plane") {
        time_frames(&plane, &s, 10)
    } else {
        (0.0, 0.0)
    };
    println!("plane trilinear 1920x1080, {threads} threads: min {min:.1} ms, median {med:.1} ms");
    if want("nearest") {
        let s = s.with_textures(
            texmap::render::TextureOverrides::default()
                .with_filter(texmap::texture::Filter::NEAREST),
        );
        let (min, med) = time_frames(&plane, &s, 10);
        println!("plane nearest 1920x1080, {threads} threads: min {min:.1} ms, median {med:.1} ms");
    }
    let sphere = builtin::sphere(199_200, None, Sampler::default());
    let (min, med) = if want("sphere") {
        time_frames(&sphere, &s, 10)
    } else {
        (0.0, 0.0)
    };
    println!(
        "sphere 199200 tris 1920x1080, {threads} threads: min {min:.1} ms, median {med:.1} ms"
    );
    let demo = builtin::demo();
    let (min, med) = if want("demo") {
        time_frames(&demo, &s, 5)
    } else {
        (0.0, 0.0)
    };
    println!("demo 1920x1080, {threads} threads: min {min:.1} ms, median {med:.1} ms");
    if let Ok(dir) = std::env::var("TEXMAP_DUMP") {
        for (name, scene) in [("plane", &plane), ("sphere", &sphere), ("demo", &demo)] {
            let f = render(scene, &scene.camera.unwrap(), &s).unwrap();
            let img = image::RgbImage::from_raw(f.width, f.height, f.to_srgb8()).unwrap();
            img.save(format!("{dir}/{name}.png")).unwrap();
        }
    }
}

#[test]
fn empty_tiles_show_the_background_premultiplied() {
    let (mut scene, cam) = white_triangle_scene();
    scene.background = Vec4::new(0.2, 0.4, 0.6, 0.5);
    let f = render(&scene, &cam, &Settings::new(300, 200).with_msaa(4)).unwrap();
    let bg = Vec4::new(0.1, 0.2, 0.3, 0.5);
    assert_eq!(f.color[0], bg);
    assert_eq!(f.color[300 * 200 - 1], bg);
    assert_eq!(f.color[100 * 300 + 150], Vec4::ONE);
}

#[test]
fn alpha_mask_discards_below_the_cutoff_and_is_opaque_above() {
    let (mut scene, cam) = white_triangle_scene();
    let s = Settings::new(32, 32);
    for (alpha, drawn) in [(0.3, false), (0.7, true)] {
        scene.materials[0] = Material {
            alpha_mode: AlphaMode::Mask(0.5),
            ..unlit(Vec4::new(1.0, 1.0, 1.0, alpha))
        };
        let f = render(&scene, &cam, &s).unwrap();
        let c = f.color[16 * 32 + 16];
        let want = if drawn { Vec4::ONE } else { Vec4::ZERO };
        assert_eq!(c, want, "alpha {alpha}");
    }
}

/// Colours each pixel by its draw and position; draw 3 drops a pattern of pixels (an alpha
/// test's discard).
struct ByDraw;
impl FragmentShader for ByDraw {
    fn shade(&self, draw: u32, q: &Quad, out: &mut [Vec4; 4]) -> u8 {
        let mut kept = q.mask;
        for (j, o) in out.iter_mut().enumerate() {
            let (x, y) = (q.x + (j as u32 & 1), q.y + (j as u32 >> 1));
            *o = Vec4::new(draw as f32 + 1.0, x as f32, y as f32, 1.0);
            if draw == 3 && (x + 2 * y) % 3 == 0 {
                kept &= !(1 << j);
            }
        }
        kept
    }
}

/// The two triangles of the rectangle `x0..x1` × `y0..y1` in clip space at depth `z`.
fn square(x0: f32, y0: f32, x1: f32, y1: f32, z: f32) -> [ClipVertex; 6] {
    [(x0, y0), (x1, y0), (x1, y1), (x0, y0), (x1, y1), (x0, y1)].map(|(x, y)| ClipVertex {
        clip: Vec4::new(x, y, z, 1.0),
        varyings: [0.0; MAX_VARYINGS],
    })
}

#[test]
fn the_depth_pre_pass_changes_no_pixel_and_shades_fewer() {
    // Overlapping opaque draws: a far square, a nearer one, the far one again (a tie the
    // first draw wins), a discarding draw between them, and a tilted triangle crossing them.
    let tilted =
        [(-0.9, -0.8, -0.5), (0.8, -0.6, 0.9), (0.1, 0.9, 0.1)].map(|(x, y, z)| ClipVertex {
            clip: Vec4::new(x, y, z, 1.0),
            varyings: [0.0; MAX_VARYINGS],
        });
    let draws: Vec<Vec<ClipVertex>> = vec![
        square(-0.8, -0.8, 0.7, 0.6, 0.5).to_vec(),
        square(-0.3, -0.5, 0.4, 0.8, 0.2).to_vec(),
        square(-0.8, -0.8, 0.7, 0.6, 0.5).to_vec(),
        square(-0.6, -0.2, 0.2, 0.3, 0.3).to_vec(),
        tilted.to_vec(),
    ];
    let indices: Vec<u32> = (0..6).collect();
    let run = |pre: bool| {
        let calls: Vec<DrawCall> = draws
            .iter()
            .enumerate()
            .map(|(k, v)| DrawCall {
                vertices: v,
                indices: &indices[..v.len()],
                state: DrawState {
                    keeps_all: pre && k != 3,
                    ..Default::default()
                },
            })
            .collect();
        pipeline::draw(&calls, &ByDraw, &target(67, 45, 1))
    };
    let (with, with_stats) = run(true);
    let (without, without_stats) = run(false);
    let bits = |c: &[Vec4]| {
        c.iter()
            .flat_map(|v| v.to_array().map(f32::to_bits))
            .collect::<Vec<_>>()
    };
    assert_eq!(bits(&with), bits(&without));
    // Every draw shows somewhere, and the hidden parts of the far square were not shaded.
    for k in [1.0, 2.0, 4.0, 5.0] {
        assert!(with.iter().any(|c| c.x == k), "draw {k} missing");
    }
    assert!(
        with_stats.pixels_shaded < without_stats.pixels_shaded,
        "{} vs {}",
        with_stats.pixels_shaded,
        without_stats.pixels_shaded
    );
}

#[test]
fn a_tile_its_first_primitive_covers_is_drawn_as_if_cleared() {
    // A screen-filling opaque square (it owns every tile it covers: no clear, no depth test),
    // a nearer square drawn over it, a farther one it hides, and a square at the far plane's
    // edge (too near the clear depth to own its tiles).
    let scenes: [Vec<Vec<ClipVertex>>; 2] = [
        vec![
            square(-1.0, -1.0, 1.0, 1.0, 0.0).to_vec(),
            square(-0.3, -0.5, 0.4, 0.8, -0.6).to_vec(),
            square(-0.8, -0.8, 0.7, 0.6, 0.4).to_vec(),
        ],
        vec![square(-1.0, -1.0, 1.0, 1.0, 0.99999).to_vec()],
    ];
    let indices: Vec<u32> = (0..6).collect();
    let run = |draws: &[Vec<ClipVertex>], owner: bool| {
        let calls: Vec<DrawCall> = draws
            .iter()
            .enumerate()
            .map(|(k, v)| DrawCall {
                vertices: v,
                indices: &indices,
                state: DrawState {
                    keeps_all: owner && k == 0,
                    ..Default::default()
                },
            })
            .collect();
        pipeline::draw(&calls, &ByDraw, &target(200, 150, 1)).0
    };
    let bits = |c: &[Vec4]| {
        c.iter()
            .flat_map(|v| v.to_array().map(f32::to_bits))
            .collect::<Vec<_>>()
    };
    // Tiles are drawn in per-thread buffers kept across frames: a frame of other colours and
    // nearer depths first leaves them full of what an owned tile must not show.
    let stale = vec![square(-1.0, -1.0, 1.0, 1.0, -0.9).to_vec(); 4];
    for draws in &scenes {
        run(&stale, false);
        let owned = run(draws, true);
        run(&stale, false);
        let cleared = run(draws, false);
        assert_eq!(bits(&owned), bits(&cleared));
    }
    // The nearer square shows over the screen-filling one; the farther one nowhere.
    let owned = run(&scenes[0], true);
    assert!(owned.iter().any(|c| c.x == 2.0));
    assert!(owned.iter().all(|c| c.x == 1.0 || c.x == 2.0));
}
