#!/usr/bin/env python3
"""Writes the big formulas that the README's measurements use, one file each.

Every family is seeded, so the files are the same on every machine. Render
them with `isotrace render -f OUT/NAME.txt --box=-1.5,1.5 --size 512`
(the cities with `--box=-5.4,5.4,-5.4,5.4,-0.1,2`). The families:

- the sums of bilinear products: p400, f1253, f2503, f12503;
- 60 KB sums of one shape of term with random three-decimal constants:
  trig (sin·cos·sin products), gauss (Gaussians), spheres (a min of ball
  distances), coarse (a min of balls with one-decimal centres);
- monomials: mono3000 (3,000 terms, powers below 7, many alike) and
  distinct (2,800 distinct monomials, powers below 15);
- trees without runs: random (min/max/cut/product/sum trees of
  quadrics), btree (a balanced min tree of boxes);
- city4: four copies of @city's blocks, written out.
"""
import argparse
import os
import re
import random

LIMIT = 64 * 1024


def c(v):
    return f"{v:.3f}"


def p400():
    return " + ".join(f"(x - {i})*(y + {i})" for i in range(1, 401))


def bilinear(n):
    terms = "+".join(f"({0.5 + i * 0.001:.3f}*x-y)*(z+{i * 0.002 + 0.001:.3f})" for i in range(n))
    return "x^2+y^2+z^2-1+1e-4*(" + terms + ")"


def fill(head, term, sep, tail=""):
    """Joins terms while the text stays under 60,000 bytes."""
    rng = random.Random(14)
    out = []
    size = len(head) + len(tail)
    while True:
        t = term(rng)
        if size + len(t) + len(sep) > 60_000:
            return head + sep.join(out) + tail
        out.append(t)
        size += len(t) + len(sep)


def ball(r, d=3):
    f = lambda v: f"{v:.{d}f}"
    a, b, e = (r.uniform(-1.2, 1.2) for _ in range(3))
    return f"sqrt((x-{f(a)})^2+(y-{f(b)})^2+(z-{f(e)})^2)-{c(r.uniform(0.05, 0.2))}"


def trig(r):
    a, b, e = (r.uniform(0.5, 3) for _ in range(3))
    return f"{c(r.uniform(0.001, 0.01))}*sin({c(a)}*x)*cos({c(b)}*y)*sin({c(e)}*z)"


def gauss(r):
    a, b, e = (r.uniform(-1, 1) for _ in range(3))
    return f"{c(r.uniform(0.01, 0.05))}*exp(-{c(r.uniform(5, 20))}*((x-{c(a)})^2+(y-{c(b)})^2+(z-{c(e)})^2))"


def monomial(r, seen=None):
    while True:
        p = [r.randrange(7 if seen is None else 15) for _ in range(3)]
        key = tuple(p)
        if seen is None or key not in seen:
            break
    if seen is not None:
        seen.add(key)
    parts = [f"{v}^{k}" if k > 1 else v for v, k in zip("xyz", p) if k]
    return "*".join([c(r.uniform(-0.01, 0.01))] + parts)


def quadric(r):
    a, b, e = (r.uniform(-1, 1) for _ in range(3))
    return f"(x-{c(a)})^2+(y-{c(b)})^2+(z-{c(e)})^2-{c(r.uniform(0.02, 0.1))}"


def random_tree(r, depth):
    if depth == 0 or r.random() < 0.1:
        return quadric(r)
    op = r.choice(["min", "min", "max", "cut", "prod", "sum"])
    a, b = random_tree(r, depth - 1), random_tree(r, depth - 1)
    if op == "cut":
        return f"max({a}, -({b}))"
    if op == "prod":
        return f"({a})*({b})"
    if op == "sum":
        return f"({a})+{c(r.uniform(0.1, 0.5))}*({b})"
    return f"{op}({a}, {b})"


def random_forest():
    r = random.Random(14)
    out = []
    while True:
        t = random_tree(r, 5)
        text = "min(" + ", ".join(out + [t]) + ")"
        if len(text) > 60_000:
            return "min(" + ", ".join(out) + ")"
        out.append(t)


def box(r):
    a, b, e = (r.uniform(-1.2, 1.2) for _ in range(3))
    s = [c(r.uniform(0.03, 0.12)) for _ in range(3)]
    return f"max(abs(x-{c(a)})-{s[0]}, abs(y-{c(b)})-{s[1]}, abs(z-{c(e)})-{s[2]})"


def balanced(items):
    if len(items) == 1:
        return items[0]
    h = len(items) // 2
    return f"min({balanced(items[:h])}, {balanced(items[h:])})"


def btree():
    r = random.Random(14)
    boxes = [box(r)]
    while len(balanced(boxes)) < 60_000:
        boxes.append(box(r))
    return balanced(boxes[:-1])


def city4(root):
    src = open(os.path.join(root, "examples/city.iso")).read()
    body = "\n".join(l for l in src.splitlines() if not l.startswith("#"))
    lets, last = body.rsplit(";", 1)
    out, roots = [], []
    shift = re.compile(r"translate\(([-0-9.]+), ([-0-9.]+),")
    for k, (dx, dy) in enumerate([(-2.7, -2.7), (2.7, -2.7), (-2.7, 2.7), (2.7, 2.7)]):
        text = re.sub(r"\b(row\d|ground)\b", lambda m: f"c{k}{m.group(1)}", lets)
        text = shift.sub(lambda m: f"translate({float(m.group(1)) + dx:g}, {float(m.group(2)) + dy:g},", text)
        out.append(text + ";")
        roots.append(re.sub(r"\b(row\d|ground)\b", lambda m: f"c{k}{m.group(1)}", last.strip()))
    return "\n".join(out) + "\nunion(" + ", ".join(roots) + ")"


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out", nargs="?", default="/tmp/big-formulas", metavar="OUT", help="directory to write NAME.txt into, created if missing (default: %(default)s)")
    out = parser.parse_args().out
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    os.makedirs(out, exist_ok=True)
    seen = set()
    families = {
        "p400": p400(),
        "f1253": bilinear(178),
        "f2503": bilinear(356),
        "f12503": bilinear(1785),
        "trig": fill("x^2+y^2+z^2-1+", trig, "+"),
        "gauss": fill("x^2+y^2+z^2-1+", gauss, "+"),
        "spheres": fill("min(", ball, ",", ")"),
        "coarse": fill("min(", lambda r: ball(r, 1), ",", ")"),
        "mono3000": "x^2+y^2+z^2-1+" + "+".join(monomial(random.Random(i)) for i in range(3000)),
        "distinct": "x^2+y^2+z^2-1+" + "+".join(monomial(random.Random(14 + i), seen) for i in range(2800)),
        "random": random_forest(),
        "btree": btree(),
        "city4": city4(root),
    }
    for name, text in families.items():
        assert len(text) <= LIMIT, (name, len(text))
        with open(os.path.join(out, name + ".txt"), "w") as f:
            f.write(text)
        print(f"{name}: {len(text)} bytes")


if __name__ == "__main__":
    main()
