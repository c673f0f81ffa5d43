// Per-tile term lists of a compiled field's rerolled min and max loops
// (spliced after the compiled field of a bisection kernel whose formula
// has such a loop; src/field/compiled/term_loops/lists.rs).
//
// A union of a thousand distances, bisected, evaluated all thousand in
// every cell of every ray, though near any one tile only a few can be the
// least. The tile pass already encloses f over each 8x8 tile's candidate
// depth slabs; while it encloses a fine slab, a second pass after the loop
// notes each term whose enclosure there reaches below the loop's upper
// bound (for max: above its lower bound), and the notes of the slabs that
// may hold the surface are gathered for the tile (field_slab_end). The
// per-pixel pass runs, for the rays of the tile and inside its candidate
// slabs, only the noted terms (field_in_tile), and so does the hit's
// gradient; shadows and reflections leave them (field_leave_frustum).
//
// Exact: a term left out lies above (below) another term everywhere in
// the candidate slabs, so there the min (max) of the kept terms is the
// same function, and its enclosures enclose it. The slabs' boxes are
// padded by twice the gradient's step (compiled::enclosures), so the
// gradient's stencil around a hit lies inside them. Only loops whose terms
// cannot make f undefined are listed (their square roots take arguments
// that are never negative by their form), so no emptiness is lost.
//
// The tile pass lists terms for itself too: the notes of a coarse slab
// that may hold the surface are the terms its eight fine slabs run (the
// fine slabs' boxes lie inside the coarse slab's), so only the coarse
// slabs' enclosures run the whole loops. (This kernel has no block pass:
// the tile pass calls field_slab_begin(false) for a coarse slab, (true)
// for a fine one.)
//
// loop_lists (field group): per tile, LOOP_TILE_WORDS words: the loop iterations its
// lists cost, the tile's bits (LOOP_BITS words: bit k of a loop's words is
// its term k), the bits of the fine slab being enclosed, and those of its
// coarse slab.
// loop_counts (field group): counts for the statistics (render::LoopListStats), zeroed before each
// dispatch: tiles with candidate slabs, tiles that run their lists, terms
// those keep and terms the loops have, summed over them.
struct LoopListCounts { tiles: atomic<u32>, listed: atomic<u32>, kept: atomic<u32>, whole: atomic<u32> }

// The tile's first word in the tile pass.
var<private> g_loop_base: u32;
// The tile pass notes terms over the slab being enclosed.
var<private> g_loop_record: bool;
// An enclosure was refused at the work limit while noting: the tile's
// notes are incomplete, so it runs the whole loops.
var<private> g_loop_spoiled: bool;
// The per-pixel pass: the tile's lists (tile + 1; 0 none) and the lists the
// evaluations run now (0 outside the candidate slabs; in the tile pass, 1
// while a fine slab runs its coarse slab's list).
var<private> g_loop_tile: u32;
var<private> g_loop_list: u32;
// The first word of the bits the listed loops run, and of those loop_note
// writes.
var<private> g_loop_at: u32;
var<private> g_loop_note_at: u32;

fn loop_lists_on() -> bool { return (F.flags & FLAG_NO_TAPE_SHORTENING) == 0u; }

fn field_tile_begin(t: u32, tile: vec2<u32>, block: bool) -> vec3<u32> {
    g_loop_base = t * LOOP_TILE_WORDS;
    g_loop_spoiled = false;
    if (loop_lists_on()) {
        for (var i = 0u; i < LOOP_BITS; i = i + 1u) { loop_lists[g_loop_base + 1u + i] = 0u; }
    }
    return vec3<u32>(0xffffffffu, 0xffffffffu, 0u);
}

// `fine`: a fine slab, which runs its coarse slab's list (unless a noting
// enclosure was refused: then that list may be short) and notes into the
// slab's bits; else a coarse slab, which runs the whole loops and notes
// into the coarse bits.
fn field_slab_begin(fine: bool) {
    g_loop_list = 0u;
    g_loop_record = loop_lists_on();
    if (!g_loop_record) { return; }
    let coarse = g_loop_base + 1u + 2u * LOOP_BITS;
    g_loop_note_at = select(coarse, g_loop_base + 1u + LOOP_BITS, fine);
    if (fine && !g_loop_spoiled) {
        g_loop_list = 1u;
        g_loop_at = coarse;
    }
    for (var i = 0u; i < LOOP_BITS; i = i + 1u) { loop_lists[g_loop_note_at + i] = 0u; }
}

// A fine slab that may hold the surface adds its notes to the tile's.
fn field_slab_end(hold: bool) {
    if (g_loop_record && hold && g_loop_note_at == g_loop_base + 1u + LOOP_BITS) {
        let tile = g_loop_base + 1u;
        for (var i = 0u; i < LOOP_BITS; i = i + 1u) { loop_lists[tile + i] = loop_lists[tile + i] | loop_lists[tile + LOOP_BITS + i]; }
    }
    g_loop_record = false;
    g_loop_list = 0u;
}

// Term `bit` may be its loop's result in the slab being enclosed.
fn loop_note(bit: u32) {
    let i = g_loop_note_at + (bit >> 5u);
    loop_lists[i] = loop_lists[i] | (1u << (bit & 31u));
}

// The tile's lists (its index + 1), with the loop iterations they cost in
// its first word; 0 (the whole loops) when lists are off, a noting
// enclosure was refused, or the lists would cost more iterations.
fn field_tile_done(mask: vec2<u32>, n: u32, block: bool) -> u32 {
    atomicAdd(&loop_counts.tiles, 1u);
    if (!loop_lists_on() || g_loop_spoiled) { return 0u; }
    var kept = 0u;
    for (var i = 0u; i < LOOP_BITS; i = i + 1u) { kept = kept + countOneBits(loop_lists[g_loop_base + 1u + i]); }
    // An iteration a kept term, and one a word of bits: a list that costs
    // more than twice the iterations of the whole loops (a few terms an
    // iteration) would spend lavapipe's loop cap sooner, for little time
    // saved. A large tile near a union of 420 shapes kept 306 of 408
    // terms, three times the whole loops' iterations, and 7 of 1,024
    // pixels ran out of them.
    if (kept + LOOP_BITS > 2u * LOOP_FALLBACK_ITERATIONS) { return 0u; }
    loop_lists[g_loop_base] = kept + LOOP_BITS;
    atomicAdd(&loop_counts.listed, 1u);
    atomicAdd(&loop_counts.kept, kept);
    atomicAdd(&loop_counts.whole, LOOP_TERMS);
    return g_loop_base / LOOP_TILE_WORDS + 1u;
}

// The rays of a tile run its lists ...
fn field_enter_tile(list: u32) {
    g_loop_tile = list;
    g_loop_list = list;
    g_loop_at = max(list, 1u) * LOOP_TILE_WORDS - LOOP_TILE_WORDS + 1u;
}
// ... at points inside its candidate slabs (a look-ahead past the run's end
// is not; the hit's gradient stencil is: the slabs were padded for it) ...
fn field_in_tile(inside: bool) { g_loop_list = select(0u, g_loop_tile, inside); }
// ... until they leave them for good.
fn field_leave_frustum() {
    g_loop_tile = 0u;
    g_loop_list = 0u;
}

// The loop iterations of an evaluation whose listed loops take `whole`
// run whole and `fallback` in the per-pixel pass's whole loops (fewer
// terms an iteration): the tile's lists' cost in their place.
fn loop_work(whole: u32, fallback: u32) -> u32 {
    if (g_loop_list == 0u) { return whole - LOOP_WHOLE_ITERATIONS + fallback; }
    return whole - LOOP_WHOLE_ITERATIONS + loop_lists[(g_loop_list - 1u) * LOOP_TILE_WORDS];
}

// The first word of the bits of the lists being run.
fn loop_bits() -> u32 { return g_loop_at; }
