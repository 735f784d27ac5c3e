//! One input made ready to render ([`prepare`]: its scene built, the camera chosen, the
//! settings, shadow maps and environment made once) and its frames drawn
//! ([`Prepared::render`], and [`Prepared::render_view`] for the viewer's camera and
//! settings): what `texmap render` and `texmap view` share.

use std::path::Path;
use std::time::Instant;

use texmap::camera::CameraProjection;
use texmap::render::framing::{choose_camera, CameraRequest, ProjectionRequest, StandardView};
use texmap::render::{
    prefilter_environment, render_into_with_shadows, render_with_volumes_shadowed,
    shadow_map_bytes, shadow_maps, shadow_maps_with_fields, CullMode, Frame, Interpolation,
    Settings, ShadingMode, Visibility,
};
use texmap::scene::Scene;
use texmap::texture::Filter;
use texmap::volume::section::render_section;
use texmap::volume::{Method, SceneVolume};
use texmap::Error;

use super::args::{CullArg, InterpArg, ShadingArg, Switch, ViewArg, VisibilityArg};
use super::{
    apply_environment, build, camera_error, checks, detail, image_out, limits, relief, round2,
    spread, Built, Common, RenderArgs,
};

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
    // A batch's next scene: what the scene before it freed goes back before this one loads.
    super::heap::release_free_memory();
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
    // The decoders' and mip builders' buffers are freed: give them back before the frames'.
    super::heap::release_free_memory();
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
    super::heap::release_free_memory();
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
        output: Option<&Path>,
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
            "format": output.map(|_| common.format.extension()),
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
