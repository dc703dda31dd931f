//! The plate with a hole on imported Gmsh meshes (issue 10) against the
//! scikit-fem reference: the scenes of `validation/plate_with_hole/gmsh/`
//! (unstructured triangles and quadrangles, one point per cell), both models.
//! Prints a Markdown table and writes `validation/plate_with_hole/results/mesh_study.csv`.
//!
//! ```text
//! cargo run --release --example mesh_plate                  # every scene of the folder
//! cargo run --release --example mesh_plate -- SCENE.toml    # given scenes
//! ```

use dhpd::reference::FemReference;
use dhpd::validation::compare_plate;
use std::fmt::Write;
use std::path::{Path, PathBuf};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = Path::new("validation/plate_with_hole/gmsh");
    let mut scenes: Vec<PathBuf> = std::env::args().skip(1).map(PathBuf::from).collect();
    if scenes.is_empty() {
        scenes = std::fs::read_dir(dir)?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|e| e == "toml"))
            .collect();
        scenes.sort();
    }
    let reference =
        FemReference::from_file(Path::new("validation/plate_with_hole/fem/reference.json"))?;
    let mut csv = String::from(
        "scene,points,bonds,l2_u,l2_u_interior,max_u_error,sxx_top,sxx_top_fem,syy_side,syy_side_fem,support_force,t_total\n",
    );
    println!("| scene | points | L2(u) | L2(u) interior | max\\|u\\| | σxx hole top dhpd / FEM (MPa) | largest support force / P·L | total (s) |");
    println!("|---|---|---|---|---|---|---|---|");
    for path in &scenes {
        let t = std::time::Instant::now();
        let scene = dhpd::scene::load(path)?;
        let s = dhpd::drivers::static_solve::solve(&scene)?;
        let total = t.elapsed().as_secs_f64();
        let c = compare_plate(&s, &reference);
        let support = s
            .reactions
            .iter()
            .flat_map(|r| r.force)
            .fold(0.0, |m: f64, f| m.max(f.abs()))
            / dhpd::validation::HOLE_TRACTION;
        let stress = |a: [f64; 2]| {
            if s.stress.is_some() {
                format!("{:.3} / {:.3}", a[0] / 1e6, a[1] / 1e6)
            } else {
                "-".into()
            }
        };
        println!(
            "| {} | {} | {:.2} % | {:.2} % | {:+.2} % | {} | {:.1e} | {:.2} |",
            scene.name,
            s.counts.points,
            100.0 * c.l2_displacement,
            100.0 * c.l2_displacement_interior,
            100.0 * c.max_displacement_error,
            stress(c.sxx_hole_top),
            support,
            total
        );
        let _ = writeln!(
            csv,
            "{},{},{},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{}",
            scene.name,
            s.counts.points,
            s.counts.bonds,
            c.l2_displacement,
            c.l2_displacement_interior,
            c.max_displacement_error,
            c.sxx_hole_top[0],
            c.sxx_hole_top[1],
            c.syy_hole_side[0],
            c.syy_hole_side[1],
            support,
            total
        );
    }
    std::fs::write("validation/plate_with_hole/results/mesh_study.csv", csv)?;
    Ok(())
}
