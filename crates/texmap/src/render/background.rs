//! The environment behind the surfaces: each pixel's camera ray reads the environment map
//! (with the ray's footprint, the pixel-to-pixel change of the direction), laid under the
//! drawn frame with premultiplied "under": `c + bg·(1 − a)`.
//!
//! Why after the pipeline and not as its clear colour: the pipeline clears to one constant,
//! and the background is a per-pixel image. It is composited at the frame's sample rate
//! before any box filter: with SSAA under every supersample (so the background is
//! supersampled like the surfaces), with MSAA under the resolved pixel — which equals blending
//! under each sample, since the resolve is a linear average and "under" is linear in `c` and
//! `a`. Pixels a surface covers entirely (`a = 1`) read nothing.
//!
//! A perspective camera's rays fan out (`d = forward + x·right + y·up` with the image plane at
//! distance 1); an orthographic camera's are parallel, so its background is the environment
//! along the view direction, one colour.

use glam::{Mat3, Vec3, Vec4};
use rayon::prelude::*;

use crate::camera::{Camera, CameraProjection};
use crate::shading::ibl::EnvLight;
use crate::texture::CubeFootprintLanes;

/// Lays the environment under `color` (`width × height`, premultiplied), seen by `camera`.
pub(super) fn composite_environment(
    color: &mut [Vec4],
    width: usize,
    height: usize,
    camera: &Camera,
    light: &EnvLight,
) {
    if width == 0 || height == 0 {
        return;
    }
    let world_from_view = Mat3::from_mat4(camera.view_from_world()).transpose();
    let aspect = width as f32 / height as f32;
    let (dx, dy, tan) = match camera.projection {
        CameraProjection::Perspective { fov_y_deg } => {
            let tan = (0.5 * fov_y_deg.to_radians()).tan();
            (
                world_from_view * Vec3::new(2.0 * tan * aspect / width as f32, 0.0, 0.0),
                world_from_view * Vec3::new(0.0, -2.0 * tan / height as f32, 0.0),
                tan,
            )
        }
        CameraProjection::Orthographic { .. } => (Vec3::ZERO, Vec3::ZERO, 0.0),
    };
    let forward = world_from_view * Vec3::NEG_Z;
    let right = world_from_view * Vec3::X;
    let up = world_from_view * Vec3::Y;
    color
        .par_chunks_mut(width)
        .enumerate()
        .for_each(|(y, row)| {
            let ndc_y = 1.0 - 2.0 * (y as f32 + 0.5) / height as f32;
            // Four pixels at a time (`background_lanes`: the same values as one by one), each
            // direction `forward + right·sx + up·sy` in that order, as for one pixel.
            let sy = ndc_y * tan;
            let derivative = |d: Vec3| [d.x, d.y, d.z].map(Vec4::splat);
            for (x0, group) in (0..).step_by(4).zip(row.chunks_mut(4)) {
                let mask =
                    group
                        .iter()
                        .enumerate()
                        .fold(0u8, |m, (j, c)| if c.w < 1.0 { m | 1 << j } else { m });
                if mask == 0 {
                    continue;
                }
                let sx = Vec4::from_array(std::array::from_fn(|j| {
                    let ndc_x = 2.0 * ((x0 + j) as f32 + 0.5) / width as f32 - 1.0;
                    ndc_x * tan * aspect
                }));
                let axis =
                    |c: usize| Vec4::splat(forward[c]) + sx * right[c] + Vec4::splat(up[c] * sy);
                let fp = CubeFootprintLanes {
                    dir: [axis(0), axis(1), axis(2)],
                    ddir_dx: derivative(dx),
                    ddir_dy: derivative(dy),
                };
                let bg = light.background_lanes(&fp, mask);
                for (j, c) in group.iter_mut().enumerate() {
                    if mask & (1 << j) != 0 {
                        *c += bg[j] * (1.0 - c.w);
                    }
                }
            }
        });
}
