//! `[[volumes]]` → [`SceneVolume`]: a scan (NIfTI, NRRD, or raw with its grid described by
//! `dims` and the keys after it), its placement in the scene, its transfer function and how
//! to render it — the options of `texmap render scan.nii.gz`, with the same names and
//! defaults. The raw keys are errors for files with their own header (it would be unclear
//! which description wins). Documented in `docs/scenes.md`.

use std::path::Path;

use glam::{Mat4, Vec3};

use super::spec::VolumeSpec;
use crate::shading::Light;
use crate::volume::scene_volume::{parse_classification, parse_mode};
use crate::volume::{
    load_volume_with, Method, RawDesc, ScalarType, SceneVolume, TransferFunction2D, VolumeOptions,
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
    options: &VolumeOptions,
) -> Result<SceneVolume> {
    let file = dir.join(&v.file);
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
    if let Some(tf) = &v.tf {
        sv.set_transfer(tf, dir)?;
    }
    if let Some(m) = &v.method {
        sv.method = Method::parse(m)
            .ok_or_else(|| Error::parameter(format!("method {m:?} is not raymarch or slices")))?;
    }
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
