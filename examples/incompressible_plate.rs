//! Near-incompressibility study (issue 4): the plate with a hole in plane
//! strain, shear model, ν = 0.3 … 0.4999, with the paper's weighted dilatation
//! and with the gradient dilatation, against the Taylor–Hood references of
//! `validation/stability/fem`. Prints one Markdown row per case and writes
//! `validation/stability/results/plate_plane_strain_dx<Δx>.csv`.
//!
//! ```text
//! cargo run --release --example incompressible_plate            # Δx = 0.005 m (the paper's), ~10 min
//! cargo run --release --example incompressible_plate -- 0.01    # coarse, ~1.5 min
//! ```

use dhpd::reference::FemReference;
use dhpd::validation::{compare_plate, HoleLoad, PlateWithHole};
use std::fmt::Write;
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let spacing: f64 = match std::env::args().nth(1) {
        Some(a) => a
            .parse()
            .map_err(|_| format!("spacing: {a:?} is not a number"))?,
        None => 0.005,
    };
    let case = PlateWithHole {
        spacing,
        horizon_factor: 3.015,
        shear: true,
        load: HoleLoad::Uniaxial,
    };
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("validation/stability");
    let mut csv = String::from(
        "spacing,nu,dilatation,points,residual,l2_u,l2_u_interior,max_u_error,sxx_hole_top_error,\
         syy_hole_side_error,sxx_max_error,gmres_iterations,seconds\n",
    );
    println!("| ν | dilatation | residual | L2(u) | max\\|u\\| | σxx hole top | max\\|σxx\\| | solver | time (s) |");
    println!("|---|---|---|---|---|---|---|---|---|");
    for label in ["0.3", "0.45", "0.49", "0.499", "0.4999"] {
        let reference =
            FemReference::from_file(&root.join(format!("fem/reference_nu{label}.json")))?;
        for gradient in [false, true] {
            let mut scene = case.plane_strain_scene(label.parse()?);
            scene.model.dilatation = if gradient {
                dhpd::scene::Dilatation::Gradient
            } else {
                dhpd::scene::Dilatation::Weighted
            };
            let t = Instant::now();
            let s = dhpd::drivers::static_solve::solve(&scene)?;
            let seconds = t.elapsed().as_secs_f64();
            let c = compare_plate(&s, &reference);
            let rel = |pair: [f64; 2]| pair[0] / pair[1] - 1.0;
            let dilatation = if gradient { "gradient" } else { "weighted" };
            let solver = match s.counts.gmres {
                Some(g) if g.stagnated => format!("GMRES {} its (round-off floor)", g.iterations),
                Some(g) => format!("GMRES {} its", g.iterations),
                None => format!("LU, {} refinement step(s)", s.counts.refinement_steps),
            };
            println!(
                "| {label} | {dilatation} | {:.1e} | {:.2} % | {:+.2} % | {:+.1} % | {:+.1} % | {solver} | {seconds:.1} |",
                s.residual,
                100.0 * c.l2_displacement,
                100.0 * c.max_displacement_error,
                100.0 * rel(c.sxx_hole_top),
                100.0 * rel(c.sxx_max),
            );
            writeln!(
                csv,
                "{spacing},{label},{dilatation},{},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{},{seconds:.3}",
                c.points,
                s.residual,
                c.l2_displacement,
                c.l2_displacement_interior,
                c.max_displacement_error,
                rel(c.sxx_hole_top),
                rel(c.syy_hole_side),
                rel(c.sxx_max),
                s.counts.gmres.map_or(0, |g| g.iterations),
            )?;
        }
    }
    let dir = root.join("results");
    std::fs::create_dir_all(&dir)?;
    std::fs::write(dir.join(format!("plate_plane_strain_dx{spacing}.csv")), csv)?;
    Ok(())
}
