//! Hostile and broken input, one case per cause: each must end with exit code 1, one line on
//! stderr naming the file or flag, no panic and no output file — or, where the case is a
//! stream that went away, end quietly. (The causes were found by fuzzing the command line.)

mod common;

use common::texmap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

fn dir(case: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("texmap-faults-{}-{case}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Exit 1, one line naming each of `needles`, no panic, `output` not written.
#[track_caller]
fn assert_refused(out: &Output, needles: &[&str], output: &Path) {
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert_eq!(err.trim().lines().count(), 1, "one line: {err}");
    assert!(!err.contains("panicked"), "{err}");
    for n in needles {
        assert!(err.contains(n), "{n:?} in {err}");
    }
    assert!(!output.exists(), "no output");
}

fn render(args: &[&str], out: &Path) -> Output {
    let mut v = args.to_vec();
    v.extend(["--size", "32x24", "--quiet", "-o", out.to_str().unwrap()]);
    let mut all = vec!["render"];
    all.extend(v);
    texmap(&all)
}

fn triangle_obj(d: &Path, name: &str, vertex: &str) -> PathBuf {
    let p = d.join(name);
    std::fs::write(&p, format!("v {vertex}\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")).unwrap();
    p
}

#[test]
fn an_mtl_colour_with_two_numbers_is_named_not_a_panic() {
    let d = dir("mtl");
    std::fs::write(d.join("a.mtl"), "newmtl m\nKs 0 0\n").unwrap();
    let obj = d.join("a.obj");
    std::fs::write(
        &obj,
        "mtllib a.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl m\nf 1 2 3\n",
    )
    .unwrap();
    let out = d.join("a.png");
    assert_refused(
        &render(&[obj.to_str().unwrap()], &out),
        &["a.mtl", "line 2", "Ks"],
        &out,
    );
    let info = texmap(&["info", obj.to_str().unwrap()]);
    assert_refused(&info, &["a.mtl"], &out);
}

#[test]
fn a_closed_stdout_ends_quietly_and_a_full_device_is_one_line() {
    let d = dir("stdout");
    let png = d.join("s.png");
    // The reader goes away before texmap writes its statistics.
    let mut child = Command::new(env!("CARGO_BIN_EXE_texmap"))
        .args([
            "render",
            "builtin:plane",
            "--size",
            "16x16",
            "--stats",
            "-o",
        ])
        .arg(&png)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success() && !err.contains("panicked"), "{err}");
    if let Ok(full) = std::fs::File::create("/dev/full") {
        for args in [
            vec!["info", png.to_str().unwrap()],
            vec!["compare", png.to_str().unwrap(), png.to_str().unwrap()],
        ] {
            let out = Command::new(env!("CARGO_BIN_EXE_texmap"))
                .args(&args)
                .stdout(full.try_clone().unwrap())
                .output()
                .unwrap();
            let err = String::from_utf8_lossy(&out.stderr);
            assert_eq!(out.status.code(), Some(1), "{args:?}: {err}");
            assert!(
                err.contains("stdout") && err.trim().lines().count() == 1,
                "{err}"
            );
        }
    } else {
        eprintln!("SKIPPED: /dev/full is not available");
    }
}

#[test]
fn scenes_with_nothing_to_draw_are_errors_and_non_finite_faces_are_dropped() {
    let d = dir("empty");
    let out = d.join("x.png");
    let empty = d.join("empty.obj");
    std::fs::write(&empty, "").unwrap();
    assert_refused(
        &render(&[empty.to_str().unwrap()], &out),
        &["empty.obj", "nothing to draw"],
        &out,
    );
    for (name, v) in [("nan.obj", "nan 0 0"), ("huge.obj", "1e39 0 0")] {
        let p = triangle_obj(&d, name, v);
        assert_refused(
            &render(&[p.to_str().unwrap()], &out),
            &[name, "nothing to draw"],
            &out,
        );
    }
    // One good triangle beside a bad one: drawn, with a warning.
    let p = d.join("half.obj");
    std::fs::write(
        &p,
        "v nan 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\n",
    )
    .unwrap();
    let r = texmap(&[
        "render",
        p.to_str().unwrap(),
        "--size",
        "32x24",
        "-o",
        out.to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&r.stderr);
    assert!(r.status.success(), "{err}");
    assert!(
        err.contains("half.obj: 1 triangle with a non-finite position not drawn"),
        "{err}"
    );
}

#[test]
fn oversized_requests_are_refused_before_allocation() {
    let d = dir("budget");
    let out = d.join("x.png");
    // A primitive of 10^10 vertices.
    let toml = d.join("grid.toml");
    std::fs::write(
        &toml,
        "[materials.m]\n[[meshes]]\nprimitive = \"plane\"\nmaterial = \"m\"\ndivisions = 100000\n",
    )
    .unwrap();
    assert_refused(
        &render(&[toml.to_str().unwrap()], &out),
        &["grid.toml", "divisions"],
        &out,
    );
    // A 16384² frame supersampled twice (16 GiB of samples) is above the default budget.
    let big = texmap(&[
        "render",
        "builtin:plane",
        "--size",
        "16384x16384",
        "--ssaa",
        "2",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_refused(&big, &["--size 16384x16384", "--max-memory"], &out);
    // A NIfTI header claiming 1024³ voxels of f64, in a small gzip file.
    let nii = d.join("claim.nii.gz");
    let mut h = vec![0u8; 352];
    h[0..4].copy_from_slice(&348i32.to_le_bytes());
    for (i, v) in [3i16, 1024, 1024, 1024, 1, 1, 1, 1].iter().enumerate() {
        h[40 + 2 * i..42 + 2 * i].copy_from_slice(&v.to_le_bytes());
    }
    h[70..72].copy_from_slice(&64i16.to_le_bytes());
    h[72..74].copy_from_slice(&64i16.to_le_bytes());
    for i in 0..3 {
        h[80 + 4 * i..84 + 4 * i].copy_from_slice(&1f32.to_le_bytes());
    }
    h[108..112].copy_from_slice(&352f32.to_le_bytes());
    h[344..348].copy_from_slice(b"n+1\0");
    let mut z = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
    std::io::Write::write_all(&mut z, &h).unwrap();
    std::io::Write::write_all(&mut z, &vec![0u8; 1 << 20]).unwrap();
    std::fs::write(&nii, z.finish().unwrap()).unwrap();
    assert_refused(
        &render(&[nii.to_str().unwrap()], &out),
        &["claim.nii.gz", "--max-memory"],
        &out,
    );
    // A ray step that would take millions of samples per ray.
    let cell = repo().join("scenes/volumes/cell.nrrd");
    assert_refused(
        &render(&[cell.to_str().unwrap(), "--step", "1e-6"], &out),
        &["--step", "samples"],
        &out,
    );
    assert_refused(
        &render(&["builtin:plane", "--frames", "1000001"], &out),
        &["--frames"],
        &out,
    );
}

#[test]
fn a_detached_nrrd_may_not_read_outside_its_folder_or_a_device() {
    let d = dir("nrrd");
    let out = d.join("x.png");
    let secret = d.join("secret.raw");
    std::fs::write(&secret, [7u8; 8]).unwrap();
    let sub = d.join("scan");
    std::fs::create_dir_all(&sub).unwrap();
    let header = |data: &str| {
        format!("NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: raw\ndata file: {data}\n\n")
    };
    let nhdr = sub.join("up.nhdr");
    std::fs::write(&nhdr, header("../secret.raw")).unwrap();
    assert_refused(
        &render(&[nhdr.to_str().unwrap()], &out),
        &["up.nhdr", "outside", "--allow-outside-paths"],
        &out,
    );
    let allowed = render(&[nhdr.to_str().unwrap(), "--allow-outside-paths"], &out);
    assert!(
        allowed.status.success(),
        "{}",
        String::from_utf8_lossy(&allowed.stderr)
    );
    let _ = std::fs::remove_file(&out);
    if Path::new("/dev/zero").exists() {
        let dev = sub.join("dev.nhdr");
        std::fs::write(&dev, header("/dev/zero")).unwrap();
        let r = render(&[dev.to_str().unwrap(), "--allow-outside-paths"], &out);
        assert_refused(&r, &["/dev/zero", "regular file"], &out);
    }
}

#[test]
fn file_contents_are_never_echoed() {
    let d = dir("echo");
    let out = d.join("x.png");
    let tf = d.join("not_a_tf.txt");
    std::fs::write(&tf, "root:SECRET:0:0\n").unwrap();
    let cell = repo().join("scenes/volumes/cell.nrrd");
    let r = render(
        &[cell.to_str().unwrap(), "--tf", tf.to_str().unwrap()],
        &out,
    );
    assert_refused(&r, &["not_a_tf.txt", "line 1"], &out);
    assert!(!String::from_utf8_lossy(&r.stderr).contains("SECRET"));
    let obj = d.join("bad.obj");
    std::fs::write(&obj, "v 0 0 0\nv SECRET 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let r = render(&[obj.to_str().unwrap()], &out);
    assert_refused(&r, &["bad.obj", "line 2"], &out);
    assert!(!String::from_utf8_lossy(&r.stderr).contains("SECRET"));
}

#[test]
fn outputs_never_destroy_an_input_or_follow_a_planted_link() {
    let d = dir("outputs");
    let obj = triangle_obj(&d, "model.obj", "0 0 0");
    let before = std::fs::read(&obj).unwrap();
    let r = texmap(&[
        "render",
        obj.to_str().unwrap(),
        "--quiet",
        "-o",
        obj.to_str().unwrap(),
    ]);
    assert_eq!(r.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&r.stderr).contains("is an input"));
    assert_eq!(
        std::fs::read(&obj).unwrap(),
        before,
        "the model is untouched"
    );
    // /dev/null stays a device: written through, not replaced.
    if Path::new("/dev/null").exists() {
        let r = texmap(&[
            "render",
            "builtin:plane",
            "--size",
            "8x8",
            "--quiet",
            "-o",
            "/dev/null",
        ]);
        assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
        let m = std::fs::metadata("/dev/null").unwrap();
        assert!(!m.is_file(), "/dev/null is still a device");
    }
    // A link planted at the temporary file's name is not written through.
    #[cfg(unix)]
    {
        let victim = d.join("victim.txt");
        std::fs::write(&victim, "keep me").unwrap();
        let out = d.join("img.png");
        // The temporary name holds the process id, unknown in advance: plant it for a range
        // of ids around the next ones.
        let me = std::process::id();
        let planted: Vec<PathBuf> = (me..me + 200)
            .map(|pid| d.join(format!(".img.png.tmp-{pid}")))
            .collect();
        for p in &planted {
            let _ = std::os::unix::fs::symlink(&victim, p);
        }
        let r = texmap(&[
            "render",
            "builtin:plane",
            "--size",
            "8x8",
            "--quiet",
            "-o",
            out.to_str().unwrap(),
        ]);
        assert_eq!(std::fs::read_to_string(&victim).unwrap(), "keep me");
        let err = String::from_utf8_lossy(&r.stderr);
        assert!(r.status.success() || err.contains(".img.png.tmp-"), "{err}");
        for p in &planted {
            let _ = std::fs::remove_file(p);
        }
    }
}

#[test]
fn numeric_flags_refuse_nan_and_threads_are_clamped() {
    let d = dir("nan");
    let out = d.join("x.png");
    assert_refused(
        &render(&["builtin:plane", "--lod-bias", "nan"], &out),
        &["lod bias"],
        &out,
    );
    assert_refused(
        &render(&["builtin:plane", "--uv-scale", "nan"], &out),
        &["--uv-scale"],
        &out,
    );
    let r = texmap(&[
        "render",
        "builtin:plane",
        "--size",
        "8x8",
        "--threads",
        "100000",
        "-o",
        out.to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&r.stderr);
    assert!(
        r.status.success() && err.contains("--threads 100000"),
        "{err}"
    );
}

#[test]
fn gltf_files_the_gltf_crate_would_panic_on_are_errors() {
    let d = dir("gltf");
    let out = d.join("x.png");
    let cases = [
        (
            "accessor.gltf",
            r#"{"asset":{"version":"2.0"},"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],"meshes":[{"primitives":[{"attributes":{"POSITION":5}}]}]}"#,
            "uses accessor 5",
        ),
        (
            "mime.gltf",
            r#"{"asset":{"version":"2.0"},"buffers":[{"byteLength":4,"uri":"data:application/octet-stream;base64,AAAAAA=="}],"bufferViews":[{"buffer":0,"byteLength":4}],"images":[{"bufferView":0}]}"#,
            "no mimeType",
        ),
        (
            "nosource.gltf",
            r#"{"asset":{"version":"2.0"},"images":[{}]}"#,
            "neither a uri nor a bufferView",
        ),
        (
            "camera.gltf",
            r#"{"asset":{"version":"2.0"},"cameras":[{"type":"orthographic","perspective":{"yfov":1.0,"znear":0.1}}]}"#,
            "cameras[0]",
        ),
    ];
    for (name, json, says) in cases {
        let p = d.join(name);
        std::fs::write(&p, json).unwrap();
        assert_refused(&render(&[p.to_str().unwrap()], &out), &[name, says], &out);
        assert_refused(&texmap(&["info", p.to_str().unwrap()]), &[name, says], &out);
    }
}

/// A NIfTI header: 4×4×4 unsigned bytes with `pixdim` spacing.
fn nifti_with_spacing(path: &Path, spacing: [f32; 3]) {
    let mut h = vec![0u8; 352];
    h[0..4].copy_from_slice(&348i32.to_le_bytes());
    for (i, d) in [3i16, 4, 4, 4, 1, 1, 1, 1].iter().enumerate() {
        h[40 + 2 * i..42 + 2 * i].copy_from_slice(&d.to_le_bytes());
    }
    h[70..72].copy_from_slice(&2i16.to_le_bytes());
    h[72..74].copy_from_slice(&8i16.to_le_bytes());
    for (i, p) in [1.0f32, spacing[0], spacing[1], spacing[2]]
        .iter()
        .enumerate()
    {
        h[76 + 4 * i..80 + 4 * i].copy_from_slice(&p.to_le_bytes());
    }
    h[108..112].copy_from_slice(&352f32.to_le_bytes());
    h[344..348].copy_from_slice(b"n+1\0");
    h.extend(0u8..64);
    std::fs::write(path, h).unwrap();
}

#[test]
fn camera_errors_name_the_scene_and_the_flags() {
    let d = dir("camera");
    let out = d.join("x.png");
    // A spacing of 1e30 once gave "camera has a non-finite value" without a file.
    let nii = d.join("far.nii");
    nifti_with_spacing(&nii, [1.0, 1e30, 1.0]);
    assert_refused(
        &render(&[nii.to_str().unwrap()], &out),
        &["far.nii", "world units"],
        &out,
    );
    let near = d.join("near.nii");
    nifti_with_spacing(&near, [1.0, 2.0, 1.0]);
    assert!(render(&[near.to_str().unwrap()], &out).status.success());
    std::fs::remove_file(&out).unwrap();
    // A glTF camera with a zero field of view and a node at 1e39 (infinite as f32).
    let cam = d.join("cam.gltf");
    std::fs::write(
        &cam,
        r#"{"asset":{"version":"2.0"},"scenes":[{"nodes":[0,1]}],"scene":0,"nodes":[{"mesh":0},{"camera":0,"translation":[0,0,1e39]}],"cameras":[{"type":"perspective","perspective":{"yfov":0.0,"znear":0.1}}],"buffers":[{"byteLength":36,"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}],"bufferViews":[{"buffer":0,"byteLength":36}],"accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}],"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}]}"#,
    )
    .unwrap();
    assert_refused(
        &render(&[cam.to_str().unwrap()], &out),
        &["cam.gltf", "camera"],
        &out,
    );
    let obj = triangle_obj(&d, "t.obj", "0 0 0");
    assert_refused(
        &render(
            &[obj.to_str().unwrap(), "--eye", "1,1,1", "--target", "1,1,1"],
            &out,
        ),
        &["t.obj with --eye --target", "coincide"],
        &out,
    );
}

fn mkfifo(path: &Path) -> bool {
    let _ = std::fs::remove_file(path);
    Command::new("mkfifo")
        .arg(path)
        .status()
        .is_ok_and(|s| s.success())
}

#[test]
fn fifos_are_refused_as_inputs_and_written_through_as_outputs() {
    use std::io::Read as _;
    use std::os::unix::fs::FileTypeExt as _;
    let d = dir("fifo");
    let out = d.join("x.png");
    let fifo = d.join("tex.png");
    if !mkfifo(&fifo) {
        eprintln!("skipped: no mkfifo on this machine");
        return;
    }
    let obj = d.join("a.obj");
    std::fs::write(d.join("a.mtl"), "newmtl m\nKd 1 1 1\nmap_Kd tex.png\n").unwrap();
    std::fs::write(
        &obj,
        "mtllib a.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nusemtl m\nf 1/1 2/2 3/3\n",
    )
    .unwrap();
    // Were the FIFO opened, this writer would end the read (an empty image), not a hang.
    let unblock = {
        let fifo = fifo.clone();
        std::thread::spawn(move || drop(std::fs::OpenOptions::new().write(true).open(fifo)))
    };
    assert_refused(
        &render(&[obj.to_str().unwrap()], &out),
        &["tex.png", "regular file"],
        &out,
    );
    // Open it ourselves so the writer thread ends either way.
    drop(std::fs::File::open(&fifo));
    unblock.join().unwrap();

    // An output FIFO is written through: the reader gets the PNG, the FIFO stays.
    let sink = d.join("sink.png");
    assert!(mkfifo(&sink));
    let reader = {
        let sink = sink.clone();
        std::thread::spawn(move || {
            let mut bytes = Vec::new();
            std::fs::File::open(sink)
                .unwrap()
                .read_to_end(&mut bytes)
                .unwrap();
            bytes
        })
    };
    let r = render(&["builtin:plane"], &sink);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let png = reader.join().unwrap();
    assert!(png.starts_with(b"\x89PNG"), "{} bytes", png.len());
    let kind = std::fs::symlink_metadata(&sink).unwrap().file_type();
    assert!(kind.is_fifo(), "the FIFO is still a FIFO");
}

#[test]
fn lights_that_light_nothing_and_meshes_of_no_area_are_errors() {
    let d = dir("lights");
    let out = d.join("x.png");
    let mesh = "[[meshes]]\nprimitive = \"sphere\"\n";
    for (name, light, says) in [
        ("zero.toml", "type = \"directional\"\ndirection = [0, 0, 0]", "direction"),
        ("nan.toml", "type = \"directional\"\ndirection = [nan, 0, 1]", "direction"),
        ("dark.toml", "type = \"point\"\nposition = [0, 1, 0]\nintensity = nan", "colour"),
        ("cone.toml", "type = \"spot\"\nposition = [0, 1, 0]\ndirection = [0, -1, 0]\ninner_deg = 50\nouter_deg = 40", "spot angles"),
    ] {
        let p = d.join(name);
        std::fs::write(&p, format!("{mesh}[[lights]]\n{light}\n")).unwrap();
        assert_refused(
            &render(&[p.to_str().unwrap()], &out),
            &[name, "lights[0]", says],
            &out,
        );
    }
    let flat = d.join("flat.toml");
    std::fs::write(&flat, format!("{mesh}scale = 0\n")).unwrap();
    assert_refused(
        &render(&[flat.to_str().unwrap()], &out),
        &["flat.toml", "zero area"],
        &out,
    );
}

/// A black RGB PNG of `w × h` in `d`.
fn black_png(d: &Path, name: &str, w: u32, h: u32) -> PathBuf {
    let p = d.join(name);
    image::RgbImage::new(w, h).save(&p).unwrap();
    p
}

#[test]
fn a_missing_environment_image_is_named() {
    let d = dir("env-missing");
    let out = d.join("x.png");
    let missing = d.join("missing.hdr");
    assert_refused(
        &render(
            &["builtin:sphere", "--env", missing.to_str().unwrap()],
            &out,
        ),
        &["missing.hdr"],
        &out,
    );
    // The same from a scene's [environment] table.
    let scene = d.join("s.toml");
    std::fs::write(
        &scene,
        "[[meshes]]\nprimitive = \"sphere\"\n[environment]\nfile = \"missing.hdr\"\n",
    )
    .unwrap();
    assert_refused(
        &render(&[scene.to_str().unwrap()], &out),
        &["missing.hdr"],
        &out,
    );
}

#[test]
fn a_corrupt_environment_image_is_named() {
    let d = dir("env-corrupt");
    let out = d.join("x.png");
    // A Radiance header whose pixels stop short, a PNG that is not one, and a directory of
    // faces missing five of them.
    let hdr = d.join("short.hdr");
    std::fs::write(
        &hdr,
        b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 8 +X 16\n\x02\x02\x02\x02",
    )
    .unwrap();
    let png = d.join("text.png");
    std::fs::write(&png, "not an image").unwrap();
    let faces = d.join("faces");
    std::fs::create_dir_all(&faces).unwrap();
    black_png(&faces, "posx.png", 8, 8);
    for (file, says) in [
        (&hdr, "short.hdr"),
        (&png, "text.png"),
        (&faces, "has no negx image"),
    ] {
        assert_refused(
            &render(&["builtin:sphere", "--env", file.to_str().unwrap()], &out),
            &[says],
            &out,
        );
    }
}

#[test]
fn environment_images_of_the_wrong_proportions_are_named() {
    let d = dir("env-proportions");
    let out = d.join("x.png");
    // Neither 2:1, 4:3, 3:4 nor 1:1: no layout fits.
    let odd = black_png(&d, "odd.png", 50, 30);
    assert_refused(
        &render(&["builtin:sphere", "--env", odd.to_str().unwrap()], &out),
        &["odd.png", "50x30", "2:1"],
        &out,
    );
    // Declared a cross, but 2:1; and close to 4:3 without being it.
    black_png(&d, "wide.png", 40, 20);
    black_png(&d, "uneven.png", 42, 31);
    for (file, says) in [("wide.png", "40x20"), ("uneven.png", "42x31")] {
        let scene = d.join(format!("{file}.toml"));
        std::fs::write(
            &scene,
            format!(
                "[[meshes]]\nprimitive = \"sphere\"\n[environment]\nfile = \"{file}\"\n\
                 kind = \"cross\"\n"
            ),
        )
        .unwrap();
        assert_refused(
            &render(&[scene.to_str().unwrap()], &out),
            &[file, says, "a cross is 4N x 3N"],
            &out,
        );
    }
}

#[test]
fn an_environment_alone_is_something_to_draw() {
    // No meshes and no volumes, but an environment: its background is the image.
    let d = dir("env-alone");
    let png = d.join("sky.png");
    image::RgbImage::from_pixel(16, 8, image::Rgb([40, 90, 200]))
        .save(&png)
        .unwrap();
    let scene = d.join("sky.toml");
    std::fs::write(&scene, "lights = []\n[environment]\nfile = \"sky.png\"\n").unwrap();
    let out = d.join("x.png");
    let o = render(&[scene.to_str().unwrap()], &out);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let img = image::open(&out).unwrap().to_rgb8();
    assert_eq!(img.get_pixel(16, 12).0, [40, 90, 200]);
}

/// A bad `[[projectors]]` entry is one line naming the file, the entry and the problem: a
/// missing slide, a target at the position, a field of view out of range, an unknown key.
#[test]
fn bad_projectors_are_named() {
    let d = dir("projectors");
    let out = d.join("out.png");
    let scene = |name: &str, entry: &str| {
        let p = d.join(name);
        std::fs::write(
            &p,
            format!(
                "[[meshes]]\nprimitive = \"plane\"\n\n[[projectors]]\nposition = [0, 2, 2]\n\
                 {entry}\n"
            ),
        )
        .unwrap();
        p
    };
    let card = repo().join("scenes/projector/test_card.png");
    let card = card.to_str().unwrap();
    for (name, entry, needles) in [
        (
            "missing.toml",
            "target = [0, 0, 0]\nimage = { file = \"nowhere.png\" }".to_string(),
            vec!["nowhere.png", "No such file"],
        ),
        (
            "nowhere.toml",
            format!("target = [0, 2, 2]\nimage = {{ file = {card:?} }}"),
            vec!["nowhere.toml", "projectors[0]", "points nowhere"],
        ),
        (
            "fov.toml",
            format!("target = [0, 0, 0]\nfov = 180\nimage = {{ file = {card:?} }}"),
            vec!["fov.toml", "projectors[0]", "fov 180"],
        ),
        (
            "key.toml",
            format!("target = [0, 0, 0]\nbrightness = 2\nimage = {{ file = {card:?} }}"),
            vec!["key.toml", "brightness"],
        ),
    ] {
        let path = scene(name, &entry);
        let r = render(&[path.to_str().unwrap()], &out);
        assert_refused(&r, &needles, &out);
    }
}
