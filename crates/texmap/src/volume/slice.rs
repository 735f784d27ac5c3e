//! Texture-based volume rendering, the hardware method of Miller & Jones: planes
//! perpendicular to the view direction, `step` apart, are cut with the volume's box; each
//! cut polygon is drawn through the texmap pipeline ([`crate::pipeline::draw`]: clipping,
//! fixed-point setup, tiles, perspective-correct varyings), its fragments read the 3D texture
//! through the texture engine ([`crate::texture::sample_3d`], trilinear), classify, and blend
//! "over" back to front.
//!
//! Rules:
//! - Slices sit at view depths `d_min + (k + ½)·step` (d along the view direction from the
//!   eye) and are submitted far to near: the pipeline draws a blended call's triangles in
//!   index order.
//! - Opacity is corrected per fragment for the distance between two slices along that
//!   pixel's ray, `step / cos θ`, so slices and rays agree off the image centre too.
//! - Only composite mode exists here (blending is "over"); MIP, iso and X-ray are ray modes.

use glam::{Mat4, Vec3, Vec4};

use super::grid::Volume;
use super::normals::{central_difference, trilinear_normal};
use super::output::{check_request, display_to_frame};
use super::params::{Classification, MarchParams, Mode};
use super::shade::VolumeLights;
use super::transfer::{correct_opacity, gradient_factor, TransferFunction};
use crate::camera::Camera;
use crate::frame::{Frame, FrameStats};
use crate::pipeline::{
    self, ClipVertex, DrawCall, DrawState, FragmentShader, Interpolation, Quad, Target,
    MAX_VARYINGS,
};
use crate::shading::Viewer;
use crate::texture::{sample_3d, Filter, Footprint3, Sampler, Wrap};
use crate::{Error, Result};

/// One convex cut of the box by a plane, world space, in order around the polygon.
pub type SlicePolygon = Vec<Vec3>;

/// Cuts the box (world corners of `vol`) with the plane `{x : (x − eye)·f = d}`.
#[must_use]
pub fn slice_polygon(corners: &[Vec3; 8], eye: Vec3, f: Vec3, d: f32) -> SlicePolygon {
    const EDGES: [(usize, usize); 12] = [
        (0, 1),
        (2, 3),
        (4, 5),
        (6, 7), // x edges
        (0, 2),
        (1, 3),
        (4, 6),
        (5, 7), // y edges
        (0, 4),
        (1, 5),
        (2, 6),
        (3, 7), // z edges
    ];
    let s: [f32; 8] = std::array::from_fn(|i| (corners[i] - eye).dot(f) - d);
    let mut pts: Vec<Vec3> = Vec::with_capacity(6);
    for (a, b) in EDGES {
        let (sa, sb) = (s[a], s[b]);
        if (sa < 0.0) != (sb < 0.0) {
            let t = sa / (sa - sb);
            pts.push(corners[a].lerp(corners[b], t));
        }
    }
    if pts.len() < 3 {
        return Vec::new();
    }
    // Order by angle about the centroid, in the plane.
    let c = pts.iter().copied().sum::<Vec3>() / pts.len() as f32;
    let u = (pts[0] - c).normalize_or_zero();
    let v = f.cross(u);
    pts.sort_by(|p, q| {
        let ap = (p - c).dot(v).atan2((p - c).dot(u));
        let aq = (q - c).dot(v).atan2((q - c).dot(u));
        ap.total_cmp(&aq)
    });
    pts
}

struct SliceShader<'a> {
    vol: &'a Volume,
    tf: &'a TransferFunction,
    sampler: Sampler,
    inv_n: Vec3,
    step: f32,
    camera: Camera,
    viewer: Viewer,
    fwd: Vec3,
    shade: bool,
    lights: VolumeLights,
    gradient_opacity: &'a [(f32, f32)],
    grad_to_world: glam::Mat3,
    /// Per pixel, the ray distance where rays stop (surfaces in front), and the image width.
    depth: Option<(&'a [f32], u32)>,
}

impl SliceShader<'_> {
    fn value(&self, q: Vec3) -> f32 {
        let level = sample_3d(
            self.vol.texture(),
            &self.sampler,
            &Footprint3::point((q + 0.5) * self.inv_n),
        )
        .x;
        self.vol.value_of(level * 65535.0)
    }
}

impl FragmentShader for SliceShader<'_> {
    fn shade(&self, _draw: u32, quad: &Quad, out: &mut [Vec4; 4]) -> u8 {
        let mut kept = 0u8;
        for (j, o) in out.iter_mut().enumerate() {
            if quad.mask & (1 << j) == 0 {
                continue;
            }
            let vy = quad.pixel(j);
            let q = Vec3::new(vy[0], vy[1], vy[2]);
            let world = Vec3::new(vy[3], vy[4], vy[5]);
            if let Some((depth, width)) = self.depth {
                // Behind a surface: the ray stopped there.
                let (x, y) = (quad.x + (j as u32 & 1), quad.y + (j as u32 >> 1));
                let stop = depth
                    .get((y * width + x) as usize)
                    .copied()
                    .unwrap_or(f32::INFINITY);
                if self.camera.ray_distance(world) > stop {
                    continue;
                }
            }
            let c = self.tf.eval(self.value(q));
            if c.w <= 0.0 {
                continue;
            }
            let dir = -self.viewer.towards(world);
            let cos = dir.dot(self.fwd).max(1e-3);
            let mut a = correct_opacity(c.w, self.step / cos);
            let mut rgb = c.truncate();
            if self.shade && self.gradient_opacity.is_empty() {
                // The marcher's normals (interpolated per-voxel normals), so both methods shade alike.
                let g = trilinear_normal(self.vol.normals(), self.vol.dims(), q);
                rgb = self.lights.shade(rgb, g, self.fwd, || world);
            } else if self.shade || !self.gradient_opacity.is_empty() {
                let g = self.grad_to_world * central_difference(|p| self.value(p), q);
                if !self.gradient_opacity.is_empty() {
                    a *= gradient_factor(self.gradient_opacity, g.length());
                }
                if self.shade {
                    rgb = self.lights.shade(rgb, g, self.fwd, || world);
                }
            }
            *o = (rgb * a).extend(a);
            kept |= 1 << j;
        }
        kept
    }
}

/// Renders `vol` with view-aligned slices through the pipeline (composite mode only;
/// post-classification), in rayon's current pool. Same frame conventions as
/// [`raymarch`](super::raymarch::raymarch).
///
/// # Errors
/// [`Error::Parameter`] for a bad camera, size or step; [`Error::Unsupported`] for a mode
/// other than composite or a classification other than post.
pub fn render_slices(
    vol: &Volume,
    tf: &TransferFunction,
    camera: &Camera,
    width: u32,
    height: u32,
    params: &MarchParams,
) -> Result<Frame> {
    render_slices_until(vol, tf, camera, width, height, params, None)
}

/// [`render_slices`] with the rays stopped at `depth` (per pixel, row-major, the eye
/// distance of the surface in front, as [`raymarch`](super::raymarch::raymarch)'s
/// `depth`): fragments farther than their pixel's distance are dropped.
///
/// # Errors
/// As [`render_slices`], and [`Error::Parameter`] for a depth buffer of the wrong length.
pub fn render_slices_until(
    vol: &Volume,
    tf: &TransferFunction,
    camera: &Camera,
    width: u32,
    height: u32,
    params: &MarchParams,
    depth: Option<&[f32]>,
) -> Result<Frame> {
    check_request(camera, width, height, params, depth)?;
    params.check_crop(vol.dims()).map_err(Error::Parameter)?;
    if params.mode != Mode::Composite || params.classification != Classification::Post {
        return Err(Error::Unsupported(
            "--method slices renders composite mode with post-classification only".into(),
        ));
    }
    let fwd = (camera.target - camera.eye).normalize();
    let corners = vol.world_corners_of(params.voxel_box(vol.dims()));
    let depths: Vec<f32> = corners.iter().map(|c| (*c - camera.eye).dot(fwd)).collect();
    let d_min = depths
        .iter()
        .copied()
        .fold(f32::INFINITY, f32::min)
        .max(camera.near);
    let d_max = depths
        .iter()
        .copied()
        .fold(f32::NEG_INFINITY, f32::max)
        .min(camera.far);
    let count = ((d_max - d_min) / params.step).floor().max(0.0) as usize;
    if count > 1_000_000 {
        return Err(Error::parameter(format!(
            "--step {} makes {count} slices",
            params.step
        )));
    }
    let aspect = width as f32 / height as f32;
    let clip_from_world: Mat4 = camera.clip_from_view(aspect) * camera.view_from_world();
    let voxel_from_world = vol.world_from_voxel().inverse();
    let mut vertices: Vec<ClipVertex> = Vec::new();
    let mut indices: Vec<u32> = Vec::new();
    for k in (0..count).rev() {
        let d = d_min + (k as f32 + 0.5) * params.step;
        let poly = slice_polygon(&corners, camera.eye, fwd, d);
        if poly.len() < 3 {
            continue;
        }
        let base = vertices.len() as u32;
        for p in &poly {
            let q = voxel_from_world.transform_point3(*p);
            let mut v = [0.0f32; MAX_VARYINGS];
            v[..3].copy_from_slice(&q.to_array());
            v[3..6].copy_from_slice(&p.to_array());
            vertices.push(ClipVertex {
                clip: clip_from_world * p.extend(1.0),
                varyings: v,
            });
        }
        for i in 1..poly.len() as u32 - 1 {
            indices.extend([base, base + i, base + i + 1]);
        }
    }
    let shader = SliceShader {
        vol,
        tf,
        sampler: Sampler::new(Filter::BILINEAR, Wrap::ClampToEdge),
        inv_n: Vec3::from_array(vol.dims().map(|n| 1.0 / n as f32)),
        step: params.step,
        camera: *camera,
        viewer: camera.viewer(),
        fwd,
        shade: params.shade,
        lights: VolumeLights::new(params.reflectance, &params.lights),
        gradient_opacity: &params.gradient_opacity,
        grad_to_world: glam::Mat3::from_mat4(voxel_from_world).transpose(),
        depth: depth.map(|d| (d, width)),
    };
    let call = DrawCall {
        vertices: &vertices,
        indices: &indices,
        state: DrawState {
            varyings: 6,
            depth_test: false,
            depth_write: false,
            blend: true,
            texture_reads: 1,
            ..DrawState::default()
        },
    };
    let target = Target {
        width,
        height,
        samples: 1,
        clear_color: Vec4::ZERO,
        interpolation: Interpolation::Perspective,
        depth_sort: false,
    };
    let (mut color, st) = pipeline::draw(&[call], &shader, &target);
    for c in color.iter_mut() {
        *c = display_to_frame(*c);
    }
    Ok(Frame {
        width,
        height,
        color,
        stats: FrameStats {
            triangles_submitted: st.triangles_submitted,
            triangles_after_clip: st.triangles_after_clip,
            pixels_shaded: st.pixels_shaded,
            texture_samples: st.texture_samples,
            ..FrameStats::default()
        },
    })
}
