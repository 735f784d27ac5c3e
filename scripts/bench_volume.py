#!/usr/bin/env python3
"""Volume benchmark: texmap's ray marcher vs VTK's vtkFixedPointVolumeRayCastMapper
(../shared/peers/vtk_volume.py), same camera (vtk_volume.py's default), transfer function and
sample distance, 512x512, --threads 2, shading off and on, measured in the same run (the two
renderers alternate, `--rounds` times; the table gives the median over all frames).

Quality: PSNR of each renderer's image against its own reference rendered with steps 8x
smaller (sample distance / 8), plus texmap vs VTK at the benchmark step.

Equal quality: texmap is also timed at the coarser steps of --texmap-steps (in the same
rounds), each image compared with the same step/8 reference; the second table gives, per case,
the coarsest of those steps whose PSNR is still at least VTK's at the benchmark step, and its
speed next to VTK's ("faster than VTK at equal or better PSNR").

Run from the repository root after `cargo build --release -p texmap-cli`:
    python3 scripts/bench_volume.py [--frames 5] [--rounds 2] [--out /tmp/volbench]
Prints a Markdown table and writes the images and a JSON file to --out.
"""
import argparse, json, os, shutil, statistics, subprocess, sys

# `PEERS=DIR` points at a copy of ../shared/peers set up elsewhere (as the tools/ scripts take).
P = os.environ.get("PEERS") or os.path.normpath(
    os.path.join(os.path.dirname(__file__), "..", "..", "shared", "peers"))
PY = os.path.join(P, ".venv", "bin", "python")
TEXMAP = os.path.join("target", "release", "texmap")
CASES = [("vol256", os.path.join(P, "data", "vol256.nii.gz"), "synth"),
         ("mni152_t1", os.path.join(P, "data", "mni152_t1.nii.gz"), "mri")]


def texmap(path, tf, shade, step, frames, out):
    # Several frames are one file each; frame 1 is the requested view, kept as `out`.
    # `--auto-camera`: vtk_volume.py's camera (texmap's own default framing differs).
    pattern = out if frames == 1 else out[:-len(".png")] + "_{frame}.png"
    cmd = [TEXMAP, "render", path, "--tf", tf, "--step", str(step), "--size", "512x512",
           "--threads", "2", "--frames", str(frames), "--stats", "--auto-camera", "-o", pattern]
    if shade:
        cmd.append("--shade")
    r = subprocess.run(cmd, capture_output=True, text=True, check=True)
    if frames > 1:
        shutil.copyfile(pattern.replace("{frame}", "0001"), out)
    return json.loads(r.stdout)


def vtk(path, tf, shade, step, frames, out):
    cmd = [PY, os.path.join(P, "vtk_volume.py"), path, "--tf", tf, "--shade", "on" if shade else "off",
           "--sample-distance", str(step), "--size", "512x512", "--threads", "2",
           "--frames", str(frames), "--json", "-o", out]
    r = subprocess.run(cmd, capture_output=True, text=True, check=True)
    return json.loads(r.stdout.strip().splitlines()[-1])


def psnr(a, b):
    r = subprocess.run([TEXMAP, "compare", a, b, "--json"], capture_output=True, text=True, check=True)
    return json.loads(r.stdout)["psnr_db"]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--frames", type=int, default=5)
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--step", type=float, default=0.5)
    ap.add_argument("--out", default="/tmp/volbench")
    ap.add_argument("--texmap-steps", default="0.75,1,2", help="coarser texmap steps to time too")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    steps = [float(x) for x in a.texmap_steps.split(",") if x]
    rows = []
    for name, path, tf in CASES:
        for shade in (False, True):
            tag = f"{name}_{'shade' if shade else 'flat'}"
            t_ms, v_ms = [], []
            coarse = {s: [] for s in steps}
            for _ in range(a.rounds):
                t = texmap(path, tf, shade, a.step, a.frames, f"{a.out}/{tag}_texmap.png")
                v = vtk(path, tf, shade, a.step, a.frames, f"{a.out}/{tag}_vtk.png")
                t_ms += t["frame_ms_all"]
                v_ms += v["frame_ms_all"]
                for st in steps:
                    c = texmap(path, tf, shade, st, a.frames, f"{a.out}/{tag}_texmap_step{st}.png")
                    coarse[st] += c["frame_ms_all"]
            ref = a.step / 8
            texmap(path, tf, shade, ref, 1, f"{a.out}/{tag}_texmap_ref.png")
            vtk(path, tf, shade, ref, 1, f"{a.out}/{tag}_vtk_ref.png")
            row = {
                "volume": name, "tf": tf, "shade": shade, "step": a.step,
                "texmap_ms": round(statistics.median(t_ms), 1), "vtk_ms": round(statistics.median(v_ms), 1),
                "texmap_psnr_vs_ref": round(psnr(f"{a.out}/{tag}_texmap.png", f"{a.out}/{tag}_texmap_ref.png"), 2),
                "vtk_psnr_vs_ref": round(psnr(f"{a.out}/{tag}_vtk.png", f"{a.out}/{tag}_vtk_ref.png"), 2),
                "texmap_vs_vtk_psnr": round(psnr(f"{a.out}/{tag}_texmap.png", f"{a.out}/{tag}_vtk.png"), 2),
                "frames_each": len(t_ms),
                "texmap_coarser": [
                    {"step": st, "ms": round(statistics.median(coarse[st]), 1),
                     "psnr_vs_ref": round(psnr(f"{a.out}/{tag}_texmap_step{st}.png",
                                               f"{a.out}/{tag}_texmap_ref.png"), 2)}
                    for st in steps],
            }
            rows.append(row)
            print(json.dumps(row), file=sys.stderr, flush=True)
    with open(f"{a.out}/bench.json", "w") as f:
        json.dump(rows, f, indent=1)
    print("| volume (TF) | shading | texmap ms/frame | VTK fixed-point ms/frame | texmap PSNR vs step/8 | VTK PSNR vs step/8 | texmap vs VTK |")
    print("|---|---|---:|---:|---:|---:|---:|")
    for r in rows:
        print(f"| {r['volume']} ({r['tf']}) | {'on' if r['shade'] else 'off'} | {r['texmap_ms']} | {r['vtk_ms']} | "
              f"{r['texmap_psnr_vs_ref']} dB | {r['vtk_psnr_vs_ref']} dB | {r['texmap_vs_vtk_psnr']} dB |")
    print()
    print("| volume (TF) | shading | VTK step | VTK ms | VTK PSNR | texmap step | texmap ms | texmap PSNR | texmap / VTK time |")
    print("|---|---|---:|---:|---:|---:|---:|---:|---:|")
    for r in rows:
        options = [(r["step"], r["texmap_ms"], r["texmap_psnr_vs_ref"])]
        options += [(c["step"], c["ms"], c["psnr_vs_ref"]) for c in r["texmap_coarser"]]
        ok = [o for o in options if o[2] >= r["vtk_psnr_vs_ref"]]
        st, ms, q = max(ok, key=lambda o: o[0]) if ok else options[0]
        print(f"| {r['volume']} ({r['tf']}) | {'on' if r['shade'] else 'off'} | {r['step']} | {r['vtk_ms']} | "
              f"{r['vtk_psnr_vs_ref']} dB | {st} | {ms} | {q} dB | {ms / r['vtk_ms']:.2f} |")


if __name__ == "__main__":
    main()
