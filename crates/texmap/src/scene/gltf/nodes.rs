//! The node hierarchy: world matrices, and a depth-first walk in document order of the
//! default scene (else scene 0, else every root node) that places each node's mesh
//! primitives, camera and light. The walk is bounded — 256 levels deep and 2^20 node visits —
//! so a cycle or a small file describing a huge DAG is an error, not a hang.

use glam::Mat4;

use super::cameras::camera;
use super::document::Loader;
use super::lights::light;
use crate::{Error, Result};

/// The largest node depth followed (a guard against cycles in a malformed file).
const MAX_NODE_DEPTH: usize = 256;
/// The most node visits (a DAG can make a small file describe a huge scene).
const MAX_NODE_VISITS: usize = 1 << 20;

fn mat4(m: [[f32; 4]; 4]) -> Mat4 {
    Mat4::from_cols_array_2d(&m)
}

impl Loader<'_> {
    /// World matrices of every node (parents found over the whole document).
    pub(super) fn node_world_matrices(&self) -> Result<Vec<Mat4>> {
        let n = self.doc.nodes().len();
        let mut parent = vec![usize::MAX; n];
        for node in self.doc.nodes() {
            for c in node.children() {
                parent[c.index()] = node.index();
            }
        }
        let local: Vec<Mat4> = self
            .doc
            .nodes()
            .map(|n| mat4(n.transform().matrix()))
            .collect();
        let mut world = vec![Mat4::IDENTITY; n];
        for i in 0..n {
            let mut m = local[i];
            let mut p = parent[i];
            let mut depth = 0;
            while p != usize::MAX {
                m = local[p] * m;
                p = parent[p];
                depth += 1;
                if depth > MAX_NODE_DEPTH {
                    return Err(Error::decode(
                        self.path,
                        "the node hierarchy is deeper than 256 levels or has a cycle",
                    ));
                }
            }
            world[i] = m;
        }
        Ok(world)
    }

    /// Every node of the default scene (else scene 0, else every root node), depth-first in
    /// document order.
    pub(super) fn load_nodes(&mut self) -> Result<()> {
        let doc = self.doc;
        let roots: Vec<gltf::Node> = match doc.default_scene().or_else(|| doc.scenes().next()) {
            Some(s) => s.nodes().collect(),
            None => {
                let mut is_child = vec![false; doc.nodes().len()];
                for node in doc.nodes() {
                    for c in node.children() {
                        is_child[c.index()] = true;
                    }
                }
                doc.nodes().filter(|n| !is_child[n.index()]).collect()
            }
        };
        for node in roots {
            self.visit(&node, Mat4::IDENTITY, 0)?;
        }
        Ok(())
    }

    fn visit(&mut self, node: &gltf::Node, parent: Mat4, depth: usize) -> Result<()> {
        self.visits += 1;
        if depth > MAX_NODE_DEPTH || self.visits > MAX_NODE_VISITS {
            return Err(Error::decode(
                self.path,
                "the node hierarchy is too deep or too large (a cycle?)",
            ));
        }
        let world = parent * mat4(node.transform().matrix());
        if let Some(mesh) = node.mesh() {
            let weights = node
                .weights()
                .or_else(|| mesh.weights())
                .unwrap_or(&[])
                .to_vec();
            for prim in mesh.primitives() {
                let name = format!(
                    "{}/{}",
                    mesh.name()
                        .map(str::to_string)
                        .unwrap_or_else(|| format!("mesh {}", mesh.index())),
                    prim.index()
                );
                if let Some(m) = self.primitive(node, &prim, world, &weights, &name)? {
                    self.scene.meshes.push(m);
                    self.info.mesh_names.push(name);
                }
            }
        }
        if let Some(cam) = node.camera() {
            self.cameras.push(camera(&cam, world));
        }
        if let Some(l) = node.light() {
            let checked = light(&l, world).checked().map_err(|m| {
                Error::decode(
                    self.path,
                    format!("light {} (node {}): {m}", l.index(), node.index()),
                )
            })?;
            self.scene.lights.push(checked);
        }
        for child in node.children() {
            self.visit(&child, world, depth + 1)?;
        }
        Ok(())
    }
}
