//! Benchmark of quasi-static crack growth: the SENT plate of validation/fracture
//! run to complete separation, with the time of every solve by route.
//!
//! ```text
//! cargo run --release --example bench_fracture -- bond_based 140 event        # ~40,000 points
//! cargo run --release --example bench_fracture -- bond_based 140 all 100
//! cargo run --release --example bench_fracture -- shear 100 event             # ~20,000 points
//! cargo run --release --example bench_fracture -- shear 100 all 100 lu        # [solver] method
//! ```
//!
//! Prints the points and bonds, the median time of a solve with a fresh
//! factorisation, of a low-rank update of the old factor and of a Krylov
//! re-solve with the old factor after bonds broke (with their ratio to the
//! fresh one), the solves that only improved a re-solve's answer, the total
//! run time, the number of bonds broken and bonds broken per second.

use dhpd::drivers::quasi_static::{self};
use dhpd::drivers::static_solve;
use dhpd::scene::{parse_spec, Scene};
use dhpd::solve::pipeline::Route;
use dhpd::validation::fracture::Sent;
use std::path::Path;
use std::time::Instant;

fn median(mut v: Vec<f64>) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let model: &'static str = if args.first().map(String::as_str) == Some("shear") {
        "shear"
    } else {
        "bond_based"
    };
    let cells: usize = args.get(1).and_then(|a| a.parse().ok()).unwrap_or(140);
    let strategy: &'static str = match args.get(2).map(String::as_str) {
        Some("all") => "all",
        Some("most_critical") => "most_critical",
        _ => "event",
    };
    let mut case = Sent::new(model, cells, 3.015);
    case.strategy = strategy;
    if strategy != "event" {
        let steps: usize = args.get(3).and_then(|a| a.parse().ok()).unwrap_or(100);
        case.stepping = format!("steps = {steps}");
    }
    // An optional fifth argument sets `[solver] method` (the route's default otherwise).
    let scene = match args.get(4) {
        None => case.scene(),
        Some(method) => {
            let text = format!("{}\n[solver]\nmethod = \"{method}\"\n", case.toml());
            let spec = parse_spec(&text, false).expect("the scene parses");
            Scene::try_from_spec(spec, Path::new("."), "sent").expect("the scene is valid")
        }
    };
    let start = Instant::now();
    let prepared = static_solve::prepare(&scene).expect("the scene prepares");
    let (points, bonds) = (prepared.disc.points.len(), prepared.disc.bonds.len());
    let s = quasi_static::run(&scene, prepared, &mut ()).expect("the run succeeds");
    let total = start.elapsed().as_secs_f64();
    // A re-solve follows broken bonds; the solves that break none improve a
    // re-solve's answer (tighter decisions, a step's final state), listed apart.
    let counted = |x: &&quasi_static::ResolveRecord, route: Route| {
        x.report.route == route && (x.bonds_broken > 0 || route == Route::Factor)
    };
    let times = |route: Route| -> Vec<f64> {
        s.solves
            .iter()
            .filter(|x| counted(x, route))
            .map(|x| x.report.factor_seconds + x.report.solve_seconds)
            .collect()
    };
    let improvements: Vec<f64> = s
        .solves
        .iter()
        .filter(|x| x.report.route == Route::Reuse && x.bonds_broken == 0)
        .map(|x| x.report.iterations as f64)
        .collect();
    let (fresh, update, krylov) = (
        times(Route::Factor),
        times(Route::Update),
        times(Route::Reuse),
    );
    let iterations = |route: Route| -> Vec<f64> {
        s.solves
            .iter()
            .filter(|x| counted(x, route))
            .map(|x| x.report.iterations as f64)
            .collect()
    };
    let fresh_median = median(fresh.clone());
    let broken = s.records.last().map_or(0, |r| r.broken_total);
    println!(
        "{model} {strategy}: {points} points, {bonds} bonds, nnz(K) {}, nnz(L) {}",
        s.nnz_k,
        s.nnz_l.map_or("-".into(), |v| v.to_string())
    );
    for (name, t, route) in [
        ("fresh factorisation + solve", &fresh, Route::Factor),
        ("low-rank update of the old factor", &update, Route::Update),
        ("Krylov re-solve with the old factor", &krylov, Route::Reuse),
    ] {
        if !t.is_empty() {
            let m = median(t.clone());
            println!(
                "  {name}: {} solves, median {m:.4} s ({:.3} of a fresh one), total {:.2} s, \
                 median {} Krylov iterations",
                t.len(),
                m / fresh_median,
                t.iter().sum::<f64>(),
                median(iterations(route))
            );
        }
    }
    if !improvements.is_empty() {
        println!(
            "  improvements of a re-solve (no bond broken): {} solves, {} Krylov iterations in all",
            improvements.len(),
            improvements.iter().sum::<f64>()
        );
    }
    println!(
        "  whole run {total:.1} s ({}), {broken} bonds broken, {:.0} bonds per second",
        s.outcome.describe(),
        broken as f64 / total
    );
}
