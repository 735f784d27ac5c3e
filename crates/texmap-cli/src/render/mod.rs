//! `texmap render [SCENE]`: one frame or a turntable of a built-in scene, a scene file, or a
//! scan (with `--mesh` files inside it).
//!
//! The flags are `args.rs`; which flags apply to which scene, `checks.rs`; the bounds of a
//! render (memory, frames, threads), `limits.rs`; the loads' freed memory handed back and
//! the largest blocks unmapped when freed, `heap.rs`; the image written (format, `--alpha`,
//! the background), `image_out.rs`.

mod args;
mod batch;
mod checks;
mod complete;
mod detail;
mod heap;
pub(crate) mod image_out;
pub(crate) mod limits;
mod naming;
pub(crate) mod plan;
mod prepare;
pub(crate) mod relief;
mod shard;

use args::ColorSpaceArg;
pub use args::{parse_size, RenderArgs};
pub(crate) use args::{parse_storage, Switch};
pub(crate) use heap::set_up_allocator;
pub(crate) use prepare::{prepare, Prepared};

use std::path::Path;
use std::sync::Arc;

use glam::Vec3;
use texmap::scene::builtin::Builtin;
use texmap::scene::{Environment, LoadOptions, Scene};
use texmap::texture::load::{load_texture_with, Limits};
use texmap::texture::{load_environment, ColorSpace, EnvironmentMap, Texture2D, TextureOptions};
use texmap::volume::SceneVolume;
use texmap::Error;

use crate::formats::OutputFormat;

/// What `render` draws.
struct Built {
    scene: Scene,
    volumes: Vec<SceneVolume>,
    /// The scene's light is the loader's default (the file has none).
    default_light: bool,
    /// A built-in scene (not read from a file).
    builtin: Option<Builtin>,
}

/// The scene, its volumes (a volume file's, or a TOML scene's with the volume flags laid
/// over them), and `--mesh` files added.
fn build(args: &RenderArgs, texture: Option<Arc<Texture2D>>) -> Result<Built, Error> {
    let mut options = LoadOptions::default()
        .allow_outside_paths(args.allow_outside_paths)
        .lenient(args.lenient)
        .variant(args.variant.clone())
        // --env replaces the scene's environment map: its own is not read.
        .environment_image(args.env.is_none())
        .texture_storage(args.texture_storage.unwrap_or_default());
    if let Some(bytes) = args.max_memory {
        options = options.max_memory(bytes);
    }
    let v = &args.volume;
    let volume_file = args
        .scene
        .as_deref()
        .filter(|s| crate::volume::is_volume_path(s));
    v.check_for_scene(volume_file.is_some())?;
    let mut built = match volume_file {
        Some(path) => {
            let path = Path::new(path);
            let (scene, sv) = match args.field.surface {
                Some(t) => (
                    Scene::default(),
                    args.field.scan_surface(
                        path,
                        t,
                        args.max_memory.unwrap_or(texmap::files::DEFAULT_MAX_BYTES),
                        v.ignore_orientation,
                    )?,
                ),
                None => crate::volume::volume_file_scene(v, path, &options)?,
            };
            Built {
                scene,
                volumes: vec![sv],
                default_light: false,
                builtin: None,
            }
        }
        None => {
            if let Some(t) = args.field.surface {
                return Err(Error::parameter(format!(
                    "--surface {t}: a threshold applies to a scan (.nii, .nii.gz, .nrrd, \
                     .nhdr); a mesh takes --solid, --bump or --hypertexture alone"
                )));
            }
            let mut built = build_scene(args, &options, texture)?;
            if args.field.wants_field() && built.volumes.is_empty() && built.builtin.is_none() {
                // A mesh drawn as its distance field.
                let path = Path::new(args.scene.as_deref().unwrap_or_default());
                let mut sv = args.field.mesh_surface(
                    &mut built.scene,
                    path,
                    args.max_memory.unwrap_or(texmap::files::DEFAULT_MAX_BYTES),
                )?;
                if !built.default_light {
                    sv.params.lights = built.scene.lights.clone();
                }
                built.volumes.push(sv);
            }
            built
        }
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
    // An environment alone draws its background (scenes/reference/env.toml).
    let environment = built.scene.environment.is_some() || args.env.is_some();
    if built.scene.triangle_count() == 0 && built.volumes.is_empty() && !environment {
        let name = args.scene.as_deref().unwrap_or("builtin:demo");
        return Err(Error::parameter(format!(
            "{name}: nothing to draw (no triangles, no volumes and no environment)"
        )));
    }
    if built.volumes.is_empty() && !environment && !built.scene.any_triangle_has_area() {
        let name = args.scene.as_deref().unwrap_or("builtin:demo");
        return Err(Error::parameter(format!(
            "{name}: nothing to draw (every triangle has zero area)"
        )));
    }
    for sv in &mut built.volumes {
        args.field.preset_hypertexture(sv);
        v.apply(sv)
            .and_then(|()| args.field.apply(sv))
            .map_err(|e| match e {
                Error::Parameter(m) | Error::Unsupported(m) => {
                    Error::parameter(format!("{}: {m}", sv.source.display()))
                }
                other => other,
            })?;
        if let Some(w) = sv.transfer_warning().filter(|_| !args.quiet) {
            crate::output::stderr_line(&format!("texmap: warning: {}: {w}", sv.source.display()));
        }
    }
    let fields = built.volumes.iter().any(|v| v.method.is_distance_field());
    let name = args.scene.as_deref().unwrap_or("builtin:demo");
    if !fields {
        let mut given = args.field.given_look_flags();
        if args.field.sdf_res.is_some() {
            given.push("--sdf-res");
        }
        if !given.is_empty() {
            return Err(Error::parameter(format!(
                "{}: {name} has no distance field to draw (a mesh file, a scan with --surface \
                 T, or a field with --method surface)",
                given.join(", ")
            )));
        }
    }
    if args.field.sdf_res.is_some() && (volume_file.is_some() || !args.field.wants_field()) {
        return Err(Error::parameter(
            "--sdf-res: the resolution of a mesh's distance field (with --solid, --bump or \
             --hypertexture on a mesh file)",
        ));
    }
    if args.field.still && (args.frames <= 1 || !built.volumes.iter().any(crate::field::animated)) {
        return Err(Error::parameter(
            "--still keeps the camera while --frames animate a hypertexture (fire, smoke, melt)",
        ));
    }
    Ok(built)
}

/// A built-in scene or a scene file (without `--mesh` files).
fn build_scene(
    args: &RenderArgs,
    options: &LoadOptions,
    texture: Option<Arc<Texture2D>>,
) -> Result<Built, Error> {
    let name = args.scene.as_deref().unwrap_or("builtin:demo");
    let no_variants = |what: &str| {
        Error::parameter(format!(
            "{name}: --variant names a glTF material variant (KHR_materials_variants); {what}"
        ))
    };
    if let Some(builtin) = Builtin::parse(name)? {
        if args.variant.is_some() {
            return Err(no_variants("a built-in scene has none"));
        }
        let scene = builtin.build(args.tris, texture).map_err(|e| match e {
            Error::Parameter(m) => Error::parameter(format!("--tris: {m}")),
            other => other,
        })?;
        return Ok(Built {
            scene,
            volumes: Vec::new(),
            default_light: false,
            builtin: Some(builtin),
        });
    }
    if args.tris.is_some() {
        return Err(Error::parameter(
            "--tris applies to builtin:sphere, not a scene file",
        ));
    }
    let path = Path::new(name);
    let loaded = texmap::scene::load(path, options)?;
    if args.variant.is_some() && loaded.info.variant.is_none() {
        // A glTF file refuses an unknown name itself; an OBJ, or a TOML scene without a
        // glTF mesh, has nothing the flag could choose.
        return Err(no_variants("the scene holds no glTF file with variants"));
    }
    if !args.quiet {
        for w in &loaded.warnings {
            crate::output::stderr_line(&format!("texmap: warning: {w}"));
        }
    }
    Ok(Built {
        scene: loaded.scene,
        volumes: loaded.volumes,
        default_light: loaded.info.default_light,
        builtin: None,
    })
}

/// `texmap render`: the plan, then every input of this shard (see `batch.rs`).
pub fn run(args: RenderArgs) -> Result<std::process::ExitCode, Error> {
    batch::run(args)
}

/// What every input of a batch shares: checked flags, the thread pool, `--texture` and
/// `--env`, read once.
pub(crate) struct Common {
    pub pool: rayon::ThreadPool,
    pub format: OutputFormat,
    msaa: u32,
    ssaa: u32,
    max_memory: u64,
    frame_buffers: limits::FrameBuffers,
    textures: texmap::render::TextureOverrides,
    texture: Option<Arc<Texture2D>>,
    env_map: Option<EnvironmentMap>,
}

/// The flags every input shares, checked, before anything is loaded.
fn check_common(args: &RenderArgs) -> Result<(), Error> {
    if let Some(s) = args.uv_scale {
        if !(s.is_finite() && s != 0.0) {
            return Err(Error::parameter(format!(
                "--uv-scale {s} must be finite and non-zero"
            )));
        }
    }
    Ok(())
}

impl Common {
    /// The shared flags checked and the shared files read (`format` is the plan's,
    /// `threads` from [`limits::frames_and_threads`]).
    pub(crate) fn new(
        args: &RenderArgs,
        format: OutputFormat,
        threads: usize,
    ) -> Result<Common, Error> {
        let max_memory = args.max_memory.unwrap_or(texmap::files::DEFAULT_MAX_BYTES);
        let msaa = args.msaa.unwrap_or(1);
        if ![1, 2, 4, 8, 16].contains(&msaa) {
            return Err(Error::parameter(format!(
                "--msaa {msaa} is not one of 1, 2, 4, 8, 16"
            )));
        }
        let ssaa = args.ssaa.unwrap_or(1);
        if !(1..=8).contains(&ssaa) {
            return Err(Error::parameter(format!("--ssaa {ssaa} is outside 1..8")));
        }
        // Checked before anything is loaded; `prepare` lays them over the scene.
        checks::shadow_overrides(args)?;
        let textures = checks::texture_overrides(args);
        textures.validate().map_err(|e| match e {
            Error::Parameter(m) => Error::parameter(format!("texture flags: {m}")),
            other => other,
        })?;
        check_common(args)?;
        let frame_buffers = limits::FrameBuffers {
            width: args.size.0,
            height: args.size.1,
            ssaa,
            output_bytes_per_pixel: format.buffer_bytes_per_pixel(),
        };
        limits::check_frame(&frame_buffers, max_memory)?;
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .map_err(|e| Error::parameter(format!("--threads: {e}")))?;
        // --texture is read first: the built-in plane and sphere are made with it (their
        // checker is then never built), every other scene takes it below.
        let texture = match &args.texture {
            Some(p) => {
                let cs = match args.color_space.unwrap_or(ColorSpaceArg::Srgb) {
                    ColorSpaceArg::Srgb => ColorSpace::Srgb,
                    ColorSpaceArg::Linear => ColorSpace::Linear,
                };
                let options = TextureOptions::default()
                    .with_storage(args.texture_storage.unwrap_or_default());
                Some(Arc::new(load_texture_with(
                    p,
                    cs,
                    &Limits::default(),
                    options,
                )?))
            }
            None => None,
        };
        // --env is read before the scene, so a bad file fails fast.
        let env_map = match &args.env {
            Some(p) => {
                let limits = match args.max_memory {
                    Some(bytes) => Limits::default().with_max_bytes(bytes),
                    None => Limits::default(),
                };
                Some(load_environment(p, None, &limits)?)
            }
            None => None,
        };
        Ok(Common {
            pool,
            format,
            msaa,
            ssaa,
            max_memory,
            frame_buffers,
            textures,
            texture,
            env_map,
        })
    }
}

/// Min, median and max of `times` (zeros when empty).
pub(crate) fn spread(times: &[f64]) -> (f64, f64, f64) {
    if times.is_empty() {
        return (0.0, 0.0, 0.0);
    }
    let mut sorted = times.to_vec();
    sorted.sort_by(f64::total_cmp);
    let n = sorted.len();
    let median = if n % 2 == 1 {
        sorted[n / 2]
    } else {
        0.5 * (sorted[n / 2 - 1] + sorted[n / 2])
    };
    (sorted[0], median, sorted[n - 1])
}

/// Lays `--env` (the map, replacing the scene's) and the environment flags over the scene's
/// environment (`--background` is `image_out::apply_background`). Flags that need one where there is none are left for `checks` to refuse.
fn apply_environment(
    args: &RenderArgs,
    scene: &mut Scene,
    map: Option<EnvironmentMap>,
) -> Result<(), Error> {
    if let Some(map) = map {
        let source = args.env.as_ref().map(|p| p.display().to_string());
        let source = source.unwrap_or_default();
        scene.environment = Some(match scene.environment.take() {
            Some(env) => env.with_map(map, source),
            None => Environment::new(map, source),
        });
    }
    let Some(env) = scene.environment.as_mut() else {
        return Ok(());
    };
    if let Some(deg) = args.env_rotate {
        if !deg.is_finite() {
            return Err(Error::parameter(format!(
                "--env-rotate {deg} is not finite"
            )));
        }
        env.rotation_deg = deg;
    }
    if let Some(k) = args.env_intensity {
        if !(k.is_finite() && k >= 0.0) {
            return Err(Error::parameter(format!(
                "--env-intensity {k} must be finite and ≥ 0"
            )));
        }
        env.intensity = k;
    }
    if let Some(s) = args.ibl {
        env.ibl = s == Switch::On;
    }
    if let Some(s) = args.reflections {
        env.reflections = s == Switch::On;
    }
    Ok(())
}

fn round2(v: f64) -> f64 {
    (v * 100.0).round() / 100.0
}

/// A camera error names where the camera came from: the scene file, and the camera flags
/// that changed it.
fn camera_error(args: &RenderArgs, e: Error) -> Error {
    let Error::Parameter(message) = e else {
        return e;
    };
    let scene = args.scene.as_deref().unwrap_or("builtin:demo");
    let flags: Vec<&str> = [
        ("--eye", args.eye.is_some()),
        ("--target", args.target.is_some()),
        ("--up", args.up.is_some()),
        ("--fov", args.fov.is_some()),
        ("--ortho", args.ortho.is_some()),
        ("--auto-camera", args.auto_camera),
        ("--view", args.view.is_some()),
    ]
    .into_iter()
    .filter_map(|(flag, given)| given.then_some(flag))
    .collect();
    if flags.is_empty() {
        Error::parameter(format!("{scene}: {message}"))
    } else {
        Error::parameter(format!("{scene} with {}: {message}", flags.join(" ")))
    }
}
