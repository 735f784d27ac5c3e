//! Every render flag acts on every kind of scene, or is refused there with one line naming it.
//!
//! For each scene kind (the four built-in scenes, a TOML scene, an OBJ file with a texture,
//! a volume file) each flag is rendered beside the same command without it: either the image
//! changes (it is not identical to the image without the flag: the renderer is deterministic,
//! so there is no noise to rise above and any difference is the flag's), or the command fails
//! with exit code 1, one line on stderr naming the flag, and no output file. Each case states
//! which of the two it expects, so a flag that silently does nothing fails the test.

mod common;

use common::texmap;
use std::path::{Path, PathBuf};

fn dir() -> PathBuf {
    let d = std::env::temp_dir().join(format!("texmap-flags-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// A 16×16 image with a diagonal colour ramp (so every filter and wrap shows).
fn write_png(path: &Path) {
    let img = image::RgbImage::from_fn(16, 16, |x, y| {
        image::Rgb([(x * 16) as u8, (y * 16) as u8, ((x + y) * 8) as u8])
    });
    img.save(path).unwrap();
}

/// A 16×16 checker, unlike every scene's own texture (what `--texture` gives).
fn write_checker(path: &Path) {
    let img = image::RgbImage::from_fn(16, 16, |x, y| {
        let on = (x / 4 + y / 4) % 2 == 0;
        image::Rgb(if on { [250, 40, 40] } else { [20, 20, 200] })
    });
    img.save(path).unwrap();
}

/// A textured quad seen at a grazing angle, as OBJ + MTL + PNG (uvs over 0..4, so wrap modes
/// show).
fn write_obj(d: &Path) -> PathBuf {
    write_png(&d.join("ramp.png"));
    std::fs::write(d.join("quad.mtl"), "newmtl m\nKd 1 1 1\nmap_Kd ramp.png\n").unwrap();
    let obj = d.join("quad.obj");
    std::fs::write(
        &obj,
        "mtllib quad.mtl\nv -4 0 -4\nv 4 0 -4\nv 4 0 4\nv -4 0 4\n\
         vt 0 0\nvt 4 0\nvt 4 4\nvt 0 4\nvn 0 1 0\nusemtl m\nf 1/1/1 4/4/1 3/3/1 2/2/1\n",
    )
    .unwrap();
    obj
}

struct Case<'a> {
    scene: &'a str,
    /// Image size (small: the flags' effects show at a few dozen pixels).
    size: &'a str,
    /// Flags added to both renders (e.g. a camera for a file without one).
    base: &'a [&'a str],
}

/// Renders `case` with and without `flag`; `Some(psnr)` when both render, `None` when the
/// flag is refused (after checking the refusal is one line naming it, with no output).
fn try_flag(d: &Path, case: &Case, flag: &[&str], tag: &str) -> Option<f64> {
    let out_a = d.join(format!("{tag}-a.png"));
    let out_b = d.join(format!("{tag}-b.png"));
    let _ = std::fs::remove_file(&out_b);
    let common = |out: &Path| {
        let mut v = vec!["render", case.scene, "--size", case.size, "--quiet", "-o"];
        v.push(out.to_str().unwrap());
        v.extend_from_slice(case.base);
        v.iter().map(|s| s.to_string()).collect::<Vec<_>>()
    };
    if !out_a.exists() {
        let args = common(&out_a);
        let a = texmap(&args.iter().map(String::as_str).collect::<Vec<_>>());
        assert!(
            a.status.success(),
            "{} {:?}: {}",
            case.scene,
            case.base,
            String::from_utf8_lossy(&a.stderr)
        );
    }
    let mut args = common(&out_b);
    args.extend(flag.iter().map(|s| s.to_string()));
    let b = texmap(&args.iter().map(String::as_str).collect::<Vec<_>>());
    if !b.status.success() {
        let err = String::from_utf8_lossy(&b.stderr);
        assert_eq!(b.status.code(), Some(1), "{tag}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{tag}: one line, got {err}");
        assert!(
            err.contains(flag[0]),
            "{tag}: the refusal names {}: {err}",
            flag[0]
        );
        assert!(!out_b.exists(), "{tag}: no output on refusal");
        return None;
    }
    let (a, b) = (
        image::open(&out_a).unwrap().to_rgb8(),
        image::open(&out_b).unwrap().to_rgb8(),
    );
    assert_eq!(a.dimensions(), b.dimensions(), "{tag}");
    let (w, h) = a.dimensions();
    let m = texmap::metrics::compare_rgb8(a.as_raw(), b.as_raw(), w as usize, h as usize, None);
    Some(m.psnr_db)
}

#[derive(Clone, Copy, PartialEq, Debug)]
enum Want {
    /// Accepted, and the image changes.
    Acts,
    /// Accepted; the image may stay as it is (a load policy with nothing to relax).
    Accepted,
    /// Refused with one line naming the flag.
    Refused,
}
use Want::{Accepted, Acts, Refused};

fn check(d: &Path, name: &str, case: &Case, flags: &[(&[&str], Want)]) {
    for (k, (flag, want)) in flags.iter().enumerate() {
        let tag = format!("{name}-{k}");
        let got = try_flag(d, case, flag, &format!("{name}-{k}"));
        match (want, got) {
            (Acts, Some(psnr)) => assert!(
                psnr.is_finite(),
                "{tag} {} {flag:?}: the flag changed nothing (PSNR {psnr:.1} dB)",
                case.scene
            ),
            (Accepted, Some(_)) => {}
            (Acts | Accepted, None) => panic!("{tag} {} {flag:?}: refused", case.scene),
            (Refused, None) => {}
            (Refused, Some(p)) => {
                panic!(
                    "{tag} {} {flag:?}: accepted (PSNR {p:.1}), should be refused",
                    case.scene
                )
            }
        }
    }
}

/// The sampler flags, in a form that changes a textured image.
const TEXTURE_FLAGS: [&[&str]; 8] = [
    &["--filter", "nearest"],
    &["--wrap", "mirror"],
    &["--uv-scale", "3"],
    &["--lod-bias", "2"],
    &["--lod-rule", "rss"],
    &["--min-lod", "3"],
    &["--max-lod", "0"],
    &["--border", "1,0,0,1", "--wrap", "border"],
];

fn texture_flags<'a>(want: Want) -> Vec<(&'a [&'a str], Want)> {
    TEXTURE_FLAGS.iter().map(|f| (*f, want)).collect()
}

#[test]
fn texture_flags_act_on_every_textured_scene() {
    let d = dir();
    let ramp = d.join("checker16.png");
    write_checker(&ramp);
    let obj = write_obj(&d);
    let obj_cam = ["--eye", "0,1.5,6", "--target", "0,0,-2"];
    let cases: Vec<(&str, Case)> = vec![
        (
            "demo",
            Case {
                scene: "builtin:demo",
                size: "48x32",
                base: &[],
            },
        ),
        (
            "plane",
            Case {
                scene: "builtin:plane",
                // The checker's 64 repeats average to grey at a few dozen pixels.
                size: "320x180",
                base: &[],
            },
        ),
        (
            "sphere",
            Case {
                scene: "builtin:sphere",
                size: "48x32",
                base: &["--tris", "2000", "--fov", "20"],
            },
        ),
        (
            "obj",
            Case {
                scene: obj.to_str().unwrap(),
                size: "48x32",
                base: &obj_cam,
            },
        ),
    ];
    let texture = ["--texture", ramp.to_str().unwrap()];
    for (name, case) in &cases {
        let mut flags = texture_flags(Acts);
        flags.push((&texture[..], Acts));
        // (The demo's textures filter anisotropically, which reads no LOD rule; its sky is
        // read trilinearly, which does.)
        check(&d, name, case, &flags);
    }
    check(
        &d,
        "demo-trilinear",
        &Case {
            scene: "builtin:demo",
            size: "48x32",
            base: &["--filter", "trilinear"],
        },
        &[(&["--lod-rule", "rss"], Acts)],
    );
}

#[test]
fn texture_flags_are_refused_where_nothing_reads_an_image() {
    let d = dir();
    let repo = repo();
    let shapes = repo.join("scenes/shapes.toml");
    let cell = repo.join("scenes/volumes/cell.nrrd");
    check(
        &d,
        "marble",
        &Case {
            scene: "builtin:marble",
            size: "48x32",
            base: &[],
        },
        &texture_flags(Refused),
    );
    check(
        &d,
        "shapes",
        &Case {
            scene: shapes.to_str().unwrap(),
            size: "48x32",
            base: &[],
        },
        &texture_flags(Refused),
    );
    let mut volume = texture_flags(Refused);
    for f in [
        &["--shading", "flat"][..],
        &["--msaa", "4"],
        &["--ssaa", "2"],
        &["--unlit"],
        &["--interp", "affine"],
        &["--cull", "back"],
    ] {
        volume.push((f, Refused));
    }
    volume.push((&["--crop", "0,23,0,47,0,39"], Acts));
    volume.push((&["--crop", "30,20,0,47,0,39"], Refused));
    volume.push((&["--tf", "ct-bone"], Acts));
    volume.push((&["--slice", "axial"], Acts));
    volume.push((&["--slice", "coronal", "--index", "3"], Acts));
    volume.push((
        &["--slice", "sagittal", "--window", "200", "--level", "100"],
        Acts,
    ));
    volume.push((&["--slice", "axial", "--index", "99"], Refused));
    volume.push((&["--slice", "axial", "--eye", "1,2,3"], Refused));
    volume.push((&["--window", "100"], Refused));
    check(
        &d,
        "cell",
        &Case {
            scene: cell.to_str().unwrap(),
            size: "48x32",
            base: &[],
        },
        &volume,
    );
    // --texture gives the solid scene's materials nothing to take (all procedural).
    let ramp = d.join("ramp-m.png");
    write_png(&ramp);
    let texture = ["--texture", ramp.to_str().unwrap()];
    check(
        &d,
        "marble-tex",
        &Case {
            scene: "builtin:marble",
            size: "48x32",
            base: &[],
        },
        &[(&texture[..], Refused)],
    );
}

#[test]
fn mesh_camera_and_load_flags_act_or_are_refused() {
    let d = dir();
    let repo = repo();
    let shapes = repo.join("scenes/shapes.toml");
    let acts: &[(&[&str], Want)] = &[
        (&["--shading", "gouraud"], Acts),
        (&["--shading", "flat"], Acts),
        (&["--msaa", "4"], Acts),
        (&["--ssaa", "2"], Acts),
        (&["--unlit"], Acts),
        (&["--fov", "30"], Acts),
        (&["--ortho"], Acts),
        (&["--eye", "1,3,6"], Acts),
        (&["--auto-camera"], Acts),
        (&["--interp", "affine"], Acts),
        // Refused on every built-in scene: they take no files, triangle counts or volumes.
        (&["--lenient"], Refused),
        (&["--allow-outside-paths"], Refused),
        (&["--tris", "100"], Refused),
        (&["--tf", "ct-bone"], Refused),
        (&["--dolly", "2"], Refused),
        (&["--color-space", "linear"], Refused),
        (&["--subdivide-error", "0.2"], Refused),
    ];
    check(
        &d,
        "demo-mesh",
        &Case {
            scene: "builtin:demo",
            size: "48x32",
            base: &[],
        },
        acts,
    );
    check(
        &d,
        "plane-mesh",
        &Case {
            scene: "builtin:plane",
            // The checker's 64 repeats average to grey at a few dozen pixels.
            size: "160x90",
            base: &[],
        },
        &[
            (&["--interp", "subdivide", "--subdivide-error", "8"], Acts),
            // The plane is double-sided: culling cannot apply.
            (&["--cull", "back"], Refused),
        ],
    );
    check(
        &d,
        "shapes-mesh",
        &Case {
            scene: shapes.to_str().unwrap(),
            size: "48x32",
            base: &[],
        },
        &[
            (&["--cull", "front"], Acts),
            (&["--lenient"], Accepted),
            (&["--tris", "100"], Refused),
        ],
    );
    check(
        &d,
        "sphere-mesh",
        &Case {
            scene: "builtin:sphere",
            size: "48x32",
            base: &[],
        },
        &[(&["--tris", "100"], Acts)],
    );
}

/// A file without a camera seen from an eye far outside the automatic framing (or close in)
/// still draws: the near and far planes follow the eye.
#[test]
fn a_moved_eye_sees_the_whole_model() {
    let d = dir().join("moved-eye");
    std::fs::create_dir_all(&d).unwrap();
    let obj = write_obj(&d);
    for eye in ["40,30,50", "0,2,3", "-60,5,0"] {
        let out = d.join("eye.png");
        let o = texmap(&[
            "render",
            obj.to_str().unwrap(),
            "--eye",
            eye,
            "--target",
            "0,0,0",
            "--size",
            "64x48",
            "--stats",
            "-o",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let stats = String::from_utf8_lossy(&o.stdout);
        let clipped = stats
            .split("\"triangles_after_clip\":")
            .nth(1)
            .and_then(|t| t.trim_start().split([',', '}']).next())
            .and_then(|n| n.trim().parse::<u64>().ok())
            .expect("triangles_after_clip in --stats");
        assert_eq!(clipped, 2, "eye {eye}: {stats}");
    }
}

/// `--projectors` acts on a scene with projectors (off removes their light, on is the
/// default, so accepted), the shadow flags reach a casting projector, and `--projectors` is
/// refused where there is none.
#[test]
fn projector_flags_act_or_are_refused() {
    let d = dir();
    let projector = repo().join("scenes/projector.toml");
    check(
        &d,
        "projector",
        &Case {
            scene: projector.to_str().unwrap(),
            size: "64x36",
            base: &[],
        },
        &[
            (&["--projectors", "off"], Acts),
            (&["--projectors", "on"], Accepted),
            // Its one light does not cast; its projector does.
            (&["--shadows=false"], Acts),
            (&["--shadows"], Acts),
            (&["--shadow-filter", "hard"], Acts),
            (&["--shadow-light-radius", "0.3"], Refused),
            (
                &["--shadow-filter", "pcss", "--shadow-light-radius", "0.3"],
                Acts,
            ),
            (&["--shadows=false", "--projectors", "off"], Refused),
            (&["--filter", "nearest"], Acts),
        ],
    );
    check(
        &d,
        "demo-projectors",
        &Case {
            scene: "builtin:demo",
            size: "32x24",
            base: &[],
        },
        &[
            (&["--projectors", "off"], Refused),
            (&["--slice", "axial"], Refused),
        ],
    );
}

/// `--view` acts on a scene with its own camera and on a camera-less model, and is refused
/// beside the flags that place the camera too.
#[test]
fn standard_views_act_or_are_refused() {
    let d = dir();
    let shapes = repo().join("scenes/shapes.toml");
    let flags: &[(&[&str], Want)] = &[
        (&["--view", "front"], Acts),
        (&["--view", "top"], Acts),
        (&["--view", "iso", "--ortho"], Acts),
        (&["--view", "left", "--eye", "1,2,3"], Refused),
        (&["--view", "back", "--auto-camera"], Refused),
    ];
    check(
        &d,
        "views",
        &Case {
            scene: shapes.to_str().unwrap(),
            size: "48x32",
            base: &[],
        },
        flags,
    );
    let obj = write_obj(&d);
    check(
        &d,
        "views-obj",
        &Case {
            scene: obj.to_str().unwrap(),
            size: "48x32",
            base: &[],
        },
        &[(&["--view", "top"], Acts), (&["--view", "bottom"], Acts)],
    );
}
