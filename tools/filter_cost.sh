#!/usr/bin/env bash
# Each texture filter's 1080p frame time as a multiple of our trilinear's, measured side by
# side: every round renders the plane with trilinear and with each filter named (the order
# rotating from round to round), and the ratio to trilinear is taken within the round.
#
#   bash tools/filter_cost.sh [ROUNDS] [FRAMES] [FILTER...]   (defaults: 8 20 aniso6 aniso5-area ewa)
#
# builtin:plane at 1920x1080, --threads 2, --discard; prints each filter's median frame time
# and the median of its per-round ratios to trilinear with their range (Markdown table).
set -euo pipefail
cd "$(dirname "$0")/.."
ROUNDS=${1:-8}
FRAMES=${2:-20}
shift $(( $# > 2 ? 2 : $# ))
FILTERS=("$@")
[ ${#FILTERS[@]} -gt 0 ] || FILTERS=(aniso6 aniso5-area ewa)
cargo build --release --quiet
exec python3 - "$ROUNDS" "$FRAMES" "${FILTERS[@]}" <<'PY'
import json, os, statistics, subprocess, sys
THREADS = os.environ.get("THREADS", "2")
rounds, frames, filters = int(sys.argv[1]), sys.argv[2], sys.argv[3:]
cases = ["trilinear"] + filters
def frame_ms(f):
    out = subprocess.run(["target/release/texmap", "render", "builtin:plane", "--filter", f,
                          "--size", "1920x1080", "--threads", THREADS, "--frames", frames,
                          "--stats", "--discard"], check=True, capture_output=True, text=True)
    return json.loads(out.stdout)["frame_ms"]["median"]
ms = {c: [] for c in cases}
for r in range(rounds):
    k = r % len(cases)
    order = cases[k:] + cases[:k]
    if r % 2:
        order.reverse()
    for c in order:
        ms[c].append(frame_ms(c))
print(f"| filter | frame ms (median of {rounds}) | / trilinear, median (range) |")
print("|---|---|---|")
print(f"| trilinear | {statistics.median(ms['trilinear']):.2f} | 1 |")
for f in filters:
    rs = [a / b for a, b in zip(ms[f], ms["trilinear"])]
    print(f"| {f} | {statistics.median(ms[f]):.2f} | "
          f"{statistics.median(rs):.2f} ({min(rs):.2f}–{max(rs):.2f}) |")
PY
