//! `[[meshes]]` → meshes: a built-in primitive (sizes default to 1), or every mesh of a glTF
//! or OBJ file, which brings its materials along unless `material` names one to use
//! instead. Either is placed (`placement`), and may generate its texture coordinates
//! (`texgen`) before the placement applies. A model file keeps its own node transforms, the
//! entry's placement applied after them; its cameras and volumes are not taken.

use std::collections::BTreeMap;
use std::path::Path;

use super::placement::placement;
use super::spec::MeshSpec;
use super::texgen::apply_texgen;
use crate::scene::asset::{LoadOptions, Loaded};
use crate::scene::format::SceneFormat;
use crate::scene::primitives::{Primitive, MAX_PRIMITIVE_VERTICES, MAX_SEGMENTS};
use crate::{Error, Result};

/// The materials a `[[meshes]]` entry may name, and the one a primitive gets otherwise.
pub(super) struct MeshMaterials {
    /// `[materials]` names → their index in `Scene::materials`.
    pub(super) by_name: BTreeMap<String, usize>,
    /// White Phong, for primitives that name none.
    pub(super) default: usize,
}

/// Adds the meshes of entry `i` (`m`) of the scene file `path` to `out`.
pub(super) fn add_mesh(
    out: &mut Loaded,
    path: &Path,
    i: usize,
    m: &MeshSpec,
    materials: &MeshMaterials,
    options: &LoadOptions,
) -> Result<()> {
    let err = |e: String| Error::decode(path, format!("meshes[{i}]: {e}"));
    let dir = path.parent().unwrap_or(Path::new(""));
    let transform = placement(m.translate, m.rotate, m.scale.as_ref(), m.matrix).map_err(err)?;
    let named = match &m.material {
        Some(n) => Some(
            *materials
                .by_name
                .get(n)
                .ok_or_else(|| err(format!("no material named {n:?} in [materials]")))?,
        ),
        None => None,
    };
    match (&m.file, &m.primitive) {
        (Some(file), None) => {
            let full = dir.join(file);
            let sub = match SceneFormat::of(&full)? {
                SceneFormat::Gltf => {
                    let options = match &m.variant {
                        Some(v) => options.clone().variant(Some(v.clone())),
                        None => options.clone(),
                    };
                    crate::scene::gltf::load(&full, &options)?
                }
                SceneFormat::Obj if m.variant.is_some() => {
                    return Err(err(
                        "variant names a glTF material variant; an OBJ file has none".to_string(),
                    ))
                }
                SceneFormat::Obj => crate::scene::obj::load(&full, options)?,
                SceneFormat::Toml => {
                    return Err(err(
                        "a scene file cannot include another scene file".to_string()
                    ))
                }
            };
            let (scene, info) = (&mut out.scene, &mut out.info);
            let offset = scene.materials.len();
            for (k, mut mesh) in sub.scene.meshes.into_iter().enumerate() {
                if let Some(t) = &m.texgen {
                    apply_texgen(&mut mesh, t).map_err(err)?;
                }
                mesh.world_from_object = transform * mesh.world_from_object;
                mesh.material = named.unwrap_or(mesh.material + offset);
                info.mesh_names.push(format!(
                    "{}: {}",
                    file.display(),
                    sub.info.mesh_names.get(k).map_or("", String::as_str)
                ));
                scene.meshes.push(mesh);
            }
            scene.materials.extend(sub.scene.materials);
            info.variants.extend(sub.info.variants);
            if sub.info.variant.is_some() {
                info.variant = sub.info.variant;
            }
            info.material_names.extend(
                sub.info
                    .material_names
                    .into_iter()
                    .map(|n| format!("{}: {n}", file.display())),
            );
            info.textures.extend(sub.info.textures);
            out.warnings.extend(sub.warnings);
        }
        (None, Some(kind)) => {
            let p = primitive(kind, m).map_err(err)?;
            let mut mesh = p.mesh(named.unwrap_or(materials.default));
            if let Some(t) = &m.texgen {
                apply_texgen(&mut mesh, t).map_err(err)?;
            }
            mesh.world_from_object = transform;
            out.info.mesh_names.push(kind.clone());
            out.scene.meshes.push(mesh);
        }
        _ => return Err(err("give exactly one of `file` and `primitive`".to_string())),
    }
    Ok(())
}

/// The built-in primitive an entry names, with its sizes; the error is the entry's problem.
fn primitive(kind: &str, m: &MeshSpec) -> std::result::Result<Primitive, String> {
    let positive = |v: Option<f32>, d: f32, what: &str| {
        let v = v.unwrap_or(d);
        if v.is_finite() && v > 0.0 {
            Ok(v)
        } else {
            Err(format!("{what} must be a positive number"))
        }
    };
    let size = positive(m.size, 1.0, "size")?;
    // Counts are refused, not clamped, outside their range; and a mesh may not exceed the
    // vertex budget (checked before anything is allocated).
    let count = |v: Option<u32>, d: u32, min: u32, what: &str| {
        let v = v.unwrap_or(d);
        if (min..=MAX_SEGMENTS).contains(&v) {
            Ok(v)
        } else {
            Err(format!("{what} {v} is outside {min}..={MAX_SEGMENTS}"))
        }
    };
    let budget = |vertices: u64, what: String| {
        if vertices <= MAX_PRIMITIVE_VERTICES {
            Ok(())
        } else {
            Err(format!(
                "{what} makes {vertices} vertices, above a primitive's budget of \
                 {MAX_PRIMITIVE_VERTICES}"
            ))
        }
    };
    Ok(match kind {
        "plane" => {
            let divisions = count(m.divisions, 1, 1, "divisions")?;
            let side = u64::from(divisions) + 1;
            budget(side * side, format!("divisions {divisions}"))?;
            Primitive::Plane {
                width: positive(m.width, size, "width")?,
                depth: positive(m.depth, size, "depth")?,
                divisions,
            }
        }
        "cube" => Primitive::Cube { size },
        "sphere" => {
            let segments = count(m.segments, 64, 3, "segments")?;
            let rings = count(m.rings, 33, 3, "rings")?;
            let n = (u64::from(segments) + 1) * u64::from(rings);
            budget(n, format!("segments {segments} × rings {rings}"))?;
            Primitive::Sphere {
                radius: positive(m.radius, 0.5 * size, "radius")?,
                segments,
                rings,
            }
        }
        "cylinder" | "cone" => {
            let radius = positive(m.radius, 0.5 * size, "radius")?;
            let height = positive(m.height, size, "height")?;
            let segments = count(m.segments, 64, 3, "segments")?;
            if kind == "cone" {
                Primitive::Cone {
                    radius,
                    height,
                    segments,
                }
            } else {
                Primitive::Cylinder {
                    radius,
                    height,
                    segments,
                }
            }
        }
        "torus" => {
            let segments = count(m.segments, 64, 3, "segments")?;
            let sides = count(m.rings, 24, 3, "rings")?;
            let n = (u64::from(segments) + 1) * (u64::from(sides) + 1);
            budget(n, format!("segments {segments} × rings {sides}"))?;
            Primitive::Torus {
                major: positive(m.major_radius, 0.375 * size, "major_radius")?,
                minor: positive(m.minor_radius, 0.125 * size, "minor_radius")?,
                segments,
                sides,
            }
        }
        other => {
            return Err(format!(
                "unknown primitive {other:?} (plane, cube, sphere, cylinder, cone, torus)"
            ))
        }
    })
}
