//! CSV files: all point fields, line profiles and probes.

use super::PointData;
use crate::drivers::quasi_static::QuasiStaticSolution;
use crate::error::{Error, NumericalError};
use crate::scene::Scene;
use std::fmt::Write;
use std::path::Path;

const AXES: [&str; 3] = ["x", "y", "z"];

pub(crate) fn header(d: usize, prefix: &str) -> String {
    AXES[..d]
        .iter()
        .map(|a| format!("{prefix}{a}"))
        .collect::<Vec<_>>()
        .join(",")
}

pub(crate) fn row(values: &[f64; 3], d: usize) -> String {
    values[..d]
        .iter()
        .map(|v| format!("{v:e}"))
        .collect::<Vec<_>>()
        .join(",")
}

/// Writes `points.csv`: id, position, displacement, volume, spacing, horizon,
/// material, bond count (intact bonds touching the point), then the stress
/// and the damage when present.
pub fn write_points(path: &Path, scene: &Scene, s: &PointData) -> Result<(), Error> {
    let d = s.disc.d;
    let p = &s.disc.points;
    let bonds = s.bond_counts();
    let components = stress_components(d);
    let stress_header: String = components
        .iter()
        .map(|(name, _, _)| format!(",{name}"))
        .collect();
    let velocity_header = match s.velocity {
        Some(_) => format!(",{}", header(d, "v_")),
        None => String::new(),
    };
    let mut t = format!(
        "id,{},{}{velocity_header},volume,spacing,horizon,material,bond_count{}{}\n",
        header(d, ""),
        header(d, "u_"),
        if s.stress.is_some() {
            stress_header.as_str()
        } else {
            ""
        },
        if s.damage.is_some() { ",damage" } else { "" }
    );
    for i in 0..p.len() {
        let stress: String = match &s.stress {
            Some(sigma) => components
                .iter()
                .map(|&(_, r, c)| format!(",{:e}", sigma[i][r][c]))
                .collect(),
            None => String::new(),
        };
        let damage = s
            .damage
            .map_or(String::new(), |phi| format!(",{:e}", phi[i]));
        let velocity = s
            .velocity
            .map_or(String::new(), |v| format!(",{}", row(&v[i], d)));
        let _ = writeln!(
            t,
            "{i},{},{}{velocity},{:e},{:e},{:e},{},{}{stress}{damage}",
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
pub fn write_profile(path: &Path, s: &PointData, points: &[(f64, usize)]) -> Result<(), Error> {
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
pub fn write_probes(path: &Path, s: &PointData, probes: &[(String, usize)]) -> Result<(), Error> {
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

/// Writes `load_displacement.csv`: one row per record of a quasi-static run
/// (step, state, load factor, prescribed displacement, reaction components of
/// every constrained set, bonds broken in the step and in total, re-solves,
/// solver route and iterations, residual, wall time).
pub fn write_load_displacement(path: &Path, s: &QuasiStaticSolution) -> Result<(), Error> {
    let d = s.disc.d;
    let reaction_header: String = s
        .set_names
        .iter()
        .map(|name| format!(",{}", header(d, &format!("reaction_{name}_"))))
        .collect();
    let mut t = format!(
        "step,state,load_factor,displacement{reaction_header},broken_in_step,broken_total,\
         resolves,route,iterations,residual,wall_time\n"
    );
    for r in &s.records {
        let reactions: String = r
            .reactions
            .iter()
            .map(|f| format!(",{}", row(f, d)))
            .collect();
        let named = [
            ("load_factor", r.load_factor),
            ("displacement", r.displacement),
            ("residual", r.residual),
            ("wall_time", r.wall_time),
        ];
        let reactions_named = s.set_names.iter().zip(&r.reactions).flat_map(|(name, f)| {
            AXES[..d]
                .iter()
                .zip(f)
                .map(move |(a, v)| (format!("reaction_{name}_{a}"), *v))
        });
        if let Some((column, value)) = named
            .iter()
            .map(|(c, v)| (c.to_string(), *v))
            .chain(reactions_named)
            .find(|(_, v)| !v.is_finite())
        {
            return Err(NumericalError::NonFinite {
                what: format!(
                    "{column} ({value}) of step {} to be written to {}; nothing was written",
                    r.step,
                    path.display()
                ),
            }
            .into());
        }
        let state = serde_json::to_value(r.state)
            .ok()
            .and_then(|v| v.as_str().map(str::to_owned))
            .unwrap_or_default();
        let _ = writeln!(
            t,
            "{},{state},{:e},{:e}{reactions},{},{},{},{},{},{:e},{:.6}",
            r.step,
            r.load_factor,
            r.displacement,
            r.broken_in_step,
            r.broken_total,
            r.resolves,
            r.route,
            r.iterations,
            r.residual,
            r.wall_time
        );
    }
    super::write_file(path, &t)
}
