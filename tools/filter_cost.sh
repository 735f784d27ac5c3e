#!/usr/bin/env bash
# Each texture filter's 1080p frame time as a multiple of our trilinear's, measured side by
# side: every round renders the plane with trilinear and with each filter named (the order
# rotating from round to round), and the ratio to trilinear is taken within the round.
#
#   bash tools/filter_cost.sh [ROUNDS] [FRAMES] [FILTER...]   (defaults: 8 20 aniso6 aniso5-area ewa)
#
# builtin:plane at 1920x1080, --threads 2, --discard; prints each filter's median frame time
# and the median of its per-round ratios to trilinear with their range (Markdown table), from
# each run's median frame and from each run's fastest frame (on a shared host whose noise
# comes in bursts, a long frame is hit more often than a short one, and the fastest frame
# stands for the undisturbed one).
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
    stats = json.loads(out.stdout)["frame_ms"]
    return stats["median"], stats["min"]
ms = {c: [] for c in cases}
fast = {c: [] for c in cases}
for r in range(rounds):
    k = r % len(cases)
    order = cases[k:] + cases[:k]
    if r % 2:
        order.reverse()
    for c in order:
        median, fastest = frame_ms(c)
        ms[c].append(median)
        fast[c].append(fastest)
def ratio(runs, f):
    rs = [a / b for a, b in zip(runs[f], runs["trilinear"])]
    return f"{statistics.median(rs):.2f} ({min(rs):.2f}–{max(rs):.2f})"
print(f"| filter | frame ms (median of {rounds}) | / trilinear, median (range) "
      f"| fastest frame ms | / trilinear, fastest frames |")
print("|---|---|---|---|---|")
print(f"| trilinear | {statistics.median(ms['trilinear']):.2f} | 1 "
      f"| {statistics.median(fast['trilinear']):.2f} | 1 |")
for f in filters:
    print(f"| {f} | {statistics.median(ms[f]):.2f} | {ratio(ms, f)} "
          f"| {statistics.median(fast[f]):.2f} | {ratio(fast, f)} |")
PY
