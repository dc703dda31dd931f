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
    let mut t = format!(
        "id,{},{},volume,spacing,horizon,material,bond_count\n",
        header(d, ""),
        header(d, "u_")
    );
    for i in 0..p.len() {
        let _ = writeln!(
            t,
            "{i},{},{},{:e},{:e},{:e},{},{}",
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
