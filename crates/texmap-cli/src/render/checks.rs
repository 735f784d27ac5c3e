//! Which render flags apply to a scene: every flag acts on the scene it is given or is
//! refused here, with one line naming it (a flag that parses but changes nothing is a bug).
//! Texture flags need an image texture that reads the value (the LOD rule only matters to
//! OpenGL's mipmapped filters, bias and clamps also to anisotropic and EWA filters, the border
//! colour only to a border wrap); mesh flags need meshes, volume flags volumes, framing flags
//! the default camera of a scene with volumes, load flags a file; `--cull` a single-sided
//! material; shadow flags a lit scene with a light that casts (the PCSS light sizes, PCSS and a
//! light of their kind); environment flags an environment (`--ibl` a lit surface,
//! `--reflections` a material that reflects or refracts). `--background` is checked where
//! it is applied (`image_out.rs`: it also acts without an environment).

use texmap::render::{ShadowOverrides, TextureOverrides};
use texmap::scene::Light;
use texmap::shading::ibl::Background;
use texmap::shading::shadow::{ShadowFilter, MAX_SHADOW_MAP_SIZE};
use texmap::shading::{MapChannel, Procedural, ShadingModel};
use texmap::texture::{Filter, LodRule, MinFilter, Sampler, Wrap};
use texmap::Error;

use super::args::{InterpArg, LodRuleArg, RenderArgs, Switch};
use super::Built;

/// The user's sampler flags, laid over every texture read.
pub(super) fn texture_overrides(args: &RenderArgs) -> TextureOverrides {
    let mut o = TextureOverrides::default();
    o.filter = args.filter;
    o.wrap = args.wrap;
    o.lod_bias = args.lod_bias;
    o.lod_rule = args.lod_rule.map(|r| match r {
        LodRuleArg::Gl => LodRule::GlMax,
        LodRuleArg::Rss => LodRule::RootSumSquares,
    });
    o.min_lod = args.min_lod;
    o.max_lod = args.max_lod;
    // Given straight; the sampler holds it premultiplied.
    o.border = args.border.map(|b| (b.truncate() * b.w).extend(b.w));
    o
}

/// The user's shadow flags, each value checked with the flag's name.
pub(super) fn shadow_overrides(args: &RenderArgs) -> Result<ShadowOverrides, Error> {
    let mut o = ShadowOverrides::default();
    o.cast = args.shadows;
    if let Some(n) = args.shadow_map_size {
        if !(1..=MAX_SHADOW_MAP_SIZE).contains(&n) {
            return Err(Error::parameter(format!(
                "--shadow-map-size {n} is outside 1..={MAX_SHADOW_MAP_SIZE}"
            )));
        }
    }
    o.map_size = args.shadow_map_size;
    o.filter = args.shadow_filter;
    for (flag, v) in [
        ("--shadow-bias", args.shadow_bias),
        ("--shadow-slope-bias", args.shadow_slope_bias),
        ("--shadow-normal-offset", args.shadow_normal_offset),
        ("--shadow-light-radius", args.shadow_light_radius),
    ] {
        if let Some(v) = v {
            if !(v.is_finite() && v >= 0.0) {
                return Err(Error::parameter(format!(
                    "{flag} {v} must be finite and at least 0"
                )));
            }
        }
    }
    if let Some(a) = args.shadow_light_angle {
        if !(0.0..90.0).contains(&a) {
            return Err(Error::parameter(format!(
                "--shadow-light-angle {a} is outside [0, 90) degrees"
            )));
        }
    }
    o.bias = args.shadow_bias;
    o.slope_bias = args.shadow_slope_bias;
    o.normal_offset = args.shadow_normal_offset;
    o.light_angle = args.shadow_light_angle;
    o.light_radius = args.shadow_light_radius;
    Ok(o)
}

/// `--projectors` needs a scene with projectors and a lit surface for them to light.
pub(super) fn check_projectors(args: &RenderArgs, built: &Built) -> Result<(), Error> {
    if args.projectors.is_none() {
        return Ok(());
    }
    let name = args.scene.as_deref().unwrap_or("builtin:demo");
    let scene = &built.scene;
    if scene.projectors.is_empty() {
        return Err(Error::parameter(format!(
            "--projectors: {name} has no projectors (a TOML scene's [[projectors]])"
        )));
    }
    if args.unlit
        || !scene.meshes.iter().any(|m| {
            scene
                .materials
                .get(m.material)
                .is_some_and(|mat| !mat.unlit)
        })
    {
        return Err(Error::parameter(format!(
            "--projectors: {name} has no lit surface for the projectors to light"
        )));
    }
    Ok(())
}

/// Refuses shadow flags that cannot change `built`'s image: `--shadows` where nothing is lit,
/// there is no light or every light already casts, `--shadows=false` where none casts, the
/// map and filter flags where no light casts, and the PCSS light sizes without PCSS or a
/// casting light of their kind.
fn check_shadow_flags(args: &RenderArgs, built: &Built, name: &str) -> Result<(), Error> {
    let scene = &built.scene;
    let lit = !args.unlit
        && scene.meshes.iter().any(|m| {
            scene
                .materials
                .get(m.material)
                .is_some_and(|mat| !mat.unlit)
        });
    let own = ShadowOverrides::default().casters(scene);
    let own_projectors = ShadowOverrides::default().casting_projectors(scene);
    let projectors_on = args.projectors != Some(Switch::Off);
    let all_cast = own.len() == scene.lights.len()
        && (!projectors_on || own_projectors.len() == scene.projectors.len());
    let none_casts = own.is_empty() && (!projectors_on || own_projectors.is_empty());
    match args.shadows {
        Some(true) if !lit => {
            return Err(Error::parameter(format!(
                "--shadows: {name} is drawn unlit (no light to shadow)"
            )))
        }
        Some(true)
            if scene.lights.is_empty() && (!projectors_on || scene.projectors.is_empty()) =>
        {
            return Err(Error::parameter(format!("--shadows: {name} has no lights")))
        }
        Some(true) if all_cast => {
            return Err(Error::parameter(format!(
                "--shadows: every light of {name} already casts shadows"
            )))
        }
        Some(false) if none_casts => {
            return Err(Error::parameter(format!(
                "--shadows=false: no light of {name} casts shadows"
            )))
        }
        _ => {}
    }
    let overrides = shadow_overrides(args)?;
    let casters = overrides.casters(scene);
    let projector_casts = projectors_on && !overrides.casting_projectors(scene).is_empty();
    let params = shadow_parameter_flags(args);
    let given: Vec<&str> = params.iter().filter(|(_, g)| *g).map(|(f, _)| *f).collect();
    if given.is_empty() {
        return Ok(());
    }
    if (casters.is_empty() && !projector_casts) || !lit {
        return Err(Error::parameter(format!(
            "{}: no light of {name} casts shadows{}",
            given.join(", "),
            if lit {
                " (add --shadows)"
            } else {
                " (it is drawn unlit)"
            }
        )));
    }
    let filter = overrides.apply(scene.shadows.params).filter;
    let kinds: Vec<&Light> = casters
        .iter()
        .filter_map(|&i| scene.lights.get(i))
        .collect();
    let directional = kinds.iter().any(|l| matches!(l, Light::Directional { .. }));
    for (flag, given, kind_casts, kind) in [
        (
            "--shadow-light-angle",
            args.shadow_light_angle.is_some(),
            directional,
            "directional light of",
        ),
        (
            "--shadow-light-radius",
            args.shadow_light_radius.is_some(),
            projector_casts
                || kinds
                    .iter()
                    .any(|l| !matches!(l, Light::Directional { .. })),
            "point or spot light or projector of",
        ),
    ] {
        if !given {
            continue;
        }
        if filter != ShadowFilter::Pcss {
            return Err(Error::parameter(format!(
                "{flag}: the light's size is read by the pcss filter; {name} filters with {} \
                 (add --shadow-filter pcss)",
                filter.name()
            )));
        }
        if !kind_casts {
            return Err(Error::parameter(format!(
                "{flag}: no {kind} {name} casts shadows"
            )));
        }
    }
    Ok(())
}

/// The distinct filters of `filters`, by name.
fn describe(filters: &[Filter]) -> String {
    let mut names: Vec<String> = filters.iter().map(|f| f.name()).collect();
    names.sort();
    names.dedup();
    names.join(", ")
}

/// The environment flags: each needs an environment (the scene's or `--env`'s); `--ibl`
/// needs a lit mesh, `--reflections` a material that reflects or refracts.
fn check_environment_flags(args: &RenderArgs, built: &Built, name: &str) -> Result<(), Error> {
    let flags: Vec<&str> = [
        ("--env-rotate", args.env_rotate.is_some()),
        ("--env-intensity", args.env_intensity.is_some()),
        ("--ibl", args.ibl.is_some()),
        ("--reflections", args.reflections.is_some()),
    ]
    .iter()
    .filter(|(_, g)| *g)
    .map(|(f, _)| *f)
    .collect();
    let scene = &built.scene;
    if scene.environment.is_none() {
        if let Some(first) = flags.first() {
            return Err(Error::parameter(format!(
                "{first}: {name} has no environment (add --env FILE)"
            )));
        }
        return Ok(());
    }
    let materials = || {
        scene
            .meshes
            .iter()
            .filter_map(|m| scene.materials.get(m.material))
    };
    let lit = !args.unlit && materials().any(|m| !m.unlit);
    if args.ibl.is_some() && !lit {
        return Err(Error::parameter(format!(
            "--ibl: {name} has no lit surface for the environment to light"
        )));
    }
    let reflective = lit
        && materials().any(|m| {
            !m.unlit
                && (m.transmission > 0.0
                    || m.map(MapChannel::Transmission).is_some()
                    || (m.reflection > 0.0 && m.model == ShadingModel::Phong))
        });
    if args.reflections.is_some() && !reflective {
        return Err(Error::parameter(format!(
            "--reflections: no material of {name} reflects or refracts the environment \
             (reflection, transmission)"
        )));
    }
    Ok(())
}

/// Refuses every flag that would change nothing in this scene, naming it: texture flags on a
/// scene that reads no image texture, mesh flags on a scene without meshes, volume flags on a
/// scene without volumes, load flags on a built-in scene.
pub(super) fn check_flags(args: &RenderArgs, built: &Built) -> Result<(), Error> {
    let name = args.scene.as_deref().unwrap_or("builtin:demo");
    let given = |flags: &[(&'static str, bool)]| -> Vec<&'static str> {
        flags.iter().filter(|(_, g)| *g).map(|(f, _)| *f).collect()
    };
    let refuse = |flags: Vec<&str>, why: String| -> Result<(), Error> {
        match flags.first() {
            None => Ok(()),
            Some(_) => Err(Error::parameter(format!("{}: {why}", flags.join(", ")))),
        }
    };
    check_environment_flags(args, built, name)?;
    // The environment's background is supersampled like the surfaces.
    let env_background = built
        .scene
        .environment
        .as_ref()
        .is_some_and(|e| e.background == Background::Environment);
    if built.scene.meshes.is_empty() {
        refuse(
            given(
                &[
                    ("--texture", args.texture.is_some()),
                    ("--interp", args.interp.is_some()),
                    ("--subdivide-error", args.subdivide_error.is_some()),
                    ("--shading", args.shading.is_some()),
                    ("--visibility", args.visibility.is_some()),
                    ("--cull", args.cull.is_some()),
                    ("--msaa", args.msaa.is_some()),
                    ("--ssaa", args.ssaa.is_some() && !env_background),
                    ("--unlit", args.unlit),
                    ("--shadows", args.shadows.is_some()),
                ]
                .into_iter()
                .chain(shadow_parameter_flags(args))
                .collect::<Vec<_>>(),
            ),
            format!("{name} has no meshes to draw (these flags act on meshes)"),
        )?;
    }
    check_shadow_flags(args, built, name)?;
    // --texture gives the scene image textures, so sampler flags then act; the filter and
    // level-of-detail flags also act on the environment map's reads (its wrap is its own).
    let mut samplers = built.scene.texture_samplers();
    if samplers.is_empty() && args.texture.is_none() {
        refuse(
            given(&[
                ("--wrap", args.wrap.is_some()),
                ("--uv-scale", args.uv_scale.is_some()),
                ("--border", args.border.is_some()),
                ("--texture-storage", args.texture_storage.is_some()),
            ]),
            format!("{name} reads no image texture (its colours are procedural or constant)"),
        )?;
    }
    // 3D textures take OpenGL's filters only (a scene file refuses others for them): an
    // anisotropic, EWA or SAT --filter on a scene whose only image textures are 3D would
    // draw trilinear's image.
    let reads_3d = built
        .scene
        .meshes
        .iter()
        .filter_map(|m| built.scene.materials.get(m.material))
        .filter(|m| matches!(m.procedural, Some(Procedural::Texture3D { .. })))
        .count();
    let only_3d = reads_3d > 0
        && reads_3d == samplers.len()
        && built.scene.environment.is_none()
        && args.texture.is_none();
    if let (Some(filter), true) = (args.filter, only_3d) {
        refuse(
            given(&[("--filter", !matches!(filter, Filter::Gl { .. }))]),
            format!(
                "{name} reads only 3D textures, which take OpenGL's filters ({}); {} would \
                 read as trilinear",
                Filter::GL_SPELLINGS,
                filter.name()
            ),
        )?;
    }
    if let Some(env) = &built.scene.environment {
        samplers.push(env.sampler);
    }
    if samplers.is_empty() && args.texture.is_none() {
        refuse(
            given(&[
                ("--filter", args.filter.is_some()),
                ("--lod-rule", args.lod_rule.is_some()),
                ("--lod-bias", args.lod_bias.is_some()),
                ("--min-lod", args.min_lod.is_some()),
                ("--max-lod", args.max_lod.is_some()),
            ]),
            format!("{name} reads no image texture (its colours are procedural or constant)"),
        )?;
    }
    // The border colour is read only where a texture clamps to its border; a --texture slot
    // added to a material starts from the default sampler.
    let overrides = texture_overrides(args);
    let added = args.texture.as_ref().map(|_| Sampler::default());
    let border_read = samplers
        .iter()
        .copied()
        .chain(added)
        .map(|s| overrides.apply(s))
        .any(|s| [s.wrap_u, s.wrap_v, s.wrap_w].contains(&Wrap::ClampToBorder));
    refuse(
        given(&[("--border", args.border.is_some() && !border_read)]),
        format!("no texture of {name} clamps to its border (add --wrap border)"),
    )?;
    // Which sampler state the effective filters read: GL's mipmapped filters choose levels by
    // the LOD rule, and with anisotropic and EWA filters they read the bias and clamps; the
    // summed-area table and the unmipmapped GL filters read none of it.
    let filters: Vec<Filter> = samplers
        .iter()
        .copied()
        .chain(added)
        .map(|s| overrides.apply(s).filter)
        .collect();
    let gl_mip = |f: &Filter| matches!(f, Filter::Gl { min, .. } if !matches!(min, MinFilter::Nearest | MinFilter::Linear));
    let reads_lod = |f: &Filter| {
        gl_mip(f)
            || matches!(
                f,
                Filter::Anisotropic { .. } | Filter::Ewa { .. } | Filter::EwaExact { .. }
            )
    };
    if !filters.is_empty() && !filters.iter().any(gl_mip) {
        refuse(
            given(&[("--lod-rule", args.lod_rule.is_some())]),
            format!(
                "the LOD rule is read by OpenGL's mipmapped filters; {name} filters with {} \
                 (add --filter trilinear)",
                describe(&filters)
            ),
        )?;
    }
    if !filters.is_empty() && !filters.iter().any(reads_lod) {
        refuse(
            given(&[
                ("--lod-bias", args.lod_bias.is_some()),
                ("--min-lod", args.min_lod.is_some()),
                ("--max-lod", args.max_lod.is_some()),
            ]),
            format!(
                "levels of detail are read by mipmapped, anisotropic and EWA filters; {name} \
                 filters with {}",
                describe(&filters)
            ),
        )?;
    }
    let meshes = &built.scene.meshes;
    let single_sided = meshes.iter().any(|m| {
        built
            .scene
            .materials
            .get(m.material)
            .is_some_and(|mat| !mat.double_sided)
    });
    refuse(
        given(&[(
            "--cull",
            args.cull.is_some() && !single_sided && !meshes.is_empty(),
        )]),
        format!("every material of {name} is double-sided (never culled)"),
    )?;
    refuse(
        given(&[(
            "--color-space",
            args.color_space.is_some() && args.texture.is_none(),
        )]),
        "applies to the image given with --texture".into(),
    )?;
    let subdivide = matches!(args.interp, Some(InterpArg::Subdivide));
    refuse(
        given(&[(
            "--subdivide-error",
            args.subdivide_error.is_some() && !subdivide,
        )]),
        "applies with --interp subdivide".into(),
    )?;
    if built.builtin.is_some() && args.volume.meshes.is_empty() {
        refuse(
            given(&[
                ("--lenient", args.lenient),
                ("--allow-outside-paths", args.allow_outside_paths),
            ]),
            format!("{name} is built in: these flags apply to loading files"),
        )?;
        refuse(
            given(&[(
                "--texture-storage",
                args.texture_storage.is_some() && args.texture.is_none(),
            )]),
            format!("{name} is built in: its textures are made in code, held decoded"),
        )?;
    }
    if built.scene.virtual_textures().is_empty() {
        refuse(
            given(&[("--vt-budget", args.vt_budget.is_some())]),
            format!("{name} reads no virtual texture"),
        )?;
    }
    if built.volumes.is_empty() {
        refuse(
            args.volume.given_volume_flags(),
            format!("{name} has no volumes (these flags act on volumes)"),
        )?;
    }
    if args.view.is_some() {
        refuse(
            given(&[
                ("--eye", args.eye.is_some()),
                ("--target", args.target.is_some()),
                ("--auto-camera", args.auto_camera),
            ]),
            "--view places the camera itself (give one or the other)".to_string(),
        )?;
    }
    let framed_by_volumes = !built.volumes.is_empty()
        && args.view.is_none()
        && (built.scene.camera.is_none() || args.auto_camera);
    if !framed_by_volumes {
        refuse(
            args.volume.given_framing_flags(),
            format!(
                "{name}: --dolly and --azimuth move the default camera of a scene with volumes"
            ),
        )?;
    }
    Ok(())
}

/// The shadow parameter flags (all but `--shadows`), each with whether it was given.
fn shadow_parameter_flags(args: &RenderArgs) -> [(&'static str, bool); 7] {
    [
        ("--shadow-map-size", args.shadow_map_size.is_some()),
        ("--shadow-filter", args.shadow_filter.is_some()),
        ("--shadow-bias", args.shadow_bias.is_some()),
        ("--shadow-slope-bias", args.shadow_slope_bias.is_some()),
        (
            "--shadow-normal-offset",
            args.shadow_normal_offset.is_some(),
        ),
        ("--shadow-light-angle", args.shadow_light_angle.is_some()),
        ("--shadow-light-radius", args.shadow_light_radius.is_some()),
    ]
}
