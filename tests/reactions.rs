//! Reactions of overlapping constrained sets (issue 10, item 6).
//!
//! Reference: equilibrium. The supports must balance the applied load, so the
//! reactions of all sets sum to minus the applied force whatever the sets'
//! overlap, each support force counted once: a prescribed component belongs to
//! the first set, in scene order, that prescribes it (`ConstrainedSet`).
//! Tolerance 1e-9 of the load: the solve's relative residual is below 1e-12
//! and the sum has a few hundred terms.

mod common;

use dhpd::drivers::static_solve;

const LOAD: f64 = 1.0e5; // 1 MPa on the +x face of a 0.1 m high, 1 m thick plate (N)

/// A 0.2 × 0.1 m plate pulled on its right face, with the given supports.
fn plate(model: &str, supports: &str) -> String {
    let nu = if model == "shear" {
        "poisson_ratio = 0.25\n"
    } else {
        ""
    };
    format!(
        "[model]\ndimension = \"plane_stress\"\nkind = \"{model}\"\n\
         [materials.m]\nyoungs_modulus = 1.0e9\n{nu}\
         [[regions]]\nmaterial = \"m\"\nspacing = 0.01\nbox = {{ min = [0.0, 0.0], max = [0.2, 0.1] }}\n\
         {supports}\
         [[loads]]\nname = \"pull\"\nkind = \"traction\"\nface = \"+x\"\nvalue = [1.0e6, 0.0]\n"
    )
}

fn support(name: &str, min: [f64; 2], max: [f64; 2], components: &str) -> String {
    format!(
        "[[boundary]]\nname = \"{name}\"\nbox = {{ min = [{}, {}], max = [{}, {}] }}\n\
         displacement = {{ {components} }}\n",
        min[0], min[1], max[0], max[1]
    )
}

fn reactions(text: &str) -> Vec<(String, [f64; 3])> {
    let solution = static_solve::solve(&common::scene(text)).expect("the plate solves");
    solution
        .reactions
        .iter()
        .map(|r| (r.name.clone(), r.force))
        .collect()
}

fn sum(r: &[(String, [f64; 3])]) -> [f64; 3] {
    let mut s = [0.0; 3];
    for (_, f) in r {
        (0..3).for_each(|c| s[c] += f[c]);
    }
    s
}

fn assert_balanced(r: &[(String, [f64; 3])]) {
    let s = sum(r);
    assert!(
        (s[0] + LOAD).abs() < 1e-9 * LOAD && s[1].abs() < 1e-9 * LOAD,
        "reactions {r:?} sum to {s:?}, not to minus the applied load ({LOAD} N along x)"
    );
}

#[test]
fn a_nested_set_does_not_count_what_its_outer_set_counts() {
    for model in ["bond_based", "shear"] {
        let outer = support("outer", [0.0, 0.0], [0.03, 0.1], "x = 0.0, y = 0.0");
        let inner = support("inner", [0.0, 0.0], [0.01, 0.1], "x = 0.0, y = 0.0");
        // Outer first: it owns every component, the inner set reports zero.
        let a = reactions(&plate(model, &format!("{outer}{inner}")));
        assert_balanced(&a);
        assert_eq!(a[1].1, [0.0; 3], "{model}: nested set counted again");
        // Inner first: it owns its column, the outer set the rest; same total,
        // and the two add up to the outer set alone.
        let b = reactions(&plate(model, &format!("{inner}{outer}")));
        assert_balanced(&b);
        assert!(
            b[0].1[0].abs() > 1e-3 * LOAD,
            "{model}: inner set carries load"
        );
        for c in 0..2 {
            let whole = a[0].1[c];
            assert!(
                (b[0].1[c] + b[1].1[c] - whole).abs() < 1e-9 * LOAD,
                "{model}: component {c}: {} + {} ≠ {whole}",
                b[0].1[c],
                b[1].1[c]
            );
        }
    }
}

#[test]
fn partly_overlapping_and_complementary_sets_sum_to_the_support_force() {
    // Two boxes sharing a band of points.
    let lower = support("lower", [0.0, 0.0], [0.03, 0.06], "x = 0.0, y = 0.0");
    let upper = support("upper", [0.0, 0.04], [0.03, 0.1], "x = 0.0, y = 0.0");
    let r = reactions(&plate("bond_based", &format!("{lower}{upper}")));
    assert_balanced(&r);
    // A roller (x only) and a pin (y only) on the same points: no component is
    // shared, each set reports its own.
    let roller = support("roller", [0.0, 0.0], [0.03, 0.1], "x = 0.0");
    let pin = support("pin", [0.0, 0.04], [0.01, 0.06], "y = 0.0");
    let r = reactions(&plate("bond_based", &format!("{roller}{pin}")));
    assert_balanced(&r);
    assert_eq!(r[0].1[1], 0.0, "the roller prescribes no y");
    assert_eq!(r[1].1[0], 0.0, "the pin prescribes no x");
    assert!((r[0].1[0] + LOAD).abs() < 1e-9 * LOAD);
}
