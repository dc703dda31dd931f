//! Static-solve benchmark (issue 2): per-phase wall time and peak memory.
//!
//! ```text
//! cargo run --release --example bench_static -- 2d 200 5   # 200 x 200 = 40,000 points, 5 repeats
//! cargo run --release --example bench_static -- 2d 400 3   # 160,000 points
//! cargo run --release --example bench_static -- 3d 37 3    # 37^3 = 50,653 points
//! ```
//!
//! Problem: a unit square (cube) of plane-stress (3D) bond-based DH-PD,
//! δ = 3.015Δ, left layer clamped, right face pulled by a traction. Each phase is
//! timed in every repeat and the median is printed; the peak resident memory
//! (VmHWM) is that of the whole process. Run one size per process.

use dhpd::assembly::dofs::DofMap;
use dhpd::assembly::loads::external_forces;
use dhpd::assembly::pattern::Pattern;
use dhpd::assembly::stiffness::Stiffness;
use dhpd::discretization;
use dhpd::model::bond_based::BondBased;
use dhpd::model::Model;
use dhpd::scene::{parse_spec, Scene};
use dhpd::solve::{relative_residual, Cholesky};
use std::time::Instant;

fn scene(dim: &str, n: usize) -> Scene {
    let h = 1.0 / n as f64;
    let text = if dim == "3d" {
        format!(
            "[model]\ndimension = \"3d\"\n[materials.m]\nyoungs_modulus = 2e11\n\
             [[regions]]\nmaterial = \"m\"\nspacing = {h}\nbox = {{ min = [0.0, 0.0, 0.0], max = [1.0, 1.0, 1.0] }}\n\
             [[boundary]]\nname = \"left\"\nbox = {{ min = [0.0, 0.0, 0.0], max = [{}, 1.0, 1.0] }}\ndisplacement = {{ x = 0.0, y = 0.0, z = 0.0 }}\n\
             [[loads]]\nname = \"pull\"\nkind = \"traction\"\nface = \"+x\"\nvalue = [1e8, 0.0, 0.0]\n",
            3.0 * h
        )
    } else {
        format!(
            "[model]\ndimension = \"plane_stress\"\n[materials.m]\nyoungs_modulus = 2e11\n\
             [[regions]]\nmaterial = \"m\"\nspacing = {h}\nbox = {{ min = [0.0, 0.0], max = [1.0, 1.0] }}\n\
             [[boundary]]\nname = \"left\"\nbox = {{ min = [0.0, 0.0], max = [{}, 1.0] }}\ndisplacement = {{ x = 0.0, y = 0.0 }}\n\
             [[loads]]\nname = \"pull\"\nkind = \"traction\"\nface = \"+x\"\nvalue = [1e8, 0.0]\n",
            3.0 * h
        )
    };
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
    let scene = scene(&dim, n);
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
        let t = Instant::now();
        let raw = discretization::generate_points(&scene).unwrap();
        times[0].push(t.elapsed().as_secs_f64());
        let t = Instant::now();
        let disc = discretization::discretize(&scene, raw).unwrap();
        times[1].push(t.elapsed().as_secs_f64());
        let model = BondBased::new(&disc, scene.dimension, &scene.materials, scene.thickness);
        let dofs = DofMap::new(&disc.points, disc.d, &scene.boundaries).unwrap();
        let (f, _) = external_forces(&disc.points, disc.d, &scene.loads).unwrap();
        let t = Instant::now();
        let pattern = Pattern::new(&disc, &dofs, model.coupling());
        times[2].push(t.elapsed().as_secs_f64());
        let t = Instant::now();
        let k = Stiffness::assemble(&model, &disc, &dofs, &pattern);
        times[3].push(t.elapsed().as_secs_f64());
        let t = Instant::now();
        let mut chol = Cholesky::analyse(k.view(&pattern)).unwrap();
        eprintln!(
            "  (factor needs {:.2} GiB)",
            chol.factor_bytes() as f64 / 1073741824.0
        );
        if let Err(e) = dhpd::solve::check_memory(chol.factor_bytes()) {
            println!("{dim} n={n}: {e}");
            return;
        }
        times[4].push(t.elapsed().as_secs_f64());
        let t = Instant::now();
        chol.factorize(k.view(&pattern)).unwrap();
        times[5].push(t.elapsed().as_secs_f64());
        let b: Vec<f64> = dofs
            .free_dofs
            .iter()
            .map(|&(i, c)| f[i as usize][c as usize])
            .collect();
        let t = Instant::now();
        let mut x = b.clone();
        chol.solve_in_place(&mut x);
        times[6].push(t.elapsed().as_secs_f64());
        let residual = relative_residual(&k.mul(&pattern, &x), &b);
        info = format!(
            "{} points, {} bonds, {} dofs, nnz(K) {}, nnz(L) {}, residual {:.1e}",
            disc.points.len(),
            disc.bonds.len(),
            dofs.n_free(),
            pattern.nnz(),
            chol.nnz_l(),
            residual
        );
    }
    println!(
        "{dim} n={n} ({repeats} repeats, {} rayon threads): {info}",
        rayon::current_num_threads()
    );
    for (name, t) in names.iter().zip(times) {
        println!(
            "  {name:<10} median {:.3} s  (min {:.3}, max {:.3})",
            median(t.clone()),
            t.iter().cloned().fold(f64::INFINITY, f64::min),
            t.iter().cloned().fold(0.0, f64::max)
        );
    }
    println!("  peak memory {:.0} MiB", peak_memory_mib());
}
