//! NIfTI-1 (`.nii`, `.nii.gz`): the 348-byte header, its orientation, the voxels.

use std::path::Path;

use glam::{Mat3, Mat4, Quat, Vec3, Vec4};

use super::super::grid::Volume;
use super::super::patient::AnatomicalSpace;
use super::super::scalar_type::ScalarType;
use super::{
    check_budget, check_dims, checked_grid, decode_voxels, gunzip, make_volume, ScalarGrid,
    VolumeOptions,
};
use crate::{Error, Result};

/// Reads a NIfTI-1 single file (`.nii`, optionally gzipped): `scl_slope`/`scl_inter` applied
/// (slope 0 means none), orientation from the sform when `sform_code > 0`, else the qform
/// when `qform_code > 0`, else the spacing alone. A 4D file gives its first volume.
///
/// # Errors
/// See [`load_volume`](super::load_volume).
pub fn load_nifti(path: &Path) -> Result<Volume> {
    load_nifti_with(path, &VolumeOptions::default())
}

/// [`load_nifti`] with `options`.
///
/// # Errors
/// See [`load_volume`](super::load_volume).
pub fn load_nifti_with(path: &Path, options: &VolumeOptions) -> Result<Volume> {
    make_volume(path, read_nifti(path, options)?)
}

/// The file's grid with its values as read (see [`ScalarGrid`](super::ScalarGrid)).
pub(super) fn read_nifti(path: &Path, options: &VolumeOptions) -> Result<ScalarGrid> {
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
    let ty = nifti_type(datatype).ok_or_else(|| {
        Error::decode(
            path,
            format!(
                "NIfTI datatype {datatype} is not supported (u8, i8, u16, i16, u32, i32, f32, \
                 f64 are)"
            ),
        )
    })?;
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
    // NIfTI's world is RAS+ by definition (the spacing-only placement too).
    checked_grid(path, dims, m, values, ty, Some(AnatomicalSpace::Ras))
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
    let ty = nifti_type(i16_at(70))?;
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

/// The voxel type of a NIfTI `datatype` code, if texmap reads it.
fn nifti_type(code: i16) -> Option<ScalarType> {
    Some(match code {
        2 => ScalarType::U8,
        4 => ScalarType::I16,
        8 => ScalarType::I32,
        16 => ScalarType::F32,
        64 => ScalarType::F64,
        256 => ScalarType::I8,
        512 => ScalarType::U16,
        768 => ScalarType::U32,
        _ => return None,
    })
}
