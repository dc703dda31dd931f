//! Results on disk: VTK (points and the series of a fracture or explicit run),
//! CSV, the JSON summary and Matrix Market, written atomically by [`Results`].
//!
//! Everything goes into a temporary sibling directory that is renamed to the
//! requested one only when complete, so a failed run leaves no partial result;
//! [`interrupt`] removes it when the run is stopped by a signal.

pub mod interrupt;
internal!(csv, dynamics, matrix_market, points, series, summary, vtu);

use crate::drivers::quasi_static::QuasiStaticSolution;
use crate::drivers::static_solve::StaticSolution;
use crate::drivers::{Observer, Snapshot, Solution};
use crate::error::{Error, InputError};
use crate::notes::Notes;
use crate::scene::Scene;
use points::{write_points, PointData};
use series::Series;
use std::path::{Path, PathBuf};

/// A run's results in a directory, written atomically: the series' step files
/// while the run goes (it is an [`Observer`] of snapshots), the rest when it
/// ends; the directory is replaced only when every file is written.
pub struct Results {
    staging: Staging,
    series: Series,
    /// Pieces of the points' VTK file (the processes of an MPI run).
    vtu_pieces: usize,
}

impl Results {
    /// Checks that `dir` may receive results ([`check_output_dir`]) and
    /// creates the staging directory beside it; what that cleaned up (the
    /// staging directories of runs that were killed) goes to `notes`.
    pub fn new(dir: &Path, notes: &mut Notes) -> Result<Self, Error> {
        check_output_dir(dir)?;
        let staging = Staging::new(dir, notes)?;
        let series = Series::new(staging.path());
        Ok(Self {
            staging,
            series,
            vtu_pieces: 1,
        })
    }

    /// Results of a static run on `processes` MPI processes: `points.pvtu`
    /// with one piece per process; this process writes the first, the others
    /// theirs with [`write_vtu_piece`] into [`Results::staging_path`].
    pub fn in_pieces(mut self, processes: usize) -> Self {
        self.vtu_pieces = processes.max(1);
        self
    }

    /// The directory that receives the files until they are complete.
    pub fn staging_path(&self) -> &Path {
        self.staging.path()
    }

    /// Writes every requested output of `solution` into the staging
    /// directory, then replaces the output directory by it.
    pub fn finish(
        self,
        scene: &Scene,
        solution: &Solution,
        total_seconds: f64,
    ) -> Result<(), Error> {
        self.finish_joined(scene, solution, total_seconds, |written| written)
    }

    /// [`Results::finish`], with what this process wrote handed to `join`
    /// before the commit (an MPI run: every process's pieces written, or the
    /// run stops without a result).
    pub fn finish_joined(
        self,
        scene: &Scene,
        solution: &Solution,
        total_seconds: f64,
        join: impl FnOnce(Result<(), Error>) -> Result<(), Error>,
    ) -> Result<(), Error> {
        let tmp = self.staging.path();
        let written = match solution {
            Solution::Static(s) => write_static(tmp, scene, s, total_seconds, self.vtu_pieces),
            Solution::QuasiStatic(s) => write_quasi_static(tmp, scene, s, total_seconds),
            Solution::Dynamics(s) => dynamics::write(tmp, scene, s, total_seconds),
        };
        join(written)?;
        self.series.finish()?;
        self.staging.commit()
    }
}

/// Writes this process's piece `piece` of `pieces` of a static run's
/// `points.pvtu` into `dir` (rank 0's [`Results::staging_path`]), when the
/// scene asks for VTK output.
pub fn write_vtu_piece(
    dir: &Path,
    scene: &Scene,
    solution: &StaticSolution,
    piece: usize,
    pieces: usize,
) -> Result<(), Error> {
    if !scene.output.vtu {
        return Ok(());
    }
    points::write_vtu_piece(dir, &solution.point_data(), piece, pieces)
}

impl Observer for Results {
    fn snapshot(&mut self, snapshot: &Snapshot) -> Result<(), Error> {
        self.series.write(snapshot)
    }
}

/// A temporary sibling directory that receives the results and becomes the
/// requested one only when complete ([`Staging::commit`]); dropped uncommitted,
/// it is removed, so a failed run leaves no partial result.
pub(crate) struct Staging {
    dir: PathBuf,
    tmp: PathBuf,
    /// Ancestors of `dir` this staging created (deepest first), removed again
    /// if the run fails and they are empty.
    created: Vec<PathBuf>,
    committed: bool,
}

/// The ancestors of `path` that do not exist yet, deepest first.
fn missing_ancestors(path: &Path) -> Vec<PathBuf> {
    path.ancestors()
        .skip(1)
        .take_while(|p| !p.as_os_str().is_empty() && !p.exists())
        .map(Path::to_path_buf)
        .collect()
}

/// Removes the (empty) directories of `created`, deepest first.
fn remove_created(created: &[PathBuf]) {
    for p in created {
        let _ = std::fs::remove_dir(p);
    }
}

impl Staging {
    /// Creates the temporary directory next to `dir`, after removing the
    /// staging directories of killed runs there (said in `notes`).
    pub(crate) fn new(dir: &Path, notes: &mut Notes) -> Result<Self, Error> {
        for (path, pid) in interrupt::clear_stale(dir) {
            notes.push(format!(
                "note: removed {}, the partial result of an earlier run (process {pid}) that \
                 was killed",
                path.display()
            ));
        }
        let tmp = temporary_sibling(dir);
        let created = missing_ancestors(&tmp);
        let _ = std::fs::remove_dir_all(&tmp);
        interrupt::register(&tmp);
        if let Err(e) = std::fs::create_dir_all(&tmp) {
            interrupt::unregister(&tmp);
            remove_created(&created);
            return Err(Error::io(&tmp, e));
        }
        Ok(Self {
            dir: dir.to_path_buf(),
            tmp,
            created,
            committed: false,
        })
    }

    /// Where files go until the commit.
    pub(crate) fn path(&self) -> &Path {
        &self.tmp
    }

    /// Replaces the requested directory by the temporary one.
    pub(crate) fn commit(mut self) -> Result<(), Error> {
        let dir = self.dir.clone();
        check_output_dir(&dir)?;
        let old = dir.with_file_name(format!(".{}.old-{}", file_name(&dir), std::process::id()));
        let replacing = dir.exists();
        if replacing {
            std::fs::rename(&dir, &old).map_err(|e| Error::io(&dir, e))?;
        }
        if let Err(e) = std::fs::rename(&self.tmp, &dir) {
            if replacing {
                let _ = std::fs::rename(&old, &dir);
            }
            return Err(Error::io(&dir, e));
        }
        self.committed = true;
        interrupt::unregister(&self.tmp);
        if replacing {
            let _ = std::fs::remove_dir_all(&old);
        }
        Ok(())
    }
}

impl Drop for Staging {
    fn drop(&mut self) {
        if !self.committed {
            let _ = std::fs::remove_dir_all(&self.tmp);
            interrupt::unregister(&self.tmp);
            remove_created(&self.created);
        }
    }
}

/// Writes every requested output of a static run into `tmp`.
fn write_static(
    tmp: &Path,
    scene: &Scene,
    solution: &StaticSolution,
    total_seconds: f64,
    vtu_pieces: usize,
) -> Result<(), Error> {
    let data = solution.point_data();
    write_points(tmp, scene, &solution.plan, &data, vtu_pieces)?;
    if scene.output.matrix_market {
        matrix_market::write(tmp, &solution.system)?;
    }
    summary::write(&tmp.join("summary.json"), scene, solution, total_seconds)
}

/// Writes the final state and the records of a quasi-static run into `tmp`.
fn write_quasi_static(
    tmp: &Path,
    scene: &Scene,
    solution: &QuasiStaticSolution,
    total_seconds: f64,
) -> Result<(), Error> {
    let data = PointData {
        disc: &solution.disc,
        u: &solution.u,
        velocity: None,
        stress: solution.stress.as_deref(),
        damage: Some(&solution.damage),
        bond_counts: None,
    };
    write_points(tmp, scene, &solution.plan, &data, 1)?;
    csv::write_load_displacement(&tmp.join("load_displacement.csv"), solution)?;
    summary::write_quasi_static(&tmp.join("summary.json"), scene, solution, total_seconds)
}

/// Refuses an output directory that holds one of the run's inputs (the scene
/// file `scene_file`, its point files and meshes): the run replaces the
/// directory, which would delete them. Call it before solving.
pub fn check_inputs_outside(
    dir: &Path,
    scene_file: &Path,
    scene: &Scene,
) -> Result<(), InputError> {
    let Ok(target) = dir.canonicalize() else {
        return Ok(()); // not there yet: it holds nothing
    };
    let inputs = std::iter::once(scene_file)
        .chain(scene.point_files.iter().map(|f| f.path.as_path()))
        .chain(scene.meshes.iter().map(|m| m.path.as_path()));
    for input in inputs {
        if input.canonicalize().is_ok_and(|p| p.starts_with(&target)) {
            return Err(InputError::new(
                "--out",
                format!(
                    "refusing to write results to {}: it holds {}, an input of this run, which \
                     replacing the directory would delete; choose another directory",
                    dir.display(),
                    input.display()
                ),
            ));
        }
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
        return probe_writable(dir).map_err(refuse);
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
    probe_writable(dir).map_err(refuse)
}

/// Creates and removes the staging directory of `dir` (and any missing
/// parent), so that an output that cannot be written (read-only location, a
/// name too long for the file system) is refused before any work, leaving
/// nothing behind.
fn probe_writable(dir: &Path) -> Result<(), String> {
    let tmp = temporary_sibling(dir);
    let created = missing_ancestors(&tmp);
    let result = std::fs::create_dir_all(&tmp)
        .map_err(|e| format!("cannot create {} there ({e})", tmp.display()));
    let _ = std::fs::remove_dir(&tmp);
    remove_created(&created);
    result
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
