//! Volume rendering against known answers (sphere MIP, ramp isosurface, step independence,
//! rays vs slices), the loaders on tiny generated files and every bad input, and golden
//! images of the real scans in `../shared/assets/volumes` (skipped when absent).
//!
//! Tolerances, stated once:
//! - MIP disk radius within 1 pixel of the analytic silhouette.
//! - Isosurface of a ramp within 0.01 world units of the plane.
//! - Opacity correction: step 0.25, 0.5, 1.0 vs step 0.125 ≥ 45 dB PSNR (8-bit sRGB).
//! - Ray marching vs slices at the same step ≥ 45 dB PSNR, shading off and on.
//! - Golden images ≥ 40 dB PSNR (`REPLACE=1` rewrites them).

use std::io::Write;
use std::path::{Path, PathBuf};

use glam::{Mat4, Vec3};
use texmap::camera::{Camera, CameraProjection};
use texmap::metrics::compare_rgb8;
use texmap::volume::{
    iso_hit, load_volume, raymarch, render_slices, Classification, MarchParams, Mode, RawDesc,
    ScalarType, TransferFunction, Volume,
};

fn tmp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("texmap-volume-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn grid(n: u32, f: impl Fn(f32, f32, f32) -> f32) -> Vec<f32> {
    let mut v = Vec::with_capacity((n * n * n) as usize);
    for z in 0..n {
        for y in 0..n {
            for x in 0..n {
                v.push(f(x as f32, y as f32, z as f32));
            }
        }
    }
    v
}

fn psnr(a: &texmap::render::Frame, b: &texmap::render::Frame) -> f64 {
    compare_rgb8(
        &a.to_srgb8(),
        &b.to_srgb8(),
        a.width as usize,
        a.height as usize,
        None,
    )
    .psnr_db
}

/// A smooth blob: value 200 at the centre falling to 0 at radius 28 voxels, plus ripples.
fn blob(n: u32) -> Volume {
    let c = (n - 1) as f32 * 0.5;
    let v = grid(n, |x, y, z| {
        let r = ((x - c).powi(2) + (y - c).powi(2) + (z - c).powi(2)).sqrt();
        (200.0 * (1.0 - r / 28.0)).max(0.0) + 20.0 * (x * 0.3).sin() * (y * 0.2).cos()
    });
    Volume::from_scalars([n; 3], Mat4::IDENTITY, v).unwrap()
}

fn blob_tf() -> TransferFunction {
    TransferFunction::parse("0:0,0,0,0;40:0.8,0.4,0.3,0;120:0.9,0.7,0.4,0.08;220:1,1,1,0.4")
        .unwrap()
}

#[test]
fn sphere_mip_is_a_disk_of_known_radius() {
    let n = 64;
    let c = 31.5;
    let r_sphere = 20.0;
    // 1 inside, 0 outside, a linear edge one voxel wide centred on r = 20.
    let v = grid(n, |x, y, z| {
        let r = ((x - c).powi(2) + (y - c).powi(2) + (z - c).powi(2)).sqrt();
        (r_sphere - r + 0.5).clamp(0.0, 1.0)
    });
    let vol = Volume::from_scalars([n; 3], Mat4::IDENTITY, v).unwrap();
    let tf = TransferFunction::parse("0:1,1,1,1;1:1,1,1,1").unwrap();
    let dist = 150.0;
    let cam = Camera {
        eye: Vec3::new(c, c - dist, c),
        target: Vec3::splat(c),
        up: Vec3::Z,
        projection: CameraProjection::Perspective { fov_y_deg: 20.0 },
        near: 1.0,
        far: 1000.0,
    };
    let size = 200;
    let params = MarchParams {
        mode: Mode::Mip,
        step: 0.1,
        jitter: false,
        ..MarchParams::default()
    };
    let f = raymarch(&vol, &tf, &cam, size, size, &params, None).unwrap();
    let rgb = f.to_srgb8();
    // Grey ≥ 0.5 (sRGB code of linear 0.5 is 188; the frame holds srgb_to_linear(grey), so
    // the code equals 255·grey): count pixels at or above 128.
    let area = rgb.chunks_exact(3).filter(|p| p[0] >= 128).count() as f64;
    let measured = (area / std::f64::consts::PI).sqrt();
    let half_angle = (r_sphere as f64 / dist as f64).asin();
    let expected = half_angle.tan() / (10.0f64.to_radians()).tan() * (size as f64 / 2.0);
    assert!(
        (measured - expected).abs() < 1.0,
        "disk radius {measured:.2} px, expected {expected:.2} px"
    );
}

#[test]
fn isosurface_of_a_ramp_is_a_plane_at_the_iso_value() {
    // v = x in voxels; spacing 2 along x, 1 elsewhere, shifted: the plane v = 20.3 is at
    // world x = 10 + 2·20.3 = 50.6.
    let n = 48;
    let v = grid(n, |x, _, _| x);
    let m = Mat4::from_translation(Vec3::new(10.0, -5.0, 3.0))
        * Mat4::from_scale(Vec3::new(2.0, 1.0, 1.0));
    let vol = Volume::from_scalars([n; 3], m, v).unwrap();
    let tf = TransferFunction::parse("0:1,1,1,0;20.3:1,1,1,1").unwrap();
    let params = MarchParams {
        iso: Some(20.3),
        step: 0.7,
        ..MarchParams::default()
    };
    let mut hits = 0;
    for k in 0..40 {
        let a = k as f32 * 0.37;
        let dir = Vec3::new(1.0, 0.1 * a.sin(), 0.1 * a.cos()).normalize();
        let origin = Vec3::new(-20.0, 15.0 + 5.0 * a.cos(), 20.0 + 4.0 * a.sin());
        let t = iso_hit(&vol, &tf, origin, dir, &params)
            .unwrap()
            .expect("the ray meets the plane");
        let p = origin + dir * t;
        assert!((p.x - 50.6).abs() < 0.01, "hit at x = {} (ray {k})", p.x);
        hits += 1;
    }
    assert_eq!(hits, 40);
    // And the image: looking along +x at the plane, every pixel inside the box is lit.
    let cam = Camera {
        eye: Vec3::new(-60.0, 18.5, 26.5),
        target: Vec3::new(50.0, 18.5, 26.5),
        up: Vec3::Z,
        projection: CameraProjection::Perspective { fov_y_deg: 10.0 },
        near: 1.0,
        far: 500.0,
    };
    let f = raymarch(
        &vol,
        &tf,
        &cam,
        32,
        32,
        &MarchParams {
            mode: Mode::Iso,
            ..params
        },
        None,
    )
    .unwrap();
    assert!(f.color.iter().all(|c| c.w == 1.0 && c.x > 0.5));
}

fn blob_camera() -> Camera {
    let vol = blob(64);
    vol.vtk_camera(1.6, 30.0)
}

#[test]
fn opacity_correction_makes_the_image_independent_of_the_step() {
    let vol = blob(64);
    let tf = blob_tf();
    let cam = blob_camera();
    let render = |step: f32| {
        let p = MarchParams {
            step,
            jitter: false,
            ..MarchParams::default()
        };
        raymarch(&vol, &tf, &cam, 96, 96, &p, None).unwrap()
    };
    let reference = render(0.125);
    for step in [0.25, 0.5, 1.0] {
        let db = psnr(&render(step), &reference);
        eprintln!("step {step}: {db:.2} dB against step 0.125");
        assert!(db >= 45.0, "step {step}: {db:.2} dB");
    }
    // Without correction (opacity per sample, not per unit length) the image would darken
    // with the step: check the test can fail by comparing opacity sums.
    let a: f32 = render(1.0).color.iter().map(|c| c.w).sum();
    let b: f32 = reference.color.iter().map(|c| c.w).sum();
    assert!((a - b).abs() / b < 0.02, "coverage {a} vs {b}");
}

#[test]
fn raymarch_and_slices_agree() {
    let vol = blob(64);
    let tf = blob_tf();
    let cam = blob_camera();
    for shade in [false, true] {
        let p = MarchParams {
            step: 0.5,
            shade,
            jitter: false,
            early_termination: 1.0,
            empty_space_skipping: false,
            ..MarchParams::default()
        };
        let r = raymarch(&vol, &tf, &cam, 96, 96, &p, None).unwrap();
        let s = render_slices(&vol, &tf, &cam, 96, 96, &p).unwrap();
        let db = psnr(&r, &s);
        eprintln!("raymarch vs slices, shade {shade}: {db:.2} dB");
        assert!(db >= 45.0, "shade {shade}: {db:.2} dB");
    }
}

#[test]
fn a_crop_box_cuts_the_volume_alike_for_rays_and_slices() {
    let vol = blob(64);
    let tf = blob_tf();
    let cam = blob_camera();
    let p = |crop: Option<[f32; 6]>| MarchParams {
        step: 0.5,
        jitter: false,
        early_termination: 1.0,
        empty_space_skipping: false,
        crop,
        ..MarchParams::default()
    };
    let whole = raymarch(&vol, &tf, &cam, 96, 96, &p(None), None).unwrap();
    // The box itself: the same image as no crop at all.
    let boxed = raymarch(
        &vol,
        &tf,
        &cam,
        96,
        96,
        &p(Some([0., 63., 0., 63., 0., 63.])),
        None,
    );
    assert_eq!(boxed.unwrap().color, whole.color);
    // Half the box along x: less is drawn, and rays and slices agree on what is left.
    let half = p(Some([0.0, 31.5, 0.0, 63.0, 0.0, 63.0]));
    let r = raymarch(&vol, &tf, &cam, 96, 96, &half, None).unwrap();
    let s = render_slices(&vol, &tf, &cam, 96, 96, &half).unwrap();
    let cover = |f: &texmap::render::Frame| f.color.iter().map(|c| c.w).sum::<f32>();
    let (a, b) = (cover(&r), cover(&whole));
    eprintln!(
        "coverage cropped {a:.1} of {b:.1}; rays vs slices {:.2} dB",
        psnr(&r, &s)
    );
    assert!(a < 0.8 * b && a > 0.2 * b, "{a} of {b}");
    assert!(psnr(&r, &s) >= 45.0);
    // No pixel is more opaque than without the crop (the cut removes, never adds), beyond
    // the shift of the samples to the crop's entry.
    let worst = r
        .color
        .iter()
        .zip(&whole.color)
        .map(|(c, w)| c.w - w.w)
        .fold(0.0f32, f32::max);
    assert!(worst < 0.02, "{worst}");
    // A box that is not one, or misses the volume, is refused naming the axis.
    for bad in [
        [5.0, 2.0, 0.0, 63.0, 0.0, 63.0],
        [0.0, 63.0, 70.0, 80.0, 0.0, 63.0],
    ] {
        let e = raymarch(&vol, &tf, &cam, 8, 8, &p(Some(bad)), None).unwrap_err();
        assert!(e.to_string().contains("crop"), "{e}");
        assert!(render_slices(&vol, &tf, &cam, 8, 8, &p(Some(bad))).is_err());
    }
}

#[test]
fn skipping_termination_and_classification_options_stay_close() {
    let vol = blob(64);
    let tf = blob_tf();
    let cam = blob_camera();
    let base = MarchParams {
        jitter: false,
        empty_space_skipping: false,
        early_termination: 1.0,
        ..MarchParams::default()
    };
    let reference = raymarch(&vol, &tf, &cam, 64, 64, &base, None).unwrap();
    // Skipping never moves samples: identical.
    let skip = raymarch(
        &vol,
        &tf,
        &cam,
        64,
        64,
        &MarchParams {
            empty_space_skipping: true,
            ..base.clone()
        },
        None,
    )
    .unwrap();
    assert_eq!(skip.color, reference.color);
    assert!(skip.stats.texture_samples < reference.stats.texture_samples);
    for (name, c) in [
        ("pre", Classification::Pre),
        ("preint", Classification::PreIntegrated),
    ] {
        let f = raymarch(
            &vol,
            &tf,
            &cam,
            64,
            64,
            &MarchParams {
                classification: c,
                ..base.clone()
            },
            None,
        )
        .unwrap();
        let db = psnr(&f, &reference);
        eprintln!("{name} vs post: {db:.2} dB");
        assert!(db >= 28.0, "{name}: {db:.2} dB");
    }
}

#[test]
fn the_image_does_not_depend_on_the_thread_count() {
    let vol = blob(48);
    let tf = blob_tf();
    let cam = vol.vtk_camera(1.6, 10.0);
    let p = MarchParams {
        shade: true,
        ..MarchParams::default()
    };
    let run = |n: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap()
            .install(|| raymarch(&vol, &tf, &cam, 48, 40, &p, None).unwrap())
    };
    assert_eq!(run(1).color, run(3).color);
}

#[test]
fn rays_stop_at_the_depth_buffer() {
    let vol = blob(48);
    let tf = blob_tf();
    let cam = vol.vtk_camera(1.6, 0.0);
    let p = MarchParams::default();
    let full = raymarch(&vol, &tf, &cam, 32, 32, &p, None).unwrap();
    // A surface just in front of the box hides everything; one far behind hides nothing.
    let near = vec![1.0f32; 32 * 32];
    let hidden = raymarch(&vol, &tf, &cam, 32, 32, &p, Some(&near)).unwrap();
    assert!(hidden.color.iter().all(|c| c.w == 0.0));
    let far = vec![1e6f32; 32 * 32];
    let shown = raymarch(&vol, &tf, &cam, 32, 32, &p, Some(&far)).unwrap();
    assert_eq!(shown.color, full.color);
    assert!(raymarch(&vol, &tf, &cam, 32, 32, &p, Some(&far[..10])).is_err());
}

// ---- Loaders -------------------------------------------------------------------------------

/// A NIfTI-1 header + extension flag + data.
fn nifti_bytes(
    dims: [i16; 3],
    datatype: i16,
    bitpix: i16,
    slope: f32,
    inter: f32,
    sform: Option<[[f32; 4]; 3]>,
    data: &[u8],
) -> Vec<u8> {
    let mut h = vec![0u8; 352];
    h[0..4].copy_from_slice(&348i32.to_le_bytes());
    let dim = [3i16, dims[0], dims[1], dims[2], 1, 1, 1, 1];
    for (i, d) in dim.iter().enumerate() {
        h[40 + 2 * i..42 + 2 * i].copy_from_slice(&d.to_le_bytes());
    }
    h[70..72].copy_from_slice(&datatype.to_le_bytes());
    h[72..74].copy_from_slice(&bitpix.to_le_bytes());
    let pixdim = [1.0f32, 1.5, 2.0, 3.0, 1.0, 1.0, 1.0, 1.0];
    for (i, p) in pixdim.iter().enumerate() {
        h[76 + 4 * i..80 + 4 * i].copy_from_slice(&p.to_le_bytes());
    }
    h[108..112].copy_from_slice(&352.0f32.to_le_bytes());
    h[112..116].copy_from_slice(&slope.to_le_bytes());
    h[116..120].copy_from_slice(&inter.to_le_bytes());
    if let Some(rows) = sform {
        h[254..256].copy_from_slice(&1i16.to_le_bytes());
        for (r, row) in rows.iter().enumerate() {
            for (c, v) in row.iter().enumerate() {
                let o = 280 + 16 * r + 4 * c;
                h[o..o + 4].copy_from_slice(&v.to_le_bytes());
            }
        }
    }
    h[344..348].copy_from_slice(b"n+1\0");
    h.extend_from_slice(data);
    h
}

fn gzip(bytes: &[u8]) -> Vec<u8> {
    let mut e = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
    e.write_all(bytes).unwrap();
    e.finish().unwrap()
}

/// Equal within half a 16-bit level of the volume's range (values are stored as levels).
fn close(a: f32, b: f32, v: &Volume) {
    assert!(
        (a - b).abs() <= 0.5 * v.value_step() + 1e-4 * b.abs(),
        "{a} vs {b}"
    );
}

fn i16_data(n: usize) -> Vec<u8> {
    (0..n).flat_map(|i| (i as i16 - 3).to_le_bytes()).collect()
}

#[test]
fn nifti_i16_with_scaling_and_sform_plain_and_gzipped() {
    let d = tmp_dir("nifti");
    let sform = [
        [0.0, 0.0, 3.0, 7.0],
        [1.5, 0.0, 0.0, -1.0],
        [0.0, 2.0, 0.0, 2.0],
    ];
    let bytes = nifti_bytes([2, 3, 4], 4, 16, 2.0, -1000.0, Some(sform), &i16_data(24));
    for (name, data) in [("a.nii", bytes.clone()), ("a.nii.gz", gzip(&bytes))] {
        let p = d.join(name);
        std::fs::write(&p, data).unwrap();
        let v = load_volume(&p, None).unwrap();
        assert_eq!(v.dims(), [2, 3, 4]);
        assert_eq!(v.range(), (-1006.0, -960.0));
        close(v.voxel(0, 0, 0), -3.0 * 2.0 - 1000.0, &v);
        close(v.voxel(1, 2, 3), 20.0 * 2.0 - 1000.0, &v);
        close(v.voxel(1, 0, 1), 4.0 * 2.0 - 1000.0, &v);
        // Voxel (1, 2, 3) → (3·3 + 7, 1.5·1 − 1, 2·2 + 2).
        let w = v
            .world_from_voxel()
            .transform_point3(Vec3::new(1.0, 2.0, 3.0));
        assert!((w - Vec3::new(16.0, 0.5, 6.0)).length() < 1e-5, "{w}");
        assert!((v.spacing() - Vec3::new(1.5, 2.0, 3.0)).length() < 1e-6);
    }
}

#[test]
fn nifti_u8_u16_f32_i8_and_no_sform_uses_pixdim() {
    let d = tmp_dir("nifti-types");
    let cases: [(i16, i16, Vec<u8>, f32); 4] = [
        (2, 8, (0..8u8).collect(), 7.0),
        (
            512,
            16,
            (0..8u16).flat_map(|v| (v * 1000).to_le_bytes()).collect(),
            7000.0,
        ),
        (
            16,
            32,
            (0..8)
                .flat_map(|v| (v as f32 * 0.5).to_le_bytes())
                .collect(),
            3.5,
        ),
        (256, 8, (0..8i8).map(|v| (v - 4) as u8).collect(), 3.0),
    ];
    for (dt, bp, data, last) in cases {
        let p = d.join(format!("t{dt}.nii"));
        std::fs::write(&p, nifti_bytes([2, 2, 2], dt, bp, 0.0, 0.0, None, &data)).unwrap();
        let v = load_volume(&p, None).unwrap();
        close(v.voxel(1, 1, 1), last, &v);
        assert!((v.spacing() - Vec3::new(1.5, 2.0, 3.0)).length() < 1e-6);
    }
}

#[test]
fn nrrd_attached_detached_raw_and_gzip() {
    let d = tmp_dir("nrrd");
    let data: Vec<u8> = (0..24u16).flat_map(|v| v.to_be_bytes()).collect();
    let header = |extra: &str| {
        format!(
            "NRRD0004\n# comment\ntype: unsigned short\ndimension: 3\nsizes: 2 3 4\n\
             space directions: (0.5,0,0) (0,2,0) (0,0,3)\nspace origin: (1,2,3)\nendian: big\n{extra}"
        )
    };
    // Attached raw.
    let mut a = header("encoding: raw\n\n").into_bytes();
    a.extend_from_slice(&data);
    std::fs::write(d.join("a.nrrd"), &a).unwrap();
    // Attached gzip.
    let mut g = header("encoding: gzip\n\n").into_bytes();
    g.extend_from_slice(&gzip(&data));
    std::fs::write(d.join("g.nrrd"), &g).unwrap();
    // Detached.
    std::fs::write(
        d.join("x.nhdr"),
        header("encoding: raw\ndata file: x.raw\n\n"),
    )
    .unwrap();
    std::fs::write(d.join("x.raw"), &data).unwrap();
    for name in ["a.nrrd", "g.nrrd", "x.nhdr"] {
        let v = load_volume(&d.join(name), None).unwrap();
        assert_eq!(v.dims(), [2, 3, 4], "{name}");
        close(v.voxel(1, 2, 3), 23.0, &v);
        let w = v
            .world_from_voxel()
            .transform_point3(Vec3::new(1.0, 1.0, 1.0));
        assert!(
            (w - Vec3::new(1.5, 4.0, 6.0)).length() < 1e-6,
            "{name}: {w}"
        );
    }
}

#[test]
fn raw_with_given_grid() {
    let d = tmp_dir("raw");
    let p = d.join("v.raw");
    std::fs::write(&p, (0..27u8).collect::<Vec<_>>()).unwrap();
    let desc = RawDesc::new([3, 3, 3], ScalarType::U8, Vec3::new(1.0, 2.0, 4.0));
    let v = load_volume(&p, Some(&desc)).unwrap();
    close(v.voxel(2, 2, 2), 26.0, &v);
    close(v.voxel(1, 0, 2), 19.0, &v);
    assert_eq!(v.spacing(), Vec3::new(1.0, 2.0, 4.0));
    // Without a grid: an error naming the file.
    let e = load_volume(&p, None).unwrap_err().to_string();
    assert!(e.contains("v.raw") && e.contains("--dims"), "{e}");
}

fn expect_error(p: &Path, raw: Option<&RawDesc>, words: &[&str]) {
    let e = match load_volume(p, raw) {
        Ok(_) => panic!("{} loaded", p.display()),
        Err(e) => e.to_string(),
    };
    let name = p.file_name().unwrap().to_string_lossy();
    assert!(e.contains(&*name), "error does not name the file: {e}");
    for w in words {
        assert!(e.contains(w), "error lacks \"{w}\": {e}");
    }
}

#[test]
fn every_bad_input_is_a_clear_error_naming_the_file() {
    let d = tmp_dir("bad");
    let good = nifti_bytes([2, 3, 4], 4, 16, 1.0, 0.0, None, &i16_data(24));
    // Header and data sizes disagree (NIfTI, NRRD, raw).
    let short = &good[..good.len() - 5];
    std::fs::write(d.join("short.nii"), short).unwrap();
    expect_error(&d.join("short.nii"), None, &["48 bytes", "43 bytes"]);
    std::fs::write(
        d.join("short.nrrd"),
        b"NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n\n1234567",
    )
    .unwrap();
    expect_error(&d.join("short.nrrd"), None, &["8 bytes", "7 bytes"]);
    std::fs::write(d.join("long.raw"), [0u8; 30]).unwrap();
    let desc = RawDesc::new([3, 3, 3], ScalarType::U8, Vec3::ONE);
    expect_error(&d.join("long.raw"), Some(&desc), &["27 bytes", "30"]);
    // Unsupported types.
    std::fs::write(
        d.join("rgb.nii"),
        nifti_bytes([1, 1, 1], 128, 24, 1.0, 0.0, None, &[1, 2, 3]),
    )
    .unwrap();
    expect_error(&d.join("rgb.nii"), None, &["datatype 128", "not supported"]);
    std::fs::write(
        d.join("block.nrrd"),
        b"NRRD0004\ntype: block\ndimension: 3\nsizes: 1 1 1\nencoding: raw\n\n1",
    )
    .unwrap();
    expect_error(&d.join("block.nrrd"), None, &["block", "not supported"]);
    // Truncated gzip.
    let gz = gzip(&good);
    std::fs::write(d.join("cut.nii.gz"), &gz[..gz.len() / 2]).unwrap();
    expect_error(&d.join("cut.nii.gz"), None, &["truncated"]);
    // NaN in the data.
    let mut f: Vec<u8> = (0..8).flat_map(|v| (v as f32).to_le_bytes()).collect();
    f[12..16].copy_from_slice(&f32::NAN.to_le_bytes());
    std::fs::write(
        d.join("nan.nii"),
        nifti_bytes([2, 2, 2], 16, 32, 1.0, 0.0, None, &f),
    )
    .unwrap();
    expect_error(&d.join("nan.nii"), None, &["voxel 3", "NaN"]);
    // Not a NIfTI file at all, a missing file, a zero size.
    std::fs::write(d.join("junk.nii"), [7u8; 400]).unwrap();
    expect_error(&d.join("junk.nii"), None, &["not a NIfTI-1"]);
    expect_error(&d.join("missing.nii.gz"), None, &[]);
    std::fs::write(
        d.join("zero.nii"),
        nifti_bytes([0, 1, 1], 2, 8, 1.0, 0.0, None, &[]),
    )
    .unwrap();
    expect_error(&d.join("zero.nii"), None, &["size 0"]);
    // A detached header whose data file is missing names the data file.
    std::fs::write(
        d.join("lost.nhdr"),
        b"NRRD0004\ntype: uchar\ndimension: 3\nsizes: 1 1 1\nencoding: raw\ndata file: lost.raw\n\n",
    )
    .unwrap();
    let e = load_volume(&d.join("lost.nhdr"), None)
        .unwrap_err()
        .to_string();
    assert!(e.contains("lost.raw"), "{e}");
}

// ---- Golden images of the real scans -------------------------------------------------------

fn volumes_dir() -> Option<PathBuf> {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/assets/volumes");
    if p.is_dir() {
        Some(p)
    } else {
        eprintln!("SKIPPED: the volume assets {} are absent", p.display());
        None
    }
}

/// Compares with `tests/golden/<name>.png` (≥ 40 dB), or writes it when `REPLACE=1`; on a
/// failure the actual image is written beside it as `<name>.actual.png`.
fn golden(name: &str, f: &texmap::render::Frame) {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden");
    let path = dir.join(format!("{name}.png"));
    let rgb = f.to_srgb8();
    let save =
        |p: &Path| image::save_buffer(p, &rgb, f.width, f.height, image::ColorType::Rgb8).unwrap();
    if std::env::var("REPLACE").is_ok_and(|v| v == "1") {
        std::fs::create_dir_all(&dir).unwrap();
        save(&path);
        eprintln!("REPLACED {}", path.display());
        return;
    }
    let reference = image::open(&path)
        .unwrap_or_else(|e| panic!("{}: {e} (run with REPLACE=1 to create it)", path.display()))
        .to_rgb8();
    assert_eq!(reference.dimensions(), (f.width, f.height));
    let c = compare_rgb8(
        &rgb,
        reference.as_raw(),
        f.width as usize,
        f.height as usize,
        None,
    );
    if c.psnr_db < 40.0 {
        save(&dir.join(format!("{name}.actual.png")));
        panic!(
            "{name}: {:.2} dB against the golden image (< 40 dB)",
            c.psnr_db
        );
    }
}

#[test]
fn golden_mni152_t1() {
    let Some(root) = volumes_dir() else { return };
    let vol = load_volume(
        &root.join("mni152_t1/mni_icbm152_t1_tal_nlin_sym_09a_converted.nii.gz"),
        None,
    )
    .unwrap();
    assert_eq!(vol.dims(), [197, 233, 189]);
    let tf = TransferFunction::preset("mri").unwrap();
    let cam = vol.vtk_camera(1.6, 180.0);
    for (name, shade) in [("mni152_t1", false), ("mni152_t1_shaded", true)] {
        let p = MarchParams {
            step: 0.5,
            shade,
            ..MarchParams::default()
        };
        golden(
            name,
            &raymarch(&vol, &tf, &cam, 128, 128, &p, None).unwrap(),
        );
    }
}

#[test]
fn golden_tooth_ct() {
    let Some(root) = volumes_dir() else { return };
    let vol = load_volume(&root.join("tooth_ct/tooth.nhdr"), None).unwrap();
    assert_eq!(vol.dims(), [103, 94, 161]);
    let tf = TransferFunction::parse(TOOTH_TF).unwrap();
    let cam = vol.vtk_camera(1.4, 60.0);
    let p = MarchParams {
        step: 0.5,
        shade: true,
        ..MarchParams::default()
    };
    golden(
        "tooth_ct",
        &raymarch(&vol, &tf, &cam, 128, 128, &p, None).unwrap(),
    );
    let iso = MarchParams {
        mode: Mode::Iso,
        iso: Some(700.0),
        ..p
    };
    golden(
        "tooth_ct_iso",
        &raymarch(&vol, &tf, &cam, 128, 128, &iso, None).unwrap(),
    );
}

/// Dentine and enamel of the tooth CT (its values are not Hounsfield units).
const TOOTH_TF: &str =
    "0:0,0,0,0;350:0,0,0,0;500:0.9,0.55,0.45,0.03;900:0.95,0.9,0.8,0.2;1300:1,1,1,0.9";
