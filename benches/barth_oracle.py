#!/usr/bin/env python3
"""How few enclosures could ANY box-based inclusion method spend on the Barth decic?

Usage: python3 benches/barth_oracle.py RAA.exr IA.exr [--step 16]
  each EXR from: NODEVICE_SELECT=1 isotrace render @barth-decic --size 1024 --algebra raa|ia -o X.exr

Replays isotrace's per-pixel bisection (templates/traverse/bisect/cells.wgsl) with an
oracle in place of the enclosure, on every --step'th row and column of the image:
- segment oracle: a cell's enclosure of f (and of f's derivative along the ray) is
  taken as the range of samples on its segment (33 points, plus every point of a
  dense grid of 8 per eps along the ray that it covers): the best any enclosure over
  the segment itself (e.g. affine arithmetic along the ray) could do.
- box oracle: the same plus a 13x13x13 grid (--box-grid) over the axis-aligned box B
  of the cell's segment: the best any enclosure over B (interval arithmetic) could do.
Both signs among the samples: the range contains 0 (certain); one sign: taken to
exclude 0 (optimistic), so the counts are LOWER bounds, up to sampling. A cell is
rejected if f's range excludes 0; else if the derivative's excludes 0 (monotone) the
end values decide (sign change: hit, else reject); else it is bisected down to d_max;
a leaf is a hit if f changes sign in it or the next 16 cells, else it is skipped.
Each oracle is run from depth 0 over the whole clipped segment ('box', 'seg'), and
behind a model of isotrace's tile pass ('+tiles': 8x8-pixel tiles, 8 coarse then 64
fine depth slabs, each judged by the same oracle over the bounding box of the frustum
part (box) or over the frustum part itself (seg), 17^3 samples (--tile-grid); each
pixel pays its share of its tile's slab tests, then bisects its runs of candidate
slabs from depth 0 each), which is what the renderer's EXR 'evals' channel counts.
Naive bound: d_max + 1 a hit (d_max of the whole segment), 1 a miss.
Deterministic; needs numpy and OpenEXR/Imath, and barth_nodes.py next to it.
"""
import argparse, os, sys, time
import numpy as np
sys.dont_write_bytecode = True   # no __pycache__ next to barth_nodes.py
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import barth_nodes as bn   # PHI, EPS, FOV, camera(), clip_domain(), read_exr(), formula(), barth() (Jet)

NSEG, DENSE = 33, 8                   # samples per cell's segment; dense samples per eps of ray
CHUNK = 256                           # rays traversed together (memory of the dense samples)
LOOKAHEAD, SLABS, COARSE = 16, 64, 8  # as in kernel.wgsl / tiles.wgsl

class Dual:
    """Value v and derivative dv along one direction (forward mode)."""
    def __init__(s, v, dv): s.v, s.dv = v, dv
    def __add__(s, o): return Dual(s.v + o.v, s.dv + o.dv) if isinstance(o, Dual) else Dual(s.v + o, s.dv)
    __radd__ = __add__
    def __sub__(s, o): return s + (-1.0) * o
    def __mul__(s, o):
        if isinstance(o, Dual): return Dual(s.v * o.v, s.dv * o.v + s.v * o.dv)
        return Dual(s.v * o, s.dv * o)
    __rmul__ = __mul__

def f_val(p): return bn.formula(p[..., 0], p[..., 1], p[..., 2])
def f_dir(p, u):
    """f and its derivative along u at points p (..., 3)."""
    r = bn.formula(*(Dual(p[..., c], np.broadcast_to(u[..., c], p.shape[:-1])) for c in range(3)))
    return r.v, r.dv

def brackets(f0, f1): return ((f0 <= 0) & (f1 >= 0)) | ((f0 >= 0) & (f1 <= 0))
def depth_for(length): return np.clip(np.ceil(np.log2(np.maximum(length, 1e-300) / bn.EPS)), 0, 18).astype(np.int64)

def grid(n): return np.stack(np.meshgrid(*[np.linspace(0, 1, n)] * 3, indexing='ij'), -1).reshape(-1, 3)
SEG = np.linspace(0, 1, NSEG)

def cell_samples(eye, u, a, b, box):
    """f and its derivative along u at the segment's points (first NSEG columns: the
    ends are columns 0 and NSEG-1), then, if box (a grid(n)), on that grid over the
    segment's bounding box."""
    pts = eye + (a[:, None] + (b - a)[:, None] * SEG)[..., None] * u[:, None, :]
    if box is not None:
        lo, hi = np.minimum(pts[:, 0], pts[:, -1]), np.maximum(pts[:, 0], pts[:, -1])
        pts = np.concatenate([pts, lo[:, None] + (hi - lo)[:, None] * box], 1)
    return f_dir(pts, u[:, None, :])

def traverse(eye, u, t0, t1, runs, box):
    """Stackless depth-first bisection of each ray's runs (list of (lo, hi) in t, nearest
    first) under the oracle, CHUNK rays at a time in lockstep. Returns cells visited, hit
    flag, hit depth, and the number of leaves without a sign change (skipped)."""
    out = [traverse_chunk(eye, u[c:c + CHUNK], t0[c:c + CHUNK], t1[c:c + CHUNK], runs[c:c + CHUNK], box)
           for c in range(0, len(u), CHUNK)]
    return [np.concatenate(x) for x in zip(*out)]

def traverse_chunk(eye, u, t0, t1, runs, box):
    n = len(u)
    # Dense samples of f and its ray derivative along the whole clipped ray, DENSE per
    # eps: every cell's segment samples include those it covers, so a thin feature on a
    # long cell is not missed (33 points alone lost ~7% of the hits on coarse cells).
    H = bn.EPS / DENSE
    nd = np.ceil((t1 - t0) / H).astype(int) + 1
    N = nd.max()
    tj = np.minimum(t0[:, None] + np.minimum(np.arange(N), nd[:, None] - 1) * H, t1[:, None])
    Fd, Dd = (np.append(x.ravel(), 0.0) for x in f_dir(eye + tj[..., None] * u[:, None, :], u[:, None, :]))
    evals, hit, t_hit, nosign = np.zeros(n), np.zeros(n, bool), np.full(n, np.inf), np.zeros(n, int)
    nxt = np.zeros(n, int)                                   # index of the next run
    s_lo, ln, dmax = np.zeros(n), np.zeros(n), np.zeros(n, np.int64)
    d, k = np.zeros(n, np.int64), np.zeros(n, np.int64)
    active = np.zeros(n, bool)
    bra, brb = np.zeros(n), np.zeros(n)                      # the hit's bracket

    def start_next(idx):                                     # on to each ray's next run, if any
        for r in idx:
            if nxt[r] < len(runs[r]):
                lo, hi = runs[r][nxt[r]]; nxt[r] += 1
                s_lo[r], ln[r], dmax[r], d[r], k[r], active[r] = lo, hi - lo, depth_for(hi - lo), 0, 0, True
            else:
                active[r] = False
    start_next(range(n))
    while active.any():
        i = np.flatnonzero(active)
        w = ln[i] / 2.0 ** d[i]
        a = s_lo[i] + k[i] * w
        b = a + w
        f, D = cell_samples(eye, u[i], a, b, box)
        ia = np.clip(np.floor((a - t0[i]) / H).astype(int), 0, nd[i] - 1)
        ib = np.clip(np.ceil((b - t0[i]) / H).astype(int), 0, nd[i] - 1)
        se = np.stack([i * N + ia, i * N + ib + 1], 1).ravel()   # dense samples [ia, ib]
        red = lambda op, x: op.reduceat(x, se)[0::2]
        evals[i] += 1
        fmin, fmax = np.minimum(f.min(1), red(np.minimum, Fd)), np.maximum(f.max(1), red(np.maximum, Fd))
        Dmin, Dmax = np.minimum(D.min(1), red(np.minimum, Dd)), np.maximum(D.max(1), red(np.maximum, Dd))
        contains = (fmin <= 0) & (fmax >= 0)                   # oracle: range of f holds 0
        mono = (Dmin > 0) | (Dmax < 0)                         # oracle: derivative excludes 0
        found = contains & mono & brackets(f[:, 0], f[:, NSEG - 1])
        ga, gb = a.copy(), b.copy()
        descend = contains & ~mono & (d[i] < dmax[i])
        leaf = contains & ~mono & (d[i] >= dmax[i])
        if leaf.any():                                       # leaf: sign change in it or the
            j = np.flatnonzero(leaf)                         # next LOOKAHEAD cells (to t1)?
            ts = np.minimum(a[j, None] + w[j, None] * np.arange(LOOKAHEAD + 2), t1[i[j], None])
            fs = f_val(eye + ts[..., None] * u[i[j], None, :])
            sc = brackets(fs[:, :-1], fs[:, 1:])
            ok = sc.any(1)
            first = sc.argmax(1)
            r = np.arange(len(j))
            found[j] = ok
            ga[j], gb[j] = ts[r, first], ts[r, first + 1]
            nosign[i[j[~ok]]] += 1
        h = i[found]
        hit[h], bra[h], brb[h], active[h] = True, ga[found], gb[found], False
        dn = i[descend]
        d[dn] += 1; k[dn] *= 2
        rj = i[~found & ~descend]                            # rejected: climb finished levels
        up = np.log2((k[rj] + 1) & -(k[rj] + 1)).astype(np.int64)   # trailing one bits of k
        go = up < d[rj]
        d[rj[go]] -= up[go]
        k[rj[go]] = (k[rj[go]] >> up[go]) + 1
        start_next(rj[~go])
    h = np.flatnonzero(hit)                                  # root by bisection (not counted)
    fa = f_val(eye + bra[h, None] * u[h])
    for _ in range(40):
        m = 0.5 * (bra[h] + brb[h])
        fm = f_val(eye + m[:, None] * u[h])
        same = (fa <= 0) == (fm <= 0)
        bra[h] = np.where(same, m, bra[h]); fa = np.where(same, fm, fa)
        brb[h] = np.where(same, brb[h], m)
    t_hit[h] = 0.5 * (bra[h] + brb[h])
    return evals, hit, t_hit, nosign

def frame(w, h):
    """Camera frame as in barth_nodes.camera: eye, forward, right, up, tan(fov/2)."""
    eye, _ = bn.camera(w, h)
    fwd = -eye / np.linalg.norm(eye)
    right = np.cross(fwd, [0, 0, 1.0]); right /= np.linalg.norm(right)
    return eye, fwd, right, np.cross(right, fwd), np.tan(np.radians(bn.FOV) / 2)

def tile_pass(pix, w, h, box, ntile):
    """Model of tiles.wgsl under the oracle for the tiles of pixels pix (N, 2: row, col):
    per pixel its candidate slab mask (N, 64) in forward depth s, the slab edges, and
    its tile's number n of slab tests."""
    eye, fwd, right, up, th = frame(w, h)
    corners = np.stack(np.meshgrid(*[[bn.LO, bn.HI]] * 3, indexing='ij'), -1).reshape(-1, 3)
    cs = (corners - eye) @ fwd
    sc = -eye @ fwd                                          # depth of the ball's centre
    dlo, dhi = max(cs.min(), sc - bn.RADIUS), min(cs.max(), sc + bn.RADIUS)
    dlo = max(dlo, 1e-6 * max(dhi, 1.0))
    edges = dlo + (dhi - dlo) * np.arange(SLABS + 1) / SLABS
    sx = lambda c: ((c + 0.5) / w * 2 - 1) * th * w / h
    sy = lambda r: (1 - (r + 0.5) / h * 2) * th
    tiles, inv = np.unique(pix // 8, axis=0, return_inverse=True)
    inv = inv.ravel()
    t_lo, t_hi = tiles * 8, np.minimum(tiles * 8 + 7, [h - 1, w - 1])
    su = np.stack([sx(t_lo[:, 1]), sx(t_hi[:, 1])], 1)
    sv = np.stack([sy(t_hi[:, 0]), sy(t_lo[:, 0])], 1)
    g = np.linspace(0, 1, ntile)
    gs, gu, gv = (c.ravel() for c in np.meshgrid(g, g, g, indexing='ij'))

    def hold(s0, s1):                                        # slab [s0, s1] of every tile
        S = np.stack([np.full(len(tiles), s0), np.full(len(tiles), s1)], 1)
        cor = (eye + S[:, :, None, None, None] * (fwd + su[:, None, :, None, None] * right
               + sv[:, None, None, :, None] * up)).reshape(len(tiles), 8, 3)
        lo, hi = cor.min(1), cor.max(1)
        pad = 1e-6 * (bn.HI - bn.LO)
        gap = np.maximum(np.maximum(lo, -hi), 0)             # ball centred at the origin
        meets = (lo <= bn.HI + pad).all(1) & (hi >= bn.LO - pad).all(1) & \
                (np.linalg.norm(gap, axis=1) <= bn.RADIUS * (1 + 1e-6) + 1e-6 * bn.DIAG)
        if box:                                              # grid over the bounding box
            pts = lo[:, None] + (hi - lo)[:, None] * np.stack([gs, gu, gv], 1)
        else:                                                # grid over the frustum part
            S_ = s0 + (s1 - s0) * gs
            U = su[:, :1] + (su[:, 1:] - su[:, :1]) * gu
            V = sv[:, :1] + (sv[:, 1:] - sv[:, :1]) * gv
            pts = eye + S_[None, :, None] * (fwd + U[..., None] * right + V[..., None] * up)
        f = f_val(pts)
        return meets & (f.min(1) <= 0) & (f.max(1) >= 0)
    coarse = np.stack([hold(edges[8 * c], edges[8 * c + 8]) for c in range(COARSE)], 1)
    fine = np.stack([hold(edges[j], edges[j + 1]) for j in range(SLABS)], 1) & np.repeat(coarse, 8, 1)
    n = COARSE + 8 * coarse.sum(1)
    return fine[inv], edges, n[inv]

def slab_runs(mask, edges, t0, t1, scale):
    """Runs of consecutive candidate slabs, clipped to the ray's [t0, t1] (t = s * scale)."""
    runs, k = [], 0
    while k < SLABS:
        if not mask[k]: k += 1; continue
        e = k
        while e < SLABS and mask[e]: e += 1
        lo, hi = max(t0, edges[k] * scale), min(t1, edges[e] * scale)
        if lo < hi: runs.append((lo, hi))
        k = e
    return runs

def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('raa'); ap.add_argument('ia')
    ap.add_argument('--step', type=int, default=16, help='every STEP-th row and column (default 16)')
    ap.add_argument('--box-grid', type=int, default=13, help='box oracle: grid side over a cell\'s box (default 13)')
    ap.add_argument('--tile-grid', type=int, default=17, help='tile pass: grid side over a slab (default 17)')
    args = ap.parse_args()
    t_start = time.time()
    # Check the Dual derivative against barth_nodes' Jet (value, gradient . u).
    p = np.random.default_rng(1).uniform(-2, 2, (50, 3)); uu = p[::-1] / np.linalg.norm(p, axis=1, keepdims=True)
    v, dv = f_dir(p, uu); jet = bn.barth(p)
    assert np.allclose(v, jet.v, rtol=1e-9, atol=1e-9) and np.allclose(dv, (jet.g * uu).sum(1), rtol=1e-8, atol=1e-8)

    ev_raa, Z_raa, w, h = bn.read_exr(args.raa)
    ev_ia, Z_ia, w2, h2 = bn.read_exr(args.ia)
    assert (w, h) == (w2, h2)
    eye, dirs = bn.camera(w, h)
    rows, cols = np.meshgrid(np.arange(args.step // 2, h, args.step), np.arange(args.step // 2, w, args.step), indexing='ij')
    pix = np.stack([rows.ravel(), cols.ravel()], 1)
    u = dirs[pix[:, 0], pix[:, 1]]
    t0, t1 = bn.clip_domain(eye, u)
    inside = t0 < t1
    sel = lambda a: a[pix[:, 0], pix[:, 1]]
    ev = {'RAA': sel(ev_raa), 'IA': sel(ev_ia)}
    Z = {'RAA': sel(Z_raa), 'IA': sel(Z_ia)}
    hit_r, hit_i = Z['RAA'] < 1e30, Z['IA'] < 1e30
    naive = np.where(hit_r, depth_for(np.where(inside, t1 - t0, 0)) + 1, 1).astype(float)
    print(f'image {w}x{h}, every {args.step}th row/col from {args.step // 2}: {len(pix)} pixels, '
          f'{inside.sum()} cross the domain, {hit_r.sum()} RAA hits, {hit_i.sum()} IA hits; eps {bn.EPS:.4g}')

    # isotrace hands out a tile's n slab tests as whole evaluations: n // 64 to every
    # pixel, one more to lanes li < n % 64; in a queued tile pixel tile_pixel(li) = local
    # (x, y) has li = 8 b + 4 (y % 2) + x % 4, b = 2 (y // 2) + x // 4 (pixels.wgsl), in a
    # tile without candidate slabs li = 8 y + x (tiles.wgsl).
    lx, ly = pix[:, 1] % 8, pix[:, 0] % 8
    lane = 8 * (2 * (ly // 2) + lx // 4) + 4 * (ly % 2) + lx % 4, 8 * ly + lx
    res, shares = {}, {}
    ii = np.flatnonzero(inside)
    _, fwd, _, _, _ = frame(w, h)
    scale = 1.0 / (u @ fwd)                                   # t (world) per unit of depth s
    for box in (True, False):
        name, g = ('box', grid(args.box_grid)) if box else ('seg', None)
        tic = time.time()
        e, hh, th_, ns = traverse(eye, u[ii], t0[ii], t1[ii], [[(t0[r], t1[r])] for r in ii], g)
        res[name] = (e, hh, th_, ns, time.time() - tic)
        tic = time.time()
        mask, edges, n = tile_pass(pix[ii], w, h, box, args.tile_grid)
        share = n // 64 + (np.where(mask.any(1), lane[0][ii], lane[1][ii]) < n % 64)   # tile_share
        shares[name] = (share.mean(), (n / 64).mean())
        runs = [slab_runs(mask[j], edges, t0[r], t1[r], scale[r]) for j, r in enumerate(ii)]
        e, hh, th_, ns = traverse(eye, u[ii], t0[ii], t1[ii], runs, g)
        res[name + '+tiles'] = (e + share, hh, th_, ns, time.time() - tic)

    cols_ = ['naive', 'box', 'seg', 'box+tiles', 'seg+tiles', 'RAA', 'IA']
    val = {'naive': naive[ii], 'RAA': ev['RAA'][ii], 'IA': ev['IA'][ii]}
    val.update({k: r[0] for k, r in res.items()})
    hr = hit_r[ii]
    print('\nmean evaluations per pixel (hit/miss by the RAA render; ratios to the naive bound)')
    print(f'{"":22s}' + ''.join(f'{c:>10s}' for c in cols_) + '   ' + ''.join(f'{c + "/nv":>13s}' for c in cols_[1:]))
    for lab, m in (('hits', hr), ('misses (in domain)', ~hr), ('all in domain', np.ones_like(hr))):
        mean = {c: val[c][m].mean() for c in cols_}
        print(f'{lab:18s}{m.sum():4d}' + ''.join(f'{mean[c]:10.2f}' for c in cols_) + '   '
              + ''.join(f'{mean[c] / mean["naive"]:13.3f}' for c in cols_[1:]))
    out = ~inside
    print(f'outside the domain: {out.sum()} px: naive 1, oracles 0 per ray (+tiles: not modelled), '
          f'RAA {ev["RAA"][out].mean():.3f}, IA {ev["IA"][out].mean():.3f} (tile-pass share)')
    print('tile-pass share per sampled pixel in the domain (as isotrace hands it out | fair n/64): '
          + ', '.join(f'{k} {a:.3f} | {b:.3f}' for k, (a, b) in shares.items()))
    print('\noracle vs render on the pixels crossing the domain (hits; depth agreement within 2 eps on common hits)')
    for k, (e, hh, th_, ns, sec) in res.items():
        for rn, hrr in (('RAA', hit_r[ii]), ('IA', hit_i[ii])):
            both = hh & hrr
            dz = np.abs(th_[both] - Z[rn][ii][both])
            print(f'  {k:10s} vs {rn:3s}: hit/miss agree {np.mean(hh == hrr):7.2%}  (oracle-only hits {np.sum(hh & ~hrr)}, '
                  f'render-only {np.sum(~hh & hrr)});  depth within 2 eps {np.mean(dz < 2 * bn.EPS):7.2%}')
        print(f'  {k:10s}: hits {hh.sum()}, leaves without a sign change (skipped) {ns.sum()} on {np.sum(ns > 0)} rays, '
              f'max evals {e.max():.0f}, {sec:.1f} s')
    print(f'\nruntime {time.time() - t_start:.1f} s')

if __name__ == '__main__':
    main()
