// isotrace derivative helpers for the interval (ia_) and affine (ra_)
// domains: the pieces of forward-mode differentiation that are not plain
// arithmetic. The generated `evald_*` functions carry, for every node, an
// enclosure of its value and of its derivative along the ray (d/ds); the
// traversal uses the derivative to prove a cell monotone. Requires
// interval.wgsl (and affine.wgsl for the ra_ helpers).

// min(a, b)' is a' where a is certainly the smaller, b' where b is, else
// either (min is continuous, so the hull of both slopes bounds it).
// (The hull written out: hundreds of these in a big formula, and lavapipe
// clones every helper call before it simplifies.)
fn ia_dmin(a: vec2<f32>, b: vec2<f32>, da: vec2<f32>, db: vec2<f32>) -> vec2<f32> {
    return select(select(vec2<f32>(min(da.x, db.x), max(da.y, db.y)), db, b.y <= a.x), da, a.y <= b.x);
}
fn ia_dmax(a: vec2<f32>, b: vec2<f32>, da: vec2<f32>, db: vec2<f32>) -> vec2<f32> {
    return select(select(vec2<f32>(min(da.x, db.x), max(da.y, db.y)), db, b.x >= a.y), da, a.x >= b.y);
}
// |a|' for a value a with slope da: da where a >= 0 over the cell (|a| is
// a there), -da where a <= 0, and their hull where a takes both signs: what
// sign(a) · da gives (or tighter, where a's range ends at 0), without
// ia_mul's general case.
fn ia_dabs(a: vec2<f32>, da: vec2<f32>) -> vec2<f32> {
    let m = max(abs(da.x), abs(da.y));
    return select(select(vec2<f32>(-m, m), -da.yx, a.y <= 0.0), da, a.x >= 0.0);
}
// sign and floor are flat between jumps; a jump inside the range makes the
// function non-monotone in the worst way (it can cross 0 without a root of
// any continuous piece), so the slope is then the whole line.
fn ia_dsign(a: vec2<f32>, da: vec2<f32>) -> vec2<f32> {
    return select(ia_whole(), vec2<f32>(0.0), a.x > 0.0 || a.y < 0.0);
}
// pown(a, n)' / a' = n·a^(n−1) (0 for n = 0).
fn ia_dpown(a: vec2<f32>, n: vec2<f32>) -> vec2<f32> {
    return ia_scale(ia_pown(a, vec2<f32>(max(n.x - 1.0, 0.0))), n.x);
}
fn ia_dfloor(a: vec2<f32>, da: vec2<f32>) -> vec2<f32> {
    return select(ia_whole(), vec2<f32>(0.0), floor(a.x) == floor(a.y));
}
