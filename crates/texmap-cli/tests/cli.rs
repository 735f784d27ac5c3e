//! The command line on good and bad scene files: exit codes, one-line messages naming the
//! file, no output file after a failure.

mod common;

use common::texmap;
use std::path::{Path, PathBuf};
use std::process::Output;

fn dir(name: &str) -> PathBuf {
    common::fresh_dir("cli", name)
}

/// A triangle's binary buffer: 3 positions, 3 uvs, 3 u16 indices (+2 bytes padding).
fn triangle_bin(indices: [u16; 3]) -> Vec<u8> {
    let mut b = Vec::new();
    for p in [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]] {
        for v in p {
            b.extend_from_slice(&v.to_le_bytes());
        }
    }
    for uv in [[0.0f32, 1.0], [1.0, 1.0], [0.0, 0.0]] {
        for v in uv {
            b.extend_from_slice(&v.to_le_bytes());
        }
    }
    for i in indices {
        b.extend_from_slice(&i.to_le_bytes());
    }
    b.extend_from_slice(&[0, 0]);
    b
}

/// glTF JSON for the triangle; `buffer_uri` None means the GLB binary chunk.
fn triangle_json(buffer_uri: Option<&str>, image_uri: Option<&str>, extra: &str) -> String {
    let buffer = match buffer_uri {
        Some(u) => format!(r#"{{"byteLength": 68, "uri": "{u}"}}"#),
        None => r#"{"byteLength": 68}"#.to_string(),
    };
    let (material, textures) = match image_uri {
        Some(u) => (
            r#","material": 0"#.to_string(),
            format!(
                r#","materials": [{{"pbrMetallicRoughness": {{"baseColorTexture": {{"index": 0}}}}}}],
                   "textures": [{{"source": 0}}], "images": [{{"uri": "{u}"}}]"#
            ),
        ),
        None => (String::new(), String::new()),
    };
    format!(
        r#"{{"asset": {{"version": "2.0"}}{extra},
  "scene": 0, "scenes": [{{"nodes": [0]}}], "nodes": [{{"mesh": 0}}],
  "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0, "TEXCOORD_0": 1}}, "indices": 2{material}}}]}}],
  "buffers": [{buffer}],
  "bufferViews": [{{"buffer": 0, "byteOffset": 0, "byteLength": 36}},
                  {{"buffer": 0, "byteOffset": 36, "byteLength": 24}},
                  {{"buffer": 0, "byteOffset": 60, "byteLength": 6}}],
  "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                  "min": [0, 0, 0], "max": [1, 1, 0]}},
                {{"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC2"}},
                {{"bufferView": 2, "componentType": 5123, "count": 3, "type": "SCALAR"}}]
  {textures}}}"#
    )
}

fn write_gltf(
    d: &Path,
    name: &str,
    indices: [u16; 3],
    image: Option<&str>,
    extra: &str,
) -> PathBuf {
    std::fs::write(d.join("tri.bin"), triangle_bin(indices)).unwrap();
    let p = d.join(name);
    std::fs::write(&p, triangle_json(Some("tri.bin"), image, extra)).unwrap();
    p
}

fn glb(json: &str, bin: &[u8]) -> Vec<u8> {
    let mut j = json.as_bytes().to_vec();
    while !j.len().is_multiple_of(4) {
        j.push(b' ');
    }
    let total = 12 + 8 + j.len() + 8 + bin.len();
    let mut out = Vec::new();
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(j.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&j);
    out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(bin);
    out
}

fn png(d: &Path, name: &str) {
    image::RgbaImage::from_pixel(4, 4, image::Rgba([10, 200, 30, 255]))
        .save(d.join(name))
        .unwrap();
}

/// Asserts a failure: non-zero exit, one line on stderr containing every `needles`, and no
/// output file.
fn assert_fails(out: &Output, needles: &[&str], output_file: &Path) {
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "expected failure, stderr: {stderr}");
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert_eq!(
        stderr.trim().lines().count(),
        1,
        "one line expected: {stderr}"
    );
    for n in needles {
        assert!(stderr.contains(n), "{n:?} not in {stderr:?}");
    }
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(
        !output_file.exists(),
        "a failed run left {}",
        output_file.display()
    );
}

fn render(file: &Path, out: &Path, extra: &[&str]) -> Output {
    let mut args = vec![
        "render",
        file.to_str().unwrap(),
        "--size",
        "32x24",
        "-o",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    texmap(&args)
}

#[test]
fn good_gltf_glb_and_obj_render_and_info_lists_them() {
    let d = dir("good");
    png(&d, "tex.png");
    let g = write_gltf(&d, "tri.gltf", [0, 1, 2], Some("tex.png"), "");
    let out = d.join("g.png");
    let r = render(&g, &out, &[]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    assert!(out.exists());

    let json = triangle_json(None, None, "");
    let b = d.join("tri.glb");
    std::fs::write(&b, glb(&json, &triangle_bin([0, 1, 2]))).unwrap();
    let r = render(&b, &d.join("b.png"), &["--quiet"]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));

    let o = d.join("q.obj");
    std::fs::write(&o, "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n").unwrap();
    let r = render(&o, &d.join("o.png"), &[]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));

    let info = texmap(&["info", g.to_str().unwrap()]);
    let text = String::from_utf8_lossy(&info.stdout);
    assert!(info.status.success());
    assert!(text.contains("meshes: 1 (1 triangles"), "{text}");
    assert!(text.contains("tex.png: 4x4"), "{text}");
    let info = texmap(&["info", o.to_str().unwrap()]);
    assert!(String::from_utf8_lossy(&info.stdout).contains("2 triangles"));
}

#[test]
fn info_lists_the_emission_with_its_strength() {
    let d = dir("emissive");
    png(&d, "tex.png");
    std::fs::write(d.join("tri.bin"), triangle_bin([0, 1, 2])).unwrap();
    let json = triangle_json(
        Some("tri.bin"),
        Some("tex.png"),
        r#","extensionsUsed": ["KHR_materials_emissive_strength"]"#,
    )
    .replace(
        r#"{"pbrMetallicRoughness":"#,
        r#"{"emissiveFactor": [1, 0.5, 0], "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 4}}, "pbrMetallicRoughness":"#,
    );
    assert!(json.contains("emissiveStrength"));
    let g = d.join("glow.gltf");
    std::fs::write(&g, json).unwrap();
    let info = texmap(&["info", g.to_str().unwrap()]);
    let text = String::from_utf8_lossy(&info.stdout);
    assert!(
        info.status.success(),
        "{}",
        String::from_utf8_lossy(&info.stderr)
    );
    assert!(text.contains("emissive (4.000, 2.000, 0.000)"), "{text}");
}

#[test]
fn truncated_glb_is_one_line_naming_the_file() {
    let d = dir("trunc");
    let json = triangle_json(None, None, "");
    let bytes = glb(&json, &triangle_bin([0, 1, 2]));
    let b = d.join("cut.glb");
    std::fs::write(&b, &bytes[..bytes.len() - 30]).unwrap();
    let out = d.join("o.png");
    assert_fails(&render(&b, &out, &[]), &["cut.glb"], &out);
}

#[test]
fn missing_texture_fails_and_lenient_draws_a_placeholder() {
    let d = dir("missing");
    let g = write_gltf(&d, "m.gltf", [0, 1, 2], Some("nothere.png"), "");
    let out = d.join("o.png");
    assert_fails(&render(&g, &out, &[]), &["nothere.png"], &out);
    let r = render(&g, &out, &["--lenient"]);
    let stderr = String::from_utf8_lossy(&r.stderr);
    assert!(r.status.success(), "{stderr}");
    assert!(
        stderr.contains("warning") && stderr.contains("placeholder"),
        "{stderr}"
    );
    assert!(out.exists());
}

#[test]
fn out_of_range_index_is_an_error() {
    let d = dir("oor");
    let g = write_gltf(&d, "oor.gltf", [0, 1, 7], None, "");
    let out = d.join("o.png");
    assert_fails(
        &render(&g, &out, &[]),
        &["oor.gltf", "index 7 is out of range"],
        &out,
    );
}

#[test]
fn malformed_obj_line_is_named() {
    let d = dir("obj");
    let o = d.join("bad.obj");
    std::fs::write(&o, "v 0 0 0\nv 1 0 0\nv 0 one 0\nf 1 2 3\n").unwrap();
    let out = d.join("o.png");
    assert_fails(&render(&o, &out, &[]), &["bad.obj", "line 3"], &out);
}

#[test]
fn unknown_toml_key_is_named() {
    let d = dir("toml");
    let t = d.join("s.toml");
    std::fs::write(&t, "[[meshes]]\nprimitive = \"cube\"\ncolour = [1, 0, 0]\n").unwrap();
    let out = d.join("o.png");
    assert_fails(
        &render(&t, &out, &[]),
        &["s.toml", "line 3", "unknown field `colour`"],
        &out,
    );
}

#[test]
fn references_outside_the_folder_need_the_flag() {
    let d = dir("outside");
    let sub = d.join("model");
    std::fs::create_dir_all(&sub).unwrap();
    png(&d, "up.png");
    let g = write_gltf(&sub, "o.gltf", [0, 1, 2], Some("../up.png"), "");
    let out = d.join("o.png");
    assert_fails(
        &render(&g, &out, &[]),
        &["o.gltf", "--allow-outside-paths"],
        &out,
    );
    let r = render(&g, &out, &["--allow-outside-paths"]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
}

#[test]
fn network_uris_are_refused() {
    let d = dir("http");
    let g = write_gltf(
        &d,
        "h.gltf",
        [0, 1, 2],
        Some("https://example.com/t.png"),
        "",
    );
    let out = d.join("o.png");
    assert_fails(
        &render(&g, &out, &["--allow-outside-paths"]),
        &["h.gltf", "network"],
        &out,
    );
}

#[test]
fn unsupported_required_extension_fails_optional_one_warns() {
    let d = dir("ext");
    let g = write_gltf(
        &d,
        "req.gltf",
        [0, 1, 2],
        None,
        r#","extensionsUsed": ["KHR_draco_mesh_compression"], "extensionsRequired": ["KHR_draco_mesh_compression"]"#,
    );
    let out = d.join("o.png");
    assert_fails(
        &render(&g, &out, &[]),
        &["req.gltf", "KHR_draco_mesh_compression"],
        &out,
    );
    let g = write_gltf(
        &d,
        "opt.gltf",
        [0, 1, 2],
        None,
        r#","extensionsUsed": ["KHR_materials_anisotropy"]"#,
    );
    let r = render(&g, &out, &[]);
    let stderr = String::from_utf8_lossy(&r.stderr);
    assert!(r.status.success(), "{stderr}");
    assert!(
        stderr.contains("warning") && stderr.contains("KHR_materials_anisotropy"),
        "{stderr}"
    );
}

#[test]
fn missing_scene_file_and_unknown_format() {
    let d = dir("nofile");
    let out = d.join("o.png");
    assert_fails(
        &render(&d.join("none.gltf"), &out, &[]),
        &["none.gltf"],
        &out,
    );
    let x = d.join("scene.fbx");
    std::fs::write(&x, "x").unwrap();
    assert_fails(&render(&x, &out, &[]), &["scene.fbx"], &out);
}

#[test]
fn ortho_flag_renders_a_parallel_view_and_info_names_the_projection() {
    let d = dir("ortho");
    let t = d.join("cube.toml");
    std::fs::write(
        &t,
        "[[cameras]]\neye = [0, 0, 5]\ntarget = [0, 0, 0]\nfov = 30\n\
         [materials.white]\nunlit = true\n\
         [[meshes]]\nprimitive = \"cube\"\nsize = 2\nmaterial = \"white\"\n",
    )
    .unwrap();
    let out = d.join("o.png");
    let (ts, os) = (t.to_str().unwrap(), out.to_str().unwrap());
    let r = texmap(&["render", ts, "--size", "96x64", "-o", os, "--ortho", "4"]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    // A visible height of 4 over 64 rows: the 2-unit face spans columns 32..64, rows 16..48.
    let img = image::open(&out).unwrap().to_rgb8();
    for (x, y, p) in img.enumerate_pixels() {
        let inside = (32..64).contains(&x) && (16..48).contains(&y);
        assert_eq!(p[0] > 128, inside, "pixel ({x}, {y}) = {p:?}");
    }
    // Without a value the height frames the bounding sphere (2.2·√3): a smaller square.
    let r = texmap(&["render", ts, "--size", "96x64", "-o", os, "--ortho"]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let img = image::open(&out).unwrap().to_rgb8();
    let rows = (0..64)
        .filter(|&y| (0..96).any(|x| img.get_pixel(x, y)[0] > 128))
        .count();
    assert!((33..=34).contains(&rows), "{rows} rows");
    // --ortho and --fov exclude each other; a bad height is one line naming it.
    let r = texmap(&["render", ts, "-o", os, "--fov", "40", "--ortho", "4"]);
    assert!(!r.status.success());
    let _ = std::fs::remove_file(&out);
    assert_fails(
        &texmap(&["render", ts, "-o", os, "--ortho", "-2"]),
        &["orthographic", "height -2"],
        &out,
    );

    std::fs::write(
        &t,
        "[[cameras]]\neye = [0, 0, 5]\ntarget = [0, 0, 0]\nprojection = \"orthographic\"\nheight = 4\n\
         [[cameras]]\neye = [0, 0, 5]\ntarget = [0, 0, 0]\n",
    )
    .unwrap();
    let info = texmap(&["info", ts]);
    let text = String::from_utf8_lossy(&info.stdout);
    assert!(info.status.success(), "{text}");
    assert!(text.contains("[0] orthographic height 4 "), "{text}");
    assert!(text.contains("[1] perspective fov 60.0°"), "{text}");
}

// ---- Volumes ---------------------------------------------------------------------------------

/// A 24³ u8 raw ball: 200 at the centre, falling to 0 at radius 12 voxels.
fn raw_ball(d: &Path) -> PathBuf {
    let mut b = Vec::new();
    for z in 0..24 {
        for y in 0..24 {
            for x in 0..24 {
                let r = ((x as f32 - 11.5).powi(2)
                    + (y as f32 - 11.5).powi(2)
                    + (z as f32 - 11.5).powi(2))
                .sqrt();
                b.push((200.0 * (1.0 - r / 12.0)).clamp(0.0, 200.0) as u8);
            }
        }
    }
    let p = d.join("ball.raw");
    std::fs::write(&p, b).unwrap();
    p
}

const BALL_FLAGS: &[&str] = &[
    "--dims",
    "24,24,24",
    "--tf",
    "0:1,1,1,0;40:1,1,1,0.08;200:1,1,1,0.08",
    "--no-jitter",
];

fn rgb(p: &Path) -> image::RgbImage {
    image::open(p).unwrap().to_rgb8()
}

#[test]
fn a_mesh_inside_a_scan_from_the_command_line() {
    let d = dir("vol-mesh");
    let ball = raw_ball(&d);
    // A square through the middle plane y = 11.5, over the left half (x < 11.5).
    let quad = d.join("quad.obj");
    std::fs::write(
        &quad,
        "v 0 11.5 0\nv 11.5 11.5 0\nv 11.5 11.5 23\nv 0 11.5 23\nf 1 2 3 4\n",
    )
    .unwrap();
    let (alone, inside) = (d.join("alone.png"), d.join("inside.png"));
    let r = render(&ball, &alone, BALL_FLAGS);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let mut flags = BALL_FLAGS.to_vec();
    flags.extend(["--mesh", quad.to_str().unwrap(), "--stats"]);
    let r = render(&ball, &inside, &flags);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let stats = String::from_utf8_lossy(&r.stdout);
    assert!(
        stats.contains("\"volumes\"") && stats.contains("[24,24,24]"),
        "{stats}"
    );
    // The camera looks along +y with z up: the square covers the left half of the image.
    let (a, b) = (rgb(&alone), rgb(&inside));
    let (w, h) = a.dimensions();
    let (mut left, mut right) = (0, 0);
    for y in 0..h {
        for x in 0..w {
            let differs = a.get_pixel(x, y) != b.get_pixel(x, y);
            if x < w / 2 - 2 && differs {
                left += 1;
            }
            if x > w / 2 + 1 && differs {
                right += 1;
            }
        }
    }
    assert!(left > 30, "the mesh changed {left} pixels on the left");
    assert_eq!(right, 0, "the right half has no mesh");
    // A missing mesh file: one line naming it.
    let out = d.join("missing.png");
    let mut flags = BALL_FLAGS.to_vec();
    flags.extend(["--mesh", "nothere.obj"]);
    assert_fails(&render(&ball, &out, &flags), &["nothere.obj"], &out);
}

#[test]
fn a_toml_scene_with_a_volume_renders_and_info_lists_it() {
    let d = dir("vol-toml");
    raw_ball(&d);
    let scene = d.join("s.toml");
    std::fs::write(
        &scene,
        r#"[[volumes]]
file = "ball.raw"
dims = [24, 24, 24]
spacing = [1, 1, 2]
tf = "0:1,1,1,0;40:1,0.5,0.2,0.08;200:1,0.5,0.2,0.08"
jitter = false
[[meshes]]
primitive = "cube"
size = 4
translate = [11.5, 11.5, 23]
"#,
    )
    .unwrap();
    let text = info_of(&scene);
    assert!(
        text.contains("volumes: 1")
            && text.contains("ball.raw: 24x24x24 u8, spacing (1, 1, 2), values 0 .. 185"),
        "{text}"
    );
    let (a, b) = (d.join("a.png"), d.join("b.png"));
    let r = render(&scene, &a, &[]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    // Flags override the table: another transfer function, another image.
    let r = render(&scene, &b, &["--tf", "mri", "--shade"]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    assert_ne!(rgb(&a), rgb(&b));
    // Orange where the ball is (the table's colour), not grey.
    let centre = *rgb(&a).get_pixel(16, 12);
    assert!(centre[0] > centre[2] + 40, "{centre:?}");
    // Raw flags belong to volume files; a bad table is one line naming the file and line.
    let out = d.join("o.png");
    assert_fails(
        &render(&scene, &out, &["--dims", "2,2,2"]),
        &["--dims"],
        &out,
    );
    let bad = d.join("bad.toml");
    std::fs::write(&bad, "[[volumes]]\nfile = \"ball.raw\"\nopacity = 1\n").unwrap();
    assert_fails(
        &render(&bad, &out, &[]),
        &["bad.toml", "line 3", "opacity"],
        &out,
    );
}

#[test]
fn info_reads_a_volume_file() {
    let d = dir("vol-info");
    let ball = raw_ball(&d);
    let info = texmap(&["info", ball.to_str().unwrap(), "--dims", "24,24,24"]);
    let text = String::from_utf8_lossy(&info.stdout);
    assert!(
        info.status.success(),
        "{}",
        String::from_utf8_lossy(&info.stderr)
    );
    assert!(
        text.contains("24x24x24 u8") && text.contains("values 0 .. 185"),
        "{text}"
    );
    let info = texmap(&["info", ball.to_str().unwrap()]);
    assert!(!info.status.success());
    assert!(String::from_utf8_lossy(&info.stderr).contains("--dims"));
}

#[test]
fn info_names_each_materials_colour_source() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let scene = root.join("scenes/solid_texture3d.toml");
    let info = texmap(&["info", scene.to_str().unwrap()]);
    let text = String::from_utf8_lossy(&info.stdout);
    assert!(
        info.status.success(),
        "{}",
        String::from_utf8_lossy(&info.stderr)
    );
    assert!(
        text.contains("colour 3D texture 64x64x64 over [-1, -1, -1]..[1, 1, 1]")
            && text.contains("colour 3D texture 96x96x96"),
        "{text}"
    );
}

/// 3D textures take OpenGL's filters only: on a scene whose only image textures are 3D, an
/// anisotropic, EWA or SAT `--filter` (which would read as trilinear) is refused in one line
/// naming the scene, and an OpenGL filter renders.
#[test]
fn filters_3d_textures_cannot_take_are_refused() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let scene = root.join("scenes/solid_texture3d.toml");
    let d = dir("filters_3d");
    let cases = [
        ("aniso5-area", false),
        ("aniso8", false),
        ("ewa", false),
        ("sat", false),
        ("nearest-mipmap-linear", true),
    ];
    for (filter, ok) in cases {
        let out = d.join(format!("{filter}.png"));
        let run = render(&scene, &out, &["--filter", filter]);
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.success(), ok, "{filter}: {stderr}");
        assert_eq!(out.exists(), ok, "{filter}: no partial output");
        if !ok {
            assert!(
                stderr.contains("--filter")
                    && stderr.contains("solid_texture3d.toml")
                    && stderr.contains("only 3D textures")
                    && stderr.lines().count() == 1,
                "{filter}: {stderr}"
            );
        }
    }
}

/// `texmap info PATH`'s standard output, asserting it succeeded.
fn info_of(path: &std::path::Path) -> String {
    let info = texmap(&["info", path.to_str().unwrap()]);
    assert!(
        info.status.success(),
        "{}",
        String::from_utf8_lossy(&info.stderr)
    );
    String::from_utf8_lossy(&info.stdout).into_owned()
}
