//! The hot loops' two copies (`texmap::cpu`): the baseline build and the x86-64-v3 one give
//! the same frames, float for float, over the pipeline's modes (the demo scene: textures under
//! every filter kind, normal maps, highlights, blending; MSAA, Gouraud, flat, unlit) and the
//! plane under the OpenGL filters (trilinear quads two at a time in AVX2 lanes at x86-64-v3),
//! anisotropic filtering and `ewa` (probes two at a time), metallic-roughness spheres with
//! every map the lit lanes read (two quads at a time in eight lanes), and a volume ray marched composite, unshaded (eight samples
//! in AVX2 lanes at x86-64-v3) and shaded. On a CPU without x86-64-v3 there is one copy and
//! the test says so. (Its own test binary: the level is the process's.)

use std::sync::Arc;

use glam::{Mat4, Vec3, Vec4};
use texmap::camera::{Camera, CameraProjection};
use texmap::cpu::{self, Level};
use texmap::render::{render, Settings, ShadingMode, TextureOverrides};
use texmap::scene::{builtin, Scene};
use texmap::shading::{
    shadow::Shadows, AlphaMode, Light, MapChannel, Material, MaterialMap, ShadingModel, TextureSlot,
};
use texmap::texture::{Filter, MagFilter, MinFilter, Sampler, Texture2D, TextureOptions, Wrap};
use texmap::volume::{raymarch, MarchParams, TransferFunction, Volume};

const W: u32 = 160;
const H: u32 = 96;

/// A texture of `f` over a 64² grid, linear.
fn texture(f: impl Fn(f32, f32) -> Vec4) -> Arc<Texture2D> {
    let t = Texture2D::from_fn(64, 64, TextureOptions::default(), |x, y| {
        f(x as f32 / 63.0, y as f32 / 63.0)
    });
    Arc::new(t.unwrap())
}

/// Two metallic-roughness spheres (one cut open: only its triangles facing +x kept, so its
/// inside shows) with every map the lit lanes read, three kinds of light and an ambient one.
fn mr_spheres(alpha_mode: AlphaMode) -> (Scene, Camera) {
    let sampler = Sampler::new(Filter::TRILINEAR, Wrap::Repeat);
    let map = |channel, tex: Arc<Texture2D>| MaterialMap {
        channel,
        slot: TextureSlot::new(tex, sampler),
        scale: 0.8,
    };
    let material = Material {
        model: ShadingModel::MetallicRoughness,
        base_color_texture: Some(TextureSlot::new(
            texture(|u, v| Vec4::new(u, v, 0.5 + 0.5 * (9.0 * u).sin(), 0.3 + 0.7 * v)),
            sampler,
        )),
        emissive: Vec3::new(0.4, 0.2, 0.1),
        double_sided: true,
        alpha_mode,
        maps: vec![
            map(
                MapChannel::Normal,
                texture(|u, v| {
                    let (x, y) = ((20.0 * u).sin() * 0.4, (14.0 * v).cos() * 0.4);
                    Vec4::new(0.5 + 0.5 * x, 0.5 + 0.5 * y, 0.9, 1.0)
                }),
            ),
            map(
                MapChannel::MetallicRoughness,
                texture(|u, v| Vec4::new(0.0, v, (u * 5.0).fract(), 1.0)),
            ),
            map(
                MapChannel::Occlusion,
                texture(|u, v| Vec4::new(0.4 + 0.6 * (u * v), 0.0, 0.0, 1.0)),
            ),
            map(
                MapChannel::Emissive,
                texture(|u, _| Vec4::new(u, 1.0 - u, 0.5, 1.0)),
            ),
        ],
        ..Default::default()
    };
    let sphere = |world: Mat4, cut: bool| {
        let mut mesh = builtin::uv_sphere(40, 20, 0);
        mesh.world_from_object = world;
        // Tangents along the parallels (+w handedness), zero at the poles.
        mesh.tangents = mesh
            .normals
            .iter()
            .map(|n| Vec3::Y.cross(*n).normalize_or_zero().extend(1.0))
            .collect();
        if cut {
            let keep: Vec<u32> = mesh
                .indices
                .chunks(3)
                .filter(|t| t.iter().all(|&i| mesh.positions[i as usize].x > -0.2))
                .flatten()
                .copied()
                .collect();
            mesh.indices = keep;
        }
        mesh
    };
    let scene = Scene {
        meshes: vec![
            sphere(Mat4::from_translation(Vec3::new(-1.1, 0.0, 0.0)), false),
            sphere(Mat4::from_translation(Vec3::new(1.1, 0.0, 0.0)), true),
        ],
        materials: vec![material],
        lights: vec![
            Light::Directional {
                direction: Vec3::new(0.3, 0.8, 0.5).normalize(),
                color: Vec3::new(1.0, 0.9, 0.8),
            },
            Light::Point {
                position: Vec3::new(0.0, 1.5, 2.0),
                color: Vec3::new(6.0, 5.0, 4.0),
                range: Some(5.0),
            },
            Light::Spot {
                position: Vec3::new(0.0, 3.0, 1.0),
                direction: Vec3::new(0.0, -1.0, -0.3).normalize(),
                color: Vec3::splat(8.0),
                inner_deg: 15.0,
                outer_deg: 40.0,
            },
        ],
        ambient_light: Vec3::new(0.3, 0.35, 0.4),
        background: Vec4::new(0.0, 0.0, 0.0, 1.0),
        ..Scene::default()
    };
    let camera = Camera {
        eye: Vec3::new(-2.5, 1.0, 4.5),
        target: Vec3::new(0.3, 0.0, 0.0),
        up: Vec3::Y,
        projection: CameraProjection::Perspective { fov_y_deg: 40.0 },
        near: 0.1,
        far: 100.0,
    };
    (scene, camera)
}

/// Every frame's colours as bits, one render per case.
fn frames() -> Vec<Vec<u32>> {
    let base = Settings::new(W, H);
    let gl = |mag, min| {
        base.with_textures(TextureOverrides::default().with_filter(Filter::Gl { mag, min }))
    };
    let demo = builtin::demo();
    let demo_camera = demo.camera.expect("the demo has a camera");
    let mut out = Vec::new();
    let demo_modes = [
        base,
        base.with_shading(ShadingMode::Gouraud),
        base.with_shading(ShadingMode::Flat),
        base.with_unlit(true),
        base.with_msaa(4),
        gl(MagFilter::Nearest, MinFilter::Nearest),
        gl(MagFilter::Linear, MinFilter::LinearMipmapLinear),
    ];
    for s in &demo_modes {
        out.push(render(&demo, &demo_camera, s).unwrap());
    }
    let plane = builtin::plane(None, 8.0, Sampler::new(Filter::BILINEAR, Wrap::Repeat));
    let plane_camera = plane.camera.expect("the plane has a camera");
    for (mag, min) in [
        (MagFilter::Nearest, MinFilter::Nearest),
        (MagFilter::Linear, MinFilter::Linear),
        (MagFilter::Linear, MinFilter::LinearMipmapLinear),
    ] {
        out.push(render(&plane, &plane_camera, &gl(mag, min)).unwrap());
    }
    // Probes (two at a time in AVX2 lanes at x86-64-v3), an odd count among them.
    for filter in [
        Filter::aniso(6),
        Filter::aniso(3),
        Filter::Ewa {
            max_eccentricity: 16.0,
        },
    ] {
        let s = base.with_textures(TextureOverrides::default().with_filter(filter));
        out.push(render(&plane, &plane_camera, &s).unwrap());
    }
    // Metallic-roughness spheres with every map the lanes read (base colour, tangent-space
    // normals, metallic-roughness, occlusion, emission), double-sided and cut open so back
    // faces show, under a directional, a point (with a range) and a spot light: two quads
    // at a time in eight lanes at x86-64-v3. Opaque, masked and blended; without shadows and
    // with two lights casting them.
    for alpha_mode in [AlphaMode::Opaque, AlphaMode::Mask(0.4), AlphaMode::Blend] {
        let (mut scene, camera) = mr_spheres(alpha_mode);
        out.push(render(&scene, &camera, &base).unwrap());
        // The directional and the point light casting shadows (looked up quad by quad).
        scene.shadows = Shadows::casting(vec![0, 1]);
        out.push(render(&scene, &camera, &base).unwrap());
    }
    // A blob with ripples, some of it transparent (empty bricks skipped), crossed by
    // jittered rays at a step that is not a power of two.
    let n = 40u32;
    let c = (n - 1) as f32 * 0.5;
    let values = (0..n * n * n)
        .map(|i| {
            let (x, y, z) = ((i % n) as f32, ((i / n) % n) as f32, (i / (n * n)) as f32);
            let r = ((x - c).powi(2) + (y - c).powi(2) + (z - c).powi(2)).sqrt();
            (220.0 * (1.0 - r / 18.0)).max(0.0) + 15.0 * (x * 0.4).sin() * (z * 0.3).cos()
        })
        .collect();
    let vol = Volume::from_scalars([n; 3], Mat4::IDENTITY, values).unwrap();
    let tf = TransferFunction::preset("synth").unwrap();
    let camera = Camera {
        eye: Vec3::new(c + 30.0, c - 90.0, c + 20.0),
        target: Vec3::splat(c),
        up: Vec3::Z,
        projection: CameraProjection::Perspective { fov_y_deg: 30.0 },
        near: 1.0,
        far: 1000.0,
    };
    for shade in [false, true] {
        let params = MarchParams {
            step: 0.37,
            shade,
            ..MarchParams::default()
        };
        out.push(raymarch(&vol, &tf, &camera, W, H, &params, None).unwrap());
    }
    out.iter()
        .map(|f| {
            f.color
                .iter()
                .flat_map(|c| c.to_array().map(f32::to_bits))
                .collect()
        })
        .collect()
}

#[test]
fn both_copies_of_the_hot_loops_render_the_same_frames() {
    if !cpu::available(Level::V3) {
        eprintln!("skipped: this CPU has no x86-64-v3, so the hot loops have one copy");
        return;
    }
    assert_eq!(cpu::force(Some(Level::Baseline)), Level::Baseline);
    let baseline = frames();
    assert_eq!(cpu::force(Some(Level::V3)), Level::V3);
    let v3 = frames();
    assert_eq!(baseline.len(), v3.len());
    for (i, (a, b)) in baseline.iter().zip(&v3).enumerate() {
        let differ = a.iter().zip(b).filter(|(x, y)| x != y).count();
        assert_eq!(
            differ, 0,
            "case {i}: {differ} floats differ between the two copies"
        );
    }
    // The frames are not empty: something was drawn in every case.
    for (i, f) in v3.iter().enumerate() {
        assert!(f.iter().any(|&x| x != 0), "case {i} drew nothing");
    }
}
