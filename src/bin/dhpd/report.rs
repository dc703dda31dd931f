//! What `dhpd run` prints on stdout when a run has succeeded: sizes, the
//! solver route, times, residual and reactions (static), records, solves and
//! peaks (fracture), steps, energy balance and throughput (dynamics).

use dhpd::results::{
    DynamicsOutcome, DynamicsSolution, QuasiStaticSolution, Route, StaticSolution,
};
use dhpd::scene::{Scene, SolverMethod};
use dhpd::Solution;
use std::path::Path;

/// Prints the report of `solution`, written into `dir`.
pub fn print(scene: &Scene, solution: &Solution, dir: &Path) {
    match solution {
        Solution::Static(s) => print_static(scene, s),
        Solution::QuasiStatic(s) => print_fracture(scene, s),
        Solution::Dynamics(s) => print_dynamics(scene, s),
    }
    println!("results in {}", dir.display());
}

fn print_dynamics(scene: &Scene, s: &DynamicsSolution) {
    println!(
        "scene {}: {} points, {} bonds; {} ({} threads)",
        scene.name,
        s.disc.points.len(),
        s.bonds,
        s.kernel,
        rayon::current_num_threads()
    );
    match s.outcome {
        DynamicsOutcome::Completed => println!(
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
        DynamicsOutcome::Converged { residual } => println!(
            "dynamic relaxation converged in {} steps (relative out-of-balance force {:.2e}), {:.3} s",
            s.steps, residual, s.timings.integration
        ),
        DynamicsOutcome::NotConverged { residual } => println!(
            "dynamic relaxation NOT converged after {} steps: relative out-of-balance force {:.2e}",
            s.steps, residual
        ),
    }
    for line in &s.log {
        println!("  {line}");
    }
}

fn print_fracture(scene: &Scene, s: &QuasiStaticSolution) {
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
    #[cfg(feature = "mpi")]
    if let Some(p) = &s.petsc {
        println!(
            "PETSc: {} + {} on {} process(es), {} rows (a fresh factorisation is a fresh set-up \
             of the preconditioner; re-solves reuse it)",
            p.ksp, p.pc, p.processes, p.rows
        );
    }
    let ranking = &s.ranking;
    if ranking.tightened + ranking.undecided > 0 {
        println!(
            "event ranking after {} Krylov re-solves: {} decided by tighter re-solves, {} undecided \
             at the round-off floor (broken as computed)",
            ranking.checked, ranking.tightened, ranking.undecided
        );
    }
    for (k, name) in s.set_names.iter().enumerate() {
        if let Some(peak) = s.peak(k) {
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
}

fn print_static(scene: &Scene, s: &StaticSolution) {
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
        (SolverMethod::Iterative, Some(k)) => println!(
            "solver: iterative (two-level preconditioner, coarse factor nnz {}), {} iterations",
            c.nnz_l.map_or("-".into(), |v| v.to_string()),
            k.iterations
        ),
        (method, Some(k)) => println!("solver: {method:?}, {} Krylov iterations", k.iterations),
        (method, None) => println!("solver: {method:?}"),
    }
    #[cfg(feature = "mpi")]
    if let Some(p) = &c.petsc {
        println!(
            "PETSc: {} + {} on {} process(es), {} rows, {}",
            p.ksp, p.pc, p.processes, p.rows, p.converged_reason
        );
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
}
