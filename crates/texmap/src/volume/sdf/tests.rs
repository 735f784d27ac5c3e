//! Distance fields against closed forms and brute force.

use glam::{DVec3, Vec3};
use proptest::prelude::*;

use super::*;
use crate::volume::{load_scalars_with, load_volume, ScalarType, VolumeOptions};

/// An octahedron subdivided `levels` times and pushed onto the sphere of radius `r`.
fn sphere_mesh(r: f32, levels: u32) -> Vec<[Vec3; 3]> {
    let v = [
        Vec3::X,
        Vec3::NEG_X,
        Vec3::Y,
        Vec3::NEG_Y,
        Vec3::Z,
        Vec3::NEG_Z,
    ];
    let mut tris: Vec<[Vec3; 3]> = [
        (0, 2, 4),
        (2, 1, 4),
        (1, 3, 4),
        (3, 0, 4),
        (2, 0, 5),
        (1, 2, 5),
        (3, 1, 5),
        (0, 3, 5),
    ]
    .iter()
    .map(|&(a, b, c)| [v[a], v[b], v[c]])
    .collect();
    for _ in 0..levels {
        tris = tris
            .iter()
            .flat_map(|&[a, b, c]| {
                let (ab, bc, ca) = (
                    (a + b).normalize(),
                    (b + c).normalize(),
                    (c + a).normalize(),
                );
                [[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]
            })
            .collect();
    }
    tris.iter().map(|t| t.map(|p| p * r)).collect()
}

/// The 12 outward triangles of the box `[lo, hi]`.
fn cube_mesh(lo: Vec3, hi: Vec3) -> Vec<[Vec3; 3]> {
    let c = |i: usize| {
        Vec3::new(
            if i & 1 == 0 { lo.x } else { hi.x },
            if i & 2 == 0 { lo.y } else { hi.y },
            if i & 4 == 0 { lo.z } else { hi.z },
        )
    };
    // Each face as a counter-clockwise quad seen from outside.
    let quads = [
        [0, 2, 3, 1], // z = lo
        [4, 5, 7, 6], // z = hi
        [0, 1, 5, 4], // y = lo
        [2, 6, 7, 3], // y = hi
        [0, 4, 6, 2], // x = lo
        [1, 3, 7, 5], // x = hi
    ];
    quads
        .iter()
        .flat_map(|q| [[c(q[0]), c(q[1]), c(q[2])], [c(q[0]), c(q[2]), c(q[3])]])
        .collect()
}

fn grid_around(tris: &[[Vec3; 3]], res: u32) -> FieldGrid {
    let t: Triangles = tris.iter().copied().collect();
    let (lo, hi) = t.bounds().unwrap();
    FieldGrid::around_box(lo, hi, res, 0.1).unwrap()
}

#[test]
fn grid_follows_the_reference_script() {
    let g = FieldGrid::around_box(DVec3::ZERO, DVec3::new(1.0, 2.0, 0.5), 10, 0.1).unwrap();
    assert_eq!(g.dims, [6, 10, 4]);
    assert!((g.spacing() - DVec3::splat(0.24)).abs().max_element() < 1e-12);
    assert!((g.point(0, 0, 0) - DVec3::splat(-0.08)).abs().max_element() < 1e-12);
    assert!(FieldGrid::around_box(DVec3::ZERO, DVec3::ZERO, 10, 0.1).is_err());
    assert!(FieldGrid::around_box(DVec3::ZERO, DVec3::ONE, 0, 0.1).is_err());
}

#[test]
fn sphere_mesh_field_is_the_sphere_distance() {
    let r = 1.0;
    let tris = sphere_mesh(r, 5);
    let grid = grid_around(&tris, 40);
    let (field, _) = mesh_field(&tris.iter().copied().collect(), &grid).unwrap();
    // The mesh lies between the sphere and its facets' planes: the largest gap is the
    // sphere's radius less the nearest plane's distance from the centre.
    let nearest = tris
        .iter()
        .map(|t| {
            let n = (t[1] - t[0]).cross(t[2] - t[0]).normalize();
            f64::from(n.dot(t[0]).abs())
        })
        .fold(f64::INFINITY, f64::min);
    let sagitta = f64::from(r) - nearest;
    let mut worst = 0.0f64;
    for k in 0..grid.dims[2] {
        for j in 0..grid.dims[1] {
            for i in 0..grid.dims[0] {
                let p = grid.point(i, j, k);
                let exact = p.length() - f64::from(r);
                let got = f64::from(field.at(i, j, k));
                worst = worst.max((got - exact).abs());
                if exact.abs() > sagitta {
                    assert_eq!(got < 0.0, exact < 0.0, "sign at {p}");
                }
            }
        }
    }
    assert!(worst <= sagitta + 1e-5, "{worst} > {sagitta}");
}

#[test]
fn cube_mesh_field_is_the_box_distance() {
    let (lo, hi) = (Vec3::new(-1.0, -0.5, -0.25), Vec3::new(1.0, 0.5, 0.75));
    let tris = cube_mesh(lo, hi);
    let grid = grid_around(&tris, 32);
    let (field, _) = mesh_field(&tris.iter().copied().collect(), &grid).unwrap();
    let shape = Shape::Box {
        center: ((lo + hi) * 0.5).as_dvec3(),
        half: ((hi - lo) * 0.5).as_dvec3(),
    };
    let exact = shape_field(&shape, &grid);
    let worst = field
        .values
        .iter()
        .zip(&exact.values)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0f32, f32::max);
    assert!(worst < 1e-5, "{worst}");
}

#[test]
fn flipped_and_missing_faces_keep_the_sign() {
    // A sphere with a hole (a cap of triangles removed) and one triangle in 17 inverted.
    let mut tris = sphere_mesh(1.0, 4);
    tris.retain(|t| (t[0] + t[1] + t[2]).z / 3.0 < 0.95);
    for t in tris.iter_mut().step_by(17) {
        *t = [t[0], t[2], t[1]];
    }
    let grid = grid_around(&tris, 32);
    let (field, _) = mesh_field(&tris.iter().copied().collect(), &grid).unwrap();
    let h = grid.spacing().x;
    let mut wrong = 0;
    for k in 0..grid.dims[2] {
        for j in 0..grid.dims[1] {
            for i in 0..grid.dims[0] {
                let exact = grid.point(i, j, k).length() - 1.0;
                if exact.abs() > 2.0 * h && (field.at(i, j, k) < 0.0) != (exact < 0.0) {
                    wrong += 1;
                }
            }
        }
    }
    assert_eq!(wrong, 0, "voxels with the wrong sign");
    // A cube with every triangle inverted is inside out: the field says so (the sign is
    // the winding number, not a guess).
    let (lo, hi) = (Vec3::splat(-1.0), Vec3::splat(1.0));
    let inverted: Triangles = cube_mesh(lo, hi)
        .into_iter()
        .map(|t| [t[0], t[2], t[1]])
        .collect();
    let grid = grid_around(&cube_mesh(lo, hi), 16);
    let (f, _) = mesh_field(&inverted, &grid).unwrap();
    let centre = grid.dims.map(|d| d / 2);
    assert!(f.at(centre[0], centre[1], centre[2]) > 0.0);
}

#[test]
fn mesh_field_does_not_depend_on_the_thread_count() {
    let tris: Triangles = sphere_mesh(1.0, 3).into_iter().collect();
    let grid = grid_around(tris.as_slice(), 24);
    let run = |n| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap()
            .install(|| mesh_field(&tris, &grid).unwrap().0)
    };
    assert_eq!(run(1).values, run(3).values);
}

#[test]
fn no_triangles_is_an_error() {
    let grid = FieldGrid::axis_aligned([2, 2, 2], DVec3::ZERO, DVec3::ONE);
    let e = mesh_field(&Triangles::new(), &grid).unwrap_err();
    assert!(e.to_string().contains("no triangles"), "{e}");
}

#[test]
fn primitives_and_csg() {
    let s = Shape::Sphere {
        center: DVec3::new(1.0, 0.0, 0.0),
        radius: 0.5,
    };
    assert!((s.distance(DVec3::new(3.0, 0.0, 0.0)) - 1.5).abs() < 1e-12);
    assert!((s.distance(DVec3::new(1.0, 0.0, 0.0)) + 0.5).abs() < 1e-12);
    let b = Shape::Box {
        center: DVec3::ZERO,
        half: DVec3::new(1.0, 2.0, 3.0),
    };
    assert!((b.distance(DVec3::new(2.0, 3.0, 0.0)) - 2f64.sqrt()).abs() < 1e-12);
    assert!((b.distance(DVec3::new(0.5, 0.0, 0.0)) + 0.5).abs() < 1e-12);
    let t = Shape::Torus {
        center: DVec3::ZERO,
        major: 2.0,
        minor: 0.5,
    };
    assert!((t.distance(DVec3::new(2.0, 0.0, 0.0)) + 0.5).abs() < 1e-12);
    assert!((t.distance(DVec3::new(0.0, 0.0, -2.0)) + 0.5).abs() < 1e-12);
    assert!((t.distance(DVec3::ZERO) - 1.5).abs() < 1e-12);
    assert!((t.distance(DVec3::new(0.0, 1.0, 2.0)) - 0.5).abs() < 1e-12);
    // CSG: the rules on sample points.
    let u = s.clone().union(b.clone());
    let i = s.clone().intersect(b.clone());
    let d = b.clone().subtract(s.clone());
    let m = s.clone().smooth_union(b.clone(), 0.3);
    for p in [
        DVec3::new(1.2, 0.1, 0.0),
        DVec3::new(0.5, 1.0, 2.0),
        DVec3::new(4.0, -1.0, 0.0),
        DVec3::new(1.0, 0.0, 0.0),
    ] {
        let (ds, db) = (s.distance(p), b.distance(p));
        assert_eq!(u.distance(p), ds.min(db));
        assert_eq!(i.distance(p), ds.max(db));
        assert_eq!(d.distance(p), db.max(-ds));
        // The smooth union never exceeds the union, and by at most k/4.
        let sm = m.distance(p);
        assert!(sm <= ds.min(db) + 1e-12 && sm >= ds.min(db) - 0.3 / 4.0 - 1e-12);
    }
    // Far from the crease the smooth union is the union.
    let far = DVec3::new(0.0, 0.0, 10.0);
    assert_eq!(m.distance(far), u.distance(far));
    // On a grid: the torus field's zero crossing lies on the tube.
    let grid = FieldGrid::axis_aligned([9, 9, 9], DVec3::splat(-4.0), DVec3::ONE);
    let f = shape_field(&t, &grid);
    assert_eq!(f.at(6, 4, 4), -0.5); // (2, 0, 0)
    assert_eq!(f.at(4, 4, 4), 1.5); // the centre
}

/// The signed distance of a mask by brute force (`sdf_ref.py mask`'s definition).
fn brute_mask(dims: [u32; 3], sp: [f64; 3], inside: &[bool]) -> Vec<f64> {
    let [nx, ny, nz] = dims.map(|d| d as usize);
    let pos = |i: usize| {
        let (x, y, z) = (i % nx, (i / nx) % ny, i / (nx * ny));
        [x as f64 * sp[0], y as f64 * sp[1], z as f64 * sp[2]]
    };
    (0..nx * ny * nz)
        .map(|i| {
            let p = pos(i);
            let d = (0..nx * ny * nz)
                .filter(|&j| inside[j] != inside[i])
                .map(|j| {
                    let q = pos(j);
                    ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt()
                })
                .fold(f64::INFINITY, f64::min);
            if inside[i] {
                -d
            } else {
                d
            }
        })
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    #[test]
    fn edt_equals_brute_force(
        dims in prop::array::uniform3(1u32..7),
        sp in prop::array::uniform3(0.25f64..3.0),
        seed in any::<u64>(),
        density in 0.05f64..0.95,
    ) {
        let n = dims.iter().product::<u32>() as usize;
        let mut s = seed | 1;
        let mut inside: Vec<bool> = (0..n)
            .map(|_| {
                s ^= s << 13; s ^= s >> 7; s ^= s << 17;
                ((s >> 11) as f64 / (1u64 << 53) as f64) < density
            })
            .collect();
        // Both sides present.
        inside[0] = true;
        if n > 1 { inside[n - 1] = false; } else { return Ok(()); }
        let grid = FieldGrid::axis_aligned(dims, DVec3::ZERO, DVec3::from_array(sp));
        let f = mask_field(&Mask { dims, inside: inside.clone() }, &grid).unwrap();
        let b = brute_mask(dims, sp, &inside);
        for (got, want) in f.values.iter().zip(&b) {
            prop_assert!((f64::from(*got) - want).abs() <= 1e-6 * want.abs().max(1.0),
                "{got} vs {want}");
        }
    }
}

#[test]
fn edt_of_a_mask_without_both_sides_is_refused() {
    let grid = FieldGrid::axis_aligned([2, 2, 1], DVec3::ZERO, DVec3::ONE);
    let all = Mask {
        dims: [2, 2, 1],
        inside: vec![true; 4],
    };
    assert!(mask_field(&all, &grid).is_err());
    let empty = Mask::threshold([2, 2, 1], &[0.0, 1.0, 2.0, 3.0], 10.0);
    assert!(mask_field(&empty, &grid).is_err());
    // No feature at all: infinite, not NaN.
    assert!(distance_transform_sq([3, 1, 1], [1.0; 3], &[false; 3])
        .iter()
        .all(|v| v.is_infinite()));
}

#[test]
fn fields_read_back_through_the_volume_loader() {
    let grid = FieldGrid::axis_aligned(
        [7, 5, 4],
        DVec3::new(-1.5, 2.0, 0.25),
        DVec3::new(0.5, 0.75, 1.25),
    );
    let shape = Shape::Torus {
        center: DVec3::new(0.0, 3.5, 2.0),
        major: 1.0,
        minor: 0.4,
    };
    let field = shape_field(&shape, &grid);
    let dir = std::env::temp_dir().join(format!("texmap-sdf-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for name in ["f.nii", "f.nii.gz", "f.nrrd"] {
        let path = dir.join(name);
        let bytes = FieldFormat::for_path(&path)
            .unwrap()
            .encode(&field)
            .unwrap();
        std::fs::write(&path, bytes).unwrap();
        let v = load_volume(&path, None).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(v.dims(), grid.dims, "{name}");
        assert_eq!(v.scalar_type(), Some(ScalarType::F32), "{name}");
        assert!(
            v.world_from_voxel()
                .abs_diff_eq(grid.world_from_voxel_f32(), 1e-6),
            "{name}"
        );
        assert!(
            (v.spacing() - Vec3::new(0.5, 0.75, 1.25))
                .abs()
                .max_element()
                < 1e-6
        );
        for (k, &want) in field.values.iter().enumerate() {
            let (i, j, l) = (k % 7, (k / 7) % 5, k / 35);
            let got = v.voxel(i as u32, j as u32, l as u32);
            assert!(
                (got - want).abs() <= v.value_step(),
                "{name} {k}: {got} vs {want}"
            );
        }
        // The values themselves, exactly.
        let s = load_scalars_with(&path, None, &VolumeOptions::default()).unwrap();
        assert_eq!(s.values, field.values, "{name}");
    }
    assert!(FieldFormat::for_path(std::path::Path::new("f.png")).is_err());
    std::fs::remove_dir_all(&dir).ok();
}
