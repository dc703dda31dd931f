//! The VTU series of a fracture or explicit run: a file `step_NNNNNN.vtu` for
//! every snapshot the scene's output asks for (`output.every`, `output.steps`),
//! listed in `series.pvd` by load factor or time.

use super::{vtu, PointData};
use crate::drivers::Snapshot;
use crate::error::Error;
use std::path::{Path, PathBuf};

/// Writes the series' step files into a directory.
pub(crate) struct Series {
    dir: PathBuf,
    /// `(timestep, file)` of every step file written.
    entries: Vec<(f64, String)>,
}

impl Series {
    /// Writes into `dir`.
    pub(crate) fn new(dir: &Path) -> Self {
        Self {
            dir: dir.to_path_buf(),
            entries: Vec::new(),
        }
    }

    /// Writes the step file of `s` (displacement, damage; velocity in dynamics;
    /// stress when asked).
    pub(crate) fn write(&mut self, s: &Snapshot) -> Result<(), Error> {
        let file = format!("step_{:06}.vtu", s.step);
        vtu::write(
            &self.dir.join(&file),
            &PointData {
                disc: s.disc,
                u: s.u,
                velocity: s.velocity,
                stress: s.stress,
                damage: Some(s.damage),
                bond_counts: s.bond_counts,
            },
        )?;
        self.entries.push((s.timestep, file));
        Ok(())
    }

    /// Writes `series.pvd` when a step file was written.
    pub(crate) fn finish(&self) -> Result<(), Error> {
        if self.entries.is_empty() {
            return Ok(());
        }
        vtu::write_collection(&self.dir.join("series.pvd"), &self.entries)
    }
}
