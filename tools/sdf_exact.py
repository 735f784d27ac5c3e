#!/usr/bin/env python3
"""A mesh field against exact values, within a band of the surface (for tools/sdf_reference.sh;
run with ../shared/peers/.venv/bin/python).

libigl's signed_distance with the fast winding number returns (1 - 2|w|) x distance, a
continuous "sign" that shrinks values where w is not 0 or 1 (near holes, on open meshes), so
`sdf_ref.py compare` reports magnitude differences there that are not errors of either side.
This check separates the two: |field| against libigl's exact unsigned distance
(point_mesh_squared_distance), and the field's sign against the exact generalized winding
number (igl.winding_number >= 1/2), over voxels with |field| <= BAND voxels.

  sdf_exact.py MESH.obj FIELD.nii.gz [BAND]     -> one JSON line
"""
import json, sys
import igl, nibabel as nib, numpy as np

mesh, field = sys.argv[1], sys.argv[2]
band = float(sys.argv[3]) if len(sys.argv) > 3 else 4.0
V, F = igl.read_triangle_mesh(mesh)
img = nib.load(field)
a = np.asarray(img.dataobj, np.float64)
h = float(np.abs(np.asarray(img.header.get_zooms()[:3])).min())
idx = np.argwhere(np.abs(a) <= band * h)
P = (img.affine @ np.c_[idx, np.ones(len(idx))].T).T[:, :3]
d2, _, _ = igl.point_mesh_squared_distance(P, V, F)
vals = a[tuple(idx.T)]
err = np.abs(np.sqrt(d2) - np.abs(vals)) / h
w = igl.winding_number(V, F, P)
print(json.dumps({"voxels": int(len(idx)), "unsigned_max_voxels": float(err.max()),
                  "unsigned_mean_voxels": float(err.mean()),
                  "sign_vs_winding_mismatch_fraction": float(((w >= 0.5) != (vals < 0)).mean())}))
