//! Bimaterial bar and strip validation study (issue 2; 000 Sec. 5.1).
//!
//! Runs the 1D bar (both spacing orders, DH-PD and the constant-horizon
//! baseline) against the series-spring solution, and the 2D strip at three
//! resolutions against the committed scikit-fem reference; prints Markdown
//! tables and writes CSV profiles for `validation/bimaterial_bar/plot.py`.
//!
//! ```text
//! cargo run --release --example bimaterial_bar
//! ```

use dhpd::reference::{ErrorStats, FemReference};
use dhpd::validation::{Bimaterial, BAR_DISPLACEMENT};
use std::fmt::Write;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::path::Path::new("validation/bimaterial_bar/results");
    std::fs::create_dir_all(out)?;

    println!("## 1D bar\n");
    println!("| spacing left/right (m) | horizons | max error interior | RMS interior | max error near layers | reaction error | time (s) |");
    println!("|---|---|---|---|---|---|---|");
    for (dl, dr) in [(0.01, 0.005), (0.005, 0.01)] {
        for constant in [false, true] {
            let case = Bimaterial {
                dx_left: dl,
                dx_right: dr,
                constant_horizon: constant,
                strip: false,
                surface_correction: true,
            };
            let t = std::time::Instant::now();
            let s = case.solve()?;
            let secs = t.elapsed().as_secs_f64();
            let (a, b) = (case.support_left(), case.support_right());
            let mut csv = String::from("x,u,u_exact\n");
            let (mut interior, mut near) = (Vec::new(), Vec::new());
            for (i, x) in s.disc.points.x.iter().enumerate() {
                let exact = case.series_displacement(x[0]);
                let _ = writeln!(csv, "{},{:e},{:e}", x[0], s.u[i][0], exact);
                if s.dofs.free_count(i) == 0 {
                    continue;
                }
                let far = x[0] > a + 3.015 * dl && x[0] < b - 3.015 * dr;
                if far { &mut interior } else { &mut near }.push((s.u[i][0], exact));
            }
            let name = format!(
                "bar1d_{}_{}.csv",
                if dl > dr { "coarse_left" } else { "fine_left" },
                if constant { "constant" } else { "dual" }
            );
            std::fs::write(out.join(name), csv)?;
            let (si, sn) = (
                ErrorStats::of(interior, BAR_DISPLACEMENT),
                ErrorStats::of(near, BAR_DISPLACEMENT),
            );
            let r = s.reaction("right").map_or(f64::NAN, |r| r[0]);
            let r_exact = case.series_reaction(1.0);
            println!(
                "| {dl} / {dr} | {} | {:.3} % | {:.3} % | {:.3} % | {:+.3} % | {secs:.4} |",
                if constant {
                    "constant (baseline)"
                } else {
                    "dual (DH-PD)"
                },
                100.0 * si.max_relative,
                100.0 * si.rms_relative,
                100.0 * sn.max_relative,
                100.0 * (r / r_exact - 1.0)
            );
        }
    }

    println!("\n## 2D strip (errors in % of the applied displacement; reaction against the FEM of the same supports)\n");
    println!("| refinement | spacing left/right (m) | points | centre line max | centre line RMS | all points max | all RMS | reaction | reaction error | neighbours | assembly | numeric Cholesky | total (s) |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for r in [1.0, 3.0] {
        let case = Bimaterial {
            dx_left: 0.01 / r,
            dx_right: 0.005 / r,
            constant_horizon: false,
            strip: true,
            surface_correction: true,
        };
        let reference = FemReference::from_json(&case.strip_reference()?)?;
        let fem_reaction = reference.reaction_x.unwrap_or(f64::NAN);
        let t = std::time::Instant::now();
        let s = case.solve()?;
        let secs = t.elapsed().as_secs_f64();
        let (mut centre, mut all) = (Vec::new(), Vec::new());
        let mut csv = String::from("x,y,u_x,u_x_fem\n");
        for (i, x) in s.disc.points.x.iter().enumerate() {
            if s.dofs.free_count(i) < 2 {
                continue;
            }
            let Some(fem) = reference.grid.interpolate("ux", x[0], x[1]) else {
                continue;
            };
            all.push((s.u[i][0], fem));
            if (x[1] - 0.05).abs() <= 0.5 * s.disc.points.spacing[i] + 1e-12 {
                centre.push((s.u[i][0], fem));
                let _ = writeln!(csv, "{},{},{:e},{:e}", x[0], x[1], s.u[i][0], fem);
            }
        }
        std::fs::write(out.join(format!("strip2d_r{r}.csv")), csv)?;
        let (c, a) = (
            ErrorStats::of(centre, BAR_DISPLACEMENT),
            ErrorStats::of(all, BAR_DISPLACEMENT),
        );
        let reaction = s.reaction("right").map_or(f64::NAN, |r| r[0]);
        let t = &s.timings;
        println!(
            "| {r} | {:.5} / {:.5} | {} | {:.3} % | {:.3} % | {:.3} % | {:.3} % | {reaction:.5e} | {:+.2} % | {:.3} | {:.3} | {:.3} | {secs:.3} |",
            case.dx_left, case.dx_right, s.counts.points, 100.0 * c.max_relative, 100.0 * c.rms_relative,
            100.0 * a.max_relative, 100.0 * a.rms_relative, 100.0 * (reaction / fem_reaction - 1.0),
            t.neighbour_search, t.pattern + t.assembly, t.numeric_factorization
        );
    }
    Ok(())
}
