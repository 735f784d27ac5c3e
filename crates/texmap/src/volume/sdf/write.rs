//! Fields as files: NIfTI-1 (`.nii`, `.nii.gz`) and NRRD (`.nrrd`, raw or gzip), `f32`,
//! little endian, placed so that [`crate::volume::load`] reads them back with the same grid,
//! spacing and placement (and any other tool with the same world coordinates).
//!
//! NIfTI: the affine is voxel → world with voxel centres at integer indices, the convention
//! of `sdf_ref.py` (nibabel) and of the loader; it goes in the sform (code 2, aligned) and,
//! when the axes are not rotated, in the qform too (identity quaternion, `pixdim` spacing,
//! `qoffset` the first voxel's centre). NRRD: `space directions` are the affine's columns and
//! `space origin` the first voxel's centre.

use std::io::Write as _;
use std::path::Path;

use super::Field;
use crate::{Error, Result};

/// A field file's format, chosen by its name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FieldFormat {
    /// NIfTI-1 single file; gzipped for `.nii.gz`.
    Nifti { gzip: bool },
    /// NRRD with attached data; gzip encoding for `.nrrd` (`raw` for `.nrrd` is not chosen by
    /// name: fields compress well).
    Nrrd { gzip: bool },
}

impl FieldFormat {
    /// The format `path`'s name asks for: `.nii`, `.nii.gz` or `.nrrd`.
    ///
    /// # Errors
    /// [`Error::Parameter`] naming the file for any other name.
    pub fn for_path(path: &Path) -> Result<FieldFormat> {
        let name = path.to_string_lossy().to_ascii_lowercase();
        if name.ends_with(".nii.gz") {
            Ok(FieldFormat::Nifti { gzip: true })
        } else if name.ends_with(".nii") {
            Ok(FieldFormat::Nifti { gzip: false })
        } else if name.ends_with(".nrrd") {
            Ok(FieldFormat::Nrrd { gzip: true })
        } else {
            Err(Error::parameter(format!(
                "{}: a distance field is written as .nii, .nii.gz or .nrrd",
                path.display()
            )))
        }
    }

    /// The file's bytes.
    ///
    /// # Errors
    /// [`Error::Parameter`] when a side of the grid does not fit NIfTI-1's 16-bit sizes.
    pub fn encode(self, field: &Field) -> Result<Vec<u8>> {
        match self {
            FieldFormat::Nifti { gzip } => write_nifti(field, gzip),
            FieldFormat::Nrrd { gzip } => Ok(write_nrrd(field, gzip)),
        }
    }
}

fn gzip_bytes(data: &[u8]) -> Vec<u8> {
    let mut e = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::new(6));
    // Writing into a Vec cannot fail.
    e.write_all(data).expect("in-memory gzip");
    e.finish().expect("in-memory gzip")
}

fn voxel_bytes(field: &Field) -> Vec<u8> {
    field.values.iter().flat_map(|v| v.to_le_bytes()).collect()
}

/// A NIfTI-1 file of `field` (see the module docs), gzipped when `gzip`.
///
/// # Errors
/// [`Error::Parameter`] when a side is above 32,767 voxels (NIfTI-1 sizes are `i16`).
pub fn write_nifti(field: &Field, gzip: bool) -> Result<Vec<u8>> {
    let g = &field.grid;
    if g.dims.iter().any(|&d| d > 32_767) {
        return Err(Error::parameter(format!(
            "a grid of {:?} does not fit NIfTI-1 (at most 32,767 per side)",
            g.dims
        )));
    }
    let mut h = vec![0u8; 352];
    let put_i16 = |h: &mut [u8], o: usize, v: i16| h[o..o + 2].copy_from_slice(&v.to_le_bytes());
    let put_i32 = |h: &mut [u8], o: usize, v: i32| h[o..o + 4].copy_from_slice(&v.to_le_bytes());
    let put_f32 = |h: &mut [u8], o: usize, v: f32| h[o..o + 4].copy_from_slice(&v.to_le_bytes());
    put_i32(&mut h, 0, 348);
    h[38] = b'r'; // regular
    put_i16(&mut h, 40, 3);
    for (i, &d) in g.dims.iter().enumerate() {
        put_i16(&mut h, 42 + 2 * i, d as i16);
    }
    for i in 3..7 {
        put_i16(&mut h, 42 + 2 * i, 1);
    }
    put_i16(&mut h, 70, 16); // float32
    put_i16(&mut h, 72, 32);
    let m = g.world_from_voxel;
    let sp = g.spacing();
    put_f32(&mut h, 76, 1.0); // qfac
    for i in 0..3 {
        put_f32(&mut h, 80 + 4 * i, sp[i] as f32);
    }
    for i in 4..8 {
        put_f32(&mut h, 76 + 4 * i, 1.0);
    }
    put_f32(&mut h, 108, 352.0); // vox_offset
    put_f32(&mut h, 112, 1.0); // scl_slope
    put_f32(&mut h, 116, 0.0); // scl_inter
    let (lo, hi) = field.range();
    put_f32(&mut h, 124, hi); // cal_max
    put_f32(&mut h, 128, lo); // cal_min
    let descrip = b"texmap signed distance field";
    h[148..148 + descrip.len()].copy_from_slice(descrip);
    // qform: only for unrotated axes (a diagonal with positive scales).
    let axis_aligned = (0..3).all(|c| {
        let col = m.col(c);
        (0..3).all(|r| if r == c { col[r] > 0.0 } else { col[r] == 0.0 })
    });
    if axis_aligned {
        put_i16(&mut h, 252, 2);
        // quatern_b, c, d = 0: the identity rotation.
        for (i, o) in [268, 272, 276].into_iter().enumerate() {
            put_f32(&mut h, o, m.w_axis[i] as f32);
        }
    }
    put_i16(&mut h, 254, 2);
    for r in 0..3 {
        for c in 0..4 {
            put_f32(&mut h, 280 + 16 * r + 4 * c, m.col(c)[r] as f32);
        }
    }
    h[344..348].copy_from_slice(b"n+1\0");
    h.extend_from_slice(&voxel_bytes(field));
    Ok(if gzip { gzip_bytes(&h) } else { h })
}

/// A NRRD file of `field` with attached data (see the module docs), gzip-encoded when
/// `gzip`.
#[must_use]
pub fn write_nrrd(field: &Field, gzip: bool) -> Vec<u8> {
    let g = &field.grid;
    let m = g.world_from_voxel;
    let v = |c: usize| {
        let col = m.col(c);
        format!("({},{},{})", col[0], col[1], col[2])
    };
    let header = format!(
        "NRRD0004\n# texmap signed distance field\ntype: float\ndimension: 3\n\
         space dimension: 3\nsizes: {} {} {}\nspace directions: {} {} {}\n\
         space origin: {}\nkinds: domain domain domain\nendian: little\nencoding: {}\n\n",
        g.dims[0],
        g.dims[1],
        g.dims[2],
        v(0),
        v(1),
        v(2),
        v(3),
        if gzip { "gzip" } else { "raw" }
    );
    let mut out = header.into_bytes();
    let data = voxel_bytes(field);
    if gzip {
        out.extend_from_slice(&gzip_bytes(&data));
    } else {
        out.extend_from_slice(&data);
    }
    out
}
