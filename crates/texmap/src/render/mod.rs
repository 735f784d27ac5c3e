//! Render one frame: `(scene, camera, settings) → Frame`.
//!
//! Wires the stages: the vertex shader here (object → world → clip, uv transform, per-vertex
//! or per-face lighting for Gouraud and flat shading), the [`pipeline`](crate::pipeline)
//! (clip, setup, bin, raster in parallel tiles, MSAA resolve), the fragment shader here
//! (texture through [`sample`] with the quad's derivatives, a per-pixel [`Surface`] from the
//! material's maps, Phong or metallic-roughness illumination from
//! [`shading`](crate::shading)), and the SSAA box filter.
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

// `!(x > y)` is deliberate: it is true for NaN, which must be rejected too.
#![allow(clippy::neg_cmp_op_on_partial_ord)]
// Hot loops index several parallel arrays with one counter.
#![allow(clippy::needless_range_loop)]

use glam::{Mat2, Mat3, Mat4, Vec2, Vec3, Vec4};
use rayon::prelude::*;

use crate::camera::Camera;
pub use crate::frame::{Frame, FrameStats};
use crate::geometry::Projection;
use crate::pipeline::{
    self, DrawCall, DrawState, FragmentShader, PostVertex, Quad, Target, Viewport, BATCH,
    MAX_VARYINGS,
};
pub use crate::pipeline::{CullMode, Interpolation};
use crate::scene::{Mesh, Scene};
use crate::shading::{
    bump, combine, illuminate, phong, shininess_from_roughness, AlphaMode, Light, Lighting,
    MapChannel, Material, Procedural, ShadingModel, SolidMap, Surface, TextureSlot, Viewer,
};
use crate::texture::{
    sample, sample_3d, sample_quad_lanes, sample_quads_lanes, Filter, Footprint, Footprint3,
    QuadCoords, Sampler, Texture2D, Wrap,
};
use crate::{Error, Result};

mod volumes;
pub use volumes::{render_with_meshes, render_with_volumes, surface_distances};

/// Where lighting is evaluated.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum ShadingMode {
    /// Once per triangle, at its centroid with the geometric normal.
    Flat,
    /// Per vertex, interpolated (the texture is still applied per pixel).
    Gouraud,
    /// Per pixel with the interpolated, renormalized normal.
    #[default]
    Phong,
}

/// How hidden surfaces are removed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Visibility {
    /// A per-sample `f32` depth buffer (test `LESS`).
    #[default]
    ZBuffer,
    /// Painter's algorithm: triangles drawn back to front by their farthest vertex, no depth
    /// buffer (wrong where triangles intersect or overlap cyclically).
    DepthSort,
}

/// Everything about how a frame is made, apart from the scene and the camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    pub width: u32,
    pub height: u32,
    pub interpolation: Interpolation,
    pub shading: ShadingMode,
    pub visibility: Visibility,
    pub cull: CullMode,
    /// MSAA samples per pixel: 1, 2, 4, 8 or 16 (Direct3D's standard positions).
    pub msaa: u32,
    /// Supersampling: render at N× the size in each direction and box-filter (1..=8).
    pub ssaa: u32,
    /// Ignore lights: colour = base colour × texture × vertex colour.
    pub unlit: bool,
    /// Replaces every texture's filter.
    pub filter_override: Option<Filter>,
    /// Replaces every texture's wrap modes.
    pub wrap_override: Option<Wrap>,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            width: 640,
            height: 360,
            interpolation: Interpolation::Perspective,
            shading: ShadingMode::Phong,
            visibility: Visibility::ZBuffer,
            cull: CullMode::None,
            msaa: 1,
            ssaa: 1,
            unlit: false,
            filter_override: None,
            wrap_override: None,
        }
    }
}

/// The largest width or height accepted.
pub const MAX_SIZE: u32 = 16384;

impl Settings {
    /// Checks the values: size in 1..=16384, msaa ∈ {1, 2, 4, 8, 16}, ssaa in 1..=8 with the
    /// supersampled size ≤ 32768, a finite subdivision error ≥ 0.01 pixel.
    pub fn validate(&self) -> Result<()> {
        if self.width == 0 || self.height == 0 || self.width > MAX_SIZE || self.height > MAX_SIZE {
            return Err(Error::parameter(format!(
                "image size {}x{} is not within 1..={MAX_SIZE}",
                self.width, self.height
            )));
        }
        if !matches!(self.msaa, 1 | 2 | 4 | 8 | 16) {
            return Err(Error::parameter(format!(
                "msaa {} is not one of 1, 2, 4, 8, 16",
                self.msaa
            )));
        }
        if !(1..=8).contains(&self.ssaa) || self.width.max(self.height) * self.ssaa > 2 * MAX_SIZE {
            return Err(Error::parameter(format!(
                "ssaa {} is not within 1..=8 (or the supersampled image exceeds {} pixels)",
                self.ssaa,
                2 * MAX_SIZE
            )));
        }
        if let Interpolation::Subdivide { max_error_px } = self.interpolation {
            if !(max_error_px.is_finite() && max_error_px >= 0.01) {
                return Err(Error::parameter(format!(
                    "subdivision error {max_error_px} must be at least 0.01 pixel"
                )));
            }
        }
        Ok(())
    }
}

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
/// let settings = Settings { width: 64, height: 36, ..Default::default() };
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
/// # Errors
/// As [`render`].
pub fn render_into(
    scene: &Scene,
    camera: &Camera,
    settings: &Settings,
    frame: &mut Frame,
) -> Result<()> {
    settings.validate()?;
    camera.validate()?;
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
    let viewport = Viewport::new(w, h);
    // Directions normalized once, not per pixel; lights that cannot shine are dropped.
    let lights: Vec<Light> = scene.lights.iter().filter_map(Light::normalized).collect();
    let lighting = Lighting {
        lights: &lights,
        ambient: scene.ambient_light,
    };

    // Submission order: the pipeline draws opaque meshes, then blended ones, as submitted.
    let meshes: Vec<&Mesh> = match settings.visibility {
        Visibility::ZBuffer => blend_order(scene, camera.view_from_world()),
        // The painter's algorithm sorts every triangle itself.
        Visibility::DepthSort => scene.meshes.iter().collect(),
    };
    let mut draws = Vec::with_capacity(meshes.len());
    let mut buffers: Vec<(Vec<PostVertex>, Option<Vec<u32>>)> = Vec::with_capacity(meshes.len());
    for &mesh in &meshes {
        let material = &scene.materials[mesh.material];
        let draw = DrawInfo::new(mesh, material, settings, &lighting);
        let vs = VertexShader {
            mesh,
            material,
            draw: &draw,
            clip_from_world,
            normal_from_object: normal_matrix(mesh.world_from_object),
            viewer: camera.viewer(),
            lighting: &lighting,
            viewport: &viewport,
        };
        buffers.push(vs.run());
        draws.push(draw);
    }
    let calls: Vec<DrawCall> = buffers
        .iter()
        .zip(meshes.iter().zip(&draws))
        .map(|((verts, idx), (mesh, draw))| DrawCall {
            vertices: verts,
            indices: idx.as_deref().unwrap_or(&mesh.indices),
            state: draw.state(settings),
        })
        .collect();
    let shader = SceneShader {
        draws: &draws,
        directional_only: !lighting.needs_position(),
        lighting,
        viewer: camera.viewer(),
    };
    let bg = scene.background;
    let target = Target {
        width: w,
        height: h,
        samples: settings.msaa,
        clear_color: (bg.truncate() * bg.w).extend(bg.w),
        interpolation: settings.interpolation,
        depth_sort: settings.visibility == Visibility::DepthSort,
    };
    let st = if n == 1 {
        pipeline::draw_into(&calls, &shader, &target, &mut frame.color)
    } else {
        let (big, st) = pipeline::draw(&calls, &shader, &target);
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
        pixels_shaded: st.pixels_shaded,
        texture_samples: st.texture_samples,
    };
    Ok(())
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
        .fold((glam::DVec3::ZERO, 0u64), |(s, n), p| {
            (s + p.as_dvec3(), n + 1)
        });
    if n == 0 {
        Vec3::ZERO
    } else {
        (sum / n as f64).as_vec3()
    }
}

fn normal_matrix(m: Mat4) -> Mat3 {
    let m3 = Mat3::from_mat4(m);
    let det = m3.determinant();
    if det.abs() > f32::MIN_POSITIVE && det.is_finite() {
        m3.inverse().transpose()
    } else {
        m3
    }
}

/// What the fragment shader computes for a draw.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Mode {
    Unlit,
    /// Varyings: normal at 2, position at 5 (when lights, specular terms or bumps need it).
    Phong,
    /// Varyings: diffuse factor D at 2, additive S at 5 (Gouraud, or flat per face); for
    /// the back faces of double-sided Gouraud draws, the same at `DrawInfo::back_at`.
    Interpolated,
}

/// A texture the fragment stage reads: image, sampler (command-line overrides applied), the
/// slot's uv transform and scale folded into one affine map (computed once per draw, not per
/// quad), its uv set, and the map's scale (normal scale, occlusion strength).
#[derive(Clone, Copy)]
struct MapRead<'a> {
    tex: &'a Texture2D,
    sampler: Sampler,
    /// `uv' = linear·uv + offset` = `transform.apply(uv) · uv_scale`.
    linear: Mat2,
    offset: Vec2,
    /// Offset of the raw uv set in the varyings (0 for set 0).
    uv_at: usize,
    scale: f32,
}

impl MapRead<'_> {
    /// The quad's four reads. The transform is affine, so applying it per pixel to the raw,
    /// interpolated uv (and its linear part to the derivatives) equals applying it per vertex.
    fn quad(&self, quad: &Quad) -> [Vec4; 4] {
        let ((u, v), dx, dy) = self.coords(quad);
        sample_quad_lanes(self.tex, &self.sampler, (u, v), dx, dy, quad.mask)
    }

    /// [`MapRead::quad`] for several quads (`out[i]` for `quads[i]`), the reads staged by
    /// [`sample_quads_lanes`].
    fn quads(&self, quads: &[Quad], out: &mut [[Vec4; 4]]) {
        for (quads, out) in quads.chunks(BATCH).zip(out.chunks_mut(BATCH)) {
            let mut coords = [QuadCoords::default(); BATCH];
            let mut masks = [0u8; BATCH];
            for ((c, m), q) in coords.iter_mut().zip(masks.iter_mut()).zip(quads) {
                let ((u, v), duv_dx, duv_dy) = self.coords(q);
                *c = QuadCoords {
                    u,
                    v,
                    duv_dx,
                    duv_dy,
                };
                *m = q.mask;
            }
            let n = quads.len();
            sample_quads_lanes(self.tex, &self.sampler, &coords[..n], &masks[..n], out);
        }
    }

    /// The quad's transformed uvs (one lane per pixel) and their screen derivatives.
    #[inline]
    fn coords(&self, quad: &Quad) -> ((Vec4, Vec4), Vec2, Vec2) {
        let k = self.uv_at;
        let (m, offset) = (self.linear, self.offset);
        let (u, v) = (quad.varyings[k], quad.varyings[k + 1]);
        let uv = (
            u * m.x_axis.x + v * m.y_axis.x + offset.x,
            u * m.x_axis.y + v * m.y_axis.y + offset.y,
        );
        let dx = m * Vec2::new(quad.ddx(k), quad.ddx(k + 1));
        let dy = m * Vec2::new(quad.ddy(k), quad.ddy(k + 1));
        (uv, dx, dy)
    }

    /// A height map's screen derivatives `(∂h/∂x, ∂h/∂y)` per pixel, times `scale`: the red
    /// channel read at uv, one pixel footprint further along x (uv + ∂uv/∂x) and along y,
    /// each with the pixel's own footprint (three quad reads).
    fn height_slopes(&self, quad: &Quad) -> [Vec2; 4] {
        let ((u, v), dx, dy) = self.coords(quad);
        let read = |u: Vec4, v: Vec4| {
            sample_quad_lanes(self.tex, &self.sampler, (u, v), dx, dy, quad.mask)
        };
        let h = read(u, v);
        let hx = read(u + dx.x, v + dx.y);
        let hy = read(u + dy.x, v + dy.y);
        std::array::from_fn(|j| Vec2::new(hx[j].x - h[j].x, hy[j].x - h[j].x) * self.scale)
    }
}

/// A solid texture on the roughness or bump channel, resolved for a draw.
#[derive(Clone, Copy)]
struct SolidRead<'a> {
    map: &'a SolidMap,
    /// Roughness: value 0 and value 1.
    range: [f32; 2],
    /// Bump: object-space gradient of the value → world-space gradient of the height
    /// (normal matrix × the transform's mean scale × the bump scale).
    world_from_gradient: Mat3,
}

/// Per-draw shading data.
struct DrawInfo<'a> {
    material: &'a Material,
    mode: Mode,
    model: ShadingModel,
    /// The material's parameters without maps; each lit pixel starts from a copy.
    surface: Surface,
    /// Some map, solid texture or the metallic-roughness model changes the surface per pixel
    /// (or, in Gouraud and flat shading, an occlusion or emissive map adjusts the factors);
    /// false keeps the plain Lambert/Phong pixel free of their checks.
    surface_maps: bool,
    /// What occlusion removes from D in Gouraud and flat shading (per unit of 1 − O): the
    /// ambient part of D, K_A·I_AL (times 1 − metallic for metallic-roughness, whose Fresnel
    /// share of a few percent is left in).
    ambient_d: Vec3,
    flat: bool,
    /// Straight-alpha base colour, premultiplied.
    base: Vec4,
    texture: Option<MapRead<'a>>,
    /// Tangent-space normal map (Phong shading with mesh tangents only).
    normal_map: Option<MapRead<'a>>,
    /// Ambient occlusion: scales the ambient term by 1 + strength·(R − 1).
    occlusion_map: Option<MapRead<'a>>,
    /// Emissive colour map: multiplies the material's emissive factor.
    emissive_map: Option<MapRead<'a>>,
    /// Metallic (B) and roughness (G), multiplying the factors (metallic-roughness materials,
    /// Phong shading).
    metal_rough_map: Option<MapRead<'a>>,
    /// Height map (Phong shading); its scale includes the transform's mean scale, so heights
    /// are in object units.
    bump_map: Option<MapRead<'a>>,
    /// OBJ `map_Ka`, `map_Ks`, `map_Ns` (Phong shading): the ambient term's colour, the
    /// specular tint, and a factor on the exponent.
    ambient_map: Option<MapRead<'a>>,
    specular_map: Option<MapRead<'a>>,
    shininess_map: Option<MapRead<'a>>,
    /// OBJ `map_d`: opacity multiplying alpha (every mode), from the image's alpha channel
    /// when it has one, else from red (`alpha_from_w`).
    alpha_map: Option<MapRead<'a>>,
    alpha_from_w: bool,
    /// Solid textures on the roughness and bump channels (Phong shading).
    solid_roughness: Option<SolidRead<'a>>,
    solid_bump: Option<SolidRead<'a>>,
    /// Offset of the raw second uv set, when some texture reads it.
    uv1_at: Option<usize>,
    /// Offset of the world-space tangent and handedness (4 floats), for normal mapping.
    tangent_at: Option<usize>,
    /// Offset of the vertex colour in the varyings.
    color_at: Option<usize>,
    /// Offset of D and S lit with the flipped normal (double-sided Gouraud draws), read on
    /// back-facing triangles.
    back_at: Option<usize>,
    needs_position: bool,
    /// Offset of the object-space position and normal (6 floats) for solid textures and
    /// projections.
    object_at: Option<usize>,
    /// The projected texture's sampler, with the command line's overrides applied.
    projected: Option<MapRead<'a>>,
    /// The projection, with an unset bounding-sphere centre resolved to the mesh's box centre.
    projection: Option<Projection>,
    varyings: usize,
    mirrored: bool,
    /// An opaque draw whose colour is the base colour (times its texture) and whose lighting
    /// is the material's own, with no map, vertex colour or procedural texture: its quads take
    /// [`SceneShader::shade_plain`], the four pixels in lanes with no per-pixel branch.
    plain: bool,
}

impl<'a> DrawInfo<'a> {
    fn new(mesh: &Mesh, material: &'a Material, settings: &Settings, lighting: &Lighting) -> Self {
        let has_normals = !mesh.normals.is_empty() && mesh.normals.len() == mesh.positions.len();
        let mode = if settings.unlit || material.unlit {
            Mode::Unlit
        } else if settings.shading == ShadingMode::Phong && has_normals {
            Mode::Phong
        } else {
            Mode::Interpolated
        };
        let flat =
            mode == Mode::Interpolated && (settings.shading == ShadingMode::Flat || !has_normals);
        let model = material.model;
        let pbr = model == ShadingModel::MetallicRoughness;
        let per_pixel = mode == Mode::Phong;
        let has_bump = material.map(MapChannel::Bump).is_some();
        let needs_position =
            per_pixel && (material.specular > 0.0 || pbr || has_bump || lighting.needs_position());
        let mut varyings = 2;
        match mode {
            Mode::Unlit => {}
            Mode::Phong => varyings += if needs_position { 6 } else { 3 },
            Mode::Interpolated => varyings += 6,
        }
        let color_at =
            (!mesh.colors.is_empty() && mesh.colors.len() == mesh.positions.len()).then(|| {
                varyings += 4;
                varyings - 4
            });
        let back_at = (mode == Mode::Interpolated && !flat && material.double_sided).then(|| {
            varyings += 6;
            varyings - 6
        });
        let solid_maps = per_pixel && !material.solid_maps.is_empty();
        let object_at = (material.procedural.is_some() || solid_maps).then(|| {
            varyings += 6;
            varyings - 6
        });
        let has_uv1 = mesh.uvs1.len() == mesh.positions.len();
        let uses_set1 = material
            .base_color_texture
            .iter()
            .map(|t| t.tex_coord)
            .chain(material.maps.iter().map(|m| m.slot.tex_coord))
            .any(|c| c == 1);
        let uv1_at = (has_uv1 && uses_set1).then(|| {
            varyings += 2;
            varyings - 2
        });
        let has_tangents = mesh.tangents.len() == mesh.positions.len();
        let tangent_at =
            (mode == Mode::Phong && has_tangents && material.map(MapChannel::Normal).is_some())
                .then(|| {
                    varyings += 4;
                    varyings - 4
                });
        let overridden = |mut s: Sampler| {
            if let Some(f) = settings.filter_override {
                s.filter = f;
            }
            if let Some(wr) = settings.wrap_override {
                s.wrap_u = wr;
                s.wrap_v = wr;
                s.wrap_w = wr;
            }
            s
        };
        let read = |slot: &'a TextureSlot, scale: f32| MapRead {
            tex: &slot.texture,
            sampler: overridden(slot.sampler),
            linear: slot.transform.matrix() * slot.uv_scale,
            offset: slot.transform.offset * slot.uv_scale,
            // A texture on set 1 of a mesh without it reads set 0 (the peers read (0, 0)).
            uv_at: if slot.tex_coord == 1 {
                uv1_at.unwrap_or(0)
            } else {
                0
            },
            scale,
        };
        let texture = material
            .base_color_texture
            .as_ref()
            .map(|slot| read(slot, 1.0));
        let map = |c: MapChannel| material.map(c).map(|m| read(&m.slot, m.scale));
        let normal_map = tangent_at.and(map(MapChannel::Normal));
        let occlusion_map = if mode == Mode::Unlit {
            None
        } else {
            map(MapChannel::Occlusion)
        };
        let emissive_map = if mode == Mode::Unlit {
            None
        } else {
            map(MapChannel::Emissive)
        };
        let world_from_object = Mat3::from_mat4(mesh.world_from_object);
        // Heights are in object units: scaled by the transform's mean scale (exact for
        // similarity transforms).
        let mean_scale = world_from_object.determinant().abs().cbrt();
        let mean_scale = if mean_scale.is_finite() && mean_scale > 0.0 {
            mean_scale
        } else {
            1.0
        };
        let metal_rough_map = (per_pixel && pbr)
            .then(|| map(MapChannel::MetallicRoughness))
            .flatten();
        let phong_map = |c: MapChannel| (per_pixel && !pbr).then(|| map(c)).flatten();
        let (ambient_map, specular_map, shininess_map) = (
            phong_map(MapChannel::Ambient),
            phong_map(MapChannel::Specular),
            phong_map(MapChannel::Shininess),
        );
        let alpha_map = map(MapChannel::Alpha);
        let alpha_from_w = alpha_map.is_some_and(|m| m.tex.format().has_alpha());
        let bump_map = if per_pixel {
            material
                .map(MapChannel::Bump)
                .map(|m| read(&m.slot, m.scale * mean_scale))
        } else {
            None
        };
        let normal_from_object = normal_matrix(mesh.world_from_object);
        let solid_roughness =
            material
                .solid_roughness()
                .filter(|_| per_pixel)
                .map(|(map, range)| SolidRead {
                    map,
                    range,
                    world_from_gradient: Mat3::IDENTITY,
                });
        let solid_bump = material
            .solid_bump()
            .filter(|_| per_pixel)
            .map(|(map, scale)| SolidRead {
                map,
                range: [0.0, 1.0],
                world_from_gradient: normal_from_object * (mean_scale * scale),
            });
        let (projected, projection) = match &material.procedural {
            Some(Procedural::Projected { slot, projection }) => {
                let projection = match *projection {
                    Projection::BoundingSphere { center } if !center.is_finite() => {
                        Projection::BoundingSphere {
                            center: mesh.object_center(),
                        }
                    }
                    p => p,
                };
                (Some(read(slot, 1.0)), Some(projection))
            }
            _ => (None, None),
        };
        let b = material.base_color;
        let ambient_d = lighting.ambient
            * material.ambient
            * if pbr {
                1.0 - material.metallic.clamp(0.0, 1.0)
            } else {
                1.0
            };
        let surface_maps = occlusion_map.is_some()
            || emissive_map.is_some()
            || (per_pixel
                && (pbr
                    || ambient_map.is_some()
                    || specular_map.is_some()
                    || shininess_map.is_some()
                    || normal_map.is_some()
                    || bump_map.is_some()
                    || solid_roughness.is_some()
                    || solid_bump.is_some()));
        DrawInfo {
            material,
            mode,
            model,
            surface: Surface::new(material, Vec3::ZERO, Vec3::ZERO),
            surface_maps,
            ambient_d,
            flat,
            base: (b.truncate() * b.w).extend(b.w),
            texture,
            normal_map,
            occlusion_map,
            emissive_map,
            metal_rough_map,
            bump_map,
            ambient_map,
            specular_map,
            shininess_map,
            alpha_map,
            alpha_from_w,
            solid_roughness,
            solid_bump,
            uv1_at,
            tangent_at,
            color_at,
            back_at,
            needs_position,
            object_at,
            projected,
            projection,
            varyings,
            mirrored: Mat3::from_mat4(mesh.world_from_object).determinant() < 0.0,
            plain: !surface_maps
                && alpha_map.is_none()
                && color_at.is_none()
                && material.procedural.is_none()
                && material.alpha_mode == AlphaMode::Opaque
                && model == ShadingModel::Phong,
        }
    }

    fn state(&self, settings: &Settings) -> DrawState {
        let blend = self.material.alpha_mode == AlphaMode::Blend;
        let zbuffer = settings.visibility == Visibility::ZBuffer;
        DrawState {
            varyings: self.varyings,
            cull: if self.material.double_sided {
                CullMode::None
            } else {
                settings.cull
            },
            mirrored: self.mirrored,
            depth_test: zbuffer,
            depth_write: zbuffer && !blend,
            blend,
            texture_reads: u32::from(self.texture.is_some())
                + u32::from(self.normal_map.is_some())
                + u32::from(self.occlusion_map.is_some())
                + u32::from(self.emissive_map.is_some())
                + u32::from(self.metal_rough_map.is_some())
                + 3 * u32::from(self.bump_map.is_some())
                + u32::from(self.ambient_map.is_some())
                + u32::from(self.specular_map.is_some())
                + u32::from(self.shininess_map.is_some())
                + u32::from(self.alpha_map.is_some())
                + u32::from(self.projected.is_some()),
        }
    }
}

struct VertexShader<'a> {
    mesh: &'a Mesh,
    material: &'a Material,
    draw: &'a DrawInfo<'a>,
    clip_from_world: Mat4,
    normal_from_object: Mat3,
    viewer: Viewer,
    lighting: &'a Lighting<'a>,
    viewport: &'a Viewport,
}

impl VertexShader<'_> {
    /// Post-transform vertices, and for flat shading the (un-indexed) index list.
    fn run(&self) -> (Vec<PostVertex>, Option<Vec<u32>>) {
        let mesh = self.mesh;
        if self.draw.flat {
            let tris = mesh.indices.len() / 3;
            let verts: Vec<PostVertex> = (0..tris)
                .into_par_iter()
                .with_min_len(1024)
                .flat_map_iter(|t| self.flat_triangle(t))
                .collect();
            let idx = (0..verts.len() as u32).collect();
            return (verts, Some(idx));
        }
        let verts = (0..mesh.positions.len())
            .into_par_iter()
            .with_min_len(4096)
            .map(|i| {
                let p = self.world_position(i);
                let mut var = self.common_varyings(i);
                match self.draw.mode {
                    Mode::Unlit => {}
                    Mode::Phong => {
                        let n = self.world_normal(i);
                        var[2..5].copy_from_slice(&n.to_array());
                        if self.draw.needs_position {
                            var[5..8].copy_from_slice(&p.to_array());
                        }
                    }
                    Mode::Interpolated => {
                        let n = self.world_normal(i);
                        let surface = Surface::new(self.material, p, n);
                        let (d, s) =
                            illuminate(self.material.model, &surface, self.lighting, self.viewer);
                        var[2..5].copy_from_slice(&d.to_array());
                        var[5..8].copy_from_slice(&s.to_array());
                        if let Some(k) = self.draw.back_at {
                            let surface = Surface {
                                normal: -n,
                                ..surface
                            };
                            let (d, s) = illuminate(
                                self.material.model,
                                &surface,
                                self.lighting,
                                self.viewer,
                            );
                            var[k..k + 3].copy_from_slice(&d.to_array());
                            var[k + 3..k + 6].copy_from_slice(&s.to_array());
                        }
                    }
                }
                PostVertex::new(self.clip_from_world * p.extend(1.0), var, self.viewport)
            })
            .collect();
        (verts, None)
    }

    fn world_position(&self, i: usize) -> Vec3 {
        self.mesh
            .world_from_object
            .transform_point3(self.mesh.positions[i])
    }

    fn world_normal(&self, i: usize) -> Vec3 {
        (self.normal_from_object * self.mesh.normals[i]).normalize_or_zero()
    }

    /// uv (transformed and scaled) and the vertex colour.
    fn common_varyings(&self, i: usize) -> [f32; MAX_VARYINGS] {
        let mut var = [0.0; MAX_VARYINGS];
        // Raw uv sets: each texture applies its own transform per pixel.
        let uv = self.mesh.uvs.get(i).copied().unwrap_or(Vec2::ZERO);
        var[0] = uv.x;
        var[1] = uv.y;
        if let Some(c) = self.draw.color_at {
            var[c..c + 4].copy_from_slice(&self.mesh.colors[i].to_array());
        }
        if let Some(k) = self.draw.uv1_at {
            var[k..k + 2].copy_from_slice(&self.mesh.uvs1[i].to_array());
        }
        if let Some(k) = self.draw.tangent_at {
            let t = self.mesh.tangents[i];
            let world =
                (Mat3::from_mat4(self.mesh.world_from_object) * t.truncate()).normalize_or_zero();
            var[k..k + 3].copy_from_slice(&world.to_array());
            var[k + 3] = t.w;
        }
        if let Some(k) = self.draw.object_at {
            var[k..k + 3].copy_from_slice(&self.mesh.positions[i].to_array());
            let n = self.mesh.normals.get(i).copied().unwrap_or(Vec3::ZERO);
            var[k + 3..k + 6].copy_from_slice(&n.to_array());
        }
        var
    }

    /// The three vertices of triangle `t`, lit once at the centroid with the face normal.
    fn flat_triangle(&self, t: usize) -> [PostVertex; 3] {
        let idx = &self.mesh.indices[3 * t..3 * t + 3];
        let n_pos = self.mesh.positions.len();
        let valid = idx.iter().all(|&i| (i as usize) < n_pos);
        let ids = if valid {
            [idx[0], idx[1], idx[2]].map(|i| i as usize)
        } else {
            [0; 3]
        };
        let p = ids.map(|i| {
            if valid {
                self.world_position(i)
            } else {
                Vec3::NAN
            }
        });
        let mut n = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
        if self.draw.mirrored {
            n = -n;
        }
        if !self.mesh.normals.is_empty() && self.mesh.normals.len() == n_pos && valid {
            let avg = ids.iter().map(|&i| self.world_normal(i)).sum::<Vec3>();
            if avg.dot(n) < 0.0 {
                n = -n;
            }
        }
        let centroid = (p[0] + p[1] + p[2]) / 3.0;
        if self.material.double_sided && n.dot(self.viewer.towards(centroid)) < 0.0 {
            n = -n;
        }
        let surface = Surface::new(self.material, centroid, n);
        let (d, s) = illuminate(self.material.model, &surface, self.lighting, self.viewer);
        [0, 1, 2].map(|k| {
            let mut var = if valid {
                self.common_varyings(ids[k])
            } else {
                [0.0; MAX_VARYINGS]
            };
            var[2..5].copy_from_slice(&d.to_array());
            var[5..8].copy_from_slice(&s.to_array());
            PostVertex::new(self.clip_from_world * p[k].extend(1.0), var, self.viewport)
        })
    }
}

struct SceneShader<'a> {
    draws: &'a [DrawInfo<'a>],
    lighting: Lighting<'a>,
    viewer: Viewer,
    /// Every light is directional (every loader's default light): map-free Phong pixels are
    /// then lit a quad at a time ([`phong_quad`]).
    directional_only: bool,
}

impl FragmentShader for SceneShader<'_> {
    fn shade_batch(&self, draw: u32, quads: &[Quad], out: &mut [[Vec4; 4]], kept: &mut [u8]) {
        let d = &self.draws[draw as usize];
        match d.texture.as_ref().filter(|_| self.is_plain(d)) {
            // Plain textured quads: all the texture reads first (staged across quads).
            Some(t) => {
                // The lighting of every quad, then every texture read, then the colours.
                for ((quads, out), kept) in quads
                    .chunks(BATCH)
                    .zip(out.chunks_mut(BATCH))
                    .zip(kept.chunks_mut(BATCH))
                {
                    let mut factors = [([Vec4::ZERO; 4], [Vec4::ZERO; 4]); BATCH];
                    for (f, quad) in factors.iter_mut().zip(quads) {
                        *f = self.plain_factors(d, quad);
                    }
                    t.quads(quads, out);
                    for (((quad, o), k), (df, sp)) in quads
                        .iter()
                        .zip(out.iter_mut())
                        .zip(kept.iter_mut())
                        .zip(&factors)
                    {
                        let texels = *o;
                        plain_colors(d, df, sp, Some(&texels), o);
                        *k = quad.mask;
                    }
                }
            }
            None if self.is_plain(d) => {
                for ((quad, o), k) in quads.iter().zip(out.iter_mut()).zip(kept.iter_mut()) {
                    *k = self.shade(draw, quad, o);
                }
            }
            // Every texture read of the batch first, map by map, then each quad's colours.
            None => {
                let mut reads = [QuadReads::default(); BATCH];
                for ((quads, out), kept) in quads
                    .chunks(BATCH)
                    .zip(out.chunks_mut(BATCH))
                    .zip(kept.chunks_mut(BATCH))
                {
                    read_batch(d, quads, &mut reads[..quads.len()]);
                    for (((quad, o), k), r) in quads
                        .iter()
                        .zip(out.iter_mut())
                        .zip(kept.iter_mut())
                        .zip(&reads)
                    {
                        *k = self.shade_read(d, quad, r, o);
                    }
                }
            }
        }
    }

    fn shade(&self, draw: u32, quad: &Quad, out: &mut [Vec4; 4]) -> u8 {
        let d = &self.draws[draw as usize];
        if self.is_plain(d) {
            let texels = d.texture.as_ref().map(|t| t.quad(quad));
            return self.shade_plain(d, quad, texels.as_ref(), out);
        }
        let mut reads = [QuadReads::default()];
        read_batch(d, std::slice::from_ref(quad), &mut reads);
        self.shade_read(d, quad, &reads[0], out)
    }
}

impl SceneShader<'_> {
    /// The general path's colours of one quad of draw `d`, its texture reads made.
    fn shade_read(&self, d: &DrawInfo, quad: &Quad, reads: &QuadReads, out: &mut [Vec4; 4]) -> u8 {
        let m = d.material;
        let mut kept = quad.mask;
        let QuadReads {
            texels,
            opacity,
            maps,
        } = reads;
        // Map-free Phong under directional lights: the quad's four pixels lit in lanes.
        let back = m.double_sided && !quad.front_facing;
        let lit = (d.mode == Mode::Phong
            && maps.is_none()
            && d.model == ShadingModel::Phong
            && self.directional_only)
            .then(|| self.phong_lanes(d, quad));
        for j in 0..4 {
            if quad.mask & (1 << j) == 0 {
                continue;
            }
            let v = quad.pixel(j);
            let mut c = d.base;
            if let Some(t) = &texels {
                c *= t[j];
            }
            if let Some(t) = &opacity {
                // Premultiplied: scaling alpha scales the whole colour.
                c *= if d.alpha_from_w { t[j].w } else { t[j].x };
            }
            if let Some(k) = d.color_at {
                let vc = Vec4::new(v[k], v[k + 1], v[k + 2], v[k + 3]);
                c *= (vc.truncate() * vc.w).extend(vc.w);
            }
            if let (Some(k), Some(proc)) = (d.object_at, &m.procedural) {
                c *= procedural_color(proc, d, quad, j, k);
            }
            let (df, sp) = match d.mode {
                Mode::Unlit => (Vec3::ONE, Vec3::ZERO),
                Mode::Phong if lit.is_some() => {
                    let (dq, sq) = lit
                        .as_ref()
                        .map_or((&[Vec4::ONE; 4], &[Vec4::ZERO; 4]), |(d, s)| (d, s));
                    (dq[j].truncate(), sq[j].truncate())
                }
                Mode::Phong => {
                    let mut normal = Vec3::new(v[2], v[3], v[4]).normalize_or_zero();
                    let position = if d.needs_position {
                        Vec3::new(v[5], v[6], v[7])
                    } else {
                        Vec3::ZERO
                    };
                    // Double-sided back faces are lit from their side, after any tilt.
                    match &maps {
                        // A Phong material without maps (the model is known): only the normal
                        // and position vary, and this surface stays in registers.
                        None => {
                            if back {
                                normal = -normal;
                            }
                            let s = Surface {
                                position,
                                normal,
                                ..d.surface
                            };
                            phong(&s, &self.lighting, self.viewer)
                        }
                        Some(maps) => {
                            let mut s = Surface {
                                position,
                                normal,
                                ..d.surface
                            };
                            d.apply_maps(maps, quad, j, c, &mut s);
                            if back {
                                s.normal = -s.normal;
                            }
                            illuminate(d.model, &s, &self.lighting, self.viewer)
                        }
                    }
                }
                Mode::Interpolated => {
                    // Double-sided back faces read the factors lit with −N.
                    let k = d.back_at.filter(|_| !quad.front_facing).unwrap_or(2);
                    let mut df = Vec3::new(v[k], v[k + 1], v[k + 2]);
                    let mut sp = Vec3::new(v[k + 3], v[k + 4], v[k + 5]);
                    let maps = maps.as_ref();
                    if let (Some(texel), Some(map)) =
                        (maps.and_then(|m| m.occlusion.as_ref()), &d.occlusion_map)
                    {
                        // The factors carry the full ambient term; take (1 − O) of it away.
                        let o = 1.0 + map.scale * (texel[j].x - 1.0);
                        df -= d.ambient_d * (1.0 - o);
                    }
                    if let Some(texel) = maps.and_then(|m| m.emission.as_ref()) {
                        // The factors carry I_E; the map scales it: I_E·texel = I_E + I_E·(texel − 1).
                        sp += m.emissive * (texel[j].truncate() - Vec3::ONE);
                    }
                    (df, sp)
                }
            };
            match combine(m.alpha_mode, c, df, sp) {
                Some(color) => out[j] = color,
                None => kept &= !(1 << j),
            }
        }
        kept
    }
}

/// [`phong`] of surface `s` for the four pixels of `quad` under directional lights only (one
/// lane per pixel): the interpolated normals at varyings 2..5 (renormalized, negated for
/// `back`), positions at 5..8 when `with_position` (for the specular view vector). The same
/// rule and the same order of operations as the per-pixel path.
#[inline]
fn phong_quad(
    s: &Surface,
    quad: &Quad,
    with_position: bool,
    back: bool,
    lighting: &Lighting,
    viewer: Viewer,
) -> ([Vec4; 4], [Vec4; 4]) {
    let lane = |k: usize| quad.varyings[k];
    let (mut nx, mut ny, mut nz) = (lane(2), lane(3), lane(4));
    // normalize_or_zero, per lane.
    let rcp = sqrt4(nx * nx + ny * ny + nz * nz).recip();
    let ok = rcp.cmplt(Vec4::INFINITY) & rcp.cmpgt(Vec4::ZERO);
    let rcp = Vec4::select(ok, rcp, Vec4::ZERO) * if back { -1.0 } else { 1.0 };
    (nx, ny, nz) = (nx * rcp, ny * rcp, nz * rcp);
    let ambient = lighting.ambient * (s.ambient * s.occlusion);
    let mut d = [
        Vec4::splat(ambient.x),
        Vec4::splat(ambient.y),
        Vec4::splat(ambient.z),
    ];
    let mut sp = [
        Vec4::splat(s.emissive.x),
        Vec4::splat(s.emissive.y),
        Vec4::splat(s.emissive.z),
    ];
    let specular = s.specular > 0.0;
    // The unit view vector per lane (only read for specular).
    let (vx, vy, vz) = match viewer {
        _ if !specular => (Vec4::ZERO, Vec4::ZERO, Vec4::ZERO),
        Viewer::Direction(v) => (Vec4::splat(v.x), Vec4::splat(v.y), Vec4::splat(v.z)),
        Viewer::Point(eye) => {
            let (px, py, pz) = if with_position {
                (lane(5), lane(6), lane(7))
            } else {
                (Vec4::ZERO, Vec4::ZERO, Vec4::ZERO)
            };
            let (x, y, z) = (
                Vec4::splat(eye.x) - px,
                Vec4::splat(eye.y) - py,
                Vec4::splat(eye.z) - pz,
            );
            let r = sqrt4(x * x + y * y + z * z).recip();
            let r = Vec4::select(r.cmplt(Vec4::INFINITY) & r.cmpgt(Vec4::ZERO), r, Vec4::ZERO);
            (x * r, y * r, z * r)
        }
    };
    for light in lighting.lights {
        let Light::Directional {
            direction: l,
            color,
        } = *light
        else {
            continue;
        };
        let n_dot_l = nx * l.x + ny * l.y + nz * l.z;
        let facing = n_dot_l.cmpgt(Vec4::ZERO);
        let diffuse = Vec4::select(facing, n_dot_l * s.diffuse, Vec4::ZERO);
        for (c, dc) in d.iter_mut().enumerate() {
            *dc += diffuse * color[c];
        }
        if specular {
            // R·V with R = 2(N·L)N − L.
            let n_dot_v = nx * vx + ny * vy + nz * vz;
            let l_dot_v = vx * l.x + vy * l.y + vz * l.z;
            let r_dot_v = n_dot_l * 2.0 * n_dot_v - l_dot_v;
            let on = (facing & r_dot_v.cmpgt(Vec4::ZERO)).bitmask();
            let rv = r_dot_v.to_array();
            let lobe = Vec4::from_array(std::array::from_fn(|j| {
                if on & (1 << j) != 0 {
                    s.specular * rv[j].powf(s.shininess)
                } else {
                    0.0
                }
            }));
            for (c, sc) in sp.iter_mut().enumerate() {
                *sc += lobe * (color[c] * s.specular_color[c]);
            }
        }
    }
    (per_pixel(d), per_pixel(sp))
}

/// Lane-wise square root (one `sqrtps`).
#[inline(always)]
fn sqrt4(v: Vec4) -> Vec4 {
    #[cfg(target_arch = "x86_64")]
    {
        // SAFETY: SSE is part of x86_64.
        Vec4::from(unsafe { std::arch::x86_64::_mm_sqrt_ps(v.into()) })
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        Vec4::from_array(v.to_array().map(f32::sqrt))
    }
}

impl SceneShader<'_> {
    /// Whether draw `d` takes [`Self::shade_plain`].
    #[inline]
    fn is_plain(&self, d: &DrawInfo) -> bool {
        d.plain && (d.mode != Mode::Phong || self.directional_only)
    }

    /// A [`DrawInfo::plain`] draw's quad (under directional lights only when Phong-shaded):
    /// the same rule as [`FragmentShader::shade`] (`combine` for an opaque colour), the
    /// factors D and S of the four pixels from lanes.
    #[inline]
    fn shade_plain(
        &self,
        d: &DrawInfo,
        quad: &Quad,
        texels: Option<&[Vec4; 4]>,
        out: &mut [Vec4; 4],
    ) -> u8 {
        let (df, sp) = self.plain_factors(d, quad);
        plain_colors(d, &df, &sp, texels, out);
        quad.mask
    }

    /// [`phong_quad`] of draw `d`'s own surface at `quad` (double-sided back faces lit from
    /// their side).
    #[inline]
    fn phong_lanes(&self, d: &DrawInfo, quad: &Quad) -> ([Vec4; 4], [Vec4; 4]) {
        let back = d.material.double_sided && !quad.front_facing;
        phong_quad(
            &d.surface,
            quad,
            d.needs_position,
            back,
            &self.lighting,
            self.viewer,
        )
    }

    /// The factors D and S of a plain draw's quad, one vector per pixel (fourth lanes 0).
    #[inline]
    fn plain_factors(&self, d: &DrawInfo, quad: &Quad) -> ([Vec4; 4], [Vec4; 4]) {
        match d.mode {
            Mode::Unlit => ([Vec4::new(1.0, 1.0, 1.0, 0.0); 4], [Vec4::ZERO; 4]),
            Mode::Phong => self.phong_lanes(d, quad),
            Mode::Interpolated => {
                // Double-sided back faces read the factors lit with −N.
                let k = d.back_at.filter(|_| !quad.front_facing).unwrap_or(2);
                let v = &quad.varyings;
                (
                    per_pixel([v[k], v[k + 1], v[k + 2]]),
                    per_pixel([v[k + 3], v[k + 4], v[k + 5]]),
                )
            }
        }
    }
}

/// A plain draw's colours from the factors and texels: `combine` for an opaque colour,
/// straight = c / a (unless a is 0 or 1), then straight·D + S with alpha 1 (the factors'
/// fourth lanes are 0).
#[inline(always)]
fn plain_colors(
    d: &DrawInfo,
    df: &[Vec4; 4],
    sp: &[Vec4; 4],
    texels: Option<&[Vec4; 4]>,
    out: &mut [Vec4; 4],
) {
    for j in 0..4 {
        let mut c = d.base;
        if let Some(t) = texels {
            c *= t[j];
        }
        let a = c.w;
        let straight = if a > 0.0 && a != 1.0 { c / a } else { c };
        out[j] = straight * df[j] + sp[j] + Vec4::W;
    }
}

/// Three lanes of factors (R, G and B, one pixel per lane) as one vector per pixel, its
/// fourth component zero: a 4×4 transpose (shuffles).
#[inline(always)]
fn per_pixel(c: [Vec4; 3]) -> [Vec4; 4] {
    let m = Mat4::from_cols(c[0], c[1], c[2], Vec4::ZERO).transpose();
    [m.x_axis, m.y_axis, m.z_axis, m.w_axis]
}

/// A quad's texture reads on the general path: the base colour texture, the opacity map, and
/// (for draws with any) the maps that feed the [`Surface`].
#[derive(Clone, Copy, Default)]
struct QuadReads {
    texels: Option<[Vec4; 4]>,
    opacity: Option<[Vec4; 4]>,
    maps: Option<QuadMaps>,
}

/// The texture reads of `quads` (of draw `d`) into `out`, map by map across the quads, so each
/// map's reads are staged ([`MapRead::quads`]).
fn read_batch(d: &DrawInfo, quads: &[Quad], out: &mut [QuadReads]) {
    for (o, quad) in out.iter_mut().zip(quads) {
        // Read only for draws with such maps: a plain draw pays one test per quad.
        *o = QuadReads {
            maps: d.surface_maps.then(|| QuadMaps {
                bumps: d.bump_map.as_ref().map(|t| t.height_slopes(quad)),
                ..QuadMaps::default()
            }),
            ..QuadReads::default()
        };
    }
    let mut buf = [[Vec4::ZERO; 4]; BATCH];
    let mut fill = |t: &MapRead, set: &dyn Fn(&mut QuadReads, [Vec4; 4])| {
        for (quads, out) in quads.chunks(BATCH).zip(out.chunks_mut(BATCH)) {
            t.quads(quads, &mut buf[..quads.len()]);
            for (o, b) in out.iter_mut().zip(&buf) {
                set(o, *b);
            }
        }
    };
    if let Some(t) = &d.texture {
        fill(t, &|r, v| r.texels = Some(v));
    }
    if let Some(t) = &d.alpha_map {
        fill(t, &|r, v| r.opacity = Some(v));
    }
    if !d.surface_maps {
        return;
    }
    type Field = fn(&mut QuadMaps) -> &mut Option<[Vec4; 4]>;
    let maps: [(Option<&MapRead>, Field); 7] = [
        (d.normal_map.as_ref(), |m| &mut m.normals),
        (d.occlusion_map.as_ref(), |m| &mut m.occlusion),
        (d.emissive_map.as_ref(), |m| &mut m.emission),
        (d.metal_rough_map.as_ref(), |m| &mut m.metal_rough),
        (d.ambient_map.as_ref(), |m| &mut m.ambient),
        (d.specular_map.as_ref(), |m| &mut m.specular),
        (d.shininess_map.as_ref(), |m| &mut m.shininess),
    ];
    for (map, field) in maps {
        if let Some(t) = map {
            fill(t, &|r, v| {
                if let Some(m) = r.maps.as_mut() {
                    *field(m) = Some(v);
                }
            });
        }
    }
}

/// A quad's reads of the maps that feed the [`Surface`] (each `None` when the draw has none).
#[derive(Clone, Copy, Default)]
struct QuadMaps {
    normals: Option<[Vec4; 4]>,
    occlusion: Option<[Vec4; 4]>,
    emission: Option<[Vec4; 4]>,
    metal_rough: Option<[Vec4; 4]>,
    /// Height slopes `(∂h/∂x, ∂h/∂y)`.
    bumps: Option<[Vec2; 4]>,
    ambient: Option<[Vec4; 4]>,
    specular: Option<[Vec4; 4]>,
    shininess: Option<[Vec4; 4]>,
}

impl DrawInfo<'_> {
    /// Pixel `j`'s surface parameters from its maps: the normal map and bumps tilt the normal
    /// (world space, before any back-face flip), occlusion, emission, metallic-roughness and
    /// solid textures set the parameters, and metallic-roughness materials take the colour `c`.
    fn apply_maps(&self, maps: &QuadMaps, quad: &Quad, j: usize, c: Vec4, s: &mut Surface) {
        let v = quad.pixel(j);
        let n = &mut s.normal;
        if let (Some(k), Some(texel), Some(map)) =
            (self.tangent_at, &maps.normals, &self.normal_map)
        {
            // Tangent space → world: T, B = (N × T)·w, N; the map's x and y scaled.
            let t = Vec3::new(v[k], v[k + 1], v[k + 2]);
            let t = (t - *n * n.dot(t)).normalize_or_zero();
            let b = n.cross(t) * v[k + 3].signum();
            let ts = texel[j].truncate() * 2.0 - Vec3::ONE;
            let ts = Vec3::new(ts.x * map.scale, ts.y * map.scale, ts.z);
            let mapped = (t * ts.x + b * ts.y + *n * ts.z).normalize_or_zero();
            if mapped != Vec3::ZERO && t != Vec3::ZERO {
                *n = mapped;
            }
        }
        if let Some(slopes) = &maps.bumps {
            let dp_dx = Vec3::new(quad.ddx(5), quad.ddx(6), quad.ddx(7));
            let dp_dy = Vec3::new(quad.ddy(5), quad.ddy(6), quad.ddy(7));
            *n = bump::tilt_screen_space(*n, dp_dx, dp_dy, slopes[j]);
        }
        if self.solid_roughness.is_some() || self.solid_bump.is_some() {
            solid_channels(self, quad, j, s);
        }
        if let (Some(texel), Some(map)) = (&maps.occlusion, &self.occlusion_map) {
            // 1 + strength·(R − 1).
            s.occlusion = 1.0 + map.scale * (texel[j].x - 1.0);
        }
        if let Some(texel) = &maps.emission {
            s.emissive *= texel[j].truncate();
        }
        if let Some(texel) = &maps.metal_rough {
            s.roughness *= texel[j].y;
            s.metallic *= texel[j].z;
        }
        if let Some(texel) = &maps.ambient {
            s.ambient_color = Some(straight(texel[j]));
        }
        if let Some(texel) = &maps.specular {
            s.specular_color = straight(texel[j]);
        }
        if let Some(texel) = &maps.shininess {
            // MTL: the map's value multiplies Ns (at least 1, so the lobe stays finite).
            s.shininess = (s.shininess * texel[j].x).max(1.0);
        }
        if self.model == ShadingModel::MetallicRoughness {
            s.base_color = straight(c);
        }
    }
}

/// The straight-alpha colour of premultiplied `c`.
#[inline]
fn straight(c: Vec4) -> Vec3 {
    if c.w > 0.0 && c.w != 1.0 {
        c.truncate() / c.w
    } else {
        c.truncate()
    }
}

/// The object-space position of pixel `j` at varyings `k..k + 3` and, when `antialias`, the
/// footprint extent |∂P/∂x| + |∂P/∂y| of the quad (zero otherwise).
#[inline]
fn object_point(quad: &Quad, j: usize, k: usize, antialias: bool) -> (glam::DVec3, glam::DVec3) {
    let v = quad.pixel(j);
    let p = Vec3::new(v[k], v[k + 1], v[k + 2]);
    let extent = if antialias {
        let dp_dx = Vec3::new(quad.ddx(k), quad.ddx(k + 1), quad.ddx(k + 2));
        let dp_dy = Vec3::new(quad.ddy(k), quad.ddy(k + 1), quad.ddy(k + 2));
        (dp_dx.abs() + dp_dy.abs()).as_dvec3()
    } else {
        glam::DVec3::ZERO
    };
    (p.as_dvec3(), extent)
}

/// Solid textures on the roughness and bump channels at pixel `j`: the roughness (or, for
/// Phong materials, the exponent it stands for) and the bump's tilt of the normal, into `s`.
fn solid_channels(d: &DrawInfo, quad: &Quad, j: usize, s: &mut Surface) {
    let Some(k) = d.object_at else {
        return;
    };
    if let Some(r) = &d.solid_roughness {
        let (p, extent) = object_point(quad, j, k, r.map.antialias);
        let value = r.map.solid.value(p, extent) as f32;
        let roughness = r.range[0] + (r.range[1] - r.range[0]) * value;
        match d.model {
            ShadingModel::MetallicRoughness => s.roughness = roughness,
            ShadingModel::Phong => s.shininess = shininess_from_roughness(roughness),
        }
    }
    if let Some(b) = &d.solid_bump {
        let (p, extent) = object_point(quad, j, k, b.map.antialias);
        let (_, gradient) = b.map.solid.value_and_gradient(p, extent);
        let grad = b.world_from_gradient * gradient.as_vec3();
        s.normal = bump::tilt_by_gradient(s.normal, grad);
    }
}

/// The procedural colour of pixel `j` of a quad, from the object-space position and normal at
/// varyings `k..k + 6` and the position's screen derivatives.
fn procedural_color(proc: &Procedural, d: &DrawInfo, quad: &Quad, j: usize, k: usize) -> Vec4 {
    match proc {
        Procedural::Solid {
            solid,
            colors,
            antialias,
        } => {
            let (p, extent) = object_point(quad, j, k, *antialias);
            solid.color(p, extent, *colors).extend(1.0)
        }
        // The slot's image, sampler and affine transform, resolved once per draw.
        Procedural::Projected { .. } => {
            let (Some(map), Some(projection)) = (&d.projected, &d.projection) else {
                return Vec4::ONE;
            };
            let v = quad.pixel(j);
            let p = Vec3::new(v[k], v[k + 1], v[k + 2]);
            let dp_dx = Vec3::new(quad.ddx(k), quad.ddx(k + 1), quad.ddx(k + 2));
            let dp_dy = Vec3::new(quad.ddy(k), quad.ddy(k + 1), quad.ddy(k + 2));
            let n = Vec3::new(v[k + 3], v[k + 4], v[k + 5]);
            let fp = projection.map_footprint(p, dp_dx, dp_dy, n);
            let fp = Footprint::new(
                map.linear * fp.uv + map.offset,
                map.linear * fp.duv_dx,
                map.linear * fp.duv_dy,
            );
            sample(map.tex, &map.sampler, &fp)
        }
        Procedural::Texture3D {
            texture,
            sampler,
            min,
            max,
            colors,
        } => {
            let v = quad.pixel(j);
            let p = Vec3::new(v[k], v[k + 1], v[k + 2]);
            let dp_dx = Vec3::new(quad.ddx(k), quad.ddx(k + 1), quad.ddx(k + 2));
            let dp_dy = Vec3::new(quad.ddy(k), quad.ddy(k + 1), quad.ddy(k + 2));
            let inv = (*max - *min).recip();
            let fp = Footprint3 {
                uvw: (p - *min) * inv,
                duvw_dx: dp_dx * inv,
                duvw_dy: dp_dy * inv,
            };
            let value = sample_3d(texture, sampler, &fp).x.clamp(0.0, 1.0);
            colors[0].lerp(colors[1], value).extend(1.0)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quad_lighting_equals_the_per_pixel_rule() {
        let lights = [
            Light::Directional {
                direction: Vec3::new(0.3, 0.8, 0.5).normalize(),
                color: Vec3::new(1.0, 0.9, 0.8),
            },
            Light::Directional {
                direction: Vec3::new(-0.6, 0.2, 0.77).normalize(),
                color: Vec3::splat(0.5),
            },
        ];
        let lighting = Lighting {
            lights: &lights,
            ambient: Vec3::new(0.3, 0.35, 0.4),
        };
        let material = Material {
            specular: 0.7,
            shininess: 24.0,
            emissive: Vec3::new(0.01, 0.02, 0.03),
            ..Default::default()
        };
        let mut surface = Surface::new(&material, Vec3::ZERO, Vec3::ZERO);
        surface.specular_color = Vec3::new(1.0, 0.5, 0.25);
        let mut quad = Quad {
            x: 0,
            y: 0,
            mask: 0b1111,
            front_facing: true,
            varyings: [Vec4::ZERO; MAX_VARYINGS],
        };
        // Unnormalized normals (one zero), positions spread out, some facing away.
        let normals = [
            Vec3::new(0.1, 2.0, 0.3),
            Vec3::new(-1.0, 0.2, 0.9),
            Vec3::ZERO,
            Vec3::new(0.2, -1.0, 0.1),
        ];
        for (j, n) in normals.iter().enumerate() {
            let p = Vec3::new(j as f32 - 1.5, 0.1 * j as f32, -2.0 + j as f32);
            for c in 0..3 {
                quad.varyings[2 + c][j] = n[c];
                quad.varyings[5 + c][j] = p[c];
            }
        }
        for viewer in [
            Viewer::Point(Vec3::new(0.5, 3.0, 4.0)),
            Viewer::Direction(Vec3::new(0.0, 0.6, 0.8)),
        ] {
            for back in [false, true] {
                let (ld, ls) = phong_quad(&surface, &quad, true, back, &lighting, viewer);
                for (j, n) in normals.iter().enumerate() {
                    let v = quad.pixel(j);
                    let mut normal = n.normalize_or_zero();
                    if back {
                        normal = -normal;
                    }
                    let s = Surface {
                        position: Vec3::new(v[5], v[6], v[7]),
                        normal,
                        ..surface
                    };
                    let (d, sp) = phong(&s, &lighting, viewer);
                    let (qd, qs) = (ld[j].truncate(), ls[j].truncate());
                    assert!(
                        (d - qd).abs().max_element() < 1e-5 && (sp - qs).abs().max_element() < 1e-5,
                        "pixel {j} {viewer:?} back {back}: {d} {sp} vs {qd} {qs}"
                    );
                }
            }
        }
    }
}
