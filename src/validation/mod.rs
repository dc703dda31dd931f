//! The validation cases of `validation/` as functions, shared by the tests (coarse
//! settings), the examples (full studies) and the default run.
//!
//! Bimaterial bar (000 Sec. 5.1): `E₁ = 1` on the left half, `E₂ = 2` on the
//! right, one spacing per half, `δ_i = 3.015 Δx_i`. The left constrained layer
//! is fixed, the right one moved by `u_R = 1e-4` m along x. The continuum
//! reference places the supports at the centre of the innermost constrained
//! point of each layer: a chain of bonds between point centres transmits the
//! load from there on, so that is where the deformable body begins.

pub mod fracture;
pub mod scenes;

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
    /// The bond-based surface correction (the default); `false` is the
    /// papers' model (`discretization.surface_correction = "none"`).
    pub surface_correction: bool,
}

impl Bimaterial {
    /// Centre of the innermost point of the left constrained layer.
    fn innermost_left(&self) -> f64 {
        if self.strip {
            0.025
        } else {
            2.5 * self.dx_left
        }
    }

    /// Centre of the innermost point of the right constrained layer.
    fn innermost_right(&self) -> f64 {
        if self.strip {
            0.9725
        } else {
            1.0 - 2.5 * self.dx_right
        }
    }

    /// Where the reference clamps the left end: with the surface correction,
    /// the face of the held cells (a grip, `model::surface`), half a spacing
    /// beyond the innermost held centre; without it, that centre (the papers'
    /// model behaves as a spring chain fixed at its last held node).
    pub fn support_left(&self) -> f64 {
        self.innermost_left()
            + if self.surface_correction {
                0.5 * self.dx_left
            } else {
                0.0
            }
    }

    /// Where the reference holds the right end: the 1D bar's is a grip as on
    /// the left; the strip's prescribes u_x only (a roller, not corrected), at
    /// the innermost centre.
    pub fn support_right(&self) -> f64 {
        let shift = if self.surface_correction && !self.strip {
            0.5 * self.dx_right
        } else {
            0.0
        };
        self.innermost_right() - shift
    }

    /// The strip's scikit-fem reference for these supports
    /// (`validation/bimaterial_bar/fem`): `reference.json` clamps x = 0.025,
    /// `reference_clamp_face.json` x = 0.03 (the paper's spacing corrected),
    /// `reference_clamp_face_r3.json` x = 0.025 + 0.01/6 (three times finer).
    pub fn strip_reference(&self) -> Result<String, std::io::Error> {
        let file = match (
            self.surface_correction,
            (0.01 / self.dx_left).round() as i64,
        ) {
            (false, _) => "reference.json",
            (true, 1) => "reference_clamp_face.json",
            (true, 3) => "reference_clamp_face_r3.json",
            (true, r) => {
                return Err(std::io::Error::other(format!(
                    "no FEM reference of the corrected strip {r} times finer"
                )))
            }
        };
        std::fs::read_to_string(
            std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("validation/bimaterial_bar/fem")
                .join(file),
        )
    }

    /// The scene: 1D: 3 points held at each end; 2D: every point up to the supports.
    pub fn scene(&self) -> Scene {
        parse(&self.text(), "bimaterial")
    }

    /// The scene's TOML text.
    pub fn text(&self) -> String {
        let (a, b) = (self.innermost_left(), self.innermost_right());
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
        format!(
            r#"
            name = "bimaterial"{correction}
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
            correction = if self.surface_correction {
                ""
            } else {
                "\n            [discretization]\n            surface_correction = \"none\""
            },
        )
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

/// Loading of the plate with a hole.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum HoleLoad {
    /// Traction P on the left and right edges (issue 3's statement).
    Uniaxial,
    /// Tension P on the left and right edges, compression P on the top and bottom
    /// (the loading that reproduces 001 Table 1's Abaqus figures).
    TensionCompression,
}

/// Plate with a hole (001 Sec. 6.3): [−0.5, 0.5]², hole radius 0.125 m, E = 30 GPa,
/// ν = 1/3, P = 1 MPa, plane stress. The loads are self-equilibrated, so the plate
/// is held statically determinately (both components of the point nearest
/// (−0.5, 0), the y component of the point nearest (0.5, 0)): the supports carry
/// no force and the solution is the free plate's up to a rigid motion, which
/// [`remove_rigid_motion`] takes out before comparing.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlateWithHole {
    /// Grid spacing.
    pub spacing: f64,
    /// δ/Δx.
    pub horizon_factor: f64,
    /// Shear-deformation model instead of bond-based.
    pub shear: bool,
    /// Loading.
    pub load: HoleLoad,
}

/// Pressure on the plate with a hole (Pa).
pub const HOLE_TRACTION: f64 = 1e6;

impl PlateWithHole {
    /// The scene (plane stress, ν = 1/3, as in the paper).
    pub fn scene(&self) -> Scene {
        parse(
            &self.text("plane_stress", 1.0 / 3.0, false),
            "plate_with_hole",
        )
    }

    /// The same plate in plane strain with Poisson ratio `nu` (the stability
    /// suite's near-incompressible cases, `validation/stability/fem`).
    pub fn plane_strain_scene(&self, nu: f64) -> Scene {
        parse(&self.text("plane_strain", nu, false), "plate_with_hole")
    }

    /// The scene's TOML text in `dimension` with Poisson ratio `nu`; `gradient`
    /// selects the shear model's gradient dilatation.
    pub fn text(&self, dimension: &str, nu: f64, gradient: bool) -> String {
        let h = self.spacing;
        let p = HOLE_TRACTION;
        let kind = if self.shear { "shear" } else { "bond_based" };
        let mut text = format!(
            r#"
            name = "plate_with_hole"
            [model]
            dimension = "{dimension}"
            kind = "{kind}"{dilatation}
            [discretization]
            horizon_factor = {m}
            [materials.concrete]
            youngs_modulus = 30e9
            poisson_ratio = {nu:?}
            [[regions]]
            material = "concrete"
            spacing = {h}
            box = {{ min = [-0.5, -0.5], max = [0.5, 0.5] }}
            [[holes]]
            center = [0.0, 0.0]
            radius = 0.125
            [[boundary]]
            name = "pin"
            box = {{ min = [-0.5, 0.0], max = [{pin_x}, {h}] }}
            displacement = {{ x = 0.0, y = 0.0 }}
            [[boundary]]
            name = "roller"
            box = {{ min = [{roller_x}, 0.0], max = [0.5, {h}] }}
            displacement = {{ y = 0.0 }}
            [[loads]]
            name = "left"
            kind = "traction"
            face = "-x"
            value = [-{p}, 0.0]
            [[loads]]
            name = "right"
            kind = "traction"
            face = "+x"
            value = [{p}, 0.0]
            "#,
            m = self.horizon_factor,
            pin_x = -0.5 + h,
            roller_x = 0.5 - h,
            dilatation = if gradient {
                "\n            formulation = \"paper\"\n            dilatation = \"gradient\""
            } else {
                ""
            },
        );
        if self.load == HoleLoad::TensionCompression {
            text += &format!(
                "[[loads]]\nname = \"bottom\"\nkind = \"traction\"\nface = \"-y\"\nvalue = [0.0, {p}]\n\
                 [[loads]]\nname = \"top\"\nkind = \"traction\"\nface = \"+y\"\nvalue = [0.0, -{p}]\n"
            );
        }
        text += "[output]\nstress = true\n";
        text
    }
}

/// Plate under tension with two regions (004 Sec. 5.1): 1 m × 1 m, plane stress,
/// E = 200 GPa, ν = 1/3, spacing 0.005 m (left half) and 0.01 m (right half),
/// δ = n Δx of each region; the clamp is a fictitious strip of `layers` point
/// columns outside the plate (004's boundary region), 200 MPa on the right edge.
pub fn plate_tension_text(kind: &str, n: f64, layers: usize) -> String {
    let (dx_left, dx_right, traction) = (0.005, 0.01, 2e8);
    let x_f = -(layers as f64) * dx_left;
    format!(
        r#"
        name = "plate_tension"
        [model]
        dimension = "plane_stress"
        kind = "{kind}"
        [discretization]
        horizon_factor = {n}
        [materials.region1]
        youngs_modulus = 200e9
        poisson_ratio = 0.3333333333333333
        [materials.region2]
        youngs_modulus = 200e9
        poisson_ratio = 0.3333333333333333
        # fictitious clamp region outside the plate
        [[regions]]
        material = "region1"
        spacing = {dx_left}
        box = {{ min = [{x_f}, 0.0], max = [0.0, 1.0] }}
        [[regions]]
        material = "region1"
        spacing = {dx_left}
        box = {{ min = [0.0, 0.0], max = [0.5, 1.0] }}
        [[regions]]
        material = "region2"
        spacing = {dx_right}
        box = {{ min = [0.5, 0.0], max = [1.0, 1.0] }}
        [[boundary]]
        name = "clamp"
        box = {{ min = [{x_f}, 0.0], max = [0.0, 1.0] }}
        displacement = {{ x = 0.0, y = 0.0 }}
        [[loads]]
        name = "pull"
        kind = "traction"
        face = "+x"
        value = [{traction}, 0.0]
        [output]
        vtu = false
        points_csv = false
        "#
    )
}

/// Parses and validates a generated scene (relative paths: none).
fn parse(text: &str, name: &str) -> Scene {
    let spec = parse_spec(text, false).expect("generated scene parses");
    Scene::try_from_spec(spec, Path::new("."), name).expect("generated scene is valid")
}

/// Subtracts the volume-weighted mean translation and rotation (2D) from `u`.
pub fn remove_rigid_motion(x: &[[f64; 3]], volume: &[f64], u: &mut [[f64; 3]]) {
    let total: f64 = volume.iter().sum();
    let mean =
        |f: &dyn Fn(usize) -> f64| (0..x.len()).map(|i| volume[i] * f(i)).sum::<f64>() / total;
    let c = [mean(&|i| x[i][0]), mean(&|i| x[i][1])];
    let t = [mean(&|i| u[i][0]), mean(&|i| u[i][1])];
    let r2 = mean(&|i| (x[i][0] - c[0]).powi(2) + (x[i][1] - c[1]).powi(2));
    let w =
        mean(&|i| (x[i][0] - c[0]) * (u[i][1] - t[1]) - (x[i][1] - c[1]) * (u[i][0] - t[0])) / r2;
    for i in 0..x.len() {
        u[i][0] -= t[0] - w * (x[i][1] - c[1]);
        u[i][1] -= t[1] + w * (x[i][0] - c[0]);
    }
}

/// Errors of a plate-with-hole solution against its FEM reference.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct HoleComparison {
    /// Points compared (those where the FEM grid can be interpolated).
    pub points: usize,
    /// `‖u − u_FEM‖₂ / ‖u_FEM‖₂` over those points (rigid motion removed).
    pub l2_displacement: f64,
    /// The same over points farther than one horizon from every boundary.
    pub l2_displacement_interior: f64,
    /// `(max|u| − max|u_FEM|) / max|u_FEM|`.
    pub max_displacement_error: f64,
    /// σ_xx at the top of the hole (mean of the two points nearest (0, r)): dhpd, FEM there.
    pub sxx_hole_top: [f64; 2],
    /// σ_yy at the side of the hole (mean of the two points nearest (r, 0)): dhpd, FEM there.
    pub syy_hole_side: [f64; 2],
    /// Largest |σ_xx| over the plate: dhpd, FEM (the paper's measure).
    pub sxx_max: [f64; 2],
    /// Largest |σ_yy| over the plate: dhpd, FEM.
    pub syy_max: [f64; 2],
}

/// Compares a plate-with-hole solution with a FEM reference (`validation/plate_with_hole/fem`).
pub fn compare_plate(
    s: &StaticSolution,
    reference: &crate::reference::FemReference,
) -> HoleComparison {
    let p = &s.disc.points;
    let mut u = s.u.clone();
    remove_rigid_motion(&p.x, &p.volume, &mut u);
    let grid = &reference.grid;
    let (mut num, mut den, mut num_in, mut den_in, mut count) = (0.0, 0.0, 0.0, 0.0, 0);
    for i in 0..p.len() {
        let [x, y, _] = p.x[i];
        let (Some(fx), Some(fy)) = (grid.interpolate("ux", x, y), grid.interpolate("uy", x, y))
        else {
            continue;
        };
        let e2 = (u[i][0] - fx).powi(2) + (u[i][1] - fy).powi(2);
        let r2 = fx * fx + fy * fy;
        num += e2;
        den += r2;
        count += 1;
        let clearance = (0.5 - x.abs())
            .min(0.5 - y.abs())
            .min((x * x + y * y).sqrt() - 0.125);
        if clearance > p.horizon[i] {
            num_in += e2;
            den_in += r2;
        }
    }
    let max_u = u
        .iter()
        .map(|v| (v[0] * v[0] + v[1] * v[1]).sqrt())
        .fold(0.0, f64::max);
    let fem_max_u = reference.max_abs_u.unwrap_or(f64::NAN);
    let (mut sxx_top, mut syy_side, mut sxx_max, mut syy_max) =
        ([0.0; 2], [0.0; 2], [0.0; 2], [0.0; 2]);
    if let Some(stress) = &s.stress {
        // The row of points just outside the hole on the axes.
        let nearest = |axis: usize| {
            let other = 1 - axis;
            let candidates: Vec<usize> = (0..p.len())
                .filter(|&i| p.x[i][other].abs() < p.spacing[i] && p.x[i][axis] > 0.0)
                .collect();
            let lowest = candidates
                .iter()
                .map(|&i| p.x[i][axis])
                .fold(f64::INFINITY, f64::min);
            let row: Vec<usize> = candidates
                .into_iter()
                .filter(|&i| p.x[i][axis] <= lowest + 1e-12)
                .collect();
            (row.clone(), lowest)
        };
        let (top, y_top) = nearest(1);
        let (side, x_side) = nearest(0);
        sxx_top[0] = top.iter().map(|&i| stress[i][0][0]).sum::<f64>() / top.len() as f64;
        sxx_top[1] = reference
            .profile_at("x=0", "y", "sxx", y_top)
            .unwrap_or(f64::NAN);
        syy_side[0] = side.iter().map(|&i| stress[i][1][1]).sum::<f64>() / side.len() as f64;
        syy_side[1] = reference
            .profile_at("y=0", "x", "syy", x_side)
            .unwrap_or(f64::NAN);
        let largest = |f: &dyn Fn(&[[f64; 3]; 3]) -> f64| {
            stress.iter().map(|s| f(s).abs()).fold(0.0, f64::max)
        };
        let fem_largest = |field: &str| {
            grid.fields.get(field).map_or(f64::NAN, |rows| {
                rows.iter()
                    .flatten()
                    .flatten()
                    .fold(0.0, |m: f64, v| m.max(v.abs()))
            })
        };
        sxx_max = [largest(&|s| s[0][0]), fem_largest("sxx")];
        syy_max = [largest(&|s| s[1][1]), fem_largest("syy")];
    }
    HoleComparison {
        points: count,
        l2_displacement: (num / den).sqrt(),
        l2_displacement_interior: (num_in / den_in).sqrt(),
        max_displacement_error: max_u / fem_max_u - 1.0,
        sxx_hole_top: sxx_top,
        syy_hole_side: syy_side,
        sxx_max,
        syy_max,
    }
}
