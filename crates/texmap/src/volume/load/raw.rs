//! Headerless raw volumes, described by a [`RawDesc`](super::RawDesc).

use std::path::Path;

use glam::Mat4;

use super::super::grid::Volume;
use super::{
    check_budget, check_dims, checked_grid, decode_voxels, make_volume, read_maybe_gzip, RawDesc,
    ScalarGrid, VolumeOptions,
};
use crate::{Error, Result};

/// Reads a raw file (optionally gzipped): `header_bytes` skipped, then exactly
/// `dims`·size bytes of voxels, x fastest, in the given byte order.
///
/// # Errors
/// See [`load_volume`](super::load_volume).
pub fn load_raw(path: &Path, desc: &RawDesc) -> Result<Volume> {
    load_raw_with(path, desc, &VolumeOptions::default())
}

/// [`load_raw`] with `options`.
///
/// # Errors
/// See [`load_volume`](super::load_volume).
pub fn load_raw_with(path: &Path, desc: &RawDesc, options: &VolumeOptions) -> Result<Volume> {
    make_volume(path, read_raw(path, desc, options)?)
}

/// The file's grid with its values as read (see [`ScalarGrid`](super::ScalarGrid)).
pub(super) fn read_raw(path: &Path, desc: &RawDesc, options: &VolumeOptions) -> Result<ScalarGrid> {
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
    checked_grid(path, dims, Mat4::from_scale(s), values, desc.scalar, None)
}
