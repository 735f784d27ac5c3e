//! The automatic framing on real models (`../shared/assets/gltf` and `obj`): every model
//! framed by default (its own camera set aside) covers 20–90% of the image's width or height
//! and touches no edge of the image (nothing clipped), at a wide and at a tall aspect ratio;
//! and a user eye anywhere on a sphere around a model (`--eye`, the target kept) draws it
//! whole (nothing on the border; at least 10% of the image unless the model is flat). Without the corpus the test prints `SKIPPED` and passes.

mod common;

use common::assets;
use std::path::{Path, PathBuf};

use glam::Vec3;
use texmap::render::framing::{choose_camera, CameraRequest};
use texmap::render::{render, Settings};
use texmap::scene::{load, LoadOptions, Scene};

/// Every .gltf/.glb of the glTF models (one per model: the first variant folder's) and
/// every .obj, sorted.
fn models(root: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut dirs: Vec<PathBuf> = std::fs::read_dir(root.join("gltf"))
        .map(|rd| rd.filter_map(|e| e.ok().map(|e| e.path())).collect())
        .unwrap_or_default();
    dirs.sort();
    for d in dirs {
        let mut files = Vec::new();
        for variant in ["glTF-Binary", "glTF"] {
            if let Ok(rd) = std::fs::read_dir(d.join(variant)) {
                files.extend(
                    rd.filter_map(|e| e.ok().map(|e| e.path()))
                        .filter(|p| p.extension().is_some_and(|e| e == "glb" || e == "gltf")),
                );
            }
        }
        files.sort();
        out.extend(files.into_iter().next());
    }
    if let Ok(rd) = std::fs::read_dir(root.join("obj")) {
        for d in rd.filter_map(|e| e.ok().map(|e| e.path())) {
            if let Ok(rd) = std::fs::read_dir(&d) {
                out.extend(
                    rd.filter_map(|e| e.ok().map(|e| e.path()))
                        .filter(|p| p.extension().is_some_and(|e| e == "obj")),
                );
            }
        }
    }
    out.sort();
    out
}

fn scene_of(path: &Path) -> Scene {
    let mut scene = load(path, &LoadOptions::default())
        .unwrap_or_else(|e| panic!("{} does not load: {e}", path.display()))
        .scene;
    scene.camera = None;
    // A transparent background: the drawn pixels are those with coverage.
    scene.background = glam::Vec4::ZERO;
    scene
}

/// The drawn pixels' extent as fractions of the width and height, and whether any lies on
/// the image's border.
fn coverage(scene: &Scene, request: &CameraRequest, w: u32, h: u32) -> (f32, f32, bool) {
    let camera = choose_camera(scene, &[], request).unwrap();
    let frame = render(scene, &camera, &Settings::new(w, h)).unwrap();
    let rgba = frame.to_srgba8();
    let (mut x0, mut x1, mut y0, mut y1) = (w, 0, h, 0);
    for y in 0..h {
        for x in 0..w {
            if rgba[((y * w + x) * 4 + 3) as usize] > 0 {
                (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
            }
        }
    }
    if x0 > x1 {
        return (0.0, 0.0, false);
    }
    let edge = x0 == 0 || y0 == 0 || x1 == w - 1 || y1 == h - 1;
    (
        (x1 - x0 + 1) as f32 / w as f32,
        (y1 - y0 + 1) as f32 / h as f32,
        edge,
    )
}

#[test]
fn every_model_is_framed_whole_and_large_enough_by_default() {
    let Some(root) = assets() else { return };
    let list = models(&root);
    assert!(list.len() >= 10, "expected the corpus's models: {list:?}");
    let mut bad = Vec::new();
    for path in &list {
        let scene = scene_of(path);
        for (w, h) in [(240, 180), (150, 200)] {
            let req = CameraRequest::default().with_aspect(w as f32 / h as f32);
            let (fw, fh, edge) = coverage(&scene, &req, w, h);
            let big = fw.max(fh);
            eprintln!(
                "{} at {w}x{h}: width {:.0}%, height {:.0}%",
                path.display(),
                100.0 * fw,
                100.0 * fh
            );
            if edge || !(0.2..=0.9).contains(&big) {
                bad.push(format!(
                    "{} at {w}x{h}: {:.0}% x {:.0}%{}",
                    path.display(),
                    100.0 * fw,
                    100.0 * fh,
                    if edge { ", clipped" } else { "" }
                ));
            }
        }
    }
    assert!(bad.is_empty(), "badly framed: {bad:#?}");
}

#[test]
fn an_eye_anywhere_on_a_sphere_around_a_model_draws_it_whole() {
    let Some(root) = assets() else { return };
    let mut bad = Vec::new();
    for path in models(&root) {
        let scene = scene_of(&path);
        let auto = choose_camera(&scene, &[], &CameraRequest::default()).unwrap();
        let (centre, dist) = (auto.target, auto.eye.distance(auto.target));
        // A flat model (a card of test patterns) seen edge-on draws nothing, rightly.
        let extent = {
            let (lo, hi) = scene.bounds();
            hi - lo
        };
        let flat = extent.min_element() < 0.01 * extent.max_element();
        // Fourteen directions: the axes and the cube's diagonals.
        let mut dirs = vec![Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z];
        for i in 0..8 {
            let s = |b: u32| if i & b == 0 { 1.0 } else { -1.0 };
            dirs.push(Vec3::new(s(1), s(2), s(4)).normalize());
        }
        for d in dirs {
            let mut req = CameraRequest::default().with_eye(centre + d * dist);
            if d.cross(Vec3::Y).length() < 1e-3 {
                req = req.with_up(Vec3::Z);
            }
            let (fw, fh, edge) = coverage(&scene, &req, 120, 90);
            if edge || (!flat && fw.max(fh) < 0.1) {
                bad.push(format!(
                    "{} from {d}: {:.0}% x {:.0}%{}",
                    path.display(),
                    100.0 * fw,
                    100.0 * fh,
                    if edge { ", clipped" } else { "" }
                ));
            }
        }
    }
    assert!(bad.is_empty(), "eyes that miss part of the model: {bad:#?}");
}

/// Every corner of `lo..hi` seen by `camera` at `aspect` lies inside the image and between
/// near and far.
fn box_in_frame(camera: &texmap::camera::Camera, corners: &[Vec3; 8], aspect: f32) -> bool {
    let m = camera.clip_from_view(aspect) * camera.view_from_world();
    corners.iter().all(|&p| {
        let c = m * p.extend(1.0);
        let n = c.truncate() / c.w;
        c.w > 0.0 && n.x.abs() <= 1.0 && n.y.abs() <= 1.0 && n.z.abs() <= 1.0
    })
}

#[test]
fn scans_face_the_viewer_and_fit_any_aspect() {
    use texmap::volume::scene_volume::SceneVolume;
    use texmap::volume::{load_volume_with, VolumeOptions};
    let Some(root) = assets() else { return };
    let scene = Scene::default();
    for (file, faces) in [
        (
            "volumes/mni152_t1/mni_icbm152_t1_tal_nlin_sym_09a_converted.nii.gz",
            true,
        ),
        ("volumes/tooth_ct/tooth.nhdr", false),
    ] {
        let path = root.join(file);
        let vol = load_volume_with(&path, None, &VolumeOptions::default()).unwrap();
        // The MNI template is RAS+: its face is toward +y and the top of its head +z.
        assert_eq!(vol.patient_front_and_top().is_some(), faces, "{file}");
        let whole = vol.world_bounds();
        let volumes = [SceneVolume::new(vol, &path)];
        // What the synth preset shows lies inside the box.
        let (lo, hi) = volumes[0].visible_world_bounds();
        assert!(lo.cmpge(whole.0).all() && hi.cmple(whole.1).all(), "{file}");
        let corners: [Vec3; 8] = std::array::from_fn(|i| {
            Vec3::new(
                if i & 1 == 0 { lo.x } else { hi.x },
                if i & 2 == 0 { lo.y } else { hi.y },
                if i & 4 == 0 { lo.z } else { hi.z },
            )
        });
        for aspect in [4.0 / 3.0, 16.0 / 9.0, 0.5, 1.0] {
            let req = CameraRequest::default().with_aspect(aspect);
            let cam = choose_camera(&scene, &volumes, &req).unwrap();
            assert!(
                box_in_frame(&cam, &corners, aspect),
                "{file} at {aspect}: {cam:?}"
            );
            let toward_eye = (cam.eye - cam.target).normalize();
            if faces {
                assert!(toward_eye.dot(Vec3::Y) > 0.99, "{file}: {toward_eye}");
                assert_eq!(cam.up, Vec3::Z, "{file}");
            } else {
                // No stated frame: VTK's view along +y, z up.
                assert!(toward_eye.dot(-Vec3::Y) > 0.99, "{file}: {toward_eye}");
            }
        }
    }
}
