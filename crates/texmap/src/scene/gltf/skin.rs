//! Skins in the rest pose: a skinned primitive's vertices are moved by their joints' node
//! transforms at load (glTF's skinning equation with the file's node matrices, no
//! animation), and the mesh node's own transform is then ignored, as the specification
//! says. Normals move by the inverse transpose, tangents by the matrix itself.

use glam::{Mat3, Mat4, Vec3, Vec4};
use gltf::Semantic;

use super::document::Loader;
use crate::{Error, Result};

impl Loader<'_> {
    /// Poses `prim`'s vertices (positions, normals, tangents) by `skin` in the rest pose:
    /// each vertex by its weighted joint matrices (joint world × inverse bind matrix), over
    /// JOINTS_0/WEIGHTS_0 and JOINTS_1/WEIGHTS_1.
    pub(super) fn skin(
        &mut self,
        skin: &gltf::Skin,
        prim: &gltf::Primitive,
        positions: &mut [Vec3],
        normals: &mut [Vec3],
        tangents: &mut [Vec4],
        name: &str,
    ) -> Result<()> {
        let joints: Vec<usize> = skin.joints().map(|j| j.index()).collect();
        let ibm: Vec<Mat4> = match skin.inverse_bind_matrices() {
            Some(a) => {
                let (v, n) = self.acc.read(&a)?;
                if n != 16 || v.len() / 16 < joints.len() {
                    return Err(Error::decode(
                        self.path,
                        format!(
                            "skin {}: inverseBindMatrices has too few matrices",
                            skin.index()
                        ),
                    ));
                }
                v.chunks_exact(16)
                    .map(|c| Mat4::from_cols_array(&std::array::from_fn(|i| c[i] as f32)))
                    .collect()
            }
            None => vec![Mat4::IDENTITY; joints.len()],
        };
        let joint_mats: Vec<Mat4> = joints
            .iter()
            .zip(&ibm)
            .map(|(&j, &ib)| self.node_world[j] * ib)
            .collect();
        let nv = positions.len();
        let mut blended = vec![Mat4::ZERO; nv];
        let mut any = false;
        for set in 0..2 {
            let (Some(ja), Some(wa)) = (
                prim.get(&Semantic::Joints(set)),
                prim.get(&Semantic::Weights(set)),
            ) else {
                continue;
            };
            let (jv, jn) = self.acc.read(&ja)?;
            let (wv, wn) = self.acc.read(&wa)?;
            if ja.count() != nv || wa.count() != nv || jn != 4 || wn != 4 {
                return Err(Error::decode(
                    self.path,
                    format!("primitive {name}: JOINTS_{set}/WEIGHTS_{set} do not match POSITION"),
                ));
            }
            for v in 0..nv {
                for k in 0..4 {
                    let w = wv[v * 4 + k] as f32;
                    if w == 0.0 {
                        continue;
                    }
                    let j = jv[v * 4 + k] as usize;
                    let m = joint_mats.get(j).ok_or_else(|| {
                        Error::decode(
                            self.path,
                            format!("primitive {name}: joint {j} is out of range"),
                        )
                    })?;
                    blended[v] += *m * w;
                    any = true;
                }
            }
        }
        if !any {
            return Ok(());
        }
        for v in 0..nv {
            let m = blended[v];
            positions[v] = m.transform_point3(positions[v]);
            let m3 = Mat3::from_mat4(m);
            if let Some(n) = normals.get_mut(v) {
                let nm = if m3.determinant().abs() > f32::MIN_POSITIVE {
                    m3.inverse().transpose()
                } else {
                    m3
                };
                *n = nm * *n;
            }
            if let Some(t) = tangents.get_mut(v) {
                *t = (m3 * t.truncate()).normalize_or_zero().extend(t.w);
            }
        }
        Ok(())
    }
}
