//! The surface-relief flags and tables: `--normal-maps`, `--bump-maps`, `--parallax`,
//! `--displacement`, `--displace-level`, `--displace-edge` each change the image of a scene
//! that has what they switch, or are refused (exit 1, one line, no output) where it has
//! nothing; a tessellation over the triangle budget and bad relief tables are one line;
//! `texmap info` lists parallax and displacement.

mod common;

use common::texmap;
use std::path::{Path, PathBuf};
use std::process::Output;

/// A folder of this test's own (tests run in parallel).
fn dir(test: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("texmap-relief-{test}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn scene(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join(format!("../../scenes/{name}.toml"))
        .to_string_lossy()
        .into_owned()
}

fn run(d: &Path, scene: &str, flags: &[&str], tag: &str) -> (Output, PathBuf) {
    let out = d.join(format!("{tag}.png"));
    let out_s = out.to_string_lossy().into_owned();
    let mut args = vec!["render", scene, "--size", "96x64", "--quiet", "-o", &out_s];
    args.extend_from_slice(flags);
    (texmap(&args), out)
}

/// Renders and returns the PNG's bytes.
fn render(d: &Path, scene: &str, flags: &[&str], tag: &str) -> Vec<u8> {
    let (o, out) = run(d, scene, flags, tag);
    assert!(
        o.status.success(),
        "{flags:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    std::fs::read(out).unwrap()
}

#[track_caller]
fn refused(d: &Path, scene: &str, flags: &[&str], needles: &[&str]) {
    let (o, out) = run(d, scene, flags, "refused");
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{flags:?}: {err}");
    assert_eq!(err.trim().lines().count(), 1, "one line: {err}");
    assert!(!err.contains("panicked"), "{err}");
    for n in needles {
        assert!(err.contains(n), "{n:?} in {err}");
    }
    assert!(!out.exists(), "no output for {flags:?}");
}

#[test]
fn each_relief_flag_changes_the_image_of_a_scene_that_has_it() {
    let d = dir("act");
    for (name, flags) in [
        (
            "parallax",
            &[
                &["--parallax", "off"][..],
                &["--parallax", "offset"],
                &["--normal-maps", "off"],
                &["--parallax-shadows", "on"],
            ][..],
        ),
        (
            "displacement",
            &[
                &["--displacement", "off"][..],
                &["--displace-level", "2"],
                &["--displace-edge", "40"],
            ],
        ),
        ("normal", &[&["--normal-maps", "off"][..]]),
        (
            "bump",
            &[&["--bump-maps", "off"][..], &["--normal-maps", "off"]],
        ),
    ] {
        let s = scene(name);
        let base = render(&d, &s, &[], &format!("{name}-base"));
        for (i, f) in flags.iter().enumerate() {
            let img = render(&d, &s, f, &format!("{name}-{i}"));
            assert_ne!(img, base, "{name}: {f:?} changed nothing");
        }
        // The default spelled out is the default.
        let same: &[&str] = match name {
            "parallax" => &["--parallax", "occlusion"],
            "displacement" => &["--displacement", "on"],
            _ => &["--normal-maps", "on"],
        };
        assert_eq!(
            render(&d, &s, same, &format!("{name}-same")),
            base,
            "{name}: {same:?}"
        );
    }
    let _ = std::fs::remove_dir_all(d);
}

#[test]
fn relief_flags_are_refused_where_the_scene_has_nothing_to_switch() {
    let d = dir("refused");
    refused(
        &d,
        &scene("normal"),
        &["--parallax", "off"],
        &["--parallax", "parallax"],
    );
    refused(
        &d,
        &scene("parallax"),
        &["--displacement", "on"],
        &["--displacement"],
    );
    // parallax.toml's material is not self-shadowed: off changes nothing.
    refused(
        &d,
        &scene("parallax"),
        &["--parallax-shadows", "off"],
        &["--parallax-shadows", "already"],
    );
    refused(
        &d,
        &scene("normal"),
        &["--parallax-shadows", "on"],
        &["--parallax-shadows", "parallax"],
    );
    refused(
        &d,
        &scene("parallax"),
        &["--displace-level", "2"],
        &["--displace-level"],
    );
    refused(
        &d,
        &scene("displacement"),
        &["--normal-maps", "off"],
        &["--normal-maps"],
    );
    refused(
        &d,
        &scene("normal"),
        &["--bump-maps", "on"],
        &["--bump-maps"],
    );
    refused(
        &d,
        &scene("displacement"),
        &["--displacement", "off", "--displace-level", "2"],
        &["--displacement on"],
    );
    refused(
        &d,
        &scene("displacement"),
        &["--displace-level", "11"],
        &["--displace-level 11"],
    );
    refused(
        &d,
        &scene("displacement"),
        &["--displace-edge", "0"],
        &["--displace-edge"],
    );
    let _ = std::fs::remove_dir_all(d);
}

#[test]
fn a_displacement_over_the_triangle_budget_is_one_line_and_no_output() {
    let d = dir("budget");
    refused(
        &d,
        &scene("displacement"),
        &["--displace-level", "10"],
        &["displacement.toml", "budget", "triangles"],
    );
    let _ = std::fs::remove_dir_all(d);
}

#[test]
fn bad_relief_tables_are_one_line_naming_the_file_and_table() {
    let d = dir("tables");
    let height =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/relief/bricks_height.png");
    let height = height.to_string_lossy().replace('\\', "/");
    for (table, needle) in [
        (format!("[materials.m.parallax]\nmap = {{ file = \"{height}\" }}\nmode = \"steep\""), "mode"),
        (format!("[materials.m.parallax]\nmap = {{ file = \"{height}\" }}\nmin_steps = 9\nmax_steps = 4"), "min_steps"),
        (format!("[materials.m.displacement]\nmap = {{ file = \"{height}\" }}\nlevel = 2\nedge_px = 3"), "edge_px"),
        (format!("[materials.m.displacement]\nmap = {{ file = \"{height}\" }}\nbase = 2"), "base"),
    ] {
        let path = d.join("bad.toml");
        let body = format!("{table}\n\n[[meshes]]\nprimitive = \"plane\"\nmaterial = \"m\"\n");
        std::fs::write(&path, body).unwrap();
        refused(&d, &path.to_string_lossy(), &[], &["bad.toml", needle]);
    }
    let _ = std::fs::remove_dir_all(d);
}

#[test]
fn info_lists_parallax_and_displacement() {
    let o = texmap(&["info", &scene("parallax")]);
    let s = String::from_utf8_lossy(&o.stdout);
    assert!(
        s.contains("parallax occlusion 256x256 scale 0.06 base 1 steps 8..32"),
        "{s}"
    );
    let o = texmap(&["info", &scene("displacement")]);
    let s = String::from_utf8_lossy(&o.stdout);
    assert!(
        s.contains("displacement 256x256 scale 0.08 base 0 level 4"),
        "{s}"
    );
    let o = texmap(&["info", &scene("normal")]);
    let s = String::from_utf8_lossy(&o.stdout);
    assert!(s.contains("normal_object 256x256"), "{s}");
}
