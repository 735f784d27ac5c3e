#!/usr/bin/env python3
"""Inputs for tools/sdf_reference.sh, written to OUT (run with ../shared/peers/.venv/bin/python).

  torus.obj      a generated torus (R = 1, r = 0.35, 96 x 48 quads split in two), closed
  open_torus.obj the same torus with a ring of quads removed (a hole) and every 13th
                 triangle reversed: the winding-number sign's robustness, against libigl's
  duck.obj       ../shared/assets/gltf/Duck's triangles in world space (node transforms
                 applied), because libigl reads OBJ, not glTF: read here with pygltflib,
                 independently of texmap's loader
  mni_aniso.nii.gz the MNI152 template's voxels with anisotropic spacing (0.7, 1.0, 1.6) mm

  sdf_inputs.py OUT ASSETS
"""
import os, struct, sys
import numpy as np


def write_obj(path, V, F):
    with open(path, "w") as f:
        f.writelines(f"v {x:.9g} {y:.9g} {z:.9g}\n" for x, y, z in V)
        f.writelines(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in F)


def torus(n=96, m=48, R=1.0, r=0.35):
    u = np.arange(n) * 2 * np.pi / n
    v = np.arange(m) * 2 * np.pi / m
    U, W = np.meshgrid(u, v, indexing="ij")
    V = np.stack([(R + r * np.cos(W)) * np.cos(U), r * np.sin(W), (R + r * np.cos(W)) * np.sin(U)], -1).reshape(-1, 3)
    F = []
    for i in range(n):
        for j in range(m):
            a, b = i * m + j, ((i + 1) % n) * m + j
            c, d = ((i + 1) % n) * m + (j + 1) % m, i * m + (j + 1) % m
            F += [(a, d, c), (a, c, b)]
    F = np.array(F)
    # Outward orientation: flip if the signed volume is negative.
    vol = np.einsum("ij,ij->i", V[F[:, 0]], np.cross(V[F[:, 1]], V[F[:, 2]])).sum()
    if vol < 0:
        F = F[:, [0, 2, 1]]
    return V, F


def gltf_world_triangles(path):
    import pygltflib
    g = pygltflib.GLTF2().load(path)
    blob = g.binary_blob()

    def accessor(i):
        a = g.accessors[i]
        bv = g.bufferViews[a.bufferView]
        comps = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}[a.type]
        dt = {5121: np.uint8, 5123: np.uint16, 5125: np.uint32, 5126: np.float32}[a.componentType]
        size = np.dtype(dt).itemsize * comps
        stride = bv.byteStride or size
        start = (bv.byteOffset or 0) + (a.byteOffset or 0)
        rows = [np.frombuffer(blob, dt, comps, start + k * stride) for k in range(a.count)]
        return np.array(rows)

    def local(node):
        if node.matrix:
            return np.array(node.matrix, float).reshape(4, 4).T
        T = np.eye(4)
        if node.translation:
            T[:3, 3] = node.translation
        Rm = np.eye(4)
        if node.rotation:
            x, y, z, w = node.rotation
            Rm[:3, :3] = [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                          [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                          [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]
        S = np.diag(list(node.scale or [1, 1, 1]) + [1])
        return T @ Rm @ S

    Vs, Fs, base = [], [], 0

    def visit(i, parent):
        nonlocal base
        node = g.nodes[i]
        M = parent @ local(node)
        if node.mesh is not None:
            for prim in g.meshes[node.mesh].primitives:
                if prim.mode not in (None, 4):
                    continue
                P = accessor(prim.attributes.POSITION).astype(float)
                idx = accessor(prim.indices).reshape(-1) if prim.indices is not None else np.arange(len(P))
                W = (M @ np.c_[P, np.ones(len(P))].T).T[:, :3]
                Vs.append(W)
                Fs.append(idx.reshape(-1, 3) + base)
                base += len(P)
        for c in node.children or []:
            visit(c, M)

    scene = g.scenes[g.scene or 0]
    for n in scene.nodes:
        visit(n, np.eye(4))
    return np.vstack(Vs), np.vstack(Fs)


def main():
    out, assets = sys.argv[1], sys.argv[2]
    V, F = torus()
    write_obj(os.path.join(out, "torus.obj"), V, F)
    # A hole: drop the quads of one ring (i = 0), then reverse every 13th triangle.
    keep = np.ones(len(F), bool)
    keep[: 2 * 48] = False
    G = F[keep].copy()
    G[::13] = G[::13][:, [0, 2, 1]]
    write_obj(os.path.join(out, "open_torus.obj"), V, G)
    duck = os.path.join(assets, "gltf/Duck/glTF-Binary/Duck.glb")
    if os.path.exists(duck):
        V, F = gltf_world_triangles(duck)
        write_obj(os.path.join(out, "duck.obj"), V, F)
    mni = os.path.join(assets, "volumes/mni152_t1/mni_icbm152_t1_tal_nlin_sym_09a_converted.nii.gz")
    if os.path.exists(mni):
        import nibabel as nib
        img = nib.load(mni)
        aff = np.diag([0.7, 1.0, 1.6, 1.0])
        aff[:3, 3] = img.affine[:3, 3]
        nib.save(nib.Nifti1Image(np.asarray(img.dataobj), aff), os.path.join(out, "mni_aniso.nii.gz"))


if __name__ == "__main__":
    main()
