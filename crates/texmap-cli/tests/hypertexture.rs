//! `texmap render` with distance fields: a mesh drawn as its field with a solid texture, a
//! bump or a hypertexture, a scan's surface at a threshold; every flag changes the image;
//! bad input (no triangles, a threshold outside the scan, a field over --max-memory, flags
//! with nothing to act on) is one line, exit 1, and no output.

mod common;

use common::texmap;
use std::path::{Path, PathBuf};
use std::process::Output;

use glam::DVec3;
use texmap::volume::sdf::{shape_field, FieldFormat, FieldGrid, Shape};

fn dir(name: &str) -> PathBuf {
    common::fresh_dir("ht", name)
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// A box [-1, 1] × [-0.5, 0.5] × [-1, 1] as an OBJ of 12 outward triangles.
fn box_obj(path: &Path) {
    let mut t = String::new();
    for i in 0..8 {
        let c = |b: i32, h: f32| if i & b == 0 { -h } else { h };
        t += &format!("v {} {} {}\n", c(1, 1.0), c(2, 0.5), c(4, 1.0));
    }
    for q in [
        [1, 3, 4, 2],
        [5, 6, 8, 7],
        [1, 2, 6, 5],
        [3, 7, 8, 4],
        [1, 5, 7, 3],
        [2, 4, 8, 6],
    ] {
        t += &format!(
            "f {} {} {}\nf {} {} {}\n",
            q[0], q[1], q[2], q[0], q[2], q[3]
        );
    }
    std::fs::write(path, t).unwrap();
}

/// Renders `input` with `flags` at 48×48; the image's bytes.
fn render(d: &Path, input: &Path, name: &str, flags: &[&str]) -> Vec<u8> {
    let out = d.join(format!("{name}.png"));
    let mut args = vec!["render", s(input), "--size", "48x48", "-q", "-o", s(&out)];
    args.extend_from_slice(flags);
    let r = texmap(&args);
    assert!(
        r.status.success(),
        "{flags:?}: {}",
        String::from_utf8_lossy(&r.stderr)
    );
    image::open(&out).unwrap().to_rgb8().into_raw()
}

/// One line on stderr containing `words`, exit 1, no output file.
fn refused(r: &Output, words: &str, output: &Path) {
    let err = String::from_utf8_lossy(&r.stderr);
    assert_eq!(r.status.code(), Some(1), "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(err.contains(words), "{err}");
    assert!(!output.exists(), "{} was written", output.display());
}

#[test]
fn every_field_flag_changes_the_image() {
    let d = dir("flags");
    let obj = d.join("box.obj");
    box_obj(&obj);
    let base = render(
        &d,
        &obj,
        "plain",
        &["--surface-color", "0.8,0.8,0.8", "--sdf-res", "32"],
    );
    let lit: f64 = base.iter().map(|&b| f64::from(b)).sum();
    assert!(lit > 0.0, "the surface is drawn");
    for (name, flags) in [
        ("marble", vec!["--solid", "marble", "--sdf-res", "32"]),
        ("bump", vec!["--bump", "--sdf-res", "32"]),
        (
            "bump_freq",
            vec!["--bump=0.3", "--bump-frequency", "6", "--sdf-res", "32"],
        ),
        (
            "red",
            vec!["--surface-color", "0.8,0.1,0.1", "--sdf-res", "32"],
        ),
        (
            "res",
            vec!["--surface-color", "0.8,0.8,0.8", "--sdf-res", "12"],
        ),
        ("fur", vec!["--hypertexture", "fur", "--sdf-res", "32"]),
        ("fire", vec!["--hypertexture", "fire", "--sdf-res", "32"]),
        (
            "smoke_no_tail",
            vec![
                "--hypertexture",
                "smoke",
                "--ht",
                "tail=off",
                "--sdf-res",
                "32",
            ],
        ),
        (
            "fire_thick",
            vec![
                "--hypertexture",
                "fire",
                "--ht",
                "thickness=0.2",
                "--sdf-res",
                "32",
            ],
        ),
    ] {
        let img = render(&d, &obj, name, &flags);
        assert_ne!(img, base, "{flags:?} changed nothing");
    }
    // And the same flags give the same bytes whatever the thread count.
    let a = render(
        &d,
        &obj,
        "t1",
        &[
            "--hypertexture",
            "smoke",
            "--threads",
            "1",
            "--sdf-res",
            "24",
        ],
    );
    let b = render(
        &d,
        &obj,
        "t2",
        &[
            "--hypertexture",
            "smoke",
            "--threads",
            "2",
            "--sdf-res",
            "24",
        ],
    );
    assert_eq!(a, b);
}

#[test]
fn melt_frames_advance_time() {
    let d = dir("melt");
    let obj = d.join("box.obj");
    box_obj(&obj);
    let out = d.join("m_{frame}.png");
    let r = texmap(&[
        "render",
        s(&obj),
        "--hypertexture",
        "melt",
        "--frames",
        "3",
        "--still",
        "--sdf-res",
        "24",
        "--size",
        "48x48",
        "-q",
        "-o",
        s(&out),
    ]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let f = |k: u32| {
        image::open(d.join(format!("m_{k:04}.png")))
            .unwrap()
            .to_rgb8()
            .into_raw()
    };
    assert_ne!(f(1), f(3), "the melt did not move");
}

#[test]
fn a_scan_surface_at_a_threshold() {
    let d = dir("scan");
    let grid = FieldGrid::axis_aligned([20, 20, 20], DVec3::ZERO, DVec3::ONE);
    let ball = Shape::Sphere {
        center: DVec3::splat(9.5),
        radius: 6.0,
    };
    // "Intensity" = 10 − distance: the ball is where it is at least 10.
    let mut f = shape_field(&ball, &grid);
    for v in &mut f.values {
        *v = 10.0 - *v;
    }
    let scan = d.join("scan.nii");
    std::fs::write(
        &scan,
        FieldFormat::for_path(&scan).unwrap().encode(&f).unwrap(),
    )
    .unwrap();
    let plain = render(&d, &scan, "ball", &["--surface", "10"]);
    let marble = render(
        &d,
        &scan,
        "ball_marble",
        &["--surface", "10", "--solid", "wood"],
    );
    assert_ne!(plain, marble);
    let out = d.join("bad.png");
    for t in ["1000", "-1000"] {
        let r = texmap(&["render", s(&scan), "--surface", t, "-o", s(&out)]);
        refused(&r, "outside the scan's values", &out);
    }
    // Look flags on a scan without --surface: nothing would read them.
    let r = texmap(&["render", s(&scan), "--solid", "marble", "-o", s(&out)]);
    refused(&r, "distance field", &out);
}

#[test]
fn bad_input_is_one_line_and_no_output() {
    let d = dir("bad");
    let out = d.join("x.png");
    let points = d.join("points.obj");
    std::fs::write(&points, "v 0 0 0\nv 1 0 0\nv 0 1 0\n").unwrap();
    let obj = d.join("box.obj");
    box_obj(&obj);
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec![s(&points), "--hypertexture", "fur"], "no triangles"),
        (
            vec![
                s(&obj),
                "--hypertexture",
                "fur",
                "--sdf-res",
                "2000",
                "--max-memory",
                "64M",
            ],
            "--max-memory",
        ),
        (vec![s(&obj), "--hypertexture", "hair"], "is not fur"),
        (
            vec![s(&obj), "--hypertexture", "fur", "--ht", "wiggle=1"],
            "no parameter",
        ),
        (
            vec![s(&obj), "--hypertexture", "fur", "--ht", "bias=2"],
            "bias",
        ),
        (
            vec![s(&obj), "--hypertexture", "smoke", "--ht", "tail=2"],
            "tail",
        ),
        (
            vec![s(&obj), "--hypertexture", "smoke", "--ht", "wide=0"],
            "wide",
        ),
        (
            vec![s(&obj), "--ht", "amplitude=1", "--solid", "wood"],
            "--hypertexture",
        ),
        (vec![s(&obj), "--solid", "cheese"], "cheese"),
        (vec![s(&obj), "--surface", "3"], "applies to a scan"),
        (
            vec!["builtin:demo", "--solid", "marble"],
            "no distance field",
        ),
        (vec![s(&obj), "--sdf-res", "64"], "--sdf-res"),
        (vec![s(&obj), "--hypertexture", "fur", "--still"], "--still"),
    ];
    for (args, words) in cases {
        let mut a = vec!["render"];
        a.extend(args.iter().copied());
        a.extend(["--size", "32x32", "-o", s(&out)]);
        let r = texmap(&a);
        refused(&r, words, &out);
    }
}

#[test]
fn shadows_flag_makes_a_field_cast_and_receive() {
    // A box drawn as its distance field over a floor, a light up and to the side.
    let d = dir("shadows");
    let b = d.join("box.obj");
    box_obj(&b);
    std::fs::write(
        d.join("floor.obj"),
        "v -4 -1 -4\nv 4 -1 -4\nv 4 -1 4\nv -4 -1 4\nvn 0 1 0\nf 1//1 3//1 2//1\nf 1//1 4//1 3//1\n",
    )
    .unwrap();
    let toml = |casting: bool| {
        format!(
            "[[cameras]]\neye = [0, 5, 7]\ntarget = [0, 0, 0]\n{}\
             [[lights]]\ntype = \"directional\"\ndirection = [0.8, 1, 0.3]\nshadows = {casting}\n\
             [[meshes]]\nfile = \"floor.obj\"\n\
             [[volumes]]\nfile = \"box.obj\"\nsdf_res = 24\nmethod = \"surface\"\n",
            if casting {
                "[shadows]\nmap_size = 256\n"
            } else {
                ""
            }
        )
    };
    let (lit, casting) = (d.join("lit.toml"), d.join("casting.toml"));
    std::fs::write(&lit, toml(false)).unwrap();
    std::fs::write(&casting, toml(true)).unwrap();
    let plain = render(&d, &lit, "plain", &[]);
    let flag = render(&d, &lit, "flag", &["--shadows", "--shadow-map-size", "256"]);
    let on = render(&d, &casting, "on", &[]);
    let off = render(&d, &casting, "off", &["--shadows=false"]);
    assert_eq!(plain, off, "with no casting light nothing changes");
    assert_eq!(flag, on, "--shadows casts as the scene's key does");
    // The shadow darkens the floor beside the box: many pixels darker, none brighter.
    let (mut darker, mut brighter) = (0, 0);
    for (a, b) in on.iter().zip(&off) {
        if *a + 8 < *b {
            darker += 1;
        }
        if *a > *b + 8 {
            brighter += 1;
        }
    }
    assert!(darker > 60, "{darker} darker values");
    assert_eq!(brighter, 0, "{brighter} brighter values");
}
