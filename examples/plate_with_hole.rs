//! Plate with a hole (001 Sec. 6.3) against the scikit-fem reference: error
//! against wall time for both models over spacings Δx and horizon ratios
//! m = δ/Δx (issue 3). Prints a Markdown table and writes
//! `validation/plate_with_hole/results/study_<load>.csv`.
//!
//! ```text
//! cargo run --release --example plate_with_hole                       # uniaxial, Δx 0.02 0.01 0.005, m 2.015 3.015 4.015
//! cargo run --release --example plate_with_hole -- tension_compression m=3.015 0.02 0.01 0.005
//! cargo run --release --example plate_with_hole -- gradient m=3.015      # shear model with the surface correction
//! ```
//!
//! Errors: relative L2 of u over all compared points and over points farther than
//! one horizon from every boundary (rigid motion removed), max |u|, and σ at the
//! hole (pointwise at the first row of points, and the paper's max-over-plate
//! measure), for both models.

use dhpd::reference::FemReference;
use dhpd::validation::{compare_plate, HoleLoad, PlateWithHole};
use std::fmt::Write;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let gradient = args.iter().any(|a| a == "gradient");
    let load = if args.iter().any(|a| a == "tension_compression") {
        HoleLoad::TensionCompression
    } else {
        HoleLoad::Uniaxial
    };
    let mut spacings: Vec<f64> = args.iter().filter_map(|a| a.parse().ok()).collect();
    if spacings.is_empty() {
        spacings = vec![0.02, 0.01, 0.005];
    }
    let mut factors: Vec<f64> = args
        .iter()
        .filter_map(|a| a.strip_prefix("m=")?.parse().ok())
        .collect();
    if factors.is_empty() {
        factors = vec![2.015, 3.015, 4.015];
    }
    let (file, tag) = match load {
        HoleLoad::Uniaxial => ("validation/plate_with_hole/fem/reference.json", "uniaxial"),
        HoleLoad::TensionCompression => (
            "validation/plate_with_hole/fem/reference_tension_compression.json",
            "tension_compression",
        ),
    };
    let reference = FemReference::from_file(std::path::Path::new(file))?;
    let mut csv = String::from(
        "model,dx,m,points,dofs,l2_u,l2_u_interior,max_u_error,sxx_top,sxx_top_fem,syy_side,syy_side_fem,sxx_max_error,syy_max_error,\
         t_neighbours,t_pattern_assembly,t_factorization,t_solve,t_total,gmres_iterations\n",
    );
    println!("| model | Δx (m) | m | points | L2(u) | L2(u) interior | max|u| | σxx hole top dhpd / FEM (MPa) | σyy hole side dhpd / FEM (MPa) | max|σxx| | max|σyy| | pattern+assembly (s) | factorisation (s) | solve (s) | total (s) |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for &spacing in &spacings {
        for &m in &factors {
            for shear in [false, true] {
                let case = PlateWithHole {
                    spacing,
                    horizon_factor: m,
                    shear,
                    load,
                };
                let t = std::time::Instant::now();
                let mut scene = case.scene();
                scene.model.dilatation = if gradient {
                    dhpd::scene::Dilatation::Gradient
                } else {
                    dhpd::scene::Dilatation::Weighted
                };
                let s = dhpd::drivers::static_solve::solve(&scene)?;
                let total = t.elapsed().as_secs_f64();
                let c = compare_plate(&s, &reference);
                let tm = &s.timings;
                let model = if shear { "shear" } else { "bond_based" };
                let rel = |a: [f64; 2]| a[0] / a[1] - 1.0;
                let _ = writeln!(
                    csv,
                    "{model},{spacing},{m},{},{},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{},{},{},{},{},{}",
                    s.counts.points, s.counts.dofs, c.l2_displacement, c.l2_displacement_interior, c.max_displacement_error,
                    c.sxx_hole_top[0], c.sxx_hole_top[1], c.syy_hole_side[0], c.syy_hole_side[1],
                    rel(c.sxx_max), rel(c.syy_max),
                    tm.neighbour_search, tm.pattern + tm.assembly, tm.symbolic_factorization + tm.numeric_factorization, tm.solve, total,
                    s.counts.gmres.map_or(0, |g| g.iterations)
                );
                let mpa = |v: [f64; 2]| format!("{:.3} / {:.3}", v[0] / 1e6, v[1] / 1e6);
                let pct = |v: f64| format!("{:+.1} %", 100.0 * v);
                println!(
                    "| {model} | {spacing} | {m} | {} | {:.2} % | {:.2} % | {:+.2} % | {} | {} | {} | {} | {:.3} | {:.3} | {:.3} | {total:.3} |",
                    s.counts.points, 100.0 * c.l2_displacement, 100.0 * c.l2_displacement_interior, 100.0 * c.max_displacement_error,
                    mpa(c.sxx_hole_top),
                    mpa(c.syy_hole_side),
                    pct(rel(c.sxx_max)),
                    pct(rel(c.syy_max)),
                    tm.pattern + tm.assembly, tm.symbolic_factorization + tm.numeric_factorization, tm.solve
                );
            }
        }
    }
    let out = std::path::Path::new("validation/plate_with_hole/results");
    std::fs::create_dir_all(out)?;
    let suffix = if gradient { "_gradient" } else { "" };
    std::fs::write(out.join(format!("study_{tag}{suffix}.csv")), csv)?;
    Ok(())
}
