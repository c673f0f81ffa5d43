// Shared by every render kernel: the frame group's uniform buffer and the
// helpers generated evaluators call.

// The uniforms arrive in a read-only storage buffer and are copied to private
// variables at every entry point (load_uniforms). As a uniform buffer they
// cost every frame a fixed delay on lavapipe, which re-inlined their values
// into the shader on every dispatch however small; read from the storage
// buffer where used, they made the tile pass markedly slower than this copy.
// Ubuf: the frame group's uniforms (src/kernel/bindings.rs).
var<private> F: Frame;
var<private> U: Traversal;

fn load_uniforms() {
    F = Ubuf.frame;
    U = Ubuf.trav;
}

fn iso_inf() -> f32 { return F.inf; }
fn iso_param(i: u32) -> f32 { return F.params[i / 4u][i % 4u]; }

// With several surfaces (CSG by level-set conditions): the surface of the
// cell last accepted, which field() evaluates. The field source sets it;
// it stays 0 for a single surface.
var<private> g_surface: u32;

// Loop iterations a field source spent in this invocation (an interpreter
// counts its nodes; a compiled field has no loops and leaves it 0), so a
// traversal can stop before lavapipe's silent cap of 65,535 loop
// iterations per invocation and report the pixel instead.
var<private> g_field_work: u32;
