#!/usr/bin/env bash
# Signed distance fields against the references of ../shared/peers/sdf_ref.py, in one run:
# every mesh through `texmap sdf` and libigl's signed_distance (fast winding number) on the
# same grid, every scan through `texmap sdf --threshold` and SciPy's exact EDT; the fields
# compared voxel for voxel with `sdf_ref.py compare` (meshes within 4 voxels of the
# surface, scans everywhere), and the build times taken alternately, ROUNDS rounds, median.
# Meshes also against exact values (tools/sdf_exact.py): exact_max = the largest
# ||field| − exact unsigned distance| in voxels, wn_mis = the fraction of voxels whose sign
# differs from the exact winding number's (w ≥ ½ inside), both in the same band; libigl's
# field is (1 − 2|w|) × distance, which departs from a distance where w is not 0 or 1.
#
#   bash tools/sdf_reference.sh [ROUNDS] [RES]        (default 3 rounds, 128 voxels)
#
# Times: texmap's `sdf_ms` (tree + grid, after loading) against sdf_ref.py's `sdf_ms` (the
# signed_distance call alone, after loading and building the query points); scans: `edt_ms`
# against its `edt_ms`. Both use every core (2 here).
# Meshes: spot; Duck (its world-space triangles written as OBJ by tools/sdf_inputs.py for
# libigl, read by texmap from the .glb itself); spider; a generated torus, and the same torus
# with a ring of faces removed and every 13th triangle reversed. Scans: the MNI152 template
# (1 mm) and the same voxels with anisotropic spacing (0.7, 1.0, 1.6) mm.
set -euo pipefail
cd "$(dirname "$0")/.."
ROUNDS=${1:-3}
RES=${2:-128}
P=${PEERS:-../shared/peers}
PY=$P/.venv/bin/python
A=../shared/assets
if [ ! -x "$PY" ] || [ ! -d "$A" ]; then
  echo "SKIPPED: needs $PY (bash $P/setup.sh) and $A"
  exit 0
fi
cargo build --release --quiet
TEXMAP=target/release/texmap
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
"$PY" tools/sdf_inputs.py "$OUT" "$A"
get() { "$PY" -c 'import json,sys; d=json.loads(sys.stdin.read().strip().splitlines()[-1]); print(d[sys.argv[1]])' "$1"; }
median() { printf '%s\n' "$@" | sort -g | awk '{a[NR]=$1} END {print (NR%2) ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2}'; }

printf '%-12s %7s %-13s %9s %9s %9s %9s %9s %10s %10s %6s\n' mesh tris grid max_vox mean_vox sign_mis exact_max wn_mis texmap_ms libigl_ms ratio
meshes=(
  "spot|$A/obj/spot/spot_triangulated.obj|$A/obj/spot/spot_triangulated.obj"
  "Duck|$A/gltf/Duck/glTF-Binary/Duck.glb|$OUT/duck.obj"
  "spider|$A/obj/spider/spider.obj|$A/obj/spider/spider.obj"
  "torus|$OUT/torus.obj|$OUT/torus.obj"
  "open_torus|$OUT/open_torus.obj|$OUT/open_torus.obj"
)
for row in "${meshes[@]}"; do
  IFS='|' read -r name ours theirs <<<"$row"
  t_ours=(); t_ref=()
  for _ in $(seq "$ROUNDS"); do
    j=$("$TEXMAP" sdf "$ours" --res "$RES" --json -o "$OUT/ours.nii.gz")
    t_ours+=("$(get sdf_ms <<<"$j")")
    r=$("$PY" $P/sdf_ref.py mesh "$theirs" --res "$RES" -o "$OUT/ref.nii.gz")
    t_ref+=("$(get sdf_ms <<<"$r")")
  done
  h=$(get spacing <<<"$r")
  band=$("$PY" -c "print(4 * $h)")
  c=$("$PY" $P/sdf_ref.py compare "$OUT/ours.nii.gz" "$OUT/ref.nii.gz" --band "$band")
  x=$("$PY" tools/sdf_exact.py "$theirs" "$OUT/ours.nii.gz" 4)
  mo=$(median "${t_ours[@]}"); mr=$(median "${t_ref[@]}")
  grid=$(get grid <<<"$j" | tr -d ' []' | tr ',' 'x')
  printf '%-12s %7s %-13s %9.4f %9.5f %9.5f %9.1e %9.5f %10.1f %10.1f %6.2f\n' "$name" "$(get triangles <<<"$j")" "$grid" \
    "$(get max_voxels <<<"$c")" "$(get mean_voxels <<<"$c")" "$(get sign_mismatch_fraction <<<"$c")" \
    "$(get unsigned_max_voxels <<<"$x")" "$(get sign_vs_winding_mismatch_fraction <<<"$x")" \
    "$mo" "$mr" "$("$PY" -c "print($mo / $mr)")"
done

echo
printf '%-12s %-13s %-16s %9s %9s %9s %10s %10s %6s\n' scan grid spacing max_vox mean_vox sign_mis texmap_ms scipy_ms ratio
scans=(
  "mni152|$A/volumes/mni152_t1/mni_icbm152_t1_tal_nlin_sym_09a_converted.nii.gz|40"
  "mni152_aniso|$OUT/mni_aniso.nii.gz|40"
)
for row in "${scans[@]}"; do
  IFS='|' read -r name scan thr <<<"$row"
  t_ours=(); t_ref=()
  for _ in $(seq "$ROUNDS"); do
    j=$("$TEXMAP" sdf "$scan" --threshold "$thr" --json -o "$OUT/ours.nii.gz")
    t_ours+=("$(get edt_ms <<<"$j")")
    r=$("$PY" $P/sdf_ref.py mask "$scan" --threshold "$thr" -o "$OUT/ref.nii.gz")
    t_ref+=("$(get edt_ms <<<"$r")")
  done
  c=$("$PY" $P/sdf_ref.py compare "$OUT/ours.nii.gz" "$OUT/ref.nii.gz")
  mo=$(median "${t_ours[@]}"); mr=$(median "${t_ref[@]}")
  grid=$(get grid <<<"$j" | tr -d ' []' | tr ',' 'x')
  sp=$(get spacing <<<"$r" | tr -d ' []')
  printf '%-12s %-13s %-16s %9.4f %9.5f %9.5f %10.1f %10.1f %6.2f\n' "$name" "$grid" "$sp" \
    "$(get max_voxels <<<"$c")" "$(get mean_voxels <<<"$c")" "$(get sign_mismatch_fraction <<<"$c")" \
    "$mo" "$mr" "$("$PY" -c "print($mo / $mr)")"
done
