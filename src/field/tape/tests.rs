//! Unit tests of the tape: codes, registers, padding, choice slots.

use super::*;

fn tape(src: &str) -> TapeData {
    TapeData::new(&crate::Formula::compile("<t>", src).expect("formula").ir).expect("tape")
}

#[test]
fn every_code_is_listed_once() {
    for (i, c) in Code::ALL.iter().enumerate() {
        assert_eq!(*c as usize, i);
    }
}

#[test]
fn registers_are_reused_along_a_long_sum() {
    let src: Vec<String> = (1..=400).map(|i| format!("(x - {i})*(y + {i})")).collect();
    let t = tape(&src.join(" + "));
    // Per term: x − i and y + i with immediates, a multiply-add.
    assert_eq!(t.ops, 1200, "{} ops", t.ops);
    assert!(t.registers <= 16, "{} registers", t.registers);
}

#[test]
fn programs_are_padded_and_described_by_the_header() {
    let t = tape("x^2 + y^2 + z^2 - 1");
    let [vs, vl, ds, dl] = t.words[0];
    assert_eq!(vs, TAPE_HEADER);
    assert_eq!(ds, vs + vl);
    assert_eq!(t.words.len() as u32, ds + dl);
    assert_eq!(vl % TAPE_UNROLL, 0);
    assert_eq!(t.value_iterations(1), vl);
    assert_eq!(t.value_iterations(4), vl / 4);
}

#[test]
fn every_catalog_formula_fits_the_register_file() {
    for e in crate::catalog::builtin() {
        let f = e.compile().expect("catalog formula");
        match TapeData::new(&f.ir) {
            Ok(t) => assert!(t.registers <= TAPE_SLOTS, "{}: {} registers", e.name, t.registers),
            Err(TapeError::Csg | TapeError::UserFunction(_)) => {}
            Err(err) => panic!("{}: {err}", e.name),
        }
    }
}

#[test]
fn min_max_and_their_derivatives_share_choice_slots() {
    let t = tape("min(sqrt(x^2+y^2+z^2)-1, max(abs(x)-0.5, y))");
    let slot = |code: Code| -> Vec<u32> { t.words.iter().skip(TAPE_HEADER as usize).filter(|w| w[0] & 0xff == code as u32).map(|w| w[3]).collect() };
    // Each min and max appears in both programs, with one slot; its
    // derivative (Dmin, Dmax) has the same slot; the formula's square
    // root restricts the domain and has one too.
    let (min, max, sqrt) = (slot(Code::Min), slot(Code::Max), slot(Code::Sqrt));
    assert_eq!((min.len(), max.len()), (2, 2));
    assert!(min.iter().all(|&s| s == min[0]) && max.iter().all(|&s| s == max[0]) && sqrt.iter().all(|&s| s == sqrt[0]));
    assert_eq!(slot(Code::Dmin), vec![min[0]]);
    assert_eq!(slot(Code::Dmax), vec![max[0]]);
    let mut all = vec![min[0], max[0], sqrt[0]];
    all.sort_unstable();
    assert_eq!(all, vec![0, 1, 2]);
    assert_eq!(t.words[2][2], 3, "slots in use");
    assert_eq!(t.words[1][3], t.ops as u32, "value instructions");
    // The logarithm a power's derivative adds does not restrict the
    // domain and gets no slot; the formula's own does and gets one.
    let d = tape("pow(x^2+1, y) + log(z^2+2)");
    let logs: Vec<[u32; 4]> = d.words.iter().skip(TAPE_HEADER as usize).copied().filter(|w| w[0] & 0xff == Code::Log as u32).collect();
    assert!(logs.iter().any(|w| w[0] & TAPE_RESTRICTS == 0), "{logs:?}");
    assert!(logs.iter().all(|w| (w[0] & TAPE_RESTRICTS != 0) == (w[3] != TAPE_NO_SLOT)), "{logs:?}");
}

#[test]
fn the_wgsl_arity_table_is_the_allocators() {
    let wgsl = wgsl_constants(features::ALL);
    let body = &wgsl[wgsl.find("fn tape_arity").expect("generated")..];
    for c in Code::ALL {
        let line = body.lines().find(|l| l.contains(&format!("code == {} ", c.wgsl_name())) || l.contains(&format!("code == {})", c.wgsl_name())));
        match line {
            Some(l) => assert!(l.contains(&format!("return {}u;", arity(c))), "{c:?}: {l}"),
            None => assert_eq!(arity(c), 4, "{c:?} falls through to 4"),
        }
    }
}

#[test]
fn csg_and_user_functions_are_refused() {
    let ir = crate::Formula::compile("<t>", "x^2 + y^2 - 1 where z < 0").expect("formula").ir;
    assert_eq!(TapeData::new(&ir), Err(TapeError::Csg));
}
