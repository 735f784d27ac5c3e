//! Rays: from the camera through a pixel, clipped to the volume's box, and the sample
//! positions along them.
//!
//! Rules:
//! - Perspective rays start at the eye; orthographic rays start on the plane through the eye
//!   perpendicular to the view direction, and all run along it. A distance along a ray is
//!   world units from its start (what a depth buffer of surfaces holds for the volumes:
//!   [`ray_distances_from_depth`], `Camera::ray_distance`).
//! - A ray taken to voxel space keeps its parameter (`o' = M·o`, `d' = M·d` for the affine
//!   `M = voxel_from_world`), so steps and stops stay world lengths.
//! - Samples sit at `t_entry + (k + j)·step`, `j ∈ [0, 1)` a hash of the pixel (jitter; 0 when
//!   off): the same pixel always gets the same offset, whatever the thread count, and
//!   nothing (skipping, early termination) moves a sample.

use glam::{Mat4, Vec3};

use crate::camera::{Camera, CameraProjection};

/// A per-pixel hash in [0, 1) (jitter): the same pixel always gets the same value.
#[inline]
#[must_use]
pub(crate) fn pixel_hash(x: u32, y: u32) -> f32 {
    let mut h = x.wrapping_mul(0x8da6_b343) ^ y.wrapping_mul(0xd816_3841) ^ 0x9e37_79b9;
    h ^= h >> 16;
    h = h.wrapping_mul(0x7feb_352d);
    h ^= h >> 15;
    h = h.wrapping_mul(0x846c_a68b);
    h ^= h >> 16;
    (h >> 8) as f32 / (1u32 << 24) as f32
}

/// A camera ray for pixel `(x, y)`: origin and unit direction in world space. Perspective
/// rays start at the eye; orthographic rays start on the plane through the eye perpendicular
/// to the view direction and all run along it.
#[inline]
#[must_use]
pub fn camera_ray(cam: &Camera, width: u32, height: u32, x: f32, y: f32) -> (Vec3, Vec3) {
    CameraRays::new(cam, width, height).ray(x, y)
}

/// [`camera_ray`] for many pixels of one frame: the camera's basis and the view's tangent
/// made once (a `tan` and three normalizations a pixel otherwise), each ray the same bits.
#[derive(Clone, Copy, Debug)]
pub(crate) struct CameraRays {
    eye: Vec3,
    /// View direction, right and up (unit).
    f: Vec3,
    r: Vec3,
    u: Vec3,
    /// Half the image height: at unit distance (perspective) or in world units (orthographic).
    th: f32,
    aspect: f32,
    width: f32,
    height: f32,
    ortho: bool,
}

impl CameraRays {
    pub fn new(cam: &Camera, width: u32, height: u32) -> Self {
        let f = (cam.target - cam.eye).normalize();
        let r = f.cross(cam.up).normalize();
        let u = r.cross(f);
        let aspect = width as f32 / height as f32;
        let (th, ortho) = match cam.projection {
            CameraProjection::Perspective { fov_y_deg } => {
                ((fov_y_deg.to_radians() * 0.5).tan(), false)
            }
            CameraProjection::Orthographic { half_height } => (half_height, true),
        };
        CameraRays {
            eye: cam.eye,
            f,
            r,
            u,
            th,
            aspect,
            width: width as f32,
            height: height as f32,
            ortho,
        }
    }

    /// The ray through image point `(x, y)` (pixels): origin and unit direction.
    #[inline]
    pub fn ray(&self, x: f32, y: f32) -> (Vec3, Vec3) {
        let sx = (2.0 * x / self.width - 1.0) * self.th * self.aspect;
        let sy = (1.0 - 2.0 * y / self.height) * self.th;
        if self.ortho {
            (self.eye + self.r * sx + self.u * sy, self.f)
        } else {
            (self.eye, (self.f + self.r * sx + self.u * sy).normalize())
        }
    }
}

/// The distance along each pixel's ray at which `depth_window` (window depth in [0, 1],
/// OpenGL projection of `camera`, 1 = nothing) lies: the `depth` argument of
/// [`raymarch`](super::raymarch::raymarch).
#[must_use]
pub fn ray_distances_from_depth(
    camera: &Camera,
    width: u32,
    height: u32,
    depth_window: &[f32],
) -> Vec<f32> {
    let (n, f) = (camera.near, camera.far);
    let fwd = (camera.target - camera.eye).normalize();
    let w = width as usize;
    let ortho = camera.projection.is_orthographic();
    let rays = CameraRays::new(camera, width, height);
    depth_window
        .iter()
        .enumerate()
        .map(|(i, &z)| {
            if z >= 1.0 {
                return f32::INFINITY;
            }
            let zn = z * 2.0 - 1.0;
            // Distance along the view direction: GL's projections inverted.
            let view_z = if ortho {
                0.5 * (zn * (f - n) + f + n)
            } else {
                2.0 * n * f / (f + n - zn * (f - n))
            };
            let (_, d) = rays.ray((i % w) as f32 + 0.5, (i / w) as f32 + 0.5);
            view_z / d.dot(fwd)
        })
        .collect()
}

/// A ray in voxel space: `origin + dir·t`, `t` the world ray's parameter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct VoxelRay {
    pub origin: Vec3,
    pub dir: Vec3,
}

impl VoxelRay {
    /// The world ray `eye + dir·t` in voxel space.
    #[inline]
    pub fn new(voxel_from_world: &Mat4, eye: Vec3, dir: Vec3) -> Self {
        VoxelRay {
            origin: voxel_from_world.transform_point3(eye),
            dir: voxel_from_world.transform_vector3(dir),
        }
    }

    /// The point at parameter `t`.
    #[inline(always)]
    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + self.dir * t
    }
}

/// The part of a ray inside the box: from `t0` to `t1` (`t0 < t1`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Span {
    pub t0: f32,
    pub t1: f32,
}

/// Where `ray` enters and leaves the box `[lo, hi]` (slabs), cut at `t_max`; `None` when it
/// misses the box or the box lies past `t_max`.
pub(crate) fn clip_to_box(ray: &VoxelRay, t_max: f32, lo: Vec3, hi: Vec3) -> Option<Span> {
    let (o, d) = (ray.origin, ray.dir);
    let (mut t0, mut t1) = (0.0f32, t_max);
    for a in 0..3 {
        if d[a].abs() < 1e-12 {
            if o[a] < lo[a] || o[a] > hi[a] {
                return None;
            }
            continue;
        }
        let inv = 1.0 / d[a];
        let (mut ta, mut tb) = ((lo[a] - o[a]) * inv, (hi[a] - o[a]) * inv);
        if ta > tb {
            std::mem::swap(&mut ta, &mut tb);
        }
        t0 = t0.max(ta);
        t1 = t1.min(tb);
    }
    (t0 < t1).then_some(Span { t0, t1 })
}

/// The sample positions of one ray across its span: sample `k < count` sits at
/// [`Self::t`]`(k) = t0 + (k + jitter)·step`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct RaySamples {
    pub ray: VoxelRay,
    pub t0: f32,
    pub step: f32,
    /// `1 / step`.
    pub inv_step: f32,
    pub jitter: f32,
    pub count: u32,
}

impl RaySamples {
    /// The samples of `span`, counted as `⌊(t1 − t0)/step − jitter⌋ + 1`.
    #[inline]
    pub fn new(ray: VoxelRay, span: Span, step: f32, jitter: f32) -> Self {
        let count = sample_count((span.t1 - span.t0) / step, jitter);
        Self::with_count(ray, span, step, jitter, count)
    }

    /// [`Self::new`] with the span multiplied by `1/step` instead of divided by `step`: the
    /// specialised composite loop's count. The two can differ by one sample lying on the
    /// span's end within rounding, so each loop keeps its own to leave every image as it was.
    #[inline]
    pub fn by_reciprocal(ray: VoxelRay, span: Span, step: f32, jitter: f32) -> Self {
        let count = sample_count((span.t1 - span.t0) * (1.0 / step), jitter);
        Self::with_count(ray, span, step, jitter, count)
    }

    #[inline(always)]
    fn with_count(ray: VoxelRay, span: Span, step: f32, jitter: f32, count: u32) -> Self {
        RaySamples {
            ray,
            t0: span.t0,
            step,
            inv_step: 1.0 / step,
            jitter,
            count,
        }
    }

    /// The ray parameter of sample `k`.
    #[inline(always)]
    pub fn t(&self, k: u32) -> f32 {
        self.t0 + (k as f32 + self.jitter) * self.step
    }

    /// The voxel-space position of sample `k`.
    #[inline(always)]
    pub fn at(&self, k: u32) -> Vec3 {
        self.ray.at(self.t(k))
    }
}

/// Samples `k ≥ 0` with `k + jitter ≤ steps`.
#[inline(always)]
fn sample_count(steps: f32, jitter: f32) -> u32 {
    ((steps - jitter).floor().max(-1.0) as i64 + 1).max(0) as u32
}

#[cfg(test)]
mod tests {
    use super::{camera_ray, ray_distances_from_depth};
    use crate::camera::{Camera, CameraProjection};
    use glam::Vec3;

    #[test]
    fn window_depth_converts_back_to_the_ray_distance() {
        let cam = Camera {
            eye: Vec3::new(1.0, 2.0, 30.0),
            target: Vec3::new(0.0, 0.0, 0.0),
            up: Vec3::Y,
            projection: CameraProjection::Perspective { fov_y_deg: 40.0 },
            near: 0.5,
            far: 200.0,
        };
        let (w, h) = (8u32, 6u32);
        let clip_from_world = cam.clip_from_view(w as f32 / h as f32) * cam.view_from_world();
        let mut window = Vec::new();
        let mut expected = Vec::new();
        for i in 0..(w * h) {
            let (o, d) = camera_ray(&cam, w, h, (i % w) as f32 + 0.5, (i / w) as f32 + 0.5);
            let t = 10.0 + i as f32;
            let c = clip_from_world * (o + d * t).extend(1.0);
            window.push(c.z / c.w * 0.5 + 0.5);
            expected.push(t);
        }
        let got = ray_distances_from_depth(&cam, w, h, &window);
        for (g, e) in got.iter().zip(&expected) {
            assert!((g - e).abs() < 1e-2 * e, "{g} vs {e}");
        }
        assert!(ray_distances_from_depth(&cam, 1, 1, &[1.0])[0].is_infinite());
    }
}
