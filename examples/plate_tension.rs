//! Plate under tension with two regions (004 Sec. 5.1, issue 3): a 1 m × 1 m steel
//! plate in plane stress (E = 200 GPa, ν = 1/3), left edge clamped, 200 MPa on the
//! right edge. The left half has spacing Δx₁ = 0.005 m, the right half
//! Δx₂ = 0.01 m, and each point's horizon is δ = n Δx of its own region
//! (n = 2…5), so the horizon doubles across x = 0.5: dual horizons.
//!
//! The clamp follows 004's fictitious boundary region: an extra strip of the left
//! material outside the plate, x ∈ [−3Δx₁, 0] (spacing Δx₁, `--layers K` changes
//! the 3), held at u = 0. The traction acts on the plate's outermost column.
//!
//! For both models (bond-based and shear) and every n, this solves the static
//! problem and compares it with the scikit-fem reference
//! `validation/plate_tension/fem/reference.json`, interpolated at each point's own
//! position:
//!
//! * u_x on the points within half their spacing of y = 0.5 (max and RMS error,
//!   normalised by the FEM u_x(1, 0.5) ≈ 9.81e-4 m);
//! * u_y on the points within half their spacing of x = 0.5 (normalised by the
//!   largest FEM |u_y| on that line);
//! * the relative error of u_x at the point nearest (1, 0.5);
//! * wall time per phase and the peak resident memory of each case.
//!
//! It prints a Markdown table (a full run also writes it to `results/table.md`)
//! and writes the profiles as CSV files to `validation/plate_tension/results/`,
//! which `validation/plate_tension/plot.py` turns into `plate_tension.png`.
//!
//! ```text
//! cargo run --release --example plate_tension
//! cargo run --release --example plate_tension -- shear 5          # one model, some n
//! cargo run --release --example plate_tension -- --layers 5 bond_based 5
//! cargo run --release --example plate_tension -- --field /tmp/fields   # also every point's u
//! ```
//!
//! Run it from the repository root (the paths are relative).

use dhpd::drivers::static_solve::{self, StaticSolution};
use dhpd::reference::FemReference;
use dhpd::scene::{parse_spec, Scene};
use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

/// Spacing of the left half (m), as in `dhpd::validation::plate_tension_text`.
const DX_LEFT: f64 = 0.005;
/// Spacing of the right half (m).
const DX_RIGHT: f64 = 0.01;
const REFERENCE: &str = "validation/plate_tension/fem/reference.json";
const RESULTS: &str = "validation/plate_tension/results";

fn scene(kind: &str, n: f64, layers: usize) -> Scene {
    let text = dhpd::validation::plate_tension_text(kind, n, layers);
    let spec = parse_spec(&text, false).expect("generated scene parses");
    Scene::try_from_spec(spec, Path::new("."), "plate_tension").expect("generated scene is valid")
}

/// Peak resident memory of this process in MiB since the last reset (Linux only).
fn peak_rss_mib() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib / 1024.0)
}

/// Resets the peak-RSS counter (Linux ≥ 4.0); harmless elsewhere.
fn reset_peak_rss() {
    let _ = std::fs::write("/proc/self/clear_refs", "5");
}

struct Profile {
    /// (x, y, dhpd, FEM) per point, sorted along the line.
    rows: Vec<[f64; 4]>,
}

impl Profile {
    fn errors(&self, scale: f64) -> (f64, f64) {
        let e: Vec<f64> = self
            .rows
            .iter()
            .map(|r| (r[2] - r[3]).abs() / scale)
            .collect();
        let max = e.iter().copied().fold(0.0, f64::max);
        let rms = (e.iter().map(|v| v * v).sum::<f64>() / e.len() as f64).sqrt();
        (max, rms)
    }

    fn write(&self, path: &Path, header: &str) -> std::io::Result<()> {
        let mut s = String::from(header);
        s.push('\n');
        for r in &self.rows {
            let _ = writeln!(s, "{:.6},{:.6},{:.9e},{:.9e}", r[0], r[1], r[2], r[3]);
        }
        std::fs::write(path, s)
    }
}

/// Points of the plate (x ≥ 0) within half their spacing of the line
/// `coord[axis] = at`, with displacement component `comp` and the FEM field there.
fn profile(s: &StaticSolution, fem: &FemReference, axis: usize, at: f64, comp: usize) -> Profile {
    let p = &s.disc.points;
    let field = ["ux", "uy"][comp];
    let mut rows: Vec<[f64; 4]> = (0..p.len())
        .filter(|&i| p.x[i][0] > 0.0 && (p.x[i][axis] - at).abs() <= 0.5 * p.spacing[i] + 1e-12)
        .filter_map(|i| {
            let [x, y, _] = p.x[i];
            fem.grid
                .interpolate(field, x, y)
                .map(|f| [x, y, s.u[i][comp], f])
        })
        .collect();
    let along = 1 - axis;
    rows.sort_by(|a, b| {
        a[along]
            .total_cmp(&b[along])
            .then(a[axis].total_cmp(&b[axis]))
    });
    Profile { rows }
}

/// Every point: x, y, u_x, u_y and the FEM u_x, u_y at its position (empty outside the plate).
fn write_field(s: &StaticSolution, fem: &FemReference, path: &Path) -> std::io::Result<()> {
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir)?;
    }
    let p = &s.disc.points;
    let mut out = String::from("x,y,spacing,horizon,u_x,u_y,u_x_fem,u_y_fem\n");
    for i in 0..p.len() {
        let [x, y, _] = p.x[i];
        let f = |name: &str| {
            fem.grid
                .interpolate(name, x, y)
                .map_or(String::new(), |v| format!("{v:.9e}"))
        };
        let _ = writeln!(
            out,
            "{x:.6},{y:.6},{},{},{:.9e},{:.9e},{},{}",
            p.spacing[i],
            p.horizon[i],
            s.u[i][0],
            s.u[i][1],
            f("ux"),
            f("uy")
        );
    }
    std::fs::write(path, out)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let mut layers = 3usize;
    if let Some(k) = args.iter().position(|a| a == "--layers") {
        layers = args.get(k + 1).ok_or("--layers needs a value")?.parse()?;
        args.drain(k..k + 2);
    }
    let mut field_dir: Option<std::path::PathBuf> = None;
    if let Some(k) = args.iter().position(|a| a == "--field") {
        field_dir = Some(args.get(k + 1).ok_or("--field needs a directory")?.into());
        args.drain(k..k + 2);
    }
    let mut models: Vec<&str> = ["bond_based", "shear"]
        .into_iter()
        .filter(|m| args.iter().any(|a| a == m))
        .collect();
    if models.is_empty() {
        models = vec!["bond_based", "shear"];
    }
    let mut ns: Vec<u32> = args.iter().filter_map(|a| a.parse().ok()).collect();
    if ns.is_empty() {
        ns = vec![2, 3, 4, 5];
    }

    let fem = FemReference::from_file(Path::new(REFERENCE))?;
    let ux_tip = fem
        .grid
        .interpolate("ux", 1.0, 0.5)
        .ok_or("FEM u_x(1, 0.5)")?;
    let uy_scale = fem
        .profiles
        .as_ref()
        .and_then(|p| p.get("x=0.5"))
        .and_then(|p| p.get("uy"))
        .ok_or("FEM profile x=0.5 / uy")?
        .iter()
        .fold(0.0f64, |m, v| m.max(v.abs()));
    std::fs::create_dir_all(RESULTS)?;
    let suffix = if layers == 3 {
        String::new()
    } else {
        format!("_layers{layers}")
    };

    let mut table = String::new();
    let _ = writeln!(
        table,
        "FEM: u_x(1, 0.5) = {ux_tip:.6e} m, max |u_y| on x = 0.5: {uy_scale:.6e} m; fictitious clamp layer {layers} Δx₁ = {} m.\n",
        layers as f64 * DX_LEFT
    );
    let _ = writeln!(table, "| model | n | δ₁ / δ₂ (m) | points | free dofs | nnz(K) | u_x on y=0.5: max / RMS err | u_y on x=0.5: max / RMS err | u_x near (1, 0.5): err | neighbours (s) | pattern+assembly (s) | factorisation (s) | solve (s) | total (s) | peak RSS (GiB) |");
    let _ = writeln!(
        table,
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
    );
    print!("{table}");
    let t_all = Instant::now();
    for &model in &models {
        for &n in &ns {
            reset_peak_rss();
            let t = Instant::now();
            let sc = scene(model, n as f64, layers);
            let s = static_solve::solve(&sc)?;
            let total = t.elapsed().as_secs_f64();
            let peak = peak_rss_mib().map_or(f64::NAN, |m| m / 1024.0);
            eprintln!(
                "{model} n={n}: residual {:.1e}, asymmetry {:.2e}, gmres {:?}, nnz(L) {:?}, reactions {:?}",
                s.residual,
                s.counts.asymmetry,
                s.counts.gmres,
                s.counts.nnz_l,
                s.reactions.iter().map(|r| r.force).collect::<Vec<_>>()
            );

            let ux = profile(&s, &fem, 1, 0.5, 0);
            let uy = profile(&s, &fem, 0, 0.5, 1);
            let (ux_max, ux_rms) = ux.errors(ux_tip);
            let (uy_max, uy_rms) = uy.errors(uy_scale);
            let p = &s.disc.points;
            let tip = (0..p.len())
                .min_by(|&a, &b| {
                    let d = |i: usize| (p.x[i][0] - 1.0).powi(2) + (p.x[i][1] - 0.5).powi(2);
                    d(a).total_cmp(&d(b))
                })
                .expect("points");
            let fem_tip = fem
                .grid
                .interpolate("ux", p.x[tip][0], p.x[tip][1])
                .ok_or("FEM at the tip point")?;
            let tip_err = s.u[tip][0] / fem_tip - 1.0;

            let name = format!("{model}_n{n}{suffix}");
            ux.write(
                &Path::new(RESULTS).join(format!("{name}_ux_y0.5.csv")),
                "x,y,u_x,u_x_fem",
            )?;
            uy.write(
                &Path::new(RESULTS).join(format!("{name}_uy_x0.5.csv")),
                "x,y,u_y,u_y_fem",
            )?;

            if let Some(dir) = &field_dir {
                write_field(&s, &fem, &dir.join(format!("{name}_field.csv")))?;
            }

            let tm = &s.timings;
            let row = format!(
                "| {} | {n} | {} / {} | {} | {} | {:.2} M | {:.2} % / {:.2} % | {:.2} % / {:.2} % | {:+.2} % (x = {:.4}, y = {:.4}) | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} |",
                if model == "shear" { "shear" } else { "bond-based" },
                n as f64 * DX_LEFT,
                n as f64 * DX_RIGHT,
                s.counts.points,
                s.counts.dofs,
                s.counts.nnz_k as f64 / 1e6,
                100.0 * ux_max,
                100.0 * ux_rms,
                100.0 * uy_max,
                100.0 * uy_rms,
                100.0 * tip_err,
                p.x[tip][0],
                p.x[tip][1],
                tm.neighbour_search,
                tm.pattern + tm.assembly,
                tm.symbolic_factorization + tm.numeric_factorization,
                tm.solve,
                total,
                peak,
            );
            println!("{row}");
            let _ = writeln!(table, "{row}");
        }
    }
    let wall = t_all.elapsed().as_secs_f64();
    println!("\ntotal wall time {wall:.1} s");
    let _ = writeln!(table, "\ntotal wall time {wall:.1} s");
    if models.len() == 2 && ns == [2, 3, 4, 5] {
        std::fs::write(Path::new(RESULTS).join(format!("table{suffix}.md")), table)?;
    }
    Ok(())
}
