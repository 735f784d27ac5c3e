//! Batch rendering: frame numbering, shards (explicit, Slurm's and Kubernetes' variables)
//! whose union is one process's render byte for byte, many inputs, resume after a kill,
//! the manifest and its verification, animations, and bad input refused before rendering.

mod common;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn texmap_cmd(args: &[&str]) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_texmap"));
    c.args(args);
    for v in [
        "SLURM_ARRAY_TASK_ID",
        "SLURM_ARRAY_TASK_MIN",
        "SLURM_ARRAY_TASK_STEP",
        "SLURM_ARRAY_TASK_COUNT",
        "JOB_COMPLETION_INDEX",
    ] {
        c.env_remove(v);
    }
    c
}

fn texmap(args: &[&str]) -> Output {
    texmap_cmd(args).output().expect("the texmap binary runs")
}

fn ok(r: &Output) {
    assert!(
        r.status.success(),
        "exit {:?}: {}",
        r.status.code(),
        String::from_utf8_lossy(&r.stderr)
    );
}

fn dir(name: &str) -> PathBuf {
    common::fresh_dir("batch", name)
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn shapes() -> &'static Path {
    static SHAPES: std::sync::OnceLock<PathBuf> = std::sync::OnceLock::new();
    SHAPES.get_or_init(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/shapes.toml"))
}

/// Every file of `d` (names not starting with '.') and its bytes; manifests left out.
fn files(d: &Path) -> BTreeMap<String, Vec<u8>> {
    std::fs::read_dir(d)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| {
            let n = p.file_name().unwrap().to_string_lossy();
            !n.starts_with('.') && !n.ends_with(".jsonl")
        })
        .map(|p| {
            (
                p.file_name().unwrap().to_string_lossy().into_owned(),
                std::fs::read(&p).unwrap(),
            )
        })
        .collect()
}

/// Union of the shards' folders; panics on a name written by two shards.
fn union(dirs: &[PathBuf]) -> BTreeMap<String, Vec<u8>> {
    let mut all = BTreeMap::new();
    for d in dirs {
        for (name, bytes) in files(d) {
            assert!(
                all.insert(name.clone(), bytes).is_none(),
                "{name} written by two shards"
            );
        }
    }
    all
}

const SIZE: &str = "32x24";

#[test]
fn frame_one_is_the_requested_view_and_ranges_select_frames() {
    let d = dir("frames");
    let one = d.join("one.png");
    ok(&texmap(&[
        "render",
        s(shapes()),
        "--size",
        SIZE,
        "--quiet",
        "-o",
        s(&one),
    ]));
    let pattern = d.join("t_{frame:06}.png");
    ok(&texmap(&[
        "render",
        s(shapes()),
        "--size",
        SIZE,
        "--frames",
        "4",
        "--quiet",
        "-o",
        s(&pattern),
    ]));
    let first = std::fs::read(d.join("t_000001.png")).unwrap();
    assert_eq!(first, std::fs::read(&one).unwrap(), "frame 1 is the view");
    let last = std::fs::read(d.join("t_000004.png")).unwrap();
    assert_ne!(last, first, "frame 4 is turned by 270°");
    // A range renders only its frames, the same bytes as the whole turntable's.
    let sub = dir("frames-range");
    ok(&texmap(&[
        "render",
        s(shapes()),
        "--size",
        SIZE,
        "--frames",
        "4",
        "--frame-range",
        "3..4",
        "--quiet",
        "-o",
        s(&sub.join("t_{frame:06}.png")),
    ]));
    let got = files(&sub);
    assert_eq!(
        got.keys().collect::<Vec<_>>(),
        ["t_000003.png", "t_000004.png"]
    );
    assert_eq!(got["t_000004.png"], last);
}

/// Renders `--frames 12` of shapes.toml into `out`, with `extra` flags and `env`.
fn frames_run(out: &Path, extra: &[&str], env: &[(&str, &str)]) -> Output {
    let pattern = out.join("f_{frame}.png");
    let manifest = out.join("m.jsonl");
    let mut args = vec![
        "render",
        s(shapes()),
        "--size",
        SIZE,
        "--frames",
        "12",
        "--quiet",
        "--manifest",
        s(&manifest),
        "-o",
        s(&pattern),
    ];
    args.extend_from_slice(extra);
    let mut c = texmap_cmd(&args);
    for (k, v) in env {
        c.env(k, v);
    }
    c.output().unwrap()
}

#[test]
fn shards_of_a_frame_list_make_the_single_render() {
    let single = dir("frames-single");
    ok(&frames_run(&single, &[], &[]));
    let expected = files(&single);
    assert_eq!(expected.len(), 12);
    // --shard I/N, Slurm's array variables (ids 10..=14, 5 tasks) and Kubernetes' index.
    let mut ways: Vec<Vec<PathBuf>> = Vec::new();
    let mut explicit = Vec::new();
    for i in 1..=5 {
        let d = dir(&format!("frames-shard-{i}"));
        ok(&frames_run(&d, &["--shard", &format!("{i}/5")], &[]));
        explicit.push(d);
    }
    ways.push(explicit);
    let mut slurm = Vec::new();
    for id in 10..=14 {
        let d = dir(&format!("frames-slurm-{id}"));
        let id = id.to_string();
        ok(&frames_run(
            &d,
            &["--shard", "auto"],
            &[
                ("SLURM_ARRAY_TASK_ID", &id),
                ("SLURM_ARRAY_TASK_MIN", "10"),
                ("SLURM_ARRAY_TASK_COUNT", "5"),
            ],
        ));
        slurm.push(d);
    }
    ways.push(slurm);
    let mut k8s = Vec::new();
    for i in 0..5 {
        let d = dir(&format!("frames-k8s-{i}"));
        let i = i.to_string();
        ok(&frames_run(
            &d,
            &["--shard", "auto", "--shard-count", "5"],
            &[("JOB_COMPLETION_INDEX", &i)],
        ));
        k8s.push(d);
    }
    ways.push(k8s);
    for dirs in &ways {
        assert_eq!(union(dirs), expected);
        // The shards' manifests together: every frame once, every hash right.
        let manifests: Vec<PathBuf> = dirs.iter().map(|d| d.join("m.jsonl")).collect();
        let mut args = vec!["manifest", "verify"];
        args.extend(manifests.iter().map(|m| s(m)));
        let r = texmap(&args);
        ok(&r);
        assert!(String::from_utf8_lossy(&r.stdout).contains("12 outputs"));
    }
    // A shard's manifest alone misses frames: verify says so.
    let r = texmap(&["manifest", "verify", s(&ways[0][0].join("m.jsonl"))]);
    assert_eq!(r.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&r.stderr).contains("missing"));
}

#[test]
fn shards_running_at_once_share_one_manifest() {
    let d = dir("shared-manifest");
    let manifest = d.join("m.jsonl");
    let pattern = d.join("f_{frame}.png");
    let children: Vec<_> = (1..=4)
        .map(|i| {
            texmap_cmd(&[
                "render",
                s(shapes()),
                "--size",
                SIZE,
                "--frames",
                "40",
                "--quiet",
                "--threads",
                "1",
                "--shard",
                &format!("{i}/4"),
                "--manifest",
                s(&manifest),
                "-o",
                s(&pattern),
            ])
            .spawn()
            .unwrap()
        })
        .collect();
    for mut c in children {
        assert!(c.wait().unwrap().success());
    }
    // Whole lines only (one append each), every frame once.
    let text = std::fs::read_to_string(&manifest).unwrap();
    assert_eq!(text.lines().count(), 40);
    for line in text.lines() {
        serde_json::from_str::<serde_json::Value>(line).expect("a whole JSON line");
    }
    let r = texmap(&["manifest", "verify", s(&manifest)]);
    ok(&r);
    assert!(String::from_utf8_lossy(&r.stdout).contains("verified 40 outputs"));
}

/// A folder of four small scenes.
fn models(d: &Path) -> PathBuf {
    let m = d.join("models");
    std::fs::create_dir_all(&m).unwrap();
    let text = std::fs::read_to_string(shapes()).unwrap();
    for name in ["a", "b", "c", "d"] {
        std::fs::write(m.join(format!("{name}.toml")), &text).unwrap();
    }
    std::fs::write(m.join("notes.txt"), "not a model").unwrap();
    m
}

#[test]
fn shards_of_a_file_list_make_the_single_render() {
    let d = dir("files");
    let folder = models(&d);
    let list = d.join("list.txt");
    let names: Vec<String> = ["a", "b", "c", "d"]
        .iter()
        .map(|n| s(&folder.join(format!("{n}.toml"))).to_string())
        .collect();
    std::fs::write(&list, format!("# models\n{}\n\n", names.join("\n"))).unwrap();
    let run = |out: &Path, input: &[&str], extra: &[&str]| {
        let pattern = out.join("{scene}.png");
        let mut args = vec!["render", "--size", SIZE, "--quiet", "-o", s(&pattern)];
        args.extend_from_slice(input);
        args.extend_from_slice(extra);
        ok(&texmap(&args));
    };
    let single = dir("files-single");
    run(&single, &[s(&folder)], &[]);
    let expected = files(&single);
    assert_eq!(
        expected.keys().collect::<Vec<_>>(),
        ["a.png", "b.png", "c.png", "d.png"]
    );
    // The folder, the list and the names as arguments, each in three shards.
    let args: Vec<&str> = names.iter().map(String::as_str).collect();
    for (k, input) in [vec![s(&folder)], vec!["--list", s(&list)], args]
        .iter()
        .enumerate()
    {
        let dirs: Vec<PathBuf> = (1..=3)
            .map(|i| {
                let o = dir(&format!("files-{k}-{i}"));
                run(&o, input, &["--shard", &format!("{i}/3")]);
                o
            })
            .collect();
        assert_eq!(union(&dirs), expected);
    }
}

#[test]
fn a_killed_shard_resumes_with_skip_existing() {
    let run = |out: &Path, extra: &[&str]| {
        let pattern = out.join("f_{frame}.png");
        let manifest = out.join("m.jsonl");
        let mut args = vec![
            "render",
            s(shapes()),
            "--size",
            SIZE,
            "--frames",
            "300",
            "--quiet",
            "--threads",
            "1",
            "--manifest",
            s(&manifest),
            "-o",
            s(&pattern),
        ];
        args.extend_from_slice(extra);
        texmap_cmd(&args)
    };
    let single = dir("kill-single");
    ok(&run(&single, &[]).output().unwrap());
    let expected = files(&single);
    assert_eq!(expected.len(), 300);
    let first = dir("kill-first");
    ok(&run(&first, &["--shard", "1/2"]).output().unwrap());
    for (signal, name) in [("KILL", "kill"), ("TERM", "term")] {
        let d = dir(&format!("kill-{name}"));
        let child = run(&d, &["--shard", "2/2"])
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        // Wait for a few frames, then stop it half-way.
        while std::fs::read_dir(&d).unwrap().count() < 20 {
            std::thread::sleep(std::time::Duration::from_millis(5));
        }
        let killed = Command::new("kill")
            .args([&format!("-{signal}"), &child.id().to_string()])
            .status()
            .unwrap();
        assert!(killed.success());
        let out = child.wait_with_output().unwrap();
        let part = files(&d);
        if signal == "TERM" {
            // Stopped between outputs: a line saying how far, exit 128 + 15.
            assert_eq!(out.status.code(), Some(143));
            let err = String::from_utf8_lossy(&out.stderr);
            assert!(
                err.contains("stopped by SIGTERM") && err.contains("written"),
                "{err}"
            );
            // Every finished file has its manifest line.
            let lines = std::fs::read_to_string(d.join("m.jsonl")).unwrap();
            assert_eq!(lines.lines().count(), part.len());
        }
        assert!(part.len() < 150, "stopped half-way ({} files)", part.len());
        for (name, bytes) in &part {
            assert_eq!(bytes, &expected[name], "{name} is whole");
        }
        let r = run(&d, &["--shard", "2/2", "--skip-existing"])
            .output()
            .unwrap();
        ok(&r);
        assert_eq!(union(&[first.clone(), d.clone()]), expected);
        let (m1, m2) = (first.join("m.jsonl"), d.join("m.jsonl"));
        let r = texmap(&["manifest", "verify", s(&m1), s(&m2)]);
        ok(&r);
        assert!(String::from_utf8_lossy(&r.stdout).contains("300 outputs"));
        // A file changed afterwards is found by verify, and rendered again by a resume.
        let victim = d.join("f_0200.png");
        std::fs::write(&victim, b"not a png").unwrap();
        let r = texmap(&["manifest", "verify", s(&m1), s(&m2)]);
        assert_eq!(r.status.code(), Some(1));
        assert!(String::from_utf8_lossy(&r.stderr).contains("f_0200.png"));
        ok(&run(&d, &["--shard", "2/2", "--skip-existing"])
            .output()
            .unwrap());
        assert_eq!(std::fs::read(&victim).unwrap(), expected["f_0200.png"]);
    }
}

#[test]
fn a_failed_input_is_reported_and_the_rest_render() {
    let d = dir("fail");
    let folder = models(&d);
    let bad = folder.join("b.toml");
    std::fs::write(&bad, "this is = not [a scene").unwrap();
    let r = texmap(&[
        "render",
        s(&folder),
        "--size",
        SIZE,
        "-o",
        s(&d.join("{scene}.png")),
    ]);
    assert_eq!(r.status.code(), Some(1));
    let err = String::from_utf8_lossy(&r.stderr);
    assert!(err.contains("b.toml"), "{err}");
    assert!(err.contains("1 input failed"), "{err}");
    for n in ["a", "c", "d"] {
        assert!(d.join(format!("{n}.png")).exists());
    }
    assert!(!d.join("b.png").exists());
}

#[test]
fn animations_and_bit_depths() {
    let d = dir("anim");
    let run = |out: &str, extra: &[&str]| {
        let mut args = vec![
            "render",
            s(shapes()),
            "--size",
            SIZE,
            "--frames",
            "3",
            "--quiet",
            "-o",
        ];
        let out = d.join(out);
        args.push(s(&out));
        args.extend_from_slice(extra);
        ok(&texmap(&args));
        out
    };
    let png1 = run("p_{frame}.png", &[]);
    let _ = png1;
    let reference = image::open(d.join("p_0001.png")).unwrap().to_rgb8();
    // APNG: three frames, the first the PNG's pixels.
    use image::AnimationDecoder;
    let apng = run("t.apng", &[]);
    let decoder = image::codecs::png::PngDecoder::new(std::io::BufReader::new(
        std::fs::File::open(&apng).unwrap(),
    ))
    .unwrap();
    let frames: Vec<_> = decoder
        .apng()
        .unwrap()
        .into_frames()
        .map(Result::unwrap)
        .collect();
    assert_eq!(frames.len(), 3);
    let first = image::DynamicImage::ImageRgba8(frames[0].buffer().clone()).to_rgb8();
    assert_eq!(first, reference);
    // GIF: three frames of the size, within a palette's error of the PNG.
    let gif = run("t.gif", &["--fps", "10"]);
    let decoder = image::codecs::gif::GifDecoder::new(std::io::BufReader::new(
        std::fs::File::open(&gif).unwrap(),
    ))
    .unwrap();
    let frames: Vec<_> = decoder.into_frames().map(Result::unwrap).collect();
    assert_eq!(frames.len(), 3);
    assert_eq!(frames[0].delay().numer_denom_ms(), (100, 1));
    let g = image::DynamicImage::ImageRgba8(frames[0].buffer().clone()).to_rgb8();
    let mse: f64 = g
        .as_raw()
        .iter()
        .zip(reference.as_raw())
        .map(|(&a, &b)| (f64::from(a) - f64::from(b)).powi(2))
        .sum::<f64>()
        / g.as_raw().len() as f64;
    let psnr = 10.0 * (255.0f64 * 255.0 / mse.max(1e-9)).log10();
    assert!(psnr > 30.0, "GIF frame PSNR {psnr:.1} dB");
    // 16-bit PNG: its top byte rounds to the 8-bit PNG's value.
    run("w_{frame}.png", &["--bit-depth", "16"]);
    let wide = image::open(d.join("w_0001.png")).unwrap().to_rgb16();
    for (w, n) in wide.as_raw().iter().zip(reference.as_raw()) {
        assert!((f64::from(*w) / 257.0 - f64::from(*n)).abs() <= 0.5 + 1e-9);
    }
    // JPEG at a quality.
    run("j_{frame}.jpg", &["--quality", "95"]);
    let j = image::open(d.join("j_0001.jpg")).unwrap();
    assert_eq!((j.width(), j.height()), (32, 24));
}

#[test]
fn bad_batches_are_one_line_before_rendering() {
    let d = dir("bad");
    let empty = dir("bad-empty");
    let out = d.join("o_{frame}.png");
    let missing_list = d.join("no-list.txt");
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec!["--shard", "3/2"], "--shard 3/2"),
        (
            vec!["--frames", "10", "--frame-range", "9..2"],
            "--frame-range 9..2",
        ),
        (
            vec!["--frames", "10", "--frame-range", "1..11"],
            "--frame-range",
        ),
        (vec!["--list", s(&missing_list)], "no-list.txt"),
        (vec![s(&empty)], "no model"),
        (vec!["--shard", "auto"], "SLURM_ARRAY_TASK_ID"),
        (vec!["--shard", "auto"], "JOB_COMPLETION_INDEX"),
        (vec!["-o", "x.webp"], ".webp"),
        (vec!["--frames", "3", "-o", "x.png"], "{frame}"),
        (vec!["-o", "x_{frames}.png"], "unknown placeholder"),
        (
            vec!["builtin:demo", "builtin:marble", "-o", "x.png"],
            "{scene}",
        ),
        (vec!["--alpha", "-o", "x.jpg"], "--alpha"),
        (vec!["--bit-depth", "16", "-o", "x.jpg"], "--bit-depth"),
        (vec!["--quality", "80", "-o", "x.png"], "--quality"),
    ];
    for (extra, needle) in cases {
        let mut args = vec!["render", "--size", "8x8"];
        if !extra.contains(&"-o") {
            args.extend(["-o", s(&out)]);
        }
        args.extend_from_slice(&extra);
        let r = texmap(&args);
        let err = String::from_utf8_lossy(&r.stderr);
        assert_eq!(r.status.code(), Some(1), "{extra:?}: {err}");
        assert_eq!(err.lines().count(), 1, "{extra:?}: {err}");
        assert!(err.contains(needle), "{extra:?}: {err}");
        assert!(files(&d).is_empty(), "{extra:?} wrote nothing");
    }
}

#[test]
fn discard_renders_every_frame_back_to_back_and_writes_nothing() {
    let d = dir("discard");
    let run = |args: &[&str]| texmap_cmd(args).current_dir(&d).output().unwrap();
    // The default output names (texmap-{scene}-{frame}.png) would land in `d`.
    let r = run(&[
        "render",
        "builtin:plane",
        "--frames",
        "3",
        "--discard",
        "--stats",
        "--size",
        SIZE,
    ]);
    ok(&r);
    let json: serde_json::Value = serde_json::from_slice(&r.stdout).unwrap();
    assert_eq!(json["frames"], 3, "{json}");
    assert_eq!(json["frame_ms_all"].as_array().unwrap().len(), 3, "{json}");
    assert!(json["output"].is_null(), "{json}");
    assert!(json["pixels_shaded"].as_u64().unwrap() > 0, "{json}");
    // Several inputs: each rendered, the summary says so.
    let r = run(&[
        "render",
        "builtin:demo",
        "builtin:plane",
        "--discard",
        "--size",
        SIZE,
    ]);
    ok(&r);
    let err = String::from_utf8_lossy(&r.stderr);
    assert!(err.contains("2 rendered and discarded"), "{err}");
    assert!(err.contains("wrote nothing (--discard)"), "{err}");
    assert!(
        files(&d).is_empty(),
        "--discard wrote {:?}",
        files(&d).keys()
    );
    // The output's options are refused with it: one line naming the option, nothing written.
    let manifest = d.join("m.jsonl");
    for (extra, needle) in [
        (vec!["-o", "x.png"], "-o"),
        (vec!["--format", "exr"], "--format"),
        (vec!["--manifest", s(&manifest)], "--manifest"),
        (vec!["--skip-existing"], "--skip-existing"),
        (vec!["--bit-depth", "16"], "--bit-depth"),
        (vec!["--quality", "80"], "--quality"),
        (vec!["--fps", "10"], "--fps"),
    ] {
        let mut args = vec!["render", "--size", "8x8", "--discard"];
        args.extend_from_slice(&extra);
        let r = run(&args);
        let err = String::from_utf8_lossy(&r.stderr);
        assert_eq!(r.status.code(), Some(1), "{extra:?}: {err}");
        assert_eq!(err.lines().count(), 1, "{extra:?}: {err}");
        assert!(
            err.contains(needle) && err.contains("--discard"),
            "{extra:?}: {err}"
        );
        assert!(!manifest.exists() && files(&d).is_empty(), "{extra:?}");
    }
}
