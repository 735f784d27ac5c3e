//! `Interpolation::Subdivide` is watertight: neighbouring triangles split their shared edges
//! identically, so a closed mesh still covers every pixel (sample) exactly once, as in the
//! other interpolation modes (`tests/pipeline.rs`).

mod common;

use glam::{Mat4, Vec3, Vec4};
use texmap::camera::{Camera, CameraProjection};
use texmap::pipeline::{
    self, ClipVertex, CullMode, DrawCall, DrawState, FragmentShader, Interpolation, Quad, Target,
    MAX_VARYINGS,
};

/// Adds (1, 0, 0, 0) per covered sample: with premultiplied "over" and alpha 0 this counts.
struct Count;
impl FragmentShader for Count {
    fn shade(&self, _: u32, q: &Quad, out: &mut [Vec4; 4]) -> u8 {
        *out = [Vec4::new(1.0, 0.0, 0.0, 0.0); 4];
        q.mask
    }
}

fn camera(eye: Vec3, target: Vec3, near: f32) -> Camera {
    Camera {
        eye,
        target,
        up: Vec3::Y,
        projection: CameraProjection::Perspective { fov_y_deg: 60.0 },
        near,
        far: 100.0,
    }
}

/// Per pixel, how many times `positions`/`indices` cover its samples, averaged over the
/// samples by the resolve (a pixel whose samples are each covered once counts 1), and the
/// number of triangles rasterized.
fn count_hits(
    positions: &[Vec3],
    indices: &[u32],
    cam: &Camera,
    (w, h): (u32, u32),
    samples: u32,
    interpolation: Interpolation,
) -> (Vec<f32>, u64) {
    let clip_from_world = cam.clip_from_view(w as f32 / h as f32) * cam.view_from_world();
    // One varying, so subdivided vertices carry something to interpolate.
    let verts: Vec<ClipVertex> = positions
        .iter()
        .map(|p| {
            let mut var = [0.0; MAX_VARYINGS];
            var[0] = p.x;
            ClipVertex {
                clip: clip_from_world * p.extend(1.0),
                varyings: var,
            }
        })
        .collect();
    let call = DrawCall {
        vertices: &verts,
        indices,
        state: DrawState {
            varyings: 1,
            cull: CullMode::None,
            depth_test: false,
            depth_write: false,
            blend: true,
            ..Default::default()
        },
    };
    let target = Target {
        width: w,
        height: h,
        samples,
        clear_color: Vec4::ZERO,
        interpolation,
        depth_sort: false,
    };
    let (color, stats) = pipeline::draw(&[call], &Count, &target);
    (
        color.iter().map(|c| c.x).collect(),
        stats.triangles_after_clip,
    )
}

#[test]
fn subdivided_closed_mesh_inside_covers_every_pixel_once() {
    let (p, idx) = common::icosphere(3);
    for near in [0.05, 1e-4] {
        let cam = camera(
            Vec3::new(0.13, -0.21, 0.17),
            Vec3::new(0.9, 0.37, -1.0),
            near,
        );
        let size = (640, 400);
        let (_, clipped) = count_hits(&p, &idx, &cam, size, 1, Interpolation::Perspective);
        for max_error_px in [0.5, 0.1, 0.02] {
            for samples in [1, 16] {
                let (hits, pieces) = count_hits(
                    &p,
                    &idx,
                    &cam,
                    size,
                    samples,
                    Interpolation::Subdivide { max_error_px },
                );
                let bad = hits.iter().filter(|&&c| c != 1.0).count();
                assert_eq!(
                    bad, 0,
                    "near {near}, error {max_error_px}, {samples} samples: \
                     {bad} pixels not covered once ({pieces} pieces)"
                );
                // The mesh really was split.
                assert!(pieces > clipped, "{pieces} pieces, {clipped} unsplit");
            }
        }
    }
}

#[test]
fn subdivided_closed_mesh_outside_covers_pixels_zero_or_two_times() {
    let (p, idx) = common::icosphere(1);
    // Close to the sphere, so depth varies a lot across each triangle.
    let cam = camera(Vec3::new(0.3, 0.4, 1.35), Vec3::ZERO, 0.05);
    let (hits, _) = count_hits(
        &p,
        &idx,
        &cam,
        (640, 480),
        16,
        Interpolation::Subdivide { max_error_px: 0.05 },
    );
    // Each of a pixel's 16 samples is hit 0 or 2 times (front and back), so the pixel's sum
    // of hits, 16·value, is even (silhouette pixels mix 0s and 2s).
    let odd = hits
        .iter()
        .filter(|&&c| !((c * 16.0).round() as u32).is_multiple_of(2))
        .count();
    assert_eq!(
        odd, 0,
        "{odd} pixels with a sample hit an odd number of times"
    );
    assert!(hits.iter().filter(|&&c| c == 2.0).count() > 640 * 480 / 4);
}

#[test]
fn a_floor_grid_across_the_depth_range_has_no_cracks() {
    // A 200×200 floor of 8×8 quads seen from 1 unit above at a grazing angle: its triangles
    // run from the camera's feet to the horizon and split their shared edges many times.
    let n = 8;
    let model = Mat4::from_rotation_y(0.4);
    let mut positions = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let p = Vec3::new(i as f32 / n as f32 - 0.5, 0.0, j as f32 / n as f32 - 0.5) * 200.0;
            positions.push(model.transform_point3(p));
        }
    }
    let mut idx = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let (a, b) = (j * (n + 1) + i, j * (n + 1) + i + 1);
            let (c, d) = (a + n + 1, b + n + 1);
            // Alternate the diagonal, so neighbours split differently.
            if (i + j) % 2 == 0 {
                idx.extend([a, c, d, a, d, b]);
            } else {
                idx.extend([a, c, b, b, c, d]);
            }
        }
    }
    let cam = camera(Vec3::new(0.0, 1.0, 0.0), Vec3::new(0.0, 0.6, -5.0), 0.05);
    let size = (640, 360);
    let (reference, _) = count_hits(&positions, &idx, &cam, size, 4, Interpolation::Perspective);
    let (hits, pieces) = count_hits(
        &positions,
        &idx,
        &cam,
        size,
        4,
        Interpolation::Subdivide { max_error_px: 0.25 },
    );
    assert!(pieces > 1000, "{pieces} pieces");
    let over = hits.iter().filter(|&&c| c > 1.0).count();
    assert_eq!(over, 0, "{over} pixels hit twice somewhere");
    // Inside the floor (a pixel whose neighbours are all covered in the perspective image) no
    // sample is missed; only the outline may move by the snapping of split points.
    let (w, h) = (size.0 as i32, size.1 as i32);
    let covered = |x: i32, y: i32| {
        x < 0 || y < 0 || x >= w || y >= h || reference[(y * w + x) as usize] == 1.0
    };
    let mut inside = 0;
    let mut missed = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let interior = (-1..=1).all(|dy| (-1..=1).all(|dx| covered(x + dx, y + dy)));
            if interior {
                inside += 1;
                if hits[(y * w + x) as usize] != 1.0 {
                    missed.push((x, y));
                }
            }
        }
    }
    assert!(
        missed.is_empty(),
        "{} pixels missed, first {:?}",
        missed.len(),
        missed.first()
    );
    assert!(inside > (w * h / 3) as usize, "{inside}");
}
