//! The `dhpd` command line.
//!
//! ```text
//! dhpd                          run the embedded default scene (2D bimaterial strip)
//!                               and compare it with its finite-element reference
//! dhpd run SCENE [--out DIR]    solve a scene, write results into DIR
//! dhpd check SCENE              validate a scene (and its point files) only
//! ```
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
use dhpd::scene::{self, Scene};
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
    let result = match cli.command {
        None => run_default(),
        Some(Command::Run { scene, out }) => {
            scene::load(&scene).and_then(|s| run(&s, out.as_deref()).map(|_| ()))
        }
        Some(Command::Check { scene }) => check(&scene),
    };
    if let Err(e) = result {
        eprintln!("dhpd: {e}");
        std::process::exit(e.exit_code());
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
fn run(scene: &Scene, out: Option<&Path>) -> Result<Solution, Error> {
    let start = Instant::now();
    let dir = out
        .map(Path::to_path_buf)
        .unwrap_or_else(|| Path::new("dhpd-out").join(&scene.name));
    let mut notes = Notes::default();
    let results = Results::new(&dir, &mut notes);
    print_notes(&mut notes);
    let mut console = Console {
        results: results?,
        progress: None,
    };
    let solution = dhpd::run(scene, &mut console)?;
    if let Some(p) = &mut console.progress {
        p.finish();
    }
    console
        .results
        .finish(scene, &solution, start.elapsed().as_secs_f64())?;
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
            setup.disc.bonds.len()
        );
    } else {
        println!(
            "{}: valid ({} points, {} bonds, {} free dofs)",
            path.display(),
            setup.disc.points.len(),
            setup.disc.bonds.len(),
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
fn run_default() -> Result<(), Error> {
    let scene = dhpd::default_scene::scene()?;
    println!("dhpd: no scene given, running the embedded default (2D bimaterial strip, bond-based DH-PD)\n");
    let Solution::Static(s) = run(&scene, None)? else {
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
