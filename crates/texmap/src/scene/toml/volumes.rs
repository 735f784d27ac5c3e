//! `[[volumes]]` → [`SceneVolume`]: a scan (NIfTI, NRRD, or raw with its grid described by
//! `dims` and the keys after it), its placement in the scene, its transfer function and how
//! to render it — the options of `texmap render scan.nii.gz`, with the same names and
//! defaults. The raw keys are errors for files with their own header (it would be unclear
//! which description wins). Documented in `docs/scenes.md`.

use std::path::Path;

use glam::{Mat4, Vec3};

use super::spec::VolumeSpec;
use crate::scene::format::SceneFormat;
use crate::scene::LoadOptions;
use crate::shading::Light;
use crate::texture::procedural::Solid;
use crate::volume::scene_volume::{parse_classification, parse_mode};
use crate::volume::sdf::{
    mask_field, mesh_field, smooth_field, FieldGrid, Hypertexture, Mask, SCAN_SMOOTHING,
};
use crate::volume::{
    load_scalars_with, load_volume_with, Method, RawDesc, ScalarType, SceneVolume,
    TransferFunction2D, Volume, VolumeOptions,
};
use crate::{Error, Result};

/// True for the file names whose header describes the grid.
fn has_header(file: &Path) -> bool {
    let l = file.to_string_lossy().to_ascii_lowercase();
    [".nii", ".nii.gz", ".nrrd", ".nhdr"]
        .iter()
        .any(|e| l.ends_with(e))
}

/// Loads and places one `[[volumes]]` entry. `transform` is the placement already read from
/// the table; `lights` are the scene's own lights (empty: the headlight).
/// `Error::Parameter` messages are the table's problem, for the caller to prefix.
pub(super) fn volume(
    dir: &Path,
    v: &VolumeSpec,
    transform: Mat4,
    lights: &[Light],
    load_options: &LoadOptions,
) -> Result<SceneVolume> {
    let options = &load_options.volume_options();
    let file = dir.join(&v.file);
    let mesh = matches!(
        SceneFormat::of(&file),
        Ok(SceneFormat::Obj | SceneFormat::Gltf)
    );
    if mesh || v.threshold.is_some() {
        let vol = if mesh {
            if v.threshold.is_some() {
                return Err(Error::parameter(
                    "threshold applies to a scan; a mesh file is drawn as its distance field",
                ));
            }
            mesh_field_volume(&file, v.sdf_res.unwrap_or(128), load_options)?
        } else {
            if v.sdf_res.is_some() {
                return Err(Error::parameter(
                    "sdf_res applies to a mesh file; a scan's field has the scan's grid",
                ));
            }
            scan_field_volume(&file, v.threshold.unwrap_or_default(), options)?
        };
        let mut sv = SceneVolume::new(vol, &file);
        sv.place(transform, v.ignore_orientation)?;
        sv.method = Method::Surface;
        return finish(sv, dir, v, lights);
    }
    let raw_keys =
        v.dtype.is_some() || v.spacing.is_some() || v.endian.is_some() || v.header_bytes.is_some();
    let raw = if raw_keys || v.dims.is_some() {
        if has_header(&file) {
            return Err(Error::parameter(format!(
                "{} has its own header: dims, dtype, spacing, endian and header_bytes are for raw files",
                v.file.display()
            )));
        }
        let dims = v.dims.ok_or_else(|| {
            Error::parameter(
                "dtype, spacing, endian and header_bytes describe a raw file and need dims",
            )
        })?;
        let scalar = match v.dtype.as_deref() {
            None => ScalarType::U8,
            Some(t) => ScalarType::parse(t).ok_or_else(|| {
                Error::parameter(format!(
                    "dtype {t:?} is not u8, i8, u16, i16, u32, i32, f32 or f64"
                ))
            })?,
        };
        let big_endian = match v.endian.as_deref() {
            None | Some("little") => false,
            Some("big") => true,
            Some(other) => {
                return Err(Error::parameter(format!(
                    "endian {other:?} is not little or big"
                )))
            }
        };
        Some(RawDesc {
            big_endian,
            header_bytes: v.header_bytes.unwrap_or(0),
            ..RawDesc::new(dims, scalar, Vec3::from(v.spacing.unwrap_or([1.0; 3])))
        })
    } else {
        None
    };
    let vol = load_volume_with(&file, raw.as_ref(), options)?;
    let mut sv = SceneVolume::new(vol, &file);
    sv.place(transform, v.ignore_orientation)?;
    finish(sv, dir, v, lights)
}

/// The table's rendering keys laid over a placed volume.
fn finish(
    mut sv: SceneVolume,
    dir: &Path,
    v: &VolumeSpec,
    lights: &[Light],
) -> Result<SceneVolume> {
    if let Some(tf) = &v.tf {
        sv.set_transfer(tf, dir)?;
    }
    if let Some(m) = &v.method {
        sv.method = Method::parse(m).ok_or_else(|| {
            Error::parameter(format!(
                "method {m:?} is not raymarch, slices, surface or hypertexture"
            ))
        })?;
    }
    look(&mut sv, v)?;
    let p = &mut sv.params;
    if let Some(m) = &v.mode {
        p.mode = parse_mode(m).ok_or_else(|| {
            Error::parameter(format!("mode {m:?} is not composite, mip, iso or xray"))
        })?;
    }
    if let Some(c) = &v.classification {
        p.classification = parse_classification(c).ok_or_else(|| {
            Error::parameter(format!("classification {c:?} is not post, pre or preint"))
        })?;
    }
    p.iso = v.iso;
    if let Some(c) = v.crop {
        p.crop = Some(c);
    }
    if let Some(s) = v.step {
        p.step = s;
    }
    p.shade = v.shade;
    p.jitter = v.jitter;
    p.empty_space_skipping = v.empty_space_skipping;
    if let Some(g) = &v.gradient_opacity {
        p.gradient_opacity = TransferFunction2D::parse_gradient(g)?;
    }
    p.lights = lights.to_vec();
    sv.validate()?;
    Ok(sv)
}

/// The distance-field keys: the surface's look and the hypertexture.
fn look(sv: &mut SceneVolume, v: &VolumeSpec) -> Result<()> {
    let given = v.solid.is_some()
        || v.solid_colors.is_some()
        || v.bump.is_some()
        || v.bump_frequency.is_some()
        || v.color.is_some()
        || v.hypertexture.is_some();
    if !given {
        return Ok(());
    }
    if let Some(table) = &v.hypertexture {
        if v.method.is_none() {
            sv.method = Method::Hypertexture;
        }
        let preset = match table.get("preset") {
            None => "fur".to_string(),
            Some(toml::Value::String(p)) => p.clone(),
            Some(other) => {
                return Err(Error::parameter(format!(
                    "hypertexture preset = {} is not a name",
                    text_of(other)
                )))
            }
        };
        let mut h = Hypertexture::preset(&preset).ok_or_else(|| {
            Error::parameter(format!(
                "hypertexture preset {preset:?} is not {}",
                crate::volume::sdf::hyper::PRESETS.join(", ")
            ))
        })?;
        for (k, value) in table.iter().filter(|(k, _)| k.as_str() != "preset") {
            h.set(k, &text_of(value))?;
        }
        sv.hypertexture = Some(h);
    }
    if !sv.method.is_distance_field() {
        return Err(Error::parameter(
            "solid, solid_colors, bump, bump_frequency, color and hypertexture draw a distance \
             field: give threshold (a scan), a mesh file, or method = \"surface\"",
        ));
    }
    let l = &mut sv.look;
    if let Some(name) = &v.solid {
        l.solid = Some(Solid::named(name).ok_or_else(|| {
            Error::parameter(format!(
                "solid {name:?} is not marble, wood, granite, clouds, checker3d or bricks"
            ))
        })?);
    }
    if let Some([a, b]) = v.solid_colors {
        l.solid_colors = Some([Vec3::from(a), Vec3::from(b)]);
    }
    if let Some(b) = v.bump {
        l.bump = b;
    }
    if let Some(f) = v.bump_frequency {
        l.bump_frequency = f;
    }
    if let Some(c) = v.color {
        l.color = Vec3::from(c);
    }
    Ok(())
}

/// A mesh file's distance field on `sdf_ref.py`'s grid (`res` voxels, margin 0.1).
fn mesh_field_volume(file: &Path, res: u32, options: &LoadOptions) -> Result<Volume> {
    let loaded = match SceneFormat::of(file)? {
        SceneFormat::Obj => crate::scene::obj::load(file, options)?,
        _ => crate::scene::gltf::load(file, options)?,
    };
    let tris = loaded.scene.world_triangles();
    let (lo, hi) = tris
        .bounds()
        .ok_or_else(|| Error::decode(file, "has no triangles: there is no surface to measure"))?;
    let grid = FieldGrid::around_box(lo, hi, res, 0.1)?;
    let bytes = grid.voxel_count().saturating_mul(8);
    if bytes > options.max_volume_bytes {
        return Err(Error::limits(
            file,
            format!(
                "its distance field of {}x{}x{} voxels needs {} MiB, above the limit of {} MiB",
                grid.dims[0],
                grid.dims[1],
                grid.dims[2],
                bytes >> 20,
                options.max_volume_bytes >> 20
            ),
        ));
    }
    let (field, _) = mesh_field(&tris, &grid)?;
    field.to_volume()
}

/// A scan's distance field: inside is value ≥ `threshold`.
fn scan_field_volume(file: &Path, threshold: f64, options: &VolumeOptions) -> Result<Volume> {
    let scan = load_scalars_with(file, None, options)?;
    let (lo, hi) = scan
        .values
        .iter()
        .fold((f32::INFINITY, f32::NEG_INFINITY), |(a, b), &x| {
            (a.min(x), b.max(x))
        });
    if !(threshold > f64::from(lo) && threshold <= f64::from(hi)) {
        return Err(Error::parameter(format!(
            "threshold {threshold} is outside {}'s values ({lo} to {hi})",
            file.display()
        )));
    }
    let grid = FieldGrid {
        dims: scan.dims,
        world_from_voxel: scan.world_from_voxel.as_dmat4(),
    };
    let mask = Mask::threshold(scan.dims, &scan.values, threshold);
    drop(scan);
    smooth_field(&mask_field(&mask, &grid)?, SCAN_SMOOTHING).to_volume()
}

/// A TOML value as the text [`Hypertexture::set`] reads: numbers and booleans as written,
/// arrays joined by commas (colours).
fn text_of(v: &toml::Value) -> String {
    match v {
        toml::Value::String(s) => s.clone(),
        toml::Value::Integer(i) => i.to_string(),
        toml::Value::Float(f) => f.to_string(),
        toml::Value::Boolean(b) => b.to_string(),
        toml::Value::Array(a) => a.iter().map(text_of).collect::<Vec<_>>().join(","),
        _ => "?".to_string(),
    }
}
