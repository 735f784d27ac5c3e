//! Displacement mapping at load: each mesh whose material has a [`Displacement`] is
//! tessellated (every edge cut into the same number of segments, so the two triangles of an
//! edge cut it alike) and its vertices moved along the normal by the height map, then its
//! normals and tangents recomputed.
//!
//! No cracks: a new vertex on an edge is computed from the edge's two endpoints in one order
//! (by position, then index), so every triangle that shares the edge — also across a uv or
//! normal seam, where the endpoints are different vertices at the same position — gets the
//! same point; and every vertex at one position moves by the same vector (the mean of their
//! normals, times the mean of their heights), so positions shared before stay shared.
//!
//! The height is read through the sampling engine with the footprint of one new edge in uv
//! (the parent triangle's uv edges over the segment count), so a fine tessellation reads a
//! fine level and a coarse one a prefiltered level.
//!
//! The triangle budget: a mesh of `t` triangles cut into `s` segments per edge becomes
//! `t·s²` triangles; the sum over the displaced meshes plus the others must not exceed
//! [`MAX_DISPLACED_TRIANGLES`] (or the caller's limit).

use std::collections::HashMap;

use glam::{Mat4, Vec2, Vec3, Vec4};

use super::{Mesh, Scene};
use crate::shading::relief::{Displacement, Tessellation};
use crate::texture::{sample, Footprint};
use crate::{Error, Result};

/// The default triangle budget of a displaced scene.
pub const MAX_DISPLACED_TRIANGLES: usize = 8_000_000;

/// The most segments per edge (`2^10`).
const MAX_SEGMENTS: u32 = 1 << 10;

/// The view an `edge_px` tessellation is measured in: world → clip, and the frame's size.
#[derive(Clone, Copy, Debug)]
pub struct DisplaceView {
    pub clip_from_world: Mat4,
    pub width: u32,
    pub height: u32,
}

/// What [`displace_scene`] does.
#[derive(Clone, Copy, Debug, Default)]
pub struct DisplaceOptions {
    /// Replaces every displacement's tessellation.
    pub tessellation: Option<Tessellation>,
    /// The most triangles the scene may have afterwards (0: [`MAX_DISPLACED_TRIANGLES`]).
    pub max_triangles: usize,
}

/// The segments per edge of `mesh` under `t`: `2^level`, or enough that its longest edge
/// seen from `view` is at most `edge_px` pixels (1 without a view).
#[must_use]
pub fn segments(mesh: &Mesh, t: Tessellation, view: Option<&DisplaceView>) -> u32 {
    match t {
        Tessellation::Level(l) => 1u32 << l.min(10),
        Tessellation::EdgePixels(px) => {
            let Some(v) = view else { return 1 };
            let m = v.clip_from_world * mesh.world_from_object;
            let size = Vec2::new(v.width as f32, v.height as f32);
            let screen: Vec<Option<Vec2>> = mesh
                .positions
                .iter()
                .map(|p| {
                    let c = m * p.extend(1.0);
                    (c.w > 1e-6).then(|| (Vec2::new(c.x, c.y) / c.w * 0.5 + 0.5) * size)
                })
                .collect();
            let mut longest = 0.0f32;
            for t in mesh.indices.chunks_exact(3) {
                let s = [0, 1, 2].map(|k| screen.get(t[k] as usize).copied().flatten());
                if let [Some(a), Some(b), Some(c)] = s {
                    longest = longest
                        .max(a.distance(b))
                        .max(b.distance(c))
                        .max(c.distance(a));
                }
            }
            if !longest.is_finite() {
                return MAX_SEGMENTS;
            }
            ((longest / px.max(0.5)).ceil() as u32).clamp(1, MAX_SEGMENTS)
        }
    }
}

/// The triangles `scene` will have once displaced (`t·s²` per displaced mesh).
#[must_use]
pub fn planned_triangles(
    scene: &Scene,
    options: &DisplaceOptions,
    view: Option<&DisplaceView>,
) -> u128 {
    scene
        .meshes
        .iter()
        .map(|mesh| {
            let t = mesh.triangle_count() as u128;
            match displacement_of(scene, mesh) {
                Some(d) => {
                    let s = segments(mesh, options.tessellation.unwrap_or(d.tessellation), view);
                    t * u128::from(s) * u128::from(s)
                }
                None => t,
            }
        })
        .sum()
}

fn displacement_of<'a>(scene: &'a Scene, mesh: &Mesh) -> Option<&'a Displacement> {
    scene
        .materials
        .get(mesh.material)
        .and_then(|m| m.displacement.as_deref())
}

/// Tessellates and displaces every mesh whose material has a displacement; returns how many.
///
/// # Errors
/// [`Error::Parameter`] when the scene would have more triangles than the budget (nothing
/// is changed then).
pub fn displace_scene(
    scene: &mut Scene,
    options: &DisplaceOptions,
    view: Option<&DisplaceView>,
) -> Result<usize> {
    let max = if options.max_triangles == 0 {
        MAX_DISPLACED_TRIANGLES
    } else {
        options.max_triangles
    };
    let planned = planned_triangles(scene, options, view);
    if planned > max as u128 {
        return Err(Error::parameter(format!(
            "displacement would make {planned} triangles (each displaced mesh's triangles × \
             segments per edge²), more than the budget of {max}"
        )));
    }
    let mut count = 0;
    for i in 0..scene.meshes.len() {
        let Some(d) = displacement_of(scene, &scene.meshes[i]).cloned() else {
            continue;
        };
        let mesh = &scene.meshes[i];
        let s = segments(mesh, options.tessellation.unwrap_or(d.tessellation), view);
        let (mut out, footprints) = tessellate(mesh, s);
        displace(&mut out, &footprints, &d);
        scene.meshes[i] = out;
        count += 1;
    }
    Ok(count)
}

/// Positions compare by their bits (−0 and 0 apart, which only splits a group).
fn key(p: Vec3) -> [u32; 3] {
    p.to_array().map(f32::to_bits)
}

/// `positions` with every position within a millionth of the mesh's extent of an earlier one
/// replaced by that one (bit for bit): generated meshes put a seam's or a pole's copies a
/// rounding error apart (sin 2π is not 0), and those copies must split edges and move alike.
#[must_use]
pub fn weld(positions: &[Vec3]) -> Vec<Vec3> {
    let (lo, hi) = positions.iter().fold(
        (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
        |(lo, hi), &p| (lo.min(p), hi.max(p)),
    );
    let cell = ((hi - lo).max_element() * 1e-6).max(f32::MIN_POSITIVE);
    let mut first: HashMap<[i64; 3], Vec3> = HashMap::new();
    positions
        .iter()
        .map(|&p| {
            if !p.is_finite() {
                return p;
            }
            let q = ((p - lo) / cell).round().as_i64vec3().to_array();
            *first.entry(q).or_insert(p)
        })
        .collect()
}

/// `mesh` with every edge cut into `s` segments (`s²` triangles per triangle), and each
/// vertex's uv footprint (one new edge along each of its first triangle's two uv edges).
/// Tangents are dropped (the caller recomputes them); triangles with two corners at one
/// position are dropped.
#[must_use]
pub fn tessellate(mesh: &Mesh, s: u32) -> (Mesh, Vec<[Vec2; 2]>) {
    let n = mesh.positions.len();
    let has = |len: usize| len == n;
    let mut out = Mesh {
        positions: weld(&mesh.positions),
        normals: if has(mesh.normals.len()) {
            mesh.normals.clone()
        } else {
            Vec::new()
        },
        uvs: if has(mesh.uvs.len()) {
            mesh.uvs.clone()
        } else {
            Vec::new()
        },
        uvs1: if has(mesh.uvs1.len()) {
            mesh.uvs1.clone()
        } else {
            Vec::new()
        },
        colors: if has(mesh.colors.len()) {
            mesh.colors.clone()
        } else {
            Vec::new()
        },
        tangents: Vec::new(),
        indices: Vec::with_capacity(mesh.indices.len() * (s * s) as usize),
        material: mesh.material,
        world_from_object: mesh.world_from_object,
    };
    let mut footprints = vec![[Vec2::ZERO; 2]; n];
    let mut seen = vec![false; n];
    let mut edges: HashMap<(u32, u32), u32> = HashMap::new();
    let sf = s as f32;
    // A new vertex at weights w of corners c.
    let add = |out: &mut Mesh, c: [usize; 3], w: [f32; 3]| -> u32 {
        let mix3 = |v: &[Vec3]| v[c[0]] * w[0] + v[c[1]] * w[1] + v[c[2]] * w[2];
        let mix2 = |v: &[Vec2]| v[c[0]] * w[0] + v[c[1]] * w[1] + v[c[2]] * w[2];
        let mix4 = |v: &[Vec4]| v[c[0]] * w[0] + v[c[1]] * w[1] + v[c[2]] * w[2];
        let p = mix3(&out.positions);
        out.positions.push(p);
        if !out.normals.is_empty() {
            let nn = mix3(&out.normals).normalize_or_zero();
            out.normals.push(nn);
        }
        if !out.uvs.is_empty() {
            let u = mix2(&out.uvs);
            out.uvs.push(u);
        }
        if !out.uvs1.is_empty() {
            let u = mix2(&out.uvs1);
            out.uvs1.push(u);
        }
        if !out.colors.is_empty() {
            let col = mix4(&out.colors);
            out.colors.push(col);
        }
        (out.positions.len() - 1) as u32
    };
    let mut grid: Vec<u32> = Vec::new();
    for tri in mesh.indices.chunks_exact(3) {
        if tri.iter().any(|&i| i as usize >= n) {
            continue;
        }
        let [i0, i1, i2] = [tri[0], tri[1], tri[2]];
        // A triangle with two corners at one position (a uv sphere's pole) has no area; cut
        // and displaced, its inner points would move apart and open a flap.
        let [k0, k1, k2] = [i0, i1, i2].map(|i| key(out.positions[i as usize]));
        if k0 == k1 || k1 == k2 || k2 == k0 {
            continue;
        }
        let fp = if out.uvs.is_empty() {
            [Vec2::ZERO; 2]
        } else {
            let u = |i: u32| out.uvs[i as usize];
            [(u(i1) - u(i0)) / sf, (u(i2) - u(i0)) / sf]
        };
        // The vertex k segments from `a` towards `b` on edge a–b (0 < k < s).
        let mut edge_vertex = |out: &mut Mesh, a: u32, b: u32, k: u32| -> u32 {
            let (pa, pb) = (out.positions[a as usize], out.positions[b as usize]);
            let a_first = (pa.x, pa.y, pa.z, a)
                .partial_cmp(&(pb.x, pb.y, pb.z, b))
                .is_none_or(|o| o.is_le());
            let (lo, hi, kk) = if a_first { (a, b, k) } else { (b, a, s - k) };
            let start = *edges.entry((lo, hi)).or_insert_with(|| {
                let first = out.positions.len() as u32;
                for j in 1..s {
                    let t = j as f32 / sf;
                    add(
                        out,
                        [lo as usize, hi as usize, lo as usize],
                        [1.0 - t, t, 0.0],
                    );
                }
                first
            });
            start + kk - 1
        };
        let idx = |a: u32, b: u32| ((a * (2 * s + 3 - a)) / 2 + b) as usize;
        grid.clear();
        grid.resize(((s + 1) * (s + 2) / 2) as usize, 0);
        for a in 0..=s {
            for b in 0..=s - a {
                let v = if a == 0 && b == 0 {
                    i0
                } else if a == s {
                    i1
                } else if b == s {
                    i2
                } else if b == 0 {
                    edge_vertex(&mut out, i0, i1, a)
                } else if a == 0 {
                    edge_vertex(&mut out, i0, i2, b)
                } else if a + b == s {
                    edge_vertex(&mut out, i1, i2, b)
                } else {
                    let (w1, w2) = (a as f32 / sf, b as f32 / sf);
                    add(
                        &mut out,
                        [i0 as usize, i1 as usize, i2 as usize],
                        [1.0 - w1 - w2, w1, w2],
                    )
                };
                grid[idx(a, b)] = v;
            }
        }
        for a in 0..s {
            for b in 0..s - a {
                out.indices
                    .extend([grid[idx(a, b)], grid[idx(a + 1, b)], grid[idx(a, b + 1)]]);
                if a + b + 1 < s {
                    out.indices.extend([
                        grid[idx(a + 1, b)],
                        grid[idx(a + 1, b + 1)],
                        grid[idx(a, b + 1)],
                    ]);
                }
            }
        }
        footprints.resize(out.positions.len(), fp);
        seen.resize(out.positions.len(), false);
        for &v in &grid {
            if !seen[v as usize] {
                seen[v as usize] = true;
                footprints[v as usize] = fp;
            }
        }
    }
    (out, footprints)
}

/// Moves `mesh`'s vertices along their normals by `d`'s height map (read with each vertex's
/// uv `footprints`), every vertex at one position by the same vector; then recomputes smooth
/// normals (area-weighted over each position) and MikkTSpace tangents.
pub fn displace(mesh: &mut Mesh, footprints: &[[Vec2; 2]], d: &Displacement) {
    let n = mesh.positions.len();
    let mut groups: HashMap<[u32; 3], usize> = HashMap::new();
    let group: Vec<usize> = mesh
        .positions
        .iter()
        .map(|&p| {
            let next = groups.len();
            *groups.entry(key(p)).or_insert(next)
        })
        .collect();
    let count = groups.len();
    // The normal before moving: the mesh's, or the faces' (area-weighted).
    let normals = if mesh.normals.len() == n {
        mesh.normals.clone()
    } else {
        face_normals(mesh, &group, count)
    };
    let mut normal = vec![Vec3::ZERO; count];
    let mut height = vec![(0.0f32, 0u32); count];
    let slot = &d.slot;
    for i in 0..n {
        let g = group[i];
        normal[g] += normals[i];
        let uv = mesh.uvs.get(i).copied().unwrap_or(Vec2::ZERO);
        let [dx, dy] = footprints.get(i).copied().unwrap_or([Vec2::ZERO; 2]);
        let fp = slot.transform.apply_footprint(&Footprint::new(uv, dx, dy));
        let fp = Footprint::new(
            fp.uv * slot.uv_scale,
            fp.duv_dx * slot.uv_scale,
            fp.duv_dy * slot.uv_scale,
        );
        let h = sample(&slot.texture, &slot.sampler, &fp).x;
        height[g].0 += h;
        height[g].1 += 1;
    }
    for i in 0..n {
        let g = group[i];
        let (sum, k) = height[g];
        let h = sum / k.max(1) as f32;
        mesh.positions[i] += normal[g].normalize_or_zero() * (d.scale * (h - d.base));
    }
    let smooth = face_normals(mesh, &group, count);
    mesh.normals = smooth;
    mesh.tangents.clear();
    if mesh.uvs.len() == n {
        super::tangents::generate(mesh, 0);
    }
}

/// Each vertex's normal: the area-weighted sum of the faces' normals over every vertex at its
/// position (`group`), normalized.
fn face_normals(mesh: &Mesh, group: &[usize], count: usize) -> Vec<Vec3> {
    let mut sum = vec![Vec3::ZERO; count];
    let p = &mesh.positions;
    for t in mesh.indices.chunks_exact(3) {
        let [a, b, c] = [t[0], t[1], t[2]].map(|i| i as usize);
        let f = (p[b] - p[a]).cross(p[c] - p[a]);
        for v in [a, b, c] {
            sum[group[v]] += f;
        }
    }
    group.iter().map(|&g| sum[g].normalize_or_zero()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn quad() -> Mesh {
        Mesh {
            positions: vec![
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(1.0, 1.0, 0.0),
                Vec3::new(0.0, 1.0, 0.0),
            ],
            normals: vec![Vec3::Z; 4],
            uvs: vec![Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::Y],
            indices: vec![0, 1, 2, 0, 2, 3],
            world_from_object: Mat4::IDENTITY,
            ..Mesh::default()
        }
    }

    #[test]
    fn tessellation_shares_edge_vertices_and_counts_s_squared() {
        for s in [1, 2, 3, 8] {
            let (m, fp) = tessellate(&quad(), s);
            assert_eq!(m.triangle_count(), 2 * (s * s) as usize);
            // (s+1)² grid points, each once: the diagonal's points are shared.
            assert_eq!(m.positions.len(), ((s + 1) * (s + 1)) as usize, "s {s}");
            assert_eq!(fp.len(), m.positions.len());
            // Winding kept: every triangle faces +z.
            for t in m.indices.chunks_exact(3) {
                let p = |i: u32| m.positions[i as usize];
                let f = (p(t[1]) - p(t[0])).cross(p(t[2]) - p(t[0]));
                assert!(f.z > 0.0, "s {s}: {f}");
            }
        }
    }

    #[test]
    fn a_seam_gets_the_same_edge_points_from_both_sides() {
        // The diagonal's endpoints duplicated (a uv seam): the two triangles use different
        // vertices at the same positions, in opposite orders.
        let mut m = quad();
        m.positions.extend([m.positions[0], m.positions[2]]);
        m.normals.extend([Vec3::Z; 2]);
        m.uvs.extend([Vec2::new(5.0, 5.0), Vec2::new(6.0, 6.0)]);
        m.indices = vec![0, 1, 2, 5, 3, 4];
        let (t, _) = tessellate(&m, 5);
        let mut keys: Vec<[u32; 3]> = t.positions.iter().map(|&p| key(p)).collect();
        keys.sort_unstable();
        keys.dedup();
        assert_eq!(keys.len(), 36, "diagonal points must coincide bit for bit");
    }
}
