//! `texmap render scan.nii.gz --tf ct-bone [--mesh model.obj] …`: the volume flags, a scan
//! named on the command line made into a scene, and the flags laid over a scene's volumes.

use std::path::{Path, PathBuf};

use clap::{Args, ValueEnum};
use glam::{Mat4, Vec3};
use texmap::scene::{LoadOptions, Scene};
use texmap::volume::{
    load_volume_with, Classification, Method, Mode, RawDesc, ScalarType, SceneVolume,
    TransferFunction2D,
};
use texmap::Error;

/// Flags for volumes: a scan named as the scene (`.nii`, `.nii.gz`, `.nrrd`, `.nhdr`, `.raw`)
/// or the `[[volumes]]` of a TOML scene, whose values they override when given.
#[derive(Args, Clone, Debug)]
pub struct VolumeArgs {
    /// Volume transfer function: a preset (ct-bone, ct-skin, ct-muscle, mri, synth), a file,
    /// or inline `value:r,g,b,a;…` points [default for a scan file: chosen from its values —
    /// ct-bone for Hounsfield units, else from its histogram; in a scene: synth].
    #[arg(long, allow_hyphen_values = true)]
    pub tf: Option<String>,
    /// Volume mode [default: composite].
    #[arg(long, value_enum)]
    pub mode: Option<ModeArg>,
    /// Iso-value for --mode iso (default: the transfer function's first opaque value).
    #[arg(long, allow_hyphen_values = true)]
    pub iso: Option<f32>,
    /// Sample distance along rays (or between slices), world units (like VTK's
    /// SampleDistance) [default: 0.5].
    #[arg(long)]
    pub step: Option<f32>,
    /// Blinn-Phong shading (ambient 0.2, diffuse 0.7, specular 0.2, power 10) with the scene's
    /// lights, else a headlight; `--shade=false` turns a scene's shading off.
    #[arg(long, num_args = 0..=1, require_equals = true, default_missing_value = "true")]
    pub shade: Option<bool>,
    /// Volume method [default: raymarch].
    #[arg(long, value_enum)]
    pub method: Option<MethodArg>,
    /// Classification: post (interpolate, then classify), pre, or preint (pre-integrated)
    /// [default: post].
    #[arg(long, value_enum)]
    pub classification: Option<ClassArg>,
    /// Opacity × a function of gradient magnitude, `g:factor;…` (a 2D transfer function).
    #[arg(long)]
    pub gradient_opacity: Option<String>,
    /// Draw only the part of the volume inside this box, in voxel coordinates
    /// `x0,x1,y0,y1,z0,z1` (voxel centres at integers, 0 to n − 1): cut-away views.
    #[arg(long, value_parser = parse_crop, allow_hyphen_values = true, value_name = "x0,x1,y0,y1,z0,z1")]
    pub crop: Option<[f32; 6]>,
    /// Start every ray at the box entry (no jittered offset), as VTK does.
    #[arg(long)]
    pub no_jitter: bool,
    /// Turn off empty-space skipping (for measurements).
    #[arg(long)]
    pub no_skip: bool,
    /// Place the grid by its spacing alone, ignoring the file's orientation and origin (as
    /// vtk_volume.py does). For a volume file; scenes set `ignore_orientation`.
    #[arg(long)]
    pub ignore_orientation: bool,
    /// Camera distance divisor after framing the bounding sphere, for the default camera of
    /// a scene with volumes (vtk_volume.py's --dolly; default 1.6 with --auto-camera, the
    /// peers' framing, and 1, the whole scene in frame, otherwise).
    #[arg(long)]
    pub dolly: Option<f32>,
    /// Turn the default camera of a scene with volumes about z by this many degrees
    /// (vtk_volume.py's --azimuth).
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub azimuth: f32,
    /// A mesh file (.gltf, .glb, .obj, .toml) drawn with the scene, e.g. inside a scan;
    /// repeatable. Its world is the scan's (the scan's units, usually mm).
    #[arg(long = "mesh", value_name = "FILE")]
    pub meshes: Vec<PathBuf>,
    #[command(flatten)]
    pub raw: RawArgs,
}

/// How to read a raw volume file.
#[derive(Args, Clone, Debug)]
pub struct RawArgs {
    /// Raw volumes: grid size X,Y,Z.
    #[arg(long, value_parser = parse_dims)]
    pub dims: Option<[u32; 3]>,
    /// Raw volumes: voxel type u8 | i8 | u16 | i16 | u32 | i32 | f32 | f64.
    #[arg(long, value_parser = parse_dtype, default_value = "u8")]
    pub dtype: ScalarType,
    /// Raw volumes: voxel spacing x,y,z.
    #[arg(long, value_parser = parse_spacing, default_value = "1,1,1")]
    pub spacing: Vec3,
    /// Raw volumes: byte order of multi-byte voxels.
    #[arg(long, value_enum, default_value = "little")]
    pub endian: EndianArg,
    /// Raw volumes: bytes to skip before the voxels (a header).
    #[arg(long, default_value_t = 0)]
    pub header_bytes: u64,
}

impl RawArgs {
    /// The raw description when `--dims` is given.
    pub fn desc(&self) -> Option<RawDesc> {
        self.dims.map(|dims| RawDesc {
            big_endian: self.endian == EndianArg::Big,
            header_bytes: self.header_bytes,
            ..RawDesc::new(dims, self.dtype, self.spacing)
        })
    }

    /// True when a raw flag differs from its default.
    fn any_given(&self) -> bool {
        self.dims.is_some()
            || self.dtype != ScalarType::U8
            || self.spacing != Vec3::ONE
            || self.endian != EndianArg::Little
            || self.header_bytes != 0
    }
}

#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum ModeArg {
    Composite,
    Mip,
    Iso,
    Xray,
}
#[derive(Clone, Copy, Debug, ValueEnum, PartialEq, Eq)]
pub enum MethodArg {
    Raymarch,
    Slices,
    /// The volume is a distance field: its surface, sphere-traced.
    Surface,
    /// The volume is a distance field: its surface with a hypertexture (--hypertexture).
    Hypertexture,
}
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum ClassArg {
    Post,
    Pre,
    Preint,
}
#[derive(Clone, Copy, Debug, ValueEnum, PartialEq, Eq)]
pub enum EndianArg {
    Little,
    Big,
}

fn parse_dims(s: &str) -> Result<[u32; 3], String> {
    let v: Vec<u32> = s
        .split(',')
        .map(|x| {
            x.trim()
                .parse::<u32>()
                .map_err(|_| format!("\"{x}\" is not a size"))
        })
        .collect::<Result<_, _>>()?;
    match v[..] {
        [x, y, z] if x > 0 && y > 0 && z > 0 => Ok([x, y, z]),
        _ => Err("expected three positive sizes X,Y,Z".into()),
    }
}
fn parse_dtype(s: &str) -> Result<ScalarType, String> {
    ScalarType::parse(s)
        .ok_or_else(|| format!("\"{s}\" is not u8, i8, u16, i16, u32, i32, f32 or f64"))
}
fn parse_spacing(s: &str) -> Result<Vec3, String> {
    let v: Vec<f32> = s
        .split(',')
        .map(|x| {
            x.trim()
                .parse::<f32>()
                .map_err(|_| format!("\"{x}\" is not a number"))
        })
        .collect::<Result<_, _>>()?;
    match v[..] {
        [x, y, z] if [x, y, z].iter().all(|c| c.is_finite() && *c > 0.0) => Ok(Vec3::new(x, y, z)),
        _ => Err("expected three positive numbers x,y,z".into()),
    }
}

/// True for the file names read as volumes.
pub fn is_volume_path(s: &str) -> bool {
    let l = s.to_ascii_lowercase();
    [".nii", ".nii.gz", ".nrrd", ".nhdr", ".raw", ".raw.gz"]
        .iter()
        .any(|e| l.ends_with(e))
}

/// The file name up to its first dot (`scan.nii.gz` → `scan`), for default output names.
pub fn short_name(path: &Path) -> String {
    path.file_name()
        .map(|n| {
            n.to_string_lossy()
                .split('.')
                .next()
                .unwrap_or("volume")
                .to_string()
        })
        .unwrap_or_else(|| "volume".into())
}

/// A scan named on the command line as a scene: the volume (placed by its file, or by its
/// spacing with `--ignore-orientation`), with no meshes yet (see [`add_meshes`]).
pub fn volume_file_scene(
    v: &VolumeArgs,
    path: &Path,
    options: &LoadOptions,
) -> Result<(Scene, SceneVolume), Error> {
    let vol = load_volume_with(path, v.raw.desc().as_ref(), &options.volume_options())?;
    let mut sv = SceneVolume::new(vol, path);
    if v.tf.is_none() {
        sv.set_auto_transfer();
    }
    if v.ignore_orientation {
        sv.place(Mat4::IDENTITY, true)?;
    }
    Ok((Scene::default(), sv))
}

/// Adds the meshes (and materials) of every `--mesh` file to `scene`, printing their warnings.
/// Returns the lights the files define themselves (not the loaders' default light).
pub fn add_meshes(
    v: &VolumeArgs,
    scene: &mut Scene,
    options: &LoadOptions,
    quiet: bool,
) -> Result<Vec<texmap::scene::Light>, Error> {
    let mut own_lights = Vec::new();
    for file in &v.meshes {
        let loaded = texmap::scene::load(file, options)?;
        if !quiet {
            for w in &loaded.warnings {
                crate::output::stderr_line(&format!("texmap: warning: {w}"));
            }
        }
        if !loaded.volumes.is_empty() {
            return Err(Error::Unsupported(format!(
                "{}: --mesh takes meshes; this file holds volumes",
                file.display()
            )));
        }
        let offset = scene.materials.len();
        for mut m in loaded.scene.meshes {
            m.material += offset;
            scene.meshes.push(m);
        }
        scene.materials.extend(loaded.scene.materials);
        if !loaded.info.default_light {
            own_lights.extend(loaded.scene.lights);
        }
    }
    Ok(own_lights)
}

impl VolumeArgs {
    /// The volume flags given (each acts on the scene's volumes).
    pub fn given_volume_flags(&self) -> Vec<&'static str> {
        [
            ("--tf", self.tf.is_some()),
            ("--mode", self.mode.is_some()),
            ("--iso", self.iso.is_some()),
            ("--step", self.step.is_some()),
            ("--shade", self.shade.is_some()),
            ("--method", self.method.is_some()),
            ("--classification", self.classification.is_some()),
            ("--gradient-opacity", self.gradient_opacity.is_some()),
            ("--no-jitter", self.no_jitter),
            ("--no-skip", self.no_skip),
            ("--crop", self.crop.is_some()),
        ]
        .into_iter()
        .filter_map(|(f, g)| g.then_some(f))
        .collect()
    }

    /// The framing flags given (they move the default camera of a scene with volumes).
    pub fn given_framing_flags(&self) -> Vec<&'static str> {
        [
            ("--dolly", self.dolly.is_some()),
            ("--azimuth", self.azimuth != 0.0),
        ]
        .into_iter()
        .filter_map(|(f, g)| g.then_some(f))
        .collect()
    }

    /// Checks the flags that only make sense for a volume file.
    pub fn check_for_scene(&self, volume_file: bool) -> Result<(), Error> {
        if !volume_file && (self.raw.any_given() || self.ignore_orientation) {
            return Err(Error::parameter(
                "--dims, --dtype, --spacing, --endian, --header-bytes and --ignore-orientation \
                 apply to a volume file; a scene sets them in its [[volumes]] tables",
            ));
        }
        if self.dolly.is_some_and(|d| !(d.is_finite() && d > 0.0)) {
            return Err(Error::parameter("--dolly must be > 0"));
        }
        Ok(())
    }

    /// Lays the given flags over a volume's own settings.
    pub fn apply(&self, sv: &mut SceneVolume) -> Result<(), Error> {
        if let Some(tf) = &self.tf {
            sv.set_transfer(tf, Path::new(""))?;
        }
        let p = &mut sv.params;
        if let Some(m) = self.mode {
            p.mode = match m {
                ModeArg::Composite => Mode::Composite,
                ModeArg::Mip => Mode::Mip,
                ModeArg::Iso => Mode::Iso,
                ModeArg::Xray => Mode::Xray,
            };
        }
        if let Some(iso) = self.iso {
            p.iso = Some(iso);
        }
        if let Some(step) = self.step {
            p.step = step;
        }
        if let Some(shade) = self.shade {
            p.shade = shade;
        }
        if let Some(c) = self.classification {
            p.classification = match c {
                ClassArg::Post => Classification::Post,
                ClassArg::Pre => Classification::Pre,
                ClassArg::Preint => Classification::PreIntegrated,
            };
        }
        if let Some(g) = &self.gradient_opacity {
            p.gradient_opacity = TransferFunction2D::parse_gradient(g)?;
        }
        if self.no_jitter {
            p.jitter = false;
        }
        if self.no_skip {
            p.empty_space_skipping = false;
        }
        if let Some(c) = self.crop {
            p.crop = Some(c);
            p.check_crop(sv.volume.dims())
                .map_err(|e| Error::parameter(format!("--{e}")))?;
        }
        if let Some(m) = self.method {
            sv.method = match m {
                MethodArg::Raymarch => Method::Raymarch,
                MethodArg::Slices => Method::Slices,
                MethodArg::Surface => Method::Surface,
                MethodArg::Hypertexture => Method::Hypertexture,
            };
        }
        if !(sv.params.step.is_finite() && sv.params.step > 0.0) {
            return Err(Error::parameter(format!(
                "--step {} must be > 0",
                sv.params.step
            )));
        }
        sv.validate()
    }
}

/// The volumes as `--stats` lists them.
pub fn stats_json(volumes: &[SceneVolume]) -> serde_json::Value {
    volumes
        .iter()
        .map(|v| {
            let vol = &v.volume;
            serde_json::json!({
                "file": v.source,
                "dims": vol.dims(),
                "spacing": vol.spacing().to_array(),
                "range": [vol.range().0, vol.range().1],
                "method": format!("{:?}", v.method).to_lowercase(),
                "mode": format!("{:?}", v.params.mode).to_lowercase(),
                "tf": v.transfer_name,
                "shade": v.params.shade,
                "lights": v.params.lights.len(),
                "step": v.params.step,
                "distance_field": v
                    .method
                    .is_distance_field()
                    .then(|| crate::field::describe(v)),
            })
        })
        .collect()
}

/// `--crop x0,x1,y0,y1,z0,z1`: six numbers.
fn parse_crop(s: &str) -> Result<[f32; 6], String> {
    let v: Vec<f32> = s
        .split(',')
        .map(|t| t.trim().parse::<f32>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("{s:?} is not six numbers x0,x1,y0,y1,z0,z1"))?;
    <[f32; 6]>::try_from(v).map_err(|_| format!("{s:?} is not six numbers x0,x1,y0,y1,z0,z1"))
}
