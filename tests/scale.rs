//! Scale invariance (issue 4): the same problem at length scales 1e-6, 1 and
//! 1e3 m and moduli 1e3, 1e9 and 1e12 Pa, loaded at the same strain (traction
//! 1e-4 E), must give the same dimensionless displacement u/L to about 1e-10.
//! Any absolute tolerance hidden in the geometry, the neighbour search, the
//! partial volumes, the rigid-motion check or the solvers would show up here.

mod common;

use common::scene;

fn dimensionless(model: &str, length: f64, modulus: f64) -> Vec<[f64; 2]> {
    let h = length / 20.0;
    let text = format!(
        "[model]\ndimension = \"plane_stress\"\nkind = \"{model}\"\n[materials.m]\nyoungs_modulus = {modulus:e}\npoisson_ratio = 0.3333333333333333\n\
         [[regions]]\nmaterial = \"m\"\nspacing = {h:e}\nbox = {{ min = [0.0, 0.0], max = [{length:e}, {length:e}] }}\n\
         [[holes]]\ncenter = [{c:e}, {c:e}]\nradius = {r:e}\n\
         [[boundary]]\nname = \"left\"\nbox = {{ min = [0.0, 0.0], max = [{b:e}, {length:e}] }}\ndisplacement = {{ x = 0.0, y = 0.0 }}\n\
         [[loads]]\nname = \"pull\"\nkind = \"traction\"\nface = \"+x\"\nvalue = [{p:e}, 0.0]\n",
        c = 0.5 * length,
        r = 0.2 * length,
        b = 3.0 * h,
        p = 1e-4 * modulus,
    );
    let s = dhpd::drivers::static_solve::solve(&scene(&text)).expect("solves");
    s.u.iter().map(|u| [u[0] / length, u[1] / length]).collect()
}

#[test]
fn dimensionless_answer_is_scale_free() {
    for model in ["bond_based", "shear"] {
        let reference = dimensionless(model, 1.0, 1e9);
        let scale = reference
            .iter()
            .flatten()
            .fold(0.0f64, |m, v| m.max(v.abs()));
        assert!(scale > 0.0);
        for (length, modulus) in [
            (1e-6, 1e3),
            (1e-6, 1e12),
            (1e3, 1e3),
            (1e3, 1e12),
            (1.0, 1e3),
            (1e-6, 1e9),
        ] {
            let other = dimensionless(model, length, modulus);
            assert_eq!(
                other.len(),
                reference.len(),
                "{model}: L = {length:e}: different point sets"
            );
            let diff = other
                .iter()
                .zip(&reference)
                .flat_map(|(a, b)| [(a[0] - b[0]).abs(), (a[1] - b[1]).abs()])
                .fold(0.0f64, f64::max);
            eprintln!(
                "{model}: L = {length:e} m, E = {modulus:e} Pa: max |Δ(u/L)| = {:.1e} of max |u/L|",
                diff / scale
            );
            assert!(
                diff <= 1e-10 * scale,
                "{model}: L = {length:e} m, E = {modulus:e} Pa: u/L differs by {:.1e} relative",
                diff / scale
            );
        }
    }
}
