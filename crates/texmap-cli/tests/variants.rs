//! `KHR_materials_variants` on the command line: `texmap info` lists the variants,
//! `texmap render --variant NAME` draws each primitive with the material the variant maps it
//! to (the TOML mesh key `variant` too), and a name the file does not define is one line
//! listing the ones it does, exit 1, no image.

mod common;

use common::texmap;
use std::path::{Path, PathBuf};
use std::process::Output;

fn dir(name: &str) -> PathBuf {
    common::fresh_dir("variants", name)
}

/// A quad facing a camera, unlit, with materials red (its own), green and blue, and the
/// variants "Leaf" (→ green) and "Sea" (→ blue). "Plain" maps nothing: the own material.
fn write_model(d: &Path) -> PathBuf {
    let mut b: Vec<u8> = Vec::new();
    for p in [
        [-1.0f32, -1.0, 0.0],
        [1.0, -1.0, 0.0],
        [1.0, 1.0, 0.0],
        [-1.0, 1.0, 0.0],
    ] {
        p.iter().for_each(|v| b.extend_from_slice(&v.to_le_bytes()));
    }
    for i in [0u16, 1, 2, 0, 2, 3] {
        b.extend_from_slice(&i.to_le_bytes());
    }
    std::fs::write(d.join("quad.bin"), &b).unwrap();
    let material = |name: &str, rgb: &str| {
        format!(
            r#"{{"name": "{name}", "pbrMetallicRoughness": {{"baseColorFactor": [{rgb}, 1]}},
                "extensions": {{"KHR_materials_unlit": {{}}}}}}"#
        )
    };
    let json = format!(
        r#"{{"asset": {{"version": "2.0"}},
  "extensionsUsed": ["KHR_materials_variants", "KHR_materials_unlit"],
  "extensions": {{"KHR_materials_variants": {{"variants": [{{"name": "Leaf"}}, {{"name": "Sea"}}, {{"name": "Plain"}}]}}}},
  "scene": 0, "scenes": [{{"nodes": [0, 1]}}],
  "nodes": [{{"mesh": 0}}, {{"camera": 0, "translation": [0, 0, 2]}}],
  "cameras": [{{"type": "perspective", "perspective": {{"yfov": 1.2, "znear": 0.1, "zfar": 10, "aspectRatio": 1}}}}],
  "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}, "indices": 1, "material": 0,
    "extensions": {{"KHR_materials_variants": {{"mappings": [
      {{"material": 1, "variants": [0]}}, {{"material": 2, "variants": [1]}}]}}}}}}]}}],
  "materials": [{}, {}, {}],
  "buffers": [{{"byteLength": {}, "uri": "quad.bin"}}],
  "bufferViews": [{{"buffer": 0, "byteLength": 48}}, {{"buffer": 0, "byteOffset": 48, "byteLength": 12}}],
  "accessors": [
    {{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-1, -1, 0], "max": [1, 1, 0]}},
    {{"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"}}]}}"#,
        material("red", "1, 0, 0"),
        material("green", "0, 1, 0"),
        material("blue", "0, 0, 1"),
        b.len(),
    );
    let path = d.join("variants.gltf");
    std::fs::write(&path, json).unwrap();
    path
}

/// The centre pixel of a PNG.
fn centre(png: &Path) -> [u8; 3] {
    let img = image::open(png).unwrap().to_rgb8();
    let (w, h) = img.dimensions();
    img.get_pixel(w / 2, h / 2).0
}

fn render(model: &Path, out: &Path, extra: &[&str]) -> Output {
    let mut args = vec![
        "render",
        model.to_str().unwrap(),
        "--size",
        "16x16",
        "-o",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    texmap(&args)
}

#[test]
fn info_lists_the_variants() {
    let d = dir("info");
    let model = write_model(&d);
    let o = texmap(&["info", model.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("variants: 3 (Leaf, Sea, Plain)"), "{text}");
    let o = texmap(&["info", model.to_str().unwrap(), "--variant", "Sea"]);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("drawn: Sea"), "{text}");
    assert!(text.contains("material 2"), "{text}");
}

#[test]
fn each_variant_draws_its_material() {
    let d = dir("render");
    let model = write_model(&d);
    for (variant, expected) in [
        (None, [255, 0, 0]),
        (Some("Leaf"), [0, 255, 0]),
        (Some("Sea"), [0, 0, 255]),
        (Some("Plain"), [255, 0, 0]),
    ] {
        let out = d.join(format!("{}.png", variant.unwrap_or("own")));
        let extra: Vec<&str> = variant.map(|v| vec!["--variant", v]).unwrap_or_default();
        let o = render(&model, &out, &extra);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        assert_eq!(centre(&out), expected, "{variant:?}");
    }
    // A TOML scene chooses a variant per glTF mesh.
    let toml = d.join("scene.toml");
    std::fs::write(
        &toml,
        "[[meshes]]\nfile = \"variants.gltf\"\nvariant = \"Sea\"\n\n[[cameras]]\neye = [0, 0, 2]\ntarget = [0, 0, 0]\nfov = 68\n",
    )
    .unwrap();
    let out = d.join("toml.png");
    let o = render(&toml, &out, &[]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(centre(&out), [0, 0, 255]);
}

#[test]
fn an_unknown_variant_is_one_line_listing_the_variants_and_no_image() {
    let d = dir("unknown");
    let model = write_model(&d);
    let out = d.join("x.png");
    let o = render(&model, &out, &["--variant", "Desert"]);
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(err.contains("variants.gltf"), "{err}");
    assert!(err.contains("\"Desert\""), "{err}");
    assert!(err.contains("Leaf, Sea, Plain"), "{err}");
    assert!(!out.exists());
    // A scene without variants says so.
    let o = texmap(&[
        "render",
        "builtin:plane",
        "--variant",
        "Leaf",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(err.contains("--variant"), "{err}");
    assert!(!out.exists());
}
