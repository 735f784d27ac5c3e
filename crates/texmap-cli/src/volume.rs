//! `texmap render scan.nii.gz --tf ct-bone …`: volume rendering flags and the volume path of
//! `render`.

use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::{Args, ValueEnum};
use glam::{Mat4, Vec3};
use texmap::render::Frame;
use texmap::scene::{Camera, CameraProjection};
use texmap::volume::{
    load_volume, raymarch, render_slices, Classification, MarchParams, Mode, RawDesc, ScalarType,
    TransferFunction, TransferFunction2D,
};
use texmap::Error;

/// Flags for volume scenes (`.nii`, `.nii.gz`, `.nrrd`, `.nhdr`, `.raw`).
#[derive(Args, Clone, Debug)]
pub struct VolumeArgs {
    /// Volume transfer function: a preset (ct-bone, ct-skin, ct-muscle, mri, synth), a file,
    /// or inline `value:r,g,b,a;…` points.
    #[arg(long, default_value = "synth", allow_hyphen_values = true)]
    pub tf: String,
    /// Volume mode: composite | mip | iso | xray.
    #[arg(long, value_enum, default_value = "composite")]
    pub mode: ModeArg,
    /// Iso-value for --mode iso (default: the transfer function's first opaque value).
    #[arg(long, allow_hyphen_values = true)]
    pub iso: Option<f32>,
    /// Sample distance along rays (or between slices), world units (like VTK's SampleDistance).
    #[arg(long, default_value_t = 0.5)]
    pub step: f32,
    /// Blinn-Phong shading with a headlight (ambient 0.2, diffuse 0.7, specular 0.2, power 10).
    #[arg(long)]
    pub shade: bool,
    /// Volume method: raymarch | slices.
    #[arg(long, value_enum, default_value = "raymarch")]
    pub method: MethodArg,
    /// Classification: post (interpolate, then classify) | pre | preint (pre-integrated).
    #[arg(long, value_enum, default_value = "post")]
    pub classification: ClassArg,
    /// Opacity × a function of gradient magnitude, `g:factor;…` (a 2D transfer function).
    #[arg(long)]
    pub gradient_opacity: Option<String>,
    /// Start every ray at the box entry (no jittered offset), as VTK does.
    #[arg(long)]
    pub no_jitter: bool,
    /// Turn off empty-space skipping (for measurements).
    #[arg(long)]
    pub no_skip: bool,
    /// Place the grid by its spacing alone, ignoring the file's orientation and origin (as
    /// vtk_volume.py does).
    #[arg(long)]
    pub ignore_orientation: bool,
    /// Camera distance divisor after framing the bounding sphere (vtk_volume.py's --dolly).
    #[arg(long, default_value_t = 1.6)]
    pub dolly: f32,
    /// Turn the default camera about z by this many degrees (vtk_volume.py's --azimuth).
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub azimuth: f32,
    /// Raw volumes: grid size X,Y,Z.
    #[arg(long, value_parser = parse_dims)]
    pub dims: Option<[u32; 3]>,
    /// Raw volumes: voxel type u8 | i8 | u16 | i16 | u32 | i32 | f32 | f64 (little endian).
    #[arg(long, value_parser = parse_dtype, default_value = "u8")]
    pub dtype: ScalarType,
    /// Raw volumes: voxel spacing x,y,z.
    #[arg(long, value_parser = parse_spacing, default_value = "1,1,1")]
    pub spacing: Vec3,
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
}
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum ClassArg {
    Post,
    Pre,
    Preint,
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

/// True for the file names the volume path renders.
pub fn is_volume_path(s: &str) -> bool {
    let l = s.to_ascii_lowercase();
    [".nii", ".nii.gz", ".nrrd", ".nhdr", ".raw", ".raw.gz"]
        .iter()
        .any(|e| l.ends_with(e))
}

/// The `render` flags the volume path shares with surface scenes.
pub struct Common<'a> {
    pub scene: &'a str,
    pub output: Option<&'a Path>,
    pub size: (u32, u32),
    pub eye: Option<Vec3>,
    pub target: Option<Vec3>,
    pub up: Option<Vec3>,
    pub fov: Option<f32>,
    /// `--ortho [HEIGHT]`.
    pub ortho: Option<Option<f32>>,
    pub frames: u32,
    pub threads: Option<usize>,
    pub stats: bool,
    pub quiet: bool,
}

/// Loads the volume, renders `frames` turntable frames, writes the last (or each) frame.
pub fn run(v: &VolumeArgs, c: &Common) -> Result<(), Error> {
    let setup_start = Instant::now();
    if c.frames == 0 {
        return Err(Error::parameter("--frames must be at least 1"));
    }
    if !(v.dolly.is_finite() && v.dolly > 0.0) {
        return Err(Error::parameter("--dolly must be > 0"));
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(c.threads.unwrap_or(0))
        .build()
        .map_err(|e| Error::parameter(format!("--threads: {e}")))?;
    let path = Path::new(c.scene);
    let raw = v.dims.map(|dims| RawDesc {
        dims,
        scalar: v.dtype,
        spacing: v.spacing,
    });
    let mut vol = pool.install(|| load_volume(path, raw.as_ref()))?;
    if v.ignore_orientation {
        vol.set_world_from_voxel(Mat4::from_scale(vol.spacing()))?;
    }
    let tf = TransferFunction::from_arg(&v.tf)?;
    let gradient_opacity = match &v.gradient_opacity {
        Some(s) => TransferFunction2D::parse_gradient(s)?,
        None => Vec::new(),
    };
    let params = MarchParams {
        mode: match v.mode {
            ModeArg::Composite => Mode::Composite,
            ModeArg::Mip => Mode::Mip,
            ModeArg::Iso => Mode::Iso,
            ModeArg::Xray => Mode::Xray,
        },
        step: v.step,
        shade: v.shade,
        classification: match v.classification {
            ClassArg::Post => Classification::Post,
            ClassArg::Pre => Classification::Pre,
            ClassArg::Preint => Classification::PreIntegrated,
        },
        iso: v.iso,
        gradient_opacity,
        jitter: !v.no_jitter,
        empty_space_skipping: !v.no_skip,
        ..MarchParams::default()
    };
    let base = vol.vtk_camera(v.dolly, v.azimuth);
    let (lo, hi) = vol.world_bounds();
    let centre = (lo + hi) * 0.5;
    let radius = ((hi - lo) * 0.5).length().max(1e-3);
    let projection = match (c.ortho, c.fov) {
        (Some(Some(height)), _) => CameraProjection::Orthographic {
            half_height: 0.5 * height,
        },
        // VTK's parallel scale after ResetCamera is the bounding radius; Dolly divides it.
        (Some(None), _) => CameraProjection::Orthographic {
            half_height: radius / v.dolly,
        },
        (None, Some(fov_y_deg)) => CameraProjection::Perspective { fov_y_deg },
        (None, None) => base.projection,
    };
    let camera = Camera {
        eye: c.eye.unwrap_or(base.eye),
        target: c.target.unwrap_or(base.target),
        up: c.up.unwrap_or(base.up),
        projection,
        ..base
    };
    camera.validate()?;
    // Near and far around the box whatever the eye.
    let dist = (camera.eye - centre).length();
    let camera = Camera {
        near: (dist - radius).max(dist * 1e-3).max(1e-4),
        far: dist + radius + 1.0,
        ..camera
    };
    // Per-volume structures (VTK builds its own in its first frame): outside the frame times.
    pool.install(|| {
        let _ = vol.bricks();
        if params.shade {
            let _ = vol.normals();
        }
    });
    let stem = path
        .file_name()
        .map(|n| {
            n.to_string_lossy()
                .split('.')
                .next()
                .unwrap_or("volume")
                .to_string()
        })
        .unwrap_or_else(|| "volume".into());
    let output = c
        .output
        .map(Path::to_path_buf)
        .unwrap_or_else(|| PathBuf::from(format!("texmap-{stem}.png")));
    let per_frame = output.to_string_lossy().contains("{frame}");
    let setup_ms = setup_start.elapsed().as_secs_f64() * 1e3;

    let (w, h) = c.size;
    let mut times = Vec::with_capacity(c.frames as usize);
    let mut last: Option<Frame> = None;
    for k in 1..=c.frames {
        let cam = if k == c.frames {
            camera
        } else {
            camera.orbit(std::f32::consts::TAU * k as f32 / c.frames as f32)
        };
        let start = Instant::now();
        let frame = pool.install(|| match v.method {
            MethodArg::Raymarch => raymarch(&vol, &tf, &cam, w, h, &params, None),
            MethodArg::Slices => render_slices(&vol, &tf, &cam, w, h, &params),
        })?;
        times.push(start.elapsed().as_secs_f64() * 1e3);
        if per_frame {
            let p = PathBuf::from(
                output
                    .to_string_lossy()
                    .replace("{frame}", &format!("{k:04}")),
            );
            crate::output::write_png_rgb8(&p, frame.width, frame.height, &frame.to_srgb8())?;
        }
        last = Some(frame);
    }
    let frame = last.ok_or_else(|| Error::parameter("no frame rendered"))?;
    if !per_frame {
        crate::output::write_png_rgb8(&output, frame.width, frame.height, &frame.to_srgb8())?;
    }
    let mut sorted = times.clone();
    sorted.sort_by(f64::total_cmp);
    let n = sorted.len();
    let median = if n % 2 == 1 {
        sorted[n / 2]
    } else {
        0.5 * (sorted[n / 2 - 1] + sorted[n / 2])
    };
    let r2 = |x: f64| (x * 100.0).round() / 100.0;
    if c.stats {
        let json = serde_json::json!({
            "scene": c.scene,
            "dims": vol.dims(),
            "spacing": vol.spacing().to_array(),
            "range": [vol.range().0, vol.range().1],
            "size": [frame.width, frame.height],
            "threads": pool.current_num_threads(),
            "method": format!("{:?}", v.method).to_lowercase(),
            "mode": format!("{:?}", v.mode).to_lowercase(),
            "tf": v.tf,
            "shade": v.shade,
            "step": v.step,
            "camera": {"eye": camera.eye.to_array(), "target": camera.target.to_array(),
                       "up": camera.up.to_array(), "fov_y_deg": camera.projection.fov_y_deg(),
                       "ortho_height": match camera.projection {
                           CameraProjection::Orthographic { half_height } => Some(2.0 * half_height),
                           CameraProjection::Perspective { .. } => None,
                       }},
            "frames": c.frames,
            "setup_ms": r2(setup_ms),
            "frame_ms": {"min": r2(sorted[0]), "median": r2(median), "max": r2(sorted[n - 1])},
            "frame_ms_all": times.iter().map(|&t| r2(t)).collect::<Vec<_>>(),
            "samples": frame.stats.texture_samples,
            "output": output,
        });
        println!("{json}");
    } else if !c.quiet {
        eprintln!(
            "wrote {} ({}x{}, {} frame{}, median {:.1} ms/frame)",
            output.display(),
            frame.width,
            frame.height,
            c.frames,
            if c.frames == 1 { "" } else { "s" },
            median
        );
    }
    Ok(())
}
