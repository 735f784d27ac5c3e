//! `texmap render SCAN --slice axial|coronal|sagittal [--index K] [--window W --level L]`: one
//! plane of a scan drawn flat (`texmap::volume::section`), through the transfer function or
//! a window/level, in place of the 3D rendering.

use clap::{Args, ValueEnum};
use texmap::volume::section::{SectionAxis, SectionLook};
use texmap::volume::SceneVolume;
use texmap::Error;

/// `--slice`'s planes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum SliceArg {
    Axial,
    Coronal,
    Sagittal,
}

/// The slice-view flags.
#[derive(Args, Clone, Debug, Default)]
pub struct SectionArgs {
    /// Draw one plane of the scan flat instead of the 3D view: axial (across world z),
    /// coronal (across y) or sagittal (across x), oriented by the file's placement.
    #[arg(long, value_enum)]
    pub slice: Option<SliceArg>,
    /// The plane's voxel index along its axis [default: the middle one].
    #[arg(long, value_name = "K")]
    pub index: Option<u32>,
    /// Window width for --slice: grey from level − W/2 (black) to level + W/2 (white), in the
    /// file's units [default: the scan's value range]; without --window or --level a given
    /// transfer function colours the plane, and without --tf either the window spans the
    /// 0.5th to 99.5th percentile of the scan's values.
    #[arg(long, value_name = "W")]
    pub window: Option<f32>,
    /// Window level (centre) for --slice [default: the middle of the scan's values].
    #[arg(long, value_name = "L", allow_hyphen_values = true)]
    pub level: Option<f32>,
}

/// A slice view, resolved.
#[derive(Clone, Debug)]
pub struct Section {
    pub axis: SectionAxis,
    pub index: u32,
    pub look: SectionLook,
}

impl SectionArgs {
    /// The slice-view flags given.
    fn given(&self) -> Vec<&'static str> {
        [
            ("--slice", self.slice.is_some()),
            ("--index", self.index.is_some()),
            ("--window", self.window.is_some()),
            ("--level", self.level.is_some()),
        ]
        .into_iter()
        .filter_map(|(f, g)| g.then_some(f))
        .collect()
    }

    /// The slice view of `volumes` (with `meshes` other meshes in the scene) these flags ask
    /// for, or `None` without `--slice`. `others` are the flags given that a flat plane
    /// cannot honour (camera, frames, 3D options).
    ///
    /// # Errors
    /// One line naming the flag: `--index`, `--window` or `--level` without `--slice`;
    /// `--slice` on a scene that is not one scan alone or beside `others`; an index outside
    /// the plane's axis (from the library).
    pub fn resolve(
        &self,
        name: &str,
        volumes: &[SceneVolume],
        meshes: usize,
        others: &[&str],
    ) -> Result<Option<Section>, Error> {
        let Some(slice) = self.slice else {
            let given = self.given();
            if !given.is_empty() {
                return Err(Error::parameter(format!(
                    "{}: these choose what --slice draws; add --slice axial|coronal|sagittal",
                    given.join(", ")
                )));
            }
            return Ok(None);
        };
        let [sv] = volumes else {
            return Err(Error::parameter(format!(
                "--slice: {name} is not one scan ({} volumes) to cut",
                volumes.len()
            )));
        };
        if meshes > 0 || sv.method.is_distance_field() {
            return Err(Error::parameter(format!(
                "--slice: {name} draws meshes or a distance field's surface; a slice view cuts \
                 a scan alone"
            )));
        }
        if let Some(flag) = others.first() {
            return Err(Error::parameter(format!(
                "{flag}: --slice draws one plane flat, which {flag} does not change"
            )));
        }
        let axis = match slice {
            SliceArg::Axial => SectionAxis::Axial,
            SliceArg::Coronal => SectionAxis::Coronal,
            SliceArg::Sagittal => SectionAxis::Sagittal,
        };
        let vol = &sv.volume;
        let across = texmap::volume::section::section_axes(vol, axis)[0].0;
        let n = vol.dims()[across];
        let index = self.index.unwrap_or(n / 2);
        if index >= n {
            return Err(Error::parameter(format!(
                "--slice {} --index {index}: {name} has voxels 0..={} across that plane",
                slice_name(slice),
                n - 1
            )));
        }
        let look = if self.window.is_some() || self.level.is_some() {
            let (lo, hi) = vol.range();
            SectionLook::Window {
                level: self.level.unwrap_or(0.5 * (lo + hi)),
                width: self.window.unwrap_or((hi - lo).max(f32::MIN_POSITIVE)),
            }
        } else if sv.transfer_was_chosen() {
            // No --tf: grey, as a radiology viewer opens a scan (the chosen function's faint
            // opacities would leave the plane dark).
            SectionLook::auto_window(vol)
        } else {
            SectionLook::Transfer(sv.transfer.clone())
        };
        Ok(Some(Section { axis, index, look }))
    }
}

fn slice_name(s: SliceArg) -> &'static str {
    match s {
        SliceArg::Axial => "axial",
        SliceArg::Coronal => "coronal",
        SliceArg::Sagittal => "sagittal",
    }
}
