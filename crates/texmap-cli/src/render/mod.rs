//! `texmap render [SCENE]`: one frame or a turntable of a built-in scene, a scene file, or a
//! scan (with `--mesh` files inside it).
//!
//! The flags are `args.rs`; which flags apply to which scene, `checks.rs`; the bounds of a
//! render (memory, frames, threads), `limits.rs`; the image written (format, `--alpha`, the
//! background), `image_out.rs`.

mod args;
mod batch;
mod checks;
mod complete;
mod detail;
pub(crate) mod image_out;
pub(crate) mod limits;
mod naming;
pub(crate) mod plan;
pub(crate) mod relief;
mod shard;

pub use args::{parse_size, RenderArgs};
pub(crate) use args::{parse_storage, Switch};
use args::{ColorSpaceArg, CullArg, InterpArg, ShadingArg, ViewArg, VisibilityArg};

use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

use glam::Vec3;
use texmap::camera::CameraProjection;
use texmap::render::framing::{choose_camera, CameraRequest, ProjectionRequest, StandardView};
use texmap::render::{
    prefilter_environment, render_into_with_shadows, render_with_volumes_shadowed,
    shadow_map_bytes, shadow_maps, shadow_maps_with_fields, CullMode, Frame, Interpolation,
    Settings, ShadingMode, Visibility,
};
use texmap::scene::builtin::Builtin;
use texmap::scene::{Environment, LoadOptions, Scene};
use texmap::texture::load::{load_texture_with, Limits};
use texmap::texture::{
    load_environment, ColorSpace, EnvironmentMap, Filter, Texture2D, TextureOptions,
};
use texmap::volume::section::render_section;
use texmap::volume::{Method, SceneVolume};
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

/// One input made ready to render: its scene, camera, settings, shadow maps and the
/// environment's prefiltering, which every frame shares.
pub(crate) struct Prepared {
    pub(crate) scene: Scene,
    pub(crate) volumes: Vec<SceneVolume>,
    pub(crate) camera: texmap::camera::Camera,
    pub(crate) settings: Settings,
    shadow_maps: texmap::shading::shadow::ShadowMaps,
    shadow_ms: f64,
    prefilter_ms: Option<f64>,
    pub setup_ms: f64,
    /// `--still`: frames animate the hypertexture, the camera stays.
    still: bool,
    /// `--slice`: one plane of the scan drawn flat instead of the 3D view.
    pub(crate) section: Option<crate::section::Section>,
}

/// Loads `args.scene` and makes everything its frames share.
pub(crate) fn prepare(args: &RenderArgs, common: &Common) -> Result<Prepared, Error> {
    let setup_start = Instant::now();
    let pool = &common.pool;
    let Built {
        mut scene,
        mut volumes,
        ..
    } = pool.install(|| {
        let mut built = build(args, common.texture.clone())?;
        apply_environment(args, &mut built.scene, common.env_map.clone())?;
        detail::apply(args, &mut built.scene)?;
        checks::check_projectors(args, &built)?;
        if args.projectors == Some(Switch::Off) {
            built.scene.projectors.clear();
        }
        image_out::apply_background(args, &mut built.scene, !built.volumes.is_empty())?;
        checks::check_flags(args, &built)?;
        Ok::<_, Error>(built)
    })?;
    if let Some(texture) = &common.texture {
        if scene.set_base_color_texture(texture.clone()) == 0 {
            let name = args.scene.as_deref().unwrap_or("builtin:demo");
            return Err(Error::parameter(format!(
                "--texture: no material of {name} takes an image (their colours are procedural)"
            )));
        }
    }
    if let Some(s) = args.uv_scale {
        scene.uv_scale = s;
    }
    let name = args.scene.as_deref().unwrap_or("builtin:demo");
    relief::apply_maps(&args.relief, name, &mut scene)?;
    let virtual_bytes: u64 = scene
        .virtual_textures()
        .iter()
        .map(|(vt, _)| args.vt_budget.unwrap_or_else(|| vt.budget()))
        .sum();
    if virtual_bytes > common.max_memory {
        let mib = |b: u64| b >> 20;
        return Err(Error::parameter(format!(
            "the virtual textures' page caches take {} MiB, above --max-memory {} MiB",
            mib(virtual_bytes),
            mib(common.max_memory)
        )));
    }
    if let Some(bytes) = args.vt_budget {
        for (vt, _) in scene.virtual_textures() {
            pool.install(|| vt.set_budget(bytes))
                .map_err(|e| Error::parameter(format!("--vt-budget: {e}")))?;
        }
    }
    let section = {
        let v = &args.volume;
        let others: Vec<&str> = [
            ("--eye", args.eye.is_some()),
            ("--target", args.target.is_some()),
            ("--up", args.up.is_some()),
            ("--fov", args.fov.is_some()),
            ("--ortho", args.ortho.is_some()),
            ("--view", args.view.is_some()),
            ("--frames", args.frames > 1),
            ("--mode", v.mode.is_some()),
            ("--method", v.method.is_some()),
            ("--shade", v.shade.is_some()),
            ("--step", v.step.is_some()),
            ("--crop", v.crop.is_some()),
            ("--classification", v.classification.is_some()),
            ("--gradient-opacity", v.gradient_opacity.is_some()),
        ]
        .into_iter()
        .filter_map(|(f, g)| g.then_some(f))
        .collect();
        let name = args.scene.as_deref().unwrap_or("builtin:demo");
        args.section
            .resolve(name, &volumes, scene.meshes.len(), &others)?
    };
    let projection = match (args.ortho, args.fov) {
        (Some(height), _) => ProjectionRequest::Orthographic { height },
        (None, Some(fov_y_deg)) => ProjectionRequest::Perspective { fov_y_deg },
        (None, None) => ProjectionRequest::Keep,
    };
    let mut request = CameraRequest::default()
        .with_projection(projection)
        .with_auto(args.auto_camera)
        .with_volume_framing(args.volume.dolly, args.volume.azimuth)
        .with_aspect(args.size.0 as f32 / args.size.1 as f32);
    request.eye = args.eye;
    request.target = args.target;
    request.up = args.up;
    request.view = args.view.map(|v| match v {
        ViewArg::Front => StandardView::Front,
        ViewArg::Back => StandardView::Back,
        ViewArg::Left => StandardView::Left,
        ViewArg::Right => StandardView::Right,
        ViewArg::Top => StandardView::Top,
        ViewArg::Bottom => StandardView::Bottom,
        ViewArg::Iso => StandardView::Iso,
    });
    let camera = choose_camera(&scene, &volumes, &request).map_err(|e| camera_error(args, e))?;
    pool.install(|| relief::displace(&args.relief, name, &mut scene, &camera, args.size))?;
    // Per-volume structures (VTK builds its own in its first frame): outside the frame times.
    pool.install(|| {
        for v in &volumes {
            let _ = v.volume.bricks();
            if v.params.shade {
                let _ = v.volume.normals();
            }
        }
    });
    let mut settings = Settings::new(args.size.0, args.size.1)
        .with_interpolation(match args.interp.unwrap_or(InterpArg::Perspective) {
            InterpArg::Perspective => Interpolation::Perspective,
            InterpArg::Affine => Interpolation::Affine,
            InterpArg::Subdivide => Interpolation::Subdivide {
                max_error_px: args.subdivide_error.unwrap_or(0.5),
            },
        })
        .with_shading(match args.shading.unwrap_or(ShadingArg::Phong) {
            ShadingArg::Flat => ShadingMode::Flat,
            ShadingArg::Gouraud => ShadingMode::Gouraud,
            ShadingArg::Phong => ShadingMode::Phong,
        })
        .with_visibility(match args.visibility.unwrap_or(VisibilityArg::Zbuffer) {
            VisibilityArg::Zbuffer => Visibility::ZBuffer,
            VisibilityArg::DepthSort => Visibility::DepthSort,
        })
        .with_msaa(common.msaa)
        .with_ssaa(common.ssaa)
        .with_unlit(args.unlit)
        .with_textures(common.textures)
        // From `args`, not `common`: the viewer prepares the scene again with `--shadows`
        // switched (the same values as `common`'s for a render).
        .with_shadows(checks::shadow_overrides(args)?);
    if let Some(cull) = args.cull {
        settings = settings.with_cull(match cull {
            CullArg::None => CullMode::None,
            CullArg::Back => CullMode::Back,
            CullArg::Front => CullMode::Front,
        });
    }
    settings.validate()?;
    limits::check_shadow_maps(
        shadow_map_bytes(&scene, &settings),
        &match args.shadow_map_size {
            Some(n) => format!("--shadow-map-size {n}"),
            None => format!(
                "{}: shadow map_size {}",
                args.scene.as_deref().unwrap_or("builtin:demo"),
                scene.shadows.params.map_size
            ),
        },
        &common.frame_buffers,
        common.max_memory,
    )?;
    // The shadow maps do not depend on the camera: drawn once for the whole turntable (the
    // stats report their time apart from the frames').
    let shadow_start = Instant::now();
    if !settings.shadows.casters(&scene).is_empty() {
        // A distance field lit by its headlight could not be shadowed: with casting lights
        // it is lit by the scene's lights, as the meshes are.
        for v in &mut volumes {
            if matches!(v.method, Method::Surface | Method::Hypertexture)
                && v.params.lights.is_empty()
            {
                v.params.lights = scene.lights.clone();
            }
        }
    }
    let shadow_maps = pool.install(|| {
        if volumes.is_empty() {
            shadow_maps(&scene, &settings)
        } else {
            shadow_maps_with_fields(&scene, &volumes, &camera, &settings)
        }
    })?;
    let shadow_ms = shadow_start.elapsed().as_secs_f64() * 1e3;
    // The environment's prefiltering (once per environment): outside the frame times.
    let prefilter_start = Instant::now();
    let prefiltered = pool.install(|| prefilter_environment(&scene, &settings));
    let prefilter_ms = prefilter_start.elapsed().as_secs_f64() * 1e3;
    Ok(Prepared {
        scene,
        volumes,
        camera,
        settings,
        shadow_maps,
        shadow_ms,
        prefilter_ms: prefiltered.then_some(prefilter_ms),
        setup_ms: setup_start.elapsed().as_secs_f64() * 1e3,
        still: args.field.still,
        section,
    })
}

impl Prepared {
    /// Renders turntable frame `k` (1-based) of `n` into `frame`: the camera turned about
    /// its target by 360·(k−1)/n degrees, so frame 1 is the requested view.
    pub fn render(
        &self,
        pool: &rayon::ThreadPool,
        k: u32,
        n: u32,
        frame: &mut Frame,
    ) -> Result<(), Error> {
        let animated = crate::field::volumes_at(&self.volumes, k, n);
        let volumes = animated.as_deref().unwrap_or(&self.volumes);
        let cam = if k <= 1 || (self.still && animated.is_some()) {
            self.camera
        } else {
            self.camera
                .orbit(std::f32::consts::TAU * (k - 1) as f32 / n as f32)
        };
        self.render_view(pool, volumes, &cam, &self.settings, frame)
    }

    /// Renders `volumes` (the prepared ones, or a hypertexture's frame of them) and the
    /// scene from `cam` with `settings` into `frame`: [`Prepared::render`]'s frame, and the
    /// viewer's, whose camera and settings are the user's.
    pub(crate) fn render_view(
        &self,
        pool: &rayon::ThreadPool,
        volumes: &[SceneVolume],
        cam: &texmap::camera::Camera,
        settings: &Settings,
        frame: &mut Frame,
    ) -> Result<(), Error> {
        if let (Some(s), Some(v)) = (&self.section, self.volumes.first()) {
            *frame = pool.install(|| {
                render_section(
                    &v.volume,
                    s.axis,
                    s.index,
                    &s.look,
                    settings.width,
                    settings.height,
                )
            })?;
            return Ok(());
        }
        pool.install(|| {
            if volumes.is_empty() {
                render_into_with_shadows(&self.scene, cam, settings, &self.shadow_maps, frame)
            } else {
                // An animated field (a hypertexture's frame, not the prepared volumes)
                // changes its shadow: its maps are made again.
                let animated = !std::ptr::eq(volumes, self.volumes.as_slice());
                let remade = if animated && !self.shadow_maps.is_empty() {
                    Some(shadow_maps_with_fields(
                        &self.scene,
                        volumes,
                        cam,
                        settings,
                    )?)
                } else {
                    None
                };
                *frame = render_with_volumes_shadowed(
                    &self.scene,
                    volumes,
                    cam,
                    settings,
                    remade.as_ref().unwrap_or(&self.shadow_maps),
                )?;
                Ok(())
            }
        })
    }

    /// `--stats`' JSON for this input: `times` are its frames' ms, `frame` the last.
    pub(crate) fn stats(
        &self,
        args: &RenderArgs,
        common: &Common,
        times: &[f64],
        frame: &Frame,
        output: &Path,
    ) -> serde_json::Value {
        let (min, median, max) = spread(times);
        let s = &frame.stats;
        let mut json = serde_json::json!({
            "scene": args.scene.as_deref().unwrap_or("builtin:demo"),
            "size": [frame.width, frame.height],
            "threads": common.pool.current_num_threads(),
            "filter": args.filter.map(Filter::name),
            "frames": times.len(),
            "setup_ms": round2(self.setup_ms),
            "shadow_maps_ms": round2(self.shadow_ms),
            "shadow_maps": self.shadow_maps.lights.iter().flatten().count(),
            "frame_ms": {"min": round2(min), "median": round2(median), "max": round2(max)},
            "frame_ms_all": times.iter().map(|&t| round2(t)).collect::<Vec<_>>(),
            "triangles_submitted": s.triangles_submitted,
            "triangles_after_clip": s.triangles_after_clip,
            "pixels_shaded": s.pixels_shaded,
            "texture_samples": s.texture_samples,
            "output": output,
            "format": common.format.extension(),
        });
        if let Some(ms) = self.prefilter_ms {
            json["env_prefilter_ms"] = serde_json::json!(round2(ms));
        }
        let virtuals = self.scene.virtual_textures();
        if !virtuals.is_empty() {
            let v = &s.virtual_pages;
            let totals = virtuals
                .iter()
                .fold(texmap::render::VirtualPageStats::default(), |t, (vt, _)| {
                    t.plus(vt.totals())
                });
            json["virtual_texture"] = serde_json::json!({
                "budget_bytes": virtuals.iter().map(|(vt, _)| vt.budget()).sum::<u64>(),
                "slots": virtuals.iter().map(|(vt, _)| vt.slots().0).sum::<usize>(),
                "pages_requested": v.requested,
                "pages_loaded": v.loaded,
                "pages_evicted": v.evicted,
                "pages_over_budget": v.over_budget,
                "pages_resident": v.resident,
                "fallback_reads": v.fallback_reads,
                "all_frames": {
                    "pages_requested": totals.requested,
                    "pages_loaded": totals.loaded,
                    "pages_evicted": totals.evicted,
                    "pages_over_budget": totals.over_budget,
                },
            });
        }
        if let Some(kb) = limits::peak_rss_kib() {
            json["peak_rss_kib"] = serde_json::json!(kb);
        }
        if !self.volumes.is_empty() {
            let camera = self.camera;
            json["volumes"] = crate::volume::stats_json(&self.volumes);
            json["camera"] = serde_json::json!({
                "eye": camera.eye.to_array(), "target": camera.target.to_array(),
                "up": camera.up.to_array(), "fov_y_deg": camera.projection.fov_y_deg(),
                "ortho_height": match camera.projection {
                    CameraProjection::Orthographic { half_height } => Some(2.0 * half_height),
                    CameraProjection::Perspective { .. } => None,
                },
            });
        }
        json
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
