#!/usr/bin/env python3
"""Renders Zanni et al.'s generated scene series sphere traced and bisected,
one row per scene, and prints a Markdown table of the frames beside each
other: GPU ms, the bisected / sphere traced ratio, inclusion evaluations per
pixel bisected, active primitives per 8x8 tile, unresolved pixels.

Each render runs twice and the second is kept, so the driver's compile
(cached by Mesa) is not in the figure.

    python3 scripts/scene-scale.py --size 1024 --max-level 3 [--isotrace PATH]
"""
import argparse
import json
import os
import re
import subprocess
import sys
import tempfile

SERIES = [("aggregate", ""), ("aggregate", "--smooth"), ("boxes", ""), ("boxes", "--smooth"),
          ("sphere-pairs", ""), ("sphere-pairs", "--smooth")]


def run(cmd, stream="stdout"):
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"failed ({r.returncode}): {' '.join(cmd)}\n{r.stderr}")
    return getattr(r, stream)


def cpu():
    try:
        with open("/proc/cpuinfo") as f:
            model = next((l.split(":", 1)[1].strip() for l in f if l.startswith("model name")), "an unknown CPU")
    except OSError:
        model = "an unknown CPU"
    return f"{model} ({os.cpu_count()} threads)"


def frame(exe, scene, method, size, out):
    cmd = [exe, "render", scene, "--method", method, "--size", str(size), "--json", "-q", "-o", out]
    run(cmd)
    return json.loads(run(cmd))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=int, default=1024)
    ap.add_argument("--max-level", type=int, default=3, choices=range(0, 5))
    ap.add_argument("--isotrace", default="isotrace", help="the isotrace binary (default: from PATH)")
    a = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "frame.png")
        head = run([a.isotrace, "--version"]).strip()
        print(f"{head} on {cpu()}, {a.size}x{a.size}, GPU ms of a frame (the second of two runs)\n")
        print("| series | level | primitives | sphere traced ms | bisected ms | bisected / sphere traced "
              "| evaluations a pixel, bisected | active primitives a tile | unresolved, bisected |")
        print("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
        device = None
        for kind, flag in SERIES:
            for level in range(a.max_level + 1):
                scene = os.path.join(tmp, f"{kind}-{level}.scene.json")
                said = run([a.isotrace, "scene", "gen", kind, "--level", str(level), *([flag] if flag else []), "-o", scene], "stderr")
                prims = int(re.search(r"(\d+) primitives", said).group(1))
                s = frame(a.isotrace, scene, "sphere", a.size, out)
                b = frame(a.isotrace, scene, "bisect", a.size, out)
                device = b["device"]
                name = f"{kind}, {'smooth' if flag else 'sharp'}"
                print(f"| {name} | {level} | {prims:,} | {s['gpu_ms']:.1f} | {b['gpu_ms']:.1f} | "
                      f"{b['gpu_ms'] / s['gpu_ms']:.2f} | {b['evals_mean']:.2f} | {b['active_mean']:.1f} | {b['unresolved']} |",
                      flush=True)
        if device:
            print(f"\nDevice: {device['name']} ({device['driver']}).")


if __name__ == "__main__":
    main()
