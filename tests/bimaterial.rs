//! Bimaterial bar (1D) and strip (2D) against independent references
//! (000 Sec. 5.1; validation/bimaterial_bar).
//!
//! References: the closed-form series-spring solution (1D) and the committed
//! scikit-fem P2 solution (2D, `validation/bimaterial_bar/fem/reference.json`,
//! converged to 3e-9 m in u_x, far below the tolerances here). Supports sit at the
//! centres of the innermost constrained points (see `dhpd::validation`).

use dhpd::reference::{ErrorStats, FemReference};
use dhpd::validation::{Bimaterial, BAR_DISPLACEMENT};

/// Max and RMS error of u (in units of the applied displacement) over free points
/// farther than one horizon from both constrained layers, and the reaction error.
fn bar_errors(case: &Bimaterial) -> (ErrorStats, f64) {
    let s = case.solve().expect("bar solves");
    let (a, b) = (case.support_left(), case.support_right());
    let pairs: Vec<(f64, f64)> = (0..s.disc.points.len())
        .filter(|&i| s.dofs.free_count(i) == 1)
        .map(|i| (s.disc.points.x[i][0], s.u[i][0]))
        .filter(|(x, _)| *x > a + 3.015 * case.dx_left && *x < b - 3.015 * case.dx_right)
        .map(|(x, u)| (u, case.series_displacement(x)))
        .collect();
    let reaction = s
        .reaction("right")
        .expect("the right grip is a constrained set")[0];
    (
        ErrorStats::of(pairs, BAR_DISPLACEMENT),
        reaction / case.series_reaction(1.0) - 1.0,
    )
}

/// Issue target: DH-PD within 1 % of the analytical displacement away from the
/// constrained layers, for both spacing orders; the reaction (the sectional force)
/// within 1 % too. The remaining error is PD's nonlocal boundary layer at the
/// interface and at the supports, which is O(δ/L).
#[test]
fn bar_1d_dual_horizon_matches_series_springs() {
    for (dl, dr) in [(0.01, 0.005), (0.005, 0.01)] {
        let (stats, reaction) = bar_errors(&Bimaterial {
            dx_left: dl,
            dx_right: dr,
            constant_horizon: false,
            strip: false,
            surface_correction: true,
        });
        assert!(stats.count > 100);
        assert!(
            stats.max_relative < 0.01,
            "spacing {dl}/{dr}: max error {:.3} %",
            100.0 * stats.max_relative
        );
        assert!(
            reaction.abs() < 0.01,
            "spacing {dl}/{dr}: reaction error {:.3} %",
            100.0 * reaction
        );
    }
}

/// The paper's Case I vs Case II: the constant-horizon baseline (every point
/// takes the largest horizon) is less accurate than DH-PD in both orders. The
/// comparison is the papers', without the surface correction: the correction
/// normalises every family at the spacing jump to its lattice, which removes
/// most of the baseline's interface error too (with it, both stay within the
/// 1 % of `bar_1d_dual_horizon_matches_series_springs`; validation/surfaces/README.md).
#[test]
fn bar_1d_dual_horizon_beats_constant_horizon_baseline() {
    for (dl, dr) in [(0.01, 0.005), (0.005, 0.01)] {
        let (dual, _) = bar_errors(&Bimaterial {
            dx_left: dl,
            dx_right: dr,
            constant_horizon: false,
            strip: false,
            surface_correction: false,
        });
        let (constant, _) = bar_errors(&Bimaterial {
            dx_left: dl,
            dx_right: dr,
            constant_horizon: true,
            strip: false,
            surface_correction: false,
        });
        assert!(
            dual.rms_relative < constant.rms_relative,
            "spacing {dl}/{dr}: DH {:?} vs constant {:?}",
            dual,
            constant
        );
    }
}

fn strip(refinement: f64) -> (ErrorStats, f64) {
    let case = Bimaterial {
        dx_left: 0.01 / refinement,
        dx_right: 0.005 / refinement,
        constant_horizon: false,
        strip: true,
        surface_correction: true,
    };
    let reference = FemReference::from_json(&case.strip_reference().unwrap()).unwrap();
    let s = case.solve().expect("strip solves");
    let centre: Vec<(f64, f64)> = (0..s.disc.points.len())
        .filter(|&i| s.dofs.free_count(i) == 2)
        .filter(|&i| (s.disc.points.x[i][1] - 0.05).abs() <= 0.5 * s.disc.points.spacing[i] + 1e-12)
        .filter_map(|i| {
            reference
                .grid
                .interpolate("ux", s.disc.points.x[i][0], s.disc.points.x[i][1])
                .map(|r| (s.u[i][0], r))
        })
        .collect();
    let reaction = s
        .reaction("right")
        .expect("the right grip is a constrained set")[0];
    (
        ErrorStats::of(centre, BAR_DISPLACEMENT),
        reaction / reference.reaction_x.unwrap() - 1.0,
    )
}

/// Issue target: u_x along the centre line within 2 % of the FEM reference at the
/// paper's spacing (0.01 / 0.005 m).
#[test]
fn strip_2d_centre_line_matches_fem() {
    let (stats, _) = strip(1.0);
    assert!(stats.count > 100);
    assert!(
        stats.max_relative < 0.02,
        "centre line max error {:.3} %",
        100.0 * stats.max_relative
    );
}

/// The reaction differs from FEM (clamped at the grip's face, x = 0.03) mostly
/// by the interior quadrature bias of the overlap rule, which the surface
/// correction leaves untouched: the lattice's uniaxial modulus at δ = 3.015Δ is
/// E (1 + 1.95 %) in plane stress (C₁₁ +0.95 %, C₁₂ −3.1 %, from the bond sums;
/// `discretization::partial_volume`, validation/surfaces). Before the
/// correction the free edges cost −6 % and the reaction was −4.6 %. Three
/// times finer the reaction must be within the 2 %, and the
/// centre-line error must shrink with refinement.
#[test]
fn strip_2d_reaction_converges_to_fem() {
    let (coarse, _) = strip(1.0);
    let (fine, reaction) = strip(3.0);
    assert!(
        reaction.abs() < 0.02,
        "reaction error {:.3} % at 3x refinement",
        100.0 * reaction
    );
    assert!(fine.max_relative < coarse.max_relative);
}
