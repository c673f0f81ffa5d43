// Per-tile tape shortening for bisection (spliced after the interpreters of
// a tape field whose tape has min or max; src/codegen/tape_field.rs).
//
// Most of a CSG formula is dead in any small region: a min's operand that
// lies above the other over the region never reaches the result, and nor
// does the subtree that computes it. The tile pass already encloses f over
// each 8x8 tile's candidate depth slabs; it encloses each fine slab that may
// hold the surface once more, and then every min and max notes in its
// choice slot which operand it can take there (tape_note_*).
// Once the tile's candidate slabs are known, a backward pass over each
// program keeps only the instructions whose results are read on the way to
// the outputs under those choices, and writes their list for the tile. The
// per-pixel pass runs the list instead of the tape for the rays of the
// tile, inside its candidate slabs only (field_leave_frustum before
// shading, shadows and reflections, which leave them).
//
// Exact, not approximate: the choices hold over every candidate slab of the
// tile, so inside them the shortened formula is the same function as f
// (where min(a, b) = a at every point, min(a, b) is a), and its enclosures
// are enclosures of f. They are not always the whole tape's: over a cell
// that spans several slabs, the interval of min(a, b) is the interval of a
// alone, where the whole tape's also takes b's interval in (with its
// derivative, the hull of both slopes). So a shortened tile rejects cells
// and proves monotony at least as often, in practice; the picture is the
// same surface to within eps (tests/tape.rs). Instructions that restrict
// the domain (sqrt, log, ...) are kept, so a tile's emptiness is decided as
// before, unless the tile pass saw
// the argument of a square root or logarithm stay in its domain over the
// tile's candidate slabs (then it cannot make f empty there).

// The tile's shortened programs: at word L - 4 of a list L the value
// program's (start, length) and the derivative program's, then the entries
// (pc | pick << 30, padded with TAPE_LIST_NOP to whole loop iterations).
@group(1) @binding(1) var<storage, read_write> tape_lists: array<u32>;
// The field group's counts, zeroed before the dispatch and read back for
// the statistics (render::TapeListStats): words of tape_lists in use, tiles
// with candidate slabs, tiles shortened, and the value instructions those
// keep and have in all.
struct TapeListCounts { used: atomic<u32>, tiles: atomic<u32>, shortened: atomic<u32>, kept: atomic<u32>, whole: atomic<u32> }
@group(1) @binding(4) var<storage, read_write> tape_counts: TapeListCounts;

// The choices noted over the tile's candidate slabs, two bits a slot (32
// words a tile; a storage buffer, not a private array: lavapipe compiles a
// dynamically indexed private array into code at every access, which cost
// the tile pass 0.5 s of compile).
@group(1) @binding(5) var<storage, read_write> tape_notes: array<u32>;
var<private> g_note_base: u32;

fn field_tile_begin(t: u32) {
    g_note_base = t * (TAPE_CHOICE_SLOTS / 16u);
    for (var i = 0u; i < TAPE_CHOICE_SLOTS / 16u; i = i + 1u) { tape_notes[g_note_base + i] = 0u; }
}

// Whether the field wants each fine slab that may hold the surface
// enclosed once more, noting its choices (the tile pass cannot know before
// the enclosure whether the slab holds, and only those that do count).
// A tape without choice slots (header word 2.z) has nothing to note.
fn field_records() -> bool { return (F.flags & FLAG_NO_TAPE_SHORTENING) == 0u && tape_word(2u).z > 0u; }

// Before a slab's enclosure: whether it is that second enclosure (the
// interpreter notes while this is set).
fn field_slab_begin(record: bool) { g_tape_record = record; }

fn tape_note_bits(slot: u32, c: u32) {
    let i = g_note_base + (slot >> 4u);
    tape_notes[i] = tape_notes[i] | (c << ((slot & 15u) * 2u));
}

// The bit of register r in a 64-register set (two words).
fn tape_reg_bit(r: u32) -> vec2<u32> {
    let i = r & TAPE_SLOT_MASK;
    return select(vec2<u32>(1u << (i & 31u), 0u), vec2<u32>(0u, 1u << (i & 31u)), i >= 32u);
}

// The two bits of choice slot `slot` over the tile's candidate slabs (0:
// never noted there).
fn tape_choice(slot: u32) -> u32 {
    return (tape_notes[g_note_base + (slot >> 4u)] >> ((slot & 15u) * 2u)) & 3u;
}

// Whether instruction w must run in the tile even when its result is dead:
// it restricts f's domain, and is not a square root or logarithm whose
// argument stays in its domain over the tile.
fn tape_restricts(w: vec4<u32>) -> bool {
    if ((w.x & TAPE_RESTRICTS) == 0u) { return false; }
    let code = w.x & 0xffu;
    return !((code == TAPE_SQRT || code == TAPE_LOG) && w.w < TAPE_CHOICE_SLOTS && tape_choice(w.w) == 1u);
}

// Which operand the tile's min or max instruction w takes (1 the first, 2
// the second) when only one can reach its result; 0 otherwise.
fn tape_pick(w: vec4<u32>) -> u32 {
    let code = w.x & 0xffu;
    if (!(code == TAPE_MIN || code == TAPE_MAX || code == TAPE_DMIN || code == TAPE_DMAX) || w.w >= TAPE_CHOICE_SLOTS) { return 0u; }
    let c = tape_choice(w.w);
    return select(0u, c, c == 1u || c == 2u);
}

// The registers instruction w reads when it takes operand `pick`.
fn tape_reads(w: vec4<u32>, pick: u32) -> vec2<u32> {
    let code = w.x & 0xffu;
    if (pick != 0u) { return tape_reg_bit(select(w.y, w.z, code >= TAPE_DMIN) >> select(0u, 16u, pick == 2u)); }
    let n = tape_arity(code);
    var m = vec2<u32>(0u);
    if (n >= 1u && (w.x & TAPE_IMM_A) == 0u) { m = m | tape_reg_bit(w.y); }
    if (n >= 2u && (w.x & TAPE_IMM_B) == 0u) { m = m | tape_reg_bit(w.y >> 16u); }
    if (n >= 3u) { m = m | tape_reg_bit(select(w.z, w.y >> 16u, (w.x & TAPE_IMM_B) != 0u)); }
    if (n >= 4u) { m = m | tape_reg_bit(w.z >> 16u); }
    return m;
}

// One backward pass over the program [start, start + len) from the output
// registers `live`: how many instructions the tile needs, written (with
// `to` > 0) as entries ending just before word `to`.
fn tape_keep(start: u32, len: u32, live0: vec2<u32>, to: u32) -> u32 {
    var live = live0;
    var n = 0u;
    for (var i = len; i > 0u; i = i - 1u) {
        let w = tape_word(start + i - 1u);
        let out = tape_reg_bit(w.x >> 16u);
        let needed = any((live & out) != vec2<u32>(0u)) || tape_restricts(w);
        if (needed && (w.x & 0xffu) != TAPE_NOP) {
            let pick = tape_pick(w);
            live = (live & ~out) | tape_reads(w, pick);
            n = n + 1u;
            if (to > 0u) { tape_lists[to - n] = (start + i - 1u) | (pick << 30u); }
        }
    }
    return n;
}

fn tape_padded(n: u32) -> u32 { return (n + TAPE_UNROLL - 1u) / TAPE_UNROLL * TAPE_UNROLL; }

// After the tile pass found candidate slabs: the tile's shortened list (0:
// none, the whole tape runs; also when the lists' buffer is full or the
// passes would go past the work limit).
fn field_tile_done() -> u32 {
    atomicAdd(&tape_counts.tiles, 1u);
    // A slab enclosure refused at the work limit noted no choices: the
    // whole tape must run.
    if (!field_records() || g_tape_exhausted) { return 0u; }
    let h = tape_word(0u);
    let o = tape_word(1u);
    if (!tape_admits(2u * (h.y + h.w))) { return 0u; }
    // Four backward passes from one call site (lavapipe compiles each
    // inlined copy): k = 0, 1 count the value and the derivative program's
    // instructions, the list is allocated, k = 2, 3 write them.
    var n = vec2<u32>(0u);
    var l = 0u;
    var pv = 0u;
    for (var k = 0u; k < 4u; k = k + 1u) {
        let prog = k & 1u;
        if (k == 2u) {
            pv = tape_padded(n.x);
            let size = 4u + pv + tape_padded(n.y);
            let base = atomicAdd(&tape_counts.used, size);
            if (base + size > arrayLength(&tape_lists)) { return 0u; }
            l = base + 4u;
            tape_lists[base] = l;
            tape_lists[base + 1u] = pv;
            tape_lists[base + 2u] = l + pv;
            tape_lists[base + 3u] = size - 4u - pv;
            for (var i = l + n.x; i < l + pv; i = i + 1u) { tape_lists[i] = TAPE_LIST_NOP; }
            for (var i = l + pv + n.y; i < base + size; i = i + 1u) { tape_lists[i] = TAPE_LIST_NOP; }
        }
        let live = select(tape_reg_bit(o.x), tape_reg_bit(o.y) | tape_reg_bit(o.z), prog == 1u);
        let to = select(0u, select(l + n.x, l + pv + n.y, prog == 1u), k >= 2u);
        let kept = tape_keep(select(h.x, h.z, prog == 1u), select(h.y, h.w, prog == 1u), live, to);
        if (k < 2u) { n[prog] = kept; }
    }
    atomicAdd(&tape_counts.shortened, 1u);
    atomicAdd(&tape_counts.kept, n.x);
    atomicAdd(&tape_counts.whole, o.w);
    return l;
}

// The per-pixel pass: rays of a tile run its list (0: the whole tape) ...
var<private> g_tile_list: u32;
fn field_enter_tile(list: u32) {
    g_tile_list = list;
    g_tape_list = list;
}
// ... at points inside its candidate slabs (a look-ahead past the run's end
// is not) ...
fn field_in_tile(inside: bool) { g_tape_list = select(0u, g_tile_list, inside); }
// ... until they leave them for good.
fn field_leave_frustum() {
    g_tile_list = 0u;
    g_tape_list = 0u;
}
