//! Every glTF map reads its own uv set and its own `KHR_texture_transform`, whatever other
//! maps the material has.
//!
//! The scene: a lit quad whose TEXCOORD_0 lies in the left half of every texture and whose
//! TEXCOORD_1 lies in the right half. Each texture is 2×1, read with nearest filtering: its
//! right texel is *neutral* (white for factors, flat for normals, so the map changes nothing)
//! and its left texel is *wrong* (black: it darkens, tilts or removes what it feeds). A map
//! that reads the coordinates its material names sees the neutral texel, so the frame equals
//! the frame of the same material without that map (bit for bit for factor maps, to 2/255
//! for normal maps, whose neutral texel is flat to 1/255); a map read through the other set
//! (or without its transform) changes the frame. Each case is checked both ways: the right
//! reading must match and a control reading the wrong texel must differ (so the check can
//! fail), alone and with every other map present. The maps: base colour, metallic-roughness,
//! normal, occlusion, emissive, and the specular, clearcoat, sheen and volume extensions'.

use std::path::PathBuf;

use base64::Engine;
use glam::Vec3;
use texmap::render::{render, Settings, ShadingMode};
use texmap::scene::{load, Environment, LoadOptions};
use texmap::texture::{EnvironmentMap, Texture2D, TextureOptions};

/// One map of the material: its JSON key and where it sits.
#[derive(Clone, Copy)]
struct Channel {
    name: &'static str,
    /// The member holding the textureInfo: `(extension or "", key)`.
    at: (&'static str, &'static str),
    /// Reads the normal-map image (flat on the right) rather than the data image.
    normal: bool,
}

const CHANNELS: &[Channel] = &[
    Channel {
        name: "base colour",
        at: ("pbrMetallicRoughness", "baseColorTexture"),
        normal: false,
    },
    Channel {
        name: "metallic-roughness",
        at: ("pbrMetallicRoughness", "metallicRoughnessTexture"),
        normal: false,
    },
    Channel {
        name: "normal",
        at: ("", "normalTexture"),
        normal: true,
    },
    Channel {
        name: "occlusion",
        at: ("", "occlusionTexture"),
        normal: false,
    },
    Channel {
        name: "emissive",
        at: ("", "emissiveTexture"),
        normal: false,
    },
    Channel {
        name: "specular weight",
        at: ("KHR_materials_specular", "specularTexture"),
        normal: false,
    },
    Channel {
        name: "specular colour",
        at: ("KHR_materials_specular", "specularColorTexture"),
        normal: false,
    },
    Channel {
        name: "clearcoat",
        at: ("KHR_materials_clearcoat", "clearcoatTexture"),
        normal: false,
    },
    Channel {
        name: "clearcoat roughness",
        at: ("KHR_materials_clearcoat", "clearcoatRoughnessTexture"),
        normal: false,
    },
    Channel {
        name: "clearcoat normal",
        at: ("KHR_materials_clearcoat", "clearcoatNormalTexture"),
        normal: true,
    },
    Channel {
        name: "sheen colour",
        at: ("KHR_materials_sheen", "sheenColorTexture"),
        normal: false,
    },
    Channel {
        name: "sheen roughness",
        at: ("KHR_materials_sheen", "sheenRoughnessTexture"),
        normal: false,
    },
    Channel {
        name: "thickness",
        at: ("KHR_materials_volume", "thicknessTexture"),
        normal: false,
    },
];

/// How a map names its coordinates; each reads the neutral (right) texel when honoured.
#[derive(Clone, Copy, Debug)]
enum Reading {
    /// `texCoord: 1`.
    Set1,
    /// `texCoord: 1` and a transform moving u by a whole period (wraps back).
    Set1Offset,
    /// `texCoord: 0` and a transform moving u by ½ (left half → right half).
    Set0Offset,
    /// `texCoord: 0` overridden to 1 by the transform's own `texCoord`.
    Set0OverriddenTo1,
    /// Control: `texCoord: 0`, no transform — reads the wrong texel.
    WrongSet0,
}

fn texture_info(texture: usize, r: Reading) -> String {
    let (set, transform) = match r {
        Reading::Set1 => (1, None),
        Reading::Set1Offset => (1, Some(r#"{"offset": [1, 0]}"#)),
        Reading::Set0Offset => (0, Some(r#"{"offset": [0.5, 0]}"#)),
        Reading::Set0OverriddenTo1 => (0, Some(r#"{"texCoord": 1}"#)),
        Reading::WrongSet0 => (0, None),
    };
    match transform {
        None => format!(r#"{{"index": {texture}, "texCoord": {set}}}"#),
        Some(t) => format!(
            r#"{{"index": {texture}, "texCoord": {set}, "extensions": {{"KHR_texture_transform": {t}}}}}"#
        ),
    }
}

fn png(texels: [[u8; 4]; 2]) -> String {
    let img = image::RgbaImage::from_fn(2, 1, |x, _| image::Rgba(texels[x as usize]));
    let mut bytes = Vec::new();
    img.write_to(
        &mut std::io::Cursor::new(&mut bytes),
        image::ImageFormat::Png,
    )
    .unwrap();
    base64::engine::general_purpose::STANDARD.encode(bytes)
}

/// The material's JSON with `maps` (channel, reading).
fn material(maps: &[(Channel, Reading)]) -> String {
    let mut top: Vec<String> = vec![r#""emissiveFactor": [0.2, 0.2, 0.2]"#.into()];
    let mut groups: std::collections::BTreeMap<&str, Vec<String>> = Default::default();
    groups.entry("pbrMetallicRoughness").or_default().extend([
        r#""baseColorFactor": [0.8, 0.7, 0.6, 1]"#.to_string(),
        r#""metallicFactor": 0.2"#.to_string(),
        r#""roughnessFactor": 0.6"#.to_string(),
    ]);
    // Every extension's factors, so each map has something to scale.
    for (ext, factors) in [
        ("KHR_materials_specular", r#""specularFactor": 1"#),
        (
            "KHR_materials_clearcoat",
            r#""clearcoatFactor": 1, "clearcoatRoughnessFactor": 0.5"#,
        ),
        (
            "KHR_materials_sheen",
            r#""sheenColorFactor": [1, 1, 1], "sheenRoughnessFactor": 0.5"#,
        ),
        ("KHR_materials_transmission", r#""transmissionFactor": 0.5"#),
        (
            "KHR_materials_volume",
            r#""thicknessFactor": 1, "attenuationDistance": 0.25, "attenuationColor": [0.2, 0.5, 0.8]"#,
        ),
    ] {
        groups.entry(ext).or_default().push(factors.to_string());
    }
    for (c, r) in maps {
        let info = texture_info(usize::from(c.normal), *r);
        let member = format!(r#""{}": {info}"#, c.at.1);
        if c.at.0.is_empty() {
            top.push(member);
        } else {
            groups.entry(c.at.0).or_default().push(member);
        }
    }
    let mut exts = Vec::new();
    for (group, members) in groups {
        let body = format!(r#"{{{}}}"#, members.join(", "));
        if group.starts_with("KHR_") {
            exts.push(format!(r#""{group}": {body}"#));
        } else {
            top.push(format!(r#""{group}": {body}"#));
        }
    }
    if !exts.is_empty() {
        top.push(format!(r#""extensions": {{{}}}"#, exts.join(", ")));
    }
    format!("{{{}}}", top.join(", "))
}

/// A glTF of the lit quad drawn with `material_json`, written to a scratch file.
fn document(name: &str, material_json: &str) -> PathBuf {
    let positions = [
        [-1.0f32, -1.0, 0.0],
        [1.0, -1.0, 0.0],
        [1.0, 1.0, 0.0],
        [-1.0, 1.0, 0.0],
    ];
    // Set 0 in u ∈ [0.05, 0.45] (the left texel), set 1 in [0.55, 0.95] (the right one).
    // u runs along x on the first triangle and along y on the second, so the generated
    // tangents differ at the two shared corners and the mesh is re-indexed (vertices added).
    let uv0 = [[0.05f32, 1.0], [0.45, 1.0], [0.45, 0.0], [0.45, 1.0]];
    let uv1 = [[0.55f32, 1.0], [0.95, 1.0], [0.95, 0.0], [0.95, 1.0]];
    let mut b: Vec<u8> = Vec::new();
    for p in positions {
        p.iter().for_each(|v| b.extend_from_slice(&v.to_le_bytes()));
    }
    for _ in 0..4 {
        [0.0f32, 0.0, 1.0]
            .iter()
            .for_each(|v| b.extend_from_slice(&v.to_le_bytes()));
    }
    for uv in uv0.iter().chain(&uv1) {
        uv.iter()
            .for_each(|v| b.extend_from_slice(&v.to_le_bytes()));
    }
    for i in [0u16, 1, 2, 0, 2, 3] {
        b.extend_from_slice(&i.to_le_bytes());
    }
    let enc = |x: &[u8]| base64::engine::general_purpose::STANDARD.encode(x);
    let data = png([[0, 0, 0, 0], [255; 4]]);
    let normal = png([[0, 0, 0, 255], [128, 128, 255, 255]]);
    let json = format!(
        r#"{{"asset": {{"version": "2.0"}},
  "extensionsUsed": ["KHR_texture_transform", "KHR_lights_punctual", "KHR_materials_specular",
    "KHR_materials_clearcoat", "KHR_materials_sheen", "KHR_materials_transmission", "KHR_materials_volume"],
  "extensions": {{"KHR_lights_punctual": {{"lights": [{{"type": "directional", "intensity": 3}}]}}}},
  "scene": 0, "scenes": [{{"nodes": [0, 1, 2]}}],
  "nodes": [{{"mesh": 0}}, {{"camera": 0, "translation": [0, 0, 2]}},
            {{"rotation": [-0.2, 0.2, 0, 0.959], "extensions": {{"KHR_lights_punctual": {{"light": 0}}}}}}],
  "cameras": [{{"type": "perspective", "perspective": {{"yfov": 1.2, "znear": 0.1, "zfar": 10, "aspectRatio": 1}}}}],
  "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2, "TEXCOORD_1": 3}},
    "indices": 4, "material": 0}}]}}],
  "materials": [{material_json}],
  "samplers": [{{"magFilter": 9728, "minFilter": 9728}}],
  "textures": [{{"source": 0, "sampler": 0}}, {{"source": 1, "sampler": 0}}],
  "images": [{{"uri": "data:image/png;base64,{data}"}}, {{"uri": "data:image/png;base64,{normal}"}}],
  "buffers": [{{"byteLength": {len}, "uri": "data:application/octet-stream;base64,{buf}"}}],
  "bufferViews": [{{"buffer": 0, "byteLength": 48}}, {{"buffer": 0, "byteOffset": 48, "byteLength": 48}},
    {{"buffer": 0, "byteOffset": 96, "byteLength": 32}}, {{"buffer": 0, "byteOffset": 128, "byteLength": 32}},
    {{"buffer": 0, "byteOffset": 160, "byteLength": 12}}],
  "accessors": [
    {{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-1, -1, 0], "max": [1, 1, 0]}},
    {{"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"}},
    {{"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"}},
    {{"bufferView": 3, "componentType": 5126, "count": 4, "type": "VEC2"}},
    {{"bufferView": 4, "componentType": 5123, "count": 6, "type": "SCALAR"}}]}}"#,
        len = b.len(),
        buf = enc(&b),
    );
    let dir = std::env::temp_dir().join(format!(
        "texmap-uv-sets-{}-{:?}",
        std::process::id(),
        std::thread::current().id()
    ));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(format!("{name}.gltf"));
    std::fs::write(&path, json).unwrap();
    path
}

/// How the frame is lit and shaded.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Mode {
    /// Per-pixel (Phong) shading with the file's light and the ambient light.
    PerPixel,
    /// Gouraud shading: the maps it reads (base colour, occlusion, emissive) still per pixel.
    Gouraud,
    /// Per-pixel shading with an environment (image-based light).
    Environment,
}

/// A panorama brighter above than below, so tilted normals and occlusion show: made once,
/// so every frame shares its prefiltered levels (clones share the cache).
fn environment() -> Environment {
    static ENV: std::sync::OnceLock<Environment> = std::sync::OnceLock::new();
    ENV.get_or_init(|| {
        let t = Texture2D::from_fn(32, 16, TextureOptions::default(), |_, y| {
            let up = 1.0 - y as f32 / 15.0;
            (Vec3::new(0.3, 0.4, 0.5) + Vec3::new(1.2, 1.0, 0.8) * up).extend(1.0)
        })
        .unwrap();
        Environment::new(EnvironmentMap::Equirect(t), "gradient")
    })
    .clone()
}

/// The frame (RGB8) of the quad drawn with `maps` in `mode`.
fn frame(mode: Mode, name: &str, maps: &[(Channel, Reading)]) -> Vec<u8> {
    let path = document(name, &material(maps));
    let loaded = load(&path, &LoadOptions::default()).unwrap_or_else(|e| panic!("{name}: {e}"));
    let mut scene = loaded.scene;
    let mut settings = Settings::new(24, 24);
    match mode {
        Mode::PerPixel => {}
        Mode::Gouraud => settings = settings.with_shading(ShadingMode::Gouraud),
        Mode::Environment => scene.environment = Some(environment()),
    }
    let camera = scene.camera.expect("the file's camera");
    render(&scene, &camera, &settings).unwrap().to_srgb8()
}

fn max_difference(a: &[u8], b: &[u8]) -> u8 {
    a.iter()
        .zip(b)
        .map(|(x, y)| x.abs_diff(*y))
        .max()
        .unwrap_or(0)
}

const READINGS: [Reading; 4] = [
    Reading::Set1,
    Reading::Set1Offset,
    Reading::Set0Offset,
    Reading::Set0OverriddenTo1,
];

/// The maps a mode reads: Gouraud shading reads the base colour, occlusion and emission
/// only; the thickness matters only to the environment seen through the surface.
fn read_in(mode: Mode, c: &Channel) -> bool {
    match mode {
        Mode::Gouraud => matches!(c.name, "base colour" | "occlusion" | "emissive"),
        Mode::PerPixel => c.name != "thickness",
        Mode::Environment => true,
    }
}

#[test]
fn each_map_reads_its_own_uv_set_and_transform_per_pixel() {
    check(Mode::PerPixel);
}

#[test]
fn each_map_reads_its_own_uv_set_and_transform_in_gouraud_shading() {
    check(Mode::Gouraud);
}

#[test]
fn each_map_reads_its_own_uv_set_and_transform_under_an_environment() {
    check(Mode::Environment);
}

fn check(mode: Mode) {
    let frame = |name: &str, maps: &[(Channel, Reading)]| frame(mode, name, maps);
    let reference = frame("reference", &[]);
    for (k, c) in CHANNELS.iter().enumerate() {
        if !read_in(mode, c) {
            continue;
        }
        // A neutral factor texel is exactly 1, so the right reading changes no bit; a neutral
        // normal texel (128, 128, 255) is flat to 1/255.
        let tolerance = if c.normal { 2 } else { 0 };
        let differs = |a: &[u8], b: &[u8], what: &str| {
            let d = max_difference(a, b);
            assert!(
                d > tolerance,
                "{mode:?}, {}, {what}: the control reading the wrong texel changes the frame by {d}/255 only",
                c.name
            );
        };
        let matches = |a: &[u8], b: &[u8], what: String| {
            let d = max_difference(a, b);
            assert!(
                d <= tolerance,
                "{mode:?}, {}, {what}: differs by {d}/255",
                c.name
            );
        };
        // Alone, against the material without maps.
        let wrong = frame(&format!("wrong{k}"), &[(*c, Reading::WrongSet0)]);
        differs(&wrong, &reference, "alone");
        for (i, r) in READINGS.iter().enumerate() {
            let alone = frame(&format!("alone{k}_{i}"), &[(*c, *r)]);
            matches(&alone, &reference, format!("alone, {r:?}"));
        }
        // With every other map (each on another reading), against the same without this one.
        for (i, r) in READINGS.iter().enumerate() {
            let others: Vec<(Channel, Reading)> = CHANNELS
                .iter()
                .enumerate()
                .filter(|(m, other)| *m != k && read_in(mode, other))
                .map(|(m, other)| (*other, READINGS[(i + m) % READINGS.len()]))
                .collect();
            let without = frame(&format!("others{k}_{i}"), &others);
            let with = |reading: Reading, name: String| {
                let mut maps = others.clone();
                maps.push((*c, reading));
                frame(&name, &maps)
            };
            matches(
                &with(*r, format!("all{k}_{i}")),
                &without,
                format!("with the others, {r:?}"),
            );
            if i == 0 {
                let wrong = with(Reading::WrongSet0, format!("allwrong{k}"));
                differs(&wrong, &without, "with the others");
            }
        }
    }
}
