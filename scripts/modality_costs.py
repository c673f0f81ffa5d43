#!/usr/bin/env python3
"""Cost of each visualisation modality relative to plain rendering, on the
Knoll suite: median GPU ms of `isotrace render --json` over REPEAT runs
(after a warm-up), per surface and modality, and the ratio to plain.

    python3 scripts/modality_costs.py [SIZE [REPEAT]]
"""
import json, statistics, subprocess, sys

SIZE = sys.argv[1] if len(sys.argv) > 1 else "512"
REPEAT = int(sys.argv[2]) if len(sys.argv) > 2 else 3
BIN = "target/release/isotrace"
KNOLL = ["sphere", "steiner", "mitchell", "teardrop", "4-bretzel", "klein-bottle", "tangle", "decocube",
         "barth-sextic", "barth-decic", "superquadric", "icos.csg", "sq.csg", "sin.blob", "cloth", "water"]
MODES = [
    ("plain", []),
    ("shadows, eps as primary", ["--shadows", "--shadow-eps", "EPS1"]),
    ("shadows, eps 4x coarser (default)", ["--shadows"]),
    ("transparency 4 layers", ["--opacity", "0.5", "--layers", "4"]),
    ("3 isovalues", ["--iso", "-0.05,0,0.05"]),
    ("reflections (1 bounce)", ["--reflect", "1"]),
]

def diagonal(name):
    """Box diagonal from `isotrace list --long` (the default eps is 2^-11 of it)."""
    out = subprocess.run([BIN, "list", "--long"], capture_output=True, text=True, check=True).stdout
    lines = out.splitlines()
    for k, line in enumerate(lines):
        if line.split() and line.split()[0] == name:
            box = lines[k + 1].split("box ")[1].split()[0]
            nums = [float(v) for v in box.replace("[", "").replace("]", "").replace("x", ",").split(",")]
            return sum((nums[2 * i + 1] - nums[2 * i]) ** 2 for i in range(3)) ** 0.5
    raise SystemExit(f"{name} not in the catalog")

def gpu_ms(name, extra):
    extra = [str(diagonal(name) * 2 ** -11) if a == "EPS1" else a for a in extra]
    times = []
    for k in range(REPEAT + 1):
        out = subprocess.run([BIN, "render", "@" + name, "--size", SIZE, "-o", "/tmp/modality.png", "--json"] + extra,
                             capture_output=True, text=True, check=True).stdout
        if k > 0:
            times.append(json.loads(out)["gpu_ms"])
    return statistics.median(times)

def main():
    print(f"{SIZE}x{SIZE}, median GPU ms of {REPEAT} runs; ratio to plain")
    print("| surface | " + " | ".join(m for m, _ in MODES) + " |")
    print("|---|" + "---:|" * len(MODES))
    ratios = {m: [] for m, _ in MODES}
    for name in KNOLL:
        row = []
        base = None
        for mode, extra in MODES:
            ms = gpu_ms(name, extra)
            base = base or ms
            ratios[mode].append(ms / base)
            row.append(f"{ms:.0f}" if mode == "plain" else f"{ms:.0f} ({ms / base:.2f}x)")
        print(f"| {name} | " + " | ".join(row) + " |", flush=True)
    geo = lambda v: statistics.geometric_mean(v)
    print("| geometric mean | " + " | ".join("1.00x" if m == "plain" else f"{geo(r):.2f}x" for m, r in ratios.items()) + " |")

main()
