//! `texmap sdf`: fields from a mesh and a scan read back through the volume loader; bad
//! input (no triangles, a threshold outside the scan, a grid over --max-memory, flags that do
//! not apply) is one line naming the file, exit 1, and no output.

mod common;

use common::texmap;
use std::path::{Path, PathBuf};
use std::process::Output;

use glam::DVec3;
use texmap::volume::sdf::{shape_field, FieldFormat, FieldGrid, Shape};
use texmap::volume::{load_scalars_with, VolumeOptions};

fn dir(name: &str) -> PathBuf {
    common::fresh_dir("sdf", name)
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// The cube [-1, 1]³ as an OBJ of 12 outward triangles.
fn cube_obj(path: &Path) {
    let mut t = String::new();
    for i in 0..8 {
        let c = |b: i32| if i & b == 0 { -1 } else { 1 };
        t += &format!("v {} {} {}\n", c(1), c(2), c(4));
    }
    for q in [
        [1, 3, 4, 2],
        [5, 6, 8, 7],
        [1, 2, 6, 5],
        [3, 7, 8, 4],
        [1, 5, 7, 3],
        [2, 4, 8, 6],
    ] {
        t += &format!(
            "f {} {} {}\nf {} {} {}\n",
            q[0], q[1], q[2], q[0], q[2], q[3]
        );
    }
    std::fs::write(path, t).unwrap();
}

/// One line on stderr, naming `file`, exit 1, no output file.
fn refused(out: &Output, file: &str, words: &str, output: &Path) {
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(err.contains(file) && err.contains(words), "{err}");
    assert!(!output.exists(), "{} was written", output.display());
}

#[test]
fn mesh_field_reads_back_with_its_grid() {
    let d = dir("mesh");
    let obj = d.join("cube.obj");
    cube_obj(&obj);
    for name in ["f.nii.gz", "f.nrrd"] {
        let out = d.join(name);
        let r = texmap(&[
            "sdf",
            s(&obj),
            "--res",
            "20",
            "--pad",
            "0.25",
            "-o",
            s(&out),
        ]);
        assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
        let g = load_scalars_with(&out, None, &VolumeOptions::default()).unwrap();
        // Side 2 grown by 0.5 on each face: 3 / 20 = 0.15 per voxel, 20 voxels a side.
        assert_eq!(g.dims, [20, 20, 20]);
        assert!((g.spacing() - glam::Vec3::splat(0.15)).abs().max_element() < 1e-6);
        assert!((g.world_from_voxel.w_axis.truncate() - glam::Vec3::splat(-1.425)).length() < 1e-5);
        // The box's distance, exactly, at every voxel.
        let grid = FieldGrid::axis_aligned([20; 3], DVec3::splat(-1.425), DVec3::splat(0.15));
        let want = shape_field(
            &Shape::Box {
                center: DVec3::ZERO,
                half: DVec3::ONE,
            },
            &grid,
        );
        let worst = g
            .values
            .iter()
            .zip(&want.values)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0f32, f32::max);
        assert!(worst < 1e-5, "{name}: {worst}");
    }
}

#[test]
fn thread_count_does_not_change_the_bytes() {
    let d = dir("threads");
    let obj = d.join("cube.obj");
    cube_obj(&obj);
    let run = |t: &str| {
        let out = d.join(format!("t{t}.nii"));
        let r = texmap(&["sdf", s(&obj), "--res", "24", "--threads", t, "-o", s(&out)]);
        assert!(r.status.success());
        std::fs::read(out).unwrap()
    };
    assert_eq!(run("1"), run("2"));
}

#[test]
fn scan_field_keeps_the_scan_placement() {
    let d = dir("scan");
    // A "scan": a ball's distance (negative inside) on an anisotropic grid.
    let grid = FieldGrid::axis_aligned(
        [12, 10, 8],
        DVec3::new(5.0, -3.0, 2.0),
        DVec3::new(0.5, 0.7, 1.1),
    );
    let ball = Shape::Sphere {
        center: DVec3::new(8.0, 0.0, 6.0),
        radius: 2.0,
    };
    let scan = d.join("scan.nii");
    let bytes = FieldFormat::for_path(&scan)
        .unwrap()
        .encode(&shape_field(&ball, &grid))
        .unwrap();
    std::fs::write(&scan, bytes).unwrap();
    // Inside: the voxels at least 1 from the ball (value ≥ 1).
    let out = d.join("field.nii.gz");
    let r = texmap(&[
        "sdf",
        s(&scan),
        "--threshold",
        "1.0",
        "-o",
        s(&out),
        "--json",
    ]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let json: serde_json::Value = serde_json::from_slice(&r.stdout).unwrap();
    assert_eq!(json["kind"], "scan");
    let f = load_scalars_with(&out, None, &VolumeOptions::default()).unwrap();
    assert_eq!(f.dims, [12, 10, 8]);
    assert!(f
        .world_from_voxel
        .abs_diff_eq(grid.world_from_voxel_f32(), 1e-6));
    // Voxels at least 1 from the ball are "inside" (value ≥ 1): negative there, positive
    // in the rest, and never zero.
    let src = load_scalars_with(&scan, None, &VolumeOptions::default()).unwrap();
    for (a, v) in f.values.iter().zip(&src.values) {
        assert_eq!(*a < 0.0, *v >= 1.0);
        assert!(a.abs() >= 0.5 - 1e-6);
    }
}

#[test]
fn a_mesh_without_triangles_is_refused() {
    let d = dir("empty");
    let obj = d.join("points.obj");
    std::fs::write(&obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\n").unwrap();
    let out = d.join("f.nii.gz");
    let r = texmap(&["sdf", s(&obj), "-o", s(&out)]);
    refused(&r, "points.obj", "no triangles", &out);
}

#[test]
fn a_threshold_outside_the_scan_is_refused() {
    let d = dir("threshold");
    let grid = FieldGrid::axis_aligned([4, 4, 4], DVec3::ZERO, DVec3::ONE);
    let f = shape_field(
        &Shape::Sphere {
            center: DVec3::splat(1.5),
            radius: 1.0,
        },
        &grid,
    );
    let scan = d.join("scan.nrrd");
    std::fs::write(
        &scan,
        FieldFormat::for_path(&scan).unwrap().encode(&f).unwrap(),
    )
    .unwrap();
    let out = d.join("f.nii");
    for t in ["1000", "-1000"] {
        let r = texmap(&["sdf", s(&scan), "--threshold", t, "-o", s(&out)]);
        refused(&r, "scan.nrrd", "outside the scan's values", &out);
    }
    let r = texmap(&["sdf", s(&scan), "-o", s(&out)]);
    refused(&r, "scan.nrrd", "--threshold", &out);
    let r = texmap(&[
        "sdf",
        s(&scan),
        "--threshold",
        "0",
        "--res",
        "64",
        "-o",
        s(&out),
    ]);
    refused(&r, "scan.nrrd", "--res", &out);
}

#[test]
fn a_grid_over_the_memory_limit_is_refused() {
    let d = dir("memory");
    let obj = d.join("cube.obj");
    cube_obj(&obj);
    let out = d.join("f.nii.gz");
    let r = texmap(&[
        "sdf",
        s(&obj),
        "--res",
        "1024",
        "--max-memory",
        "64M",
        "-o",
        s(&out),
    ]);
    refused(&r, "cube.obj", "--max-memory", &out);
}

#[test]
fn flags_that_do_not_apply_and_bad_names_are_refused() {
    let d = dir("flags");
    let obj = d.join("cube.obj");
    cube_obj(&obj);
    let out = d.join("f.png");
    let r = texmap(&["sdf", s(&obj), "-o", s(&out)]);
    refused(&r, "f.png", ".nii", &out);
    let out = d.join("f.nii");
    let r = texmap(&["sdf", s(&obj), "--threshold", "3", "-o", s(&out)]);
    refused(&r, "cube.obj", "--threshold", &out);
    let r = texmap(&["sdf", s(&obj), "--res", "0", "-o", s(&out)]);
    refused(&r, "cube.obj", "--res", &out);
    let txt = d.join("cube.txt");
    std::fs::write(&txt, "x").unwrap();
    let r = texmap(&["sdf", s(&txt), "-o", s(&out)]);
    refused(&r, "cube.txt", "neither a mesh", &out);
}
