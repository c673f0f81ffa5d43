#!/usr/bin/env python3
"""Plots `isotrace bench --suite scenes --json FILE` as an SVG: GPU ms per
frame against primitive count (both axes logarithmic), one line per
(series, blending, path): the sparse scene path solid, the dense baseline
(the whole tree in every tile) dashed. Standard library only.

    scripts/plot-scenes.py scenes.json -o docs/scenes.svg
"""
import argparse
import json
import math

COLOURS = {"aggregate": "#1f77b4", "boxes": "#d62728", "sphere-pairs": "#2ca02c"}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("json")
    ap.add_argument("-o", "--output", required=True)
    a = ap.parse_args()
    with open(a.json) as f:
        doc = json.load(f)
    lines = {}
    for r in doc["rows"]:
        key = (r["kind"], r["blending"], r["path"])
        lines.setdefault(key, []).append((r["primitives"], r["gpu_ms"]))
    xs = [p for pts in lines.values() for p, _ in pts]
    ys = [m for pts in lines.values() for _, m in pts]
    x0, x1 = math.log10(min(xs)), math.log10(max(xs)) + 1e-9
    y0, y1 = math.log10(min(ys)) - 0.1, math.log10(max(ys)) + 0.1
    w, h, m = 720, 440, 60
    sx = lambda v: m + (math.log10(v) - x0) / (x1 - x0) * (w - 2 * m)
    sy = lambda v: h - m - (math.log10(v) - y0) / (y1 - y0) * (h - 2 * m)
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" font-family="sans-serif" font-size="11">',
           f'<rect width="{w}" height="{h}" fill="white"/>',
           f'<text x="{w / 2}" y="18" text-anchor="middle" font-size="13">{doc["machine"]}, {doc["size"][0]}x{doc["size"][1]}</text>',
           f'<line x1="{m}" y1="{h - m}" x2="{w - m}" y2="{h - m}" stroke="black"/>',
           f'<line x1="{m}" y1="{m}" x2="{m}" y2="{h - m}" stroke="black"/>',
           f'<text x="{w / 2}" y="{h - 15}" text-anchor="middle">primitives</text>',
           f'<text x="15" y="{h / 2}" transform="rotate(-90 15 {h / 2})" text-anchor="middle">GPU ms per frame</text>']
    for e in range(math.floor(x0), math.ceil(x1) + 1):
        if x0 <= e <= x1:
            out.append(f'<text x="{sx(10 ** e)}" y="{h - m + 15}" text-anchor="middle">{10 ** e}</text>')
    for e in range(math.floor(y0), math.ceil(y1) + 1):
        if y0 <= e <= y1:
            out.append(f'<text x="{m - 5}" y="{sy(10 ** e) + 4}" text-anchor="end">{10 ** e:g}</text>')
    legend_y = m
    for (kind, blend, path), pts in sorted(lines.items()):
        pts.sort()
        colour = COLOURS.get(kind, "black")
        dash = ' stroke-dasharray="5,4"' if path == "dense" else ""
        width = 2 if blend == "smooth" else 1
        poly = " ".join(f"{sx(p):.1f},{sy(v):.1f}" for p, v in pts)
        out.append(f'<polyline points="{poly}" fill="none" stroke="{colour}" stroke-width="{width}"{dash}/>')
        out.append(f'<line x1="{w - m - 150}" y1="{legend_y}" x2="{w - m - 125}" y2="{legend_y}" stroke="{colour}" stroke-width="{width}"{dash}/>')
        out.append(f'<text x="{w - m - 120}" y="{legend_y + 4}">{kind} {blend} {path}</text>')
        legend_y += 14
    out.append("</svg>")
    with open(a.output, "w") as f:
        f.write("\n".join(out) + "\n")


if __name__ == "__main__":
    main()
