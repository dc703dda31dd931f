//! What to write (`[output]`): the point files, stress recovery, the linear
//! system, line profiles, probes and, for fracture and explicit runs, the
//! steps of the VTU series.

use super::fields::{coords, name};
use super::spec::OutputSpec;
use crate::error::InputError;

/// A validated line profile.
#[derive(Debug, Clone, PartialEq)]
pub struct Profile {
    /// Name (safe as a file name).
    pub name: String,
    /// Start.
    pub from: [f64; 3],
    /// End.
    pub to: [f64; 3],
}

/// A validated probe.
#[derive(Debug, Clone, PartialEq)]
pub struct Probe {
    /// Name.
    pub name: String,
    /// Location.
    pub at: [f64; 3],
}

/// What to write.
#[derive(Debug, Clone, PartialEq)]
pub struct OutputSettings {
    /// `points.vtu`.
    pub vtu: bool,
    /// `points.csv`.
    pub points_csv: bool,
    /// Stress recovery.
    pub stress: bool,
    /// `K.mtx`, `f.mtx`.
    pub matrix_market: bool,
    /// Profiles.
    pub profiles: Vec<Profile>,
    /// Probes.
    pub probes: Vec<Probe>,
    /// Fracture runs: a VTU file every this many steps.
    pub every: Option<usize>,
    /// Fracture runs: a VTU file at these steps.
    pub steps: Vec<usize>,
}

/// Validates `[output]` of a `d`-dimensional scene.
pub(super) fn validate(o: &OutputSpec, d: usize) -> Result<OutputSettings, InputError> {
    let mut profiles = Vec::new();
    for (k, p) in o.profiles.iter().enumerate() {
        let f = format!("output.profiles[{k}]");
        name(&format!("{f}.name"), &p.name)?;
        if o.profiles[..k].iter().any(|q| q.name == p.name) {
            return Err(InputError::new(
                format!("{f}.name"),
                format!("\"{}\" is used twice", p.name),
            ));
        }
        let (from, to) = (
            coords(&format!("{f}.from"), &p.from, d)?,
            coords(&format!("{f}.to"), &p.to, d)?,
        );
        if from == to {
            return Err(InputError::new(f, "from and to coincide"));
        }
        profiles.push(Profile {
            name: p.name.clone(),
            from,
            to,
        });
    }
    let mut probes = Vec::new();
    for (k, p) in o.probes.iter().enumerate() {
        let f = format!("output.probes[{k}]");
        name(&format!("{f}.name"), &p.name)?;
        if o.probes[..k].iter().any(|q| q.name == p.name) {
            return Err(InputError::new(
                format!("{f}.name"),
                format!(
                    "\"{}\" is used twice (each probe is a column of probes.csv)",
                    p.name
                ),
            ));
        }
        probes.push(Probe {
            name: p.name.clone(),
            at: coords(&format!("{f}.at"), &p.at, d)?,
        });
    }
    if o.every == Some(0) {
        return Err(InputError::new(
            "output.every",
            "0 steps; give a positive number of steps",
        ));
    }
    Ok(OutputSettings {
        every: o.every,
        steps: o.steps.clone(),
        vtu: o.vtu,
        points_csv: o.points_csv,
        stress: o.stress,
        matrix_market: o.matrix_market,
        profiles,
        probes,
    })
}
