//! What every ray of a frame reads, prepared once per frame ([`Marcher`]), and the per-sample
//! reads the ray loops share: the level at a point, its classification, the gradient and the
//! shaded colour.
//!
//! Rules:
//! - Values are read as fractional 16-bit levels from the plain copy ([`super::cell`]), or
//!   through the texture engine when `engine_sampling` asks (slow; for checks).
//! - Classification is the nearest entry of the frame's table (opacity corrected for the
//!   step), indexed straight from the level; the table is also kept premultiplied, so the
//!   unshaded loop composites an entry with one 4-wide multiply-add.
//! - Everything a frame's options decide (tables, empty bricks, the iso-value, whether the
//!   normals are needed) is decided here once, not per ray or per sample.
//! - The headlight's direction is the camera's view direction for every ray (as VTK's shading
//!   tables, which use the centre view direction); scene lights take it as the view direction.

use glam::{Mat3, Mat4, Vec3, Vec4};

use super::bricks::EmptyBricks;
use super::cell::trilinear;
use super::grid::Volume;
use super::normals::central_difference;
use super::params::{Classification, MarchParams, Mode};
use super::shade::VolumeLights;
use super::transfer::{PreIntegrated, TransferFunction, TransferLut};
use crate::{Error, Result};

/// Everything a ray of one frame needs, prepared once per frame.
pub(crate) struct Marcher<'a> {
    pub vol: &'a Volume,
    /// The 16-bit levels, x fastest.
    pub data: &'a [u16],
    pub dims: [u32; 3],
    /// The box drawn (voxel space): `0` and `n − 1` per axis, or the crop box.
    pub lo: Vec3,
    pub hi: Vec3,
    pub voxel_from_world: Mat4,
    pub world_from_voxel: Mat4,
    /// Level differences → world gradient: the transposed linear part of `voxel_from_world`
    /// times the value of one level.
    grad_to_world: Mat3,
    /// 16-bit level → table index.
    q_to_index: f32,
    lut: TransferLut,
    /// The table premultiplied: `[r·a, g·a, b·a, a]`.
    lut_pm: Vec<Vec4>,
    pub pre_int: Option<PreIntegrated>,
    pub empty: EmptyBricks,
    pub p: &'a MarchParams,
    /// The iso-value as a fractional level, and the colour of the iso-surface.
    pub iso_q: f32,
    pub iso_color: Vec3,
    /// Per-voxel unit normals (world space, ×127) when shading without gradient opacity.
    pub normals: Option<&'a [[i8; 4]]>,
    /// The headlight's direction for every ray; `None` uses each ray's own.
    pub headlight: Option<Vec3>,
    lights: VolumeLights,
}

/// What one ray gives: its display-space premultiplied colour and the samples it took.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Traced {
    pub color: Vec4,
    pub samples: u64,
}

impl Traced {
    /// A ray that met nothing.
    pub const NOTHING: Traced = Traced {
        color: Vec4::ZERO,
        samples: 0,
    };
}

impl<'a> Marcher<'a> {
    /// The frame's tables for `vol` under `tf` and `p`, the headlight along `headlight`.
    ///
    /// # Errors
    /// [`Error::Parameter`] when the iso-value is not finite or the crop box is not one.
    pub fn new(
        vol: &'a Volume,
        tf: &TransferFunction,
        p: &'a MarchParams,
        headlight: Option<Vec3>,
    ) -> Result<Self> {
        p.check_crop(vol.dims()).map_err(Error::Parameter)?;
        let range = vol.range();
        let lut = TransferLut::new(tf, range, p.step);
        let pre_int = (p.classification == Classification::PreIntegrated
            && p.mode == Mode::Composite)
            .then(|| PreIntegrated::new(tf, range, p.step, 256));
        let iso = p
            .iso
            .or_else(|| tf.first_opaque_value())
            .unwrap_or(0.5 * (range.0 + range.1));
        if !iso.is_finite() {
            return Err(Error::parameter("--iso must be finite"));
        }
        let c = tf.eval(iso).truncate();
        let iso_color = if c.max_element() > 0.05 { c } else { Vec3::ONE };
        let voxel_from_world = vol.world_from_voxel().inverse();
        let value_step = vol.value_step();
        let iso_q = if value_step > 0.0 {
            (iso - range.0) / value_step
        } else {
            0.0
        };
        let (bricks, dims) = (vol.bricks(), vol.dims());
        let crop = p.voxel_box(dims);
        let empty = if !p.empty_space_skipping {
            EmptyBricks::none(bricks, dims)
        } else {
            match p.mode {
                Mode::Composite => EmptyBricks::new(bricks, dims, |lo, hi| {
                    // Pre-integrated segments may span a brick edge; the table of the
                    // brick's own values is still the right test for samples inside it.
                    lut.is_transparent(vol.value_of(lo), vol.value_of(hi))
                }),
                Mode::Iso => EmptyBricks::new(bricks, dims, |_, hi| hi < iso_q),
                Mode::Mip | Mode::Xray => EmptyBricks::none(bricks, dims),
            }
        };
        Ok(Marcher {
            vol,
            data: vol.quantized(),
            dims,
            lo: crop.0,
            hi: crop.1,
            voxel_from_world,
            world_from_voxel: vol.world_from_voxel(),
            grad_to_world: Mat3::from_mat4(voxel_from_world).transpose() * value_step,
            q_to_index: value_step * lut.scale,
            lut_pm: lut
                .table
                .iter()
                .map(|c| (c.truncate() * c.w).extend(c.w))
                .collect(),
            lut,
            pre_int,
            empty,
            p,
            iso_q,
            iso_color,
            normals: (p.shade
                && p.gradient_opacity.is_empty()
                && p.mode == Mode::Composite
                && !p.engine_sampling)
                .then(|| vol.normals().as_slice()),
            headlight,
            lights: VolumeLights::new(p.reflectance, &p.lights),
        })
    }

    /// The 16-bit level (fractional) at voxel-space `q`.
    #[inline(always)]
    pub fn value(&self, q: Vec3) -> f32 {
        if self.p.engine_sampling {
            self.vol.level_at_engine(q)
        } else {
            trilinear(self.data, self.dims, q)
        }
    }

    /// `[r, g, b, a_step]` of a level.
    #[inline(always)]
    pub fn classify(&self, q: f32) -> Vec4 {
        // `as u32`, not `as usize`: a float → u64 conversion is a long instruction sequence.
        let i = ((q * self.q_to_index + 0.5) as u32 as usize).min(self.lut.table.len() - 1);
        self.lut.table[i]
    }

    /// `[r·a, g·a, b·a, a]` of a level (the same entry as [`Self::classify`]).
    #[inline(always)]
    pub fn classify_premultiplied(&self, q: f32) -> Vec4 {
        let i = ((q * self.q_to_index + 0.5) as u32 as usize).min(self.lut_pm.len() - 1);
        self.lut_pm[i]
    }

    /// The premultiplied table [`Self::classify_premultiplied`] reads (never empty).
    #[inline(always)]
    pub fn table_premultiplied(&self) -> &[Vec4] {
        &self.lut_pm
    }

    /// The table [`Self::classify`] reads, `[r, g, b, a_step]` (never empty).
    #[inline(always)]
    pub fn table(&self) -> &[Vec4] {
        &self.lut.table
    }

    /// [`VolumeLights::headlight_by_squaring`] of the frame's lights.
    #[inline]
    pub fn headlight_by_squaring(&self) -> Option<(super::shade::Reflectance, u32)> {
        self.lights.headlight_by_squaring()
    }

    /// The factor from a fractional 16-bit level to the table's index (before its `+ ½`).
    #[inline(always)]
    pub fn q_to_index(&self) -> f32 {
        self.q_to_index
    }

    /// World-space gradient of the values by central differences (one voxel each way).
    #[inline]
    pub fn gradient(&self, q: Vec3) -> Vec3 {
        self.grad_to_world * central_difference(|p| self.value(p), q)
    }

    /// Blinn-Phong of colour `c` with gradient `g` at voxel-space `q`, seen along `ray`: the
    /// headlight or the scene's lights ([`VolumeLights`]).
    #[inline(always)]
    pub fn shade(&self, c: Vec3, g: Vec3, ray: Vec3, q: Vec3) -> Vec3 {
        self.lights
            .shade(c, g, ray, || self.world_from_voxel.transform_point3(q))
    }
}
