//! Volumes beyond a single scan: presets against the peer's own file, scene lights on a
//! synthetic volume, volumes in TOML scenes (placement, transfer function, options, errors)
//! and the example scene's golden image.
//!
//! Tolerances, stated once:
//! - Presets: the same numbers as `vtk_volume.py` (exact, as parsed from both texts).
//! - Scene lights: the lit half ≥ 1.5× the other; the headlight's halves within 2%.
//! - Placement: a ball's image centre within 1 pixel of its projected centre.
//! - Rays vs slices stopped at a surface ≥ 45 dB PSNR (measured 59.9 dB).
//! - Golden images ≥ 40 dB PSNR (`tests/common`, `REPLACE=1` rewrites them).

mod common;

use std::path::{Path, PathBuf};

use glam::{Mat4, Vec3};
use texmap::render::{render_with_volumes, Frame};
use texmap::scene::{load, Light, LoadOptions};
use texmap::volume::transfer::PRESETS;
use texmap::volume::{
    raymarch, render_slices, Classification, MarchParams, Method, Mode, ScalarType, SceneVolume,
    TransferFunction, Volume,
};

/// The string literals of `vtk_volume.py`'s `PRESETS = { "name": "…" "…", … }` (adjacent
/// literals concatenated, `#` comments skipped).
fn python_presets(src: &str) -> Vec<(String, String)> {
    let start = src.find("PRESETS = {").expect("PRESETS in vtk_volume.py") + 11;
    let mut out: Vec<(String, String)> = Vec::new();
    let mut strings: Vec<String> = Vec::new();
    let mut key: Option<String> = None;
    let mut chars = src[start..].chars();
    while let Some(c) = chars.next() {
        match c {
            '#' => {
                for c in chars.by_ref() {
                    if c == '\n' {
                        break;
                    }
                }
            }
            '"' => strings.push(chars.by_ref().take_while(|&c| c != '"').collect()),
            ':' => key = strings.pop(),
            ',' | '}' => {
                if let Some(k) = key.take() {
                    out.push((k, strings.concat()));
                }
                strings.clear();
                if c == '}' {
                    break;
                }
            }
            _ => {}
        }
    }
    out
}

#[test]
fn presets_use_the_points_of_vtk_volume_py() {
    let peer = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/peers/vtk_volume.py");
    let Ok(src) = std::fs::read_to_string(&peer) else {
        eprintln!("SKIPPED: {} is absent", peer.display());
        return;
    };
    let theirs = python_presets(&src);
    assert!(theirs.len() >= 3, "parsed {theirs:?}");
    for (name, points) in &theirs {
        let Some(ours) = TransferFunction::preset(name) else {
            panic!("vtk_volume.py has a preset {name:?} that texmap lacks");
        };
        let peer_tf = TransferFunction::parse(points).expect("the peer's points parse");
        assert_eq!(ours.points(), peer_tf.points(), "{name}");
    }
    // The five presets texmap promises.
    for name in ["ct-bone", "ct-skin", "ct-muscle", "mri", "synth"] {
        assert!(PRESETS.iter().any(|p| p.0 == name), "{name}");
    }
}

fn repo_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

// ---- Scene lights ----------------------------------------------------------------------------

/// A ball: 200 at the centre of a 48³ grid falling linearly to 0 at radius 24 voxels.
fn ball() -> Volume {
    let n = 48u32;
    let c = (n - 1) as f32 * 0.5;
    let mut v = Vec::new();
    for z in 0..n {
        for y in 0..n {
            for x in 0..n {
                let r = Vec3::new(x as f32 - c, y as f32 - c, z as f32 - c).length();
                v.push((200.0 * (1.0 - r / 24.0)).max(0.0));
            }
        }
    }
    Volume::from_scalars([n; 3], Mat4::IDENTITY, v).unwrap()
}

/// Nearly opaque white from 110 up: a surface of radius ≈ 11 voxels.
fn ball_tf() -> TransferFunction {
    TransferFunction::parse("0:1,1,1,0;100:1,1,1,0;110:1,1,1,0.8;200:1,1,1,1").unwrap()
}

/// Mean of the colour channels over the left and the right half of the image.
fn halves(f: &Frame) -> (f64, f64) {
    let (mut l, mut r) = (0.0f64, 0.0f64);
    for (i, c) in f.color.iter().enumerate() {
        let v = f64::from(c.x + c.y + c.z);
        if (i as u32 % f.width) < f.width / 2 {
            l += v;
        } else {
            r += v;
        }
    }
    (l, r)
}

#[test]
fn a_light_from_plus_x_brightens_the_plus_x_side() {
    let vol = ball();
    let tf = ball_tf();
    // vtk_volume.py's camera: along +y, z up, so +x is the right of the image.
    let cam = vol.vtk_camera(1.6, 0.0);
    let light = |x: f32| Light::Directional {
        direction: Vec3::new(x, 0.0, 0.0),
        color: Vec3::ONE,
    };
    let params = |lights: Vec<Light>| MarchParams {
        shade: true,
        jitter: false,
        lights,
        ..MarchParams::default()
    };
    for slices in [false, true] {
        let draw = |p: &MarchParams| {
            if slices {
                render_slices(&vol, &tf, &cam, 64, 64, p).unwrap()
            } else {
                raymarch(&vol, &tf, &cam, 64, 64, p, None).unwrap()
            }
        };
        let (hl, hr) = halves(&draw(&params(Vec::new())));
        let (pl, pr) = halves(&draw(&params(vec![light(1.0)])));
        let (ml, mr) = halves(&draw(&params(vec![light(-1.0)])));
        let what = if slices { "slices" } else { "rays" };
        // The headlight lights both halves alike; a light from +x the right one, from −x the left.
        assert!(
            (hl - hr).abs() < 0.02 * (hl + hr),
            "{what} headlight: {hl} vs {hr}"
        );
        assert!(pr > 1.5 * pl, "{what} light from +x: left {pl}, right {pr}");
        assert!(ml > 1.5 * mr, "{what} light from −x: left {ml}, right {mr}");
        // Mirror images of each other.
        assert!((pr - ml).abs() < 0.02 * pr, "{what}: {pr} vs {ml}");
    }
}

// ---- Volumes in TOML scenes ------------------------------------------------------------------

fn tmp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("texmap-vscene-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// An 8×6×5 big-endian u16 raw file after a 7-byte header: value x + 10y + 100z.
fn write_raw_u16_be(path: &Path) {
    let mut b = b"HEADER!".to_vec();
    for z in 0..5u16 {
        for y in 0..6u16 {
            for x in 0..8u16 {
                b.extend_from_slice(&(x + 10 * y + 100 * z).to_be_bytes());
            }
        }
    }
    std::fs::write(path, b).unwrap();
}

fn load_scene(dir: &Path, body: &str) -> texmap::Result<texmap::scene::Loaded> {
    let p = dir.join("s.toml");
    std::fs::write(&p, body).unwrap();
    load(&p, &LoadOptions::default())
}

#[test]
fn a_volume_table_reads_every_key() {
    let d = tmp_dir("keys");
    std::fs::create_dir_all(d.join("data")).unwrap();
    write_raw_u16_be(&d.join("data/v.raw"));
    std::fs::write(
        d.join("data/tf.txt"),
        "# points\n0:0,0,0,0\n400:1,0.5,0.25,0.5\n",
    )
    .unwrap();
    let l = load_scene(
        &d,
        r#"
[[lights]]
type = "point"
position = [0, 0, 50]
intensity = 100
[[volumes]]
file = "data/v.raw"
dims = [8, 6, 5]
dtype = "u16"
spacing = [1, 2, 3]
endian = "big"
header_bytes = 7
translate = [10, 20, 30]
rotate = [0, 0, 90]
scale = 2
tf = "data/tf.txt"
mode = "iso"
iso = 250
step = 0.25
shade = true
method = "raymarch"
classification = "pre"
gradient_opacity = "0:0;5:1"
jitter = false
empty_space_skipping = false
"#,
    )
    .unwrap();
    assert_eq!(l.volumes.len(), 1);
    assert_eq!(l.info.volumes.len(), 1);
    assert!(!l.info.default_light);
    let v = &l.volumes[0];
    let vol = &v.volume;
    assert_eq!(vol.dims(), [8, 6, 5]);
    assert_eq!(vol.scalar_type(), Some(ScalarType::U16));
    assert_eq!(vol.range(), (0.0, 457.0));
    assert!(
        (vol.voxel(3, 2, 1) - 123.0).abs() < 0.01,
        "{}",
        vol.voxel(3, 2, 1)
    );
    // Spacing (1, 2, 3), then scale 2, rotate 90° about z, translate.
    let m = vol.world_from_voxel();
    let close = |a: Vec3, b: Vec3| (a - b).length() < 1e-4;
    assert!(close(
        m.transform_point3(Vec3::ZERO),
        Vec3::new(10.0, 20.0, 30.0)
    ));
    assert!(close(
        m.transform_point3(Vec3::X),
        Vec3::new(10.0, 22.0, 30.0)
    ));
    assert!(close(
        m.transform_point3(Vec3::Y),
        Vec3::new(6.0, 20.0, 30.0)
    ));
    assert!(close(
        m.transform_point3(Vec3::Z),
        Vec3::new(10.0, 20.0, 36.0)
    ));
    // The transfer function file resolves from the scene's folder.
    assert_eq!(v.transfer.points().len(), 2);
    assert_eq!(v.transfer.points()[1].0, 400.0);
    let p = &v.params;
    assert_eq!(
        (p.mode, p.iso, p.step, p.shade, p.classification),
        (Mode::Iso, Some(250.0), 0.25, true, Classification::Pre)
    );
    assert_eq!(p.gradient_opacity, vec![(0.0, 0.0), (5.0, 1.0)]);
    assert!(!p.jitter && !p.empty_space_skipping);
    assert_eq!(v.method, Method::Raymarch);
    // The scene's own light shades the volume.
    assert_eq!(p.lights, l.scene.lights);
    assert_eq!(p.lights.len(), 1);
}

#[test]
fn defaults_headlight_and_matrix_placement() {
    let d = tmp_dir("defaults");
    write_raw_u16_be(&d.join("v.raw"));
    let raw = r#"file = "v.raw"
dims = [8, 6, 5]
dtype = "u16"
endian = "big"
header_bytes = 7"#;
    // Without lights: the loader's default light is for surfaces; volumes get the headlight.
    let a = load_scene(
        &d,
        &format!("[[volumes]]\n{raw}\ntranslate = [1, 2, 3]\nscale = [1, 2, 4]\n"),
    )
    .unwrap();
    assert!(a.info.default_light);
    let v = &a.volumes[0];
    assert!(v.params.lights.is_empty());
    assert_eq!(v.transfer_name, "synth");
    assert_eq!(
        (v.method, v.params.mode, v.params.step),
        (Method::Raymarch, Mode::Composite, 0.5)
    );
    assert!(!v.params.shade && v.params.jitter && v.params.empty_space_skipping);
    // The same placement as a column-major matrix.
    let m = Mat4::from_scale_rotation_translation(
        Vec3::new(1.0, 2.0, 4.0),
        glam::Quat::IDENTITY,
        Vec3::new(1.0, 2.0, 3.0),
    );
    let numbers: Vec<String> = m.to_cols_array().iter().map(|x| format!("{x}")).collect();
    let b = load_scene(
        &d,
        &format!("[[volumes]]\n{raw}\nmatrix = [{}]\n", numbers.join(", ")),
    )
    .unwrap();
    assert_eq!(
        b.volumes[0].volume.world_from_voxel(),
        v.volume.world_from_voxel()
    );
}

#[test]
fn bad_volume_tables_are_errors_naming_the_problem() {
    let d = tmp_dir("bad");
    write_raw_u16_be(&d.join("v.raw"));
    let raw = "file = \"v.raw\"\ndims = [8, 6, 5]\ndtype = \"u16\"\nheader_bytes = 7\n";
    let cases: &[(&str, &[&str])] = &[
        (
            "file = \"v.raw\"\ncolour = 1\n",
            &["s.toml", "line 3", "colour"],
        ),
        ("file = \"v.raw\"\n", &["v.raw", "--dims"]),
        (
            "file = \"v.raw\"\ndtype = \"u16\"\n",
            &["volumes[0]", "need dims"],
        ),
        (
            "file = \"x.nrrd\"\ndims = [1, 1, 1]\n",
            &["volumes[0]", "own header"],
        ),
        ("file = \"missing.nii\"\n", &["missing.nii"]),
        (
            "file = \"v.raw\"\ndims = [8, 6, 6]\ndtype = \"u16\"\n",
            &["v.raw", "bytes"],
        ),
        (&format!("{raw}mode = \"dvr\"\n"), &["volumes[0]", "dvr"]),
        (
            &format!("{raw}method = \"splat\"\n"),
            &["volumes[0]", "splat"],
        ),
        (
            &format!("{raw}classification = \"x\"\n"),
            &["volumes[0]", "\"x\""],
        ),
        (&format!("{raw}dtype = \"u12\"\n"), &["duplicate key"]),
        (
            &format!("{raw}endian = \"middle\"\n"),
            &["volumes[0]", "middle"],
        ),
        (&format!("{raw}step = 0\n"), &["volumes[0]", "step"]),
        (&format!("{raw}tf = \"nope\"\n"), &["nope", "preset"]),
        (&format!("{raw}tf = \"0:1,1,1\"\n"), &["0:1,1,1"]),
        (
            &format!("{raw}method = \"slices\"\nmode = \"mip\"\n"),
            &["volumes[0]", "slices"],
        ),
        (
            &format!("{raw}matrix = [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1]\nscale = 2\n"),
            &["volumes[0]", "matrix"],
        ),
        (&format!("{raw}scale = 0\n"), &["volumes[0]", "singular"]),
    ];
    for (body, needles) in cases {
        let e = match load_scene(&d, &format!("[[volumes]]\n{body}")) {
            Ok(_) => panic!("loaded: {body}"),
            Err(e) => e.to_string(),
        };
        for n in *needles {
            assert!(e.contains(n), "{n:?} not in {e:?} ({body})");
        }
    }
}

#[test]
fn placed_volumes_and_meshes_render_together() {
    // A ball of 48³ voxels at the origin and one moved +60 along x; a mesh square in front of
    // the left half of the first. The camera looks along +y, so +x is to the right.
    let vol = ball();
    let sv = |x: f32| {
        let mut v = SceneVolume::new(vol.clone(), Path::new("ball"));
        v.transfer = ball_tf();
        v.params.jitter = false;
        v.place(
            Mat4::from_translation(Vec3::new(x - 23.5, -23.5, -23.5)),
            false,
        )
        .unwrap();
        v
    };
    let volumes = vec![sv(0.0), sv(60.0)];
    let cam = texmap::volume::vtk_camera_for_bounds(
        Vec3::new(-30.0, -30.0, -30.0),
        Vec3::new(90.0, 30.0, 30.0),
        1.0,
        0.0,
    );
    let settings = texmap::render::Settings::new(96, 48);
    let empty = texmap::scene::Scene::default();
    let f = render_with_volumes(&empty, &volumes, &cam, &settings).unwrap();
    // Two balls, centred where their placements put them.
    let centre_x = |f: &Frame, x0: u32, x1: u32| {
        let (mut s, mut n) = (0.0f64, 0.0f64);
        for (i, c) in f.color.iter().enumerate() {
            let x = i as u32 % f.width;
            if (x0..x1).contains(&x) && c.w > 0.5 {
                s += f64::from(x) + 0.5;
                n += 1.0;
            }
        }
        s / n
    };
    let project = |p: Vec3| {
        let clip = cam.clip_from_view(2.0) * cam.view_from_world() * p.extend(1.0);
        (clip.x / clip.w * 0.5 + 0.5) * 96.0
    };
    for (lo, hi, x) in [(0, 48, 0.0), (48, 96, 60.0)] {
        let got = centre_x(&f, lo, hi);
        let want = f64::from(project(Vec3::new(x, 0.0, 0.0)));
        assert!(
            (got - want).abs() < 1.0,
            "ball at x = {x}: {got} px, expected {want}"
        );
    }
    // An opaque red square in front of the first ball hides it: the rays stop there.
    let mut scene = texmap::scene::Scene {
        materials: vec![texmap::scene::Material {
            base_color: glam::Vec4::new(1.0, 0.0, 0.0, 1.0),
            unlit: true,
            ..Default::default()
        }],
        ..Default::default()
    };
    scene.meshes.push(texmap::scene::Mesh {
        positions: vec![
            Vec3::new(-15.0, -20.0, -15.0),
            Vec3::new(15.0, -20.0, -15.0),
            Vec3::new(15.0, -20.0, 15.0),
            Vec3::new(-15.0, -20.0, 15.0),
        ],
        indices: vec![0, 1, 2, 0, 2, 3],
        world_from_object: Mat4::IDENTITY,
        ..Default::default()
    });
    let g = render_with_volumes(&scene, &volumes, &cam, &settings).unwrap();
    let x = project(Vec3::ZERO) as u32;
    let c = g.color[(24 * 96 + x) as usize];
    assert!(c.x > 0.99 && c.y < 0.01 && c.w > 0.99, "{c}");
    // The second ball is unchanged by the square.
    let x2 = project(Vec3::new(60.0, 0.0, 0.0)) as u32;
    let i = (24 * 96 + x2) as usize;
    assert!((g.color[i] - f.color[i]).abs().max_element() < 1e-6);
}

// ---- The example scene ---------------------------------------------------------------------

#[test]
fn example_scene_matches_its_golden_image() {
    let l = load(
        &repo_root().join("scenes/volume.toml"),
        &LoadOptions::default(),
    )
    .unwrap();
    assert_eq!((l.scene.meshes.len(), l.volumes.len()), (1, 1));
    assert_eq!(l.volumes[0].volume.dims(), [48, 48, 40]);
    assert_eq!(l.volumes[0].params.lights.len(), 1, "the scene's light");
    let cam = l.scene.camera.expect("the scene's camera");
    let settings = texmap::render::Settings::new(320, 240);
    let f = render_with_volumes(&l.scene, &l.volumes, &cam, &settings).unwrap();
    common::assert_golden("scene_volume", 320, 240, &f.to_srgb8(), 40.0);
}

#[test]
fn slices_stop_at_surfaces_like_rays() {
    // A translucent ball with a square through its middle plane y = 0 over the left half:
    // rays and slices both stop there, and agree.
    let mut sv = SceneVolume::new(ball(), Path::new("ball"));
    sv.transfer =
        TransferFunction::parse("0:1,0.8,0.6,0;40:1,0.8,0.6,0.03;200:1,0.8,0.6,0.03").unwrap();
    sv.params.jitter = false;
    sv.place(Mat4::from_translation(Vec3::splat(-23.5)), false)
        .unwrap();
    let mut scene = texmap::scene::Scene::default();
    scene.materials.push(texmap::scene::Material {
        base_color: glam::Vec4::new(0.1, 0.2, 0.9, 1.0),
        unlit: true,
        ..Default::default()
    });
    scene.meshes.push(texmap::scene::Mesh {
        positions: vec![
            Vec3::new(-30.0, 0.0, -30.0),
            Vec3::new(0.0, 0.0, -30.0),
            Vec3::new(0.0, 0.0, 30.0),
            Vec3::new(-30.0, 0.0, 30.0),
        ],
        indices: vec![0, 1, 2, 0, 2, 3],
        world_from_object: Mat4::IDENTITY,
        ..Default::default()
    });
    let cam = sv.volume.vtk_camera(1.6, 0.0);
    let settings = texmap::render::Settings::new(64, 64);
    let rays = render_with_volumes(&scene, std::slice::from_ref(&sv), &cam, &settings).unwrap();
    sv.method = Method::Slices;
    let slices = render_with_volumes(&scene, std::slice::from_ref(&sv), &cam, &settings).unwrap();
    let alone = render_with_volumes(
        &texmap::scene::Scene::default(),
        std::slice::from_ref(&sv),
        &cam,
        &settings,
    )
    .unwrap();
    let psnr = |a: &Frame, b: &Frame| {
        texmap::metrics::compare_rgb8(&a.to_srgb8(), &b.to_srgb8(), 64, 64, None).psnr_db
    };
    assert!(
        psnr(&rays, &slices) >= 45.0,
        "{:.1} dB",
        psnr(&rays, &slices)
    );
    // Left of centre the square shows through the front half of the ball; right of it the
    // slices are those of the ball alone.
    let (l, r) = (32 * 64 + 16, 32 * 64 + 48);
    assert!(slices.color[l].z > slices.color[l].x, "{}", slices.color[l]);
    assert!(alone.color[l].x > alone.color[l].z, "{}", alone.color[l]);
    assert!((slices.color[r] - alone.color[r]).abs().max_element() < 1e-6);
}
