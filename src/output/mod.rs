//! Observers: VTK, CSV, JSON summary and Matrix Market, written atomically.
//!
//! Everything goes into a temporary sibling directory that is renamed to the
//! requested one only when complete, so a failed run leaves no partial result.

pub mod csv;
pub mod matrix_market;
pub mod summary;
pub mod vtu;

use crate::discretization::Discretization;
use crate::drivers::static_solve::StaticSolution;
use crate::error::{Error, InputError};
use crate::geometry::{dot, norm, sub};
use crate::scene::Scene;
use std::path::{Path, PathBuf};

/// The points each requested profile and probe reads, resolved before solving.
#[derive(Debug, Clone, PartialEq)]
pub struct Plan {
    /// Per profile: `(name, [(arc length, point)])` sorted by arc length.
    pub profiles: Vec<(String, Vec<(f64, usize)>)>,
    /// Per probe: `(name, nearest point)`.
    pub probes: Vec<(String, usize)>,
}

impl Plan {
    /// Selects the profile and probe points; a profile that selects no point is an input error.
    pub fn new(scene: &Scene, disc: &Discretization) -> Result<Self, InputError> {
        let x = &disc.points.x;
        let mut profiles = Vec::new();
        for (k, p) in scene.output.profiles.iter().enumerate() {
            let dir = sub(&p.to, &p.from);
            let len = norm(&dir);
            let mut pts: Vec<(f64, usize)> = (0..x.len())
                .filter_map(|i| {
                    let rel = sub(&x[i], &p.from);
                    let s = dot(&rel, &dir) / len;
                    let off = sub(&rel, &std::array::from_fn(|a| s * dir[a] / len));
                    let tol = 0.5 * disc.points.spacing[i] * (1.0 + 1e-9);
                    (s >= -tol && s <= len + tol && norm(&off) <= tol).then_some((s, i))
                })
                .collect();
            if pts.is_empty() {
                return Err(InputError::new(
                    format!("output.profiles[{k}]"),
                    format!(
                        "profile \"{}\" passes within half a spacing of no point",
                        p.name
                    ),
                ));
            }
            pts.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            profiles.push((p.name.clone(), pts));
        }
        let probes = scene
            .output
            .probes
            .iter()
            .map(|p| {
                let nearest = (0..x.len())
                    .min_by(|&a, &b| norm(&sub(&x[a], &p.at)).total_cmp(&norm(&sub(&x[b], &p.at))))
                    .unwrap_or(0);
                (p.name.clone(), nearest)
            })
            .collect();
        Ok(Plan { profiles, probes })
    }
}

/// Writes every requested output of a static run into `dir`, atomically.
pub fn write_static(
    dir: &Path,
    scene: &Scene,
    plan: &Plan,
    solution: &StaticSolution,
    total_seconds: f64,
) -> Result<(), Error> {
    let tmp = temporary_sibling(dir);
    let _ = std::fs::remove_dir_all(&tmp);
    let result = (|| {
        std::fs::create_dir_all(&tmp).map_err(|e| Error::io(&tmp, e))?;
        if scene.output.vtu {
            vtu::write(&tmp.join("points.vtu"), scene, solution)?;
        }
        if scene.output.points_csv {
            csv::write_points(&tmp.join("points.csv"), scene, solution)?;
        }
        for (name, pts) in &plan.profiles {
            csv::write_profile(
                &tmp.join(format!("profile_{name}.csv")),
                scene,
                solution,
                pts,
            )?;
        }
        if !plan.probes.is_empty() {
            csv::write_probes(&tmp.join("probes.csv"), scene, solution, &plan.probes)?;
        }
        if scene.output.matrix_market {
            matrix_market::write(&tmp, &solution.system)?;
        }
        summary::write(&tmp.join("summary.json"), scene, solution, total_seconds)
    })();
    if let Err(e) = result {
        let _ = std::fs::remove_dir_all(&tmp);
        return Err(e);
    }
    check_output_dir(dir)?;
    let old = dir.with_file_name(format!(".{}.old-{}", file_name(dir), std::process::id()));
    let replacing = dir.exists();
    if replacing {
        std::fs::rename(dir, &old).map_err(|e| Error::io(dir, e))?;
    }
    if let Err(e) = std::fs::rename(&tmp, dir) {
        if replacing {
            let _ = std::fs::rename(&old, dir);
        }
        let _ = std::fs::remove_dir_all(&tmp);
        return Err(Error::io(dir, e));
    }
    if replacing {
        let _ = std::fs::remove_dir_all(&old);
    }
    Ok(())
}

/// Checks that `dir` may receive results: it must not exist, or be an empty
/// directory, or hold a previous dhpd result (`summary.json`); it may not be the
/// working directory or one of its ancestors. Call it before solving.
pub fn check_output_dir(dir: &Path) -> Result<(), InputError> {
    let refuse = |why: String| {
        InputError::new(
            "--out",
            format!("refusing to write results to {}: {why}", dir.display()),
        )
    };
    match dir.file_name().and_then(|n| n.to_str()) {
        Some(n) if n != "." && n != ".." => {}
        _ => {
            return Err(refuse(
                "give a directory name (not '.', '..' or a root)".into(),
            ))
        }
    }
    if !dir.exists() {
        return Ok(());
    }
    if !dir.is_dir() {
        return Err(refuse("it exists and is not a directory".into()));
    }
    if let (Ok(target), Ok(cwd)) = (
        dir.canonicalize(),
        std::env::current_dir().and_then(|c| c.canonicalize()),
    ) {
        if cwd.starts_with(&target) {
            return Err(refuse("it is the working directory or contains it".into()));
        }
    }
    let empty = std::fs::read_dir(dir)
        .map(|mut entries| entries.next().is_none())
        .unwrap_or(false);
    if !empty && !dir.join("summary.json").is_file() {
        return Err(refuse("it exists, is not empty and holds no dhpd result (summary.json); it is replaced only then".into()));
    }
    Ok(())
}

fn file_name(dir: &Path) -> String {
    dir.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "out".into())
}

fn temporary_sibling(dir: &Path) -> PathBuf {
    dir.with_file_name(format!(
        ".{}.partial-{}",
        file_name(dir),
        std::process::id()
    ))
}

/// Writes `text` to `path`, mapping errors.
pub(crate) fn write_file(path: &Path, text: &str) -> Result<(), Error> {
    std::fs::write(path, text).map_err(|e| Error::io(path, e))
}
