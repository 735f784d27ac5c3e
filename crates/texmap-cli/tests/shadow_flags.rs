//! The shadow flags and keys from the command line: each acts (the image differs from the
//! same command without it) or is refused with exit code 1, one line on stderr naming the
//! flag or the file, and no output; `texmap info` lists the casting lights.

mod common;

use common::texmap;
use std::path::{Path, PathBuf};

/// A folder of this test's own (tests run in parallel and each removes its folder).
fn dir(test: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("texmap-shadow-{test}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn scene() -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes/shadows.toml")
        .to_string_lossy()
        .into_owned()
}

/// Renders `scene` at 96×64 with `flags` into `d/tag.png` and returns its pixels.
fn render(d: &Path, scene: &str, flags: &[&str], tag: &str) -> Vec<u8> {
    let out = d.join(format!("{tag}.png"));
    let out_s = out.to_string_lossy().into_owned();
    let mut args = vec!["render", scene, "--size", "96x64", "--quiet", "-o", &out_s];
    args.extend_from_slice(flags);
    let o = texmap(&args);
    assert!(
        o.status.success(),
        "{flags:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    image::open(&out).unwrap().to_rgb8().into_raw()
}

/// Asserts `args` fail with exit code 1, one stderr line containing `names`, no output.
fn refused(d: &Path, args: &[&str], names: &str, tag: &str) {
    let out = d.join(format!("{tag}.png"));
    let out_s = out.to_string_lossy().into_owned();
    let mut all = args.to_vec();
    all.extend(["--size", "96x64", "-o", &out_s]);
    let o = texmap(&all);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{args:?}: {err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{args:?}: {err}");
    assert!(
        err.contains(names),
        "{args:?}: {err:?} does not name {names}"
    );
    assert!(!out.exists(), "{args:?} wrote {}", out.display());
}

#[test]
fn every_shadow_flag_changes_the_image() {
    let d = dir("flags");
    let s = scene();
    let base = render(&d, &s, &[], "base");
    let pcss = render(&d, &s, &["--shadow-filter", "pcss"], "pcss");
    for (flags, against, name) in [
        (&["--shadows=false"][..], &base, "shadows-off"),
        (&["--shadow-filter", "hard"], &base, "hard"),
        (&["--shadow-filter", "pcf5"], &base, "pcf5"),
        (&["--shadow-filter", "poisson"], &base, "poisson"),
        (&["--shadow-map-size", "256"], &base, "size"),
        (&["--shadow-bias", "40"], &base, "bias"),
        (&["--shadow-slope-bias", "40"], &base, "slope"),
        (&["--shadow-normal-offset", "40"], &base, "offset"),
        (
            &["--shadow-filter", "pcss", "--shadow-light-angle", "12"],
            &pcss,
            "angle",
        ),
        (
            &["--shadow-filter", "pcss", "--shadow-light-radius", "0.4"],
            &pcss,
            "radius",
        ),
    ] {
        let img = render(&d, &s, flags, name);
        assert!(&img != against, "{flags:?} did not change the image");
    }
    assert!(pcss != base, "pcss did not change the image");
    // --shadows makes the lights of a scene that casts none cast.
    let demo_off = render(&d, "builtin:demo", &["--shadows=false"], "demo-off");
    let demo = render(&d, "builtin:demo", &[], "demo");
    assert!(demo != demo_off, "builtin:demo shows no shadows");
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn bad_shadow_map_sizes_are_one_line_naming_the_flag_or_file() {
    let d = dir("sizes");
    let s = scene();
    refused(
        &d,
        &["render", &s, "--shadow-map-size", "0"],
        "--shadow-map-size",
        "zero",
    );
    refused(
        &d,
        &["render", &s, "--shadow-map-size", "4097"],
        "--shadow-map-size",
        "big",
    );
    refused(
        &d,
        &[
            "render",
            &s,
            "--shadow-map-size",
            "4096",
            "--max-memory",
            "64M",
        ],
        "--max-memory",
        "budget",
    );
    let text = std::fs::read_to_string(&s).unwrap();
    for (size, tag) in [("0", "toml-zero"), ("8192", "toml-big")] {
        let file = d.join(format!("{tag}.toml"));
        std::fs::write(
            &file,
            text.replace("map_size = 2048", &format!("map_size = {size}")),
        )
        .unwrap();
        let f = file.to_string_lossy().into_owned();
        refused(&d, &["render", &f], &f, tag);
        refused(&d, &["render", &f], "map_size", tag);
    }
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn shadow_flags_that_cannot_act_are_refused() {
    let d = dir("refused");
    let s = scene();
    // builtin:plane's light casts nothing unless --shadows says so.
    refused(
        &d,
        &["render", "builtin:plane", "--shadow-filter", "pcf5"],
        "--shadow-filter",
        "no-caster",
    );
    refused(&d, &["render", &s, "--shadows"], "--shadows", "already");
    refused(
        &d,
        &["render", &s, "--shadow-light-angle", "5"],
        "--shadow-light-angle",
        "not-pcss",
    );
    refused(
        &d,
        &["render", &s, "--shadow-bias=-1"],
        "--shadow-bias",
        "negative",
    );
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn info_lists_the_casting_lights() {
    let o = texmap(&["info", &scene()]);
    assert!(o.status.success());
    let text = String::from_utf8_lossy(&o.stdout);
    let line = text
        .lines()
        .find(|l| l.starts_with("shadows:"))
        .unwrap_or_else(|| panic!("no shadows line in {text}"));
    assert!(
        line.contains("3 cast")
            && line.contains("directional")
            && line.contains("spot")
            && line.contains("cube of six")
            && line.contains("pcf3")
            && line.contains("2048"),
        "{line}"
    );
}
