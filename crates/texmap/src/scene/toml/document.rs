//! One TOML scene file → [`Loaded`]: the text is parsed into the `spec` tables (a syntax
//! error or an unknown key names its line), then each table is turned into scene data in
//! file order — cameras, lights, materials, meshes, volumes — and tangents are generated
//! where a normal map needs them. A table's own problem is reported with the file and the
//! table (`materials.wood: …`); errors from the files it names name those files.

use std::collections::BTreeMap;
use std::path::Path;

use glam::{Vec3, Vec4};

use super::cameras::camera;
use super::environment::environment;
use super::lights::{default_light, light, shadows};
use super::materials::material;
use super::meshes::{add_mesh, MeshMaterials};
use super::placement::placement;
use super::projectors::projector;
use super::spec::SceneFile;
use super::volumes::volume;
use crate::scene::asset::{AssetInfo, LoadOptions, Loaded};
use crate::scene::files::read_bounded;
use crate::scene::texture_cache::TextureCache;
use crate::scene::{tangents, Scene};
use crate::shading::{Light, Material};
use crate::{Error, Result};

/// Loads a `.toml` scene file.
///
/// # Errors
/// An [`Error`] naming the file (the scene file, or a model, image or scan it names) and the
/// problem, one line.
pub fn load(path: &Path, options: &LoadOptions) -> Result<Loaded> {
    let bytes = read_bounded(path, options.max_buffer_bytes)?;
    let text = String::from_utf8(bytes).map_err(|_| Error::decode(path, "not UTF-8 text"))?;
    let spec: SceneFile = ::toml::from_str(&text).map_err(|e| {
        let line = e
            .span()
            .map(|s| text.get(..s.start).unwrap_or(&text).matches('\n').count() + 1);
        let msg = e.message().replace('\n', " ");
        match line {
            Some(l) => Error::decode(path, format!("line {l}: {msg}")),
            None => Error::decode(path, msg),
        }
    })?;
    let dir = path.parent().unwrap_or(Path::new("")).to_path_buf();
    let err = |m: String| Error::decode(path, m);

    let mut out = Loaded {
        scene: Scene {
            background: Vec4::from(spec.background.unwrap_or([0.0, 0.0, 0.0, 1.0])),
            ambient_light: Vec3::from(spec.ambient.unwrap_or([1.0; 3])),
            ..Default::default()
        },
        cameras: Vec::new(),
        info: AssetInfo {
            format: "TOML scene".into(),
            ..Default::default()
        },
        volumes: Vec::new(),
        warnings: Vec::new(),
    };
    let mut textures = TextureCache::new(options);

    for (i, c) in spec.cameras.iter().enumerate() {
        let cam = camera(c).map_err(|e| err(format!("cameras[{i}]: {e}")))?;
        out.cameras.push(cam);
    }
    out.scene.camera = out.cameras.first().copied();

    let file_lights = spec.lights.as_deref().unwrap_or_default();
    for (i, l) in file_lights.iter().enumerate() {
        let l = light(l)
            .checked()
            .map_err(|e| err(format!("lights[{i}]: {e}")))?;
        out.scene.lights.push(l);
    }
    out.scene.shadows = shadows(spec.shadows.as_ref(), file_lights).map_err(err)?;
    if spec.lights.is_none() {
        out.scene.lights.push(default_light());
    }
    if let Some(e) = &spec.environment {
        let env = environment(&dir, e, options).map_err(|e| match e {
            Error::Parameter(msg) => err(format!("environment: {msg}")),
            other => other,
        })?;
        out.scene.environment = Some(env);
    }

    for (i, p) in spec.projectors.iter().enumerate() {
        let in_entry = |e: Error| match e {
            Error::Parameter(msg) => err(format!("projectors[{i}]: {msg}")),
            other => other,
        };
        if let Some(p) = projector(&dir, p, &mut textures).map_err(in_entry)? {
            out.scene.projectors.push(p);
        }
    }

    let mut by_name = BTreeMap::new();
    for (name, m) in &spec.materials {
        let mat = material(&dir, m, &mut textures).map_err(|e| match e {
            Error::Parameter(msg) => err(format!("materials.{name}: {msg}")),
            other => other,
        })?;
        by_name.insert(name.clone(), out.scene.materials.len());
        out.scene.materials.push(mat);
        out.info.material_names.push(name.clone());
    }
    let materials = MeshMaterials {
        by_name,
        default: out.scene.materials.len(),
    };
    out.scene.materials.push(Material::default());
    out.info.material_names.push("(default)".into());

    for (i, m) in spec.meshes.iter().enumerate() {
        add_mesh(&mut out, path, i, m, &materials, options)?;
    }

    // Volumes shade with the file's own lights, else with a headlight.
    let volume_lights: &[Light] = if file_lights.is_empty() {
        &[]
    } else {
        &out.scene.lights
    };
    for (i, v) in spec.volumes.iter().enumerate() {
        let transform = placement(v.translate, v.rotate, v.scale.as_ref(), v.matrix)
            .map_err(|e| err(format!("volumes[{i}]: {e}")))?;
        let sv = volume(&dir, v, transform, volume_lights, options).map_err(|e| match e {
            Error::Parameter(msg) | Error::Unsupported(msg) => err(format!("volumes[{i}]: {msg}")),
            other => other,
        })?;
        out.info.volumes.push(sv.source.display().to_string());
        out.volumes.push(sv);
    }
    super::layers::check_uv_sets(&out.scene, &out.info.material_names).map_err(err)?;
    out.info.default_light = spec.lights.is_none();
    for i in tangents::generate_where_needed(&mut out.scene.meshes, &out.scene.materials) {
        out.warnings.push(format!(
            "{}: mesh {i}: no tangents for its normal map (it lacks normals or uvs)",
            path.display()
        ));
    }
    out.warnings.append(&mut textures.warnings);
    out.info.textures.append(&mut textures.infos);
    Ok(out)
}
