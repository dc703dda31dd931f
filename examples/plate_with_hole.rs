//! Plate with a hole (001 Sec. 6.3) against the scikit-fem reference, both models,
//! several spacings: errors and wall time per phase (issue 3).
//!
//! ```text
//! cargo run --release --example plate_with_hole -- [uniaxial|tension_compression] [gmres] [spacings...]
//! ```

use dhpd::reference::FemReference;
use dhpd::validation::{compare_plate, HoleLoad, PlateWithHole};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let load = if args.first().map(String::as_str) == Some("tension_compression") {
        HoleLoad::TensionCompression
    } else {
        HoleLoad::Uniaxial
    };
    let gmres = args.iter().any(|a| a == "gmres");
    let spacings: Vec<f64> = args.iter().filter_map(|a| a.parse().ok()).collect();
    let spacings = if spacings.is_empty() {
        vec![0.02, 0.01, 0.005]
    } else {
        spacings
    };
    let file = match load {
        HoleLoad::Uniaxial => "validation/plate_with_hole/fem/reference.json",
        HoleLoad::TensionCompression => {
            "validation/plate_with_hole/fem/reference_tension_compression.json"
        }
    };
    let reference = FemReference::from_file(std::path::Path::new(file))?;
    println!("| model | Δx (m) | points | L2(u) | L2(u) interior | max|u| | σxx hole top dhpd / FEM (MPa) | σyy hole side dhpd / FEM (MPa) | max|σxx| err | max|σyy| err | pattern+assembly (s) | factorisation (s) | total (s) |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for &spacing in &spacings {
        for shear in [false, true] {
            let case = PlateWithHole {
                spacing,
                horizon_factor: 3.015,
                shear,
                load,
            };
            let t = std::time::Instant::now();
            let mut scene = case.scene();
            if shear && gmres {
                scene.solver = dhpd::scene::SolverMethod::Gmres;
            }
            let s = dhpd::drivers::static_solve::solve(&scene)?;
            eprintln!(
                "asymmetry {:.3e}, gmres {:?}, residual {:.1e}",
                s.counts.asymmetry, s.counts.gmres, s.residual
            );
            let total = t.elapsed().as_secs_f64();
            let c = compare_plate(&s, &reference);
            let tm = &s.timings;
            let mpa = |v: f64| v / 1e6;
            println!(
                "| {} | {spacing} | {} | {:.2} % | {:.2} % | {:+.2} % | {} | {} | {} | {} | {:.3} | {:.3} | {:.3} |",
                if shear { "shear" } else { "bond-based" },
                s.counts.points,
                100.0 * c.l2_displacement,
                100.0 * c.l2_displacement_interior,
                100.0 * c.max_displacement_error,
                if shear { format!("{:.3} / {:.3}", mpa(c.sxx_hole_top[0]), mpa(c.sxx_hole_top[1])) } else { "-".into() },
                if shear { format!("{:.3} / {:.3}", mpa(c.syy_hole_side[0]), mpa(c.syy_hole_side[1])) } else { "-".into() },
                if shear { format!("{:+.1} %", 100.0 * (c.sxx_max[0] / c.sxx_max[1] - 1.0)) } else { "-".into() },
                if shear { format!("{:+.1} %", 100.0 * (c.syy_max[0] / c.syy_max[1] - 1.0)) } else { "-".into() },
                tm.pattern + tm.assembly,
                tm.symbolic_factorization + tm.numeric_factorization,
                total
            );
        }
    }
    Ok(())
}
