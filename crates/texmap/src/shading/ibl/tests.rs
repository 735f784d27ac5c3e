//! Tests of image-based light.

use std::f32::consts::{PI, TAU};

use glam::{Mat3, Vec3, Vec4};

use super::*;
use crate::shading::{pbr, Material, ShadingModel, Surface, Viewer};
use crate::texture::environment::EnvironmentMap;
use crate::texture::{CubeFootprint, Texture2D, TextureOptions};

fn uniform(c: Vec3) -> Environment {
    let t = Texture2D::from_fn(64, 32, TextureOptions::default(), |_, _| c.extend(1.0)).unwrap();
    Environment::new(EnvironmentMap::Equirect(t), "uniform")
}

/// A panorama lit by a small bright disc around `sun` (radius 5°) over a dim sky.
fn sun_env(sun: Vec3) -> Environment {
    let (w, h) = (256, 128);
    let t = Texture2D::from_fn(w, h, TextureOptions::default(), |x, y| {
        let u = (x as f32 + 0.5) / w as f32;
        let v = y as f32 / (h - 1) as f32;
        let d = crate::texture::environment::equirect_direction(u, v);
        let c = if d.dot(sun) > 5f32.to_radians().cos() {
            100.0
        } else {
            0.1
        };
        Vec4::new(c, c, c, 1.0)
    })
    .unwrap();
    Environment::new(EnvironmentMap::Equirect(t), "sun")
}

#[test]
fn a_uniform_environment_is_a_uniform_ambient_light_of_its_radiance() {
    // The furnace: radiance 0.7 everywhere gives I_env = 0.7 for every normal, and every
    // prefiltered level reads 0.7.
    let env = uniform(Vec3::splat(0.7));
    let light = EnvLight::new(&env, true, true);
    for n in [Vec3::X, -Vec3::Y, Vec3::new(0.3, 0.5, -0.8).normalize()] {
        let e = light.irradiance(n);
        assert!(
            (e - Vec3::splat(0.7)).abs().max_element() < 2e-3,
            "{n}: {e}"
        );
        for r in [0.1, 0.3, 0.55, 1.0] {
            let fp = CubeFootprint {
                dir: n,
                ..Default::default()
            };
            let l = light.radiance(&fp, r);
            assert!(
                (l - Vec3::splat(0.7)).abs().max_element() < 2e-3,
                "{r}: {l}"
            );
        }
    }
}

#[test]
fn irradiance_of_a_small_sun_follows_the_cosine_law() {
    // A disc of radiance 100 and solid angle 2π(1 − cos 5°) over a sky of 0.1: facing it,
    // I_env = (100 − 0.1)·Ω·cos/π + 0.1.
    let sun = Vec3::new(0.3, 0.8, -0.5).normalize();
    let env = sun_env(sun);
    let light = EnvLight::new(&env, true, false);
    let omega = TAU * (1.0 - 5f32.to_radians().cos());
    for angle in [0.0f32, 30.0, 60.0] {
        // A normal `angle` degrees from the sun.
        let axis = sun.cross(Vec3::Y).normalize();
        let n = Mat3::from_axis_angle(axis, angle.to_radians()) * sun;
        let want = (100.0 - 0.1) * omega * angle.to_radians().cos() / PI + 0.1;
        let got = light.irradiance(n).x;
        assert!(
            (got - want).abs() < 0.02 * want,
            "{angle}°: {got} vs {want}"
        );
    }
}

#[test]
fn rough_levels_blur_the_sun_and_keep_its_energy() {
    let sun = Vec3::new(0.0, 0.6, -0.8).normalize();
    let env = sun_env(sun);
    let light = EnvLight::new(&env, false, true);
    let at = |d: Vec3, r: f32| {
        light
            .radiance(
                &CubeFootprint {
                    dir: d,
                    ..Default::default()
                },
                r,
            )
            .x
    };
    // Towards the sun the peak falls as the lobe widens; 25° away it rises.
    let away = Mat3::from_rotation_x(25f32.to_radians()) * sun;
    let (p3, p6, p9) = (at(sun, 0.3), at(sun, 0.6), at(sun, 0.9));
    assert!(p3 > p6 && p6 > p9, "{p3} {p6} {p9}");
    assert!(
        at(away, 0.9) > at(away, 0.3),
        "{} {}",
        at(away, 0.9),
        at(away, 0.3)
    );
    // A wide footprint reads a blurrier level than a point.
    let wide = CubeFootprint {
        dir: sun,
        ddir_dx: Vec3::new(0.5, 0.0, 0.0),
        ddir_dy: Vec3::ZERO,
    };
    assert!(light.radiance(&wide, 0.3).x < p3);
}

#[test]
fn refraction_follows_snell_and_reflection_the_mirror_law() {
    let n = Vec3::Y;
    let v = Vec3::new(1.0, 1.0, 0.0).normalize();
    let r = reflect(n, v);
    assert!((r - Vec3::new(-1.0, 1.0, 0.0).normalize()).length() < 1e-6);
    let t = refract(n, v, 1.5);
    // sin θt = sin 45° / 1.5.
    let sin_t = t.x.abs() / t.length();
    assert!((sin_t - 45f32.to_radians().sin() / 1.5).abs() < 1e-5, "{t}");
    assert!(t.y < 0.0 && t.x < 0.0);
    // Head-on the ray goes straight through.
    assert!((refract(n, n, 1.5) + n).length() < 1e-6);
    assert_eq!(dielectric_f0(1.5), pbr::DIELECTRIC_F0);
}

#[test]
fn phong_mirror_and_glass_weights() {
    let env = uniform(Vec3::splat(2.0));
    let light = EnvLight::new(&env, true, true);
    let mut m = Material {
        ambient: 0.0,
        ..Default::default()
    };
    m.ior = 1.5;
    let s = Surface::new(&m, Vec3::ZERO, Vec3::Z);
    let viewer = Viewer::Point(Vec3::Z * 3.0);
    let rays = point_rays(&s, viewer);
    let mirror = EnvMaterial {
        reflection: 1.0,
        transmission: 0.0,
        phong_roughness: 0.0,
    };
    let (d, sp) = environment_terms(ShadingModel::Phong, &s, &mirror, viewer, &rays, &light);
    assert_eq!(d, Vec3::ZERO);
    assert!((sp - Vec3::splat(2.0)).abs().max_element() < 1e-5, "{sp}");
    // Glass head-on: 4% reflected, 96% transmitted, summing to the environment.
    let glass = EnvMaterial {
        transmission: 1.0,
        ..mirror
    };
    let (d, sp) = environment_terms(ShadingModel::Phong, &s, &glass, viewer, &rays, &light);
    assert!(
        (sp.x - 0.08).abs() < 1e-4 && (d.x - 1.92).abs() < 1e-4,
        "{d} {sp}"
    );
}

/// A smooth panorama: each channel a low-order function of the direction.
fn smooth_env() -> Environment {
    let (w, h) = (512, 256);
    let t = Texture2D::from_fn(w, h, TextureOptions::default(), |x, y| {
        let u = (x as f32 + 0.5) / w as f32;
        let v = (y as f32 + 0.5) / h as f32;
        let d = crate::texture::environment::equirect_direction(u, v);
        Vec4::new(1.0 + 0.5 * d.x, 1.0 + 0.5 * d.y, 1.0 + 0.5 * d.z * d.x, 1.0)
    })
    .unwrap();
    Environment::new(EnvironmentMap::Equirect(t), "smooth")
}

#[test]
fn the_mirror_cube_reads_what_the_map_holds_at_every_level_and_across_face_edges() {
    let env = smooth_env();
    let cube = env.mirror_cube();
    assert!(cube.size().is_power_of_two() && cube.size() <= 512);
    let sampler = env.sampler;
    // Directions on faces, on edges and at corners; footprints from none to a quarter face.
    let dirs = [
        Vec3::X,
        Vec3::new(0.3, -0.8, 0.5),
        Vec3::new(1.0, 1.0, 0.2),
        Vec3::new(-1.0, 1.0, -1.0),
        Vec3::new(0.01, 0.02, -1.0),
    ];
    for d in dirs {
        let d = d.normalize();
        let (t, b) = (
            d.any_orthonormal_vector(),
            d.cross(d.any_orthonormal_vector()),
        );
        for w in [0.0, 0.003, 0.05, 0.4] {
            let fp = CubeFootprint {
                dir: d,
                ddir_dx: t * w,
                ddir_dy: b * w,
            };
            let (got, _) = cube.read(&sampler, &fp);
            let got = glam::Vec3::from(got);
            let want = env.map().sample(&sampler, &fp).truncate();
            // Wide footprints average differently shaped regions (a cube level's box against
            // the panorama's): up to 6% apart at a cube corner.
            let tolerance = if w > 0.1 { 0.08 } else { 0.02 };
            assert!(
                (got - want).abs().max_element() < tolerance,
                "{d} width {w}: mirror cube {got}, map {want}"
            );
        }
    }
}

#[test]
fn a_smooth_reflection_reads_the_mirror_cube_like_the_map() {
    // Under roughness 1/8 the sharp end of the blend is the mirror cube; with a trilinear
    // sampler it agrees with the map's own read, and with another filter the map is read.
    let env = smooth_env();
    let light = EnvLight::new(&env, true, true);
    let fp = CubeFootprint {
        dir: Vec3::new(0.2, 0.4, -0.9).normalize(),
        ..Default::default()
    };
    let sharp = light.radiance(&fp, 0.02);
    let mut generic = light;
    generic.sampler = crate::texture::Sampler::new(
        crate::texture::Filter::BILINEAR,
        crate::texture::Wrap::Repeat,
    );
    let from_map = generic.radiance(&fp, 0.02);
    assert!(
        (sharp - from_map).abs().max_element() < 0.02,
        "{sharp} {from_map}"
    );
}

#[test]
fn sheen_levels_keep_a_uniform_environment_and_lean_to_the_horizon() {
    // The furnace: every Charlie level of a uniform environment reads its radiance.
    let env = uniform(Vec3::splat(0.7));
    let light = EnvLight::new(&env, true, false).with_sheen(true);
    for n in [Vec3::Y, Vec3::new(0.3, -0.5, 0.8).normalize()] {
        for r in [0.0, 0.2, 0.5, 1.0] {
            let l = light.sheen_radiance(n, n, r);
            assert!(
                (l - Vec3::splat(0.7)).abs().max_element() < 2e-3,
                "{n} {r}: {l}"
            );
        }
    }
    // A bright band around the horizon (|y| < 0.25) over black: facing up, a cosine-weighted
    // irradiance sees the band at grazing angles only, while a smooth sheen's light comes
    // from near the horizon of the normal — its reads must lean to the band, the more so the
    // smoother the sheen.
    let (w, h) = (256, 128);
    let band = Texture2D::from_fn(w, h, TextureOptions::default(), |x, y| {
        let u = (x as f32 + 0.5) / w as f32;
        let v = y as f32 / (h - 1) as f32;
        let d = crate::texture::environment::equirect_direction(u, v);
        let c = if d.y.abs() < 0.25 { 1.0 } else { 0.0 };
        Vec4::new(c, c, c, 1.0)
    })
    .unwrap();
    let env = Environment::new(EnvironmentMap::Equirect(band), "band");
    let light = EnvLight::new(&env, true, false).with_sheen(true);
    let e = light.irradiance(Vec3::Y).x;
    let smooth = light.sheen_radiance(Vec3::Y, Vec3::Y, 0.125).x;
    let rough = light.sheen_radiance(Vec3::Y, Vec3::Y, 1.0).x;
    assert!(
        smooth > rough && rough > e && smooth > 0.5,
        "irradiance {e}, sheen r=1/8 {smooth}, r=1 {rough}"
    );
    // Without the levels a sheen takes the irradiance, as before.
    let plain = EnvLight::new(&env, true, false);
    assert_eq!(plain.sheen_radiance(Vec3::Y, Vec3::Y, 0.5).x, e);
}

/// The background four pixels at a time is the background pixel by pixel, bit for bit, with
/// the map turned (the turn in lanes) and not.
#[test]
fn background_lanes_are_the_background_per_pixel() {
    let sun = Vec3::new(-0.4, 0.8, 0.45).normalize();
    for degrees in [0.0, 30.0] {
        let env = sun_env(sun).with_rotation_deg(degrees);
        let light = EnvLight::new(&env, false, false);
        let (ddir_dx, ddir_dy) = (Vec3::new(2e-3, 0.0, 1e-4), Vec3::new(0.0, -2e-3, 3e-4));
        for k in 0..16 {
            let group: [CubeFootprint; 4] = std::array::from_fn(|j| CubeFootprint {
                dir: Vec3::new((k * 4 + j) as f32 * 0.11 - 3.0, 0.7 - k as f32 * 0.1, -1.0),
                ddir_dx,
                ddir_dy,
            });
            let lanes = crate::texture::CubeFootprintLanes {
                dir: [0, 1, 2].map(|c| Vec4::from_array(group.map(|f| f.dir[c]))),
                ddir_dx: [0, 1, 2].map(|c| Vec4::splat(ddir_dx[c])),
                ddir_dy: [0, 1, 2].map(|c| Vec4::splat(ddir_dy[c])),
            };
            let got = light.background_lanes(&lanes, 0b1111);
            for j in 0..4 {
                let want = light.background(&group[j]);
                assert_eq!(
                    got[j].to_array().map(f32::to_bits),
                    want.to_array().map(f32::to_bits),
                    "rotation {degrees}, group {k}, lane {j}"
                );
            }
        }
    }
}
