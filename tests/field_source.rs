//! A fourth field source, defined here and nowhere in the library: a torus
//! given as data (its radii in a storage buffer of the field group), with
//! its own WGSL for the scalar field and its interval enclosures. It goes
//! through the public `FieldSource` trait only, is rendered by both
//! traversals, and is compared with the compiled formula of the same torus.
//! Its radii change with `Renderer::set_field`, without a new shader.


use isotrace::bindings::{Binding, Slot};
use isotrace::field::{BindingRequest, CodeRequest, FieldSource, Refusal};
use isotrace::ir::Domain;
use isotrace::render::{BisectOptions, Frame, SphereOptions, Status, Traversal};
use isotrace::{Formula, Renderer, Settings};

/// A torus about the z axis: major radius `major`, minor radius `minor`.
struct DataTorus {
    major: f32,
    minor: f32,
}

/// The radii: (major, minor, 0, 0).
const RADII: Slot = Slot::storage(0, "torus radii", "torus_radii", "array<vec4<f32>>", true);

/// The field, its ray form and the hooks every source provides; in IA the
/// enclosure `surf_ia` over a box, from which the library's ray segment
/// and slab enclosures are made. The slope is left unknown (the whole
/// line): bisection then never takes a cell as monotonic, which costs
/// evaluations, not correctness.
const TORUS_WGSL: &str = "
fn field(p: vec3<f32>) -> f32 {
    let t = torus_radii[0];
    let q = length(p.xy) - t.x;
    return q * q + p.z * p.z - t.y * t.y;
}
fn field_ray(o: vec3<f32>, dir: vec3<f32>, s: f32) -> f32 { return field(o + dir * s); }
fn field_cost() -> u32 { return 1u; }
fn field_exhausted() -> bool { return false; }
fn field_tree() -> u32 { return 0u; }
fn field_entry(li: u32) {}
fn field_begin_ray(o: vec3<f32>, dir: vec3<f32>, s_ref: f32, len: f32) {}
";

const TORUS_IA: &str = "
fn surf_ia(X: vec2<f32>, Y: vec2<f32>, Z: vec2<f32>, T: vec2<f32>) -> vec2<f32> {
    let t = torus_radii[0];
    let q = ia_sub(ia_sqrt(ia_add(ia_sqr(X), ia_sqr(Y))), ia_const(t.x));
    return ia_sub(ia_add(ia_sqr(q), ia_sqr(Z)), ia_sqr(ia_const(t.y)));
}
fn cell_enclosure(o: vec3<f32>, dir: vec3<f32>, s0: f32, s1: f32, slope: bool) -> vec4<f32> {
    return vec4<f32>(cell_range(o, dir, s0, s1), -F.inf, F.inf);
}
";

impl FieldSource for DataTorus {
    fn name(&self) -> &'static str {
        "data torus"
    }

    fn code(&self, r: &CodeRequest<'_>) -> String {
        let mut out = isotrace::codegen::library(Domain::Scalar).to_string();
        out.push_str(&isotrace::bindings::declarations(&[&RADII]));
        out.push_str(TORUS_WGSL);
        out.push_str(isotrace::field::UNTILED_FIELD_HOOKS);
        out.push_str(isotrace::field::UNSHORTENED_FIELD_HOOKS);
        if let Some(d) = r.domain {
            assert_eq!(d, Domain::Interval, "the data torus encloses in IA only");
            out.push_str(isotrace::codegen::library(d));
            out.push_str(TORUS_IA);
            out.push_str(&isotrace::field::compiled::enclosures(d, false));
        }
        out
    }

    fn bindings(&self, _: &BindingRequest) -> Vec<Binding> {
        vec![RADII.data(vec![self.major.to_bits(), self.minor.to_bits(), 0, 0])]
    }

    fn has_enclosures(&self) -> bool {
        true
    }

    fn replaces(&self, kernel_name: &'static str, _: u32) -> Result<(), Refusal> {
        if kernel_name == self.name() { Ok(()) } else { Err(Refusal::new("field", "not a data torus kernel")) }
    }
}

fn bisect() -> Traversal {
    Traversal::Bisect(BisectOptions::new(Domain::Interval))
}

fn sphere() -> Traversal {
    Traversal::Sphere(SphereOptions { lipschitz: 2.0, ..Default::default() })
}

/// Pixels hit in one frame and not the other (beyond `slack` of the
/// silhouette), and the largest depth difference where both hit.
fn compare(a: &Frame, b: &Frame) -> (usize, f32) {
    let (mut differ, mut depth) = (0, 0.0f32);
    for (p, q) in a.pixels.iter().zip(&b.pixels) {
        match (p.status, q.status) {
            (Status::Hit, Status::Hit) => depth = depth.max((p.depth - q.depth).abs()),
            (x, y) if x != y => differ += 1,
            _ => {}
        }
    }
    (differ, depth)
}

fn compiled_torus(major: f32, minor: f32) -> Formula {
    Formula::compile("<torus>", &format!("(sqrt(x^2 + y^2) - {major})^2 + z^2 - {minor}^2")).unwrap()
}

#[test]
fn a_source_outside_the_library_renders_as_the_compiled_formula_does() {
    let gpu = gpu();
    let s = Settings::for_box([-1.6, 1.6, -1.6, 1.6, -1.6, 1.6], 160, 120);
    let torus = DataTorus { major: 1.0, minor: 0.4 };
    let formula = compiled_torus(1.0, 0.4);
    for (name, traversal) in [("bisection", bisect()), ("sphere tracing", sphere())] {
        let ours = Renderer::new(gpu, &torus, traversal.clone()).unwrap().render(&s).unwrap();
        let compiled = Renderer::new(gpu, &formula.ir, traversal).unwrap().render(&s).unwrap();
        let hits = ours.pixels.iter().filter(|p| p.status == Status::Hit).count();
        assert!(hits > 1000, "{name}: the torus fills much of the frame ({hits} hits)");
        let (differ, depth) = compare(&ours, &compiled);
        // A few silhouette pixels may go either way at the eps of the traversal.
        assert!(differ <= 20, "{name}: {differ} pixels hit by one field and not the other");
        assert!(depth < 2e-3, "{name}: depths differ by {depth}");
    }
}

#[test]
fn its_data_changes_without_a_new_shader() {
    let gpu = gpu();
    let s = Settings::for_box([-1.6, 1.6, -1.6, 1.6, -1.6, 1.6], 120, 90);
    let mut r = Renderer::new(gpu, &DataTorus { major: 1.0, minor: 0.4 }, bisect()).unwrap();
    let wgsl = r.wgsl().to_string();
    r.set_field(&DataTorus { major: 0.9, minor: 0.2 }).unwrap();
    assert_eq!(r.wgsl(), wgsl);
    let thinner = r.render(&s).unwrap();
    let compiled = Renderer::new(gpu, &compiled_torus(0.9, 0.2).ir, bisect()).unwrap().render(&s).unwrap();
    let (differ, depth) = compare(&thinner, &compiled);
    assert!(differ <= 20 && depth < 2e-3, "{differ} pixels differ, depths by {depth}");
    // A field of another kind is refused by the source's own rule.
    let e = r.set_field(&compiled_torus(1.0, 0.4).ir).err().expect("refused").to_string();
    assert!(e.contains("a compiled field is part of the shader"), "{e}");
}

/// The device shared by the tests.
fn gpu() -> &'static isotrace::Gpu {
    static GPU: std::sync::OnceLock<isotrace::Gpu> = std::sync::OnceLock::new();
    GPU.get_or_init(|| isotrace::Gpu::new().expect("a Vulkan device (install mesa-vulkan-drivers)"))
}
