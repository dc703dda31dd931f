//! The validation cases of `validation/` as functions, shared by the tests (coarse
//! settings), the examples (full studies) and the default run.
//!
//! Bimaterial bar (000 Sec. 5.1): `E₁ = 1` on the left half, `E₂ = 2` on the
//! right, one spacing per half, `δ_i = 3.015 Δx_i`. The left constrained layer
//! is fixed, the right one moved by `u_R = 1e-4` m along x. The continuum
//! reference places the supports at the centre of the innermost constrained
//! point of each layer: a chain of bonds between point centres transmits the
//! load from there on, so that is where the deformable body begins.

use crate::drivers::static_solve::{self, StaticSolution};
use crate::error::Error;
use crate::scene::{parse_spec, Scene};
use std::path::Path;

/// Displacement applied at the right end of the bimaterial cases (m).
pub const BAR_DISPLACEMENT: f64 = 1e-4;

/// Setup of a bimaterial bar or strip.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bimaterial {
    /// Spacing of the left (E = 1) half.
    pub dx_left: f64,
    /// Spacing of the right (E = 2) half.
    pub dx_right: f64,
    /// `"dual"` or `"constant"` horizons.
    pub constant_horizon: bool,
    /// 2D strip (1 m × 0.1 m, plane stress, ν = 1/3) instead of a 1D bar.
    pub strip: bool,
}

impl Bimaterial {
    /// Centre of the innermost point of the left constrained layer (support of the reference).
    pub fn support_left(&self) -> f64 {
        if self.strip {
            0.025
        } else {
            2.5 * self.dx_left
        }
    }

    /// Centre of the innermost point of the right constrained layer.
    pub fn support_right(&self) -> f64 {
        if self.strip {
            0.9725
        } else {
            1.0 - 2.5 * self.dx_right
        }
    }

    /// The scene: 1D: 3 points held at each end; 2D: every point up to the supports.
    pub fn scene(&self) -> Scene {
        let (a, b) = (self.support_left(), self.support_right());
        let (left_max, right_min) = (a + 0.25 * self.dx_left, b - 0.25 * self.dx_right);
        let horizons = if self.constant_horizon {
            "constant"
        } else {
            "dual"
        };
        let (model, lo, hi, mid_lo, mid_hi, nu, fixed) = if self.strip {
            (
                "plane_stress",
                "0.0, 0.0",
                "1.0, 0.1",
                "0.5, 0.0",
                "0.5, 0.1",
                "poisson_ratio = 0.3333333333333333",
                "x = 0.0, y = 0.0",
            )
        } else {
            ("1d", "0.0", "1.0", "0.5", "0.5", "", "x = 0.0")
        };
        let pad = |v: f64| {
            if self.strip {
                format!("{v}, 0.0")
            } else {
                format!("{v}")
            }
        };
        let pad_hi = |v: f64| {
            if self.strip {
                format!("{v}, 0.1")
            } else {
                format!("{v}")
            }
        };
        let text = format!(
            r#"
            name = "bimaterial"
            [model]
            dimension = "{model}"
            horizons = "{horizons}"
            [materials.one]
            youngs_modulus = 1.0
            {nu}
            [materials.two]
            youngs_modulus = 2.0
            {nu}
            [[regions]]
            material = "one"
            spacing = {dl}
            box = {{ min = [{lo}], max = [{mid_hi}] }}
            [[regions]]
            material = "two"
            spacing = {dr}
            box = {{ min = [{mid_lo}], max = [{hi}] }}
            [[boundary]]
            name = "left"
            box = {{ min = [{lo}], max = [{lmax}] }}
            displacement = {{ {fixed} }}
            [[boundary]]
            name = "right"
            box = {{ min = [{rmin}], max = [{hi}] }}
            displacement = {{ x = {u} }}
            "#,
            dl = self.dx_left,
            dr = self.dx_right,
            lmax = pad_hi(left_max),
            rmin = pad(right_min),
            u = BAR_DISPLACEMENT,
        );
        let spec = parse_spec(&text, false).expect("generated scene parses");
        Scene::try_from_spec(spec, Path::new("."), "bimaterial").expect("generated scene is valid")
    }

    /// Solves the case.
    pub fn solve(&self) -> Result<StaticSolution, Error> {
        static_solve::solve(&self.scene())
    }

    /// Closed-form 1D (series springs) displacement at `x`.
    pub fn series_displacement(&self, x: f64) -> f64 {
        crate::reference::series_bar(
            x,
            self.support_left(),
            self.support_right(),
            0.5,
            1.0,
            2.0,
            BAR_DISPLACEMENT,
        )
    }

    /// Closed-form 1D reaction (N) for a cross-section `area`.
    pub fn series_reaction(&self, area: f64) -> f64 {
        let (a, b) = (self.support_left(), self.support_right());
        BAR_DISPLACEMENT * area / ((0.5 - a) / 1.0 + (b - 0.5) / 2.0)
    }
}
