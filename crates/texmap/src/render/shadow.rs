//! Shadow maps for a frame: which lights cast (the scene's choice, or the user's
//! [`ShadowOverrides`]), each light's view fitted to the scene, and the depth passes drawn
//! through the pipeline ([`shadow_maps`]).
//!
//! Views: a directional light looks along its rays at the scene, an orthographic rectangle
//! fitted to where shadows can fall (`directional`: two texels of margin a side); a spot light of outer angle up to 60° is one perspective map covering
//! its cone; a point light (or a wider spot) is a cube of six 90° faces, each widened by three
//! texels so filters near a face's edge still read drawn texels. Near and far planes enclose
//! the box.
//!
//! The depth pass is a plain pipeline draw, like `volumes.rs`'s distance pass: the vertex
//! shader carries the view depth as the one varying, the z-buffer keeps the nearest surface,
//! and the fragment shader writes that depth into the colour target, which becomes the map.
//! Both faces of every triangle cast (no culling); meshes whose material blends do not (a map
//! holds one depth per texel, no partial cover), and alpha-tested ones cast whole (the pass
//! reads no texture).
//!
//! A projector that casts ([`crate::shading::Projector::shadows`]) gets the map of a spot
//! light at its position whose cone holds its frustum: its slide does not pass through the
//! surfaces nearest to it.
//!
//! The maps depend on the scene and the lights, not on the camera: a turntable makes them
//! once ([`super::render_into_with_shadows`]).

use glam::{Mat4, Vec2, Vec3, Vec4};

use super::settings::Settings;
use crate::pipeline::{
    self, ClipVertex, DrawCall, DrawState, FragmentShader, Interpolation, Quad, Target,
    VertexShader, MAX_VARYINGS,
};
use crate::pixels::Pixels;
use crate::scene::{Mesh, Scene};
use crate::shading::shadow::{
    LightExtent, LightMaps, LightShadow, MapView, ShadowFilter, ShadowMap, ShadowMaps,
    ShadowParams, MAX_SHADOW_MAP_SIZE,
};
use crate::shading::{AlphaMode, Light, Projector};
use crate::Result;

/// Spot lights with an outer angle above this get a cube of maps.
pub const MAX_SPOT_MAP_DEG: f32 = 60.0;

/// The user's shadow choices, laid over the scene's ([`crate::shading::shadow::Shadows`]):
/// each field that is set replaces the scene's. The command line's `--shadows`,
/// `--shadow-map-size`, `--shadow-filter`, `--shadow-bias`, `--shadow-slope-bias`,
/// `--shadow-normal-offset`, `--shadow-light-angle` and `--shadow-light-radius` fill it.
///
/// ```
/// use texmap::render::ShadowOverrides;
/// use texmap::shading::shadow::{ShadowFilter, ShadowParams};
/// let o = ShadowOverrides::default().with_cast(true).with_filter(ShadowFilter::Pcf5);
/// assert_eq!(o.apply(ShadowParams::default()).filter, ShadowFilter::Pcf5);
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Default)]
#[non_exhaustive]
pub struct ShadowOverrides {
    /// `Some(true)`: every light casts; `Some(false)`: none does; `None`: the scene's lights
    /// that say they cast.
    pub cast: Option<bool>,
    pub map_size: Option<u32>,
    pub filter: Option<ShadowFilter>,
    pub bias: Option<f32>,
    pub slope_bias: Option<f32>,
    pub normal_offset: Option<f32>,
    pub light_angle: Option<f32>,
    pub light_radius: Option<f32>,
}

impl ShadowOverrides {
    #[must_use]
    pub fn with_cast(mut self, cast: bool) -> Self {
        self.cast = Some(cast);
        self
    }
    #[must_use]
    pub fn with_map_size(mut self, texels: u32) -> Self {
        self.map_size = Some(texels);
        self
    }
    #[must_use]
    pub fn with_filter(mut self, filter: ShadowFilter) -> Self {
        self.filter = Some(filter);
        self
    }
    #[must_use]
    pub fn with_bias(mut self, texels: f32) -> Self {
        self.bias = Some(texels);
        self
    }
    #[must_use]
    pub fn with_slope_bias(mut self, texels: f32) -> Self {
        self.slope_bias = Some(texels);
        self
    }
    #[must_use]
    pub fn with_normal_offset(mut self, texels: f32) -> Self {
        self.normal_offset = Some(texels);
        self
    }
    #[must_use]
    pub fn with_light_angle(mut self, degrees: f32) -> Self {
        self.light_angle = Some(degrees);
        self
    }
    #[must_use]
    pub fn with_light_radius(mut self, radius: f32) -> Self {
        self.light_radius = Some(radius);
        self
    }

    /// `params` with every set field replaced.
    #[must_use]
    pub fn apply(&self, mut params: ShadowParams) -> ShadowParams {
        let set = |v: Option<f32>, to: &mut f32| {
            if let Some(v) = v {
                *to = v;
            }
        };
        if let Some(s) = self.map_size {
            params.map_size = s;
        }
        if let Some(f) = self.filter {
            params.filter = f;
        }
        set(self.bias, &mut params.bias);
        set(self.slope_bias, &mut params.slope_bias);
        set(self.normal_offset, &mut params.normal_offset);
        set(self.light_angle, &mut params.light_angle);
        set(self.light_radius, &mut params.light_radius);
        params
    }

    /// The scene's lights that cast under these overrides (indices into `scene.lights`).
    #[must_use]
    pub fn casters(&self, scene: &Scene) -> Vec<usize> {
        match self.cast {
            Some(true) => (0..scene.lights.len()).collect(),
            Some(false) => Vec::new(),
            None => {
                let mut l = scene.shadows.lights.clone();
                l.retain(|&i| i < scene.lights.len());
                l.sort_unstable();
                l.dedup();
                l
            }
        }
    }

    /// The scene's projectors that cast under these overrides (indices into
    /// `scene.projectors`): `--shadows` makes every one cast, `--shadows=false` none.
    #[must_use]
    pub fn casting_projectors(&self, scene: &Scene) -> Vec<usize> {
        (0..scene.projectors.len())
            .filter(|&k| self.cast.unwrap_or(scene.projectors[k].shadows))
            .collect()
    }

    /// Checks the set values as [`ShadowParams::validate`] does.
    ///
    /// # Errors
    /// [`crate::Error::Parameter`] naming the first bad value.
    pub fn validate(&self) -> Result<()> {
        self.apply(ShadowParams::default()).validate()
    }
}

/// The shadow maps of `scene`'s casting lights under `settings` (the scene's [`Shadows`]
/// with [`Settings::shadows`] laid over them), one entry per light the frame lights — the
/// scene's lights with a usable direction, in order. Empty when no light casts, the frame is
/// unlit or there is nothing to draw.
///
/// [`Shadows`]: crate::shading::shadow::Shadows
///
/// # Errors
/// [`crate::Error::Parameter`] for bad shadow parameters (a map size of 0 or above
/// [`MAX_SHADOW_MAP_SIZE`], negative biases, …).
pub fn shadow_maps(scene: &Scene, settings: &Settings) -> Result<ShadowMaps> {
    shadow_maps_with(scene, settings, &[], &|_: &mut ShadowMap| {})
}

/// [`shadow_maps`] with more casters that the pipeline does not draw: `proxies` (their
/// boxes as meshes) widen the maps' views and depth ranges as casting meshes do, and
/// `add` then writes their depths into each map drawn (`field_shadow.rs`).
pub(super) fn shadow_maps_with(
    scene: &Scene,
    settings: &Settings,
    proxies: &[Mesh],
    add: &(dyn Fn(&mut ShadowMap) + Sync),
) -> Result<ShadowMaps> {
    let casters = settings.shadows.casters(scene);
    let projectors = settings.shadows.casting_projectors(scene);
    let params = settings.shadows.apply(scene.shadows.params);
    if casters.is_empty() && projectors.is_empty() {
        return Ok(ShadowMaps::default());
    }
    params.validate()?;
    let casting: Vec<&Mesh> = scene
        .meshes
        .iter()
        .filter(|m| {
            scene
                .materials
                .get(m.material)
                .is_some_and(|mat| mat.alpha_mode != AlphaMode::Blend)
        })
        .collect();
    let fit: Vec<&Mesh> = casting.iter().copied().chain(proxies).collect();
    if settings.unlit || fit.is_empty() {
        return Ok(ShadowMaps::default());
    }
    let bounds = proxies
        .iter()
        .flat_map(|m| {
            m.positions
                .iter()
                .map(|&p| m.world_from_object.transform_point3(p))
        })
        .fold(scene.bounds(), |(lo, hi), p| (lo.min(p), hi.max(p)));
    let mut target = Pixels::default();
    let lights = scene
        .lights
        .iter()
        .enumerate()
        .filter_map(|(i, l)| Some((i, l.normalized()?)))
        .map(|(i, light)| {
            casters.contains(&i).then(|| LightShadow {
                maps: light_maps(&light, bounds, &params, (&fit, &casting), &mut target, add),
                origin: origin(&light),
                extent: match light {
                    Light::Directional { .. } => LightExtent::Angle {
                        tan_half: (0.5 * params.light_angle).to_radians().tan(),
                    },
                    _ => LightExtent::Radius {
                        radius: params.light_radius,
                    },
                },
            })
        })
        .collect();
    let projectors = scene
        .projectors
        .iter()
        .enumerate()
        .map(|(k, p)| {
            projectors.contains(&k).then(|| LightShadow {
                maps: light_maps(
                    &projector_light(p),
                    bounds,
                    &params,
                    (&fit, &casting),
                    &mut target,
                    add,
                ),
                origin: p.position,
                extent: LightExtent::Radius {
                    radius: params.light_radius,
                },
            })
        })
        .collect();
    Ok(ShadowMaps {
        lights,
        params,
        projectors,
    })
}

/// A spot light with projector `p`'s position and axis whose cone holds its frustum: what its
/// depth map is drawn for.
fn projector_light(p: &Projector) -> Light {
    Light::Spot {
        position: p.position,
        direction: p.axis(),
        color: Vec3::ONE,
        inner_deg: 0.0,
        outer_deg: p.cone_half_deg().min(89.0),
    }
}

/// The bytes [`shadow_maps`] holds for `scene` under `settings`: four per texel of every
/// map (six for a cube) and sixteen per texel of the one colour target the passes reuse;
/// 0 when no light casts. Callers bound it before drawing (the command line by
/// `--max-memory`).
#[must_use]
pub fn shadow_map_bytes(scene: &Scene, settings: &Settings) -> u64 {
    let casters = settings.shadows.casters(scene);
    let projectors = settings.shadows.casting_projectors(scene);
    if (casters.is_empty() && projectors.is_empty()) || settings.unlit {
        return 0;
    }
    let n = u64::from(settings.shadows.apply(scene.shadows.params).map_size);
    let maps: u64 = casters
        .iter()
        .filter_map(|&i| scene.lights.get(i)?.normalized())
        .chain(
            projectors
                .iter()
                .map(|&k| projector_light(&scene.projectors[k])),
        )
        .map(|l| match l {
            Light::Directional { .. } => 1,
            Light::Spot { outer_deg, .. } if outer_deg <= MAX_SPOT_MAP_DEG => 1,
            _ => 6,
        })
        .sum();
    if maps == 0 {
        return 0;
    }
    n * n * (4 * maps + 16)
}

/// Where `light` is, as [`LightShadow::origin`] records it: its position, or its direction
/// towards the light.
pub(super) fn origin(light: &Light) -> Vec3 {
    match *light {
        Light::Directional { direction, .. } => direction,
        Light::Point { position, .. } | Light::Spot { position, .. } => position,
    }
}

/// Every map of `light` (unit directions), fitted to `fit`, `drawn` drawn into it, then
/// `add`'s casters.
fn light_maps(
    light: &Light,
    bounds: (Vec3, Vec3),
    params: &ShadowParams,
    (casting, drawn): (&[&Mesh], &[&Mesh]),
    target: &mut Pixels,
    add: &(dyn Fn(&mut ShadowMap) + Sync),
) -> LightMaps {
    let n = params.map_size.clamp(1, MAX_SHADOW_MAP_SIZE);
    let mut draw = |m: ShadowMap| {
        let mut m = draw_map(m, drawn, target);
        add(&mut m);
        m
    };
    match *light {
        Light::Directional { direction, .. } => {
            LightMaps::One(draw(directional(direction, bounds, casting, n)))
        }
        Light::Spot {
            position,
            direction,
            outer_deg,
            ..
        } if outer_deg <= MAX_SPOT_MAP_DEG => {
            // Two texels of margin beyond the cone.
            let tan_half =
                outer_deg.max(0.1).to_radians().tan() * n as f32 / (n as f32 - 4.0).max(1.0);
            LightMaps::One(draw(perspective(position, direction, tan_half, bounds, n)))
        }
        Light::Spot { position, .. } | Light::Point { position, .. } => {
            let tan_half = n as f32 / (n as f32 - 6.0).max(1.0);
            let faces = [Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z]
                .map(|axis| draw(perspective(position, axis, tan_half, bounds, n)));
            LightMaps::Cube(Box::new(faces))
        }
    }
}

/// An up vector for a view along `dir` (unit).
fn up_for(dir: Vec3) -> Vec3 {
    if dir.y.abs() < 0.99 {
        Vec3::Y
    } else {
        Vec3::X
    }
}

fn corners((lo, hi): (Vec3, Vec3)) -> [Vec3; 8] {
    std::array::from_fn(|k| {
        Vec3::new(
            if k & 1 == 0 { lo.x } else { hi.x },
            if k & 2 == 0 { lo.y } else { hi.y },
            if k & 4 == 0 { lo.z } else { hi.z },
        )
    })
}

/// A mesh seen along a directional light: the rectangle it covers across the rays and the
/// depth range it spans, and whether it is flat (a flat mesh cannot shadow itself).
struct Footprint {
    lo: Vec3,
    hi: Vec3,
    flat: bool,
}

impl Footprint {
    fn of(mesh: &Mesh, view_from_world: &Mat4) -> Option<Footprint> {
        let view_from_object = *view_from_world * mesh.world_from_object;
        let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        let points: Vec<Vec3> = mesh
            .positions
            .iter()
            .map(|&p| view_from_object.transform_point3(p))
            .filter(|p| p.is_finite())
            .collect();
        for &q in &points {
            lo = lo.min(q);
            hi = hi.max(q);
        }
        if points.is_empty() {
            return None;
        }
        // Flat: every point on the plane of the first triangle with an area.
        let extent = (hi - lo).max_element().max(1e-6);
        let plane = mesh.indices.chunks_exact(3).find_map(|t| {
            let [a, b, c] = [t[0], t[1], t[2]].map(|i| points.get(i as usize).copied());
            let (a, b, c) = (a?, b?, c?);
            let n = (b - a).cross(c - a);
            (n.length() > 1e-9 * extent * extent).then(|| (a, n.normalize()))
        });
        let flat = plane.is_some_and(|(a, n)| {
            points
                .iter()
                .all(|&p| (p - a).dot(n).abs() <= 1e-5 * extent)
        });
        Some(Footprint { lo, hi, flat })
    }

    /// The overlap of two rectangles across the rays, if any.
    fn overlap(&self, other: &Footprint) -> Option<(Vec2, Vec2)> {
        let lo = self.lo.truncate().max(other.lo.truncate());
        let hi = self.hi.truncate().min(other.hi.truncate());
        (lo.x <= hi.x && lo.y <= hi.y).then_some((lo, hi))
    }
}

/// A directional light's map (`towards`: unit, towards the light): orthographic, its depth
/// range enclosing the casters, its rectangle fitted with two texels of margin a side to
/// where a shadow can fall — a shadow lies inside its caster's rectangle across the rays and
/// on another mesh, or on the caster itself unless it is flat. So a large floor widens the
/// map only where other meshes overlap it (lookups outside the rectangle are lit); a scene
/// of one flat mesh gets its whole box.
fn directional(towards: Vec3, bounds: (Vec3, Vec3), casting: &[&Mesh], n: u32) -> ShadowMap {
    let centre = (bounds.0 + bounds.1) * 0.5;
    let view_from_world = Mat4::look_at_rh(centre + towards, centre, up_for(towards));
    let prints: Vec<Footprint> = casting
        .iter()
        .filter_map(|m| Footprint::of(m, &view_from_world))
        .collect();
    let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    for f in &prints {
        lo = lo.min(f.lo);
        hi = hi.max(f.hi);
    }
    if prints.is_empty() {
        for c in corners(bounds) {
            let q = view_from_world.transform_point3(c);
            lo = lo.min(q);
            hi = hi.max(q);
        }
    }
    let (mut rect_lo, mut rect_hi) = (Vec2::splat(f32::INFINITY), Vec2::splat(f32::NEG_INFINITY));
    for (a, fa) in prints.iter().enumerate() {
        if !fa.flat {
            rect_lo = rect_lo.min(fa.lo.truncate());
            rect_hi = rect_hi.max(fa.hi.truncate());
            continue;
        }
        for (b, fb) in prints.iter().enumerate() {
            if let (true, Some((l, h))) = (a != b, fa.overlap(fb)) {
                rect_lo = rect_lo.min(l);
                rect_hi = rect_hi.max(h);
            }
        }
    }
    if !(rect_lo.x <= rect_hi.x && rect_lo.y <= rect_hi.y) {
        (rect_lo, rect_hi) = (lo.truncate(), hi.truncate());
    }
    let extent = (hi - lo).max_element().max(1e-6);
    // Flat boxes seen edge-on still get a rectangle.
    let size = (rect_hi - rect_lo).max(Vec2::splat(1e-3 * extent));
    let margin = size * (2.0 / (n as f32 - 4.0).max(1.0));
    let mid = (rect_lo + rect_hi) * 0.5;
    let depth_pad = 1e-3 * extent;
    ShadowMap {
        view_from_world,
        view: MapView::Orthographic {
            min: mid - size * 0.5 - margin,
            max: mid + size * 0.5 + margin,
        },
        near: -hi.z - depth_pad,
        far: -lo.z + depth_pad,
        size: n,
        depth: Vec::new(),
        tiles: Vec::new(),
    }
}

/// A perspective map from `eye` along `axis` (unit) with `tan_half`, its depth range
/// enclosing the box.
fn perspective(eye: Vec3, axis: Vec3, tan_half: f32, bounds: (Vec3, Vec3), n: u32) -> ShadowMap {
    let view_from_world = Mat4::look_at_rh(eye, eye + axis, up_for(axis));
    let far_corner = corners(bounds)
        .iter()
        .map(|c| c.distance(eye))
        .fold(0.0f32, f32::max);
    let far = (far_corner * 1.01).max(1e-3);
    // The nearest point of the box (0 inside it); casters nearer than `near` are clipped.
    let inside = (bounds.0 - eye)
        .max(eye - bounds.1)
        .max(Vec3::ZERO)
        .length();
    let near = (inside * 0.99).max(far * 1e-4);
    ShadowMap {
        view_from_world,
        view: MapView::Perspective { tan_half },
        near,
        far,
        size: n,
        depth: Vec::new(),
        tiles: Vec::new(),
    }
}

/// One caster mesh seen from a light: clip position and view depth (the one varying).
struct LightVertices<'a> {
    mesh: &'a Mesh,
    clip_from_world: Mat4,
    view_from_world: Mat4,
}

impl VertexShader for LightVertices<'_> {
    fn vertex_count(&self) -> usize {
        self.mesh.positions.len()
    }
    fn vertex(&self, i: usize) -> ClipVertex {
        let p = self
            .mesh
            .world_from_object
            .transform_point3(self.mesh.positions[i]);
        let mut varyings = [0.0; MAX_VARYINGS];
        varyings[0] = -self.view_from_world.transform_point3(p).z;
        ClipVertex {
            clip: self.clip_from_world * p.extend(1.0),
            varyings,
        }
    }
}

/// Writes each fragment's interpolated view depth.
struct DepthShader;

impl FragmentShader for DepthShader {
    fn shade(&self, _draw: u32, quad: &Quad, out: &mut [Vec4; 4]) -> u8 {
        let d = quad.varyings[0].to_array();
        for (o, d) in out.iter_mut().zip(d) {
            *o = Vec4::new(d, 0.0, 0.0, 1.0);
        }
        quad.mask
    }
}

/// Draws `map`'s depth pass over `casting` into `target` (reused between maps) and keeps the
/// depths.
fn draw_map(mut map: ShadowMap, casting: &[&Mesh], target: &mut Pixels) -> ShadowMap {
    let clip_from_world = map.clip_from_world();
    let vertices: Vec<LightVertices> = casting
        .iter()
        .map(|&mesh| LightVertices {
            mesh,
            clip_from_world,
            view_from_world: map.view_from_world,
        })
        .collect();
    let calls: Vec<DrawCall> = vertices
        .iter()
        .map(|v| DrawCall {
            vertices: v,
            indices: &v.mesh.indices,
            state: DrawState {
                varyings: 1,
                ..DrawState::default()
            },
        })
        .collect();
    let t = Target {
        width: map.size,
        height: map.size,
        samples: 1,
        clear_color: Vec4::new(f32::INFINITY, 0.0, 0.0, 1.0),
        interpolation: Interpolation::Perspective,
        depth_sort: false,
    };
    pipeline::draw_into(&calls, &DepthShader, &t, target);
    map.set_rows(target.iter().map(|c| c.x));
    map
}
