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
//!
//! Files: `mod.rs` (the options, the dispatch by extension, what every format shares:
//! gzip, the budget, voxel decoding, placement checks), `nifti.rs`, `nrrd.rs`, `raw.rs`.

use std::path::Path;

use glam::{Mat4, Vec3};

use super::grid::Volume;
use super::patient::{AnatomicalSpace, PatientAxes};
use super::scalar_type::ScalarType;
use crate::{Error, Result};

mod nifti;
mod nrrd;
mod raw;

pub use nifti::{load_nifti, load_nifti_with};
pub use nrrd::{load_nrrd, load_nrrd_with};
pub use raw::{load_raw, load_raw_with};

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
    make_volume(path, load_scalars_with(path, raw, options)?)
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

/// A grid as a file holds it: its size, placement and values (after the file's scale and
/// offset), exactly as read, before the 16-bit levels a [`Volume`] keeps. What needs the
/// values themselves (a threshold, a distance transform) reads this.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct ScalarGrid {
    /// Voxels per axis.
    pub dims: [u32; 3],
    /// Voxel `(i, j, k)`'s centre is `world_from_voxel · (i, j, k, 1)`.
    pub world_from_voxel: Mat4,
    /// `dims[0]·dims[1]·dims[2]` finite values, x fastest.
    pub values: Vec<f32>,
    /// The file's voxel type.
    pub scalar_type: ScalarType,
    /// The anatomical frame the file states its world in (NIfTI's is RAS+), if any.
    pub space: Option<AnatomicalSpace>,
}

impl ScalarGrid {
    /// The voxel spacing: the lengths of the transform's first three columns.
    #[must_use]
    pub fn spacing(&self) -> Vec3 {
        let m = &self.world_from_voxel;
        Vec3::new(
            m.x_axis.truncate().length(),
            m.y_axis.truncate().length(),
            m.z_axis.truncate().length(),
        )
    }
}

/// Loads a volume file's values as read, choosing the reader as [`load_volume_with`] does.
///
/// # Errors
/// As [`load_volume`].
pub fn load_scalars_with(
    path: &Path,
    raw: Option<&RawDesc>,
    options: &VolumeOptions,
) -> Result<ScalarGrid> {
    let name = path.to_string_lossy().to_ascii_lowercase();
    if name.ends_with(".nii") || name.ends_with(".nii.gz") {
        nifti::read_nifti(path, options)
    } else if name.ends_with(".nrrd") || name.ends_with(".nhdr") {
        nrrd::read_nrrd(path, options)
    } else {
        let desc = raw.ok_or_else(|| {
            Error::decode(
                path,
                "a raw volume needs its grid: --dims X,Y,Z --dtype TYPE [--spacing x,y,z]",
            )
        })?;
        raw::read_raw(path, desc, options)
    }
}

/// A grid whose placement keeps every voxel within [`MAX_WORLD_REACH`] of the origin.
fn checked_grid(
    path: &Path,
    dims: [u32; 3],
    m: Mat4,
    values: Vec<f32>,
    ty: ScalarType,
    space: Option<AnatomicalSpace>,
) -> Result<ScalarGrid> {
    let n = dims.map(|d| d.saturating_sub(1) as f32);
    let mut reach = 0.0f32;
    for c in 0..8 {
        let v = Vec3::new(
            if c & 1 == 0 { 0.0 } else { n[0] },
            if c & 2 == 0 { 0.0 } else { n[1] },
            if c & 4 == 0 { 0.0 } else { n[2] },
        );
        reach = reach.max(m.transform_point3(v).abs().max_element());
    }
    if !(reach <= MAX_WORLD_REACH) {
        return Err(Error::decode(
            path,
            format!(
                "its spacing or placement puts voxels {reach:e} world units from the origin \
                 (at most {MAX_WORLD_REACH:e})"
            ),
        ));
    }
    Ok(ScalarGrid {
        dims,
        world_from_voxel: m,
        values,
        scalar_type: ty,
        space,
    })
}

fn make_volume(path: &Path, grid: ScalarGrid) -> Result<Volume> {
    let mut v = Volume::from_scalars(grid.dims, grid.world_from_voxel, grid.values)
        .map_err(|e| Error::decode(path, e.to_string()))?;
    v.set_scalar_type(grid.scalar_type);
    if let Some(space) = grid.space {
        v.set_patient_axes(PatientAxes::new(space, grid.world_from_voxel));
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
