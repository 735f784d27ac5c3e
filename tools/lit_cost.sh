#!/usr/bin/env bash
# The lit glTF frame's time as a multiple of the same frame unlit (issue 16's lit target),
# measured side by side: every round renders the scene lit and with --unlit (the order
# alternating from round to round), and the ratio is taken within the round.
#
#   bash tools/lit_cost.sh [ROUNDS] [FRAMES] [SCENE]
#   (defaults: 12 40 ../shared/assets/gltf/DamagedHelmet/glTF-Binary/DamagedHelmet.glb)
#
# 1920x1080, --threads 2 (THREADS=… to change), --discard; prints each case's median frame
# time and the median of the per-round ratios with their range (Markdown table), from each
# run's median frame and from its fastest frame (as tools/filter_cost.sh: on a host whose
# noise comes in bursts the fastest frame stands for the undisturbed one). Exits with a
# message when the scene is not there (the shared asset corpus is not part of the repository).
set -euo pipefail
ROUNDS=${1:-12}
FRAMES=${2:-40}
for n in "$ROUNDS" "$FRAMES"; do
    if ! [[ $n =~ ^[1-9][0-9]*$ ]]; then
        echo "lit_cost.sh: $n: ROUNDS and FRAMES must be positive whole numbers" >&2
        exit 1
    fi
done
# A scene named on the command line is found from where the script was called.
HELMET=$(dirname "$0")/../../shared/assets/gltf/DamagedHelmet/glTF-Binary/DamagedHelmet.glb
SCENE=$(realpath -m "${3:-$HELMET}")
cd "$(dirname "$0")/.."
if [ ! -f "$SCENE" ]; then
    echo "lit_cost.sh: $SCENE: no such scene (DamagedHelmet is in ../shared/assets)" >&2
    exit 1
fi
cargo build --release --quiet
exec python3 - "$ROUNDS" "$FRAMES" "$SCENE" <<'PY'
import json, os, statistics, subprocess, sys
THREADS = os.environ.get("THREADS", "2")
rounds, frames, scene = int(sys.argv[1]), sys.argv[2], sys.argv[3]
cases = {"lit": [], "unlit": ["--unlit"]}
def frame_ms(extra):
    out = subprocess.run(["target/release/texmap", "render", scene, *extra,
                          "--size", "1920x1080", "--threads", THREADS, "--frames", frames,
                          "--stats", "--discard"], check=True, capture_output=True, text=True)
    stats = json.loads(out.stdout)["frame_ms"]
    return stats["median"], stats["min"]
ms = {c: [] for c in cases}
fast = {c: [] for c in cases}
for r in range(rounds):
    order = list(cases) if r % 2 == 0 else list(cases)[::-1]
    for c in order:
        median, fastest = frame_ms(cases[c])
        ms[c].append(median)
        fast[c].append(fastest)
def ratio(runs):
    rs = [a / b for a, b in zip(runs["lit"], runs["unlit"])]
    return f"{statistics.median(rs):.3f} ({min(rs):.3f}–{max(rs):.3f})"
print(f"| case | frame ms (median of {rounds}) | lit / unlit, median (range) "
      f"| fastest frame ms | lit / unlit, fastest frames |")
print("|---|---|---|---|---|")
print(f"| unlit | {statistics.median(ms['unlit']):.2f} | "
      f"| {statistics.median(fast['unlit']):.2f} | |")
print(f"| lit | {statistics.median(ms['lit']):.2f} | {ratio(ms)} "
      f"| {statistics.median(fast['lit']):.2f} | {ratio(fast)} |")
PY
