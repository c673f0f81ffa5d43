#!/usr/bin/env python3
"""Measures each big-formula family's cold first frame against its
evaluation floor, and prints a Markdown table.

The frame: the whole `isotrace render` process at SIZE² with Mesa's shader
cache off (the driver's compile included), `--field auto`. The floor: the
time of the evaluations that frame's traversal needed, without the
traversal: its inclusion evaluations (`evals_mean` × pixels) times the
device's time per evaluation, measured with `isotrace eval` (same field
source and algebra, boxes of a mid-depth cell's size, the slope between two
batch sizes so that start-up and the compile cancel; for a formula `auto`
renders as a scene, the compiled formula's, whose whole tree is more than
a tile's pruned one). The target of the
benchmark report is a frame within 2 × floor + 1 s.

    python3 scripts/big-floor.py [--dir /tmp/big-formulas] [--size 512] [--timeout 120] [FAMILY...]
"""
import argparse
import json
import os
import random
import subprocess
import sys
import tempfile
import time

BOX = {"p400": "-2,2", "f1253": "-2,2", "f2503": "-2,2", "f12503": "-2,2", "city4": "-5.4,5.4,-5.4,5.4,-0.1,2"}
FAMILIES = ["p400", "f1253", "f2503", "f12503", "trig", "gauss", "spheres", "coarse", "mono3000", "btree", "city4", "distinct", "random"]
SMALL, LARGE = 4096, 131072


def box_of(name):
    v = [float(x) for x in BOX.get(name, "-1.5,1.5").split(",")]
    return v * 3 if len(v) == 2 else v


def cold_frame(exe, path, name, size, timeout, out):
    env = dict(os.environ, MESA_SHADER_CACHE_DISABLE="true", NODEVICE_SELECT="1")
    cmd = [exe, "render", "-f", path, f"--box={BOX.get(name, '-1.5,1.5')}", "--size", str(size), "--json", "-q", "-o", out]
    t0 = time.monotonic()
    try:
        r = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=timeout)
    except subprocess.TimeoutExpired:
        return None, None
    wall = time.monotonic() - t0
    if r.returncode != 0:
        sys.exit(f"{name}: render failed: {r.stderr}")
    return wall, json.loads(r.stdout)


def eval_seconds(exe, path, stats, boxes_path, timeout):
    # A scene's enclosures run only inside its render kernel, on each tile's
    # pruned tree: its floor takes the compiled formula's evaluation, of the
    # whole tree (so it lies above the scene's own).
    field = "compiled" if stats["field"] == "scene" else stats["field"]
    cmd = [exe, "eval", "-f", path, "--algebra", stats["algebra"], "--field", field, "--boxes", boxes_path, "-q"]
    t0 = time.monotonic()
    try:
        r = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env=dict(os.environ, NODEVICE_SELECT="1"))
    except subprocess.TimeoutExpired:
        sys.exit(f"eval of {path} took over {timeout:.0f} s")
    if r.returncode != 0:
        sys.exit(f"eval failed: {r.stderr}")
    return time.monotonic() - t0


def write_boxes(path, n, b, width, rng):
    with open(path, "w") as f:
        for _ in range(n):
            lo = [rng.uniform(b[2 * a], b[2 * a + 1] - width[a]) for a in range(3)]
            f.write(" ".join(f"{lo[a]:.6f} {lo[a] + width[a]:.6f}" for a in range(3)) + "\n")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("families", nargs="*", default=FAMILIES)
    ap.add_argument("--dir", default="/tmp/big-formulas", help="where scripts/big-formulas.py wrote the files (written if missing)")
    ap.add_argument("--size", type=int, default=512)
    ap.add_argument("--timeout", type=float, default=120.0, help="seconds a cold frame may take before the row says '>'")
    ap.add_argument("--isotrace", default="isotrace")
    a = ap.parse_args()
    if not os.path.isdir(a.dir):
        subprocess.run([sys.executable, os.path.join(os.path.dirname(__file__), "big-formulas.py"), a.dir], check=True, capture_output=True)
    rng = random.Random(5)
    print(f"{a.size}x{a.size}, cold whole process (MESA_SHADER_CACHE_DISABLE=true), --field auto\n")
    print("| family | field | algebra | first frame s | evaluations a pixel | µs an evaluation | floor s | 2 × floor + 1 s | within |")
    print("|---|---|---|---:|---:|---:|---:|---:|---|")
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "frame.png")
        for name in a.families:
            path = os.path.join(a.dir, f"{name}.txt")
            wall, stats = cold_frame(a.isotrace, path, name, a.size, a.timeout, out)
            if stats is None:
                print(f"| {name} | | | > {a.timeout:.0f} | | | | | no |", flush=True)
                continue
            b = box_of(name)
            # A cell a few levels above the leaves: 1/64 of the box a side.
            width = [(b[2 * k + 1] - b[2 * k]) / 64 for k in range(3)]
            small, large = os.path.join(tmp, "small.txt"), os.path.join(tmp, "large.txt")
            write_boxes(small, SMALL, b, width, rng)
            write_boxes(large, LARGE, b, width, rng)
            eval_seconds(a.isotrace, path, stats, small, 600)  # compiles, fills the cache
            per = (eval_seconds(a.isotrace, path, stats, large, 600) - eval_seconds(a.isotrace, path, stats, small, 600)) / (LARGE - SMALL)
            per = max(per, 0.0)
            floor = stats["evals_mean"] * stats["pixels"] * per
            limit = 2 * floor + 1
            print(f"| {name} | {stats['field']} | {stats['algebra']} | {wall:.2f} | {stats['evals_mean']:.2f} | {per * 1e6:.3f} | {floor:.2f} | {limit:.2f} | {'yes' if wall <= limit else 'no'} |", flush=True)


if __name__ == "__main__":
    main()
