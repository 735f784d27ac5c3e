//! `texmap render [SCENE]`: one frame or a turntable of a built-in scene, a scene file, or a
//! scan (with `--mesh` files inside it).

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use clap::{Args, ValueEnum};
use glam::Vec3;
use texmap::camera::{Camera, CameraProjection};
use texmap::render::render_with_volumes;
use texmap::render::{
    render_into, CullMode, Frame, FrameStats, Interpolation, Settings, ShadingMode, Visibility,
};
use texmap::scene::{builtin, LoadOptions, Scene, TextureSlot};
use texmap::texture::load::{load_texture, Limits};
use texmap::texture::{ColorSpace, Filter, LodRule, Sampler, Texture2D, Wrap};
use texmap::volume::SceneVolume;
use texmap::Error;

#[derive(Args)]
pub struct RenderArgs {
    /// `builtin:demo` (default), `builtin:plane`, `builtin:sphere`, `builtin:marble`, a scene
    /// file (`.gltf`, `.glb`, `.obj` or `.toml`), or a volume (`.nii`, `.nii.gz`, `.nrrd`,
    /// `.nhdr`, `.raw`).
    scene: Option<String>,
    /// A missing or undecodable texture becomes a warning and a magenta placeholder.
    #[arg(long)]
    lenient: bool,
    /// Let a file's references leave its folder (`..`, absolute paths).
    #[arg(long)]
    allow_outside_paths: bool,
    /// Ignore the file's own camera: frame the bounding box as `gl_render.py` does.
    #[arg(long)]
    auto_camera: bool,
    /// Output PNG; a `{frame}` in the name writes every turntable frame.
    #[arg(short = 'o', long = "output")]
    output: Option<PathBuf>,
    /// Image size, WxH.
    #[arg(long, default_value = "640x360", value_parser = parse_size)]
    size: (u32, u32),
    /// Camera position x,y,z.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    eye: Option<Vec3>,
    /// Point the camera looks at, x,y,z.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    target: Option<Vec3>,
    /// Camera up vector, x,y,z.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    up: Option<Vec3>,
    /// Vertical field of view in degrees.
    #[arg(long)]
    fov: Option<f32>,
    /// Orthographic projection showing HEIGHT world units vertically (the width follows the
    /// image's aspect); without a value, the height that frames the scene's bounding sphere.
    #[arg(
        long,
        value_name = "HEIGHT",
        num_args = 0..=1,
        allow_negative_numbers = true,
        conflicts_with = "fov"
    )]
    ortho: Option<Option<f32>>,
    // The help is the library's list of names (a doc comment cannot name a constant).
    #[arg(long, value_parser = Filter::parse, help = Filter::SPELLINGS)]
    filter: Option<Filter>,
    #[arg(long, value_parser = Wrap::parse, help = Wrap::SPELLINGS)]
    wrap: Option<Wrap>,
    /// Texture coordinate scale (default 64 for the plane, 1 otherwise).
    #[arg(long)]
    uv_scale: Option<f32>,
    /// Replace the scene's base-colour texture with this image.
    #[arg(long)]
    texture: Option<PathBuf>,
    /// What --texture's 8/16-bit channels hold.
    #[arg(long, value_enum, default_value = "srgb")]
    color_space: ColorSpaceArg,
    /// LOD rule: gl (longer derivative) or rss (root of the sum of squares, the article's).
    #[arg(long, value_enum, default_value = "gl")]
    lod_rule: LodRuleArg,
    /// Added to every level of detail.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    lod_bias: f32,
    /// perspective | affine | subdivide.
    #[arg(long, value_enum, default_value = "perspective")]
    interp: InterpArg,
    /// Largest affine error in pixels before --interp subdivide splits a triangle.
    #[arg(long, default_value_t = 0.5)]
    subdivide_error: f32,
    /// flat | gouraud | phong.
    #[arg(long, value_enum, default_value = "phong")]
    shading: ShadingArg,
    /// zbuffer | depth-sort.
    #[arg(long, value_enum, default_value = "zbuffer")]
    visibility: VisibilityArg,
    /// none | back | front.
    #[arg(long, value_enum, default_value = "none")]
    cull: CullArg,
    /// Multisample anti-aliasing: 1, 2, 4, 8 or 16 samples per pixel.
    #[arg(long, default_value_t = 1)]
    msaa: u32,
    /// Supersampling: render N×N samples per pixel and average.
    #[arg(long, default_value_t = 1)]
    ssaa: u32,
    /// Texture colour only, no lighting.
    #[arg(long)]
    unlit: bool,
    /// Worker threads (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
    /// Turntable frames: the camera orbits the target by 360/N degrees per frame.
    #[arg(long, default_value_t = 1)]
    frames: u32,
    /// Triangle count of builtin:sphere.
    #[arg(long, default_value_t = 199_200)]
    tris: usize,
    /// Print statistics as JSON on stdout.
    #[arg(long)]
    stats: bool,
    /// Print nothing but errors.
    #[arg(long, short)]
    quiet: bool,
    #[command(flatten)]
    pub volume: Box<crate::volume::VolumeArgs>,
}

#[derive(Clone, Copy, ValueEnum)]
enum ColorSpaceArg {
    Srgb,
    Linear,
}
#[derive(Clone, Copy, ValueEnum)]
enum LodRuleArg {
    Gl,
    Rss,
}
#[derive(Clone, Copy, ValueEnum)]
enum InterpArg {
    Perspective,
    Affine,
    Subdivide,
}
#[derive(Clone, Copy, ValueEnum)]
enum ShadingArg {
    Flat,
    Gouraud,
    Phong,
}
#[derive(Clone, Copy, ValueEnum)]
enum VisibilityArg {
    Zbuffer,
    DepthSort,
}
#[derive(Clone, Copy, ValueEnum)]
enum CullArg {
    None,
    Back,
    Front,
}

pub fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .to_lowercase()
        .split_once('x')
        .map(|(a, b)| (a.to_string(), b.to_string()))
        .ok_or("expected WxH")?;
    let w: u32 = w.parse().map_err(|_| "width is not a number")?;
    let h: u32 = h.parse().map_err(|_| "height is not a number")?;
    if w == 0 || h == 0 || w > 16384 || h > 16384 {
        return Err(format!("{w}x{h} is outside 1x1..16384x16384"));
    }
    Ok((w, h))
}

fn parse_vec3(s: &str) -> Result<Vec3, String> {
    let v: Vec<f32> = s
        .split(',')
        .map(|p| p.trim().parse::<f32>())
        .collect::<Result<_, _>>()
        .map_err(|e| e.to_string())?;
    if v.len() != 3 || v.iter().any(|x| !x.is_finite()) {
        return Err("expected three finite numbers x,y,z".into());
    }
    Ok(Vec3::new(v[0], v[1], v[2]))
}

/// What `render` draws.
struct Built {
    scene: Scene,
    volumes: Vec<SceneVolume>,
    /// The default output name's stem.
    short: String,
    /// Read from a file (not built in).
    from_file: bool,
}

/// The scene, its volumes (a volume file's, or a TOML scene's with the volume flags laid
/// over them), and `--mesh` files added.
fn build(args: &RenderArgs, sampler: Sampler) -> Result<Built, Error> {
    let options = LoadOptions {
        allow_outside_paths: args.allow_outside_paths,
        lenient: args.lenient,
        ..Default::default()
    };
    let v = &args.volume;
    let volume_file = args
        .scene
        .as_deref()
        .filter(|s| crate::volume::is_volume_path(s));
    v.check_for_scene(volume_file.is_some())?;
    let mut built = match volume_file {
        Some(path) => {
            let path = Path::new(path);
            let (scene, sv) = crate::volume::volume_file_scene(v, path)?;
            Built {
                scene,
                volumes: vec![sv],
                short: crate::volume::short_name(path),
                from_file: true,
            }
        }
        None => build_scene(args, sampler, &options)?,
    };
    let own_lights = crate::volume::add_meshes(v, &mut built.scene, &options, args.quiet)?;
    if volume_file.is_some() {
        // The mesh files' own lights light the scan too; without any, the meshes get the
        // peers' light and the scan its headlight.
        for sv in &mut built.volumes {
            sv.params.lights = own_lights.clone();
        }
        built.scene.lights = own_lights;
        if built.scene.lights.is_empty() {
            built.scene.lights.push(texmap::scene::Light::Directional {
                direction: Vec3::new(0.3, 0.8, 0.5).normalize(),
                color: Vec3::ONE,
            });
        }
        built.scene.ambient_light = Vec3::ONE;
    } else {
        built.scene.lights.extend(own_lights);
    }
    for sv in &mut built.volumes {
        v.apply(sv).map_err(|e| match e {
            Error::Parameter(m) | Error::Unsupported(m) => {
                Error::parameter(format!("{}: {m}", sv.source.display()))
            }
            other => other,
        })?;
    }
    Ok(built)
}

/// A built-in scene or a scene file (without `--mesh` files).
fn build_scene(args: &RenderArgs, sampler: Sampler, options: &LoadOptions) -> Result<Built, Error> {
    let name = args.scene.as_deref().unwrap_or("builtin:demo");
    let texture: Option<Arc<Texture2D>> = match &args.texture {
        Some(p) => {
            let cs = match args.color_space {
                ColorSpaceArg::Srgb => ColorSpace::Srgb,
                ColorSpaceArg::Linear => ColorSpace::Linear,
            };
            Some(Arc::new(load_texture(p, cs, &Limits::default())?))
        }
        None => None,
    };
    let scene = match name {
        "builtin:demo" => builtin::demo(),
        "builtin:marble" => builtin::marble(),
        "builtin:plane" => builtin::plane(texture.clone(), args.uv_scale.unwrap_or(64.0), sampler),
        "builtin:sphere" => {
            if args.tris < 8 || args.tris > 50_000_000 {
                return Err(Error::parameter(format!(
                    "--tris {} is outside 8..50000000",
                    args.tris
                )));
            }
            builtin::sphere(args.tris, texture.clone(), sampler)
        }
        other if other.starts_with("builtin:") => {
            return Err(Error::parameter(format!(
                "{other}: unknown built-in scene (builtin:demo, builtin:plane, builtin:sphere, builtin:marble)"
            )))
        }
        other => {
            let (scene, volumes) = load_file(args, Path::new(other), texture, options)?;
            let short = Path::new(other)
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_else(|| "scene".into());
            return Ok(Built {
                scene,
                volumes,
                short,
                from_file: true,
            });
        }
    };
    Ok(Built {
        scene,
        volumes: Vec::new(),
        short: name.trim_start_matches("builtin:").to_string(),
        from_file: false,
    })
}

/// Loads a scene file, prints its warnings, and applies `--texture`, `--uv-scale` and
/// `--auto-camera`.
fn load_file(
    args: &RenderArgs,
    path: &Path,
    texture: Option<Arc<Texture2D>>,
    options: &LoadOptions,
) -> Result<(Scene, Vec<SceneVolume>), Error> {
    let loaded = texmap::scene::load(path, options)?;
    if !args.quiet {
        for w in &loaded.warnings {
            eprintln!("texmap: warning: {w}");
        }
    }
    let mut scene = loaded.scene;
    for m in &mut scene.materials {
        if let Some(t) = &texture {
            match &mut m.base_color_texture {
                Some(slot) => slot.texture = t.clone(),
                None => {
                    m.base_color_texture = Some(TextureSlot::new(t.clone(), Sampler::default()))
                }
            }
        }
        if let (Some(s), Some(slot)) = (args.uv_scale, &mut m.base_color_texture) {
            slot.uv_scale *= s;
        }
    }
    if args.auto_camera {
        scene.camera = None;
    }
    Ok((scene, loaded.volumes))
}

pub fn run(args: RenderArgs) -> Result<(), Error> {
    let setup_start = Instant::now();
    if args.frames == 0 {
        return Err(Error::parameter("--frames must be at least 1"));
    }
    if ![1, 2, 4, 8, 16].contains(&args.msaa) {
        return Err(Error::parameter(format!(
            "--msaa {} is not one of 1, 2, 4, 8, 16",
            args.msaa
        )));
    }
    if !(1..=8).contains(&args.ssaa) {
        return Err(Error::parameter(format!(
            "--ssaa {} is outside 1..8",
            args.ssaa
        )));
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads.unwrap_or(0))
        .build()
        .map_err(|e| Error::parameter(format!("--threads: {e}")))?;
    let mut sampler = Sampler::new(
        args.filter.unwrap_or(Filter::TRILINEAR),
        args.wrap.unwrap_or(Wrap::Repeat),
    );
    sampler.lod_bias = args.lod_bias;
    sampler.lod_rule = match args.lod_rule {
        LodRuleArg::Gl => LodRule::GlMax,
        LodRuleArg::Rss => LodRule::RootSumSquares,
    };
    let progress = crate::progress::Progress::new(args.frames, args.quiet);
    progress.message("loading");
    let Built {
        scene,
        volumes,
        short,
        from_file,
    } = pool.install(|| build(&args, sampler))?;
    let fov = args.fov.unwrap_or(60.0);
    // With volumes and no camera in the file: vtk_volume.py's camera over everything.
    let volume_camera = scene.camera.is_none() && !volumes.is_empty();
    let base = match scene.camera {
        Some(c) => c,
        None if volume_camera => crate::volume::default_camera(&scene, &volumes, &args.volume),
        None => scene.framing_camera(fov),
    };
    // --ortho, else --fov, else a file's camera (and the volume camera) keeps its projection.
    let projection = match (args.ortho, from_file, scene.camera) {
        (Some(Some(height)), ..) => CameraProjection::Orthographic {
            half_height: 0.5 * height,
        },
        // VTK's parallel scale: the bounding radius over --dolly.
        (Some(None), ..) if volume_camera => CameraProjection::Orthographic {
            half_height: crate::volume::bounding_radius(&scene, &volumes) / args.volume.dolly,
        },
        (Some(None), ..) => scene.framing_camera_orthographic().projection,
        (None, true, Some(c)) => {
            args.fov
                .map_or(c.projection, |fov_y_deg| CameraProjection::Perspective {
                    fov_y_deg,
                })
        }
        (None, ..) if volume_camera => {
            args.fov
                .map_or(base.projection, |fov_y_deg| CameraProjection::Perspective {
                    fov_y_deg,
                })
        }
        _ => CameraProjection::Perspective { fov_y_deg: fov },
    };
    let camera = Camera {
        eye: args.eye.unwrap_or(base.eye),
        target: args.target.unwrap_or(base.target),
        up: args.up.unwrap_or(base.up),
        projection,
        ..base
    };
    camera.validate()?;
    let camera = if volume_camera {
        crate::volume::enclose(camera, &scene, &volumes)
    } else {
        camera
    };
    // Per-volume structures (VTK builds its own in its first frame): outside the frame times.
    pool.install(|| {
        for v in &volumes {
            let _ = v.volume.bricks();
            if v.params.shade {
                let _ = v.volume.normals();
            }
        }
    });
    let settings = Settings {
        width: args.size.0,
        height: args.size.1,
        interpolation: match args.interp {
            InterpArg::Perspective => Interpolation::Perspective,
            InterpArg::Affine => Interpolation::Affine,
            InterpArg::Subdivide => Interpolation::Subdivide {
                max_error_px: args.subdivide_error,
            },
        },
        shading: match args.shading {
            ShadingArg::Flat => ShadingMode::Flat,
            ShadingArg::Gouraud => ShadingMode::Gouraud,
            ShadingArg::Phong => ShadingMode::Phong,
        },
        visibility: match args.visibility {
            VisibilityArg::Zbuffer => Visibility::ZBuffer,
            VisibilityArg::DepthSort => Visibility::DepthSort,
        },
        cull: match args.cull {
            CullArg::None => CullMode::None,
            CullArg::Back => CullMode::Back,
            CullArg::Front => CullMode::Front,
        },
        msaa: args.msaa,
        ssaa: args.ssaa,
        unlit: args.unlit,
        // Built-in plane and sphere already carry the sampler; elsewhere override only if asked.
        filter_override: if short == "demo" || from_file {
            args.filter
        } else {
            None
        },
        wrap_override: if short == "demo" || from_file {
            args.wrap
        } else {
            None
        },
    };
    let output = args
        .output
        .clone()
        .unwrap_or_else(|| PathBuf::from(format!("texmap-{short}.png")));
    let per_frame = output.to_string_lossy().contains("{frame}");
    let setup_ms = setup_start.elapsed().as_secs_f64() * 1e3;

    let mut times = Vec::with_capacity(args.frames as usize);
    // One frame buffer for the whole sequence.
    let mut frame = Frame {
        width: 0,
        height: 0,
        color: Vec::new(),
        stats: FrameStats::default(),
    };
    progress.message("rendering");
    for k in 1..=args.frames {
        let angle = std::f32::consts::TAU * k as f32 / args.frames as f32;
        let cam = if k == args.frames {
            camera
        } else {
            camera.orbit(angle)
        };
        let start = Instant::now();
        pool.install(|| {
            if volumes.is_empty() {
                render_into(&scene, &cam, &settings, &mut frame)
            } else {
                frame = render_with_volumes(&scene, &volumes, &cam, &settings)?;
                Ok(())
            }
        })?;
        times.push(start.elapsed().as_secs_f64() * 1e3);
        if per_frame {
            let path = PathBuf::from(
                output
                    .to_string_lossy()
                    .replace("{frame}", &format!("{k:04}")),
            );
            crate::output::write_png_rgb8(&path, frame.width, frame.height, &frame.to_srgb8())?;
        }
        progress.tick();
    }
    progress.finish();
    if times.is_empty() {
        return Err(Error::parameter("no frame rendered"));
    }
    if !per_frame {
        crate::output::write_png_rgb8(&output, frame.width, frame.height, &frame.to_srgb8())?;
    }
    let mut sorted = times.clone();
    sorted.sort_by(f64::total_cmp);
    let median = if sorted.len() % 2 == 1 {
        sorted[sorted.len() / 2]
    } else {
        0.5 * (sorted[sorted.len() / 2 - 1] + sorted[sorted.len() / 2])
    };
    if args.stats {
        let s = &frame.stats;
        let mut json = serde_json::json!({
            "scene": args.scene.as_deref().unwrap_or("builtin:demo"),
            "size": [frame.width, frame.height],
            "threads": pool.current_num_threads(),
            "filter": args.filter.map(|f| format!("{f:?}")),
            "frames": args.frames,
            "setup_ms": round2(setup_ms),
            "frame_ms": {"min": round2(sorted[0]), "median": round2(median), "max": round2(sorted[sorted.len() - 1])},
            "frame_ms_all": times.iter().map(|&t| round2(t)).collect::<Vec<_>>(),
            "triangles_submitted": s.triangles_submitted,
            "triangles_after_clip": s.triangles_after_clip,
            "pixels_shaded": s.pixels_shaded,
            "texture_samples": s.texture_samples,
            "output": output,
        });
        if !volumes.is_empty() {
            json["volumes"] = crate::volume::stats_json(&volumes);
            json["camera"] = serde_json::json!({
                "eye": camera.eye.to_array(), "target": camera.target.to_array(),
                "up": camera.up.to_array(), "fov_y_deg": camera.projection.fov_y_deg(),
                "ortho_height": match camera.projection {
                    CameraProjection::Orthographic { half_height } => Some(2.0 * half_height),
                    CameraProjection::Perspective { .. } => None,
                },
            });
        }
        println!("{json}");
    } else if !args.quiet {
        eprintln!(
            "wrote {} ({}x{}, {} frame{}, median {:.1} ms/frame)",
            output.display(),
            frame.width,
            frame.height,
            args.frames,
            if args.frames == 1 { "" } else { "s" },
            median
        );
    }
    Ok(())
}

fn round2(v: f64) -> f64 {
    (v * 100.0).round() / 100.0
}

#[cfg(test)]
mod tests {
    use clap::{Args, Command};

    use super::*;

    fn command() -> Command {
        RenderArgs::augment_args(Command::new("render"))
    }

    #[test]
    fn filter_and_wrap_help_is_the_library_list() {
        let cmd = command();
        let help = |id: &str| {
            let arg = cmd.get_arguments().find(|a| a.get_id() == id);
            arg.and_then(|a| a.get_help()).map(|h| h.to_string())
        };
        assert_eq!(help("filter").as_deref(), Some(Filter::SPELLINGS));
        assert_eq!(help("wrap").as_deref(), Some(Wrap::SPELLINGS));
    }

    #[test]
    fn unknown_filter_and_wrap_names_are_refused_with_the_list() {
        let refused = |args: &[&str]| {
            let e = command().try_get_matches_from(args).unwrap_err();
            e.to_string()
        };
        let e = refused(&["render", "--filter", "aniso32"]);
        assert!(e.contains(Filter::SPELLINGS), "{e}");
        let e = refused(&["render", "--wrap", "tile"]);
        assert!(e.contains(Wrap::SPELLINGS), "{e}");
    }

    #[test]
    fn mipmapped_filter_names_reach_the_sampler() {
        let m = command()
            .try_get_matches_from(["render", "--filter", "nearest-mipmap-linear"])
            .unwrap();
        assert_eq!(
            m.get_one::<Filter>("filter").map(|f| f.name()).as_deref(),
            Some("nearest-mipmap-linear")
        );
    }
}
