//! glTF mesh primitives → [`Mesh`]es: POSITION, NORMAL, TEXCOORD_0/1, COLOR_0 (VEC3 or
//! VEC4, any component type) and TANGENT, each checked to have one element per position;
//! morph targets at their default weights (the node's, else the mesh's); skins in the rest
//! pose (`skin`); strips and fans converted to lists in glTF's vertex orders; indices
//! checked against the vertex count. Points and lines are skipped with a warning. Missing
//! tangents are generated (MikkTSpace) when the material has a normal map.

use glam::{Mat4, Vec2, Vec3, Vec4};
use gltf::mesh::Mode;
use gltf::Semantic;

use super::document::Loader;
use crate::scene::{tangents, Mesh};
use crate::shading::MapChannel;
use crate::{Error, Result};

impl Loader<'_> {
    /// Primitive `prim` of `node`'s mesh as a [`Mesh`] (`name` is for messages), posed with
    /// the node's morph weights and skin; `None` (a warning) for points, lines, or no
    /// POSITION.
    pub(super) fn primitive(
        &mut self,
        node: &gltf::Node,
        prim: &gltf::Primitive,
        world: Mat4,
        weights: &[f32],
        name: &str,
    ) -> Result<Option<Mesh>> {
        let skip = |this: &mut Self, why: &str| {
            this.warnings.push(format!(
                "{}: primitive {name} skipped: {why}",
                this.path.display()
            ));
            Ok(None)
        };
        let mode = prim.mode();
        if !matches!(
            mode,
            Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
        ) {
            return skip(self, "points and lines are not drawn");
        }
        let Some(pos_acc) = prim.get(&Semantic::Positions) else {
            return skip(self, "it has no POSITION");
        };
        let mut positions: Vec<Vec3> = self
            .acc
            .read_vec::<3>(&pos_acc, "POSITION")?
            .into_iter()
            .map(Vec3::from)
            .collect();
        let nv = positions.len();
        let attr = |this: &Self, sem: Semantic, what: &str| -> Result<Option<(Vec<f64>, usize)>> {
            let Some(a) = prim.get(&sem) else {
                return Ok(None);
            };
            let (v, n) = this.acc.read(&a)?;
            if a.count() != nv {
                return Err(Error::decode(
                    this.path,
                    format!(
                        "primitive {name}: {what} has {} elements but POSITION has {nv}",
                        a.count()
                    ),
                ));
            }
            Ok(Some((v, n)))
        };
        let vec3s = |v: (Vec<f64>, usize)| -> Vec<Vec3> {
            v.0.chunks_exact(v.1.max(1))
                .map(|c| {
                    Vec3::new(
                        c[0] as f32,
                        c.get(1).copied().unwrap_or(0.0) as f32,
                        c.get(2).copied().unwrap_or(0.0) as f32,
                    )
                })
                .collect()
        };
        let vec2s = |v: (Vec<f64>, usize)| -> Vec<Vec2> {
            v.0.chunks_exact(v.1.max(1))
                .map(|c| Vec2::new(c[0] as f32, c.get(1).copied().unwrap_or(0.0) as f32))
                .collect()
        };
        let mut normals = attr(self, Semantic::Normals, "NORMAL")?
            .map(vec3s)
            .unwrap_or_default();
        let uvs = attr(self, Semantic::TexCoords(0), "TEXCOORD_0")?
            .map(vec2s)
            .unwrap_or_default();
        let uvs1 = attr(self, Semantic::TexCoords(1), "TEXCOORD_1")?
            .map(vec2s)
            .unwrap_or_default();
        // VEC3 or VEC4; a missing fourth component is 1 (colour alpha, tangent handedness).
        let vec4s = |(v, n): (Vec<f64>, usize)| -> Vec<Vec4> {
            v.chunks_exact(n.max(1))
                .map(|c| {
                    let at = |i: usize, d: f64| c.get(i).copied().unwrap_or(d) as f32;
                    Vec4::new(
                        at(0, 0.0),
                        at(1, 0.0),
                        at(2, 0.0),
                        if n == 4 { at(3, 1.0) } else { 1.0 },
                    )
                })
                .collect()
        };
        let colors: Vec<Vec4> = attr(self, Semantic::Colors(0), "COLOR_0")?
            .map(vec4s)
            .unwrap_or_default();
        let mut tangents: Vec<Vec4> = attr(self, Semantic::Tangents, "TANGENT")?
            .map(vec4s)
            .unwrap_or_default();

        // Morph targets at their default weights.
        for (t, target) in prim.morph_targets().enumerate() {
            let w = weights.get(t).copied().unwrap_or(0.0);
            if w == 0.0 {
                continue;
            }
            if let Some(a) = target.positions() {
                let d = self.acc.read_vec::<3>(&a, "morph POSITION")?;
                for (p, d) in positions.iter_mut().zip(d) {
                    *p += w * Vec3::from(d);
                }
            }
            if let Some(a) = target.normals() {
                let d = self.acc.read_vec::<3>(&a, "morph NORMAL")?;
                for (n, d) in normals.iter_mut().zip(d) {
                    *n += w * Vec3::from(d);
                }
            }
        }

        // Skins in the rest pose: the mesh node's own transform is ignored.
        let mut world_from_object = world;
        if let Some(skin) = node.skin() {
            self.skin(
                &skin,
                prim,
                &mut positions,
                &mut normals,
                &mut tangents,
                name,
            )?;
            world_from_object = Mat4::IDENTITY;
        }

        let list: Vec<u32> = match prim.indices() {
            Some(a) => {
                let (v, _) = self.acc.read(&a)?;
                let mut out = Vec::with_capacity(v.len());
                for x in v {
                    if x >= nv as f64 {
                        return Err(Error::decode(
                            self.path,
                            format!("primitive {name}: index {x} is out of range ({nv} vertices)"),
                        ));
                    }
                    out.push(x as u32);
                }
                out
            }
            None => (0..nv as u32).collect(),
        };
        let indices = to_triangle_list(mode, &list);
        for n in &mut normals {
            *n = n.normalize_or_zero();
        }
        // The last material is glTF's default one; a variant's mapping names a file material.
        let default = self.scene.materials.len() - 1;
        let material = self
            .variant
            .and_then(|v| super::variants::material_of(prim, v))
            .filter(|&m| m < default)
            .or(prim.material().index())
            .unwrap_or(default);
        let mut mesh = Mesh {
            positions,
            normals,
            uvs,
            uvs1,
            colors,
            tangents,
            indices,
            material,
            world_from_object,
        };
        if mesh.tangents.is_empty() {
            let mat = &self.scene.materials[material];
            let normal_map = mat
                .map(MapChannel::Normal)
                .or_else(|| mat.map(MapChannel::ClearcoatNormal));
            if let Some(map) = normal_map {
                let set = map.slot.tex_coord;
                if !tangents::generate(&mut mesh, set) {
                    self.warnings.push(format!(
                        "{}: primitive {name}: tangents could not be generated (no normals or uvs)",
                        self.path.display()
                    ));
                }
            }
        }
        Ok(Some(mesh))
    }
}

/// Converts a strip or fan index sequence to a triangle list (glTF's vertex orders).
fn to_triangle_list(mode: Mode, v: &[u32]) -> Vec<u32> {
    match mode {
        Mode::TriangleStrip => (0..v.len().saturating_sub(2))
            .flat_map(|i| {
                if i % 2 == 0 {
                    [v[i], v[i + 1], v[i + 2]]
                } else {
                    [v[i], v[i + 2], v[i + 1]]
                }
            })
            .collect(),
        Mode::TriangleFan => (1..v.len().saturating_sub(1))
            .flat_map(|i| [v[i], v[i + 1], v[0]])
            .collect(),
        _ => v[..v.len() / 3 * 3].to_vec(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strips_and_fans_become_lists() {
        assert_eq!(
            to_triangle_list(Mode::TriangleStrip, &[0, 1, 2, 3]),
            [0, 1, 2, 1, 3, 2]
        );
        assert_eq!(
            to_triangle_list(Mode::TriangleFan, &[0, 1, 2, 3]),
            [1, 2, 0, 2, 3, 0]
        );
        assert_eq!(to_triangle_list(Mode::Triangles, &[0, 1, 2, 3]), [0, 1, 2]);
    }
}
