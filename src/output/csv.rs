//! CSV files: all point fields, line profiles and probes.

use crate::drivers::static_solve::StaticSolution;
use crate::error::Error;
use crate::scene::Scene;
use std::fmt::Write;
use std::path::Path;

const AXES: [&str; 3] = ["x", "y", "z"];

fn header(d: usize, prefix: &str) -> String {
    AXES[..d]
        .iter()
        .map(|a| format!("{prefix}{a}"))
        .collect::<Vec<_>>()
        .join(",")
}

fn row(values: &[f64; 3], d: usize) -> String {
    values[..d]
        .iter()
        .map(|v| format!("{v:e}"))
        .collect::<Vec<_>>()
        .join(",")
}

/// Writes `points.csv`: id, position, displacement, volume, spacing, horizon, material, bond count.
pub fn write_points(path: &Path, scene: &Scene, s: &StaticSolution) -> Result<(), Error> {
    let d = s.disc.d;
    let p = &s.disc.points;
    let bonds = s.disc.bonds.touch_counts(p.len());
    let components = stress_components(d);
    let stress_header: String = components
        .iter()
        .map(|(name, _, _)| format!(",{name}"))
        .collect();
    let mut t = format!(
        "id,{},{},volume,spacing,horizon,material,bond_count{}\n",
        header(d, ""),
        header(d, "u_"),
        if s.stress.is_some() {
            stress_header.as_str()
        } else {
            ""
        }
    );
    for i in 0..p.len() {
        let stress: String = match &s.stress {
            Some(sigma) => components
                .iter()
                .map(|&(_, r, c)| format!(",{:e}", sigma[i][r][c]))
                .collect(),
            None => String::new(),
        };
        let _ = writeln!(
            t,
            "{i},{},{},{:e},{:e},{:e},{},{}{stress}",
            row(&p.x[i], d),
            row(&s.u[i], d),
            p.volume[i],
            p.spacing[i],
            p.horizon[i],
            scene.materials[p.material[i] as usize].name,
            bonds[i]
        );
    }
    super::write_file(path, &t)
}

/// Names and indices of the independent stress components in `d` dimensions.
pub fn stress_components(d: usize) -> Vec<(&'static str, usize, usize)> {
    if d == 3 {
        vec![
            ("sxx", 0, 0),
            ("syy", 1, 1),
            ("szz", 2, 2),
            ("syz", 1, 2),
            ("sxz", 0, 2),
            ("sxy", 0, 1),
        ]
    } else {
        vec![("sxx", 0, 0), ("syy", 1, 1), ("sxy", 0, 1)]
    }
}

/// Writes one profile: arc length, point id, position, displacement.
pub fn write_profile(
    path: &Path,
    _scene: &Scene,
    s: &StaticSolution,
    points: &[(f64, usize)],
) -> Result<(), Error> {
    let d = s.disc.d;
    let mut t = format!("s,id,{},{}\n", header(d, ""), header(d, "u_"));
    for &(arc, i) in points {
        let _ = writeln!(
            t,
            "{arc:e},{i},{},{}",
            row(&s.disc.points.x[i], d),
            row(&s.u[i], d)
        );
    }
    super::write_file(path, &t)
}

/// Writes `probes.csv`: name, point id, position, displacement.
pub fn write_probes(
    path: &Path,
    _scene: &Scene,
    s: &StaticSolution,
    probes: &[(String, usize)],
) -> Result<(), Error> {
    let d = s.disc.d;
    let mut t = format!("name,id,{},{}\n", header(d, ""), header(d, "u_"));
    for (name, i) in probes {
        let _ = writeln!(
            t,
            "{name},{i},{},{}",
            row(&s.disc.points.x[*i], d),
            row(&s.u[*i], d)
        );
    }
    super::write_file(path, &t)
}
