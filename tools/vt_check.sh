#!/usr/bin/env bash
# vt_check.sh — the virtual-texture figures: scenes/virtual_texture.toml (65,536²) at
# 1280x720 under /usr/bin/time -v with --stats, and the same scene at 4,096² rendered
# through pages and held whole (resident = true), compared by texmap compare.
# Usage: bash tools/vt_check.sh [FILTER]   (default trilinear; e.g. aniso8)
set -euo pipefail
cd "$(dirname "$0")/.."
filter=${1:-trilinear}
bin=target/release/texmap
cargo build --release -q -p texmap-cli
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

echo "== scenes/virtual_texture.toml, 1280x720, --filter $filter"
/usr/bin/time -v "$bin" render scenes/virtual_texture.toml --size 1280x720 --filter "$filter" \
    -o "$tmp/vt65536.png" --stats 2>"$tmp/time.txt"
grep -E 'Maximum resident|Elapsed' "$tmp/time.txt"

# The same scene at 4,096² (the floor shrunk with it, so a texel stays 1 mm).
sed -e 's/^size = 65536 .*/size = 4096/' -e 's/^size = 65.536 .*/size = 4.096/' \
    scenes/virtual_texture.toml >"$tmp/paged.toml"
sed -e 's/^budget_mib = .*/resident = true/' "$tmp/paged.toml" >"$tmp/whole.toml"
for s in paged whole; do
    "$bin" render "$tmp/$s.toml" --size 1280x720 --filter "$filter" -o "$tmp/$s.png" --stats \
        | sed "s/^/$s: /"
done
echo "== 4096² through pages against held whole"
"$bin" compare "$tmp/paged.png" "$tmp/whole.png"
