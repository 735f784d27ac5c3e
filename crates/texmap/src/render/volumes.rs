//! Volumes and meshes in one frame: the surfaces are drawn by the pipeline, a second pass
//! draws their distance from the eye, the rays stop there, and the volume is laid over the
//! surfaces (a mesh inside a scan).
//!
//! The distance pass is a plain pipeline draw whose fragment shader writes the eye distance
//! of the (perspective-correct) world position into the colour target, with the z-buffer on:
//! the nearest surface per pixel wins, so no pipeline change was needed.
//!
//! Several volumes ([`render_with_volumes`]) are drawn one at a time, each stopped at the
//! surfaces, and laid over the frame from the farthest box centre to the nearest: right for
//! volumes one behind the other, approximate where boxes overlap along a ray (their samples
//! are not interleaved).

use glam::{Vec3, Vec4};

use super::{render, render_into_with_shadows, shadow_maps_with_fields, Frame, Settings};
use crate::camera::Camera;
use crate::pipeline::{
    self, ClipVertex, DrawCall, DrawState, FragmentShader, Interpolation, Quad, Target,
    MAX_VARYINGS,
};
use crate::scene::Scene;
use crate::shading::shadow::ShadowMaps;
use crate::volume::sdf::render_distance_field_shadowed;
use crate::volume::{
    raymarch, render_slices_until, MarchParams, Method, SceneVolume, TransferFunction, Volume,
};
use crate::{Error, Result};

struct DistanceShader {
    camera: Camera,
}

impl FragmentShader for DistanceShader {
    fn shade(&self, _draw: u32, quad: &Quad, out: &mut [Vec4; 4]) -> u8 {
        for (j, o) in out.iter_mut().enumerate() {
            let v = quad.pixel(j);
            let d = self.camera.ray_distance(Vec3::new(v[0], v[1], v[2]));
            *o = Vec4::new(d, 0.0, 0.0, 1.0);
        }
        quad.mask
    }
}

/// Per pixel (row-major, top row first), the distance along the pixel's ray (from the eye, or
/// for an orthographic camera from the eye's plane) to the nearest surface of `scene`;
/// infinite where no surface is drawn.
///
/// # Errors
/// [`Error::Parameter`] for a bad camera or size.
pub fn surface_distances(
    scene: &Scene,
    camera: &Camera,
    width: u32,
    height: u32,
) -> Result<Vec<f32>> {
    camera.validate()?;
    if width == 0 || height == 0 || width > 16384 || height > 16384 {
        return Err(Error::parameter(format!(
            "image size {width}x{height} is out of range"
        )));
    }
    let clip_from_world =
        camera.clip_from_view(width as f32 / height as f32) * camera.view_from_world();
    // Varyings: the world position (3 floats), for the eye distance.
    let vertices: Vec<Vec<ClipVertex>> = scene
        .meshes
        .iter()
        .map(|m| {
            m.positions
                .iter()
                .map(|p| {
                    let w = m.world_from_object.transform_point3(*p);
                    let mut v = [0.0f32; MAX_VARYINGS];
                    v[..3].copy_from_slice(&w.to_array());
                    ClipVertex {
                        clip: clip_from_world * w.extend(1.0),
                        varyings: v,
                    }
                })
                .collect()
        })
        .collect();
    let calls: Vec<DrawCall> = scene
        .meshes
        .iter()
        .zip(&vertices)
        .map(|(m, v)| DrawCall {
            vertices: v,
            indices: &m.indices,
            state: DrawState {
                varyings: 3,
                ..DrawState::default()
            },
        })
        .collect();
    let target = Target {
        width,
        height,
        samples: 1,
        clear_color: Vec4::new(f32::INFINITY, 0.0, 0.0, 1.0),
        interpolation: Interpolation::Perspective,
        depth_sort: false,
    };
    let shader = DistanceShader { camera: *camera };
    let (color, _) = pipeline::draw(&calls, &shader, &target);
    Ok(color.into_iter().map(|c| c.x).collect())
}

/// Renders `scene`'s surfaces with `settings`, then `vol` with rays stopped at those
/// surfaces, composited over them ("over", in the frame's linear colour).
///
/// # Errors
/// As [`render`] and [`raymarch()`].
pub fn render_with_meshes(
    scene: &Scene,
    vol: &Volume,
    tf: &TransferFunction,
    camera: &Camera,
    settings: &Settings,
    params: &MarchParams,
) -> Result<Frame> {
    let surfaces = render(scene, camera, settings)?;
    let depth = surface_distances(scene, camera, settings.width, settings.height)?;
    let volume = raymarch(
        vol,
        tf,
        camera,
        settings.width,
        settings.height,
        params,
        Some(&depth),
    )?;
    let color = volume
        .color
        .iter()
        .zip(&surfaces.color)
        .map(|(v, s)| *v + *s * (1.0 - v.w))
        .collect();
    Ok(Frame {
        color,
        stats: surfaces.stats,
        ..surfaces
    })
}

/// Renders `scene`'s surfaces with `settings` and every volume of `volumes` over them, each
/// with its own transfer function, options and method, rays (or slices) stopped at the
/// surfaces; farthest volume first. Without meshes the volumes are laid over the scene's
/// background, and no surface pass is drawn.
///
/// # Errors
/// As [`render`], [`raymarch()`] and [`crate::volume::render_slices`].
pub fn render_with_volumes(
    scene: &Scene,
    volumes: &[SceneVolume],
    camera: &Camera,
    settings: &Settings,
) -> Result<Frame> {
    let shadows = shadow_maps_with_fields(scene, volumes, camera, settings)?;
    render_with_volumes_shadowed(scene, volumes, camera, settings, &shadows)
}

/// [`render_with_volumes`] with shadow maps made before by
/// [`shadow_maps_with_fields`] for this scene, these volumes and settings (a turntable
/// makes them once): the meshes and the distance-field surfaces lit by the scene's lights
/// receive the shadows of both.
///
/// # Errors
/// As [`render_with_volumes`].
pub fn render_with_volumes_shadowed(
    scene: &Scene,
    volumes: &[SceneVolume],
    camera: &Camera,
    settings: &Settings,
    shadows: &ShadowMaps,
) -> Result<Frame> {
    let (w, h) = (settings.width, settings.height);
    let depth = if scene.meshes.is_empty() {
        None
    } else {
        Some(surface_distances(scene, camera, w, h)?)
    };
    let mut order: Vec<&SceneVolume> = volumes.iter().collect();
    // Farthest first, along the rays (from the eye, or its plane for orthographic cameras).
    order.sort_by(|a, b| {
        camera
            .ray_distance(b.centre())
            .total_cmp(&camera.ray_distance(a.centre()))
    });
    let mut frame: Option<Frame> = if scene.meshes.is_empty() && !volumes.is_empty() {
        None
    } else {
        let mut f = Frame::default();
        render_into_with_shadows(scene, camera, settings, shadows, &mut f)?;
        Some(f)
    };
    for v in order {
        let f = match v.method {
            Method::Raymarch | Method::Slices => {
                let method = if v.method == Method::Raymarch {
                    raymarch
                } else {
                    render_slices_until
                };
                method(
                    &v.volume,
                    &v.transfer,
                    camera,
                    w,
                    h,
                    &v.params,
                    depth.as_deref(),
                )?
            }
            Method::Surface | Method::Hypertexture => render_distance_field_shadowed(
                &v.volume,
                camera,
                w,
                h,
                &v.params,
                &v.look,
                v.hypertexture
                    .as_ref()
                    .filter(|_| v.method == Method::Hypertexture),
                depth.as_deref(),
                // The maps are the scene lights'; a volume lit otherwise (its headlight)
                // does not read them.
                (!v.params.lights.is_empty() && v.params.lights == scene.lights).then_some(shadows),
            )?,
        };
        frame = Some(match frame {
            None => {
                // The farthest volume over the background.
                let bg = scene.background;
                let bg = (bg.truncate() * bg.w).extend(bg.w);
                let mut f = f;
                for c in &mut f.color {
                    *c += bg * (1.0 - c.w);
                }
                f
            }
            Some(mut under) => {
                for (c, s) in under.color.iter_mut().zip(&f.color) {
                    *c = *s + *c * (1.0 - s.w);
                }
                under.stats.texture_samples += f.stats.texture_samples;
                under
            }
        });
    }
    frame.ok_or_else(|| Error::parameter("nothing to render"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Material, Mesh};
    use glam::Mat4;

    /// A square at y = `y` facing −y, covering x, z ∈ [lo, hi].
    fn square(y: f32, lo: f32, hi: f32) -> Mesh {
        Mesh {
            positions: vec![
                Vec3::new(lo, y, lo),
                Vec3::new(hi, y, lo),
                Vec3::new(hi, y, hi),
                Vec3::new(lo, y, hi),
            ],
            indices: vec![0, 1, 2, 0, 2, 3],
            world_from_object: Mat4::IDENTITY,
            ..Mesh::default()
        }
    }

    #[test]
    fn rays_stop_at_a_mesh_inside_the_scan() {
        // A uniform, semi-transparent 32³ volume; a square through its middle plane y = 15.5
        // covering the left half of x.
        let n = 32;
        let vol =
            Volume::from_scalars([n; 3], Mat4::IDENTITY, vec![1.0; (n * n * n) as usize]).unwrap();
        let tf = TransferFunction::parse("0:1,1,1,0.05;2:1,1,1,0.05").unwrap();
        let cam = vol.vtk_camera(1.6, 0.0);
        let scene = Scene {
            meshes: vec![square(15.5, -5.0, 15.5)],
            materials: vec![Material::default()],
            ambient_light: Vec3::ONE,
            ..Scene::default()
        };
        let (w, h) = (48, 48);
        let depth = surface_distances(&scene, &cam, w, h).unwrap();
        let p = MarchParams {
            jitter: false,
            ..MarchParams::default()
        };
        let alone = raymarch(&vol, &tf, &cam, w, h, &p, None).unwrap();
        let stopped = raymarch(&vol, &tf, &cam, w, h, &p, Some(&depth)).unwrap();
        let (mut covered, mut open) = (0, 0);
        for (i, &di) in depth.iter().enumerate() {
            if di.is_finite() {
                // The surface is at the eye distance of the plane y = 15.5 along this ray.
                let (o, d) = crate::volume::camera_ray(
                    &cam,
                    w,
                    h,
                    (i % w as usize) as f32 + 0.5,
                    (i / w as usize) as f32 + 0.5,
                );
                let expected = (15.5 - o.y) / d.y;
                assert!(
                    (depth[i] - expected).abs() < 1e-2 * expected,
                    "pixel {i}: {} vs {expected}",
                    depth[i]
                );
                // Part of the path through the volume: never more opacity than the whole path,
                // clearly less where the ray goes on through the volume behind the plane.
                assert!(stopped.color[i].w <= alone.color[i].w + 1e-6, "pixel {i}");
                if stopped.color[i].w < alone.color[i].w * 0.8 {
                    covered += 1;
                }
            } else {
                assert_eq!(stopped.color[i], alone.color[i]);
                open += 1;
            }
        }
        assert!(
            covered > 100 && open > 100,
            "{covered} covered, {open} open"
        );
        // And the composite shows the surface (lit white) where it is.
        let s = Settings::new(w, h);
        let f = render_with_meshes(&scene, &vol, &tf, &cam, &s, &p).unwrap();
        let i = depth.iter().position(|d| d.is_finite()).unwrap();
        assert!(f.color[i].w > 0.99, "{}", f.color[i]);
    }
}
