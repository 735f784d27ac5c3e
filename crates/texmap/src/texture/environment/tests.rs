//! Environment maps' tests: projections, footprints, the lanes reads against the scalar ones,
//! loading.

use super::*;
use crate::texture::{CubeFace, Filter};

fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("texmap-env-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// A linear colour that identifies a direction (smooth, every component in 0..1).
fn colour_of(d: Vec3) -> Vec4 {
    (d * 0.5 + Vec3::splat(0.5)).extend(1.0)
}

/// Four reads in lanes give the four scalar reads' bits: panoramas stored as floats and as
/// 16-bit texels, OpenGL filters magnified and minified (one level, two, nearest) and
/// anisotropic, directions at the seam, the poles and zero, footprints from a point to
/// wider than the image, every mask.
#[test]
fn equirect_lanes_read_as_four_scalar_reads() {
    let float = Texture2D::from_fn(64, 32, TextureOptions::default(), |x, y| {
        Vec4::new(
            x as f32 / 64.0,
            y as f32 / 32.0,
            ((x * 7 + y * 3) % 11) as f32,
            1.0,
        )
    })
    .unwrap();
    let bytes: Vec<u8> = (0..64 * 32 * 4).map(|i| (i * 37 % 251) as u8).collect();
    let unorm = Texture2D::from_rgba8(64, 32, ColorSpace::Srgb, &bytes).unwrap();
    let mut seed = 7u32;
    let mut rand = move || {
        seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
        (seed >> 8) as f32 / (1 << 24) as f32 * 2.0 - 1.0
    };
    let mut fps = Vec::new();
    for i in 0..64 {
        let dir = Vec3::new(rand(), rand(), rand());
        let scale = [0.0, 1e-4, 1e-2, 0.3, 3.0][i % 5];
        let ddir_dx = Vec3::new(rand(), rand(), rand()) * scale;
        let ddir_dy = Vec3::new(rand(), rand(), rand()) * scale;
        fps.push(CubeFootprint {
            dir,
            ddir_dx,
            ddir_dy,
        });
    }
    let special = [
        Vec3::NEG_Z,
        Vec3::Y,
        Vec3::NEG_Y,
        Vec3::ZERO,
        Vec3::new(0.0, 0.5, -1.0),
    ];
    for (fp, dir) in fps.iter_mut().zip(special) {
        fp.dir = dir;
    }
    let samplers = [
        Sampler::new(Filter::TRILINEAR, Wrap::Repeat),
        Sampler::new(Filter::BILINEAR, Wrap::Repeat),
        Sampler::new(Filter::NEAREST, Wrap::Repeat),
        Sampler::new(Filter::aniso(4), Wrap::Repeat),
    ];
    for map in [
        EnvironmentMap::Equirect(float),
        EnvironmentMap::Equirect(unorm),
    ] {
        for s in &samplers {
            for (k, group) in fps.chunks_exact(4).enumerate() {
                let fp = CubeFootprintLanes {
                    dir: [0, 1, 2]
                        .map(|c| Vec4::from_array(std::array::from_fn(|j| group[j].dir[c]))),
                    ddir_dx: [0, 1, 2]
                        .map(|c| Vec4::from_array(std::array::from_fn(|j| group[j].ddir_dx[c]))),
                    ddir_dy: [0, 1, 2]
                        .map(|c| Vec4::from_array(std::array::from_fn(|j| group[j].ddir_dy[c]))),
                };
                let mask = [0b1111, 0b0101, 0b1000][k % 3];
                let got = map.sample_lanes(s, &fp, mask);
                for j in 0..4 {
                    assert_eq!(fp.footprint(j), group[j]);
                    let want = if mask & (1 << j) != 0 {
                        map.sample(s, &group[j])
                    } else {
                        Vec4::ZERO
                    };
                    let bits = |v: Vec4| v.to_array().map(f32::to_bits);
                    assert_eq!(bits(got[j]), bits(want), "{s:?} group {k} lane {j}");
                }
            }
        }
    }
}

#[test]
fn convention_matches_the_peers_docstring() {
    let h = 512;
    let at = |d: Vec3| {
        let uv = equirect_uv(d.normalize(), h);
        (uv.x, (uv.y * h as f32 - 0.5) / (h as f32 - 1.0))
    };
    let close = |a: (f32, f32), b: (f32, f32)| (a.0 - b.0).abs() < 1e-6 && (a.1 - b.1).abs() < 1e-6;
    assert!(close(at(Vec3::Z), (0.5, 0.5)));
    assert!(close(at(Vec3::X), (0.25, 0.5)));
    assert!(close(at(-Vec3::X), (0.75, 0.5)));
    assert!(close(at(-Vec3::Z), (0.0, 0.5)));
    assert!(close(at(Vec3::Y), (0.5, 0.0)) || at(Vec3::Y).1.abs() < 1e-6);
    // The inverse.
    for (u, v) in [(0.1f32, 0.3f32), (0.5, 0.5), (0.9, 0.8)] {
        let d = equirect_direction(u, v);
        let (u2, v2) = at(d);
        assert!(
            (u - u2).abs() < 1e-5 && (v - v2).abs() < 1e-5,
            "{u} {v}: {u2} {v2}"
        );
    }
}

#[test]
fn equirect_derivatives_are_the_chain_rule_and_continuous_across_the_seam() {
    let h = 64;
    for d in [
        Vec3::new(0.3, 0.2, -0.9),
        Vec3::new(-0.001, 0.1, -1.0),
        Vec3::new(0.001, 0.1, -1.0),
    ] {
        let dd = Vec3::new(0.01, 0.004, 0.002);
        let fp = equirect_footprint(
            &CubeFootprint {
                dir: d,
                ddir_dx: dd,
                ddir_dy: Vec3::ZERO,
            },
            h,
        );
        // Central differences of the mapping, unwrapped.
        let e = 1e-3;
        let a = equirect_uv((d - dd * e).normalize(), h);
        let b = equirect_uv((d + dd * e).normalize(), h);
        let mut du = b.x - a.x;
        du -= du.round();
        let numeric = Vec2::new(du, b.y - a.y) / (2.0 * e);
        assert!(
            (numeric - fp.duv_dx).length() < 1e-3 * numeric.length().max(1.0),
            "{d}: {numeric} vs {}",
            fp.duv_dx
        );
    }
}

#[test]
fn sphere_map_centre_rim_and_derivatives() {
    let fp = |d: Vec3| {
        sphere_map_footprint(&CubeFootprint {
            dir: d,
            ..Default::default()
        })
    };
    assert!((fp(Vec3::Z).uv - Vec2::splat(0.5)).length() < 1e-6);
    // +x at 90° lands at u = ½ + 1/(2√2).
    let u = fp(Vec3::X).uv.x;
    assert!((u - (0.5 + 0.5 / 2f32.sqrt())).abs() < 1e-6, "{u}");
    // Up is up: +y reads above the centre (smaller v).
    assert!(fp(Vec3::new(0.0, 0.5, 1.0)).uv.y < 0.5);
    let d = Vec3::new(0.3, -0.4, 0.6);
    let dd = Vec3::new(0.02, 0.01, -0.01);
    let f = sphere_map_footprint(&CubeFootprint {
        dir: d,
        ddir_dx: dd,
        ddir_dy: dd,
    });
    let e = 1e-3;
    let numeric = (fp(d + dd * e).uv - fp(d - dd * e).uv) / (2.0 * e);
    assert!(
        (numeric - f.duv_dx).length() < 1e-3,
        "{numeric} {}",
        f.duv_dx
    );
}

fn write_cross(path: &Path, n: u32, vertical: bool) {
    // Each face painted with the colour of the direction through each texel centre, in
    // the face images' (mirrored) convention.
    let (w, h) = if vertical {
        (3 * n, 4 * n)
    } else {
        (4 * n, 3 * n)
    };
    let cells: [(u32, u32); 6] = if vertical {
        [(2, 1), (0, 1), (1, 0), (1, 2), (1, 1), (1, 3)]
    } else {
        [(2, 1), (0, 1), (1, 0), (1, 2), (1, 1), (3, 1)]
    };
    let mut img = image::Rgb32FImage::new(w, h);
    for (f, &(cx, cy)) in cells.iter().enumerate() {
        for y in 0..n {
            for x in 0..n {
                let sc = 2.0 * (x as f32 + 0.5) / n as f32 - 1.0;
                let tc = 2.0 * (y as f32 + 0.5) / n as f32 - 1.0;
                let g = CubeFace::direction(f, sc, tc);
                // The world direction that reads this texel: x mirrored.
                let world = Vec3::new(-g.x, g.y, g.z).normalize();
                let c = colour_of(world);
                let (px, py) = if vertical && f == 5 {
                    (cx * n + n - 1 - x, cy * n + n - 1 - y)
                } else {
                    (cx * n + x, cy * n + y)
                };
                img.put_pixel(px, py, image::Rgb([c.x, c.y, c.z]));
            }
        }
    }
    DynamicImage::ImageRgb32F(img).save(path).unwrap();
}

#[test]
fn crosses_read_back_the_directions_they_were_painted_with() {
    let s = Sampler::new(Filter::BILINEAR, Wrap::ClampToEdge);
    for vertical in [false, true] {
        let p = tmp(if vertical { "vcross.exr" } else { "hcross.exr" });
        write_cross(&p, 16, vertical);
        let env = load_environment(&p, None, &Limits::default()).unwrap();
        assert_eq!(env.kind(), EnvironmentKind::Faces);
        for d in [
            Vec3::new(0.3, 0.2, -0.9),
            Vec3::new(1.0, 0.99, 0.2),
            Vec3::new(-0.5, -0.7, 0.4),
            Vec3::new(0.01, 0.02, -1.0),
            Vec3::new(0.2, 0.1, 1.0),
            Vec3::new(0.0, -1.0, 0.0),
        ] {
            let got = env.sample(
                &s,
                &CubeFootprint {
                    dir: d,
                    ..Default::default()
                },
            );
            let want = colour_of(d.normalize());
            assert!(
                (got - want).abs().max_element() < 0.04,
                "vertical {vertical} {d}: {got} vs {want}"
            );
        }
    }
}

#[test]
fn wrong_proportions_and_bad_cube_files_are_refused_naming_the_file() {
    let p = tmp("odd.png");
    image::RgbImage::new(30, 20).save(&p).unwrap();
    let e = load_environment(&p, None, &Limits::default()).unwrap_err();
    assert!(
        e.to_string().contains("odd.png") && e.to_string().contains("30x20"),
        "{e}"
    );
    let e = load_environment(&p, Some(EnvironmentKind::Cross), &Limits::default()).unwrap_err();
    assert!(e.to_string().contains("4N x 3N"), "{e}");
    let p = tmp("cube.dds");
    std::fs::write(&p, b"DDS ").unwrap();
    let e = load_environment(&p, None, &Limits::default()).unwrap_err();
    assert!(e.to_string().contains("cube.dds"), "{e}");
    let e = load_environment(&tmp("missing.hdr"), None, &Limits::default()).unwrap_err();
    assert!(e.to_string().contains("missing.hdr"), "{e}");
    let dir = tmp("faces-empty");
    std::fs::create_dir_all(&dir).unwrap();
    let e = load_environment(&dir, None, &Limits::default()).unwrap_err();
    assert!(e.to_string().contains("posx"), "{e}");
}
