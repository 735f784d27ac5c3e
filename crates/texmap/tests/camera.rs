//! Cameras: orthographic projection through every path that uses the camera (rasterized
//! coverage, lighting's view vector, flat shading's facing, glTF and TOML cameras, volume
//! rays, slices and the mesh-distance pass).
//!
//! Geometry is chosen so edges fall on pixel boundaries, never on pixel centres: coverage is
//! then exact, and the tests compare pixel sets without tolerance.

use std::path::PathBuf;

use glam::{Mat4, Vec3, Vec4};
use texmap::camera::{Camera, CameraProjection};
use texmap::metrics::compare_rgb8;
use texmap::render::{render, surface_distances, Frame, Settings, ShadingMode};
use texmap::scene::primitives::Primitive;
use texmap::scene::{self, Light, LoadOptions, Material, Mesh, Scene};
use texmap::volume::{raymarch, render_slices, MarchParams, Mode, TransferFunction, Volume};

fn ortho(eye: Vec3, target: Vec3, half_height: f32) -> Camera {
    Camera {
        eye,
        target,
        up: Vec3::Y,
        projection: CameraProjection::Orthographic { half_height },
        near: 0.0,
        far: 20.0,
    }
}

fn unlit_white() -> Material {
    Material {
        unlit: true,
        ..Material::default()
    }
}

fn cube_at(size: f32, centre: Vec3) -> Mesh {
    let mut m = Primitive::Cube { size }.mesh(0);
    m.world_from_object = Mat4::from_translation(centre);
    m
}

fn settings(width: u32, height: u32) -> Settings {
    Settings::new(width, height)
}

/// The pixels showing the (white, unlit) surfaces over the black background, row-major.
fn covered(f: &Frame) -> Vec<bool> {
    f.color.iter().map(|c| c.x > 0.5).collect()
}

/// A row-major mask of the union of pixel rectangles `[x0, x1) × [y0, y1)`.
fn rects(w: u32, h: u32, r: &[[u32; 4]]) -> Vec<bool> {
    (0..w * h)
        .map(|i| {
            let (x, y) = (i % w, i / w);
            r.iter()
                .any(|&[x0, y0, x1, y1]| x >= x0 && x < x1 && y >= y0 && y < y1)
        })
        .collect()
}

fn assert_mask_eq(got: &[bool], want: &[bool], w: u32) {
    let wrong: Vec<(usize, usize)> = got
        .iter()
        .zip(want)
        .enumerate()
        .filter(|(_, (a, b))| a != b)
        .map(|(i, _)| (i % w as usize, i / w as usize))
        .collect();
    assert!(
        wrong.is_empty(),
        "{} pixels differ, first {:?}",
        wrong.len(),
        &wrong[..wrong.len().min(8)]
    );
}

#[test]
fn orthographic_cubes_cover_their_size_whatever_their_depth() {
    // 96×64 pixels over a visible height of 4: 1/16 world unit per pixel, x ∈ [−3, 3],
    // y ∈ [−2, 2]. Two unit cubes, 4 units apart in depth, seen face on.
    let scene = Scene {
        meshes: vec![
            cube_at(1.0, Vec3::new(-1.5, 0.5, 0.0)),
            cube_at(1.0, Vec3::new(1.5, -0.5, -4.0)),
        ],
        materials: vec![unlit_white()],
        ..Scene::default()
    };
    let cam = ortho(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, 2.0);
    let f = render(&scene, &cam, &settings(96, 64)).unwrap();
    // Near cube: x ∈ [−2, −1] → columns 16..32, y ∈ [0, 1] → rows 16..32; far cube: x ∈ [1, 2]
    // → columns 64..80, y ∈ [−1, 0] → rows 32..48.
    let want = rects(96, 64, &[[16, 16, 32, 32], [64, 32, 80, 48]]);
    assert_mask_eq(&covered(&f), &want, 96);
    // A perspective camera at the same place shows the near cube larger than the far one.
    let persp = Camera {
        projection: CameraProjection::Perspective { fov_y_deg: 45.0 },
        near: 0.1,
        ..cam
    };
    let f = render(&scene, &persp, &settings(96, 64)).unwrap();
    let (left, right) =
        covered(&f)
            .iter()
            .enumerate()
            .filter(|(_, &c)| c)
            .fold(
                (0, 0),
                |(l, r), (i, _)| {
                    if i % 96 < 48 {
                        (l + 1, r)
                    } else {
                        (l, r + 1)
                    }
                },
            );
    assert!(left > 2 * right, "{left} vs {right}");
}

#[test]
fn orthographic_turntable_keeps_the_projection_and_the_size() {
    let scene = Scene {
        meshes: vec![cube_at(2.0, Vec3::ZERO)],
        materials: vec![unlit_white()],
        ..Scene::default()
    };
    let cam = ortho(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, 2.0);
    // A quarter turn looks at another face of the cube: the same square.
    let turned = cam.orbit(std::f32::consts::FRAC_PI_2);
    assert_eq!(turned.projection, cam.projection);
    let f = render(&scene, &turned, &settings(64, 64)).unwrap();
    let mask = covered(&f);
    let n = mask.iter().filter(|&&c| c).count();
    // 32×32 up to the rounding of the rotated eye (a pixel row at most).
    assert!((32 * 31..=32 * 33).contains(&n), "{n} pixels");
}

#[test]
fn orthographic_specular_is_the_same_all_over_a_plane() {
    // A plane under a directional light: with parallel view rays V is constant, so Phong's
    // specular term is too; seen in perspective it varies across the plane.
    let plane = Primitive::Plane {
        width: 4.0,
        depth: 4.0,
        divisions: 4,
    }
    .mesh(0);
    let scene = Scene {
        meshes: vec![plane],
        materials: vec![Material {
            specular: 1.0,
            shininess: 8.0,
            ..Material::default()
        }],
        lights: vec![Light::Directional {
            direction: Vec3::new(0.0, 1.0, 1.0).normalize(),
            color: Vec3::ONE,
        }],
        ambient_light: Vec3::ZERO,
        ..Scene::default()
    };
    // The view direction is the mirror image of the light's about the plane's normal.
    let eye = Vec3::new(0.0, 3.0, -3.0);
    let spread = |cam: &Camera| {
        let f = render(&scene, cam, &settings(64, 64)).unwrap();
        let lit: Vec<f32> = f.color.iter().filter(|c| c.w > 0.0).map(|c| c.x).collect();
        assert!(lit.len() > 1000, "{} pixels", lit.len());
        let lo = lit.iter().copied().fold(f32::INFINITY, f32::min);
        let hi = lit.iter().copied().fold(0.0f32, f32::max);
        (lo, hi)
    };
    let (lo, hi) = spread(&ortho(eye, Vec3::ZERO, 1.0));
    assert!(hi - lo < 1e-4, "{lo} .. {hi}");
    // V along the mirror direction of L: the peak, diffuse 0.8·cos 45° + specular 1.
    assert!((lo - (0.8 * 0.5f32.sqrt() + 1.0)).abs() < 1e-3, "{lo}");
    let persp = Camera {
        projection: CameraProjection::Perspective { fov_y_deg: 40.0 },
        near: 0.1,
        ..ortho(eye, Vec3::ZERO, 1.0)
    };
    let (lo, hi) = spread(&persp);
    assert!(hi - lo > 0.05, "{lo} .. {hi}");
}

#[test]
fn orthographic_flat_shading_faces_by_the_view_direction() {
    // A double-sided square 10 units to the right of the eye, its front side facing +x and
    // +z at 45°. The eye point lies behind its plane, but with parallel rays along −z the
    // front side faces the camera. The light is on the front side.
    let n = Vec3::new(1.0, 0.0, 1.0).normalize();
    let (t, b) = (Vec3::Y * 2.0, n.cross(Vec3::Y) * 2.0);
    let c = Vec3::new(10.0, 0.0, 0.0);
    let quad = Mesh {
        positions: vec![c - t - b, c - t + b, c + t + b, c + t - b],
        indices: vec![0, 2, 1, 0, 3, 2],
        ..Mesh::default()
    };
    // Counter-clockwise seen from the front side; the eye (0, 0, 5) is behind the plane.
    let p = &quad.positions;
    assert!((p[2] - p[0]).cross(p[1] - p[0]).dot(n) > 0.0);
    let eye = Vec3::new(0.0, 0.0, 5.0);
    assert!(n.dot(eye - c) < 0.0);
    let scene = Scene {
        meshes: vec![quad],
        materials: vec![Material {
            double_sided: true,
            ambient: 0.0,
            ..Material::default()
        }],
        lights: vec![Light::Directional {
            direction: n,
            color: Vec3::ONE,
        }],
        ..Scene::default()
    };
    // 128×32 over a half-height of 3: x ∈ [−12, 12]; pixel (117, 16) is at (10.03, −0.09).
    let cam = ortho(eye, Vec3::ZERO, 3.0);
    for shading in [ShadingMode::Flat, ShadingMode::Phong] {
        let s = settings(128, 32).with_shading(shading);
        let f = render(&scene, &cam, &s).unwrap();
        let px = f.color[16 * 128 + 117];
        assert!(px.w > 0.0, "{shading:?}: not drawn");
        assert!((px.x - 0.8).abs() < 1e-3, "{shading:?}: {px}");
    }
}

fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("texmap-camera-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn gltf_orthographic_camera_loads_and_frames_the_view() {
    // A 2×2 square at the origin, and an orthographic camera (ymag 2, xmag 1: the image's
    // aspect wins) on a node at z = 5; a perspective camera after it is not the first.
    let mut bin = Vec::new();
    for p in [
        [-1.0f32, -1.0, 0.0],
        [1.0, -1.0, 0.0],
        [1.0, 1.0, 0.0],
        [-1.0, 1.0, 0.0],
    ] {
        p.iter()
            .for_each(|v| bin.extend_from_slice(&v.to_le_bytes()));
    }
    for i in [0u16, 1, 2, 0, 2, 3] {
        bin.extend_from_slice(&i.to_le_bytes());
    }
    let json = r#"{"asset": {"version": "2.0"},
  "scene": 0, "scenes": [{"nodes": [0, 1, 2]}],
  "nodes": [{"mesh": 0}, {"camera": 0, "translation": [0, 0, 5]}, {"camera": 1, "translation": [0, 0, 9]}],
  "cameras": [{"type": "orthographic", "orthographic": {"xmag": 1, "ymag": 2, "znear": 0, "zfar": 10}},
              {"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1}}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1,
      "material": 0}]}],
  "materials": [{"extensions": {"KHR_materials_unlit": {}}}],
  "extensionsUsed": ["KHR_materials_unlit"],
  "buffers": [{"byteLength": 60, "uri": "quad.bin"}],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48},
                  {"buffer": 0, "byteOffset": 48, "byteLength": 12}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
                 "min": [-1, -1, 0], "max": [1, 1, 0]},
                {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"}]}"#;
    let d = temp_dir("gltf");
    std::fs::write(d.join("quad.bin"), &bin).unwrap();
    let path = d.join("ortho.gltf");
    std::fs::write(&path, json).unwrap();
    let loaded = scene::load(&path, &LoadOptions::default()).unwrap();
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    assert_eq!(loaded.cameras.len(), 2);
    let cam = loaded.scene.camera.unwrap();
    assert_eq!(
        cam.projection,
        CameraProjection::Orthographic { half_height: 2.0 }
    );
    assert_eq!(
        (cam.eye, cam.near, cam.far),
        (Vec3::new(0.0, 0.0, 5.0), 0.0, 10.0)
    );
    assert!(loaded.cameras[1].projection.fov_y_deg().is_some());
    // 96×64: 1/16 unit per pixel; the square spans columns 32..64 and rows 16..48.
    let f = render(&loaded.scene, &cam, &settings(96, 64)).unwrap();
    assert_mask_eq(&covered(&f), &rects(96, 64, &[[32, 16, 64, 48]]), 96);
}

#[test]
fn framing_camera_orthographic_fits_the_bounding_sphere() {
    let scene = Scene {
        meshes: vec![cube_at(2.0, Vec3::new(1.0, 2.0, 3.0))],
        materials: vec![unlit_white()],
        ..Scene::default()
    };
    let cam = scene.framing_camera_orthographic();
    let persp = scene.framing_camera(60.0);
    assert_eq!((cam.eye, cam.target), (persp.eye, persp.target));
    let r = 3.0f32.sqrt();
    match cam.projection {
        CameraProjection::Orthographic { half_height } => {
            assert!((half_height - 1.1 * r).abs() < 1e-5, "{half_height}")
        }
        p => panic!("{p:?}"),
    }
    // The cube's face (2 units) fills 2 / (2.2·√3) of the height: 33.6 of 64 rows.
    let f = render(&scene, &cam, &settings(64, 64)).unwrap();
    let rows = (0..64)
        .filter(|y| (0..64).any(|x| f.color[y * 64 + x].w > 0.0))
        .count();
    assert!((33..=34).contains(&rows), "{rows} rows");
}

// ---- volumes -------------------------------------------------------------------------------

fn sphere_volume(n: u32, r: f32) -> Volume {
    let c = (n - 1) as f32 * 0.5;
    let mut v = Vec::with_capacity((n * n * n) as usize);
    for z in 0..n {
        for y in 0..n {
            for x in 0..n {
                let d = Vec3::new(x as f32 - c, y as f32 - c, z as f32 - c).length();
                v.push((r - d + 0.5).clamp(0.0, 1.0));
            }
        }
    }
    Volume::from_scalars([n; 3], Mat4::IDENTITY, v).unwrap()
}

#[test]
fn orthographic_mip_of_a_sphere_is_a_disk_whatever_the_distance() {
    let (n, r) = (48, 15.0);
    let vol = sphere_volume(n, r);
    let tf = TransferFunction::parse("0:1,1,1,1;1:1,1,1,1").unwrap();
    let c = Vec3::splat((n - 1) as f32 * 0.5);
    let params = MarchParams {
        mode: Mode::Mip,
        step: 0.1,
        jitter: false,
        ..MarchParams::default()
    };
    let size = 100;
    // 25 world units of half-height over 50 pixels: a radius of 15 is 30 pixels.
    for dist in [40.0, 400.0] {
        let cam = Camera {
            up: Vec3::Z,
            far: 1000.0,
            ..ortho(c - Vec3::Y * dist, c, 25.0)
        };
        let f = raymarch(&vol, &tf, &cam, size, size, &params, None).unwrap();
        let area = f.to_srgb8().chunks_exact(3).filter(|p| p[0] >= 128).count() as f64;
        let radius = (area / std::f64::consts::PI).sqrt();
        assert!(
            (radius - 30.0).abs() < 1.0,
            "distance {dist}: {radius:.2} px"
        );
    }
}

#[test]
fn orthographic_slices_agree_with_rays() {
    let n = 48;
    let c = (n - 1) as f32 * 0.5;
    let mut v = Vec::new();
    for z in 0..n {
        for y in 0..n {
            for x in 0..n {
                let d = Vec3::new(x as f32 - c, y as f32 - c, z as f32 - c).length();
                v.push((150.0 * (1.0 - d / 22.0)).max(0.0) + 20.0 * (x as f32 * 0.3).sin());
            }
        }
    }
    let vol = Volume::from_scalars([n; 3], Mat4::IDENTITY, v).unwrap();
    let tf =
        TransferFunction::parse("0:0,0,0,0;40:0.8,0.4,0.3,0;100:0.9,0.7,0.4,0.08;170:1,1,1,0.4")
            .unwrap();
    let centre = Vec3::splat(c);
    let cam = Camera {
        up: Vec3::Z,
        far: 500.0,
        ..ortho(centre + Vec3::new(30.0, -60.0, 20.0), centre, 30.0)
    };
    let p = MarchParams {
        step: 0.5,
        jitter: false,
        ..MarchParams::default()
    };
    let rays = raymarch(&vol, &tf, &cam, 80, 64, &p, None).unwrap();
    let slices = render_slices(&vol, &tf, &cam, 80, 64, &p).unwrap();
    let db = compare_rgb8(&rays.to_srgb8(), &slices.to_srgb8(), 80, 64, None).psnr_db;
    assert!(db >= 45.0, "{db:.2} dB");
    let opaque: f32 = rays.color.iter().map(|c| c.w).sum();
    assert!(opaque > 100.0, "the volume is visible: {opaque}");
}

#[test]
fn orthographic_surface_distances_are_measured_along_the_view_direction() {
    // A square facing the camera at depth 7 from the eye's plane: every covered pixel's ray
    // meets it after 7 units, however far from the axis.
    let quad = Mesh {
        positions: vec![
            Vec3::new(-1.0, -1.0, -2.0),
            Vec3::new(1.0, -1.0, -2.0),
            Vec3::new(1.0, 1.0, -2.0),
            Vec3::new(-1.0, 1.0, -2.0),
        ],
        indices: vec![0, 1, 2, 0, 2, 3],
        ..Mesh::default()
    };
    let scene = Scene {
        meshes: vec![quad],
        materials: vec![Material::default()],
        ..Scene::default()
    };
    let cam = ortho(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, 2.0);
    let d = surface_distances(&scene, &cam, 32, 32).unwrap();
    let hit: Vec<f32> = d.iter().copied().filter(|x| x.is_finite()).collect();
    assert_eq!(hit.len(), 16 * 16);
    assert!(hit.iter().all(|&x| (x - 7.0).abs() < 1e-4), "{hit:?}");
    // And the window depth of the pipeline converts back the same way.
    let clip = cam.clip_from_view(1.0) * cam.view_from_world();
    let p = clip * Vec4::new(0.9, -0.9, -2.0, 1.0);
    let z = p.z / p.w * 0.5 + 0.5;
    let back = texmap::volume::ray_distances_from_depth(&cam, 1, 1, &[z]);
    assert!((back[0] - 7.0).abs() < 1e-4, "{}", back[0]);
}

#[test]
fn orthographic_rays_and_slices_stop_at_a_surface_alike() {
    // A translucent ball with an opaque square through its middle plane y = 0 over the left
    // half, seen with parallel rays along +y: both methods stop at the square and agree.
    use texmap::render::render_with_volumes;
    use texmap::volume::{Method, SceneVolume};
    let mut sv = SceneVolume::new(sphere_volume(48, 20.0), std::path::Path::new("ball"));
    sv.transfer = TransferFunction::parse("0:1,0.8,0.6,0.02;1:1,0.8,0.6,0.05").unwrap();
    sv.params.jitter = false;
    sv.place(Mat4::from_translation(Vec3::splat(-23.5)), false)
        .unwrap();
    let square = Mesh {
        positions: vec![
            Vec3::new(-30.0, 0.0, -30.0),
            Vec3::new(0.0, 0.0, -30.0),
            Vec3::new(0.0, 0.0, 30.0),
            Vec3::new(-30.0, 0.0, 30.0),
        ],
        indices: vec![0, 1, 2, 0, 2, 3],
        ..Mesh::default()
    };
    let scene = Scene {
        meshes: vec![square],
        materials: vec![Material {
            base_color: Vec4::new(0.1, 0.2, 0.9, 1.0),
            unlit: true,
            ..Material::default()
        }],
        ..Scene::default()
    };
    let cam = Camera {
        up: Vec3::Z,
        far: 200.0,
        ..ortho(Vec3::new(0.0, -80.0, 0.0), Vec3::ZERO, 30.0)
    };
    let s = settings(64, 64);
    let rays = render_with_volumes(&scene, std::slice::from_ref(&sv), &cam, &s).unwrap();
    sv.method = Method::Slices;
    let slices = render_with_volumes(&scene, std::slice::from_ref(&sv), &cam, &s).unwrap();
    let db = compare_rgb8(&rays.to_srgb8(), &slices.to_srgb8(), 64, 64, None).psnr_db;
    assert!(db >= 45.0, "{db:.2} dB");
    // Pixel (16, 32) meets the square at x = −15 behind the ball's front half: blue under a
    // veil; pixel (48, 32) sees through the whole ball, no square.
    let (l, r) = (rays.color[32 * 64 + 16], rays.color[32 * 64 + 48]);
    assert!(l.z > l.x && l.w > 0.99, "{l}");
    assert!(r.x > r.z, "{r}");
}
