//! NRRD (`.nrrd`, or `.nhdr` with a detached data file): the text header, raw or gzip data.

use std::path::{Path, PathBuf};

use glam::{Mat4, Vec3, Vec4};

use super::super::grid::Volume;
use super::super::patient::AnatomicalSpace;
use super::super::scalar_type::ScalarType;
use super::{
    check_budget, check_dims, checked_grid, decode_voxels, gunzip, make_volume, ScalarGrid,
    VolumeOptions,
};
use crate::{Error, Result};

/// Reads a NRRD file with an attached (`.nrrd`) or detached (`.nhdr` + `data file:`) header;
/// encodings `raw` and `gzip`; orientation from `space directions` and `space origin`, else
/// `spacings`.
///
/// # Errors
/// See [`load_volume`](super::load_volume).
pub fn load_nrrd(path: &Path) -> Result<Volume> {
    load_nrrd_with(path, &VolumeOptions::default())
}

/// [`load_nrrd`] with `options`.
///
/// # Errors
/// See [`load_volume`](super::load_volume).
pub fn load_nrrd_with(path: &Path, options: &VolumeOptions) -> Result<Volume> {
    make_volume(path, read_nrrd(path, options)?)
}

/// The file's grid with its values as read (see [`ScalarGrid`](super::ScalarGrid)).
pub(super) fn read_nrrd(path: &Path, options: &VolumeOptions) -> Result<ScalarGrid> {
    let bytes = crate::files::read_bounded(path, options.max_bytes)?;
    if !bytes.starts_with(b"NRRD000") {
        return Err(Error::decode(path, "not a NRRD file (no NRRD000x magic)"));
    }
    // Header: lines up to the first empty line.
    let mut pos = 0;
    let mut fields: Vec<(String, String)> = Vec::new();
    let mut first = true;
    loop {
        let Some(nl) = bytes[pos..].iter().position(|&b| b == b'\n') else {
            pos = bytes.len();
            break;
        };
        let line = String::from_utf8_lossy(&bytes[pos..pos + nl])
            .trim_end_matches('\r')
            .to_string();
        pos += nl + 1;
        if first {
            first = false;
            continue;
        }
        if line.is_empty() {
            break;
        }
        if line.starts_with('#') {
            continue;
        }
        if let Some((k, v)) = line.split_once(":=") {
            fields.push((k.trim().to_ascii_lowercase(), v.trim().to_string()));
        } else if let Some((k, v)) = line.split_once(':') {
            fields.push((k.trim().to_ascii_lowercase(), v.trim().to_string()));
        }
    }
    let get = |k: &str| fields.iter().find(|(n, _)| n == k).map(|(_, v)| v.as_str());
    let need = |k: &str| {
        get(k).ok_or_else(|| Error::decode(path, format!("NRRD header has no \"{k}\" field")))
    };
    let ty = match need("type")? {
        "uchar" | "unsigned char" | "uint8" | "uint8_t" => ScalarType::U8,
        "signed char" | "int8" | "int8_t" => ScalarType::I8,
        "short" | "short int" | "signed short" | "signed short int" | "int16" | "int16_t" => {
            ScalarType::I16
        }
        "ushort" | "unsigned short" | "unsigned short int" | "uint16" | "uint16_t" => {
            ScalarType::U16
        }
        "int" | "signed int" | "int32" | "int32_t" => ScalarType::I32,
        "uint" | "unsigned int" | "uint32" | "uint32_t" => ScalarType::U32,
        "float" => ScalarType::F32,
        "double" => ScalarType::F64,
        other => {
            return Err(Error::decode(
                path,
                format!("NRRD type \"{other}\" is not supported"),
            ))
        }
    };
    let dimension: usize = need("dimension")?
        .parse()
        .map_err(|_| Error::decode(path, "NRRD dimension is not a number"))?;
    if dimension != 3 {
        return Err(Error::decode(
            path,
            format!("NRRD dimension {dimension} is not supported (3 is)"),
        ));
    }
    let sizes: Vec<i64> = need("sizes")?
        .split_whitespace()
        .map(|s| {
            s.parse::<i64>()
                .map_err(|_| Error::decode(path, format!("bad NRRD size \"{s}\"")))
        })
        .collect::<Result<_>>()?;
    if sizes.len() != 3 {
        return Err(Error::decode(path, "NRRD sizes must have 3 entries"));
    }
    let dims = check_dims(path, &sizes)?;
    let big = match get("endian") {
        Some("big") => true,
        Some("little") | None => false,
        Some(other) => return Err(Error::decode(path, format!("bad NRRD endian \"{other}\""))),
    };
    let gz = match get("encoding").unwrap_or("raw") {
        "raw" => false,
        "gzip" | "gz" => true,
        other => {
            return Err(Error::decode(
                path,
                format!("NRRD encoding \"{other}\" is not supported (raw and gzip are)"),
            ))
        }
    };
    let parse_vec = |s: &str| -> Option<Vec3> {
        let s = s.trim().strip_prefix('(')?.strip_suffix(')')?;
        let v: Vec<f32> = s
            .split(',')
            .map(|x| x.trim().parse().ok())
            .collect::<Option<_>>()?;
        (v.len() == 3).then(|| Vec3::new(v[0], v[1], v[2]))
    };
    let mut m = Mat4::IDENTITY;
    if let Some(sd) = get("space directions") {
        let cols: Vec<Vec3> = sd
            .split_whitespace()
            .map(|t| {
                parse_vec(t)
                    .ok_or_else(|| Error::decode(path, format!("bad NRRD space direction \"{t}\"")))
            })
            .collect::<Result<_>>()?;
        if cols.len() != 3 {
            return Err(Error::decode(
                path,
                "NRRD space directions must have 3 vectors",
            ));
        }
        m = Mat4::from_cols(
            cols[0].extend(0.0),
            cols[1].extend(0.0),
            cols[2].extend(0.0),
            Vec4::W,
        );
    } else if let Some(sp) = get("spacings") {
        let s: Vec<f32> = sp
            .split_whitespace()
            .map(|x| x.parse().unwrap_or(1.0))
            .collect();
        if s.len() == 3 {
            m = Mat4::from_scale(Vec3::new(s[0], s[1], s[2]).map(|v| {
                if v.is_finite() && v > 0.0 {
                    v
                } else {
                    1.0
                }
            }));
        }
    }
    if let Some(o) = get("space origin") {
        let o = parse_vec(o)
            .ok_or_else(|| Error::decode(path, format!("bad NRRD space origin \"{o}\"")))?;
        m.w_axis = o.extend(1.0);
    }
    // Data: attached after the blank line, or in the detached file.
    let (data_path, mut data): (PathBuf, Vec<u8>) =
        match get("data file").or_else(|| get("datafile")) {
            Some(f) => {
                if f.starts_with("LIST") || f.contains('%') {
                    return Err(Error::decode(path, "NRRD multi-file data is not supported"));
                }
                let p = crate::files::resolve_within(path, f, options.allow_outside_paths)?;
                let d = crate::files::read_bounded(&p, options.max_bytes)?;
                (p, d)
            }
            None => (path.to_path_buf(), bytes[pos..].to_vec()),
        };
    if let Some(skip) = get("line skip") {
        let n: usize = skip
            .parse()
            .map_err(|_| Error::decode(path, "bad NRRD line skip"))?;
        let mut p = 0;
        for _ in 0..n {
            p += data[p..]
                .iter()
                .position(|&b| b == b'\n')
                .map_or(data.len() - p, |i| i + 1);
        }
        data.drain(..p);
    }
    let count: usize = dims.iter().map(|&d| d as usize).product();
    let byte_skip: i64 = get("byte skip").map_or(Ok(0), |s| {
        s.parse()
            .map_err(|_| Error::decode(path, "bad NRRD byte skip"))
    })?;
    check_budget(path, count as u64, ty, data.len() as u64, options.max_bytes)?;
    if gz {
        // The voxels, and a little more (NRRD allows trailing bytes with `byte skip: -1`).
        let expected = (count * ty.size()) as u64;
        let max = options
            .max_bytes
            .min(expected.saturating_mul(2).saturating_add(1 << 20));
        data = gunzip(&data_path, &data, max)?;
    }
    let data = if byte_skip == -1 {
        let need = count * ty.size();
        if data.len() < need {
            &data[..]
        } else {
            &data[data.len() - need..]
        }
    } else {
        let s = byte_skip.max(0) as usize;
        data.get(s..).unwrap_or(&[])
    };
    if !gz && data.len() != count * ty.size() && byte_skip != -1 {
        return Err(Error::decode(
            &data_path,
            format!(
                "the header describes {count} voxels of {ty:?} ({} bytes) but the data has {} bytes",
                count * ty.size(),
                data.len()
            ),
        ));
    }
    let values = decode_voxels(&data_path, data, ty, big, count, 1.0, 0.0)?;
    let space = get("space").and_then(AnatomicalSpace::from_nrrd);
    checked_grid(path, dims, m, values, ty, space)
}
