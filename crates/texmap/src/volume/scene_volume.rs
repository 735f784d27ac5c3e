//! A volume as a scene holds it: the placed volume, its transfer function and how to render
//! it (a TOML `[[volumes]]` entry, or a scan named on the command line).

use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::{Mat4, Vec3};

use super::bricks::BRICK;
use super::grid::Volume;
use super::params::{Classification, MarchParams, Mode};
use super::sdf::{Hypertexture, SurfaceLook};
use super::transfer::{TransferFunction, TransferLut};
use crate::{Error, Result};

/// How a volume is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Method {
    /// Rays from the camera ([`raymarch`](super::raymarch::raymarch)).
    #[default]
    Raymarch,
    /// View-aligned slices through the pipeline ([`super::render_slices`]; composite mode).
    Slices,
    /// The volume is a distance field: its surface, sphere-traced and coloured by
    /// [`SceneVolume::look`] ([`super::sdf::render_distance_field`]).
    Surface,
    /// The volume is a distance field: its surface with [`SceneVolume::hypertexture`]
    /// around it.
    Hypertexture,
}

impl Method {
    /// `raymarch`, `slices`, `surface` or `hypertexture`.
    #[must_use]
    pub fn parse(s: &str) -> Option<Method> {
        match s {
            "raymarch" => Some(Method::Raymarch),
            "slices" => Some(Method::Slices),
            "surface" => Some(Method::Surface),
            "hypertexture" => Some(Method::Hypertexture),
            _ => None,
        }
    }

    /// True for the methods that read the volume as a distance field.
    #[must_use]
    pub fn is_distance_field(self) -> bool {
        matches!(self, Method::Surface | Method::Hypertexture)
    }
}

/// `composite`, `mip`, `iso` or `xray`.
#[must_use]
pub fn parse_mode(s: &str) -> Option<Mode> {
    match s {
        "composite" => Some(Mode::Composite),
        "mip" => Some(Mode::Mip),
        "iso" => Some(Mode::Iso),
        "xray" => Some(Mode::Xray),
        _ => None,
    }
}

/// `post`, `pre` or `preint`.
#[must_use]
pub fn parse_classification(s: &str) -> Option<Classification> {
    match s {
        "post" => Some(Classification::Post),
        "pre" => Some(Classification::Pre),
        "preint" => Some(Classification::PreIntegrated),
        _ => None,
    }
}

/// A volume in a scene.
#[derive(Clone, Debug)]
pub struct SceneVolume {
    /// The volume, placed: its `world_from_voxel` includes the scene's transform.
    pub volume: Arc<Volume>,
    pub transfer: TransferFunction,
    /// The transfer function as written (a preset name, points or a file), for listings.
    pub transfer_name: String,
    pub params: MarchParams,
    pub method: Method,
    /// The surface's material when the volume is a distance field ([`Method::Surface`],
    /// [`Method::Hypertexture`]).
    pub look: SurfaceLook,
    /// The hypertexture of [`Method::Hypertexture`].
    pub hypertexture: Option<Hypertexture>,
    /// The file the volume was read from.
    pub source: PathBuf,
}

impl SceneVolume {
    /// Default rendering (the `synth` preset, composite, step 0.5, raymarch) of `volume`.
    #[must_use]
    pub fn new(volume: Volume, source: &Path) -> Self {
        SceneVolume {
            volume: Arc::new(volume),
            transfer: TransferFunction::preset("synth").expect("the synth preset parses"),
            transfer_name: "synth".into(),
            params: MarchParams::default(),
            method: Method::Raymarch,
            look: SurfaceLook::default(),
            hypertexture: None,
            source: source.to_path_buf(),
        }
    }

    /// Sets the transfer function from a preset name, inline points or a file (relative
    /// paths from `dir`), as [`TransferFunction::from_arg_in`].
    ///
    /// # Errors
    /// As [`TransferFunction::from_arg_in`].
    pub fn set_transfer(&mut self, s: &str, dir: &Path) -> Result<()> {
        self.transfer = TransferFunction::from_arg_in(s, dir)?;
        self.transfer_name = s.to_string();
        Ok(())
    }

    /// Sets the transfer function chosen from the scan's own values
    /// ([`super::auto_transfer::transfer_for`]: `ct-bone` for Hounsfield units, else from the
    /// histogram).
    pub fn set_auto_transfer(&mut self) {
        let (tf, name) = super::auto_transfer::transfer_for(&self.volume);
        self.transfer = tf;
        self.transfer_name = name;
    }

    /// Whether the transfer function was chosen from the scan's values
    /// ([`Self::set_auto_transfer`]) rather than given.
    #[must_use]
    pub fn transfer_was_chosen(&self) -> bool {
        self.transfer_name
            .starts_with(super::auto_transfer::CHOSEN_PREFIX)
    }

    /// What is wrong with the transfer function for this scan's values, if anything a user
    /// should hear before looking at the image (composite rendering of a scan, not of a
    /// distance field): it is transparent over every value the scan holds (nothing would be
    /// drawn), or it is visible at the scan's lowest value — its background, air in a CT,
    /// outside the head in an MRI — and everywhere above it, so the box renders as a wall
    /// (a CT preset on an MRI, or on data that is not in Hounsfield units).
    #[must_use]
    pub fn transfer_warning(&self) -> Option<String> {
        if self.method.is_distance_field() || self.params.mode != Mode::Composite {
            return None;
        }
        let (lo, hi) = self.volume.range();
        let alpha = |k: u32| {
            let v = lo + (hi - lo) * k as f32 / 255.0;
            self.transfer.eval(v).w
        };
        let name = &self.transfer_name;
        if (0..=255).all(|k| alpha(k) <= 0.0) {
            return Some(format!(
                "transfer function {name} is transparent over every value of the scan \
                 ({lo} .. {hi}): nothing would be drawn"
            ));
        }
        if (0..=255).all(|k| alpha(k) > 0.0) {
            return Some(format!(
                "transfer function {name} is visible at the scan's lowest value {lo} (its \
                 background) and at every value above it ({lo} .. {hi}): the box renders as a \
                 wall; a preset made for other units (CT presets are in Hounsfield units) or a \
                 --tf with a transparent start fits it"
            ));
        }
        None
    }

    /// The world box of what the volume shows: the bricks its transfer function makes
    /// visible (composite rays and slices), or that reach the iso-value (iso-surfaces), within
    /// the crop box. MIP, X-ray and distance fields, and a volume that shows nothing, give the
    /// whole (cropped) box. The automatic framing fits this box, so a brain inside a mostly
    /// empty scan fills the frame.
    #[must_use]
    pub fn visible_world_bounds(&self) -> (Vec3, Vec3) {
        let vol = &*self.volume;
        let dims = vol.dims();
        let (lo, hi) = self.params.voxel_box(dims);
        let whole = |lo: Vec3, hi: Vec3| corners_bounds(&vol.world_corners_of((lo, hi)));
        let p = &self.params;
        let visible: Box<dyn Fn(f32, f32) -> bool> = match (self.method.is_distance_field(), p.mode)
        {
            (false, Mode::Composite) => {
                let lut = TransferLut::new(&self.transfer, vol.range(), p.step);
                Box::new(move |a, b| !lut.is_transparent(vol.value_of(a), vol.value_of(b)))
            }
            (false, Mode::Iso) => {
                let Some(iso) = p.iso.or_else(|| self.transfer.first_opaque_value()) else {
                    return whole(lo, hi);
                };
                Box::new(move |_, b| vol.value_of(b) >= iso)
            }
            _ => return whole(lo, hi),
        };
        let bricks = vol.bricks();
        let n = bricks.counts;
        let top = Vec3::from_array(dims.map(|d| d.saturating_sub(1) as f32));
        let (mut vlo, mut vhi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        for (i, &(a, b)) in bricks.min_max.iter().enumerate() {
            if !visible(a, b) {
                continue;
            }
            let i = i as u32;
            let c = Vec3::new(
                (i % n[0]) as f32,
                ((i / n[0]) % n[1]) as f32,
                (i / (n[0] * n[1])) as f32,
            ) * BRICK as f32;
            vlo = vlo.min(c);
            vhi = vhi.max((c + Vec3::splat(BRICK as f32)).min(top));
        }
        let (vlo, vhi) = (vlo.max(lo), vhi.min(hi));
        if vlo.cmple(vhi).all() {
            whole(vlo, vhi)
        } else {
            whole(lo, hi)
        }
    }

    /// Places the volume: `world_from_object` applied after the file's own placement, or
    /// after its spacing alone when `ignore_orientation` (as `vtk_volume.py` places scans).
    ///
    /// # Errors
    /// [`Error::Parameter`] for a singular or non-finite result.
    pub fn place(&mut self, world_from_object: Mat4, ignore_orientation: bool) -> Result<()> {
        let vol = Arc::make_mut(&mut self.volume);
        let file = if ignore_orientation {
            Mat4::from_scale(vol.spacing())
        } else {
            vol.world_from_voxel()
        };
        vol.set_world_from_voxel(world_from_object * file)
    }

    /// Checks the options that the renderers would otherwise reject frame by frame.
    ///
    /// # Errors
    /// [`Error::Parameter`] for a bad step or iso-value, [`Error::Unsupported`] for slices in
    /// a mode or classification they do not draw.
    pub fn validate(&self) -> Result<()> {
        let p = &self.params;
        if !(p.step.is_finite() && p.step > 0.0) {
            return Err(Error::parameter(format!("step {} must be > 0", p.step)));
        }
        if p.iso.is_some_and(|v| !v.is_finite()) {
            return Err(Error::parameter("iso must be finite"));
        }
        p.check_crop(self.volume.dims()).map_err(Error::Parameter)?;
        if p.crop.is_some() && self.method.is_distance_field() {
            return Err(Error::parameter(
                "crop applies to a scan drawn by rays or slices, not to a distance field's surface",
            ));
        }
        if self.method == Method::Slices
            && (p.mode != Mode::Composite || p.classification != Classification::Post)
        {
            return Err(Error::Unsupported(
                "method slices renders composite mode with post-classification only".into(),
            ));
        }
        if self.method.is_distance_field() {
            let (lo, hi) = self.volume.range();
            if !(lo < 0.0 && hi > 0.0) {
                return Err(Error::parameter(format!(
                    "{}: values {lo} to {hi} are not a distance field (negative inside, \
                     positive outside): nothing to draw as a surface",
                    self.source.display()
                )));
            }
            self.look.validate()?;
        }
        match (&self.method, &self.hypertexture) {
            (Method::Hypertexture, None) => {
                return Err(Error::parameter("method hypertexture needs a hypertexture"))
            }
            (_, Some(h)) => h.validate()?,
            _ => {}
        }
        Ok(())
    }

    /// The centre of the volume's box in world space.
    #[must_use]
    pub fn centre(&self) -> Vec3 {
        let (lo, hi) = self.volume.world_bounds();
        (lo + hi) * 0.5
    }
}

/// The axis-aligned box of `corners`.
fn corners_bounds(corners: &[Vec3; 8]) -> (Vec3, Vec3) {
    corners.iter().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(lo, hi), &c| (lo.min(c), hi.max(c)),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 16³ ramp over 0..255: a scan in 8-bit units, not Hounsfield.
    fn ramp() -> SceneVolume {
        let scalars = (0..16 * 16 * 16).map(|i| (i % 256) as f32).collect();
        let v = Volume::from_scalars([16; 3], Mat4::IDENTITY, scalars).unwrap();
        SceneVolume::new(v, Path::new("ramp.nrrd"))
    }

    #[test]
    fn a_transfer_function_that_misses_the_scan_is_named() {
        let mut sv = ramp();
        // synth is transparent at 0 and visible above 45: no warning.
        assert_eq!(sv.transfer_warning(), None);
        // A CT preset on 8-bit data: visible from its lowest value up.
        sv.set_transfer("ct-bone", Path::new("")).unwrap();
        let w = sv.transfer_warning().unwrap();
        assert!(w.contains("ct-bone") && w.contains("wall"), "{w}");
        // Opaque only above the scan's values: nothing would be drawn.
        sv.set_transfer("0:0,0,0,0;1000:1,1,1,0;2000:1,1,1,1", Path::new(""))
            .unwrap();
        assert!(sv
            .transfer_warning()
            .unwrap()
            .contains("nothing would be drawn"));
        // MIP ignores the opacity: no warning.
        sv.params.mode = Mode::Mip;
        assert_eq!(sv.transfer_warning(), None);
    }
}
