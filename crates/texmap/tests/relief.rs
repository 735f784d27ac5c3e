//! Surface relief: object- and tangent-space normal maps agree, the bump's sign matches the
//! normal map of the same heights, parallax occlusion mapping at a grazing angle matches the
//! displaced mesh of the same height map (stated PSNR), displacement leaves no cracks
//! (watertight counts as in `pipeline.rs`) and refuses a tessellation over the budget.

use std::f32::consts::TAU;
use std::sync::Arc;

use glam::{Mat4, Vec2, Vec3, Vec4};
use texmap::camera::{Camera, CameraProjection};
use texmap::metrics::compare_rgb8;
use texmap::pipeline::{
    self, ClipVertex, CullMode, DrawCall, DrawState, FragmentShader, Interpolation, Quad, Target,
    MAX_VARYINGS,
};
use texmap::render::{render, Frame, Settings};
use texmap::scene::displace::{displace_scene, DisplaceOptions};
use texmap::scene::primitives::Primitive;
use texmap::scene::{tangents, Light, Material, Mesh, Scene, TextureSlot};
use texmap::shading::relief::{Displacement, Parallax, ParallaxMode, Tessellation};
use texmap::shading::{MapChannel, MaterialMap};
use texmap::texture::{Filter, Sampler, Texture2D, TextureOptions, Wrap};

const N: u32 = 128;

/// Domes: 4 × 4 per tile, height 1 at their tops, 0 between.
fn dome(u: f32, v: f32) -> f32 {
    (0.5 - 0.5 * (TAU * 4.0 * u).cos()) * (0.5 - 0.5 * (TAU * 4.0 * v).cos())
}

/// ∂h/∂u, ∂h/∂v of [`dome`].
fn dome_gradient(u: f32, v: f32) -> Vec2 {
    let (a, b) = (TAU * 4.0 * u, TAU * 4.0 * v);
    let k = 0.5 * TAU * 4.0;
    Vec2::new(
        k * a.sin() * (0.5 - 0.5 * b.cos()),
        k * b.sin() * (0.5 - 0.5 * a.cos()),
    )
}

fn texture(f: impl Fn(f32, f32) -> Vec4) -> Arc<Texture2D> {
    Arc::new(
        Texture2D::from_fn(N, N, TextureOptions::default(), |x, y| {
            f((x as f32 + 0.5) / N as f32, (y as f32 + 0.5) / N as f32)
        })
        .unwrap(),
    )
}

fn slot(t: Arc<Texture2D>) -> TextureSlot {
    TextureSlot::new(t, Sampler::new(Filter::TRILINEAR, Wrap::Repeat))
}

fn heights() -> TextureSlot {
    slot(texture(|u, v| Vec4::new(dome(u, v), 0.0, 0.0, 1.0)))
}

fn light() -> Vec3 {
    Vec3::new(0.3, 0.8, 0.5).normalize()
}

/// A 2 × 2 plane (uv 0..1, u along +x, v along +z) with tangents, under `transform`.
fn plane(divisions: u32, transform: Mat4) -> Mesh {
    let mut m = Primitive::Plane {
        width: 2.0,
        depth: 2.0,
        divisions,
    }
    .mesh(0);
    assert!(tangents::generate(&mut m, 0));
    m.world_from_object = transform;
    m
}

fn scene(mesh: Mesh, material: Material) -> Scene {
    Scene {
        meshes: vec![mesh],
        materials: vec![material],
        lights: vec![Light::Directional {
            direction: light(),
            color: Vec3::ONE,
        }],
        ambient_light: Vec3::ONE,
        background: Vec4::new(0.0, 0.0, 0.0, 1.0),
        ..Scene::default()
    }
}

fn camera(eye: Vec3, target: Vec3, up: Vec3) -> Camera {
    Camera {
        eye,
        target,
        up,
        projection: CameraProjection::Perspective { fov_y_deg: 40.0 },
        near: 0.05,
        far: 100.0,
    }
}

fn shot(s: &Scene, c: &Camera, w: u32, h: u32) -> Frame {
    render(s, c, &Settings::new(w, h)).unwrap()
}

fn dump(name: &str, f: &Frame) {
    if std::env::var_os("RELIEF_DUMP").is_some() {
        image::RgbImage::from_raw(f.width, f.height, f.to_srgb8())
            .unwrap()
            .save(format!("/tmp/rl/{name}.png"))
            .unwrap();
    }
}

fn psnr(a: &Frame, b: &Frame) -> f64 {
    let (w, h) = (a.width as usize, a.height as usize);
    compare_rgb8(&a.to_srgb8(), &b.to_srgb8(), w, h, None).psnr_db
}

fn lit(maps: Vec<MaterialMap>) -> Material {
    Material {
        base_color: Vec4::new(0.8, 0.5, 0.3, 1.0),
        specular: 0.3,
        shininess: 20.0,
        maps,
        ..Default::default()
    }
}

fn map(channel: MapChannel, slot: TextureSlot) -> MaterialMap {
    MaterialMap {
        channel,
        slot,
        scale: 1.0,
    }
}

/// The tangent-space normal of heights `k·dome` on the plane (one uv unit = 2 object units).
fn dome_normal(u: f32, v: f32, k: f32) -> Vec3 {
    let g = dome_gradient(u, v) * (k / 2.0);
    Vec3::new(-g.x, -g.y, 1.0).normalize()
}

fn encode(n: Vec3) -> Vec4 {
    (n * 0.5 + 0.5).extend(1.0)
}

#[test]
fn object_space_and_tangent_space_normal_maps_agree_on_a_rotated_plane() {
    let transform = Mat4::from_rotation_y(0.7) * Mat4::from_rotation_x(0.5);
    let mesh = plane(4, transform);
    // The plane's tangent frame (one for the whole plane), object space.
    let t = mesh.tangents[0];
    let n = mesh.normals[0];
    let tt = t.truncate();
    let b = n.cross(tt) * t.w.signum();
    let k = 0.15;
    let tangent_map = slot(texture(|u, v| encode(dome_normal(u, v, k))));
    let object_map = slot(texture(|u, v| {
        let ts = dome_normal(u, v, k);
        encode((tt * ts.x + b * ts.y + n * ts.z).normalize())
    }));
    let cam = camera(
        transform.transform_point3(Vec3::new(0.2, 2.2, 0.4)),
        Vec3::ZERO,
        Vec3::Y,
    );
    let a = shot(
        &scene(
            mesh.clone(),
            lit(vec![map(MapChannel::Normal, tangent_map)]),
        ),
        &cam,
        160,
        120,
    );
    let o = shot(
        &scene(
            mesh.clone(),
            lit(vec![map(MapChannel::NormalObject, object_map)]),
        ),
        &cam,
        160,
        120,
    );
    let flat = shot(&scene(mesh, lit(vec![])), &cam, 160, 120);
    let agree = psnr(&a, &o);
    let differ = psnr(&a, &flat);
    eprintln!("tangent vs object space: {agree:.2} dB; tangent vs no map: {differ:.2} dB");
    assert!(
        agree >= 40.0,
        "tangent vs object space {agree:.2} dB < 40 dB"
    );
    assert!(
        differ < 30.0,
        "the maps must change the image ({differ:.2} dB)"
    );
}

#[test]
fn the_bump_sign_matches_the_normal_map_of_the_same_heights() {
    let k = 0.15;
    let mesh = plane(4, Mat4::IDENTITY);
    let bump = MaterialMap {
        scale: k,
        ..map(MapChannel::Bump, heights())
    };
    let normal = map(
        MapChannel::Normal,
        slot(texture(|u, v| encode(dome_normal(u, v, k)))),
    );
    // Top-down: screen right is +x, screen down is +z.
    let cam = camera(Vec3::new(0.0, 2.0, 0.0), Vec3::ZERO, Vec3::NEG_Z);
    let (w, h) = (192, 192);
    let fb = shot(&scene(mesh.clone(), lit(vec![bump])), &cam, w, h);
    let fnm = shot(&scene(mesh, lit(vec![normal])), &cam, w, h);
    let agree = psnr(&fb, &fnm);
    eprintln!("bump vs normal map of the same heights: {agree:.2} dB");
    assert!(agree >= 30.0, "bump vs normal map {agree:.2} dB < 30 dB");
    // The dome at u = v = 5/8 (x = z = 0.25): its slope facing the light (+x side, u = 11/16)
    // is brighter than the one facing away (u = 9/16).
    let clip = cam.clip_from_view(1.0) * cam.view_from_world();
    let px = |p: Vec3| {
        let c = clip * p.extend(1.0);
        let s = (Vec2::new(c.x, -c.y) / c.w * 0.5 + 0.5) * w as f32;
        fb.color[(s.y as u32 * w + s.x as u32) as usize]
            .truncate()
            .length()
    };
    let lit_side = px(Vec3::new(0.375, 0.0, 0.25));
    let dark_side = px(Vec3::new(0.125, 0.0, 0.25));
    assert!(
        lit_side > dark_side + 0.05,
        "slope towards the light {lit_side} vs away {dark_side}"
    );
}

/// Lit by the ambient term alone (K_A = 1, K_D = K_S = 0): the colour is the texture, so the
/// comparison measures where each pixel reads the texture, not the shading.
fn ambient_only(extra: impl FnOnce(&mut Material)) -> Material {
    let stripes = slot(texture(|u, v| {
        let s = 0.5 + 0.5 * (TAU * 16.0 * u).sin() * (TAU * 8.0 * v).cos();
        Vec4::new(s, 0.3 + 0.4 * u, 1.0 - s, 1.0)
    }));
    let mut m = Material {
        ambient: 1.0,
        diffuse: 0.0,
        specular: 0.0,
        base_color_texture: Some(stripes),
        ..Default::default()
    };
    extra(&mut m);
    m
}

/// PSNR over the rows from `from` down (below the far edge, whose silhouette only the
/// displaced mesh changes).
fn psnr_below(a: &Frame, b: &Frame, from: u32) -> f64 {
    let (w, h) = (a.width as usize, a.height as usize);
    let mask: Vec<bool> = (0..w * h).map(|i| i / w >= from as usize).collect();
    compare_rgb8(&a.to_srgb8(), &b.to_srgb8(), w, h, Some(&mask)).psnr_db
}

#[test]
fn parallax_occlusion_at_a_grazing_angle_matches_the_displaced_mesh() {
    // An 8 × 8 plane (the 2 × 2 one scaled by 4), the height map repeated 4 times across,
    // relief 0.03 object units = 0.12 world units, seen 12° above its surface.
    let scale = 0.03;
    let transform = Mat4::from_scale(Vec3::splat(4.0));
    let cam = camera(
        Vec3::new(0.1, 0.45, 2.0),
        Vec3::new(0.0, 0.0, -0.2),
        Vec3::Y,
    );
    let (w, h) = (240, 160);
    let tiled = || TextureSlot {
        uv_scale: 4.0,
        ..heights()
    };
    // The displaced plane: carved in (base 1), each of 32 triangles cut 128 × 128.
    let mut displaced = scene(
        plane(4, transform),
        ambient_only(|m| {
            m.displacement = Some(Box::new(Displacement {
                slot: tiled(),
                scale,
                base: 1.0,
                tessellation: Tessellation::Level(7),
            }));
        }),
    );
    displace_scene(&mut displaced, &DisplaceOptions::default(), None).unwrap();
    let reference = shot(&displaced, &cam, w, h);
    dump("ref", &reference);
    let with = |mode: Option<ParallaxMode>| {
        let m = ambient_only(|m| {
            m.parallax = mode.map(|mode| {
                Box::new(Parallax {
                    slot: tiled(),
                    mode,
                    scale,
                    base: 1.0,
                    min_steps: 16,
                    max_steps: 64,
                    shadows: false,
                })
            });
        });
        let f = shot(&scene(plane(4, transform), m), &cam, w, h);
        dump(&format!("{mode:?}"), &f);
        f
    };
    let from = h / 3;
    let pom = psnr_below(&with(Some(ParallaxMode::Occlusion)), &reference, from);
    let offset = psnr_below(&with(Some(ParallaxMode::Offset)), &reference, from);
    let none = psnr_below(&with(None), &reference, from);
    eprintln!(
        "against the displaced mesh: occlusion {pom:.2} dB, offset {offset:.2} dB, none {none:.2} dB"
    );
    assert!(pom >= 20.0, "parallax occlusion {pom:.2} dB < 20 dB");
    assert!(
        pom > none + 3.0,
        "occlusion {pom:.2} dB must beat none {none:.2} dB by 3 dB"
    );
    assert!(
        offset > none,
        "offset {offset:.2} dB must beat none {none:.2} dB"
    );
}

#[test]
fn parallax_self_shadowing_darkens_the_pit_behind_a_wall_and_nothing_under_a_light_overhead() {
    // A step in the height map: the left half (u < ½, x < 0) at the top, the right half a pit
    // 0.1 deep (carved in, base 1). Seen from straight above (orthographic, x to the right).
    let step = slot(texture(|u, _| {
        Vec4::new(if u < 0.5 { 1.0 } else { 0.0 }, 0.0, 0.0, 1.0)
    }));
    let cam = Camera {
        eye: Vec3::new(0.0, 4.0, 0.0),
        target: Vec3::ZERO,
        up: -Vec3::Z,
        projection: CameraProjection::Orthographic { half_height: 1.0 },
        near: 0.1,
        far: 10.0,
    };
    let (w, h) = (128u32, 64u32);
    let shot_with = |towards_light: Vec3, shadows: bool| {
        let material = Material {
            base_color: Vec4::ONE,
            ambient: 0.0,
            specular: 0.0,
            parallax: Some(Box::new(Parallax {
                slot: step.clone(),
                mode: ParallaxMode::Occlusion,
                scale: 0.1,
                base: 1.0,
                min_steps: 16,
                max_steps: 32,
                shadows,
            })),
            ..Default::default()
        };
        let mut s = scene(plane(1, Mat4::IDENTITY), material);
        s.lights = vec![Light::Directional {
            direction: towards_light.normalize(),
            color: Vec3::ONE,
        }];
        shot(&s, &cam, w, h)
    };
    // Pixel column of world x, middle row.
    let at = |f: &Frame, x: f32| {
        let i = (((x + 2.0) / 4.0) * w as f32) as u32;
        f.color[((h / 2) * w + i) as usize].x
    };
    // A low light from −x (tan of its elevation 0.3): the wall at x = 0 shadows the pit out
    // to x ≈ 0.1 / 0.3 = 0.33.
    let low = Vec3::new(-1.0, 0.3, 0.0);
    let (on, off) = (shot_with(low, true), shot_with(low, false));
    let near_wall = 0.12;
    eprintln!(
        "pit near the wall: {:.3} shadowed, {:.3} without; far: {:.3} / {:.3}; top {:.3} / {:.3}",
        at(&on, near_wall),
        at(&off, near_wall),
        at(&on, 0.8),
        at(&off, 0.8),
        at(&on, -0.5),
        at(&off, -0.5)
    );
    assert!(at(&off, near_wall) > 0.2, "lit without shadows");
    assert!(
        at(&on, near_wall) < 0.25 * at(&off, near_wall),
        "the wall shadows the pit"
    );
    for x in [0.8, -0.5] {
        assert!(
            (at(&on, x) - at(&off, x)).abs() < 1e-3,
            "x {x}: nothing stands between it and the light"
        );
    }
    // A light straight above: the march stays over its own texel, nothing is shadowed.
    let (on, off) = (shot_with(Vec3::Y, true), shot_with(Vec3::Y, false));
    assert_eq!(on.color, off.color);
}

// ---- cracks --------------------------------------------------------------------------------

/// Adds (1, 0, 0, 0) per covered sample: with premultiplied "over" and alpha 0 this counts.
struct Count;
impl FragmentShader for Count {
    fn shade(&self, _: u32, q: &Quad, out: &mut [Vec4; 4]) -> u8 {
        *out = [Vec4::new(1.0, 0.0, 0.0, 0.0); 4];
        q.mask
    }
}

fn count_hits(mesh: &Mesh, cam: &Camera, w: u32, h: u32, cull: CullMode) -> Vec<f32> {
    let clip = cam.clip_from_view(w as f32 / h as f32) * cam.view_from_world();
    let verts: Vec<ClipVertex> = mesh
        .positions
        .iter()
        .map(|p| ClipVertex {
            clip: clip * mesh.world_from_object * p.extend(1.0),
            varyings: [0.0; MAX_VARYINGS],
        })
        .collect();
    let call = DrawCall {
        vertices: &verts,
        indices: &mesh.indices,
        state: DrawState {
            cull,
            depth_test: false,
            depth_write: false,
            blend: true,
            ..Default::default()
        },
    };
    let target = Target {
        width: w,
        height: h,
        samples: 1,
        clear_color: Vec4::ZERO,
        interpolation: Interpolation::Perspective,
        depth_sort: false,
    };
    let (color, _) = pipeline::draw(&[call], &Count, &target);
    color.iter().map(|c| c.x).collect()
}

/// Heights that vary around the sphere and vanish towards the poles, continuous across the
/// seam: gentle enough that the displaced surface never folds over itself (a fold's edge
/// may fall on a sample and count once, which would read as a crack).
fn sphere_heights() -> TextureSlot {
    slot(texture(|u, v| {
        let h = 0.5 + 0.5 * (TAU * 3.0 * u).sin() * (std::f32::consts::PI * v).sin().powi(2);
        Vec4::new(h, 0.0, 0.0, 1.0)
    }))
}

fn displaced_sphere(level: u32) -> Scene {
    let sphere = Primitive::Sphere {
        radius: 1.0,
        segments: 24,
        rings: 12,
    }
    .mesh(0);
    let material = Material {
        displacement: Some(Box::new(Displacement {
            slot: sphere_heights(),
            scale: 0.1,
            base: 0.0,
            tessellation: Tessellation::Level(level),
        })),
        ..Default::default()
    };
    scene(sphere, material)
}

#[test]
fn displacement_leaves_no_cracks_across_the_uv_seam_and_the_poles() {
    let mut s = displaced_sphere(3);
    let before = s.meshes[0].triangle_count();
    displace_scene(&mut s, &DisplaceOptions::default(), None).unwrap();
    let mesh = &s.meshes[0];
    assert_eq!(mesh.triangle_count(), before * 64);
    // Inside: every pixel covered exactly once (looking at the seam, u = 0, and a pole).
    for target in [Vec3::new(0.0, 0.0, -1.0), Vec3::new(1.0, 0.2, 0.3), Vec3::Y] {
        let up = if target == Vec3::Y { Vec3::Z } else { Vec3::Y };
        let cam = Camera {
            near: 0.01,
            ..camera(Vec3::new(0.02, -0.03, 0.01), target, up)
        };
        let hits = count_hits(mesh, &cam, 97, 61, CullMode::None);
        let bad = hits.iter().filter(|&&c| c != 1.0).count();
        assert_eq!(bad, 0, "towards {target}: {bad} pixels not covered once");
    }
    // Outside, front faces only: every uncovered pixel joined to the image's border by
    // uncovered pixels (a crack would be an uncovered island; near the limb a bump may hide
    // another front face, so counts of 2 are allowed).
    // (Both sides counted would be 0 or 2 away from the silhouette only: a sample on a
    // silhouette edge is inside exactly one of its two triangles.)
    for eye in [
        Vec3::new(0.3, 0.4, 3.0),
        Vec3::new(-3.0, 0.5, 0.2),
        Vec3::new(0.1, 3.0, 0.2),
    ] {
        let (w, h) = (128usize, 96usize);
        let cam = camera(eye, Vec3::ZERO, Vec3::Y);
        let hits = count_hits(mesh, &cam, w as u32, h as u32, CullMode::Back);
        let mut outside = vec![false; w * h];
        let mut stack: Vec<usize> = (0..w * h)
            .filter(|&i| {
                (i % w == 0 || i % w == w - 1 || i / w == 0 || i / w == h - 1) && hits[i] == 0.0
            })
            .collect();
        while let Some(i) = stack.pop() {
            if outside[i] || hits[i] != 0.0 {
                continue;
            }
            outside[i] = true;
            let (x, y) = (i % w, i / w);
            if x > 0 {
                stack.push(i - 1);
            }
            if x + 1 < w {
                stack.push(i + 1);
            }
            if y > 0 {
                stack.push(i - w);
            }
            if y + 1 < h {
                stack.push(i + w);
            }
        }
        let holes = (0..w * h)
            .filter(|&i| hits[i] == 0.0 && !outside[i])
            .count();
        assert_eq!(
            holes, 0,
            "from {eye}: {holes} uncovered pixels inside the silhouette"
        );
        assert!(hits.iter().filter(|&&c| c >= 1.0).count() > w * h / 8);
    }
    // The vertices moved out by up to the scale (the faces of the 24 × 12 sphere lie up to
    // 2% inside its radius), and the normals and tangents were recomputed.
    let r = mesh.positions.iter().map(|p| p.length());
    let (lo, hi) = r.fold((f32::MAX, 0.0f32), |(a, b), x| (a.min(x), b.max(x)));
    assert!(lo > 0.97 && hi > 1.08 && hi < 1.1, "radii {lo}..{hi}");
    assert_eq!(mesh.normals.len(), mesh.positions.len());
    assert_eq!(mesh.tangents.len(), mesh.positions.len());
}

#[test]
fn a_tessellation_over_the_triangle_budget_is_refused_and_changes_nothing() {
    let mut s = displaced_sphere(10);
    let before = s.meshes[0].triangle_count();
    let e = displace_scene(&mut s, &DisplaceOptions::default(), None)
        .unwrap_err()
        .to_string();
    assert!(e.contains("budget") && e.contains("triangles"), "{e}");
    assert!(!e.contains('\n'), "{e}");
    assert_eq!(s.meshes[0].triangle_count(), before);
    let small = DisplaceOptions {
        tessellation: Some(Tessellation::Level(1)),
        max_triangles: before * 4,
    };
    assert_eq!(displace_scene(&mut s, &small, None).unwrap(), 1);
    assert_eq!(s.meshes[0].triangle_count(), before * 4);
}

// ---- mirrored uvs --------------------------------------------------------------------------

/// Runs of indices where `on` holds, at least `min` long.
fn runs(on: impl Iterator<Item = bool>, min: usize) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut start = None;
    for (i, b) in on.chain(std::iter::once(false)).enumerate() {
        match (b, start) {
            (true, None) => start = Some(i),
            (false, Some(s)) => {
                if i - s >= min {
                    out.push((s, i));
                }
                start = None;
            }
            _ => {}
        }
    }
    out
}

/// glTF's NormalTangentMirrorTest seen head-on under a light from the upper left: each row of
/// each block has a cell of real geometry, then the same relief as a normal map, with its
/// uvs mirrored in v and in u. With tangents handled right (MikkTSpace's sign w for mirrored
/// uvs), the three normal-mapped cells agree with one another and with the geometry.
#[test]
fn normal_maps_on_mirrored_uvs_agree_with_the_unmirrored_and_the_geometry() {
    let assets = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/assets");
    // The cells differ only by the small arrows in their corners: measured 30.0 dB (mirrored vs
    // unmirrored) and 31.5 dB (normal maps vs geometry) at 800×640.
    let path = assets.join("gltf/NormalTangentMirrorTest/glTF-Binary/NormalTangentMirrorTest.glb");
    if !path.is_file() {
        eprintln!("SKIPPED: {} is absent", path.display());
        return;
    }
    let mut loaded = texmap::scene::load(&path, &texmap::scene::LoadOptions::default()).unwrap();
    let s = &mut loaded.scene;
    s.lights = vec![Light::Directional {
        direction: Vec3::new(-0.5, 0.5, 1.0).normalize(),
        color: Vec3::ONE,
    }];
    s.ambient_light = Vec3::splat(0.3);
    s.background = Vec4::new(0.0, 0.0, 0.0, 1.0);
    let cam = Camera {
        eye: Vec3::new(0.0, -0.08, 5.0),
        target: Vec3::new(0.0, -0.08, 0.0),
        up: Vec3::Y,
        projection: CameraProjection::Orthographic { half_height: 1.2 },
        near: 0.1,
        far: 20.0,
    };
    let (w, h) = (800usize, 640usize);
    let f = render(s, &cam, &Settings::new(w as u32, h as u32)).unwrap();
    dump("mirror", &f);
    let rgb = f.to_srgb8();
    let on = |x: usize, y: usize| rgb[(y * w + x) * 3..][..3].iter().any(|&c| c > 12);
    // Cell rows: rows covered across most of the blocks; cells: the column runs in a row.
    let rows = runs(
        (0..h).map(|y| (0..w).filter(|&x| on(x, y)).count() > w / 2),
        30,
    );
    assert_eq!(rows.len(), 5, "cell rows {rows:?}");
    let mid = (rows[0].0 + rows[0].1) / 2;
    let cols = runs((0..w).map(|x| on(x, mid)), 30);
    assert_eq!(cols.len(), 8, "cells {cols:?}");
    let crop = |r: (usize, usize), c: (usize, usize)| -> Vec<u8> {
        let side = (r.1 - r.0).min(c.1 - c.0) - 4;
        let mut out = Vec::new();
        for y in r.0 + 2..r.0 + 2 + side {
            for x in c.0 + 2..c.0 + 2 + side {
                out.extend_from_slice(&rgb[(y * w + x) * 3..][..3]);
            }
        }
        out
    };
    let side = |r: (usize, usize), c: (usize, usize)| (r.1 - r.0).min(c.1 - c.0) - 4;
    let mut worst_mirror = f64::INFINITY;
    let mut worst_geometry = f64::INFINITY;
    for &r in &rows {
        for block in [0, 4] {
            let n = side(r, cols[block]).min(side(r, cols[block + 1]));
            let n = (1..4).map(|k| side(r, cols[block + k])).fold(n, usize::min);
            let cell = |k: usize| {
                let c = cols[block + k];
                crop(r, (c.0, c.0 + n + 4))
            };
            let geometry = cell(0);
            let normal = cell(1);
            for k in [2, 3] {
                let p = compare_rgb8(&normal, &cell(k), n, n, None).psnr_db;
                worst_mirror = worst_mirror.min(p);
            }
            for k in 1..4 {
                let p = compare_rgb8(&geometry, &cell(k), n, n, None).psnr_db;
                worst_geometry = worst_geometry.min(p);
            }
        }
    }
    eprintln!(
        "mirrored vs unmirrored normal map: worst {worst_mirror:.2} dB; normal maps vs geometry: worst {worst_geometry:.2} dB"
    );
    assert!(worst_mirror >= 27.0, "mirrored cells {worst_mirror:.2} dB");
    assert!(
        worst_geometry >= 18.0,
        "normal-mapped vs geometry {worst_geometry:.2} dB"
    );
}

// ---- goldens -------------------------------------------------------------------------------

mod common;

/// Each relief scene of `scenes/` at 160×90 against its reviewed golden image
/// (`tests/golden/relief_*.png`), at 40 dB: the same code gives the same image to float
/// rounding (far above 40 dB); a changed technique moves whole bricks (well below).
#[test]
fn relief_scenes_match_their_golden_images() {
    let repo = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    for name in ["parallax", "displacement", "normal", "bump"] {
        let path = repo.join(format!("scenes/{name}.toml"));
        let mut loaded = texmap::scene::load(&path, &texmap::scene::LoadOptions::default())
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let s = &mut loaded.scene;
        displace_scene(s, &DisplaceOptions::default(), None).unwrap();
        let cam = s.camera.expect("the scene's camera");
        let f = render(s, &cam, &Settings::new(160, 90)).unwrap();
        common::assert_golden(&format!("relief_{name}"), 160, 90, &f.to_srgb8(), 40.0);
    }
}
