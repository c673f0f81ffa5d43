//! The work budgets of the interpreted and looped fields under lavapipe's
//! silent loop cap: it stops any shader loop after 65,535 iterations,
//! counted across all loops of a SIMD bundle, and the code after the loop
//! runs as if it had ended. A field that loops (a tape's interpreter, a
//! compiled formula's loops over repeated terms) counts its own work and
//! gives up before the cap, so that a pixel it cannot finish is reported,
//! never drawn wrong.

/// Loop iterations the interpreter may spend in one invocation; past it an
/// evaluation gives up (enclosures become the whole line, the pixel is
/// reported unresolved). lavapipe's silent cap of 65,535 iterations counts
/// the loops of a SIMD bundle of 8 invocations together, and invocations
/// that diverge run the interpreter one after another (a tape of some
/// 18,000 instructions whose tile pass stopped at 2 evaluations per
/// invocation still had its loops cut and culled visible tiles). So each invocation
/// gets an eighth of what the traversal's budget (at most
/// [`TAPE_MAX_ITER`]) and its short loops leave: 8 × 5,500 + 16,000 +
/// slack < 65,535.
pub const TAPE_WORK_LIMIT: u32 = 5_500;
/// Loop iterations the interpreter may spend in one SIMD bundle of a kernel
/// that counts them per bundle ([`super::tape::features::BUNDLE_WORK`]): each run adds
/// the longest run of its active lanes plus one (the caller's loop
/// iteration), which is what the bundle's loops execute. The cap of 65,535
/// less the traversal's budget ([`TAPE_MAX_ITER`]) leaves 9,535 iterations
/// for the traversal's short loops.
pub const TAPE_BUNDLE_LIMIT: u32 = 40_000;
/// The work limit of bisection's tile pass (and the tape's block pass), per
/// SIMD bundle: they run no traversal, only their slab loop (at most 136
/// iterations), the notes' loops (at most 128 a slab) and list writing, so
/// they may go closer to lavapipe's cap than the per-pixel pass. A tape of
/// 2,975 value and 13,008 derivative instructions (four copies of `@city`'s
/// blocks) left 101 of 507 tiles and blocks unshortened at
/// [`TAPE_BUNDLE_LIMIT`].
pub const TAPE_TILE_PASS_BUNDLE_LIMIT: u32 = 54_000;
/// [`TAPE_TILE_PASS_BUNDLE_LIMIT`] counted per invocation (an eighth).
pub const TAPE_TILE_PASS_WORK_LIMIT: u32 = 6_750;
/// Largest bisection iteration budget with a tape field (see
/// [`TAPE_WORK_LIMIT`]).
pub const TAPE_MAX_ITER: u32 = 16_000;

/// The work limit counted per SIMD bundle with subgroup operations
/// ([`features::BUNDLE_WORK`]): what lavapipe's loop cap counts. A run's
/// loop executes as often as its longest active lane needs, so the bundle
/// adds that (plus the caller's iteration) to one count in workgroup
/// memory, kept by its lowest active lane. The slot is the smallest local index of the
/// bundle, taken at the entry point where every lane is active, so it
/// does not depend on how the driver groups lanes. Shared with a compiled
/// field's loops over repeated terms (`term_loops::support`).
pub(crate) const BUNDLE_WORK_WGSL: &str = "
// One count per bundle, indexed by its smallest local index: 256 covers the
// largest workgroup (bisection's main, 8 x 8 x 4).
var<workgroup> g_bundle_work: array<atomic<u32>, 256>;
var<private> g_bundle: u32;
var<private> g_lane: u32;
var<private> g_work_limit: u32 = TAPE_BUNDLE_LIMIT;
fn field_entry(li: u32) {
    g_lane = li;
    g_bundle = subgroupMin(li);
}
// Whether a run of `iters` loop iterations keeps the bundle within the
// limit (and counts it).
fn bundle_admits(iters: u32) -> bool {
    let m = subgroupMax(iters) + 1u;
    var before = 0u;
    // One active lane (the first) keeps the count.
    if (g_lane == subgroupBroadcastFirst(g_lane)) { before = atomicAdd(&g_bundle_work[g_bundle], m); }
    return subgroupMax(before) + m <= g_work_limit;
}
";

