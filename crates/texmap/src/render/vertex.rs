//! The scene's vertex shader: object → world → clip, and the varyings of the draw's
//! [`VaryingLayout`](super::varyings::VaryingLayout) — raw uv sets (each texture applies its
//! own transform per pixel), vertex colour, tangent, object point, and per the lighting path
//! the world normal and position (Phong), or the lit factors D and S (Gouraud per vertex, and
//! for double-sided draws also lit with −N; flat per face).
//!
//! Flat shading draws un-indexed vertices, three per triangle; each triangle is lit once, at
//! its centroid with the geometric normal (turned towards the vertex normals when the mesh has
//! them, and towards the viewer for double-sided materials), before the vertex stage runs.

use glam::{Mat3, Mat4, Vec2, Vec3};
use rayon::prelude::*;

use super::draw::{normal_matrix, world_normal, DrawInfo, LightingPath};
use crate::pipeline::{ClipVertex, VertexShader, MAX_VARYINGS};
use crate::scene::Mesh;
use crate::shading::{Lighting, Surface, Viewer};

/// One mesh's vertex stage.
pub(super) struct SceneVertices<'a> {
    mesh: &'a Mesh,
    draw: &'a DrawInfo<'a>,
    clip_from_world: Mat4,
    normal_from_object: Mat3,
    viewer: Viewer,
    lighting: &'a Lighting<'a>,
    /// Flat shading: each triangle's factors (D, S), and whether its indices are valid.
    faces: Vec<Option<(Vec3, Vec3)>>,
}

impl<'a> SceneVertices<'a> {
    pub fn new(
        mesh: &'a Mesh,
        draw: &'a DrawInfo<'a>,
        clip_from_world: Mat4,
        viewer: Viewer,
        lighting: &'a Lighting<'a>,
    ) -> Self {
        let mut v = SceneVertices {
            mesh,
            draw,
            clip_from_world,
            normal_from_object: normal_matrix(mesh.world_from_object),
            viewer,
            lighting,
            faces: Vec::new(),
        };
        if draw.flat {
            v.faces = (0..mesh.triangle_count())
                .into_par_iter()
                .with_min_len(1024)
                .map(|t| v.light_face(t))
                .collect();
        }
        v
    }

    /// The index list to draw with: the mesh's, or for flat shading one vertex per corner.
    pub fn indices(&self) -> Option<Vec<u32>> {
        self.draw
            .flat
            .then(|| (0..3 * self.faces.len() as u32).collect())
    }

    fn world_position(&self, i: usize) -> Vec3 {
        self.mesh
            .world_from_object
            .transform_point3(self.mesh.positions[i])
    }

    fn world_normal(&self, i: usize) -> Vec3 {
        world_normal(self.normal_from_object, self.mesh.normals[i])
    }

    /// Triangle `t`'s corners, when all three index a position.
    fn corners(&self, t: usize) -> Option<[usize; 3]> {
        let idx = &self.mesh.indices[3 * t..3 * t + 3];
        let n = self.mesh.positions.len();
        idx.iter()
            .all(|&i| (i as usize) < n)
            .then(|| [idx[0], idx[1], idx[2]].map(|i| i as usize))
    }

    /// Triangle `t` lit once at its centroid with the face normal (`None` for bad indices).
    fn light_face(&self, t: usize) -> Option<(Vec3, Vec3)> {
        let ids = self.corners(t)?;
        let p = ids.map(|i| self.world_position(i));
        let mut n = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
        if self.draw.mirrored {
            n = -n;
        }
        let has_normals = self.mesh.normals.len() == self.mesh.positions.len();
        if !self.mesh.normals.is_empty() && has_normals {
            let avg = ids.iter().map(|&i| self.world_normal(i)).sum::<Vec3>();
            if avg.dot(n) < 0.0 {
                n = -n;
            }
        }
        let centroid = (p[0] + p[1] + p[2]) / 3.0;
        let material = self.draw.material;
        if material.double_sided && n.dot(self.viewer.towards(centroid)) < 0.0 {
            n = -n;
        }
        let surface = Surface::new(material, centroid, n);
        Some(
            self.draw
                .illuminate_vertex(&surface, self.lighting, self.viewer),
        )
    }

    /// The varyings every path carries: uv sets, vertex colour, tangent, object point.
    fn common_varyings(&self, i: usize) -> [f32; MAX_VARYINGS] {
        let (mesh, layout) = (self.mesh, &self.draw.layout);
        let mut var = [0.0; MAX_VARYINGS];
        let uv = mesh.uvs.get(i).copied().unwrap_or(Vec2::ZERO);
        layout.uv0.write(&mut var, uv.to_array());
        if let Some(s) = layout.color {
            s.write(&mut var, mesh.colors[i].to_array());
        }
        if let Some(s) = layout.uv1 {
            s.write(&mut var, mesh.uvs1[i].to_array());
        }
        if let Some(s) = layout.tangent {
            let t = mesh.tangents[i];
            let world =
                (Mat3::from_mat4(mesh.world_from_object) * t.truncate()).normalize_or_zero();
            s.write(&mut var, world.extend(t.w).to_array());
        }
        if let Some(s) = layout.object_position {
            s.write(&mut var, mesh.positions[i].to_array());
        }
        if let Some(s) = layout.object_normal {
            let n = mesh.normals.get(i).copied().unwrap_or(Vec3::ZERO);
            s.write(&mut var, n.to_array());
        }
        var
    }

    /// Corner `k` of flat triangle `t`.
    fn flat_vertex(&self, t: usize, k: usize) -> ClipVertex {
        let (Some(ids), Some(lit)) = (self.corners(t), self.faces[t]) else {
            // Bad indices: a vertex the pipeline rejects.
            return ClipVertex {
                clip: self.clip_from_world * Vec3::NAN.extend(1.0),
                varyings: [0.0; MAX_VARYINGS],
            };
        };
        let mut varyings = self.common_varyings(ids[k]);
        if let Some(f) = self.draw.layout.factors {
            f.write(&mut varyings, lit);
        }
        let p = self.world_position(ids[k]);
        // Projectors read the position (the face normal comes from its derivatives).
        if let Some(s) = self.draw.layout.position {
            s.write(&mut varyings, p.to_array());
        }
        ClipVertex {
            clip: self.clip_from_world * p.extend(1.0),
            varyings,
        }
    }
}

impl VertexShader for SceneVertices<'_> {
    fn vertex_count(&self) -> usize {
        if self.draw.flat {
            3 * self.faces.len()
        } else {
            self.mesh.positions.len()
        }
    }

    fn vertex(&self, i: usize) -> ClipVertex {
        if self.draw.flat {
            return self.flat_vertex(i / 3, i % 3);
        }
        let (draw, layout) = (self.draw, &self.draw.layout);
        let p = self.world_position(i);
        let mut varyings = self.common_varyings(i);
        match draw.path {
            LightingPath::Unlit => {}
            LightingPath::PerPixel => {
                if let Some(s) = layout.normal {
                    s.write(&mut varyings, self.world_normal(i).to_array());
                }
                if let Some(s) = layout.position {
                    s.write(&mut varyings, p.to_array());
                }
            }
            LightingPath::Interpolated => {
                let material = draw.material;
                let surface = Surface::new(material, p, self.world_normal(i));
                let lit = |s: &Surface| draw.illuminate_vertex(s, self.lighting, self.viewer);
                if let Some(f) = layout.factors {
                    f.write(&mut varyings, lit(&surface));
                }
                if let Some(f) = layout.back_factors {
                    let back = Surface {
                        normal: -surface.normal,
                        ..surface
                    };
                    f.write(&mut varyings, lit(&back));
                }
                // Read by the frame's projectors (`projectors.rs`).
                if let Some(s) = layout.normal {
                    s.write(&mut varyings, surface.normal.to_array());
                }
                if let Some(s) = layout.position {
                    s.write(&mut varyings, p.to_array());
                }
            }
        }
        ClipVertex {
            clip: self.clip_from_world * p.extend(1.0),
            varyings,
        }
    }
}
