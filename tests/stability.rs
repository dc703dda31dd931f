//! Stiff and extreme cases (issue 4, first part): stiffness contrast across a
//! material interface. A 1D DH-PD bar of two materials with E₂/E₁ = 10^±2, 10^±4,
//! 10^±6 (spacing 0.01 / 0.005 m, supports at the innermost held points, as in
//! `validation/bimaterial_bar`) against the series-spring solution.
//!
//! Measured: relative residuals 2-3e-15 at every contrast (Cholesky pivot range
//! up to 3e6, grows with the contrast as it should). The displacement error
//! against series springs is a discretisation property: 2.7-4.0 % at 10^±2,
//! saturating at 3.2 % (stiff right half) and 5.4-5.6 % (soft right half) for
//! 10^±4 and 10^±6. With a large contrast all the strain sits in the soft half,
//! and the nonlocal interface layer (one horizon wide) shifts its effective
//! length; the effect does not grow past 1e4, so no digits are lost to the
//! contrast. The test asserts both: residual below 1e-10 at every contrast, and
//! the error at 10^±6 within 10 % of the error at 10^±4 (a solver losing digits
//! with the contrast would break the second).

use dhpd::reference::{series_bar, ErrorStats};
use dhpd::scene::{parse_spec, Scene};

#[test]
fn stiffness_contrast_series_springs() {
    let (dl, dr, u_end) = (0.01, 0.005, 1e-4);
    let (a, b) = (2.5 * dl, 1.0 - 2.5 * dr);
    let mut errors = Vec::new();
    for exponent in [-6, -4, -2, 2, 4, 6] {
        let e2 = 10f64.powi(exponent);
        let text = format!(
            "[model]\ndimension = \"1d\"\n[materials.one]\nyoungs_modulus = 1.0\n[materials.two]\nyoungs_modulus = {e2:e}\n\
             [[regions]]\nmaterial = \"one\"\nspacing = {dl}\nbox = {{ min = [0.0], max = [0.5] }}\n\
             [[regions]]\nmaterial = \"two\"\nspacing = {dr}\nbox = {{ min = [0.5], max = [1.0] }}\n\
             [[boundary]]\nname = \"left\"\nbox = {{ min = [0.0], max = [{:e}] }}\ndisplacement = {{ x = 0.0 }}\n\
             [[boundary]]\nname = \"right\"\nbox = {{ min = [{:e}], max = [1.0] }}\ndisplacement = {{ x = {u_end:e} }}\n",
            a + 0.25 * dl,
            b - 0.25 * dr
        );
        let scene = Scene::try_from_spec(
            parse_spec(&text, false).unwrap(),
            std::path::Path::new("."),
            "contrast",
        )
        .unwrap();
        let s = dhpd::drivers::static_solve::solve(&scene).expect("solves");
        let pairs: Vec<(f64, f64)> = (0..s.disc.points.len())
            .filter(|&i| s.dofs.free_count(i) == 1)
            .map(|i| (s.disc.points.x[i][0], s.u[i][0]))
            .filter(|(x, _)| *x > a + 3.015 * dl && *x < b - 3.015 * dr)
            .map(|(x, u)| (u, series_bar(x, a, b, 0.5, 1.0, e2, u_end)))
            .collect();
        let stats = ErrorStats::of(pairs, u_end);
        let pivots = s.counts.pivots.unwrap();
        eprintln!(
            "E2/E1 = 1e{exponent}: max error {:.3} %, residual {:.1e}, pivot range {:.1e}, smallest pivot ratio {:.1e}",
            100.0 * stats.max_relative, s.residual, pivots.max / pivots.min, pivots.min_ratio
        );
        assert!(
            s.residual < 1e-10,
            "E2/E1 = 1e{exponent}: residual {:e}",
            s.residual
        );
        errors.push((exponent, stats.max_relative));
    }
    let error = |e: i32| errors.iter().find(|(x, _)| *x == e).unwrap().1;
    for sign in [-1, 1] {
        let (e4, e6) = (error(4 * sign), error(6 * sign));
        assert!(
            (e6 / e4 - 1.0).abs() < 0.1,
            "error grows with the contrast: {e4:e} at 1e{}, {e6:e} at 1e{}",
            4 * sign,
            6 * sign
        );
    }
}
