//! Render one frame: `(scene, camera, settings) → Frame`.
//!
//! The frame driver ([`render_into`]) orders the meshes (opaque, then blended back to front),
//! compiles each into a draw (`draw.rs`: lighting path, `varyings.rs` layout, texture reads
//! with the user's [`TextureOverrides`]), hands the draws to the [`crate::pipeline`]
//! with the scene's vertex and fragment shaders (`vertex.rs`, `fragment.rs`, reading through
//! `maps.rs`, `surface.rs` and `procedural.rs`), and box-filters supersampled frames.
//! Surfaces with volumes are composed by [`render_with_volumes`]; a camera is chosen by
//! [`framing::choose_camera`].
//!
//! Where each material channel is read:
//!
//! | channel | Phong shading (per pixel) | Gouraud, flat |
//! |---|---|---|
//! | base colour, vertex colour, solid/projected colour, alpha | per pixel | per pixel |
//! | lighting (either model) | per pixel | per vertex / per face, material factors only |
//! | normal map, bump map, solid bump | per pixel | not read |
//! | metallic-roughness map, solid roughness | per pixel | not read |
//! | occlusion | per pixel, in the ambient term | per pixel, scales the ambient part of D |
//! | emissive map | per pixel | per pixel |
//!
//! Culling: `Settings::cull` applies to single-sided materials; double-sided ones are never
//! culled, and their back faces are lit with the flipped normal: per pixel in Phong shading,
//! per face in flat shading, and in Gouraud shading per vertex for both sides (six more
//! varyings), the fragment stage taking the side the rasterizer says is facing.
//! A mesh without (or with a wrong number of) normals is shaded flat; Phong and Gouraud
//! need vertex normals.
//!
//! Blending: blended meshes are drawn after the opaque ones, back to front by the view depth
//! of their centroid, each in index order (`gl_render.py`'s rule); `Visibility::DepthSort`
//! sorts every triangle instead.

mod background;
mod behind;
mod draw;
mod environment;
mod field_shadow;
mod fragment;
pub mod framing;
mod layers;
mod maps;
mod mr_quad;
mod parallax;
mod procedural;
mod projectors;
mod reads;
mod settings;
mod shadow;
mod surface;
mod varyings;
mod vertex;
mod virtual_pages;
mod volumes;

use glam::{DVec3, Mat4, Vec3, Vec4};

use crate::camera::Camera;
pub use crate::frame::{Frame, FrameStats, VirtualPageStats};
use crate::pipeline::{self, DrawCall, Target};
pub use crate::pipeline::{CullMode, Interpolation};
use crate::scene::{Mesh, Scene};
use crate::shading::ibl::{Background, EnvLight};
use crate::shading::shadow::{LightShadow, ShadowMaps};
use crate::shading::{AlphaMode, Light, Lighting, ShadingModel};
use crate::{Error, Result};

use draw::DrawInfo;
pub use environment::prefilter_environment;
pub use field_shadow::shadow_maps_with_fields;
use fragment::SceneShader;
use projectors::{ProjectorRead, Projectors};
pub use settings::{Settings, ShadingMode, TextureOverrides, Visibility, MAX_SIZE};
pub use shadow::{shadow_map_bytes, shadow_maps, ShadowOverrides, MAX_SPOT_MAP_DEG};
use vertex::SceneVertices;
pub use volumes::{
    render_with_meshes, render_with_volumes, render_with_volumes_shadowed, surface_distances,
};

/// Renders `scene` seen by `camera`, in rayon's current thread pool.
///
/// The image does not depend on the number of threads.
///
/// ```
/// use texmap::render::{render, Settings};
/// use texmap::scene::builtin;
/// use texmap::texture::Sampler;
///
/// let scene = builtin::plane(None, 64.0, Sampler::default());
/// let settings = Settings::new(64, 36);
/// let frame = render(&scene, &scene.camera.unwrap(), &settings)?;
/// assert_eq!(frame.to_srgb8().len(), 64 * 36 * 3);
/// // The sky is the black background; the floor is lit.
/// assert_eq!(frame.color[0].truncate(), glam::Vec3::ZERO);
/// assert!(frame.color[64 * 35].x > 0.0);
/// # Ok::<(), texmap::Error>(())
/// ```
///
/// # Errors
/// [`Error::Parameter`] for invalid settings or camera (zero or absurd size, non-finite
/// camera, `near ≤ 0`, `far ≤ near`) or a mesh naming a material that does not exist.
pub fn render(scene: &Scene, camera: &Camera, settings: &Settings) -> Result<Frame> {
    let mut frame = Frame::default();
    render_into(scene, camera, settings, &mut frame)?;
    Ok(frame)
}

/// [`render`] into `frame`, reusing its colour buffer: a sequence of frames (a turntable)
/// does not pay for a fresh image each time. On error `frame` is left unchanged.
///
/// The shadow maps of the lights that cast are drawn first, every call
/// ([`render_into_with_shadows`] takes them made once).
///
/// # Errors
/// As [`render`], and bad shadow parameters ([`shadow_maps`]).
pub fn render_into(
    scene: &Scene,
    camera: &Camera,
    settings: &Settings,
    frame: &mut Frame,
) -> Result<()> {
    let shadows = shadow_maps(scene, settings)?;
    render_into_with_shadows(scene, camera, settings, &shadows, frame)
}

/// [`render_into`] with shadow maps made before by [`shadow_maps`] for this scene and these
/// settings: they do not depend on the camera, so a turntable makes them once.
///
/// # Errors
/// As [`render`]; [`Error::Parameter`] when `shadows` were made for other lights.
pub fn render_into_with_shadows(
    scene: &Scene,
    camera: &Camera,
    settings: &Settings,
    shadows: &ShadowMaps,
    frame: &mut Frame,
) -> Result<()> {
    settings.validate()?;
    camera.validate()?;
    let virtuals = scene.virtual_textures();
    if virtuals.is_empty() {
        return draw_frame(scene, camera, settings, shadows, frame);
    }
    // Virtual textures: a feedback pass says which pages the frame needs, the caches bring
    // them in, then the frame is drawn (virtual_pages.rs).
    let pages = virtual_pages::feedback(&virtuals, settings, |fb: &Settings| {
        let mut scratch = Frame::default();
        draw_frame(scene, camera, fb, shadows, &mut scratch)
    })?;
    draw_frame(scene, camera, settings, shadows, frame)?;
    frame.stats.virtual_pages = virtual_pages::with_fallbacks(&virtuals, pages);
    Ok(())
}

/// One frame drawn: [`render_into_with_shadows`] once the virtual textures are ready.
fn draw_frame(
    scene: &Scene,
    camera: &Camera,
    settings: &Settings,
    shadows: &ShadowMaps,
    frame: &mut Frame,
) -> Result<()> {
    settings.validate()?;
    camera.validate()?;
    if let Some(env) = &scene.environment {
        env.validate()?;
    }
    for (i, m) in scene.meshes.iter().enumerate() {
        if m.material >= scene.materials.len() {
            return Err(Error::parameter(format!(
                "mesh {i} uses material {} but the scene has {}",
                m.material,
                scene.materials.len()
            )));
        }
        if !m.world_from_object.is_finite() {
            return Err(Error::parameter(format!(
                "mesh {i} has a non-finite transform"
            )));
        }
    }
    let n = settings.ssaa;
    let (w, h) = (settings.width * n, settings.height * n);
    let aspect = settings.width as f32 / settings.height as f32;
    let clip_from_world = camera.clip_from_view(aspect) * camera.view_from_world();
    // Directions normalized once, not per pixel; lights that cannot shine are dropped.
    let lights: Vec<Light> = scene.lights.iter().filter_map(Light::normalized).collect();
    let all_shadows = shadows;
    let shadows = (!shadows.is_empty()).then_some(shadows);
    if let Some(maps) = shadows {
        let other = |(m, l): (&Option<LightShadow>, &Light)| {
            m.as_ref().is_some_and(|m| m.origin != shadow::origin(l))
        };
        if maps.lights.len() != lights.len() || maps.lights.iter().zip(&lights).any(other) {
            return Err(Error::parameter(
                "the shadow maps were made for other lights than the scene's",
            ));
        }
    }
    let lighting = Lighting {
        lights: &lights,
        ambient: scene.ambient_light,
        shadows,
    };
    let projector_maps = all_shadows.projectors.iter().any(Option::is_some);
    if projector_maps && all_shadows.projectors.len() != scene.projectors.len() {
        return Err(Error::parameter(
            "the shadow maps were made for other projectors than the scene's",
        ));
    }
    let projectors = Projectors {
        reads: scene
            .projectors
            .iter()
            .map(|p| ProjectorRead {
                projector: p,
                sampler: settings.textures.apply(p.slide.sampler),
                view: p.view(),
            })
            .collect(),
        shadows: projector_maps.then_some(all_shadows),
    };
    let has_projectors = !projectors.reads.is_empty();

    // Submission order: the pipeline draws opaque meshes, then blended ones, as submitted.
    let meshes: Vec<&Mesh> = match settings.visibility {
        Visibility::ZBuffer => blend_order(scene, camera.view_from_world()),
        // The painter's algorithm sorts every triangle itself.
        Visibility::DepthSort => scene.meshes.iter().collect(),
    };
    let viewer = camera.viewer();
    // The environment's prefiltered forms are made here, once per environment (cached).
    let env_light = scene.environment.as_ref().map(|env| {
        let (diffuse, specular, sheen) = environment::prefilters_needed(scene, settings);
        let mut light = EnvLight::new(env, diffuse, specular).with_sheen(sheen);
        light.sampler = settings.textures.apply(env.sampler);
        light
    });
    let draws: Vec<DrawInfo> = meshes
        .iter()
        .map(|&mesh| {
            let material = &scene.materials[mesh.material];
            DrawInfo::new(mesh, material, settings, &lighting, scene.uv_scale)
                .with_environment(env_light.as_ref(), settings, scene.uv_scale)
                .with_projectors(has_projectors)
                .with_uniform_lighting(mesh, &lighting)
        })
        .collect();
    let vertices: Vec<SceneVertices> = meshes
        .iter()
        .zip(&draws)
        .map(|(&mesh, draw)| SceneVertices::new(mesh, draw, clip_from_world, viewer, &lighting))
        .collect();
    let flat_indices: Vec<Option<Vec<u32>>> = vertices.iter().map(SceneVertices::indices).collect();
    let calls: Vec<DrawCall> = vertices
        .iter()
        .zip(meshes.iter().zip(&draws))
        .zip(&flat_indices)
        .map(|((vs, (mesh, draw)), flat)| DrawCall {
            vertices: vs,
            indices: flat.as_deref().unwrap_or(&mesh.indices),
            state: draw.state(settings),
        })
        .collect();
    let shader = SceneShader {
        draws: &draws,
        lighting,
        viewer,
        projectors: has_projectors.then_some(&projectors),
        behind: None,
    };
    let bg = match scene.environment.as_ref().map(|e| e.background) {
        Some(Background::Environment | Background::None) => Vec4::ZERO,
        Some(Background::Color) | None => scene.background,
    };
    // Laid under the frame at its sample rate (background.rs).
    let env_background = env_light
        .as_ref()
        .filter(|l| l.env.background == Background::Environment);
    let target = Target {
        width: w,
        height: h,
        samples: settings.msaa,
        clear_color: (bg.truncate() * bg.w).extend(bg.w),
        interpolation: settings.interpolation,
        depth_sort: settings.visibility == Visibility::DepthSort,
    };
    // Transmitting metallic-roughness surfaces see the frame's other surfaces (behind.rs).
    let (behind, behind_stats) = match scene_behind(&calls, &shader, &target, clip_from_world) {
        Some((b, st)) => (Some(b), Some(st)),
        None => (None, None),
    };
    let shader = SceneShader {
        behind: behind.as_ref(),
        ..shader
    };
    let st = if n == 1 {
        let st = pipeline::draw_into(&calls, &shader, &target, &mut frame.color);
        if let Some(l) = env_background {
            background::composite_environment(&mut frame.color, w as usize, h as usize, camera, l);
        }
        st
    } else {
        let (mut big, st) = pipeline::draw(&calls, &shader, &target);
        if let Some(l) = env_background {
            background::composite_environment(&mut big, w as usize, h as usize, camera, l);
        }
        frame.color = pipeline::downsample_box(
            big,
            settings.width as usize,
            settings.height as usize,
            n as usize,
        );
        st
    };
    frame.width = settings.width;
    frame.height = settings.height;
    frame.stats = FrameStats {
        triangles_submitted: st.triangles_submitted,
        triangles_after_clip: st.triangles_after_clip,
        // The pass drawing what transmitting surfaces see is shading work of this frame too
        // (its triangles are the frame's own, counted once).
        pixels_shaded: st.pixels_shaded + behind_stats.map_or(0, |b| b.pixels_shaded),
        texture_samples: st.texture_samples + behind_stats.map_or(0, |b| b.texture_samples),
        virtual_pages: VirtualPageStats::default(),
    };
    Ok(())
}

/// The frame drawn without its transmitting and blended draws onto a transparent target,
/// when a transmitting metallic-roughness draw will read it (behind.rs), with the pass's
/// statistics; else `None`.
fn scene_behind(
    calls: &[DrawCall],
    shader: &SceneShader,
    target: &Target,
    clip_from_world: Mat4,
) -> Option<(behind::SceneBehind, pipeline::DrawStats)> {
    let sees = |d: &DrawInfo| {
        d.model == ShadingModel::MetallicRoughness && d.env.as_ref().is_some_and(|e| e.refracts)
    };
    if !shader.draws.iter().any(sees) {
        return None;
    }
    let through = |d: &DrawInfo| {
        d.env.as_ref().is_some_and(|e| e.refracts) || d.material.alpha_mode == AlphaMode::Blend
    };
    let opaque: Vec<DrawCall> = calls
        .iter()
        .zip(shader.draws)
        .map(|(c, d)| DrawCall {
            vertices: c.vertices,
            indices: if through(d) { &[] } else { c.indices },
            state: c.state,
        })
        .collect();
    let target = Target {
        clear_color: Vec4::ZERO,
        ..*target
    };
    let mut color = crate::pixels::Pixels::default();
    let stats = pipeline::draw_into(&opaque, shader, &target, &mut color);
    let (w, h) = (target.width as usize, target.height as usize);
    Some((
        behind::SceneBehind::new(color, w, h, clip_from_world),
        stats,
    ))
}

/// The scene's meshes with the blended ones moved to the end and sorted back to front by the
/// view-space depth of their centroid (the mean of their world positions over the index list,
/// ties in scene order): the rule of `gl_render.py` and the Khronos sample viewer. Each mesh's
/// triangles are then drawn in index order, so a blended mesh that overlaps itself shows the
/// order it was modelled in, as on a GPU.
fn blend_order(scene: &Scene, view_from_world: Mat4) -> Vec<&Mesh> {
    let blended = |m: &Mesh| scene.materials[m.material].alpha_mode == AlphaMode::Blend;
    let mut order: Vec<&Mesh> = scene.meshes.iter().filter(|m| !blended(m)).collect();
    let mut back: Vec<(f32, &Mesh)> = scene
        .meshes
        .iter()
        .filter(|m| blended(m))
        .map(|m| {
            let c = m.world_from_object.transform_point3(centroid(m));
            (view_from_world.transform_point3(c).z, m)
        })
        .collect();
    // The camera looks down −z: ascending z is far to near. A stable sort keeps ties in order.
    back.sort_by(|a, b| a.0.total_cmp(&b.0));
    order.extend(back.into_iter().map(|(_, m)| m));
    order
}

/// The mean object-space position over a mesh's index list (each triangle's corners count
/// once per use; out-of-range indices are skipped; the origin for an empty mesh).
fn centroid(m: &Mesh) -> Vec3 {
    let (sum, n) = m
        .indices
        .iter()
        .filter_map(|&i| m.positions.get(i as usize))
        .fold((DVec3::ZERO, 0u64), |(s, n), p| (s + p.as_dvec3(), n + 1));
    if n == 0 {
        Vec3::ZERO
    } else {
        (sum / n as f64).as_vec3()
    }
}
