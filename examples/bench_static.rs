//! Static-solve benchmark: per-phase wall time (the driver's own timers) and peak memory.
//!
//! ```text
//! cargo run --release --example bench_static -- 2d 200 5                 # bond-based, 40,000 points, 5 repeats
//! cargo run --release --example bench_static -- 2d 400 3                 # 160,000 points
//! cargo run --release --example bench_static -- 3d 37 1                  # 37^3 = 50,653 points
//! cargo run --release --example bench_static -- 2d 201 3 shear           # shear model, 40,401 points (GMRES)
//! cargo run --release --example bench_static -- 2d 201 1 shear lu        # the same with sparse LU
//! cargo run --release --example bench_static -- 2d 400 3 bond_based amd  # the ordering: amd,
//!                                                  # nested_dissection or auto (default)
//! cargo run --release --example bench_static -- 2d 400 3 mixed           # single-precision factor
//! cargo run --release --example bench_static -- 3d 58 1 iterative        # CG, two-level preconditioner
//! RAYON_NUM_THREADS=1 cargo run --release --example bench_static -- ...  # one thread
//! ```
//!
//! Problem: a unit square (cube), δ = 3.015Δ, ν = 1/3 plane stress (1/4 in 3D),
//! left layer clamped, right face pulled by a traction. Medians over the repeats;
//! the peak resident memory (VmHWM) is that of the whole process: run one size
//! per process.

use dhpd::drivers::static_solve;
use dhpd::scene::{parse_spec, Scene};

fn scene(dim: &str, n: usize, model: &str, method: &str, ordering: &str, precision: &str) -> Scene {
    let h = 1.0 / n as f64;
    let (dimension, nu, lo, hi, fix, hi_left, value) = if dim == "3d" {
        (
            "3d",
            0.25,
            "[0.0, 0.0, 0.0]",
            "[1.0, 1.0, 1.0]",
            "x = 0.0, y = 0.0, z = 0.0",
            format!("[{}, 1.0, 1.0]", 3.0 * h),
            "[1e8, 0.0, 0.0]",
        )
    } else {
        (
            "plane_stress",
            1.0 / 3.0,
            "[0.0, 0.0]",
            "[1.0, 1.0]",
            "x = 0.0, y = 0.0",
            format!("[{}, 1.0]", 3.0 * h),
            "[1e8, 0.0]",
        )
    };
    let text = format!(
        "[model]\ndimension = \"{dimension}\"\nkind = \"{model}\"\n[materials.m]\nyoungs_modulus = 2e11\npoisson_ratio = {nu}\n\
         [[regions]]\nmaterial = \"m\"\nspacing = {h}\nbox = {{ min = {lo}, max = {hi} }}\n\
         [[boundary]]\nname = \"left\"\nbox = {{ min = {lo}, max = {hi_left} }}\ndisplacement = {{ {fix} }}\n\
         [[loads]]\nname = \"pull\"\nkind = \"traction\"\nface = \"+x\"\nvalue = {value}\n{}",
        {
            let mut solver = String::new();
            for (key, value) in [("method", method), ("ordering", ordering), ("precision", precision)] {
                if !value.is_empty() {
                    solver += &format!("{key} = \"{value}\"\n");
                }
            }
            if solver.is_empty() { solver } else { format!("[solver]\n{solver}") }
        }
    );
    Scene::try_from_spec(
        parse_spec(&text, false).unwrap(),
        std::path::Path::new("."),
        "bench",
    )
    .unwrap()
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn peak_memory_mib() -> f64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("VmHWM"))
                .and_then(|l| l.split_whitespace().nth(1)?.parse::<f64>().ok())
        })
        .map_or(f64::NAN, |kib| kib / 1024.0)
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let dim = args.get(1).map_or("2d", String::as_str).to_string();
    let n: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(200);
    let repeats: usize = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(3);
    let rest = args.get(4..).unwrap_or_default();
    let pick = |choices: &[&str], default: &str| {
        rest.iter()
            .find(|a| choices.contains(&a.as_str()))
            .map_or(default.to_string(), |a| a.clone())
    };
    let model = pick(&["bond_based", "shear"], "bond_based");
    let method = pick(&["cholesky", "lu", "gmres", "iterative"], "");
    let ordering = pick(&["amd", "nested_dissection", "auto"], "");
    let precision = pick(&["double", "mixed"], "");
    let scene = scene(&dim, n, &model, &method, &ordering, &precision);
    let names = [
        "points",
        "neighbours",
        "pattern",
        "assembly",
        "symbolic",
        "numeric",
        "solve",
    ];
    let mut times: Vec<Vec<f64>> = vec![Vec::new(); names.len()];
    let mut info = String::new();
    for _ in 0..repeats {
        let s = match static_solve::solve(&scene) {
            Ok(s) => s,
            Err(e) => {
                println!("{dim} n={n} {model}: {e}");
                return;
            }
        };
        let t = &s.timings;
        for (k, v) in [
            t.discretization,
            t.neighbour_search,
            t.pattern,
            t.assembly,
            t.symbolic_factorization,
            t.numeric_factorization,
            t.solve,
        ]
        .into_iter()
        .enumerate()
        {
            times[k].push(v);
        }
        let c = &s.counts;
        info = format!(
            "{} points, {} bonds, {} dofs, solver {:?}, nnz(K) {}, nnz(L) {}, asymmetry {:.2e}, krylov iterations {}, residual {:.1e}, ordering {}",
            c.points, c.bonds, c.dofs, c.solver, c.nnz_k, c.nnz_l.map_or("-".into(), |v| v.to_string()), c.asymmetry,
            c.gmres.map_or("-".into(), |g| g.iterations.to_string()), s.residual,
            c.ordering.map_or("-".into(), |o| format!(
                "{:?} (nnz(L) AMD {:?}, ND {:?}; flops AMD {:.3e}, ND {:.3e}; dissection {:.3} s)",
                o.chosen, o.nnz_l_amd, o.nnz_l_nested_dissection,
                o.flops_amd.unwrap_or(f64::NAN), o.flops_nested_dissection.unwrap_or(f64::NAN),
                o.dissection_seconds
            ))
        );
    }
    println!(
        "{dim} n={n} {model} {method} {ordering} {precision} ({repeats} repeats, {} rayon threads): {info}",
        rayon::current_num_threads()
    );
    for (name, t) in names.iter().zip(times) {
        let (lo, hi) = (
            t.iter().cloned().fold(f64::INFINITY, f64::min),
            t.iter().cloned().fold(0.0, f64::max),
        );
        println!(
            "  {name:<10} median {:.3} s  (min {lo:.3}, max {hi:.3})",
            median(t)
        );
    }
    println!("  peak memory {:.0} MiB", peak_memory_mib());
}
