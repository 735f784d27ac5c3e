//! Volume loaders: NIfTI-1 (`.nii`, `.nii.gz`), NRRD (`.nrrd`, `.nhdr` + detached data; raw or
//! gzip), and headerless raw files whose grid is given by the caller.
//!
//! Every error names the file: a header and data size that disagree, an unsupported voxel
//! type, truncated gzip data, NaN or infinite values.
//!
//! Files are read by the crate's file rules ([`crate::files`]): regular files only, gzip
//! inflated to a bounded size, and a NRRD header's detached `data file` kept inside the
//! header's folder unless [`VolumeOptions::allow_outside_paths`]. A volume whose loading
//! would hold more than [`VolumeOptions::max_bytes`] (the file, its voxels as read, as `f32`,
//! and the two 16-bit copies the renderer keeps) is refused from its header, before the
//! voxels are decoded.

use std::path::{Path, PathBuf};

use glam::{Mat3, Mat4, Quat, Vec3, Vec4};

use super::grid::Volume;
use super::scalar_type::ScalarType;
use crate::{Error, Result};

/// How to read a raw file: grid, voxel type, spacing, byte order and the bytes to skip before
/// the voxels (a header texmap does not read); x fastest.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RawDesc {
    pub dims: [u32; 3],
    pub scalar: ScalarType,
    pub spacing: Vec3,
    /// Multi-byte voxels are big endian (default little).
    pub big_endian: bool,
    /// Bytes skipped at the start of the (decompressed) file.
    pub header_bytes: u64,
}

impl RawDesc {
    /// A little-endian raw file without a header.
    #[must_use]
    pub fn new(dims: [u32; 3], scalar: ScalarType, spacing: Vec3) -> Self {
        RawDesc {
            dims,
            scalar,
            spacing,
            big_endian: false,
            header_bytes: 0,
        }
    }
}

/// How volume files are read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub struct VolumeOptions {
    /// Let a NRRD header's detached `data file` leave the header's folder.
    pub allow_outside_paths: bool,
    /// The most bytes loading one volume may hold (see the module docs).
    pub max_bytes: u64,
}

impl Default for VolumeOptions {
    /// Data files inside the header's folder; [`crate::files::DEFAULT_MAX_BYTES`].
    fn default() -> Self {
        VolumeOptions {
            allow_outside_paths: false,
            max_bytes: crate::files::DEFAULT_MAX_BYTES,
        }
    }
}

impl VolumeOptions {
    #[must_use]
    pub fn allow_outside_paths(mut self, allow: bool) -> Self {
        self.allow_outside_paths = allow;
        self
    }
    #[must_use]
    pub fn max_bytes(mut self, bytes: u64) -> Self {
        self.max_bytes = bytes;
        self
    }
}

/// Loads a volume, choosing the reader by the file name: `.nii`/`.nii.gz` (NIfTI-1),
/// `.nrrd`/`.nhdr` (NRRD), anything else as raw (which needs `raw`), with the default
/// [`VolumeOptions`].
///
/// # Errors
/// [`Error::Io`] when a file cannot be read; [`Error::Decode`] (naming the file) for a bad
/// header, a size mismatch, an unsupported type, truncated gzip data or non-finite values;
/// [`Error::Limits`] for a volume above the memory budget or a file that is not a regular
/// file; [`Error::Parameter`] for a data file outside the header's folder.
pub fn load_volume(path: &Path, raw: Option<&RawDesc>) -> Result<Volume> {
    load_volume_with(path, raw, &VolumeOptions::default())
}

/// [`load_volume`] with `options`.
///
/// # Errors
/// As [`load_volume`].
pub fn load_volume_with(
    path: &Path,
    raw: Option<&RawDesc>,
    options: &VolumeOptions,
) -> Result<Volume> {
    let name = path.to_string_lossy().to_ascii_lowercase();
    if name.ends_with(".nii") || name.ends_with(".nii.gz") {
        load_nifti_with(path, options)
    } else if name.ends_with(".nrrd") || name.ends_with(".nhdr") {
        load_nrrd_with(path, options)
    } else {
        let desc = raw.ok_or_else(|| {
            Error::decode(
                path,
                "a raw volume needs its grid: --dims X,Y,Z --dtype TYPE [--spacing x,y,z]",
            )
        })?;
        load_raw_with(path, desc, options)
    }
}

/// Reads a whole file of at most `max_bytes`, gunzipping it to at most `max_inflated` when
/// it starts with the gzip magic.
fn read_maybe_gzip(path: &Path, max_bytes: u64, max_inflated: u64) -> Result<Vec<u8>> {
    let bytes = crate::files::read_bounded(path, max_bytes)?;
    if bytes.starts_with(&[0x1f, 0x8b]) {
        gunzip(path, &bytes, max_inflated)
    } else {
        Ok(bytes)
    }
}

fn gunzip(path: &Path, bytes: &[u8], max_bytes: u64) -> Result<Vec<u8>> {
    crate::files::gunzip_bounded(path, bytes, max_bytes)
}

/// Refuses a grid of `count` voxels of `ty` whose loading, beside `held` bytes already read,
/// would exceed `max_bytes`: the voxels as read, as `f32`, and two 16-bit copies.
fn check_budget(path: &Path, count: u64, ty: ScalarType, held: u64, max_bytes: u64) -> Result<()> {
    let need = count
        .saturating_mul(ty.size() as u64 + 8)
        .saturating_add(held);
    if need > max_bytes {
        return Err(Error::limits(
            path,
            format!(
                "{count} voxels of {ty:?} need about {need} bytes to load, above the limit of \
                 {max_bytes} (raise it with --max-memory)"
            ),
        ));
    }
    Ok(())
}

/// Decodes `count` voxels of `ty` from `data` into values `v·slope + inter`.
fn decode_voxels(
    path: &Path,
    data: &[u8],
    ty: ScalarType,
    big_endian: bool,
    count: usize,
    slope: f32,
    inter: f32,
) -> Result<Vec<f32>> {
    let need = count * ty.size();
    if data.len() < need {
        return Err(Error::decode(
            path,
            format!(
                "the header describes {count} voxels of {ty:?} ({need} bytes) but the data has {} bytes",
                data.len()
            ),
        ));
    }
    let data = &data[..need];
    macro_rules! conv {
        ($t:ty) => {{
            const N: usize = std::mem::size_of::<$t>();
            data.chunks_exact(N)
                .map(|c| {
                    let mut a = [0u8; N];
                    a.copy_from_slice(c);
                    let v = if big_endian {
                        <$t>::from_be_bytes(a)
                    } else {
                        <$t>::from_le_bytes(a)
                    };
                    v as f32
                })
                .collect::<Vec<f32>>()
        }};
    }
    let mut v = match ty {
        ScalarType::U8 => data.iter().map(|&b| f32::from(b)).collect(),
        ScalarType::I8 => data.iter().map(|&b| f32::from(b as i8)).collect(),
        ScalarType::U16 => conv!(u16),
        ScalarType::I16 => conv!(i16),
        ScalarType::U32 => conv!(u32),
        ScalarType::I32 => conv!(i32),
        ScalarType::F32 => conv!(f32),
        ScalarType::F64 => conv!(f64),
    };
    if let Some(i) = v.iter().position(|x| !x.is_finite()) {
        return Err(Error::decode(
            path,
            format!("voxel {i} is not a finite number ({})", v[i]),
        ));
    }
    if slope != 1.0 || inter != 0.0 {
        for x in &mut v {
            *x = *x * slope + inter;
        }
    }
    Ok(v)
}

fn make_volume(
    path: &Path,
    dims: [u32; 3],
    m: Mat4,
    values: Vec<f32>,
    ty: ScalarType,
) -> Result<Volume> {
    let mut v =
        Volume::from_scalars(dims, m, values).map_err(|e| Error::decode(path, e.to_string()))?;
    v.set_scalar_type(ty);
    let (lo, hi) = v.world_bounds();
    let reach = lo.abs().max(hi.abs()).max_element();
    if !(reach <= MAX_WORLD_REACH) {
        return Err(Error::decode(
            path,
            format!(
                "its spacing or placement puts voxels {reach:e} world units from the origin \
                 (at most {MAX_WORLD_REACH:e})"
            ),
        ));
    }
    Ok(v)
}

/// How far from the origin a loaded volume may reach, in world units: far beyond any scan
/// (a metre is 10³ in millimetres), near enough that a camera framing it stays finite.
pub const MAX_WORLD_REACH: f32 = 1.0e12;

fn check_dims(path: &Path, dims: &[i64]) -> Result<[u32; 3]> {
    let mut out = [1u32; 3];
    for (i, &d) in dims.iter().take(3).enumerate() {
        if !(1..=65_535).contains(&d) {
            return Err(Error::decode(path, format!("axis {i} has size {d}")));
        }
        out[i] = d as u32;
    }
    let count: u64 = out.iter().map(|&d| u64::from(d)).product();
    if count > 1 << 31 {
        return Err(Error::limits(
            path,
            format!("{count} voxels is more than 2^31"),
        ));
    }
    Ok(out)
}

/// Reads a NIfTI-1 single file (`.nii`, optionally gzipped): `scl_slope`/`scl_inter` applied
/// (slope 0 means none), orientation from the sform when `sform_code > 0`, else the qform
/// when `qform_code > 0`, else the spacing alone. A 4D file gives its first volume.
///
/// # Errors
/// See [`load_volume`].
pub fn load_nifti(path: &Path) -> Result<Volume> {
    load_nifti_with(path, &VolumeOptions::default())
}

/// [`load_nifti`] with `options`.
///
/// # Errors
/// See [`load_volume`].
pub fn load_nifti_with(path: &Path, options: &VolumeOptions) -> Result<Volume> {
    let file = crate::files::read_bounded(path, options.max_bytes)?;
    let bytes = if file.starts_with(&[0x1f, 0x8b]) {
        // Size the data from the header before inflating it: a small file of zeros must not
        // expand into gigabytes.
        let max = match nifti_data_bytes(&crate::files::gunzip_prefix(&file, 348)) {
            Some((count, ty, end)) => {
                check_budget(path, count, ty, file.len() as u64, options.max_bytes)?;
                options.max_bytes.min(end.saturating_add(1))
            }
            None => options.max_bytes,
        };
        gunzip(path, &file, max)?
    } else {
        file
    };
    if bytes.len() < 348 {
        return Err(Error::decode(
            path,
            format!(
                "{} bytes is too short for a NIfTI-1 header (348)",
                bytes.len()
            ),
        ));
    }
    let le = i32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]);
    let be = i32::from_be_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]);
    let big = match (le, be) {
        (348, _) => false,
        (_, 348) => true,
        _ => {
            return Err(Error::decode(
                path,
                "not a NIfTI-1 file (sizeof_hdr is not 348)",
            ))
        }
    };
    let i16_at = |o: usize| {
        let a = [bytes[o], bytes[o + 1]];
        if big {
            i16::from_be_bytes(a)
        } else {
            i16::from_le_bytes(a)
        }
    };
    let f32_at = |o: usize| {
        let a = [bytes[o], bytes[o + 1], bytes[o + 2], bytes[o + 3]];
        if big {
            f32::from_be_bytes(a)
        } else {
            f32::from_le_bytes(a)
        }
    };
    let magic = &bytes[344..348];
    if magic == b"ni1\0" {
        return Err(Error::decode(
            path,
            "a NIfTI-1 .hdr/.img pair is not supported; use a single .nii file",
        ));
    }
    if magic != b"n+1\0" {
        return Err(Error::decode(path, "bad NIfTI-1 magic (expected \"n+1\")"));
    }
    let ndim = i16_at(40);
    if !(1..=7).contains(&ndim) {
        return Err(Error::decode(
            path,
            format!("dim[0] = {ndim} is not in 1..7"),
        ));
    }
    let mut d = [1i64; 3];
    for (i, di) in d.iter_mut().enumerate().take((ndim as usize).min(3)) {
        *di = i64::from(i16_at(42 + 2 * i));
    }
    let dims = check_dims(path, &d)?;
    let datatype = i16_at(70);
    let ty = match datatype {
        2 => ScalarType::U8,
        4 => ScalarType::I16,
        8 => ScalarType::I32,
        16 => ScalarType::F32,
        64 => ScalarType::F64,
        256 => ScalarType::I8,
        512 => ScalarType::U16,
        768 => ScalarType::U32,
        other => {
            return Err(Error::decode(
                path,
                format!("NIfTI datatype {other} is not supported (u8, i8, u16, i16, u32, i32, f32, f64 are)"),
            ))
        }
    };
    let pixdim: [f32; 8] = std::array::from_fn(|i| f32_at(76 + 4 * i));
    let vox_offset = f32_at(108);
    let (mut slope, inter) = (f32_at(112), f32_at(116));
    if slope == 0.0 || !slope.is_finite() {
        slope = 1.0;
    }
    let inter = if inter.is_finite() { inter } else { 0.0 };
    let spacing = Vec3::new(pixdim[1], pixdim[2], pixdim[3]).abs().map(|s| {
        if s > 0.0 && s.is_finite() {
            s
        } else {
            1.0
        }
    });
    let (qform_code, sform_code) = (i16_at(252), i16_at(254));
    let m = if sform_code > 0 {
        let row = |o: usize| Vec4::new(f32_at(o), f32_at(o + 4), f32_at(o + 8), f32_at(o + 12));
        let (rx, ry, rz) = (row(280), row(296), row(312));
        Mat4::from_cols(
            Vec4::new(rx.x, ry.x, rz.x, 0.0),
            Vec4::new(rx.y, ry.y, rz.y, 0.0),
            Vec4::new(rx.z, ry.z, rz.z, 0.0),
            Vec4::new(rx.w, ry.w, rz.w, 1.0),
        )
    } else if qform_code > 0 {
        let (b, c, dq) = (f32_at(256), f32_at(260), f32_at(264));
        let a = (1.0 - (b * b + c * c + dq * dq)).max(0.0).sqrt();
        let r = Mat3::from_quat(Quat::from_xyzw(b, c, dq, a));
        let qfac = if pixdim[0] < 0.0 { -1.0 } else { 1.0 };
        let s = Mat3::from_diagonal(Vec3::new(spacing.x, spacing.y, spacing.z * qfac));
        let mut m = Mat4::from_mat3(r * s);
        m.w_axis = Vec4::new(f32_at(268), f32_at(272), f32_at(276), 1.0);
        m
    } else {
        Mat4::from_scale(spacing)
    };
    let off = if vox_offset.is_finite() && vox_offset >= 348.0 {
        vox_offset as usize
    } else {
        352
    };
    if off > bytes.len() {
        return Err(Error::decode(
            path,
            format!(
                "vox_offset {off} is past the end of the file ({} bytes)",
                bytes.len()
            ),
        ));
    }
    let count = dims.iter().map(|&d| d as usize).product();
    check_budget(
        path,
        count as u64,
        ty,
        bytes.len() as u64,
        options.max_bytes,
    )?;
    let values = decode_voxels(path, &bytes[off..], ty, big, count, slope, inter)?;
    make_volume(path, dims, m, values, ty)
}

/// From a NIfTI-1 header alone: the voxel count, type, and where the first volume's data
/// ends; `None` when the header is not one (the full parse says why).
fn nifti_data_bytes(h: &[u8]) -> Option<(u64, ScalarType, u64)> {
    if h.len() < 348 {
        return None;
    }
    let big = match i32::from_le_bytes([h[0], h[1], h[2], h[3]]) {
        348 => false,
        _ if i32::from_be_bytes([h[0], h[1], h[2], h[3]]) == 348 => true,
        _ => return None,
    };
    let i16_at = |o: usize| {
        let a = [h[o], h[o + 1]];
        if big {
            i16::from_be_bytes(a)
        } else {
            i16::from_le_bytes(a)
        }
    };
    let ty = match i16_at(70) {
        2 => ScalarType::U8,
        4 => ScalarType::I16,
        8 => ScalarType::I32,
        16 => ScalarType::F32,
        64 => ScalarType::F64,
        256 => ScalarType::I8,
        512 => ScalarType::U16,
        768 => ScalarType::U32,
        _ => return None,
    };
    let ndim = usize::try_from(i16_at(40)).ok()?.clamp(1, 3);
    let count: u64 = (0..ndim)
        .map(|i| u64::try_from(i16_at(42 + 2 * i)).unwrap_or(0).max(1))
        .product();
    let off = {
        let a = [h[108], h[109], h[110], h[111]];
        let v = if big {
            f32::from_be_bytes(a)
        } else {
            f32::from_le_bytes(a)
        };
        if v.is_finite() && v >= 348.0 {
            v as u64
        } else {
            352
        }
    };
    // Saturating: `vox_offset` may be as large as f32 goes.
    Some((
        count,
        ty,
        off.saturating_add(count.saturating_mul(ty.size() as u64)),
    ))
}

/// Reads a NRRD file with an attached (`.nrrd`) or detached (`.nhdr` + `data file:`) header;
/// encodings `raw` and `gzip`; orientation from `space directions` and `space origin`, else
/// `spacings`.
///
/// # Errors
/// See [`load_volume`].
pub fn load_nrrd(path: &Path) -> Result<Volume> {
    load_nrrd_with(path, &VolumeOptions::default())
}

/// [`load_nrrd`] with `options`.
///
/// # Errors
/// See [`load_volume`].
pub fn load_nrrd_with(path: &Path, options: &VolumeOptions) -> Result<Volume> {
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
    make_volume(path, dims, m, values, ty)
}

/// Reads a raw file (optionally gzipped): `header_bytes` skipped, then exactly
/// `dims`·size bytes of voxels, x fastest, in the given byte order.
///
/// # Errors
/// See [`load_volume`].
pub fn load_raw(path: &Path, desc: &RawDesc) -> Result<Volume> {
    load_raw_with(path, desc, &VolumeOptions::default())
}

/// [`load_raw`] with `options`.
///
/// # Errors
/// See [`load_volume`].
pub fn load_raw_with(path: &Path, desc: &RawDesc, options: &VolumeOptions) -> Result<Volume> {
    let dims = check_dims(path, &desc.dims.map(i64::from))?;
    let count: usize = dims.iter().map(|&d| d as usize).product();
    check_budget(path, count as u64, desc.scalar, 0, options.max_bytes)?;
    let expected = (count * desc.scalar.size()) as u64 + desc.header_bytes;
    // Inflated data beyond the grid is an error below; a byte past it is enough to tell.
    let inflated = options.max_bytes.min(expected.saturating_add(1));
    let bytes = read_maybe_gzip(path, options.max_bytes, inflated)?;
    let skip = usize::try_from(desc.header_bytes)
        .ok()
        .filter(|&h| h <= bytes.len())
        .ok_or_else(|| {
            Error::decode(
                path,
                format!(
                    "a header of {} bytes is longer than the file ({} bytes)",
                    desc.header_bytes,
                    bytes.len()
                ),
            )
        })?;
    let data = &bytes[skip..];
    if data.len() != count * desc.scalar.size() {
        let after = if skip > 0 {
            format!(" after its {skip}-byte header")
        } else {
            String::new()
        };
        return Err(Error::decode(
            path,
            format!(
                "--dims {}x{}x{} of {:?} need {} bytes but the file has {}{after}",
                dims[0],
                dims[1],
                dims[2],
                desc.scalar,
                count * desc.scalar.size(),
                data.len()
            ),
        ));
    }
    let s = desc.spacing;
    if !(s.is_finite() && s.min_element() > 0.0) {
        return Err(Error::parameter(format!("--spacing {s} must be positive")));
    }
    let values = decode_voxels(path, data, desc.scalar, desc.big_endian, count, 1.0, 0.0)?;
    make_volume(path, dims, Mat4::from_scale(s), values, desc.scalar)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn raw_header_is_skipped_and_big_endian_is_read() {
        let dir = std::env::temp_dir().join(format!("texmap-raw-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("be.raw");
        // A 5-byte header, then 2×1×1 big-endian u16: 258 and 1000.
        std::fs::write(&p, [9, 9, 9, 9, 9, 0x01, 0x02, 0x03, 0xe8]).unwrap();
        let desc = RawDesc {
            big_endian: true,
            header_bytes: 5,
            ..RawDesc::new([2, 1, 1], ScalarType::U16, Vec3::ONE)
        };
        let v = load_raw(&p, &desc).unwrap();
        assert_eq!(v.range(), (258.0, 1000.0));
        assert_eq!(v.scalar_type(), Some(ScalarType::U16));
        // Little endian reads other numbers; a wrong header length is a size error.
        let le = load_raw(
            &p,
            &RawDesc {
                big_endian: false,
                ..desc
            },
        )
        .unwrap();
        assert_eq!(le.voxel(0, 0, 0), 513.0);
        let e = load_raw(
            &p,
            &RawDesc {
                header_bytes: 4,
                ..desc
            },
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("be.raw") && e.contains("4-byte header"), "{e}");
        let e = load_raw(
            &p,
            &RawDesc {
                header_bytes: 99,
                ..desc
            },
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("longer than the file"), "{e}");
    }
}
