#!/usr/bin/env bash
# Every level of every face and slice of every DDS under a folder, decoded by `texmap convert`
# and by the independent reference ../shared/peers/bc_decode.py, compared pixel byte for pixel
# byte (the decoded RGBA values, not the PNG files' bytes).
#   tools/bc_reference.sh                      # ../shared/assets/compressed
#   tools/bc_reference.sh DIR_OR_FILE.dds ...  # other DDS files or folders
# Prints one line per file (images compared, how many differ, the first differing pixel) and a
# total: "F files, N images compared, D differ". Exits 1 when any image differs or a convert
# fails. TEXMAP=path/to/texmap uses that binary; else the release build is made.
# The reference decodes BC1-BC5 and BC7 (not BC6H) and the 32-bit uncompressed formats; a file
# it refuses is reported and skipped.
set -uo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
peers=${PEERS:-$root/../shared/peers}
py="$peers/.venv/bin/python"
[ -x "$py" ] || { echo "bc_reference: $py is missing (run ../shared/peers/setup.sh)"; exit 1; }
if [ -z "${TEXMAP:-}" ]; then
  (cd "$root" && cargo build --release -q -p texmap-cli) || exit 1
  TEXMAP="$root/target/release/texmap"
fi
[ $# -gt 0 ] || set -- "$root/../shared/assets/compressed"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

files=0 images=0 differ=0 skipped=0 failed=0
while IFS= read -r -d '' f; do
  work="$tmp/$((files + skipped))"
  mkdir -p "$work/peer" "$work/texmap"
  if ! "$py" "$peers/bc_decode.py" "$f" -o "$work/peer" >"$work/peer.log" 2>&1; then
    echo "$f: skipped, the reference does not decode it: $(tail -1 "$work/peer.log")"
    skipped=$((skipped + 1))
    continue
  fi
  files=$((files + 1))
  stem=$(basename "${f%.*}")
  faces=$("$py" -c 'import json,sys; print(6 if json.load(open(sys.argv[1]))["cube"] else 1)' \
    "$work/peer/$stem.json")
  # The reference's names: <stem>_s<layer·faces + face>_m<level>[_z<slice>].png
  for png in "$work/peer/$stem"_s*_m*.png; do
    name=$(basename "$png" .png)
    rest=${name#"${stem}"_s}
    s=${rest%%_*}
    rest=${rest#*_m}
    m=${rest%%_*}
    z=
    [[ $rest == *_z* ]] && z=${rest#*_z}
    layer=$((s / faces)) face=$((s % faces))
    slice=${z:-$layer}
    if ! "$TEXMAP" convert "$f" "$work/texmap/$name.png" --level "$m" --face "$face" \
        --slice "$slice" 2>"$work/texmap.log"; then
      echo "$f: texmap convert --level $m --face $face --slice $slice failed: $(tail -1 "$work/texmap.log")"
      failed=$((failed + 1))
    fi
  done
  # Decoded pixels compared, image by image.
  line=$("$py" - "$work/peer" "$work/texmap" <<'PY'
import os, sys
import numpy as np
from PIL import Image
peer, ours = sys.argv[1], sys.argv[2]
n = bad = 0
first = ""
for name in sorted(os.listdir(peer)):
    if not name.endswith(".png"):
        continue
    n += 1
    p = os.path.join(ours, name)
    if not os.path.exists(p):
        bad += 1
        first = first or f"{name}: not converted"
        continue
    a = np.asarray(Image.open(os.path.join(peer, name)).convert("RGBA"))
    b = np.asarray(Image.open(p).convert("RGBA"))
    if a.shape != b.shape:
        bad += 1
        first = first or f"{name}: {b.shape[1]}x{b.shape[0]}, reference {a.shape[1]}x{a.shape[0]}"
    elif (a != b).any():
        bad += 1
        y, x = map(int, np.argwhere((a != b).any(axis=2))[0])
        first = first or f"{name}: first at ({x}, {y}) {tuple(b[y, x])} vs {tuple(a[y, x])}"
print(n, bad, first)
PY
)
  read -r n bad first <<<"$line"
  images=$((images + n))
  differ=$((differ + bad))
  echo "$f: $n images, $bad differ${first:+ ($first)}"
done < <(find "$@" -type f -iname '*.dds' -print0 | sort -z)

echo "$files files, $images images compared, $differ differ ($skipped skipped, $failed converts failed)"
[ "$differ" -eq 0 ] && [ "$failed" -eq 0 ]
