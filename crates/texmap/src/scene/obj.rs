//! Wavefront OBJ with MTL materials, through `tobj`.
//!
//! - Geometry: `v`, `vt`, `vn`, negative (relative) indices, polygons triangulated as fans,
//!   one mesh per object/group and material. Without `vn`, smooth (area-weighted) normals are
//!   computed when the file turns smoothing on (`s 1`…), else faces stay flat.
//! - OBJ's `vt` has v up; texmap's v runs down the image, so v → 1 − v once, here.
//! - MTL: `Ka` (K_A = mean), `Kd` (base colour), `Ks` (K_S = mean, with `illum` ≥ 2), `Ns`,
//!   `d` / `Tr` (opacity; below 1 blends), `illum` 0 (unlit), `map_Kd` (sRGB),
//!   `map_Ka` / `map_Ks` (sRGB), `map_Ns`, `map_d`, `bump` / `map_bump` (with `-bm`),
//!   `norm` (linear). Texture options (`-o`, `-s`, `-bm`, `-clamp`, …) are parsed: `-o`/`-s`
//!   become the slot's transform, `-clamp on` clamps to the edge. Windows `\` separators
//!   are accepted. Every referenced file follows the folder rule of `scene::files`.

use std::cell::RefCell;
use std::io::BufReader;
use std::path::Path;

use glam::{Vec2, Vec3, Vec4};

use super::asset::{AssetInfo, LoadOptions, Loaded};
use super::files::{read_bounded, resolve_reference};
use super::texture_cache::{channel_color_space, AlphaChannel, ImageSource, TextureCache};
use super::{AlphaMode, Light, Material, Mesh, Scene, TextureSlot};
use crate::shading::{MapChannel, MaterialMap};
use crate::texture::{ColorSpace, Sampler, TextureTransform, Wrap};
use crate::{Error, Result};

/// Loads an `.obj` file and the `.mtl` files it names.
pub fn load(path: &Path, options: &LoadOptions) -> Result<Loaded> {
    let bytes = read_bounded(path, options.max_buffer_bytes)?;
    // tobj slices statements by byte offsets after their keyword, which splits a character
    // when the keyword follows multi-byte whitespace: every line goes in trimmed.
    let text = trimmed_lines(&String::from_utf8_lossy(&bytes));
    let mtl_errors: RefCell<Vec<Error>> = RefCell::new(Vec::new());
    let load_mtl = |p: &Path| -> tobj::MTLLoadResult {
        let name = p.to_string_lossy().replace('\\', "/");
        let r = resolve_reference(path, &name, options)
            .and_then(|full| read_bounded(&full, options.max_buffer_bytes).map(|b| (full, b)));
        match r {
            Ok((full, b)) => {
                let mtl = trimmed_lines(&String::from_utf8_lossy(&b));
                if let Err(e) = check_mtl(&full, &mtl) {
                    mtl_errors.borrow_mut().push(e);
                    return Err(tobj::LoadError::MaterialParseError);
                }
                let res = tobj::load_mtl_buf(&mut BufReader::new(mtl.as_bytes()));
                if let Err(e) = &res {
                    mtl_errors
                        .borrow_mut()
                        .push(Error::decode(full, format!("malformed MTL: {e}")));
                }
                res
            }
            Err(e) => {
                mtl_errors.borrow_mut().push(e);
                Err(tobj::LoadError::OpenFileFailed)
            }
        }
    };
    let opts = tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        ignore_points: true,
        ignore_lines: true,
    };
    let (models, materials) =
        tobj::load_obj_buf(&mut BufReader::new(text.as_bytes()), &opts, load_mtl)
            .map_err(|e| obj_error(path, &text, &e))?;
    let mut warnings = Vec::new();
    let materials = match materials {
        Ok(m) => m,
        Err(_) => {
            let errors = mtl_errors.into_inner();
            match errors.into_iter().next() {
                Some(e) if !options.lenient => return Err(e),
                Some(e) => {
                    warnings.push(format!("{e} (default material used)"));
                    Vec::new()
                }
                None => Vec::new(),
            }
        }
    };
    let smooth = text.lines().any(|l| {
        let mut w = l.split_whitespace();
        w.next() == Some("s") && w.next().is_some_and(|v| v != "off" && v != "0")
    });

    let mut textures = TextureCache::new(options);
    let mut scene = Scene {
        ambient_light: Vec3::ONE,
        background: Vec4::new(0.0, 0.0, 0.0, 1.0),
        lights: vec![Light::Directional {
            direction: Vec3::new(0.3, 0.8, 0.5).normalize(),
            color: Vec3::ONE,
        }],
        ..Default::default()
    };
    let mut info = AssetInfo {
        format: "Wavefront OBJ".into(),
        default_light: true,
        ..Default::default()
    };
    for m in &materials {
        scene
            .materials
            .push(material(path, m, &mut textures, options)?);
        info.material_names.push(m.name.clone());
    }
    scene.materials.push(Material::default());
    info.material_names.push("(default)".into());
    let default_material = scene.materials.len() - 1;

    for model in models {
        let mesh = model.mesh;
        let nv = mesh.positions.len() / 3;
        if mesh.indices.iter().any(|&i| i as usize >= nv) {
            return Err(Error::decode(
                path,
                format!("object {}: a face index is out of range", model.name),
            ));
        }
        let positions: Vec<Vec3> = mesh
            .positions
            .chunks_exact(3)
            .map(|c| Vec3::new(c[0], c[1], c[2]))
            .collect();
        let mut normals: Vec<Vec3> = if mesh.normals.len() == mesh.positions.len() {
            mesh.normals
                .chunks_exact(3)
                .map(|c| Vec3::new(c[0], c[1], c[2]).normalize_or_zero())
                .collect()
        } else {
            Vec::new()
        };
        let uvs: Vec<Vec2> = if mesh.texcoords.len() == nv * 2 {
            mesh.texcoords
                .chunks_exact(2)
                .map(|c| Vec2::new(c[0], 1.0 - c[1]))
                .collect()
        } else {
            Vec::new()
        };
        let colors: Vec<Vec4> = if mesh.vertex_color.len() == mesh.positions.len() {
            mesh.vertex_color
                .chunks_exact(3)
                .map(|c| Vec4::new(c[0], c[1], c[2], 1.0))
                .collect()
        } else {
            Vec::new()
        };
        if normals.is_empty() && smooth {
            normals = smooth_normals(&positions, &mesh.indices);
        }
        let material = mesh
            .material_id
            .filter(|&i| i < materials.len())
            .unwrap_or(default_material);
        info.mesh_names.push(if model.name.is_empty() {
            "(unnamed)".into()
        } else {
            model.name.clone()
        });
        scene.meshes.push(Mesh {
            positions,
            normals,
            uvs,
            colors,
            indices: mesh.indices,
            material,
            ..Default::default()
        });
    }
    for i in super::tangents::generate_where_needed(&mut scene.meshes, &scene.materials) {
        warnings.push(format!(
            "{}: mesh {i}: no tangents for its normal map (it lacks normals or uvs)",
            path.display()
        ));
    }
    warnings.append(&mut textures.warnings);
    info.textures = textures.infos;
    Ok(Loaded {
        scene,
        cameras: Vec::new(),
        info,
        volumes: Vec::new(),
        warnings,
    })
}

/// One line naming the file, and the first offending line when a parse error can be placed.
/// `text` with every line's leading whitespace removed.
fn trimmed_lines(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for l in text.lines() {
        out.push_str(l.trim_start());
        out.push('\n');
    }
    out
}

/// Refuses the MTL statements tobj would panic on: a colour (`Ka`, `Kd`, `Ks`, `Ke`) with
/// fewer than three numbers. The error names the file and line, not the line's content.
fn check_mtl(path: &Path, text: &str) -> Result<()> {
    for (n, line) in text.lines().enumerate() {
        let mut w = line.split_whitespace();
        if let Some(key @ ("Ka" | "Kd" | "Ks" | "Ke")) = w.next() {
            let numbers = w.take(3).filter(|x| x.parse::<f32>().is_ok()).count();
            if numbers < 3 {
                return Err(Error::decode(
                    path,
                    format!("line {}: {key} needs three numbers (r g b)", n + 1),
                ));
            }
        }
    }
    Ok(())
}

/// The error for a file tobj refused: the first line whose syntax is wrong, by statement
/// (the line's content is not quoted: error messages never echo a file).
fn obj_error(path: &Path, text: &str, e: &tobj::LoadError) -> Error {
    let bad = text.lines().enumerate().find(|(_, l)| !line_is_valid(l));
    match bad {
        Some((n, l)) => {
            let what = match l.split_whitespace().next() {
                Some("v" | "vn") => "needs three numbers",
                Some("vt") => "needs at least one number",
                Some("f") => "needs three or more vertex references (v, v/vt, v//vn or v/vt/vn)",
                _ => "is malformed",
            };
            let key = l.split_whitespace().next().unwrap_or("statement");
            Error::decode(path, format!("line {}: `{key}` {what} ({e})", n + 1))
        }
        None => Error::decode(path, format!("malformed OBJ: {e}")),
    }
}

/// A quick check of the statements whose syntax tobj enforces.
fn line_is_valid(line: &str) -> bool {
    let mut w = line.split_whitespace();
    let floats = |w: std::str::SplitWhitespace, min: usize| {
        let v: Vec<&str> = w.collect();
        v.len() >= min && v.iter().all(|x| x.parse::<f32>().is_ok())
    };
    match w.next() {
        Some("v") | Some("vn") => floats(w, 3),
        Some("vt") => floats(w, 1),
        Some("f") => {
            let v: Vec<&str> = w.collect();
            v.len() >= 3
                && v.iter().all(|c| {
                    c.split('/').enumerate().all(|(k, x)| {
                        (k > 0 && x.is_empty()) || x.parse::<i64>().is_ok_and(|i| i != 0)
                    })
                })
        }
        _ => true,
    }
}

/// Area-weighted vertex normals.
fn smooth_normals(positions: &[Vec3], indices: &[u32]) -> Vec<Vec3> {
    let mut n = vec![Vec3::ZERO; positions.len()];
    for t in indices.chunks_exact(3) {
        let [a, b, c] = [t[0], t[1], t[2]].map(|i| i as usize);
        let f = (positions[b] - positions[a]).cross(positions[c] - positions[a]);
        n[a] += f;
        n[b] += f;
        n[c] += f;
    }
    n.into_iter().map(|v| v.normalize_or(Vec3::Y)).collect()
}

/// A texture statement's options and file name (`-bm 0.5 -clamp on dir\file.png`).
struct MapSpec {
    file: String,
    bump_multiplier: f32,
    /// `-clamp on`: clamp to the edge; else repeat.
    wrap: Wrap,
    offset: Vec2,
    scale: Vec2,
}

fn parse_map(s: &str) -> MapSpec {
    let tokens: Vec<&str> = s.split_whitespace().collect();
    let mut spec = MapSpec {
        file: String::new(),
        bump_multiplier: 1.0,
        wrap: Wrap::Repeat,
        offset: Vec2::ZERO,
        scale: Vec2::ONE,
    };
    // Option name → how many arguments it takes (up to 3 for -o/-s/-t).
    let mut i = 0;
    let num = |t: Option<&&str>| t.and_then(|x| x.parse::<f32>().ok());
    while i < tokens.len() {
        let t = tokens[i];
        match t {
            "-bm" => {
                spec.bump_multiplier = num(tokens.get(i + 1)).unwrap_or(1.0);
                i += 2;
            }
            "-clamp" => {
                spec.wrap = if tokens.get(i + 1) == Some(&"on") {
                    Wrap::ClampToEdge
                } else {
                    Wrap::Repeat
                };
                i += 2;
            }
            "-o" | "-s" | "-t" => {
                let mut vals = Vec::new();
                let mut j = i + 1;
                while j < tokens.len() && vals.len() < 3 {
                    match tokens[j].parse::<f32>() {
                        Ok(v) => vals.push(v),
                        Err(_) => break,
                    }
                    j += 1;
                }
                let v = Vec2::new(
                    vals.first()
                        .copied()
                        .unwrap_or(if t == "-s" { 1.0 } else { 0.0 }),
                    vals.get(1)
                        .copied()
                        .unwrap_or(if t == "-s" { 1.0 } else { 0.0 }),
                );
                match t {
                    "-o" => spec.offset = v,
                    "-s" => spec.scale = v,
                    _ => {}
                }
                i = j;
            }
            "-blendu" | "-blendv" | "-cc" | "-texres" | "-imfchan" | "-type" => i += 2,
            "-mm" => i += 3,
            _ => {
                // The rest is the file name (it may contain spaces).
                spec.file = tokens[i..].join(" ").replace('\\', "/");
                break;
            }
        }
    }
    spec
}

fn material(
    path: &Path,
    m: &tobj::Material,
    textures: &mut TextureCache,
    options: &LoadOptions,
) -> Result<Material> {
    let mean = |c: [f32; 3]| (c[0] + c[1] + c[2]) / 3.0;
    let illum = m.illumination_model.unwrap_or(2);
    let opacity = m
        .dissolve
        .or_else(|| {
            m.unknown_param
                .get("Tr")
                .and_then(|t| t.trim().parse::<f32>().ok())
                .map(|t| 1.0 - t)
        })
        .unwrap_or(1.0)
        .clamp(0.0, 1.0);
    let kd = m.diffuse.unwrap_or([0.8, 0.8, 0.8]);
    let mut mat = Material {
        base_color: Vec4::new(kd[0], kd[1], kd[2], opacity),
        ambient: m.ambient.map_or(0.2, mean),
        diffuse: 0.8,
        specular: if illum >= 2 {
            m.specular.map_or(0.0, mean)
        } else {
            0.0
        },
        shininess: m.shininess.unwrap_or(32.0).max(0.0),
        unlit: illum == 0,
        double_sided: true,
        alpha_mode: if opacity < 1.0 {
            AlphaMode::Blend
        } else {
            AlphaMode::Opaque
        },
        ..Default::default()
    };
    // With a diffuse map, K_D scales the texture (most exporters write Kd 0.8 beside map_Kd;
    // the peer draws the texture alone): the base colour is the texture, K_D stays the
    // Phong coefficient.
    let mut slot =
        |spec: &str, color_space: ColorSpace| -> Result<Option<(TextureSlot, MapSpec)>> {
            let spec = parse_map(spec);
            if spec.file.is_empty() {
                return Ok(None);
            }
            let file = resolve_reference(path, &spec.file, options)?;
            let Some(tex) = textures.get(
                &file.to_string_lossy(),
                ImageSource::File(file.clone()),
                color_space,
                AlphaChannel::Keep,
            )?
            else {
                return Ok(None);
            };
            let mut s = TextureSlot::new(
                tex,
                Sampler::new(crate::texture::Filter::TRILINEAR, spec.wrap),
            );
            // OBJ's -o/-s act on v-up coordinates; in v-down ones the offset's v flips.
            s.transform = TextureTransform {
                offset: Vec2::new(spec.offset.x, -spec.offset.y),
                rotation: 0.0,
                scale: spec.scale,
            };
            Ok(Some((s, spec)))
        };
    if let Some(t) = &m.diffuse_texture {
        if let Some((s, _)) = slot(t, ColorSpace::Srgb)? {
            mat.base_color = Vec4::new(1.0, 1.0, 1.0, opacity);
            mat.base_color_texture = Some(s);
        }
    }
    let mut maps: Vec<(MapChannel, &String)> = Vec::new();
    if let Some(t) = &m.ambient_texture {
        maps.push((MapChannel::Ambient, t));
    }
    if let Some(t) = &m.specular_texture {
        maps.push((MapChannel::Specular, t));
    }
    if let Some(t) = &m.shininess_texture {
        maps.push((MapChannel::Shininess, t));
    }
    if let Some(t) = &m.dissolve_texture {
        maps.push((MapChannel::Alpha, t));
        if mat.alpha_mode == AlphaMode::Opaque {
            mat.alpha_mode = AlphaMode::Mask(0.5);
        }
    }
    if let Some(t) = &m.normal_texture {
        maps.push((MapChannel::Bump, t));
    }
    if let Some(t) = m.unknown_param.get("norm") {
        maps.push((MapChannel::Normal, t));
    }
    for (channel, t) in maps {
        if let Some((s, spec)) = slot(t, channel_color_space(channel))? {
            let scale = if channel == MapChannel::Bump {
                spec.bump_multiplier
            } else {
                1.0
            };
            mat.maps.push(MaterialMap {
                channel,
                slot: s,
                scale,
            });
        }
    }
    Ok(mat)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn texture_options_are_parsed() {
        let s = parse_map("-bm 0.5 -clamp on -o 0.1 0.2 -s 2 3 1 dir\\my file.png");
        assert_eq!(s.file, "dir/my file.png");
        assert_eq!(s.bump_multiplier, 0.5);
        assert_eq!(s.wrap, Wrap::ClampToEdge);
        assert_eq!(s.offset, Vec2::new(0.1, 0.2));
        assert_eq!(s.scale, Vec2::new(2.0, 3.0));
        assert_eq!(parse_map(".\\SpiderTex.jpg").file, "./SpiderTex.jpg");
    }

    #[test]
    fn line_checks() {
        assert!(line_is_valid("v 1 2 3"));
        assert!(line_is_valid("f 1/2/3 -1//2 4"));
        assert!(!line_is_valid("v 1 x 3"));
        assert!(!line_is_valid("f 1 2"));
        assert!(!line_is_valid("f 0 1 2"));
        assert!(line_is_valid("# comment"));
    }

    fn tmp(name: &str, body: &str) -> std::path::PathBuf {
        crate::scene::test_file("obj", name, body)
    }

    #[test]
    fn quad_with_negative_indices_and_flipped_v() {
        let p = tmp(
            "quad.obj",
            "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf -4/-4 -3/-3 -2/-2 -1/-1\n",
        );
        let l = load(&p, &LoadOptions::default()).unwrap();
        assert_eq!(l.scene.triangle_count(), 2);
        let m = &l.scene.meshes[0];
        // vt (0, 0) is the image's bottom-left: v = 1 in texmap's convention.
        let i = m.positions.iter().position(|&q| q == Vec3::ZERO).unwrap();
        assert_eq!(m.uvs[i], Vec2::new(0.0, 1.0));
    }

    #[test]
    fn a_colour_with_two_numbers_is_an_error_naming_the_mtl_and_line() {
        tmp("short.mtl", "newmtl m\nKd 1 1 1\nKs 0 0\n");
        let p = tmp(
            "short.obj",
            "mtllib short.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl m\nf 1 2 3\n",
        );
        let e = load(&p, &LoadOptions::default()).unwrap_err().to_string();
        assert!(
            e.contains("short.mtl") && e.contains("line 3") && e.contains("Ks"),
            "{e}"
        );
    }

    #[test]
    fn statements_after_multibyte_whitespace_keep_their_names() {
        // U+00A0, U+3000, U+00A0: seven bytes of whitespace before the keyword.
        let ws = "\u{a0}\u{3000}\u{a0}";
        tmp("ws.mtl", &format!("{ws}newmtl m\n{ws}Kd 1 0 0\n"));
        let p = tmp(
            "ws.obj",
            &format!(
                "mtllib ws.mtl\n{ws}o thing\nv 0 0 0\nv 1 0 0\nv 0 1 0\n{ws}usemtl m\nf 1 2 3\n"
            ),
        );
        let l = load(&p, &LoadOptions::default()).unwrap();
        assert_eq!(l.scene.triangle_count(), 1);
        // tobj takes an object's name from the byte after the line's first character.
        assert_eq!(l.info.mesh_names, ["thing"]);
        assert_eq!(l.info.material_names[0], "m");
    }

    #[test]
    fn malformed_line_is_named() {
        let p = tmp("bad.obj", "v 0 0 0\nv 1 zero 0\nv 0 1 0\nf 1 2 3\n");
        let e = load(&p, &LoadOptions::default()).unwrap_err().to_string();
        assert!(e.contains("bad.obj") && e.contains("line 2"), "{e}");
    }

    #[test]
    fn out_of_range_face_is_an_error() {
        let p = tmp("oor.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
        let e = load(&p, &LoadOptions::default()).unwrap_err().to_string();
        assert!(e.contains("oor.obj"), "{e}");
    }
}
