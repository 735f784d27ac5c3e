//! MikkTSpace tangents for meshes that have normals and texture coordinates but no tangents
//! (what glTF asks for when a normal map is used without TANGENT).
//!
//! MikkTSpace works on faces, so a vertex shared by faces may receive different tangents: the
//! mesh is unwelded into face corners, tangents generated, and corners with identical
//! attributes welded again.

use std::collections::HashMap;

use glam::{Vec2, Vec4};

use super::Mesh;

struct Corners<'a> {
    mesh: &'a Mesh,
    uvs: &'a [Vec2],
    out: Vec<Vec4>,
}

impl bevy_mikktspace::Geometry for Corners<'_> {
    fn num_faces(&self) -> usize {
        self.mesh.indices.len() / 3
    }
    fn num_vertices_of_face(&self, _face: usize) -> usize {
        3
    }
    fn position(&self, face: usize, vert: usize) -> [f32; 3] {
        self.mesh.positions[self.mesh.indices[face * 3 + vert] as usize].to_array()
    }
    fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
        self.mesh.normals[self.mesh.indices[face * 3 + vert] as usize].to_array()
    }
    fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
        self.uvs[self.mesh.indices[face * 3 + vert] as usize].to_array()
    }
    fn set_tangent(
        &mut self,
        tangent_space: Option<bevy_mikktspace::TangentSpace>,
        face: usize,
        vert: usize,
    ) {
        let t = tangent_space.map_or([1.0, 0.0, 0.0, 1.0], |t| t.tangent_encoded());
        self.out[face * 3 + vert] = Vec4::from(t);
    }
}

/// Generates `mesh.tangents` from its normals and the uv set `set` (0 or 1), re-indexing the
/// mesh where corners need different tangents. Returns false (and leaves the mesh as it was)
/// when the mesh lacks normals or that uv set, or indices are out of range.
pub fn generate(mesh: &mut Mesh, set: u32) -> bool {
    let n = mesh.positions.len();
    let uvs = if set == 1 { &mesh.uvs1 } else { &mesh.uvs };
    if mesh.normals.len() != n || uvs.len() != n || mesh.indices.iter().any(|&i| i as usize >= n) {
        return false;
    }
    let uvs = uvs.clone();
    let mut corners = Corners {
        mesh,
        uvs: &uvs,
        out: vec![Vec4::new(1.0, 0.0, 0.0, 1.0); mesh.indices.len()],
    };
    if bevy_mikktspace::generate_tangents(&mut corners).is_err() {
        return false;
    }
    let tangent_of_corner = corners.out;
    // Which per-vertex attributes the mesh has, decided before any vertex is added (their
    // lengths grow with the positions below).
    let (has_uvs, has_uvs1, has_colors) = (
        mesh.uvs.len() == n,
        mesh.uvs1.len() == n,
        mesh.colors.len() == n,
    );
    // Weld: a vertex keeps its index when all its corners agree, else it is duplicated.
    let mut tangents = vec![Vec4::ZERO; n];
    let mut assigned = vec![false; n];
    let mut extra: HashMap<(u32, [u32; 4]), u32> = HashMap::new();
    let bits = |t: Vec4| t.to_array().map(f32::to_bits);
    for (c, t) in tangent_of_corner.into_iter().enumerate() {
        let v = mesh.indices[c] as usize;
        if !assigned[v] {
            assigned[v] = true;
            tangents[v] = t;
            continue;
        }
        if bits(tangents[v]) == bits(t) {
            continue;
        }
        let key = (v as u32, bits(t));
        let new = *extra.entry(key).or_insert_with(|| {
            let k = mesh.positions.len() as u32;
            mesh.positions.push(mesh.positions[v]);
            mesh.normals.push(mesh.normals[v]);
            for (attr, has) in [(&mut mesh.uvs, has_uvs), (&mut mesh.uvs1, has_uvs1)] {
                if has {
                    let x: Vec2 = attr[v];
                    attr.push(x);
                }
            }
            if has_colors {
                let x = mesh.colors[v];
                mesh.colors.push(x);
            }
            tangents.push(t);
            k
        });
        mesh.indices[c] = new;
    }
    mesh.tangents = tangents;
    true
}

/// Generates tangents for every mesh without them whose material has a normal map (using the
/// map's uv set). Returns the indices of meshes where that was not possible.
pub fn generate_where_needed(
    meshes: &mut [Mesh],
    materials: &[crate::shading::Material],
) -> Vec<usize> {
    let mut failed = Vec::new();
    for (i, m) in meshes.iter_mut().enumerate() {
        if !m.tangents.is_empty() {
            continue;
        }
        let Some(map) = materials
            .get(m.material)
            .and_then(|mat| mat.map(crate::shading::MapChannel::Normal))
        else {
            continue;
        };
        if !generate(m, map.slot.tex_coord) {
            failed.push(i);
        }
    }
    failed
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn a_quad_in_the_xy_plane_gets_tangent_plus_x() {
        let mut m = Mesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y],
            normals: vec![Vec3::Z; 4],
            // glTF uv: v down the image, so +y on the mesh is −v.
            uvs: vec![
                Vec2::new(0.0, 1.0),
                Vec2::new(1.0, 1.0),
                Vec2::new(1.0, 0.0),
                Vec2::ZERO,
            ],
            indices: vec![0, 1, 2, 0, 2, 3],
            ..Default::default()
        };
        assert!(generate(&mut m, 0));
        assert_eq!(m.tangents.len(), m.positions.len());
        for t in &m.tangents {
            assert!((t.truncate() - Vec3::X).length() < 1e-4, "{t}");
        }
    }

    #[test]
    fn every_attribute_follows_the_added_vertices() {
        // u along x on the first triangle, along y on the second: both shared corners get
        // two tangents, so two vertices are added; each must carry both uv sets and the
        // colour (an added vertex once left set 1 short, and the draw read set 0 instead).
        let mut m = Mesh {
            positions: vec![
                Vec3::new(-1.0, -1.0, 0.0),
                Vec3::new(1.0, -1.0, 0.0),
                Vec3::new(1.0, 1.0, 0.0),
                Vec3::new(-1.0, 1.0, 0.0),
            ],
            normals: vec![Vec3::Z; 4],
            uvs: vec![
                Vec2::new(0.0, 1.0),
                Vec2::new(1.0, 1.0),
                Vec2::new(1.0, 0.0),
                Vec2::new(1.0, 1.0),
            ],
            uvs1: vec![Vec2::splat(0.5); 4],
            colors: vec![glam::Vec4::ONE; 4],
            indices: vec![0, 1, 2, 0, 2, 3],
            ..Default::default()
        };
        assert!(generate(&mut m, 0));
        let n = m.positions.len();
        assert!(n >= 6, "{n} vertices: the corners were not split");
        assert_eq!(
            [m.uvs.len(), m.uvs1.len(), m.colors.len(), m.normals.len()],
            [n; 4]
        );
        assert_eq!(m.tangents.len(), n);
    }

    #[test]
    fn missing_uvs_are_refused() {
        let mut m = Mesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
            normals: vec![Vec3::Z; 3],
            indices: vec![0, 1, 2],
            ..Default::default()
        };
        assert!(!generate(&mut m, 0));
    }
}
