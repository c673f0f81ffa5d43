//! The bench variants (`--method`, `--algebra`, `--omega`) as lists.

#[test]
fn bench_variants_are_methods_times_algebras_or_omegas() {
    use crate::bench::{variants, Variant};
    let v = variants("sphere,bisect", "ia,raa", "1,1.2").unwrap();
    assert_eq!(v, [Variant::Sphere(1.0), Variant::Sphere(1.2), Variant::Bisect("ia".into()), Variant::Bisect("raa".into())]);
    assert_eq!(v.iter().map(|x| x.label(true)).collect::<Vec<_>>(), ["sphere-w1", "sphere-w1.2", "ia", "raa"]);
    assert_eq!(Variant::Sphere(1.2).label(false), "sphere");
    // The algebra only matters for bisection.
    assert_eq!(variants("sphere", "ia,raa,auto", "1.2").unwrap(), [Variant::Sphere(1.2)]);
    use crate::bench::VariantList as L;
    let err = |m, a, w| variants(m, a, w).map(|_| ()).unwrap_err();
    assert_eq!((err("march", "ia", "1").list, err("march", "ia", "1").value.as_str()), (L::Method, "march"));
    assert_eq!((err("sphere", "ia", "2").list, err("sphere", "ia", "2").value.as_str()), (L::Omega, "2"));
    assert_eq!((err("bisect", "fast", "1").list, err("bisect", "fast", "1").value.as_str()), (L::Algebra, "fast"));
}
