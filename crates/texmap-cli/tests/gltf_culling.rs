//! glTF's single-sided materials are back-face culled by default (the specification's rule),
//! double-sided ones never; `--cull` still decides when given.

use std::path::{Path, PathBuf};
use std::process::Command;

/// A quad whose back faces the camera, unlit white, single- or double-sided.
fn write_model(d: &Path, double_sided: bool) -> PathBuf {
    let mut b: Vec<u8> = Vec::new();
    for p in [
        [-1.0f32, -1.0, 0.0],
        [1.0, -1.0, 0.0],
        [1.0, 1.0, 0.0],
        [-1.0, 1.0, 0.0],
    ] {
        p.iter().for_each(|v| b.extend_from_slice(&v.to_le_bytes()));
    }
    // Clockwise seen from +z: the back face looks at the camera.
    for i in [0u16, 2, 1, 0, 3, 2] {
        b.extend_from_slice(&i.to_le_bytes());
    }
    std::fs::write(d.join("quad.bin"), &b).unwrap();
    let json = format!(
        r#"{{"asset": {{"version": "2.0"}}, "extensionsUsed": ["KHR_materials_unlit"],
  "scene": 0, "scenes": [{{"nodes": [0, 1]}}],
  "nodes": [{{"mesh": 0}}, {{"camera": 0, "translation": [0, 0, 2]}}],
  "cameras": [{{"type": "perspective", "perspective": {{"yfov": 1.2, "znear": 0.1, "zfar": 10}}}}],
  "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}, "indices": 1, "material": 0}}]}}],
  "materials": [{{"doubleSided": {double_sided}, "extensions": {{"KHR_materials_unlit": {{}}}}}}],
  "buffers": [{{"byteLength": 60, "uri": "quad.bin"}}],
  "bufferViews": [{{"buffer": 0, "byteLength": 48}}, {{"buffer": 0, "byteOffset": 48, "byteLength": 12}}],
  "accessors": [
    {{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-1, -1, 0], "max": [1, 1, 0]}},
    {{"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"}}]}}"#
    );
    let path = d.join(format!("quad-{double_sided}.gltf"));
    std::fs::write(&path, json).unwrap();
    path
}

/// The centre pixel's red channel of the render of `model` with `extra` flags.
fn centre(model: &Path, out: &Path, extra: &[&str]) -> u8 {
    let o = Command::new(env!("CARGO_BIN_EXE_texmap"))
        .args(["render", model.to_str().unwrap(), "--size", "16x16", "-o"])
        .arg(out)
        .args(extra)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let img = image::open(out).unwrap().to_rgb8();
    img.get_pixel(8, 8).0[0]
}

#[test]
fn single_sided_gltf_materials_are_back_face_culled_unless_cull_says() {
    let d = std::env::temp_dir().join(format!("texmap-gltf-cull-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    let out = d.join("x.png");
    let single = write_model(&d, false);
    let double = write_model(&d, true);
    assert_eq!(
        centre(&single, &out, &[]),
        0,
        "a single-sided back face is drawn"
    );
    assert_eq!(
        centre(&double, &out, &[]),
        255,
        "a double-sided back face is culled"
    );
    assert_eq!(centre(&single, &out, &["--cull", "none"]), 255);
    assert_eq!(centre(&single, &out, &["--cull", "front"]), 255);
}
