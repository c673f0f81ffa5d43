#!/usr/bin/env bash
# Re-runs the benchmarks of docs/benchmarks.md and regenerates its tables.
#
#   scripts/benchmarks.sh [--quick] [--only SECTIONS] [--out DIR] [--doc FILE]
#
# SECTIONS (comma-separated; default all): knoll, peer, scenes, scene-edit, big, latency.
#   knoll       isotrace bench --suite knoll at 1024² (about 10 minutes)
#   peer        benches/peer against fidget, both views (builds fidget first: about 10 minutes
#               the first time, then about 15 minutes)
#   scenes      isotrace bench --suite scenes to level 3 and the peer's scene series (over an hour:
#               the dense baseline's frames take up to a minute each)
#   scene-edit  cargo bench --features internals --bench scene_edit
#   big         the big formulas of scripts/big-formulas.py, cold, whole process (about 10 minutes)
#   latency     catalog surfaces' first picture, cold and warm, whole process (about a minute)
#
# Raw results go to --out (default target/benchmarks); the tables between the
# `<!-- benchmarks.sh: NAME -->` and `<!-- benchmarks.sh: end -->` lines of --doc (default
# docs/benchmarks.md) are replaced. A full run also refreshes the raw files the docs keep
# (docs/peer-1024.txt, docs/scenes-1024.json, docs/scenes-1024-peer.txt, docs/scenes.svg,
# docs/contact-sheet.png). --quick runs every section small (tiny sizes, one repeat, the peer
# harness left out) into a scratch copy of the doc in --out, to check this script.
#
# Not run in CI. Run it on an otherwise idle machine: the figures are wall and GPU times.
set -euo pipefail
cd "$(dirname "$0")/.."

quick=0
only="knoll,peer,scenes,scene-edit,big,latency"
out=target/benchmarks
doc=docs/benchmarks.md
while [ $# -gt 0 ]; do
    case "$1" in
        --quick) quick=1 ;;
        --only) only="$2"; shift ;;
        --out) out="$2"; shift ;;
        --doc) doc="$2"; shift ;;
        -h|--help) sed -n '2,24p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
        *) echo "benchmarks.sh: unknown argument '$1' (see --help)" >&2; exit 1 ;;
    esac
    shift
done
wants() { case ",$only," in *",$1,"*) return 0 ;; *) return 1 ;; esac; }

export NODEVICE_SELECT=1
cargo build --release --locked
bin="$PWD/target/release/isotrace"
mkdir -p "$out"

if [ "$quick" = 1 ]; then
    size=128; repeat=1; level=1; peer_size=128
    cp "$doc" "$out/benchmarks.md"; doc="$out/benchmarks.md"
else
    size=1024; repeat=5; level=3; peer_size=1024
fi

if wants knoll; then
    echo "benchmarks: the Knoll suite" >&2
    "$bin" bench --suite knoll --size "$size" --repeat "$repeat" --algebra ia,raa,auto \
        --out "$out/knoll-images" --json "$out/knoll.json" --markdown "$out/knoll.md"
fi

peer_bin=benches/peer/target/release/isotrace-peer-bench
if wants peer && [ "$quick" = 0 ]; then
    echo "benchmarks: isotrace against fidget" >&2
    cargo build --release --locked --manifest-path benches/peer/Cargo.toml
    "$peer_bin" --size "$peer_size" --repeat 3 --view both | tee "$out/peer-1024.txt"
fi

if wants scenes; then
    echo "benchmarks: the generated scene series" >&2
    "$bin" bench --suite scenes --max-level "$level" --size "$size" --repeat 1 \
        --json "$out/scenes.json" --markdown "$out/scenes.md"
    if [ "$quick" = 0 ]; then
        cargo build --release --locked --manifest-path benches/peer/Cargo.toml
        "$peer_bin" --scenes --max-level "$level" --size "$peer_size" --repeat 3 --guard 60 | tee "$out/scenes-peer.txt"
    fi
fi

if wants scene-edit; then
    echo "benchmarks: scene edits" >&2
    if [ "$quick" = 1 ]; then
        cargo bench --locked --features internals --bench scene_edit -- --warm-up-time 1 --measurement-time 2 "in place" 2>&1 | tee "$out/scene-edit.txt"
    else
        cargo bench --locked --features internals --bench scene_edit 2>&1 | tee "$out/scene-edit.txt"
    fi
fi

if wants big; then
    python3 scripts/big-formulas.py "$out/big-formulas" >/dev/null
fi

# Timings of whole processes and the tables.
python3 - "$bin" "$out" "$doc" "$quick" "$only" <<'PY'
import json, os, re, subprocess, sys, time, math

BIN, OUT, DOC, QUICK, ONLY = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4] == "1", sys.argv[5].split(",")


def cpu():
    model = "unknown CPU"
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                model = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    return f"{model}, {os.cpu_count()} cores"


def device():
    """The Vulkan device and driver, from a tiny render's --json."""
    r = subprocess.run([BIN, "render", "@sphere", "--size", "8", "-o", os.path.join(OUT, "probe.png"), "--json"],
                       capture_output=True, text=True, check=True)
    d = json.loads(r.stdout)["device"]
    return f"{d['name']}, {d['driver']}"


def machine_line(dev=None):
    return f"Machine: {cpu()}; {dev or device()}; measured {time.strftime('%Y-%m-%d')}."


def ms(v):
    return f"{v:,.1f}" if v < 100 else f"{v:,.0f}"


def secs(values):
    lo, hi = min(values), max(values)
    return f"{lo:.2f} s" if f"{lo:.2f}" == f"{hi:.2f}" else f"{lo:.2f}-{hi:.2f} s"


def wall(args, env=None, timeout=300):
    """Wall seconds of one whole isotrace process, and its stderr (None on timeout)."""
    start = time.monotonic()
    try:
        r = subprocess.run([BIN] + args, capture_output=True, text=True, env=env, timeout=timeout)
    except subprocess.TimeoutExpired:
        return None, ""
    if r.returncode != 0:
        raise SystemExit(f"benchmarks: {' '.join(args)} failed:\n{r.stderr}")
    return time.monotonic() - start, r.stderr


def cold_env():
    env = dict(os.environ)
    env["MESA_SHADER_CACHE_DISABLE"] = "true"
    return env


# --- tables ---------------------------------------------------------------------------------

def knoll_table(path):
    rep = json.load(open(path))
    rows, order = {}, []
    for r in rep["results"]:
        if r["surface"] not in rows:
            order.append(r["surface"])
            rows[r["surface"]] = {"degree": r["degree"].split(" (")[0]}
        rows[r["surface"]][r["algebra"]] = r
    dev = rep["device"]
    size = rep["settings"]["size"]
    out = [f"Machine: {cpu()}; {dev['name']}, {dev['driver']}; measured {rep['date'][:10]}.",
           f"{size[0]}², median of {rep['settings']['repeat']} timed runs after a warm-up.", "",
           "| surface | degree | IA ms / evals | RAA ms / evals | auto picks | auto ms | auto evals / lower bound |",
           "|---|---|---:|---:|---|---:|---:|"]
    for s in order:
        row = rows[s]
        ia, raa, auto = row.get("ia"), row.get("raa"), row.get("auto")
        cell = {}
        for name, r in (("ia", ia), ("raa", raa)):
            cell[name] = "—" if r is None else "failed" if r.get("gpu_ms") is None else f"{ms(r['gpu_ms'])} / {r['evals_mean']:.2f}"
        if ia and raa and ia.get("gpu_ms") and raa.get("gpu_ms"):
            faster = "ia" if ia["gpu_ms"] <= raa["gpu_ms"] else "raa"
            ms_part, ev = cell[faster].split(" / ")
            cell[faster] = f"**{ms_part}** / {ev}"
        if auto and auto.get("gpu_ms") is not None:
            a = (auto.get("resolved_algebra") or "").upper(), ms(auto["gpu_ms"]), f"{auto['ratio']:.2f}"
        else:
            a = ("—", "failed", "—")
        out.append(f"| {s} | {row['degree']} | {cell['ia']} | {cell['raa']} | {a[0]} | {a[1]} | {a[2]} |")
    return "\n".join(out)


def peer_sections(path):
    """{title: [(surface, iso ms, fidget ms, ratio)], ...} and the header's device line."""
    sections, current, head = {}, None, ""
    for line in open(path):
        if line.startswith("# CPU:"):
            head = line[2:].strip().removeprefix("CPU: ")
        if line.startswith("## "):
            current = line[3:].strip()
            sections[current] = []
            continue
        w = line.split()
        if current is None or not w or w[0] in ("surface", "scene") or line.startswith("#"):
            continue
        sections[current].append(w)
    return sections, head


def peer_table(path):
    sections, head = peer_sections(path)
    views = {}
    for title, rows in sections.items():
        if not title.startswith("Knoll surfaces"):
            continue
        view = "ortho" if "view: ortho" in title else "perspective"
        table = {}
        for w in rows:
            if w[0] == "geomean":
                table["geomean"] = (float(w[1]), float(w[3]), float(w[4]))
            else:
                table[w[0]] = (float(w[2]), float(w[4]), float(w[5]))
        views[view] = table
    p, o = views["perspective"], views.get("ortho", {})
    out = [f"Machine: {head}; measured {time.strftime('%Y-%m-%d')}.", "",
           "| surface | isotrace ms | fidget ms | fidget / isotrace | ortho: isotrace ms | fidget ms | fidget / isotrace |",
           "|---|---:|---:|---:|---:|---:|---:|"]
    for s in [k for k in p if k != "geomean"] + ["geomean"]:
        a, b = p[s], o.get(s)
        name = "**geometric mean**" if s == "geomean" else s
        ratio = (lambda x: f"**{x:.2f}**") if s == "geomean" else (lambda x: f"{x:.2f}")
        right = f"{ms(b[0])} | {ms(b[1])} | {ratio(b[2])}" if b else "— | — | —"
        out.append(f"| {name} | {ms(a[0])} | {ms(a[1])} | {ratio(a[2])} | {right} |")
    return "\n".join(out)


SERIES = [("aggregate", "sharp"), ("aggregate", "smooth"), ("boxes", "sharp"), ("boxes", "smooth"),
          ("sphere-pairs", "sharp"), ("sphere-pairs", "smooth")]


def scenes_table(path):
    rep = json.load(open(path))
    cells, prims, levels = {}, {}, set()
    for r in rep["rows"]:
        cells[(r["kind"], r["blending"], r["path"], r["level"])] = r["gpu_ms"]
        prims[(r["kind"], r["level"])] = r["primitives"]
        levels.add(r["level"])
    levels = sorted(levels)
    top = levels[-1]
    head = ["series (primitives " + " / ".join(f"L{l}" for l in levels) + ")"]
    head += [f"sparse L{l}" for l in levels] + [f"sync L{top}"] + [f"dense L{l}" for l in levels] + ["compiled L0"]
    out = [f"Machine: {cpu()}; {rep['machine']}; measured {time.strftime('%Y-%m-%d')}.",
           f"{rep['size'][0]}², one run, GPU ms of a frame.", "",
           "| " + " | ".join(head) + " |", "|---|" + "---:|" * (len(head) - 1)]
    for kind, blend in SERIES:
        if not any(k[0] == kind and k[1] == blend for k in cells):
            continue
        counts = " / ".join(f"{prims.get((kind, l), 0):,}" for l in levels)
        get = lambda path, l: ms(cells[(kind, blend, path, l)]) if (kind, blend, path, l) in cells else "—"
        row = [f"{kind}, {blend} ({counts})"] + [get("sparse", l) for l in levels] + [get("sync", top)]
        row += [get("dense", l) for l in levels] + [get("compiled", 0)]
        out.append("| " + " | ".join(row) + " |")
    return "\n".join(out)


def scenes_peer_table(path):
    sections, head = peer_sections(path)
    rows = [w for title, ws in sections.items() if title.startswith("scenes") for w in ws]
    levels = sorted({int(w[2]) for w in rows})
    table = {}
    for w in rows:
        key = (w[0], w[1], int(w[2]))
        if "skipped:" in " ".join(w):
            m = re.search(r"fid/iso > ([0-9.]+)", " ".join(w))
            table[key] = f"> {float(m.group(1)):.0f}" if m else "—"
        else:
            table[key] = f"{float(w[7]):.2f}"
    out = [f"Machine: {head}; measured {time.strftime('%Y-%m-%d')}.", "", "| series | " + " | ".join(f"L{l}" for l in levels) + " |",
           "|---|" + "---:|" * len(levels)]
    for kind, blend in SERIES:
        if any((kind, blend, l) in table for l in levels):
            out.append(f"| {kind}, {blend} | " + " | ".join(table.get((kind, blend, l), "—") for l in levels) + " |")
    return "\n".join(out)


def scene_edit_table(path):
    text = open(path).read()
    found = re.findall(r"scene edit[^\n]*/([^\n]+)\n\s*time:\s*\[\S+ \S+ (\S+) (\S+) \S+ \S+\]", text)
    out = [machine_line(), "", "| operation | median time |", "|---|---:|"]
    for name, value, unit in found:
        out.append(f"| {name.strip()} | {value} {unit} |")
    return "\n".join(out)


BIG = [  # (file, what it is, --box)
    ("p400", "400 products (x − i)·(y + i)", "-2,2"),
    ("f1253", "a sum of 178 bilinear terms (1,253 operations)", "-2,2"),
    ("f2503", "356 bilinear terms (2,503 operations)", "-2,2"),
    ("f12503", "1,785 bilinear terms (12,503 operations, 39 KB)", "-2,2"),
    ("mono3000", "3,000 monomials of powers below 7, many alike", "-1.5,1.5"),
    ("trig", "a 60 KB sum of sin·cos·sin products", "-1.5,1.5"),
    ("gauss", "a 60 KB sum of Gaussians", "-1.5,1.5"),
    ("spheres", "a 60 KB min of ball distances", "-1.5,1.5"),
    ("coarse", "a 60 KB min of balls, one-decimal centres", "-1.5,1.5"),
    ("btree", "a balanced min tree of boxes", "-1.5,1.5"),
    ("city4", "four copies of @city's blocks, written out", "-5.4,5.4,-5.4,5.4,-0.1,2"),
    ("distinct", "2,800 distinct monomials", "-1.5,1.5"),
    ("random", "random min/max trees of quadrics (no repetition)", "-1.5,1.5"),
]


def big_table():
    size = "64" if QUICK else "512"
    rows = {}
    for name, what, box in BIG:
        f = os.path.join(OUT, "big-formulas", name + ".txt")
        times, field, limit = [], "?", 60 if QUICK else 300
        for _ in range(2):
            t, err = wall(["render", "-f", f, f"--box={box}", "--size", size, "-o", os.path.join(OUT, "big.png"), "--stats"],
                          env=cold_env(), timeout=limit)
            if t is None:
                times = None
                break
            times.append(t)
            m = re.search(r"\bfield (\w+)", err)
            field = m.group(1) if m else field
        rows[name] = (what, box, field, f"> {limit} s" if times is None else secs(times))
        print(f"big {name}: {rows[name][3]}", file=sys.stderr)
    json.dump(rows, open(os.path.join(OUT, "big.json"), "w"), indent=1)
    out = [machine_line(), f"Cold whole process (`MESA_SHADER_CACHE_DISABLE=true`), {size}², two runs.", "",
           "| formula | what it is | `--box` | `auto` runs | first picture |", "|---|---|---|---|---:|"]
    for name, (what, box, field, t) in rows.items():
        out.append(f"| `{name}` | {what} | `{box}` | {field} | {t} |")
    return "\n".join(out)


LATENCY = [  # arguments after `render`
    ["@tangle"], ["@decocube"], ["@barth-decic"], ["@creature"], ["@city"],
    ["@creature", "--method", "bisect", "--algebra", "raa"],
    ["@city", "--method", "bisect", "--algebra", "ia"],
    ["@city", "--method", "bisect", "--algebra", "raa"],
]


def latency_table():
    size = "64" if QUICK else "512"
    png = os.path.join(OUT, "latency.png")
    out = [machine_line(), f"Whole process, `isotrace render … --size {size} -o x.png`, two runs each: cold with "
           "`MESA_SHADER_CACHE_DISABLE=true`, warm after a run that filled the shader cache.", "",
           "| command | `auto` runs | cold | warm |", "|---|---|---:|---:|"]
    for args in LATENCY:
        cmd = ["render"] + args + ["--size", size, "-o", png]
        cold = [wall(cmd, env=cold_env())[0] for _ in range(2)]
        _, err = wall(cmd + ["--stats"])
        warm = [wall(cmd)[0] for _ in range(2)]
        field = re.search(r"\bfield (\w+)", err)
        method = "sphere traced" if "method sphere" in err else "bisection"
        out.append(f"| `isotrace render {' '.join(args)}` | {field.group(1) if field else '?'}, {method} | {secs(cold)} | {secs(warm)} |")
        print(f"latency {' '.join(args)}: {secs(cold)} / {secs(warm)}", file=sys.stderr)
    return "\n".join(out)


# --- splicing -------------------------------------------------------------------------------

def splice(text, name, table):
    pattern = re.compile(r"(<!-- benchmarks\.sh: " + re.escape(name) + r" -->\n).*?(\n<!-- benchmarks\.sh: end -->)", re.S)
    if not pattern.search(text):
        raise SystemExit(f"benchmarks: {DOC} has no '<!-- benchmarks.sh: {name} -->' block")
    return pattern.sub(lambda m: m.group(1) + table + m.group(2), text, count=1)


text = open(DOC).read()
raw = lambda f: os.path.join(OUT, f)
if "knoll" in ONLY and os.path.exists(raw("knoll.json")):
    text = splice(text, "knoll", knoll_table(raw("knoll.json")))
if "peer" in ONLY and os.path.exists(raw("peer-1024.txt")):
    text = splice(text, "peer", peer_table(raw("peer-1024.txt")))
if "scenes" in ONLY and os.path.exists(raw("scenes.json")):
    text = splice(text, "scenes", scenes_table(raw("scenes.json")))
if "scenes" in ONLY and os.path.exists(raw("scenes-peer.txt")):
    text = splice(text, "scenes-peer", scenes_peer_table(raw("scenes-peer.txt")))
if "scene-edit" in ONLY and os.path.exists(raw("scene-edit.txt")):
    text = splice(text, "scene-edit", scene_edit_table(raw("scene-edit.txt")))
if "big" in ONLY:
    text = splice(text, "big", big_table())
if "latency" in ONLY:
    text = splice(text, "latency", latency_table())
open(DOC, "w").write(text)
print(f"benchmarks: tables written to {DOC}", file=sys.stderr)
PY

# A full run also refreshes the raw data and figures the docs keep.
if [ "$quick" = 0 ]; then
    if wants knoll && [ -f "$out/knoll-images/contact-sheet.png" ]; then cp "$out/knoll-images/contact-sheet.png" docs/contact-sheet.png; fi
    if wants peer && [ -f "$out/peer-1024.txt" ]; then cp "$out/peer-1024.txt" docs/peer-1024.txt; fi
    if wants scenes && [ -f "$out/scenes.json" ]; then
        cp "$out/scenes.json" docs/scenes-1024.json
        if [ -f "$out/scenes-peer.txt" ]; then cp "$out/scenes-peer.txt" docs/scenes-1024-peer.txt; fi
        python3 scripts/plot-scenes.py docs/scenes-1024.json --peer docs/scenes-1024-peer.txt -o docs/scenes.svg
    fi
fi
