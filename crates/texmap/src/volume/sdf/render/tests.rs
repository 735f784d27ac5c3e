//! The tracer's settings against the march they stand for.

use glam::{DVec3, Vec3};

use super::super::{shape_field, FieldGrid, Hypertexture, Shape, SurfaceLook};
use super::{render_distance_field, CameraRays, Tracer};
use crate::camera::{Camera, CameraProjection};
use crate::volume::params::MarchParams;

/// A 40³ field of a ball of radius 0.6 at the origin.
fn ball() -> crate::volume::Volume {
    let n = 40;
    let h = 2.0 / f64::from(n);
    let grid = FieldGrid::axis_aligned([n; 3], DVec3::splat(-1.0 + 0.5 * h), DVec3::splat(h));
    let shape = Shape::Sphere {
        center: DVec3::ZERO,
        radius: 0.6,
    };
    shape_field(&shape, &grid)
        .to_volume()
        .expect("a small field")
}

/// A 40° perspective camera at `eye` looking at the origin.
fn camera(eye: Vec3) -> Camera {
    Camera {
        eye,
        target: Vec3::ZERO,
        up: Vec3::Y,
        projection: CameraProjection::Perspective { fov_y_deg: 40.0 },
        near: 0.1,
        far: 100.0,
    }
}

/// The ball seen from above and aside, unjittered, with the default look: the switches'
/// tests' scene.
fn unjittered() -> (crate::volume::Volume, Camera, MarchParams, SurfaceLook) {
    let params = MarchParams {
        jitter: false,
        ..MarchParams::default()
    };
    (
        ball(),
        camera(Vec3::new(0.4, 0.8, 2.4)),
        params,
        SurfaceLook::default(),
    )
}

#[test]
fn without_the_tail_the_image_is_the_march_without_extrapolation() {
    let (vol, cam, params, look) = unjittered();
    let (w, h) = (48, 48);
    for preset in ["smoke", "fur"] {
        let on = Hypertexture::preset(preset).expect("a preset");
        let mut off = on.clone();
        off.set("tail", "off").expect("a value");
        let marched = render_distance_field(&vol, &cam, w, h, &params, &look, Some(&off), None)
            .expect("a frame");
        // The reference: the default's tracer with its extrapolation switched off by hand.
        let mut tr = Tracer::new(&vol, &cam, h, &params, &look, Some(&on));
        tr.tail_from = f32::INFINITY;
        assert_eq!(traced(&tr, &cam, w, h), marched.color, "{preset}");
        // The default extrapolates here (the test can fail).
        let tailed = render_distance_field(&vol, &cam, w, h, &params, &look, Some(&on), None)
            .expect("a frame");
        assert_ne!(tailed.color, marched.color, "{preset}: no ray extrapolated");
    }
}

/// `trace` of every pixel of a `w × h` frame by `tr`, unjittered.
fn traced(tr: &Tracer<'_>, cam: &Camera, w: u32, h: u32) -> Vec<glam::Vec4> {
    let rays = CameraRays::new(cam, w, h);
    let mut out = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let (o, d) = rays.ray(x as f32 + 0.5, y as f32 + 0.5);
            out.push(tr.trace(o, d, f32::INFINITY, 0.0).0);
        }
    }
    out
}

#[test]
fn wide_steps_are_the_march_taking_every_second_point_from_their_opacity() {
    let (vol, cam, params, look) = unjittered();
    let (w, h) = (48, 48);
    for preset in ["smoke", "fire"] {
        let on = Hypertexture::preset(preset).expect("a preset");
        assert!(on.wide < 1.0, "{preset}: wide by default");
        let mut off = on.clone();
        off.set("wide", "off").expect("a value");
        assert_eq!(off.wide, 1.0);
        let single = render_distance_field(&vol, &cam, w, h, &params, &look, Some(&off), None)
            .expect("a frame");
        // `off` is the default's tracer with its wide steps switched off by hand.
        let mut tr = Tracer::new(&vol, &cam, h, &params, &look, Some(&on));
        tr.wide_from = f32::INFINITY;
        assert_eq!(traced(&tr, &cam, w, h), single.color, "{preset}");
        // The default widens here: fewer reads, the same picture within a margin.
        let wide = render_distance_field(&vol, &cam, w, h, &params, &look, Some(&on), None)
            .expect("a frame");
        assert_ne!(wide.color, single.color, "{preset}: no ray widened");
        let (a, b) = (
            wide.stats.texture_samples as f64,
            single.stats.texture_samples as f64,
        );
        // Smoke's dense material widens most rays; fire's glow few on this small ball.
        let most = if preset == "smoke" { 0.97 } else { 1.0 };
        assert!(a < most * b, "{preset}: {a} reads against {b}");
        // RMSE over the channels (linear, premultiplied; fire glows up to 2). Measured:
        // smoke 0.004, fire 0.010.
        let sq: f64 = wide
            .color
            .iter()
            .zip(&single.color)
            .map(|(p, q)| f64::from((*p - *q).length_squared()))
            .sum();
        let rmse = (sq / (4 * wide.color.len()) as f64).sqrt();
        assert!(rmse < 0.02, "{preset}: RMSE {rmse}");
    }
}

#[test]
fn the_melted_cores_own_loop_and_its_pairs_are_the_generic_march() {
    let vol = ball();
    let cam = camera(Vec3::new(0.3, 0.5, 2.6));
    let (w, h) = (40, 40);
    let params = MarchParams::default();
    let look = SurfaceLook::default();
    let mut melt = Hypertexture::preset("melt").expect("a preset");
    melt.set("time", "0.8").expect("a value");
    for depth_only in [false, true] {
        let mut tr = Tracer::new(&vol, &cam, h, &params, &look, Some(&melt));
        tr.depth_only = depth_only;
        let warp = tr.warp.as_ref().expect("a melted core's lattice");
        let rays = CameraRays::new(&cam, w, h);
        let mut hits = 0;
        for y in 0..h {
            for x in 0..w {
                let (o, d) = rays.ray(x as f32 + 0.5, y as f32 + 0.5);
                let own = tr.march_melted(warp, o, d, f32::INFINITY);
                let generic = tr.march::<{ super::kind::GENERIC }>(o, d, f32::INFINITY, 0.0, None);
                assert_eq!(own.0, generic.0, "colour at {x}, {y}");
                assert_eq!(own.1, generic.1, "reads at {x}, {y}");
                assert_eq!(own.2.to_bits(), generic.2.to_bits(), "hit at {x}, {y}");
                hits += usize::from(own.2.is_finite());
                // Two rays marched in turn take each one's own steps.
                let (o2, d2) = rays.ray(x as f32 + 0.5, (h - 1 - y) as f32 + 0.5);
                let pair =
                    tr.march_melted_pair(warp, [(o, d, f32::INFINITY), (o2, d2, f32::INFINITY)]);
                let other = tr.march_melted(warp, o2, d2, f32::INFINITY);
                for (got, want) in pair.iter().zip([own, other]) {
                    assert_eq!(got.0, want.0, "pair colour at {x}, {y}");
                    assert_eq!(got.1, want.1, "pair reads at {x}, {y}");
                    assert_eq!(got.2.to_bits(), want.2.to_bits(), "pair hit at {x}, {y}");
                }
            }
        }
        assert!(hits > 100, "{hits} rays met the melted ball");
    }
}

#[test]
fn core_crossings_are_placed_within_the_tolerance() {
    // False position from the last sample's distance: the hit is within half the tolerance
    // (1/100 voxel) of a point outside and one inside, for the plain surface, a material
    // with a core (fire, fur) and jittered grids.
    let vol = ball();
    let cam = camera(Vec3::new(0.3, 0.5, 2.6));
    let (w, h) = (40, 40);
    let look = SurfaceLook::default();
    for preset in [None, Some("fire"), Some("fur")] {
        let hyper = preset.map(|p| Hypertexture::preset(p).expect("a preset"));
        for jitter in [0.0, 0.37] {
            let params = MarchParams::default();
            let tr = Tracer::new(&vol, &cam, h, &params, &look, hyper.as_ref());
            let tol = 0.01 * tr.field.voxel;
            let rays = CameraRays::new(&cam, w, h);
            let mut hits = 0;
            for y in 0..h {
                for x in 0..w {
                    let (o, d) = rays.ray(x as f32 + 0.5, y as f32 + 0.5);
                    let hit = tr.trace(o, d, f32::INFINITY, jitter).2;
                    if !hit.is_finite() {
                        continue;
                    }
                    hits += 1;
                    let at = |t: f32| tr.core_distance(o + d * t);
                    assert!(at(hit - 0.5 * tol) > 0.0, "{preset:?}: outside at {x}, {y}");
                    assert!(at(hit + 0.5 * tol) <= 0.0, "{preset:?}: inside at {x}, {y}");
                }
            }
            // Fur's strands stop most rays before the core.
            let least = if preset == Some("fur") { 1 } else { 200 };
            assert!(hits >= least, "{preset:?}: {hits} rays met the ball");
        }
    }
}

#[test]
fn the_ways_in_two_at_a_time_are_each_rays_own_march() {
    let vol = ball();
    let cam = camera(Vec3::new(0.3, 0.5, 2.6));
    let (w, h) = (40, 40);
    let look = SurfaceLook::default();
    let params = MarchParams::default();
    for preset in ["fur", "fire", "smoke"] {
        let hyper = Hypertexture::preset(preset).expect("a preset");
        let tr = Tracer::new(&vol, &cam, h, &params, &look, Some(&hyper));
        assert!(tr.kind & super::kind::PLAIN != 0, "{preset}: a plain kind");
        let rays = CameraRays::new(&cam, w, h);
        let ray = |x: u32, y: u32| {
            let (o, d) = rays.ray(x as f32 + 0.5, y as f32 + 0.5);
            (o, d, f32::INFINITY)
        };
        let (mut resumed, mut ended) = (0, 0);
        for y in 0..h {
            for x in 0..w {
                // This ray beside another from across the frame (unlike ways, unlike ends).
                let pair = [ray(x, y), ray(w - 1 - x, (y * 7) % h)];
                let jitters = [0.31, 0.77];
                let ways = tr.approach_pair(pair);
                for ((way, (o, d, t_max)), j) in ways.into_iter().zip(pair).zip(jitters) {
                    let want = tr.trace(o, d, t_max, j);
                    let got = match way {
                        super::approach::Approached::Ended(n) => {
                            ended += 1;
                            (glam::Vec4::ZERO, n, f32::INFINITY)
                        }
                        super::approach::Approached::At(s) => {
                            resumed += 1;
                            tr.trace_from(o, d, t_max, j, Some(s))
                        }
                    };
                    assert_eq!(got.0, want.0, "{preset}: colour at {x}, {y}");
                    assert_eq!(got.1, want.1, "{preset}: reads at {x}, {y}");
                    assert_eq!(
                        got.2.to_bits(),
                        want.2.to_bits(),
                        "{preset}: hit at {x}, {y}"
                    );
                }
            }
        }
        assert!(
            resumed > 500 && ended > 500,
            "{preset}: {resumed} resumed, {ended} ended"
        );
    }
}

#[test]
fn a_field_longer_than_its_reads_take_is_refused() {
    // 2^24 + 1 voxels along x: read as empty, it would draw nothing; the render refuses it.
    let n = super::super::reader::MAX_AXIS + 1;
    let vol =
        crate::volume::Volume::from_scalars([n, 1, 1], glam::Mat4::IDENTITY, vec![1.0; n as usize])
            .expect("a long, thin field");
    let cam = camera(Vec3::new(0.0, 0.0, 5.0));
    let err = render_distance_field(
        &vol,
        &cam,
        4,
        4,
        &MarchParams::default(),
        &SurfaceLook::default(),
        None,
        None,
    )
    .expect_err("refused");
    assert!(err.to_string().contains("16777217 voxels along x"), "{err}");
}
