#!/usr/bin/env python3
"""Plots `isotrace bench --suite scenes --json FILE` as an SVG: ms per frame
against primitive count (both axes logarithmic), one panel per series
(aggregate, boxes, sphere pairs), one line per path: the sparse scene path, the same bisected,
the same with the tile's rays walking its slabs together (sync), the dense baseline (the whole tree in every tile), the compiled formula
where it was measured, and, with --peer, fidget's ms from the table that
`benches/peer --scenes` prints (its stdout saved to a file). Sharp blends
are solid lines, smooth ones dashed. Standard library only.

    scripts/plot-scenes.py scenes.json --peer peer.txt -o docs/scenes.svg
"""
import argparse
import json
import math

PATHS = {"sparse": "#1f77b4", "bisect": "#ff7f0e", "sync": "#9467bd", "dense": "#d62728", "compiled": "#7f7f7f", "fidget": "#2ca02c"}
KINDS = ["aggregate", "boxes", "sphere-pairs"]


def peer_rows(path):
    """(kind, blend, prims, fidget ms) from a saved `benches/peer --scenes` table."""
    rows = []
    with open(path) as f:
        for line in f:
            w = line.split()
            if len(w) >= 7 and w[0] in KINDS and w[1] in ("sharp", "smooth") and "skipped" not in line:
                try:
                    rows.append((w[0], w[1], int(w[3]), float(w[6])))
                except ValueError:
                    pass
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("json")
    ap.add_argument("--peer", help="the saved stdout of benches/peer --scenes (same size)")
    ap.add_argument("-o", "--output", required=True)
    a = ap.parse_args()
    with open(a.json) as f:
        doc = json.load(f)
    lines = {}
    for r in doc["rows"]:
        lines.setdefault((r["kind"], r["blending"], r["path"]), []).append((r["primitives"], r["gpu_ms"]))
    if a.peer:
        for kind, blend, prims, ms in peer_rows(a.peer):
            lines.setdefault((kind, blend, "fidget"), []).append((prims, ms))
    xs = [p for pts in lines.values() for p, _ in pts]
    ys = [m for pts in lines.values() for _, m in pts]
    x0, x1 = math.log10(min(xs)) - 0.1, math.log10(max(xs)) + 0.1
    y0, y1 = math.log10(min(ys)) - 0.1, math.log10(max(ys)) + 0.1
    pw, h, m, top = 300, 420, 55, 40
    w = m + len(KINDS) * (pw + 20) + 10
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" font-family="sans-serif" font-size="11">',
           f'<rect width="{w}" height="{h}" fill="white"/>',
           f'<text x="{w / 2}" y="16" text-anchor="middle" font-size="13">{doc["machine"]}, {doc["size"][0]}x{doc["size"][1]}: ms per frame against primitives</text>',
           f'<text x="14" y="{h / 2}" transform="rotate(-90 14 {h / 2})" text-anchor="middle">ms per frame</text>']
    for k, kind in enumerate(KINDS):
        left = m + k * (pw + 20)
        sx = lambda v, left=left: left + (math.log10(v) - x0) / (x1 - x0) * pw
        sy = lambda v: h - m - (math.log10(v) - y0) / (y1 - y0) * (h - m - top)
        out += [f'<text x="{left + pw / 2}" y="{top - 8}" text-anchor="middle" font-size="12">{kind}</text>',
                f'<line x1="{left}" y1="{h - m}" x2="{left + pw}" y2="{h - m}" stroke="black"/>',
                f'<line x1="{left}" y1="{top}" x2="{left}" y2="{h - m}" stroke="black"/>',
                f'<text x="{left + pw / 2}" y="{h - m + 30}" text-anchor="middle">primitives</text>']
        for e in range(math.ceil(x0), math.floor(x1) + 1):
            out.append(f'<text x="{sx(10 ** e)}" y="{h - m + 14}" text-anchor="middle">{10 ** e}</text>')
        for e in range(math.ceil(y0), math.floor(y1) + 1):
            out.append(f'<line x1="{left}" y1="{sy(10 ** e)}" x2="{left + pw}" y2="{sy(10 ** e)}" stroke="#ddd"/>')
            if k == 0:
                out.append(f'<text x="{left - 4}" y="{sy(10 ** e) + 4}" text-anchor="end">{10 ** e:g}</text>')
        for (kd, blend, path), pts in sorted(lines.items()):
            if kd != kind:
                continue
            pts.sort()
            dash = ' stroke-dasharray="5,3"' if blend == "smooth" else ""
            poly = " ".join(f"{sx(p):.1f},{sy(v):.1f}" for p, v in pts)
            out.append(f'<polyline points="{poly}" fill="none" stroke="{PATHS.get(path, "black")}" stroke-width="1.6"{dash}/>')
            out += [f'<circle cx="{sx(p):.1f}" cy="{sy(v):.1f}" r="2" fill="{PATHS.get(path, "black")}"/>' for p, v in pts]
    legend = [(p, b) for p in PATHS for b in ("sharp", "smooth") if any(k[1:] == (b, p) for k in lines)]
    for i, (path, blend) in enumerate(legend):
        x, y = m + 10 + (i % 4) * 150, top + 8 + (i // 4) * 14
        dash = ' stroke-dasharray="5,3"' if blend == "smooth" else ""
        out += [f'<line x1="{x}" y1="{y}" x2="{x + 22}" y2="{y}" stroke="{PATHS[path]}" stroke-width="1.6"{dash}/>',
                f'<text x="{x + 26}" y="{y + 4}">{path} {blend}</text>']
    out.append("</svg>")
    with open(a.output, "w") as f:
        f.write("\n".join(out) + "\n")


if __name__ == "__main__":
    main()
