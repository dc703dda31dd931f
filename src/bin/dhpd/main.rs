//! The `dhpd` command line.
//!
//! ```text
//! dhpd                          run the embedded default scene (2D bimaterial strip)
//!                               and compare it with its finite-element reference
//! dhpd run SCENE [--out DIR]    solve a scene, write results into DIR
//! dhpd check SCENE              validate a scene (and its point files) only
//! ```
//!
//! Built with the `mpi` feature, every run initialises PETSc and MPI
//! (`mpirun -np N dhpd run SCENE -- PETSC_OPTIONS`): scenes with
//! `solver.method = "petsc"` solve on all the processes, rank 0 alone prints
//! the notes and reports and writes the results (every rank its piece of
//! `points.pvtu`, into rank 0's staging directory), and every rank prints its
//! errors.
//!
//! Exit codes: 0 success, 2 input error, 3 numerical failure, 4 I/O error,
//! 130 / 143 interrupted by SIGINT / SIGTERM (partial results removed).
//!
//! The library prints nothing: this program prints the notes its observer
//! receives, the progress of long runs, the reports and the errors.

mod progress;
mod report;

use clap::{Parser, Subcommand};
use dhpd::error::Error;
use dhpd::output::Results;
use dhpd::scene::{self, Scene, SolverMethod};
use dhpd::InputError;
use dhpd::{Notes, Observer, Progress, Snapshot, Solution};
use std::path::{Path, PathBuf};
use std::time::Instant;

#[derive(Parser)]
#[command(name = "dhpd", version, about = "Implicit dual-horizon peridynamics")]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand)]
enum Command {
    /// Solve a scene (TOML, or JSON by extension) and write its results.
    Run {
        /// Scene file.
        scene: PathBuf,
        /// Output directory (default: `dhpd-out/<scene name>`); replaced when the run succeeds.
        #[arg(long)]
        out: Option<PathBuf>,
        /// PETSc options after `--` (e.g. `-- -ksp_monitor -ksp_view`), for
        /// `solver.method = "petsc"`.
        #[cfg(feature = "mpi")]
        #[arg(last = true, allow_hyphen_values = true)]
        petsc_options: Vec<String>,
    },
    /// Validate a scene and its point files without solving.
    Check {
        /// Scene file.
        scene: PathBuf,
    },
}

fn main() {
    // Before any thread starts: SIGINT and SIGTERM remove the partial results.
    dhpd::output::interrupt::install(|signal, removed| {
        eprintln!(
            "dhpd: interrupted by {signal}; {removed} partial result(s) removed, nothing written"
        )
    });
    let cli = Cli::parse();
    let world = match World::start(&cli) {
        Ok(world) => world,
        Err(e) => {
            eprintln!("dhpd: {e}");
            std::process::exit(e.exit_code());
        }
    };
    let result = match cli.command {
        None => run_default(&world),
        Some(Command::Run { scene, out, .. }) => scene::load(&scene).and_then(|s| {
            dhpd::output::check_inputs_outside(&out_dir(&s, out.as_deref()), &scene, &s)?;
            run(&s, out.as_deref(), &world).map(|_| ())
        }),
        Some(Command::Check { scene }) => check(&scene),
    };
    if let Err(e) = result {
        match world.size() {
            1 => eprintln!("dhpd: {e}"),
            n => eprintln!("dhpd (rank {} of {n}): {e}", world.rank()),
        }
        drop(world);
        std::process::exit(e.exit_code());
    }
}

/// The processes of this run: one, or (the `mpi` feature) those of an MPI
/// run, with PETSc initialised until this is dropped.
struct World {
    #[cfg(feature = "mpi")]
    petsc: dhpd::mpi::Petsc,
}

impl World {
    /// Initialises PETSc and MPI in the `mpi` build, with the command line's
    /// PETSc options.
    fn start(cli: &Cli) -> Result<Self, Error> {
        #[cfg(feature = "mpi")]
        {
            let options = match &cli.command {
                Some(Command::Run { petsc_options, .. }) => petsc_options.as_slice(),
                _ => &[],
            };
            Ok(World {
                petsc: dhpd::mpi::Petsc::init(options)?,
            })
        }
        #[cfg(not(feature = "mpi"))]
        {
            let _ = cli;
            Ok(World {})
        }
    }

    /// This process's rank (0 prints and writes).
    fn rank(&self) -> usize {
        #[cfg(feature = "mpi")]
        return self.petsc.rank();
        #[cfg(not(feature = "mpi"))]
        0
    }

    /// The number of processes.
    fn size(&self) -> usize {
        #[cfg(feature = "mpi")]
        return self.petsc.size();
        #[cfg(not(feature = "mpi"))]
        1
    }

    /// Rank 0's `path` on every process (collective; the others pass `None`).
    fn share_path(&self, path: Option<&Path>) -> Result<PathBuf, Error> {
        #[cfg(feature = "mpi")]
        return dhpd::mpi::share_path(path);
        #[cfg(not(feature = "mpi"))]
        Ok(path.map(Path::to_path_buf).unwrap_or_default())
    }

    /// `result` where every process has `Ok`, else an error (collective).
    fn on_every_process<T>(&self, result: Result<T, Error>) -> Result<T, Error> {
        #[cfg(feature = "mpi")]
        return dhpd::mpi::on_every_process(result);
        #[cfg(not(feature = "mpi"))]
        result
    }
}

/// The observer of a run on the command line: notes on stderr, progress on
/// stderr, snapshots into the results' series.
struct Console {
    results: Results,
    progress: Option<progress::Display>,
}

impl Observer for Console {
    fn note(&mut self, note: &str) {
        eprintln!("{note}");
    }

    fn progress(&mut self, progress: &Progress) {
        progress::show(&mut self.progress, progress);
    }

    fn snapshot(&mut self, snapshot: &Snapshot) -> Result<(), Error> {
        self.results.snapshot(snapshot)
    }
}

/// Prints notes on stderr.
fn print_notes(notes: &mut Notes) {
    notes.take().iter().for_each(|n| eprintln!("{n}"));
}

/// Solves `scene` with the driver it asks for and writes its results into
/// `out` (default `dhpd-out/<scene name>`), through a staging directory that
/// replaces it when complete.
/// On several processes (`mpirun`), only `solver.method = "petsc"` runs, and
/// only rank 0 prints and writes.
/// Where a run writes: `--out`, or `dhpd-out/<scene name>`.
fn out_dir(scene: &Scene, out: Option<&Path>) -> PathBuf {
    out.map(Path::to_path_buf)
        .unwrap_or_else(|| Path::new("dhpd-out").join(&scene.name))
}

fn run(scene: &Scene, out: Option<&Path>, world: &World) -> Result<Solution, Error> {
    if world.size() > 1 && scene.solver.method != SolverMethod::Petsc {
        return Err(InputError::new(
            "solver.method",
            format!(
                "this run has {} processes and only solver.method = \"petsc\" solves on \
                 several; set it, or run on one process (without mpirun)",
                world.size()
            ),
        )
        .into());
    }
    if world.size() > 1 && scene.output.matrix_market {
        return Err(InputError::new(
            "output.matrix_market",
            format!(
                "this run has {} processes, each of which assembles only its own columns of K; \
                 export the matrix from a run on one process",
                world.size()
            ),
        )
        .into());
    }
    let several = world.size() > 1;
    if world.rank() > 0 {
        // Each writes its piece of the points' VTK file into rank 0's staging
        // directory, which rank 0 commits once every piece is written (once
        // rank 0 could make it: an error there stops every rank).
        world.on_every_process(Ok(()))?;
        let staging = world.share_path(None)?;
        let solution = dhpd::run(scene, &mut ())?;
        let written = match &solution {
            Solution::Static(s) => {
                dhpd::output::write_vtu_piece(&staging, scene, s, world.rank(), world.size())
            }
            _ => Ok(()),
        };
        world.on_every_process(written)?;
        return Ok(solution);
    }
    let start = Instant::now();
    let dir = out_dir(scene, out);
    let mut notes = Notes::default();
    let results = Results::new(&dir, &mut notes);
    print_notes(&mut notes);
    let results = world.on_every_process(results)?.in_pieces(world.size());
    if several {
        world.share_path(Some(results.staging_path()))?;
    }
    let mut console = Console {
        results,
        progress: None,
    };
    let solution = dhpd::run(scene, &mut console)?;
    if let Some(p) = &mut console.progress {
        p.finish();
    }
    let elapsed = start.elapsed().as_secs_f64();
    console
        .results
        .finish_joined(scene, &solution, elapsed, |written| match several {
            true => world.on_every_process(written),
            false => written,
        })?;
    report::print(scene, &solution, &dir);
    Ok(solution)
}

/// Validates a scene, its point files, the point selections and the supports.
fn check(path: &Path) -> Result<(), Error> {
    let scene = scene::load(path)?;
    let setup = dhpd::check(&scene, &mut Printer)?;
    if scene.dynamics.is_some() {
        println!(
            "{}: valid ({} points, {} bonds; explicit dynamics)",
            path.display(),
            setup.disc.points.len(),
            setup.bond_count()
        );
    } else {
        println!(
            "{}: valid ({} points, {} bonds, {} free dofs)",
            path.display(),
            setup.disc.points.len(),
            setup.bond_count(),
            setup.dofs.n_free()
        );
    }
    Ok(())
}

/// An observer that prints the notes only.
struct Printer;

impl Observer for Printer {
    fn note(&mut self, note: &str) {
        eprintln!("{note}");
    }
}

/// The embedded default scene, solved and compared with its FEM reference.
fn run_default(world: &World) -> Result<(), Error> {
    let scene = dhpd::default_scene::scene()?;
    println!("dhpd: no scene given, running the embedded default (2D bimaterial strip, bond-based DH-PD)\n");
    let Solution::Static(s) = run(&scene, None, world)? else {
        unreachable!("the default scene is static")
    };
    let c = dhpd::default_scene::compare(&s);
    println!("\ncomparison with the scikit-fem P2 reference (validation/bimaterial_bar/fem):");
    println!(
        "  u_x at {} free points: max error {:.2} %, RMS {:.2} % of the applied 1e-4 m",
        c.points,
        100.0 * c.max_relative,
        100.0 * c.rms_relative
    );
    if let Some((r, fem)) = c.reaction {
        println!(
            "  reaction at the right grip: dhpd {:.6e} N, FEM {:.6e} N ({:+.2} %)",
            r,
            fem,
            100.0 * (r / fem - 1.0)
        );
    }
    Ok(())
}
