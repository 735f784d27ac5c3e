//! Virtual textures from the command line: a scene's `virtual_texture` table renders, the
//! page counts are in `--stats`, paged reads equal the texture held whole (`resident =
//! true`), `texmap info` prints the size and pages, and bad budgets, filters and wraps are
//! one line, exit 1 and no output.

mod common;

use common::texmap;
use std::path::{Path, PathBuf};
use std::process::Output;

fn dir(name: &str) -> PathBuf {
    common::fresh_dir("vt", name)
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// A floor with a `size`² quadtree on it; `extra` lines go into the table.
fn scene(dir: &Path, name: &str, size: u32, extra: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(
        &path,
        format!(
            r#"[[cameras]]
eye = [0.0, 0.3, 0.0]
target = [0.2, 0.0, -2.0]
fov = 60
near = 0.01

[materials.floor]
unlit = true

[materials.floor.virtual_texture]
pattern = "quadtree"
size = {size}
{extra}

[[meshes]]
primitive = "plane"
size = 8
material = "floor"
"#
        ),
    )
    .unwrap();
    path
}

/// One line on stderr, exit 1, `out` not written; the line returned.
fn refused(o: &Output, out: &Path) -> String {
    let err = String::from_utf8_lossy(&o.stderr).to_string();
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(!out.exists(), "{} written", out.display());
    err
}

fn psnr(a: &Path, b: &Path) -> f64 {
    let (a, b) = (
        image::open(a).unwrap().to_rgb8(),
        image::open(b).unwrap().to_rgb8(),
    );
    let (w, h) = a.dimensions();
    texmap::metrics::compare_rgb8(a.as_raw(), b.as_raw(), w as usize, h as usize, None).psnr_db
}

#[test]
fn a_paged_render_reports_its_pages_and_equals_the_texture_held_whole() {
    let d = dir("render");
    let paged = scene(&d, "paged.toml", 1024, "budget_mib = 8");
    let whole = scene(&d, "whole.toml", 1024, "resident = true");
    let (a, b) = (d.join("a.png"), d.join("b.png"));
    let o = texmap(&[
        "render",
        s(&paged),
        "--size",
        "160x90",
        "-o",
        s(&a),
        "--stats",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let stats: serde_json::Value =
        serde_json::from_str(String::from_utf8_lossy(&o.stdout).lines().next().unwrap()).unwrap();
    let vt = &stats["virtual_texture"];
    assert!(vt["pages_loaded"].as_u64().unwrap() > 0, "{stats}");
    assert_eq!(vt["pages_evicted"].as_u64(), Some(0));
    assert_eq!(vt["budget_bytes"].as_u64(), Some(8 << 20));
    assert_eq!(vt["fallback_reads"].as_u64(), Some(0));
    let o = texmap(&["render", s(&whole), "--size", "160x90", "-o", s(&b)]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let db = psnr(&a, &b);
    assert!(db >= 45.0, "{db:.2} dB");

    // A budget of 14 pages (8 of them the pinned levels of 128² and below) evicts over a
    // turntable and says so.
    let c = d.join("c-{frame}.png");
    let o = texmap(&[
        "render",
        s(&paged),
        "--size",
        "160x90",
        "-o",
        s(&c),
        "--stats",
        "--vt-budget",
        "2M",
        "--frames",
        "3",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let stats: serde_json::Value =
        serde_json::from_str(String::from_utf8_lossy(&o.stdout).lines().next().unwrap()).unwrap();
    let vt = &stats["virtual_texture"];
    assert_eq!(vt["slots"].as_u64(), Some(14), "{stats}");
    assert!(
        vt["all_frames"]["pages_evicted"].as_u64().unwrap() > 0,
        "{stats}"
    );
    assert_eq!(vt["pages_resident"].as_u64(), Some(14), "{stats}");
}

#[test]
fn info_prints_the_size_and_the_pages() {
    let d = dir("info");
    let p = scene(&d, "big.toml", 65536, "");
    let o = texmap(&["info", s(&p)]);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(out.contains("virtual textures: 1"), "{out}");
    assert!(out.contains("65536x65536, 17 levels"), "{out}");
    assert!(out.contains("levels 9..16 are one page each"), "{out}");
    assert!(out.contains("budget 64.00 MiB = 453 pages"), "{out}");
    assert!(out.contains("base_color virtual 65536x65536"), "{out}");
}

#[test]
fn bad_budgets_filters_and_wraps_are_refused() {
    let d = dir("bad");
    let out = d.join("out.png");
    let p = scene(&d, "ok.toml", 65536, "");
    let render = |extra: &[&str]| {
        let mut args = vec!["render", s(&p), "--size", "64x36", "-o", s(&out)];
        args.extend_from_slice(extra);
        texmap(&args)
    };
    let e = refused(&render(&["--vt-budget", "1M"]), &out);
    assert!(e.contains("--vt-budget") && e.contains("too small"), "{e}");
    let e = refused(&render(&["--vt-budget", "2G", "--max-memory", "1G"]), &out);
    assert!(
        e.contains("page caches take 2048 MiB") && e.contains("--max-memory"),
        "{e}"
    );
    let e = refused(&render(&["--filter", "ewa"]), &out);
    assert!(e.contains("not ewa"), "{e}");
    let e = refused(&render(&["--filter", "sat"]), &out);
    assert!(e.contains("not sat"), "{e}");
    let e = refused(&render(&["--wrap", "clamp"]), &out);
    assert!(e.contains("wraps repeat/repeat"), "{e}");
    let e = refused(
        &texmap(&[
            "render",
            "builtin:plane",
            "--vt-budget",
            "8M",
            "-o",
            s(&out),
        ]),
        &out,
    );
    assert!(
        e.contains("--vt-budget") && e.contains("no virtual texture"),
        "{e}"
    );
    for (extra, says) in [
        ("budget_mib = 0.5", "too small"),
        ("budget_mib = -1", "budget_mib"),
        ("filter = \"ewa\"", "not ewa"),
        ("wrap = \"mirror\"", "repeat or clamp"),
        ("resident = true", "too large to hold whole"),
    ] {
        let bad = scene(&d, "bad.toml", 65536, extra);
        let o = texmap(&["render", s(&bad), "--size", "64x36", "-o", s(&out)]);
        let e = refused(&o, &out);
        assert!(
            e.contains("virtual_texture") && e.contains(says),
            "{extra}: {e}"
        );
    }
    for (size, pattern) in [(1000, "quadtree"), (1024, "marble")] {
        let bad = d.join("bad.toml");
        let text = std::fs::read_to_string(scene(&d, "bad.toml", size, ""))
            .unwrap()
            .replace("\"quadtree\"", &format!("{pattern:?}"));
        std::fs::write(&bad, text).unwrap();
        let e = refused(
            &texmap(&["render", s(&bad), "--size", "64x36", "-o", s(&out)]),
            &out,
        );
        assert!(e.contains("virtual_texture"), "{e}");
    }
}
