//! A mesh's `texgen`: texture coordinates generated per vertex by a projection in object
//! space, replacing uv set 0 or 1. Seam triangles get their own vertex copies (no smear
//! where u wraps), and every other attribute follows the copies; tangents follow set 0, so
//! they are dropped (and regenerated where a normal map needs them) when set 0 changes.

use glam::Vec3;

use super::spec::TexgenSpec;
use crate::geometry::Projection;
use crate::scene::Mesh;

/// Replaces uv set `t.set` of `mesh` with per-vertex coordinates from the projection; the
/// error is the table's problem, for the caller to prefix.
pub(super) fn apply_texgen(mesh: &mut Mesh, t: &TexgenSpec) -> Result<(), String> {
    let mut projection = Projection::parse(&t.projection).ok_or_else(|| {
        format!(
            "texgen: projection {:?}: expected planar-x, planar-y, planar-z, cylindrical, spherical, cube or bounding-sphere",
            t.projection
        )
    })?;
    if t.set > 1 {
        return Err(format!("texgen: set {} is not 0 or 1", t.set));
    }
    if let Projection::BoundingSphere { center } = &mut projection {
        *center = t.center.map_or_else(|| mesh.object_center(), Vec3::from);
    }
    let (uvs, indices, remap) = crate::geometry::texgen::generate_uvs(
        &projection,
        &mesh.positions,
        &mesh.normals,
        &mesh.indices,
    );
    fn follow<T: Copy>(v: &mut Vec<T>, remap: &[u32], n: usize) {
        if v.len() == n {
            *v = remap.iter().map(|&i| v[i as usize]).collect();
        }
    }
    let n = mesh.positions.len();
    follow(&mut mesh.positions, &remap, n);
    follow(&mut mesh.normals, &remap, n);
    follow(&mut mesh.uvs, &remap, n);
    follow(&mut mesh.uvs1, &remap, n);
    follow(&mut mesh.colors, &remap, n);
    // Tangents follow set 0; they are regenerated when set 0 changes.
    if t.set == 0 {
        mesh.tangents.clear();
        mesh.uvs = uvs;
    } else {
        follow(&mut mesh.tangents, &remap, n);
        mesh.uvs1 = uvs;
    }
    mesh.indices = indices;
    Ok(())
}
