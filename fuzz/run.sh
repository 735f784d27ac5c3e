#!/usr/bin/env bash
# Runs fuzz targets one after another, SECONDS each (default 600), over corpus/<target>
# (fill it first with ./seeds.sh), and prints each target's executions and findings.
#   ./run.sh                 # every target, 10 minutes each
#   ./run.sh 60 gltf obj     # one minute each for two targets
# Findings land in artifacts/<target>/ (crash-*, timeout-*, oom-*); the log of each run in
# logs/<target>.log.
set -uo pipefail
cd "$(dirname "$0")"
secs=${1:-600}; shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(gltf glb obj toml image nifti nrrd raw dds ktx ktx2)
mkdir -p logs
for t in "${targets[@]}"; do
  mkdir -p "corpus/$t" "artifacts/$t"
  # -s none: the code under test is safe Rust, so a panic (not a sanitizer) is the fault;
  # 10 s a run is a hang, 2 GiB of memory an unbounded allocation.
  cargo +nightly fuzz run -s none "$t" "corpus/$t" -- \
    -max_total_time="$secs" -timeout=10 -rss_limit_mb=2048 -max_len=65536 \
    -artifact_prefix="artifacts/$t/" -print_final_stats=1 >"logs/$t.log" 2>&1
  rc=$?
  execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "logs/$t.log" | grep -o '[0-9]*$')
  found=$(ls "artifacts/$t" | wc -l)
  # libFuzzer's own count of the seconds it fuzzed ("Done N runs in S second(s)"); none
  # when it stopped at a finding.
  took=$(grep -o 'runs in [0-9]* second' "logs/$t.log" | grep -o '[0-9]*' | tail -1)
  printf '%-6s exit %d, fuzzed %s s, %s executions, %d findings\n' \
    "$t" "$rc" "${took:-?}" "${execs:-?}" "$found"
done
