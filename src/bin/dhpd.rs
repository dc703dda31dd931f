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

use clap::{Parser, Subcommand};
use dhpd::drivers::{dynamics, quasi_static, static_solve};
use dhpd::error::Error;
use dhpd::output::series::SeriesWriter;
use dhpd::output::{self, Plan};
use dhpd::reference::{ErrorStats, FemReference, BIMATERIAL_STRIP_FEM};
use dhpd::scene::{self, Scene};
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
    output::interrupt::install();
    let cli = Cli::parse();
    let result = match cli.command {
        None => run_default(),
        Some(Command::Run { scene, out }) => scene::load(&scene).and_then(|s| {
            if s.quasi_static.is_some() {
                run_fracture(&s, out.as_deref())
            } else if s.dynamics.is_some() {
                run_dynamics(&s, out.as_deref())
            } else {
                run(&s, out.as_deref()).map(|_| ())
            }
        }),
        Some(Command::Check { scene }) => check(&scene),
    };
    if let Err(e) = result {
        eprintln!("dhpd: {e}");
        std::process::exit(e.exit_code());
    }
}

fn check(path: &Path) -> Result<(), Error> {
    let scene = scene::load(path)?;
    if scene.dynamics.is_some() {
        // An explicit (Verlet) run may have a free body.
        let disc = dhpd::discretization::build(&scene)?;
        Plan::new(&scene, &disc)?;
        let dofs = dhpd::assembly::dofs::DofMap::new(&disc, &scene.boundaries)?;
        if scene.dynamics.as_ref().map(|d| d.method)
            == Some(dhpd::scene::DynamicsMethod::Relaxation)
        {
            // Relaxation seeks a static equilibrium: the body must be held.
            dhpd::assembly::rigid_modes::check(&disc, &dofs)?;
        }
        println!(
            "{}: valid ({} points, {} bonds; explicit dynamics)",
            path.display(),
            disc.points.len(),
            disc.bonds.len()
        );
        return Ok(());
    }
    let prepared = static_solve::prepare(&scene)?;
    Plan::new(&scene, &prepared.disc)?;
    println!(
        "{}: valid ({} points, {} bonds, {} free dofs)",
        path.display(),
        prepared.disc.points.len(),
        prepared.disc.bonds.len(),
        prepared.dofs.n_free()
    );
    Ok(())
}

fn run(scene: &Scene, out: Option<&Path>) -> Result<static_solve::StaticSolution, Error> {
    let start = Instant::now();
    let dir = output_dir(scene, out);
    output::check_output_dir(&dir)?;
    let prepared = static_solve::prepare(scene)?;
    let plan = Plan::new(scene, &prepared.disc)?;
    let solution = prepared.solve(scene)?;
    output::write_static(&dir, scene, &plan, &solution, start.elapsed().as_secs_f64())?;
    print_report(scene, &solution, &dir);
    Ok(solution)
}

fn output_dir(scene: &Scene, out: Option<&Path>) -> PathBuf {
    out.map(Path::to_path_buf)
        .unwrap_or_else(|| Path::new("dhpd-out").join(&scene.name))
}

/// A quasi-static fracture run: the series' step files are written while it runs,
/// into a staging directory that replaces the output directory when complete.
fn run_fracture(scene: &Scene, out: Option<&Path>) -> Result<(), Error> {
    let start = Instant::now();
    let dir = output_dir(scene, out);
    output::check_output_dir(&dir)?;
    let prepared = static_solve::prepare(scene)?;
    let plan = Plan::new(scene, &prepared.disc)?;
    let staging = output::Staging::new(&dir)?;
    let settings = scene.quasi_static.as_ref().expect("a fracture scene");
    let steps =
        (settings.strategy != dhpd::scene::Strategy::Event).then_some(settings.steps as u64);
    let mut series = SeriesWriter::new(staging.path(), steps, settings.max_load_factor);
    let solution = quasi_static::run(scene, prepared, &mut series)?;
    let entries = series.finish();
    output::write_quasi_static(
        staging,
        scene,
        &plan,
        &solution,
        &entries,
        start.elapsed().as_secs_f64(),
    )?;
    print_fracture_report(scene, &solution, &dir);
    Ok(())
}

/// An explicit dynamics or dynamic relaxation run, written like a fracture run.
fn run_dynamics(scene: &Scene, out: Option<&Path>) -> Result<(), Error> {
    let start = Instant::now();
    let dir = output_dir(scene, out);
    output::check_output_dir(&dir)?;
    let disc = dhpd::discretization::build(scene)?;
    let plan = Plan::new(scene, &disc)?;
    drop(disc);
    let staging = output::Staging::new(&dir)?;
    let probes: Vec<usize> = plan.probes.iter().map(|p| p.1).collect();
    let relaxation =
        scene.dynamics.as_ref().map(|d| d.method) == Some(dhpd::scene::DynamicsMethod::Relaxation);
    let mut writer = output::dynamics::DynamicsWriter::new(staging.path(), relaxation);
    let solution = dynamics::run(scene, &probes, &mut writer)?;
    let entries = writer.finish();
    output::dynamics::write(
        staging,
        scene,
        &plan,
        &solution,
        &entries,
        start.elapsed().as_secs_f64(),
    )?;
    let s = &solution;
    println!(
        "scene {}: {} points, {} bonds; {} ({} threads)",
        scene.name,
        s.disc.points.len(),
        s.bonds,
        s.kernel,
        rayon::current_num_threads()
    );
    match s.outcome {
        dynamics::Outcome::Completed => println!(
            "{} steps of {:.4e} s (stable {:.4e} s) to t = {:.4e} s; {:.3} s integrating, \
             {:.1} M directed bond updates/s; energy balance error ≤ {:.2e}; {} bonds broken",
            s.steps,
            s.time_step,
            s.stable_time_step.unwrap_or(f64::NAN),
            s.time,
            s.timings.integration,
            s.bond_updates_per_second / 1e6,
            s.max_balance_error,
            s.records.last().map_or(0, |r| r.broken_bonds)
        ),
        dynamics::Outcome::Converged { residual } => println!(
            "dynamic relaxation converged in {} steps (relative out-of-balance force {:.2e}), {:.3} s",
            s.steps, residual, s.timings.integration
        ),
        dynamics::Outcome::NotConverged { residual } => println!(
            "dynamic relaxation NOT converged after {} steps: relative out-of-balance force {:.2e}",
            s.steps, residual
        ),
    }
    for line in &s.log {
        println!("  {line}");
    }
    println!("results in {}", dir.display());
    Ok(())
}

fn print_fracture_report(scene: &Scene, s: &quasi_static::QuasiStaticSolution, dir: &Path) {
    println!(
        "scene {}: {} points, {} bonds, {} free dofs, nnz(K) {}, nnz(L) {}",
        scene.name,
        s.disc.points.len(),
        s.bonds,
        s.dofs_free,
        s.nnz_k,
        s.nnz_l.map_or("-".into(), |v| v.to_string())
    );
    let broken = s.records.last().map_or(0, |r| r.broken_total);
    let count = |route| s.solves.iter().filter(|x| x.report.route == route).count();
    use dhpd::solve::pipeline::Route;
    println!(
        "{} records, {} bonds broken, {} solves ({} fresh factorisations, {} low-rank updates of the factor, \
         {} Krylov re-solves with the old factor); {}",
        s.records.len(),
        broken,
        s.solves.len(),
        count(Route::Factor),
        count(Route::Update),
        count(Route::Reuse),
        s.outcome.describe()
    );
    for (k, name) in s.set_names.iter().enumerate() {
        if let Some(peak) = s.records.iter().max_by(|a, b| {
            dhpd::vector::magnitude(&a.reactions[k])
                .total_cmp(&dhpd::vector::magnitude(&b.reactions[k]))
        }) {
            let f = peak.reactions[k];
            println!(
                "peak reaction {:>10}: [{:.6e}, {:.6e}, {:.6e}] N at load factor {:.6e} (step {})",
                name, f[0], f[1], f[2], peak.load_factor, peak.step
            );
        }
    }
    for line in s.log.iter().take(10) {
        println!("  {line}");
    }
    if s.log.len() > 10 {
        println!("  ... {} more in summary.json", s.log.len() - 10);
    }
    println!("results in {}", dir.display());
}

fn print_report(scene: &Scene, s: &static_solve::StaticSolution, dir: &Path) {
    let c = &s.counts;
    let t = &s.timings;
    println!(
        "scene {}: {} points, {} bonds, {} free dofs, nnz(K) {}, nnz(L) {}",
        scene.name,
        c.points,
        c.bonds,
        c.dofs,
        c.nnz_k,
        c.nnz_l.map_or("-".into(), |v| v.to_string())
    );
    match (c.solver, c.gmres) {
        (scene::SolverMethod::Iterative, Some(k)) => println!(
            "solver: iterative (two-level preconditioner, coarse factor nnz {}), {} iterations",
            c.nnz_l.map_or("-".into(), |v| v.to_string()),
            k.iterations
        ),
        (method, Some(k)) => println!("solver: {method:?}, {} Krylov iterations", k.iterations),
        (method, None) => println!("solver: {method:?}"),
    }
    if let Some(o) = &c.ordering {
        let size = |v: Option<usize>| v.map_or("-".into(), |v| v.to_string());
        println!(
            "ordering {:?} (nnz(L) with AMD {}, with nested dissection {})",
            o.chosen,
            size(o.nnz_l_amd),
            size(o.nnz_l_nested_dissection)
        );
    }
    println!(
        "time [s]: points {:.3}, neighbours {:.3}, pattern {:.3}, assembly {:.3}, symbolic {:.3}, numeric {:.3}, solve {:.3}",
        t.discretization, t.neighbour_search, t.pattern, t.assembly, t.symbolic_factorization, t.numeric_factorization, t.solve
    );
    println!("relative residual {:.2e}", s.residual);
    for r in &s.reactions {
        println!(
            "reaction {:>10}: [{:.6e}, {:.6e}, {:.6e}] N",
            r.name, r.force[0], r.force[1], r.force[2]
        );
    }
    println!("results in {}", dir.display());
}

fn run_default() -> Result<(), Error> {
    let spec = scene::parse_spec(scene::DEFAULT_SCENE, false)?;
    let scene = Scene::try_from_spec(spec, Path::new("."), "default")?;
    println!("dhpd: no scene given, running the embedded default (2D bimaterial strip, bond-based DH-PD)\n");
    let s = run(&scene, None)?;
    let reference =
        FemReference::from_json(BIMATERIAL_STRIP_FEM).expect("embedded reference is valid JSON");
    let scale = 1e-4;
    let pairs: Vec<(f64, f64)> = (0..s.disc.points.len())
        .filter(|&i| s.dofs.free_count(i) == 2)
        .filter_map(|i| {
            let x = s.disc.points.x[i];
            reference
                .grid
                .interpolate("ux", x[0], x[1])
                .map(|r| (s.u[i][0], r))
        })
        .collect();
    let stats = ErrorStats::of(pairs, scale);
    println!("\ncomparison with the scikit-fem P2 reference (validation/bimaterial_bar/fem):");
    println!(
        "  u_x at {} free points: max error {:.2} %, RMS {:.2} % of the applied 1e-4 m",
        stats.count,
        100.0 * stats.max_relative,
        100.0 * stats.rms_relative
    );
    if let (Some(fem), Some(r)) = (reference.reaction_x, s.reaction("right")) {
        println!(
            "  reaction at the right grip: dhpd {:.6e} N, FEM {:.6e} N ({:+.2} %)",
            r[0],
            fem,
            100.0 * (r[0] / fem - 1.0)
        );
    }
    Ok(())
}
