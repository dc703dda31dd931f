//! The observer of a fracture run: a VTU file for every step the scene's output
//! asks for (`output.every`, `output.steps`), listed in `series.pvd` by load
//! factor, and progress on stderr (step, load factor, bonds broken, ETA): a bar
//! on a terminal, a line every 30 s otherwise ([`super::progress`]).

use super::progress::Progress;
use super::{vtu, PointData};
use crate::drivers::quasi_static::{Observer, Snapshot, StepRecord};
use crate::error::Error;
use std::path::{Path, PathBuf};

/// Writes the series' step files into a directory and shows progress.
pub struct SeriesWriter {
    dir: PathBuf,
    entries: Vec<(f64, String)>,
    progress: Progress,
    /// The run's maximal load factor (the ETA extrapolates by λ / max).
    max_load_factor: f64,
}

impl SeriesWriter {
    /// Writes into `dir`; `steps` is the number of load steps when known
    /// (stepped strategies; else events are counted).
    pub fn new(dir: &Path, steps: Option<u64>, max_load_factor: f64) -> Self {
        Self {
            dir: dir.to_path_buf(),
            entries: Vec::new(),
            progress: Progress::new(steps, if steps.is_some() { "step" } else { "event" }),
            max_load_factor,
        }
    }

    /// The `(load factor, file)` entries written so far; ends the progress bar.
    pub fn finish(mut self) -> Vec<(f64, String)> {
        self.progress.finish();
        self.entries
    }
}

impl Observer for SeriesWriter {
    fn record(&mut self, record: &StepRecord, snapshot: Option<&Snapshot>) -> Result<(), Error> {
        self.progress.update(
            record.step as u64,
            record.load_factor / self.max_load_factor,
            || {
                format!(
                    "load factor {:.4e} of {:.4e}, bonds broken {}",
                    record.load_factor, self.max_load_factor, record.broken_total
                )
            },
        );
        if let Some(s) = snapshot {
            let file = format!("step_{:06}.vtu", s.step);
            vtu::write(
                &self.dir.join(&file),
                &PointData {
                    disc: s.disc,
                    u: s.u,
                    velocity: None,
                    stress: None,
                    damage: Some(s.damage),
                },
            )?;
            self.entries.push((s.load_factor, file));
        }
        Ok(())
    }
}
