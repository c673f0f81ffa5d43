#!/usr/bin/env python3
"""Why bisection on the Barth decic costs more than issue 8's lower bound.

Usage: python3 benches/barth_nodes.py RENDER.exr [MORE.exr ...]
  each EXR from: NODEVICE_SELECT=1 isotrace render @barth-decic --size N --algebra raa|ia -o RENDER.exr --stats

1. Finds the nodes (f = 0, grad f = 0) of examples/barth-decic.iso in f64: Newton
   on grad f from a grid of starts, with an exact second-order jet, then closes the
   set under the icosahedral symmetry as a check.
2. Rebuilds isotrace's default camera (azimuth 35, elevation 25, fov 40, box
   [-2,2]^3 clipped to the ball of radius 2) and checks it against the EXR depth.
3. Per pixel: delta = distance from the traversed part of its ray to the nearest
   node, the lower bound (hit: d_ray + 1, miss: 1) and the excess evals - bound;
   tables per log2 bin of delta, shares of the excess near nodes, a log fit and a
   counterfactual ratio. Needs only numpy and OpenEXR/Imath.
"""
import sys
import numpy as np
import OpenEXR, Imath

PHI = (1 + 5 ** 0.5) / 2
LO, HI, RADIUS = -2.0, 2.0, 2.0           # domain: box [-2,2]^3 and ball of radius 2
DIAG = (HI - LO) * 3 ** 0.5                # box diagonal
EPS = DIAG * 2.0 ** -11                    # isotrace's eps cell
FOV = 40.0

class Jet:
    """Value v (N), gradient g (N,3) and Hessian h (N,3,3) at N points."""
    def __init__(s, v, g, h): s.v, s.g, s.h = v, g, h

    @staticmethod
    def var(p, k):
        g = np.zeros(p.shape); g[:, k] = 1
        return Jet(p[:, k].copy(), g, np.zeros(p.shape + (3,)))

    def __add__(s, o):
        if not isinstance(o, Jet): return Jet(s.v + o, s.g, s.h)
        return Jet(s.v + o.v, s.g + o.g, s.h + o.h)
    __radd__ = __add__
    def __sub__(s, o): return s + (-1.0) * o
    def __mul__(s, o):
        if not isinstance(o, Jet): return Jet(s.v * o, s.g * o, s.h * o)
        gg = s.g[:, :, None] * o.g[:, None, :]
        return Jet(s.v * o.v, s.g * o.v[:, None] + o.g * s.v[:, None],
                   s.h * o.v[:, None, None] + o.h * s.v[:, None, None] + gg + gg.transpose(0, 2, 1))
    __rmul__ = __mul__

def formula(x, y, z):
    """The formula of examples/barth-decic.iso, for floats, arrays, Jets or
    any number type with +, - and * (barth_oracle.py passes its Duals)."""
    x2, y2, z2 = x * x, y * y, z * z
    p4 = PHI ** 4
    r2 = x2 + y2 + z2
    q = x2 * x2 + y2 * y2 + z2 * z2 - 2 * (x2 * y2 + x2 * z2 + y2 * z2)
    a = (r2 - 1) * (r2 - (2 - PHI))
    return 8 * (x2 - p4 * y2) * (y2 - p4 * z2) * (z2 - p4 * x2) * q + (3 + 5 * PHI) * a * a

def barth(p):
    """The formula as a Jet at points p (N,3)."""
    return formula(*(Jet.var(p, k) for k in range(3)))

def rotation(axis, angle):
    a = np.asarray(axis, float) / np.linalg.norm(axis)
    k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k

# Generators of the symmetry group of f (order 120): a 5-fold turn about (0, phi, 1),
# the cyclic permutation of x, y, z and a mirror (f is even in each coordinate).
GENERATORS = [rotation((0, PHI, 1), 2 * np.pi / 5),
              np.array([[0., 1, 0], [0, 0, 1], [1, 0, 0]]), np.diag([-1., 1, 1])]

def dedup(pts, tol=1e-7):
    keep = []
    for q in pts[np.lexsort(pts.T[::-1])]:
        if not keep or np.min(np.linalg.norm(np.array(keep) - q, axis=1)) > tol:
            keep.append(q)
    return np.array(keep)

def find_nodes(n=25, iters=60):
    """Critical points of f by damped Newton from an n^3 grid on [-2.5,2.5]^3;
    the nodes are those with f = 0. Deterministic (no random starts)."""
    g1 = np.linspace(-2.5, 2.5, n) + 1e-3     # offset: avoid starting on the mirror planes
    p = np.stack(np.meshgrid(g1, g1 * 0.999, g1 * 1.001, indexing='ij'), -1).reshape(-1, 3)
    for _ in range(iters):
        j = barth(p)
        step = np.linalg.solve(j.h + 1e-14 * np.eye(3), j.g[..., None])[..., 0]
        size = np.linalg.norm(step, axis=1, keepdims=True)
        p = p - step * np.minimum(1, 0.5 / np.maximum(size, 1e-300))   # at most 0.5 a step
        p = np.where(np.abs(p) < 10, p, 0)
    j = barth(p)
    crit = dedup(p[np.linalg.norm(j.g, axis=1) < 1e-8])
    found = crit[np.abs(barth(crit).v) < 1e-8]
    # Symmetry check: every image of a node under a generator must be a node;
    # closing the set under the group also adds any orbit member Newton missed.
    nodes = found
    while True:
        imgs = np.concatenate([nodes] + [nodes @ g.T for g in GENERATORS])
        new = dedup(imgs)
        if len(new) == len(nodes): break
        nodes = new
    jn = barth(nodes)
    assert np.abs(jn.v).max() < 1e-8 and np.linalg.norm(jn.g, axis=1).max() < 1e-8
    return nodes, len(crit), len(found), np.linalg.eigvalsh(jn.h)

def camera(w, h):
    """isotrace's default view of the box: eye, unit ray directions (h, w, 3)."""
    az, el = np.radians(35.0), np.radians(25.0)
    half_v = np.radians(FOV) / 2
    half_h = np.arctan(np.tan(half_v) * w / h)
    radius = 0.5 * DIAG
    eye = np.array([np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el)]) * radius / np.sin(min(half_v, half_h)) * 1.02
    fwd = -eye / np.linalg.norm(eye)
    right = np.cross(fwd, [0, 0, 1.0]); right /= np.linalg.norm(right)
    up = np.cross(right, fwd)
    sx = ((np.arange(w) + 0.5) / w * 2 - 1) * np.tan(half_v) * w / h
    sy = (1 - (np.arange(h) + 0.5) / h * 2) * np.tan(half_v)
    d = fwd + sx[None, :, None] * right + sy[:, None, None] * up
    return eye, d / np.linalg.norm(d, axis=2, keepdims=True)

def clip_domain(eye, d):
    """Entry/exit distances of unit rays d through box and ball (t0 >= t1: misses)."""
    with np.errstate(divide='ignore', invalid='ignore'):
        a, b = (LO - eye) / d, (HI - eye) / d
    t0 = np.maximum(np.minimum(a, b).max(-1), 0)
    t1 = np.maximum(a, b).min(-1)
    bb = d @ eye
    disc = bb * bb - (eye @ eye - RADIUS ** 2)
    q = np.sqrt(np.maximum(disc, 0))
    t0, t1 = np.maximum(t0, -bb - q), np.minimum(t1, -bb + q)
    return t0, np.where(disc < 0, -1.0, t1)

def read_exr(path):
    f = OpenEXR.InputFile(path)
    dw = f.header()['dataWindow']
    w, h = dw.max.x - dw.min.x + 1, dw.max.y - dw.min.y + 1
    ch = lambda c: np.frombuffer(f.channel(c, Imath.PixelType(Imath.PixelType.FLOAT)), np.float32).reshape(h, w).astype(float)
    return ch('evals'), ch('Z'), w, h

def ray_node_distance(eye, d, t0, t1, nodes, chunk=1 << 15):
    """Per ray: distance from the segment eye + t d, t in [t0, t1], to the nearest node,
    and the depth t of the closest point."""
    e2n = nodes - eye
    n2 = (e2n * e2n).sum(1)
    dist, depth = np.full(len(d), np.inf), np.full(len(d), np.nan)
    for s in range(0, len(d), chunk):
        sl = slice(s, s + chunk)
        proj = d[sl] @ e2n.T
        t = np.clip(proj, t0[sl, None], t1[sl, None])
        d2 = n2 - 2 * t * proj + t * t
        k = np.argmin(d2, axis=1)
        r = np.arange(len(k))
        dist[sl], depth[sl] = np.sqrt(np.maximum(d2[r, k], 0)), t[r, k]
    return dist, depth

def analyse(path, nodes):
    evals, Z, w, h = read_exr(path)
    eye, dirs = camera(w, h)
    hit = Z < 1e30
    # Camera check: the distance estimate |f|/|grad f| at eye + Z d, in eps cells,
    # with this model and with the rows flipped.
    for name, dd in (('as modelled', dirs), ('rows flipped', dirs[::-1])):
        jt = barth(eye + Z[hit][:, None] * dd[hit])
        de = np.abs(jt.v) / np.linalg.norm(jt.g, axis=1) / EPS
        print(f'  camera {name:12s}: |f|/|grad f| at the EXR depth, in eps: median {np.median(de):.3g}  p99 {np.percentile(de, 99):.3g}')
    d, hit, evals, Z = dirs.reshape(-1, 3), hit.ravel(), evals.ravel(), Z.ravel()
    t0, t1 = clip_domain(eye, d)
    inside = t0 < t1
    seg = np.where(inside, t1 - t0, 0)
    d_ray = np.where(inside, np.clip(np.ceil(np.log2(np.maximum(seg, 1e-300) / EPS)), 0, 18), 0)
    bound = np.where(hit, d_ray + 1, 1)
    print(f'  pixels {w}x{h}: hits {hit.sum()}, misses through the domain {(inside & ~hit).sum()}; '
          f'evals mean {evals.mean():.3f}, bound mean {bound.mean():.3f}, ratio {evals.sum() / bound.sum():.3f}')
    # delta: only the part of the ray the traversal examines (up to one eps past a hit).
    tend = np.where(hit, np.minimum(t1, Z + EPS), t1)
    dist, depth = ray_node_distance(eye, d[inside], t0[inside], tend[inside], nodes)
    delta = np.full(len(d), np.inf); delta[inside] = dist / DIAG
    foot = np.full(len(d), np.inf)          # delta in pixel footprints at the node's depth
    foot[inside] = dist / (2 * np.tan(np.radians(FOV / 2)) * depth / h)
    ex = evals - bound

    print('  per bin of delta (box diagonals; footprint = px footprints at the node depth)')
    print('   delta bin        ~px | HITS   n   evals bound excess | MISSES(in domain) n evals excess')
    edges = np.concatenate([[0], 2.0 ** np.arange(-14, 1), [np.inf]])
    for lo_, hi_ in zip(edges[:-1], edges[1:]):
        b = inside & (delta >= lo_) & (delta < hi_)
        if not b.any(): continue
        bh, bm = b & hit, b & ~hit
        row = f'   [{lo_:7.1e},{hi_:7.1e}) {np.median(foot[b]):7.2f} |'
        row += f' {bh.sum():7d} {evals[bh].mean():6.2f} {bound[bh].mean():5.2f} {ex[bh].mean():6.2f} |' if bh.any() else ' ' * 30 + '|'
        row += f' {bm.sum():7d} {evals[bm].mean():6.2f} {ex[bm].mean():6.2f}' if bm.any() else ''
        print(row)
    out = ~inside
    print(f'   outside the domain: {out.sum()} px, evals mean {evals[out].mean():.3f} (tile-pass share), excess sum {ex[out].sum():.0f}')

    pos, net = np.maximum(ex, 0), np.where(inside, ex, 0)   # net: pixels in the domain only
    print(f'  in the domain alone: ratio {evals[inside].sum() / bound[inside].sum():.3f}; excess: hits {ex[hit].sum():.0f}, '
          f'misses {ex[inside & ~hit].sum():.0f}, outside the domain {ex[out].sum():.0f} (its bound 1 > its tile share)')
    print('  share of the excess from pixels within k footprints of a node (positive part / net over the domain):')
    for k in (1, 2, 4, 8, 16, 32, 64):
        m = foot <= k
        print(f'   k={k:3d}: {m.sum():7d} px ({m.sum() / inside.sum():6.1%} of the domain px)  '
              f'{pos[m].sum() / pos.sum():6.1%} / {net[m].sum() / net.sum():6.1%}  '
              f'[hits {pos[m & hit].sum() / pos.sum():5.1%}, misses {pos[m & ~hit].sum() / pos.sum():5.1%}]')

    # Fit excess = a + b log2(1/delta) where the node should dominate: 1 to 8 footprints
    # (below ~1 the eps cell caps the depth; beyond ~8 the rest of the surface takes over).
    print('  fit excess = a + b*log2(1/delta) over 1..8 footprints (per pixel; b also on half-octave bin means):')
    for name, m in (('hits', hit), ('misses', ~hit & inside)):
        sel = m & (foot >= 1) & (foot <= 8)
        x = np.log2(1 / delta[sel])
        b, a = np.polyfit(x, ex[sel], 1)
        lb = np.floor(2 * np.log2(foot[sel]))               # half-octave bins
        xb = np.array([x[lb == v].mean() for v in np.unique(lb)])
        yb = np.array([ex[sel][lb == v].mean() for v in np.unique(lb)])
        print(f'   {name:6s}: n={sel.sum():6d}  a={a:7.2f}  b={b:5.2f}  (bin means: b={np.polyfit(xb, yb, 1)[0]:5.2f})')

    print('  counterfactual ratio to the bound:')
    for k in (1, 2, 4, 8, 16):
        near = foot <= k
        only_near = np.where(near, evals, bound).sum() / bound.sum()
        no_near = np.where(near, bound, evals).sum() / bound.sum()
        print(f'   k={k:2d}: far pixels at their bound -> {only_near:.3f};  near pixels at their bound -> {no_near:.3f}')

    # Caveat check: a miss's cost follows its closest approach to the surface at least as
    # much as delta. Every 2nd row and column; |f|/|grad f| at 600 samples along the segment.
    sub = np.zeros((h, w), bool); sub[::2, ::2] = True
    ms = np.flatnonzero(sub.ravel() & inside & ~hit)
    near = np.full(len(ms), np.inf)
    s = np.linspace(0, 1, 600)
    for c in range(0, len(ms), 128):
        i = ms[c:c + 128]
        t = t0[i, None] + (t1 - t0)[i, None] * s
        jt = barth((eye + t[..., None] * d[i, None, :]).reshape(-1, 3))
        near[c:c + 128] = (np.abs(jt.v) / np.linalg.norm(jt.g, axis=1)).reshape(len(i), -1).min(1) / EPS
    print(f'  misses (every 2nd row/col, {len(ms)}): mean excess by closest approach to the surface '
          f'(|f|/|grad f| in eps), split by delta <=4 | 4..16 | >16 footprints:')
    for lo_, hi_ in ((0, 1), (1, 2), (2, 4), (4, 8), (8, 16), (16, 32), (32, np.inf)):
        r = (near >= lo_) & (near < hi_)
        cells = [f'{ex[ms][q].mean():5.1f} ({q.sum():5d})' if q.any() else ' ' * 13
                 for q in (r & (foot[ms] <= 4), r & (foot[ms] > 4) & (foot[ms] <= 16), r & (foot[ms] > 16))]
        print(f'   [{lo_:2},{hi_:4}) all {ex[ms][r].mean():5.1f} ({r.sum():5d}) | ' + ' | '.join(cells))

def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    nodes, ncrit, nfound, eig = find_nodes()
    r = np.linalg.norm(nodes, axis=1)
    print(f'critical points of f found: {ncrit}; nodes by Newton: {nfound}; after symmetry closure: {len(nodes)}')
    print(f'nodes in the ball of radius {RADIUS}: {(r <= RADIUS).sum()}; radii and counts:',
          dict(zip(*[a.tolist() for a in np.unique(np.round(r, 5), return_counts=True)])))
    print(f'Hessian at the nodes: signature (+,+,-) at {((eig > 0).sum(1) == 2).sum()}, min |eigenvalue| {np.abs(eig).min():.3f}')
    print('(the other 45 of the 345 lie at infinity: crossings of the 10 planes of the degree-10 part)')
    inside = nodes[(r <= RADIUS) & (np.abs(nodes) <= HI).all(1)]
    for path in sys.argv[1:]:
        print(f'\n== {path}')
        analyse(path, inside)

if __name__ == '__main__':
    main()
