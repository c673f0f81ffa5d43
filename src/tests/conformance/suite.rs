//! The conformance suite, written once and run once per backend, as fidget
//! runs its `interval_tests!`: `src/tests/conformance.rs` invokes
//! [`conformance_suite!`] for the CPU reference and
//! `src/tests/conformance_device.rs` for the generated WGSL on the device. A
//! case added to the tables of `formulas.rs` (or to the catalog's `knoll`
//! suite) is therefore checked on both.

/// How many random expression trees a backend checks, and on how many
/// regions each. The backends differ only here: the device pays one
/// dispatch per formula and algebra, so it checks fewer trees on more
/// boxes; the CPU pays per box.
#[derive(Debug, Clone, Copy)]
pub struct Budget {
    /// Random trees checked on boxes.
    pub trees: usize,
    /// Random boxes per tree.
    pub boxes_per_tree: usize,
    /// Random trees checked on ray segments, next to every operation and
    /// Knoll surface.
    pub segment_trees: usize,
}

/// The suite's `#[test]`s for `$backend` (a [`super::Backend`] value)
/// with `$budget` (a [`Budget`]). Every other count and every seed is
/// fixed here, the same for both backends.
macro_rules! conformance_suite {
    ($backend:expr, $budget:expr) => {
        /// Every operation of the language on 3000 random boxes of every kind.
        #[test]
        fn every_operation_encloses() {
            use self::harness::*;
            check_all(&$backend, &op_cases(), &mut |_, rng| random_boxes(rng, 3000), 11);
        }

        /// The Knoll surfaces of the catalog on cells of their own box and
        /// on random boxes ([`knoll_boxes`]).
        #[test]
        fn knoll_surfaces_enclose() {
            use self::harness::*;
            check_all(&$backend, &knoll_cases(), &mut knoll_boxes, 12);
        }

        /// Random expression trees on random boxes.
        #[test]
        fn random_trees_enclose() {
            use self::harness::*;
            let b: Budget = $budget;
            check_all(&$backend, &random_cases(13, b.trees), &mut |_, rng| random_boxes(rng, b.boxes_per_tree), 13);
        }

        /// Ray segments lifted as the render kernel lifts them (RAA: x, y,
        /// z affine in the one shared symbol e1, which boxes never
        /// exercise), 1000 per case, on every operation, the Knoll surfaces
        /// and random trees.
        #[test]
        fn ray_segments_enclose() {
            use self::harness::*;
            let b: Budget = $budget;
            let mut cases = op_cases();
            cases.extend(knoll_cases());
            cases.extend(random_cases(17, b.segment_trees));
            check_all_segments(&$backend, &cases, 1000, 16);
        }

        /// Every operation applied to an undefined argument is empty.
        #[test]
        fn emptiness_propagates() {
            use self::harness::*;
            check_emptiness(&$backend, &empty_cases(), 14);
        }
    };
}
pub(crate) use conformance_suite;
