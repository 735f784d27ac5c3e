//! Shadow maps on distance-field surfaces: a field casts onto meshes (the shadow of a sphere
//! field on a plane has the area geometry gives), a field in a mesh's shadow is darkened,
//! with no casting light nothing changes, and a golden image of a field and meshes
//! shadowing each other.
//!
//! Tolerances, stated once:
//! - The sphere's shadow (pixels below half way from lit to fully shadowed) within 8% of
//!   the ellipse the light's direction gives (π·r²/sin(elevation)).
//! - A field under a mesh that hides it from the light: its mean brightness below 60% of
//!   the unshadowed one.
//! - Golden image: ≥ 35 dB PSNR.

mod common;

use std::path::Path;

use glam::{DVec3, Mat4, Vec2, Vec3, Vec4};
use texmap::camera::{Camera, CameraProjection};
use texmap::render::{render, render_with_volumes, Frame, Settings, ShadowOverrides};
use texmap::scene::{Mesh, Scene};
use texmap::shading::shadow::{ShadowParams, Shadows};
use texmap::shading::{Light, Material};
use texmap::volume::sdf::{render_distance_field, shape_field, FieldGrid, Shape};
use texmap::volume::{Method, SceneVolume};

/// A `2·half` square at height `y`, facing +y.
fn quad(half: f32, y: f32) -> Mesh {
    Mesh {
        positions: vec![
            Vec3::new(-half, y, -half),
            Vec3::new(half, y, -half),
            Vec3::new(half, y, half),
            Vec3::new(-half, y, half),
        ],
        normals: vec![Vec3::Y; 4],
        uvs: vec![Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::Y],
        indices: vec![0, 2, 1, 0, 3, 2],
        world_from_object: Mat4::IDENTITY,
        ..Default::default()
    }
}

/// A ball of `radius` at `center` as a distance-field surface lit by `lights`.
fn ball(center: Vec3, radius: f64, lights: &[Light]) -> SceneVolume {
    let n = 40;
    let side = 2.6 * radius;
    let h = side / f64::from(n);
    let lo = center.as_dvec3() - DVec3::splat(0.5 * side - 0.5 * h);
    let grid = FieldGrid::axis_aligned([n; 3], lo, DVec3::splat(h));
    let f = shape_field(
        &Shape::Sphere {
            center: center.as_dvec3(),
            radius,
        },
        &grid,
    );
    let mut v = SceneVolume::new(f.to_volume().unwrap(), Path::new("ball"));
    v.method = Method::Surface;
    v.params.lights = lights.to_vec();
    v.params.jitter = false;
    v
}

/// White Lambertian meshes under one casting light, no ambient light.
fn scene(meshes: Vec<Mesh>, light: Light) -> Scene {
    Scene {
        meshes,
        materials: vec![Material {
            base_color: Vec4::new(0.8, 0.8, 0.8, 1.0),
            ambient: 0.0,
            diffuse: 1.0,
            specular: 0.0,
            double_sided: true,
            ..Default::default()
        }],
        lights: vec![light],
        ambient_light: Vec3::ZERO,
        background: Vec4::new(0.0, 0.0, 0.0, 1.0),
        // Maps of 512² texels keep the test quick.
        shadows: Shadows::casting(vec![0]).with_params(ShadowParams::default().with_map_size(512)),
        ..Default::default()
    }
}

/// Looking straight down at the origin, `half` world units each side of the centre.
fn top_camera(half: f32) -> Camera {
    Camera {
        eye: Vec3::new(0.0, 10.0, 0.0),
        target: Vec3::ZERO,
        up: Vec3::NEG_Z,
        projection: CameraProjection::Orthographic { half_height: half },
        near: 0.1,
        far: 100.0,
    }
}

fn luma(c: Vec4) -> f32 {
    c.x + c.y + c.z
}

fn off(s: Settings) -> Settings {
    s.with_shadows(ShadowOverrides::default().with_cast(false))
}

#[test]
fn a_sphere_field_casts_a_shadow_of_the_expected_size() {
    // The light 45° above the horizon towards +x: the ball's shadow on the floor is an
    // ellipse of half-axes r/sin 45° (along x) and r, centred a height's run towards −x.
    let e = 45f32.to_radians();
    let light = Light::Directional {
        direction: Vec3::new(e.cos(), e.sin(), 0.0),
        color: Vec3::ONE,
    };
    let (r, height) = (0.6f32, 1.5f32);
    let sc = scene(vec![quad(4.5, 0.0)], light);
    let vols = [ball(Vec3::new(1.0, height, 0.0), f64::from(r), &[light])];
    let (w, half) = (200u32, 4.0f32);
    let cam = top_camera(half);
    let s = Settings::new(w, w);
    let on = render_with_volumes(&sc, &vols, &cam, &s).unwrap();
    let plain = render_with_volumes(&sc, &vols, &cam, &off(s)).unwrap();
    // Floor pixels (the ball covers x ∈ [0.4, 1.6]): the fraction of light left.
    let texel = 2.0 * half / w as f32;
    let ratios: Vec<f32> = (0..(w * w) as usize)
        .filter(|&i| {
            let x = -half + ((i % w as usize) as f32 + 0.5) * texel;
            x < 0.2 && luma(plain.color[i]) > 0.1
        })
        .map(|i| luma(on.color[i]) / luma(plain.color[i]))
        .collect();
    let least = ratios.iter().copied().fold(1.0, f32::min);
    assert!(least < 0.05, "the shadow's core keeps {least} of the light");
    let dark = ratios.iter().filter(|&&q| q < 0.5).count();
    let area = dark as f32 * texel * texel;
    let expected = std::f32::consts::PI * r * r / e.sin();
    println!("shadow area {area:.3} world² (expected {expected:.3})");
    assert!(
        (area / expected - 1.0).abs() < 0.08,
        "shadow {area:.3} vs {expected:.3} world²"
    );
    // The lit fraction of the floor left of the ball: the shadow is all the darkening.
    let lit = ratios.iter().filter(|&&q| q > 0.99).count() as f32 / ratios.len() as f32;
    println!("lit fraction of the floor beside the ball {lit:.3}");
    assert!(lit > 0.85 && lit < 0.99, "lit fraction {lit}");
}

#[test]
fn a_field_in_a_meshs_shadow_is_darkened() {
    // A roof over the ball, the light straight above.
    let light = Light::Directional {
        direction: Vec3::Y,
        color: Vec3::ONE,
    };
    let sc = scene(vec![quad(1.0, 2.0)], light);
    let vols = [ball(Vec3::ZERO, 0.6, &[light])];
    let cam = Camera {
        eye: Vec3::new(0.0, 0.3, 5.0),
        target: Vec3::ZERO,
        up: Vec3::Y,
        projection: CameraProjection::Perspective { fov_y_deg: 30.0 },
        near: 0.1,
        far: 100.0,
    };
    let s = Settings::new(96, 96);
    let on = render_with_volumes(&sc, &vols, &cam, &s).unwrap();
    let plain = render_with_volumes(&sc, &vols, &cam, &off(s)).unwrap();
    // The ball's lit side (the roof's underside, seen from below, is unlit).
    let lit: Vec<usize> = (0..plain.color.len())
        .filter(|&i| luma(plain.color[i]) > 0.3)
        .collect();
    assert!(lit.len() > 300, "{} lit pixels", lit.len());
    let mean = |f: &Frame| lit.iter().map(|&i| luma(f.color[i])).sum::<f32>() / lit.len() as f32;
    let (a, b) = (mean(&on), mean(&plain));
    println!("ball under the roof: {a:.3} vs {b:.3} unshadowed");
    assert!(a < 0.6 * b, "shadowed {a} vs lit {b}");
}

#[test]
fn without_a_casting_light_nothing_changes() {
    // What the frame was before fields cast: the meshes drawn, the field over them.
    let light = Light::Directional {
        direction: Vec3::new(0.3, 1.0, 0.2).normalize(),
        color: Vec3::ONE,
    };
    let mut sc = scene(vec![quad(3.0, -0.7)], light);
    sc.shadows = Shadows::default();
    let vols = [ball(Vec3::ZERO, 0.6, &[light])];
    let cam = top_camera(2.0);
    let s = Settings::new(64, 64);
    let f = render_with_volumes(&sc, &vols, &cam, &s).unwrap();
    let meshes = render(&sc, &cam, &s).unwrap();
    let depth = texmap::render::surface_distances(&sc, &cam, 64, 64).unwrap();
    let v = &vols[0];
    let field = render_distance_field(
        &v.volume,
        &cam,
        64,
        64,
        &v.params,
        &v.look,
        None,
        Some(&depth),
    )
    .unwrap();
    for (i, (c, (m, v))) in f
        .color
        .iter()
        .zip(meshes.color.iter().zip(&field.color))
        .enumerate()
    {
        assert_eq!(*c, *v + *m * (1.0 - v.w), "pixel {i}");
    }
}

#[test]
fn golden_field_and_meshes_shadow_each_other() {
    let light = Light::Directional {
        direction: Vec3::new(0.5, 1.0, 0.3).normalize(),
        color: Vec3::ONE,
    };
    let mut roof = quad(0.35, 1.3);
    roof.world_from_object = Mat4::from_translation(Vec3::new(0.2, 0.0, 0.1));
    let sc = scene(vec![quad(3.0, -0.6), roof], light);
    let vols = [ball(Vec3::ZERO, 0.6, &[light])];
    let cam = Camera {
        eye: Vec3::new(1.2, 2.0, 3.6),
        target: Vec3::new(0.0, -0.2, 0.0),
        up: Vec3::Y,
        projection: CameraProjection::Perspective { fov_y_deg: 45.0 },
        near: 0.1,
        far: 100.0,
    };
    let f = render_with_volumes(&sc, &vols, &cam, &Settings::new(128, 96)).unwrap();
    common::assert_golden("field_shadows", 128, 96, &f.to_srgb8(), 35.0);
}
