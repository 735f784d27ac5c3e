//! Shadow maps that hold distance-field surfaces beside the meshes
//! ([`shadow_maps_with_fields`]): a field shadows meshes and itself, and meshes shadow it.
//!
//! Rules:
//! - Each field's box, as a mesh, widens the maps' views and depth ranges as a casting mesh
//!   does (it is not drawn). After the meshes' depth pass, every texel's ray from the light
//!   is traced against each field's core surface ([`FieldCaster`]), and the texel keeps the
//!   nearer of the two depths. Rows are traced in parallel; each texel's depth depends on
//!   its ray only, so the maps are the same at any thread count.
//! - Receivers look the maps up as meshes do (`ShadowMaps::visibility`: the normal offset,
//!   the biases, the filter), so a field's shadows are filtered like a mesh's.
//! - With no casting light (`shadows` off) the maps are empty and nothing changes.

use glam::{Mat4, Vec3};
use rayon::prelude::*;

use super::shadow::shadow_maps_with;
use super::Settings;
use crate::camera::Camera;
use crate::scene::{Mesh, Scene};
use crate::shading::shadow::{MapView, ShadowMap, ShadowMaps};
use crate::volume::sdf::FieldCaster;
use crate::volume::{Method, SceneVolume};
use crate::Result;

/// The shadow maps of `scene`'s casting lights under `settings` (as
/// [`super::shadow_maps`]) holding the meshes and the core surfaces of the distance fields
/// among `volumes` (drawn as `camera` sees them: its up is the melt's).
///
/// # Errors
/// As [`super::shadow_maps`].
pub fn shadow_maps_with_fields(
    scene: &Scene,
    volumes: &[SceneVolume],
    camera: &Camera,
    settings: &Settings,
) -> Result<ShadowMaps> {
    let fields: Vec<&SceneVolume> = volumes
        .iter()
        .filter(|v| matches!(v.method, Method::Surface | Method::Hypertexture))
        .collect();
    let proxies: Vec<Mesh> = fields
        .iter()
        .map(|v| box_mesh(v.volume.world_corners()))
        .collect();
    let casters: Vec<FieldCaster> = fields
        .iter()
        .map(|v| {
            FieldCaster::new(
                &v.volume,
                camera,
                &v.params,
                &v.look,
                v.hypertexture
                    .as_ref()
                    .filter(|_| v.method == Method::Hypertexture),
            )
        })
        .collect();
    shadow_maps_with(scene, settings, &proxies, &|map: &mut ShadowMap| {
        trace_into(map, &casters);
    })
}

/// A box's corners (x fastest, then y, then z) as a closed mesh of twelve triangles.
fn box_mesh(c: [Vec3; 8]) -> Mesh {
    const FACES: [[u32; 4]; 6] = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    Mesh {
        positions: c.to_vec(),
        indices: FACES
            .iter()
            .flat_map(|&[a, b, c, d]| [a, b, c, a, c, d])
            .collect(),
        world_from_object: Mat4::IDENTITY,
        ..Mesh::default()
    }
}

/// Every texel of `map` keeps the nearer of its depth and the casters' first hit along its
/// ray.
fn trace_into(map: &mut ShadowMap, casters: &[FieldCaster]) {
    if casters.is_empty() {
        return;
    }
    let n = map.size as usize;
    let world_from_view = map.view_from_world.inverse();
    let size = map.size as f32;
    let m = &*map;
    let rows: Vec<Vec<f32>> = (0..n)
        .into_par_iter()
        .map(|j| {
            (0..n)
                .map(|i| {
                    let old = m.depth[m.index(i, j)];
                    let (u, v) = (i as f32 + 0.5, j as f32 + 0.5);
                    // The texel's ray in view space: its origin, unit direction, and the
                    // view depth gained per unit along it.
                    let (o, d, per) = match m.view {
                        MapView::Orthographic { min, max } => {
                            let t = (max - min) / size;
                            let x = min.x + u * t.x;
                            let y = max.y - v * t.y;
                            (Vec3::new(x, y, -m.near), Vec3::NEG_Z, 1.0)
                        }
                        MapView::Perspective { tan_half } => {
                            let s = 2.0 * tan_half / size;
                            let r = Vec3::new(u * s - tan_half, tan_half - v * s, -1.0);
                            let len = r.length();
                            (Vec3::ZERO, r / len, 1.0 / len)
                        }
                    };
                    let start = -o.z;
                    let t_max = ((old.min(m.far) - start) / per).max(0.0);
                    let origin = world_from_view.transform_point3(o);
                    let dir = world_from_view.transform_vector3(d).normalize();
                    casters
                        .iter()
                        .filter_map(|c| c.hit(origin, dir, t_max))
                        .map(|t| start + t * per)
                        .fold(old, f32::min)
                })
                .collect()
        })
        .collect();
    for (j, row) in rows.iter().enumerate() {
        for (i, &d) in row.iter().enumerate() {
            let at = map.index(i, j);
            map.depth[at] = d;
        }
    }
    map.refresh_tiles();
}
