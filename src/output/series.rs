//! The observer of a fracture run: a VTU file for every step the scene's output
//! asks for (`output.every`, `output.steps`), listed in `series.pvd` by load
//! factor, and a progress bar on stderr (step, load factor, bonds broken, ETA)
//! for runs longer than a few seconds, silent when stderr is not a terminal.

use super::{vtu, PointData};
use crate::drivers::quasi_static::{Observer, Snapshot, StepRecord};
use crate::error::Error;
use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// Runs shorter than this show no progress bar.
const QUIET_FOR: Duration = Duration::from_secs(2);

/// Writes the series' step files into a directory and shows progress.
pub struct SeriesWriter {
    dir: PathBuf,
    entries: Vec<(f64, String)>,
    progress: Progress,
}

impl SeriesWriter {
    /// Writes into `dir`; `steps` is the number of load steps when known (stepped strategies).
    pub fn new(dir: &Path, steps: Option<u64>) -> Self {
        Self {
            dir: dir.to_path_buf(),
            entries: Vec::new(),
            progress: Progress::new(steps),
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
        self.progress.update(record);
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

/// A progress bar that appears only on a terminal and only after [`QUIET_FOR`].
struct Progress {
    bar: Option<ProgressBar>,
    start: Instant,
    steps: Option<u64>,
    terminal: bool,
}

impl Progress {
    fn new(steps: Option<u64>) -> Self {
        Self {
            bar: None,
            start: Instant::now(),
            steps,
            terminal: std::io::stderr().is_terminal(),
        }
    }

    fn update(&mut self, record: &StepRecord) {
        if !self.terminal || self.start.elapsed() < QUIET_FOR {
            return;
        }
        let (steps, elapsed) = (self.steps, self.start.elapsed());
        let bar = self.bar.get_or_insert_with(|| {
            let (bar, template) = match steps {
                Some(n) => (
                    ProgressBar::new(n),
                    "{elapsed_precise} [{bar:30}] step {pos}/{len}, ETA {eta} | {msg}",
                ),
                None => (
                    ProgressBar::new_spinner(),
                    "{elapsed_precise} {spinner} event {pos} | {msg}",
                ),
            };
            if let Ok(style) = ProgressStyle::with_template(template) {
                bar.set_style(style.progress_chars("=> "));
            }
            bar.with_elapsed(elapsed)
        });
        bar.set_position(record.step as u64);
        bar.set_message(format!(
            "load factor {:.4e}, bonds broken {}",
            record.load_factor, record.broken_total
        ));
    }

    fn finish(&mut self) {
        if let Some(bar) = self.bar.take() {
            bar.finish_and_clear();
        }
    }
}
