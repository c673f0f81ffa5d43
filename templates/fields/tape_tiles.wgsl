// Per-tile tape shortening for bisection (spliced after the interpreters of
// a tape field whose tape has min or max; src/field/tape/wgsl.rs).
//
// Most of a CSG formula is dead in any small region: a min's operand that
// lies above the other over the region never reaches the result, and nor
// does the subtree that computes it. The tile pass already encloses f over
// each 8x8 tile's candidate depth slabs; while it encloses a fine slab,
// every min and max notes in its choice slot which operand it can take
// there (tape_note_*), and the notes of the slabs that may hold the surface
// are added up for the tile (field_slab_end). A block pass does the same
// for blocks of 2x2 tiles over their coarse slabs first, and the tile pass
// starts from its block's list (field_tile_begin).
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

// tape_lists (field group): the tile's shortened programs: at word L - 4 of a list L the value
// program's (start, length) and the derivative program's, then the entries
// (pc | pick << 30, padded with TAPE_LIST_NOP to whole loop iterations).
// tape_counts (field group): counts, zeroed before the dispatch and read back for
// the statistics (render::TapeListStats): words of tape_lists in use, tiles
// with candidate slabs, tiles shortened, and the value instructions those
// keep and have in all; blocks, blocks shortened, and what those keep.
struct TapeListCounts { used: atomic<u32>, tiles: atomic<u32>, shortened: atomic<u32>, kept: atomic<u32>, whole: atomic<u32>, blocks: atomic<u32>, blocks_shortened: atomic<u32>, blocks_kept: atomic<u32> }

// tape_notes (field group): the choices noted over the tile's candidate slabs, two bits a slot (a
// vec4 holds 64), then those of the slab being enclosed (a storage buffer,
// not a private array: lavapipe compiles a dynamically indexed private
// array into code at every access, which lengthened the tile pass's
// compile noticeably).
// The tile's first vec4 of notes.
var<private> g_note_base: u32;

// The block pass (a dispatch before the tile pass, through its entry point)
// shortens the tape per block of FIELD_BLOCK x FIELD_BLOCK tiles over the
// block's coarse slabs, as the tile pass does per tile over its fine slabs;
// the tile pass then encloses and shortens the block's list, not the whole
// tape. A tape of thousands of instructions (four copies of `@city`'s
// blocks: 2,975) is mostly dead in a block too, and without the block pass
// the tile pass's enclosures and backward passes over the whole of it went
// past the work limit in all but one tile in 269. The first words of
// tape_lists hold, per block, its list (0: the whole tape), the coarse
// slabs it may hold (as the fine slabs' 64-bit mask: only those are left to
// its tiles) and the enclosures it spent.
fn tape_blocks_x() -> u32 { return (F.tile_size.x + 8u * FIELD_BLOCK - 1u) / (8u * FIELD_BLOCK); }
fn tape_reserved() -> u32 { return 4u * tape_blocks_x() * ((F.tile_size.y + 8u * FIELD_BLOCK - 1u) / (8u * FIELD_BLOCK)); }
var<private> g_block: u32;
var<private> g_block_list: u32;
// Whether the lists' buffer holds the blocks' entries (the browser page
// sizes it for the frame it starts with): if not, there is no block pass.
fn tape_blocks_fit() -> bool { return tape_reserved() <= arrayLength(&tape_lists); }

// Before a tile's (with `block`, a block's) slabs: zeroes its notes (a
// block uses its first tile's, which the tile pass zeroes again after it),
// and gives the slabs its block left it, its block's list to run, and its
// share of the block's enclosures.
fn field_tile_begin(t: u32, tile: vec2<u32>, block: bool) -> vec3<u32> {
    g_note_base = t * (TAPE_CHOICE_SLOTS / 32u);
    for (var i = 0u; i < tape_note_words(); i = i + 1u) { tape_notes[g_note_base + i] = vec4<u32>(0u); }
    tape_tile_pass_limit();
    g_block = 4u * ((tile.y / FIELD_BLOCK) * tape_blocks_x() + tile.x / FIELD_BLOCK);
    if (block || !tape_blocks_fit()) {
        g_block_list = 0u;
        g_tape_list = 0u;
        return vec3<u32>(0xffffffffu, 0xffffffffu, 0u);
    }
    let b = vec4<u32>(tape_lists[g_block], tape_lists[g_block + 1u], tape_lists[g_block + 2u], tape_lists[g_block + 3u]);
    g_block_list = b.x;
    g_tape_list = b.x;
    // The block's enclosures, shared among its tiles.
    let k = (tile.y % FIELD_BLOCK) * FIELD_BLOCK + tile.x % FIELD_BLOCK;
    let per = FIELD_BLOCK * FIELD_BLOCK;
    return vec3<u32>(b.yz, b.w / per + select(0u, 1u, k < b.w % per));
}

// Whether the tape notes its choices: shortening is on and the tape has
// choice slots (header word 2.z).
fn field_records() -> bool { return (F.flags & FLAG_NO_TAPE_SHORTENING) == 0u && tape_word(2u).z > 0u; }

// The notes of the slab being enclosed (after the tile's), and how many
// vec4s of notes the tape's slots fill.
fn tape_slab_notes() -> u32 { return g_note_base + TAPE_CHOICE_SLOTS / 64u; }
fn tape_note_words() -> u32 { return (tape_word(2u).z + 63u) / 64u; }

// Before a slab's enclosure: whether it is a slab the tile's list is for
// (a fine slab, a block's coarse slab). The interpreter then notes its
// choices for the slab apart, and field_slab_end adds them to the tile's if
// the slab may hold the surface: only those count, and the pass cannot
// know before the enclosure. (Enclosing each such slab a second time to
// note them would cost twice the interpreter's work, to save a clear and
// a merge of the slots in use.)
fn field_slab_begin(record: bool) {
    g_tape_record = record && field_records();
    if (!g_tape_record) { return; }
    let base = tape_slab_notes();
    for (var i = 0u; i < tape_note_words(); i = i + 1u) { tape_notes[base + i] = vec4<u32>(0u); }
}

// After the slab's enclosure: whether it may hold the surface.
fn field_slab_end(hold: bool) {
    if (g_tape_record && hold) {
        let base = tape_slab_notes();
        for (var i = 0u; i < tape_note_words(); i = i + 1u) { tape_notes[g_note_base + i] = tape_notes[g_note_base + i] | tape_notes[base + i]; }
    }
    g_tape_record = false;
}

fn tape_note_bits(slot: u32, c: u32) {
    let i = tape_slab_notes() + (slot >> 6u);
    let k = (slot >> 4u) & 3u;
    tape_notes[i][k] = tape_notes[i][k] | (c << ((slot & 15u) * 2u));
}

// The bit of register r in a 64-register set (two words).
fn tape_reg_bit(r: u32) -> vec2<u32> {
    let i = r & TAPE_SLOT_MASK;
    return select(vec2<u32>(1u << (i & 31u), 0u), vec2<u32>(0u, 1u << (i & 31u)), i >= 32u);
}

// The two bits of choice slot `slot` over the tile's candidate slabs (0:
// never noted there).
fn tape_choice(slot: u32) -> u32 {
    return (tape_notes[g_note_base + (slot >> 6u)][(slot >> 4u) & 3u] >> ((slot & 15u) * 2u)) & 3u;
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

// One backward pass over program `prog` as the interpreter would run it now
// (the whole tape, or the block's list: tape_span, tape_entry) from the
// output registers `live`: how many instructions the tile needs, written
// (with `to` > 0) as entries ending just before word `to`. TAPE_KEEP_STEP
// entries an iteration (lines marked `each backward step K` are written
// once for each K from 1 to TAPE_KEEP_STEP - 1 by src/field/tape/wgsl.rs;
// programs and lists are padded to a multiple of it): one for most tapes,
// where more, written out, cost lavapipe markedly more compile; four for
// the longest, whose passes would not fit the work limit one at a time.
fn tape_keep(prog: u32, live0: vec2<u32>, to: u32) -> u32 {
    let span = tape_span(prog);
    var k = vec3<u32>(live0, 0u);
    for (var i = span.y; i > 0u; i = i - TAPE_KEEP_STEP) {
        k = tape_keep_entry(tape_entry(span.x + i - 1u), k, to);
        k = tape_keep_entry(tape_entry(span.x + i - 1u - Ku), k, to); // each backward step K
    }
    return k.z;
}

// One entry of tape_keep: k is (live registers, entries kept so far). A min
// or max the block's list already picks keeps its pick (the tile's
// enclosures ran it as a copy, so their notes on it say nothing).
fn tape_keep_entry(e: u32, k: vec3<u32>, to: u32) -> vec3<u32> {
    let pc = e & TAPE_PC_MASK;
    let w = tape_word(pc);
    let out = tape_reg_bit(w.x >> 16u);
    let needed = any((k.xy & out) != vec2<u32>(0u)) || tape_restricts(w);
    if (!needed || e == TAPE_LIST_NOP || (w.x & 0xffu) == TAPE_NOP) { return k; }
    let given = e >> 30u;
    let pick = select(tape_pick(w), given, given != 0u);
    let n = k.z + 1u;
    if (to > 0u) { tape_lists[to - n] = pc | (pick << 30u); }
    return vec3<u32>((k.xy & ~out) | tape_reads(w, pick), n);
}

// Lists are padded to whole iterations of the interpreter's loop.
fn tape_padded(n: u32) -> u32 { return (n + TAPE_UNROLL - 1u) / TAPE_UNROLL * TAPE_UNROLL; }

// The tile's (or block's) shortened list and the value instructions it
// keeps, from the notes of its slabs ((0, 0): none; also when the lists'
// buffer is full or the passes would go past the work limit).
fn tape_shorten() -> vec2<u32> {
    // A slab enclosure refused at the work limit noted no choices.
    if (!field_records() || g_tape_exhausted) { return vec2<u32>(0u); }
    let o = tape_word(1u);
    if (!tape_admits(2u * (tape_span(0u).y + tape_span(1u).y) / TAPE_KEEP_STEP)) { return vec2<u32>(0u); }
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
            let base = tape_reserved() + atomicAdd(&tape_counts.used, size);
            if (base + size > arrayLength(&tape_lists)) { return vec2<u32>(0u); }
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
        let kept = tape_keep(prog, live, to);
        if (k < 2u) { n[prog] = kept; }
    }
    return vec2<u32>(l, n.x);
}

// After the tile pass found candidate slabs (`mask`, `n` enclosures): the
// tile's list (0: the whole tape). Without one of its own, the tile runs
// its block's: that is exact inside the block's candidate slabs, and the
// tile's lie inside them. With `block`, after the block pass's slabs: the
// block's entry, which every block writes (the lists' buffer outlives the
// frame).
fn field_tile_done(mask: vec2<u32>, n: u32, block: bool) -> u32 {
    if (block && !tape_blocks_fit()) { return 0u; }
    var s = vec2<u32>(0u);
    if (any(mask != vec2<u32>(0u))) { s = tape_shorten(); }
    if (block) {
        atomicAdd(&tape_counts.blocks, 1u);
        if (s.x != 0u) {
            atomicAdd(&tape_counts.blocks_shortened, 1u);
            atomicAdd(&tape_counts.blocks_kept, s.y);
        }
        tape_lists[g_block] = s.x;
        tape_lists[g_block + 1u] = mask.x;
        tape_lists[g_block + 2u] = mask.y;
        tape_lists[g_block + 3u] = n;
        return s.x;
    }
    atomicAdd(&tape_counts.tiles, 1u);
    if (s.x == 0u && g_block_list != 0u) { s = vec2<u32>(g_block_list, tape_lists[g_block_list - 3u]); }
    if (s.x == 0u) { return 0u; }
    atomicAdd(&tape_counts.shortened, 1u);
    atomicAdd(&tape_counts.kept, s.y);
    atomicAdd(&tape_counts.whole, tape_word(1u).w);
    return s.x;
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
