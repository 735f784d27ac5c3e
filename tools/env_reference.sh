#!/usr/bin/env bash
# Environment mapping and image-based light against ground truth, in one run: renders the
# fixed scenes of ../shared/peers/mitsuba_ref.py (env, mirror, metal, diffuse, plastic, glass)
# with Mitsuba 3 (a path tracer) and with texmap (scenes/reference/*.toml), for each
# panorama, and prints the PSNR of every pair (8-bit sRGB, whole image).
#
#   bash tools/env_reference.sh [SPP] [OUT_DIR]        (SPP: Mitsuba's samples, default 1024)
#
# Panoramas: the corpus's venice_sunset_1k.hdr and blender_studiolight_forest.exr (when
# ../shared/assets is present) and a synthetic one the script writes (sky gradient, a sun,
# coloured bands and a checker ground; no files needed). Mitsuba's images are kept in OUT_DIR
# (default target/env-reference) and reused when present, so a second run costs only
# texmap's side. texmap renders at 256x256 with --ssaa 4; TEXMAP overrides the binary
# (default target/release/texmap). Targets (issue 12): env ≥ 40 dB, mirror ≥ 35, metal ≥ 30,
# diffuse ≥ 32; plastic and glass are reported only.
set -euo pipefail
cd "$(dirname "$0")/.."
SPP=${1:-1024}
OUT=${2:-target/env-reference}
P=${PEERS:-../shared/peers}
PY=$P/.venv/bin/python
TEXMAP=${TEXMAP:-target/release/texmap}
A=../shared/assets/env/equirect
mkdir -p "$OUT"
[ -x "$TEXMAP" ] || { echo "no $TEXMAP: cargo build --release first" >&2; exit 1; }
[ -x "$PY" ] || { echo "no $PY: run bash $P/setup.sh first" >&2; exit 1; }

# The synthetic panorama (tools/synthetic_env.py: linear radiance, 1024x512, EXR), written once.
SYN="$OUT/synthetic.exr"
[ -f "$SYN" ] || "$PY" tools/synthetic_env.py 1024 "$SYN"

panoramas=("synthetic|$SYN")
[ -f "$A/venice_sunset_1k.hdr" ] && panoramas=("venice|$A/venice_sunset_1k.hdr" "${panoramas[@]}")
[ -f "$A/blender_studiolight_forest.exr" ] && panoramas+=("forest|$A/blender_studiolight_forest.exr")

target() {
    case $1 in env) echo 40 ;; mirror) echo 35 ;; metal) echo 30 ;; diffuse) echo 32 ;; *) echo - ;; esac
}
mitsuba_args() {
    case $1 in
        metal) echo "--roughness 0.3 --base 1,1,1" ;;
        diffuse) echo "--base 0.8,0.2,0.2" ;;
        plastic) echo "--roughness 0.5 --base 0.8,0.2,0.2" ;;
        *) echo "" ;;
    esac
}

printf '%-10s %-8s %10s %8s  %s\n' panorama scene "PSNR dB" target command
fail=0
for p in "${panoramas[@]}"; do
    name=${p%%|*}
    file=${p#*|}
    for s in env mirror metal diffuse plastic glass; do
        ref="$OUT/$name-$s-mitsuba-$SPP.png"
        if [ ! -f "$ref" ]; then
            # shellcheck disable=SC2046
            "$PY" $P/mitsuba_ref.py "$s" --env "$file" --size 256x256 --spp "$SPP" \
                $(mitsuba_args "$s") -o "$ref" > /dev/null
        fi
        img="$OUT/$name-$s-texmap.png"
        cmd="texmap render scenes/reference/$s.toml --env $file --size 256x256 --ssaa 4"
        "$TEXMAP" render "scenes/reference/$s.toml" --env "$file" --size 256x256 --ssaa 4 \
            --quiet -o "$img"
        psnr=$("$TEXMAP" compare "$img" "$ref" --json | "$PY" -c \
            "import json,sys; print('%.2f' % json.load(sys.stdin)['psnr_db'])")
        t=$(target "$s")
        mark=""
        if [ "$t" != - ] && awk "BEGIN{exit !($psnr < $t)}"; then mark=" BELOW"; fail=1; fi
        printf '%-10s %-8s %10s %8s  %s%s\n' "$name" "$s" "$psnr" "$t" "$cmd" "$mark"
    done
done
exit $fail
