//! Fracture validation studies (validation/fracture/README.md): the single-edge-
//! notched tension (SENT) plate against LEFM for both models, the energy
//! dissipated to separation, DH-PD with a fine band along the crack path, the
//! three breakage strategies, and the kink of a crack under in-plane shear.
//!
//! ```text
//! cargo run --release --example fracture_study -- lefm bond_based   # peak load sweep (δ/a, m)
//! cargo run --release --example fracture_study -- lefm shear
//! cargo run --release --example fracture_study -- energy bond_based # full separation: ∫P du vs G₀ A
//! cargo run --release --example fracture_study -- band              # DH-PD fine band vs uniform
//! cargo run --release --example fracture_study -- strategies        # event / all / most_critical
//! cargo run --release --example fracture_study -- kink              # shear grip: kink angle (from=N resumes)
//! cargo run --release --example fracture_study -- kink_strategies   # the same with each strategy
//! cargo run --release --example fracture_study -- scenes            # write the scene files
//! ```
//!
//! Results go to `validation/fracture/results/` (CSV); `validation/fracture/plot.py`
//! draws the figures. Add `quick` after the study name for the coarse settings only.

use dhpd::drivers::quasi_static::{self, QuasiStaticSolution};
use dhpd::drivers::static_solve;
use dhpd::output::csv::write_load_displacement;
use dhpd::reference::FemReference;
use dhpd::solve::pipeline::Route;
use dhpd::validation::fracture::{
    Loading, Sent, FRACTURE_ENERGY, INCLINED_HALF_LENGTH, NOTCH, WIDTH,
};
use dhpd::vector::{norm, sub};
use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

const RESULTS: &str = "validation/fracture/results";

/// The LEFM critical load (FEM, clamped grips) of a specimen: the SENT plate with
/// an edge notch `a`, or the centre-cracked panel with half-length `c`
/// (`fem/reference_sent.json`, `fem/reference_cct.json`).
fn lefm_peak(case: &Sent) -> f64 {
    let (file, material, a) = match case.centre_crack {
        Some(c) => ("reference_cct.json", "plane_stress_nu_1/3", c),
        None => ("reference_sent.json", "plane_stress_nu_1/3", case.notch),
    };
    let text = std::fs::read_to_string(format!("validation/fracture/fem/{file}"))
        .expect("run from the repository root");
    let json: serde_json::Value = serde_json::from_str(&text).expect("valid JSON");
    let case = json["materials"].get(material).unwrap_or(&json);
    let a_over_w = case["a_over_W"].as_array().expect("a_over_W");
    let k = a_over_w
        .iter()
        .position(|v| (v.as_f64().unwrap() - a / WIDTH).abs() < 1e-9)
        .expect("the crack length is in the FEM sweep");
    case["P_c"][k].as_f64().expect("P_c")
}

/// One run and what the studies read from it.
struct Outcome {
    solution: QuasiStaticSolution,
    points: usize,
    seconds: f64,
    peak: f64,
    first_break: f64,
}

fn run(case: &Sent) -> Outcome {
    let scene = if case.lattice_angle == 0.0 {
        case.scene()
    } else {
        let path = case
            .write(Path::new("validation/fracture/scenes"))
            .expect("scenes directory writable");
        dhpd::scene::load(&path).expect("the rotated-lattice scene loads")
    };
    let t = Instant::now();
    let prepared = static_solve::prepare(&scene).expect("the scene prepares");
    let points = prepared.disc.points.len();
    let solution = quasi_static::run(&scene, prepared, &mut ()).expect("the run succeeds");
    let seconds = t.elapsed().as_secs_f64();
    let top = solution.set_names.iter().position(|n| n == "top").unwrap();
    let axis = if case.loading == Loading::Tension {
        1
    } else {
        0
    };
    let peak = solution
        .records
        .iter()
        .map(|r| r.reactions[top][axis].abs())
        .fold(0.0, f64::max);
    // The load at which the first bond reaches its critical value: the first
    // critical state (event strategy), else the first step that broke a bond.
    let first_break = solution
        .records
        .iter()
        .find(|r| r.state == quasi_static::StateKind::Critical || r.broken_total > 0)
        .map_or(f64::NAN, |r| r.reactions[top][axis].abs());
    std::fs::create_dir_all(RESULTS).expect("results directory");
    let curve = Path::new(RESULTS).join(format!("curve_{}.csv", case.name()));
    write_load_displacement(&curve, &solution).expect("results directory writable");
    Outcome {
        solution,
        points,
        seconds,
        peak,
        first_break,
    }
}

/// Energy dissipated: at every event the reaction drops at fixed displacement,
/// releasing `Δ (R_critical − R_broken) / 2`; summed to separation this is `∫ P du`.
fn dissipated(s: &QuasiStaticSolution) -> f64 {
    let top = s.set_names.iter().position(|n| n == "top").unwrap();
    s.records
        .windows(2)
        .filter(|w| {
            w[0].state == quasi_static::StateKind::Critical
                && w[1].state == quasi_static::StateKind::Broken
        })
        .map(|w| 0.5 * w[1].displacement * (w[0].reactions[top][1] - w[1].reactions[top][1]))
        .sum()
}

/// Solves with a fresh factorisation, and re-solves with the old factor (low-rank
/// update or Krylov).
fn solves(s: &QuasiStaticSolution) -> (usize, usize) {
    let fresh = s
        .solves
        .iter()
        .filter(|x| x.report.route == Route::Factor)
        .count();
    (fresh, s.solves.len() - fresh)
}

fn write(name: &str, text: &str) {
    std::fs::create_dir_all(RESULTS).expect("results directory");
    let path = Path::new(RESULTS).join(name);
    std::fs::write(&path, text).expect("results writable");
    println!("wrote {}", path.display());
}

/// The specimens of the peak-load study: SENT with a/W = 0.5 and 0.3 and the
/// centre-cracked panel with c/W = 0.2, each at horizon factor `m` with spacings
/// giving δ/a ≈ 0.2, 0.1 (and 0.05 for the SENT a/W = 0.5).
fn specimens(model: &'static str, quick: bool) -> Vec<Sent> {
    let mut cases = Vec::new();
    let sweep: &[(Option<f64>, f64, &[(usize, f64)])] = if quick {
        &[(None, NOTCH, &[(30, 3.015), (40, 4.015)])]
    } else if model == "shear" {
        &[
            (None, NOTCH, &[(30, 3.015), (60, 3.015)]),
            (None, 0.03, &[(50, 3.015)]),
            (Some(0.02), 0.02, &[(75, 3.015)]),
        ]
    } else {
        &[
            (
                None,
                NOTCH,
                &[
                    (30, 3.015),
                    (40, 4.015),
                    (60, 3.015),
                    (80, 4.015),
                    (120, 3.015),
                    (160, 4.015),
                ],
            ),
            (
                None,
                0.03,
                &[(50, 3.015), (67, 4.015), (100, 3.015), (134, 4.015)],
            ),
            (Some(0.02), 0.02, &[(75, 3.015), (100, 4.015), (150, 3.015)]),
        ]
    };
    for &(centre, notch, grid) in sweep {
        for &(cells, m) in grid {
            let mut case = Sent::new(model, cells, m);
            case.notch = notch;
            case.centre_crack = centre;
            case.stop_after_peak = Some(0.7);
            cases.push(case);
        }
    }
    cases
}

/// Peak load against LEFM on every specimen, with the three calibrations.
fn lefm(model: &'static str, quick: bool) {
    let mut csv = String::from(
        "model,criterion,specimen,calibration,cells,m,delta_over_a,points,peak,lefm,error,first_break,fresh,reuse,seconds\n",
    );
    let criteria: &[&str] = if model == "shear" {
        &["energy", "deviatoric"]
    } else {
        &["stretch"]
    };
    // The peak calibration with the default criterion (it scales every event load of
    // the dissipation-calibrated run by 1/r; the deviatoric rule keeps two runs).
    let variants = criteria.iter().flat_map(|&c| {
        let calibrations: &[&str] = if c == "deviatoric" {
            &["dissipation", "continuum"]
        } else {
            &["dissipation", "peak", "continuum"]
        };
        calibrations.iter().map(move |&k| (k, c))
    });
    for base in specimens(model, quick) {
        for (calibration, criterion) in variants.clone() {
            let mut case = base.clone();
            case.calibration = calibration;
            if model == "shear" {
                case.shear_criterion = criterion;
            }
            let reference = lefm_peak(&case);
            let o = run(&case);
            let (fresh, reuse) = solves(&o.solution);
            let crack = case.centre_crack.unwrap_or(case.notch);
            let delta_a = case.horizon() / crack;
            let specimen = match case.centre_crack {
                Some(c) => format!("cct_c{:.0}mm", 1e3 * c),
                None => format!("sent_a{:.0}mm", 1e3 * case.notch),
            };
            println!(
                "{model} {criterion} {specimen} {calibration} W/Δx = {}, m = {}, δ/a = {delta_a:.3}: {} points, peak {:.4e} N/m vs LEFM {reference:.4e} ({:+.1} %), first break at {:.3e}, {fresh} + {reuse} solves, {:.1} s",
                case.cells,
                case.horizon_factor,
                o.points,
                o.peak,
                100.0 * (o.peak / reference - 1.0),
                o.first_break,
                o.seconds
            );
            let _ = writeln!(
                csv,
                "{model},{criterion},{specimen},{calibration},{},{},{delta_a:.4},{},{:.6e},{reference:.6e},{:.5},{:.6e},{fresh},{reuse},{:.2}",
                case.cells,
                case.horizon_factor,
                o.points,
                o.peak,
                o.peak / reference - 1.0,
                o.first_break,
                o.seconds
            );
            write(&format!("lefm_{model}.csv"), &csv);
        }
    }
}

/// Full separation: work of the grip against `G₀ × ligament`, with the energy
/// of the broken bonds at their critical stretch (bond-based).
fn energy(model: &'static str, quick: bool) {
    let area = FRACTURE_ENERGY * (WIDTH - NOTCH);
    let mut csv = String::from(
        "model,cells,m,points,dissipated_over_g0a,crossing_bonds_over_g0a,broken_on_line_over_g0a,broken_off_line_over_g0a,peak,seconds\n",
    );
    let grid: &[(usize, f64)] = if quick {
        &[(30, 3.015)]
    } else if model == "shear" {
        // The shear model's factor is measured at m = 3.015 (other m keep the
        // continuum value).
        &[(30, 3.015), (40, 3.015), (60, 3.015)]
    } else {
        &[
            (30, 3.015),
            (40, 4.015),
            (40, 3.015),
            (60, 3.015),
            (50, 5.015),
        ]
    };
    for &(cells, m) in grid {
        let case = Sent::new(model, cells, m);
        let o = run(&case);
        let w = dissipated(&o.solution);
        // The bond energies split by line are a bond-based analysis (empty fields
        // for the shear model).
        let split = if model == "bond_based" {
            let (crossing, on, off) = bond_energies(&case, &o.solution);
            println!(
                "bonds crossing the ligament at s₀: {crossing:.4} G₀A; broken on the line {on:.4}, off the line {off:.4}"
            );
            format!("{crossing:.5},{on:.5},{off:.5}")
        } else {
            ",,".to_string()
        };
        println!(
            "{model} W/Δx = {cells}, m = {m}: ∫P du = {:.4} G₀A; {:.1} s",
            w / area,
            o.seconds
        );
        let _ = writeln!(
            csv,
            "{model},{cells},{m},{},{:.5},{split},{:.6e},{:.2}",
            o.points,
            w / area,
            o.peak,
            o.seconds
        );
    }
    write(&format!("energy_{model}.csv"), &csv);
}

/// Energies `C s₀² |ξ| V_i V_j ν / 2` (per unit G₀ × ligament) of: every bond
/// crossing the ligament line (the continuum calibration of s₀, discretised),
/// the broken bonds crossing it, and the broken bonds off it.
fn bond_energies(case: &Sent, s: &QuasiStaticSolution) -> (f64, f64, f64) {
    let scene = case.scene();
    let bb = dhpd::model::bond_based::BondBased::new(
        &s.disc,
        scene.model.dimension,
        &scene.materials,
        scene.model.thickness,
    );
    let criterion = dhpd::damage::Criterion::new(&scene, &s.disc);
    let (x, v, bonds) = (&s.disc.points.x, &s.disc.points.volume, &s.disc.bonds);
    let (mut crossing, mut on, mut off) = (0.0, 0.0, 0.0);
    for i in 0..x.len() {
        for b in bonds.owned_by(i) {
            let j = bonds.neighbour[b] as usize;
            let s0 = criterion.critical(i);
            let e = 0.5
                * bb.micromodulus[i]
                * s0
                * s0
                * norm(&sub(&x[j], &x[i]))
                * v[i]
                * v[j]
                * bonds.volume_factor[b];
            let crosses = x[i][1] * x[j][1] < 0.0 && {
                let t = x[i][1] / (x[i][1] - x[j][1]);
                x[i][0] + t * (x[j][0] - x[i][0]) > NOTCH
            };
            if crosses {
                crossing += e;
            }
            if !bonds.intact[b] {
                if crosses {
                    on += e;
                } else {
                    off += e;
                }
            }
        }
    }
    let area = FRACTURE_ENERGY * (WIDTH - NOTCH);
    (crossing / area, on / area, off / area)
}

/// DH-PD where it matters: a fine band along the crack path, twice the spacing
/// elsewhere, against the uniform fine and coarse plates and the
/// constant-horizon baseline on the same points.
fn band(quick: bool) {
    let reference = lefm_peak(&Sent::new("bond_based", 40, 3.015));
    let (cells, m) = if quick { (40, 3.015) } else { (80, 3.015) };
    let fine = Sent::new("bond_based", cells, m);
    let half = |cells_band: usize| cells_band as f64 * 2.0 * fine.spacing();
    let mut banded = fine.clone();
    banded.fine_band = Some(half(if quick { 4 } else { 6 }));
    let mut constant = banded.clone();
    constant.horizons = "constant";
    let coarse = Sent::new("bond_based", cells / 2, m);
    let mut csv = String::from("case,points,peak,error,deviation,seconds\n");
    for (label, mut case) in [
        ("uniform fine", fine),
        ("DH-PD fine band", banded),
        ("constant horizon, same points", constant),
        ("uniform coarse", coarse),
    ] {
        case.stop_after_peak = Some(0.5);
        let o = run(&case);
        let deviation = crack_deviation(&o.solution, NOTCH, 0.0);
        if case.fine_band.is_some() && case.horizons == "dual" {
            write_damage(&case.name(), &o.solution);
        }
        println!(
            "{label}: {} points, peak {:.4e} N/m ({:+.1} % vs LEFM), crack within {:.2e} m of y = 0, {:.1} s",
            o.points,
            o.peak,
            100.0 * (o.peak / reference - 1.0),
            deviation,
            o.seconds
        );
        let _ = writeln!(
            csv,
            "{label},{},{:.6e},{:.5},{deviation:.4e},{:.2}",
            o.points,
            o.peak,
            o.peak / reference - 1.0,
            o.seconds
        );
    }
    write("band.csv", &csv);
}

/// The largest distance from `y = y0`, over the point columns ahead of
/// `x_tip`, of the centroid of each column's most damaged points.
fn crack_deviation(s: &QuasiStaticSolution, x_tip: f64, y0: f64) -> f64 {
    let x = &s.disc.points.x;
    let mut columns: Vec<f64> = x.iter().map(|p| p[0]).filter(|&c| c > x_tip).collect();
    columns.sort_by(f64::total_cmp);
    columns.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
    columns
        .iter()
        .filter_map(|&c| {
            let column: Vec<usize> = (0..x.len())
                .filter(|&i| (x[i][0] - c).abs() < 1e-9)
                .collect();
            let top = column.iter().map(|&i| s.damage[i]).fold(0.0, f64::max);
            (top > 0.0).then(|| {
                let cracked: Vec<usize> = column
                    .into_iter()
                    .filter(|&i| s.damage[i] >= 0.5 * top)
                    .collect();
                (cracked.iter().map(|&i| x[i][1]).sum::<f64>() / cracked.len() as f64 - y0).abs()
            })
        })
        .fold(0.0, f64::max)
}

/// The three strategies on one plate: curves, peaks, solves and times.
fn strategies(quick: bool) {
    let reference = lefm_peak(&Sent::new("bond_based", 40, 3.015));
    let cells = if quick { 30 } else { 40 };
    let mut csv =
        String::from("strategy,steps,peak,error,records,fresh,reuse,bonds,seconds,curve\n");
    for (k, (strategy, stepping)) in [
        ("event", ""),
        ("all", "steps = 100"),
        ("all", "steps = 400"),
        ("most_critical", "steps = 100"),
        ("all", "steps = 100\nmax_broken_per_step = 4"),
    ]
    .into_iter()
    .enumerate()
    {
        let mut case = Sent::new("bond_based", cells, 3.015);
        case.strategy = strategy;
        case.stepping = stepping.into();
        let o = run(&case);
        let (fresh, reuse) = solves(&o.solution);
        let broken = o.solution.records.last().map_or(0, |r| r.broken_total);
        let label = stepping.replace('\n', " ");
        let curve = format!("curve_strategy_{k}.csv");
        write_load_displacement(&Path::new(RESULTS).join(&curve), &o.solution)
            .expect("results writable");
        println!(
            "{strategy} {label}: peak {:.4e} N/m ({:+.1} %), {} records, {fresh} + {reuse} solves, {broken} bonds, {:.1} s",
            o.peak,
            100.0 * (o.peak / reference - 1.0),
            o.solution.records.len(),
            o.seconds
        );
        let _ = writeln!(
            csv,
            "{strategy},{label},{:.6e},{:.5},{},{fresh},{reuse},{broken},{:.2},{curve}",
            o.peak,
            o.peak / reference - 1.0,
            o.solution.records.len(),
            o.seconds
        );
    }
    write("strategies.csv", &csv);
}

/// Mode II: the shear grip on the notched plate; the direction in which the
/// crack leaves the notch tip, against the maximum tangential stress criterion,
/// over resolution (δ/a), horizon factor and the lattice's orientation; then the
/// inclined centre crack under tension.
/// The shear-grip (pure mode II) cases: model, W/Δx, m and the lattice's angle
/// against the notch (degrees).
const SHEAR_GRIP_SWEEP: &[(&str, usize, f64, f64)] = &[
    ("shear", 30, 3.015, 0.0),
    ("shear", 40, 3.015, 0.0),
    ("bond_based", 40, 3.015, 0.0),
    ("bond_based", 60, 3.015, 0.0),
    ("bond_based", 80, 3.015, 0.0),
    ("bond_based", 120, 3.015, 0.0),
    ("bond_based", 80, 4.015, 0.0),
    ("bond_based", 100, 5.015, 0.0),
    ("bond_based", 40, 3.015, 10.0),
    ("bond_based", 40, 3.015, 20.0),
    ("bond_based", 40, 3.015, 30.0),
    ("bond_based", 40, 3.015, 45.0),
];

/// `from`: the first case of the shear-grip sweep to run (a resumed sweep writes
/// `kink_part.csv`).
fn kink(quick: bool, from: usize) {
    let json: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string("validation/fracture/fem/reference_sent.json").unwrap(),
    )
    .unwrap();
    let mts = json["mode_mixity_B"]["mts_kink_angle_deg"]
        .as_f64()
        .expect("MTS angle");
    let mut csv = String::from(
        "case,model,cells,m,delta_over_a,lattice_deg,kink_deg,mts_deg,bonds_in_fit,broken,seconds\n",
    );
    let grid: &[(&'static str, usize, f64, f64)] = if quick {
        &[("shear", 30, 3.015, 0.0), ("bond_based", 30, 3.015, 0.0)]
    } else {
        SHEAR_GRIP_SWEEP
    };
    for &(model, cells, m, lattice) in grid.iter().skip(from) {
        let mut case = Sent::new(model, cells, m);
        case.loading = Loading::Shear;
        case.lattice_angle = lattice;
        // LEFM initiation under the shear grip is at Δ = 2.24e-4 m (FEM, J = G_c).
        case.max_load_factor = 10.0;
        case.stop_after_peak = Some(0.5);
        case.output_every = Some(1_000_000);
        let o = run(&case);
        let delta = case.horizon();
        let (angle, fitted) = kink_angle(&o.solution, [NOTCH, 0.0, 0.0], [1.0, 0.0, 0.0], delta);
        let broken = o.solution.records.last().map_or(0, |r| r.broken_total);
        println!(
            "{model} W/Δx = {cells}, m = {m}, lattice {lattice}°: kink {angle:.1}° (MTS {mts:.1}°) from {fitted} bonds, {broken} bonds, {:.1} s",
            o.seconds
        );
        let _ = writeln!(
            csv,
            "shear grip,{model},{cells},{m},{:.4},{lattice},{},{mts:.3},{fitted},{broken},{:.2}",
            delta / NOTCH,
            csv_angle(angle),
            o.seconds
        );
        write_damage(&case.name(), &o.solution);
    }
    // Mixed mode: the inclined centre crack under tension (K_I ≈ K_II).
    let json: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string("validation/fracture/fem/reference_inclined.json").unwrap(),
    )
    .unwrap();
    let _ = &json;
    let mts_inclined = -8.04;
    let grid: &[(&'static str, usize)] = if quick {
        &[("shear", 30), ("bond_based", 30)]
    } else {
        &[
            ("shear", 40),
            ("shear", 60),
            ("bond_based", 40),
            ("bond_based", 60),
        ]
    };
    for &(model, cells) in grid {
        let mut case = Sent::new(model, cells, 3.015);
        case.inclined = true;
        case.max_load_factor = 10.0;
        case.stop_after_peak = Some(0.5);
        let o = run(&case);
        // Each tip's kink against its own MTS direction (point symmetric: 180° apart).
        let tips = dhpd::validation::fracture::inclined_tips();
        let broken = o.solution.records.last().map_or(0, |r| r.broken_total);
        let e1 = std::f64::consts::FRAC_1_SQRT_2;
        for (tip, ahead, mts) in [
            (tips[0], [e1, e1, 0.0], mts_inclined),
            (tips[1], [-e1, -e1, 0.0], mts_inclined + 180.0),
        ] {
            let (angle, fitted) = kink_angle(&o.solution, tip, ahead, case.horizon());
            println!(
                "inclined, {model} W/Δx = {cells}: tip ({:.4}, {:.4}): kink {angle:.1}° from +x (MTS {mts:.1}°) from {fitted} broken bonds ahead of it, {broken} bonds in all, {:.1} s",
                tip[0], tip[1], o.seconds
            );
            let _ = writeln!(
                csv,
                "inclined tip ({:.4} {:.4}),{model},{cells},3.015,{:.4},0,{},{mts:.3},{fitted},{broken},{:.2}",
                tip[0],
                tip[1],
                case.horizon() / INCLINED_HALF_LENGTH,
                csv_angle(angle),
                o.seconds
            );
        }
        write_damage(&case.name(), &o.solution);
    }
    write(
        if from == 0 {
            "kink.csv"
        } else {
            "kink_part.csv"
        },
        &csv,
    );
}

/// The direction in which a crack left `tip` (degrees from +x, in (−180°, 180°])
/// and the number of broken bonds it rests on: the line through the tip that fits
/// the midpoints of the broken bonds between one and five horizons `delta` from
/// the tip best (least squares of their distances to it; the principal axis of
/// their second moment about the tip), pointing to their mean. Only midpoints
/// within 150° of `ahead` (the crack's direction at the tip) count, so the
/// pre-crack's own band is left out; the inner horizon, where every bond around
/// the tip breaks, too. NaN and 0 when fewer than two bonds qualify.
fn kink_angle(s: &QuasiStaticSolution, tip: [f64; 3], ahead: [f64; 3], delta: f64) -> (f64, usize) {
    let (x, bonds) = (&s.disc.points.x, &s.disc.bonds);
    let cos_limit = 150f64.to_radians().cos();
    let (mut sxx, mut syy, mut sxy, mut mx, mut my, mut n) = (0.0, 0.0, 0.0, 0.0, 0.0, 0);
    for i in 0..x.len() {
        for b in bonds.owned_by(i).filter(|&b| !bonds.intact[b]) {
            let j = bonds.neighbour[b] as usize;
            let mid: [f64; 3] = std::array::from_fn(|a| 0.5 * (x[i][a] + x[j][a]));
            let r = sub(&mid, &tip);
            let d = norm(&r);
            if d < delta || d > 5.0 * delta || (r[0] * ahead[0] + r[1] * ahead[1]) < cos_limit * d {
                continue;
            }
            sxx += r[0] * r[0];
            syy += r[1] * r[1];
            sxy += r[0] * r[1];
            mx += r[0];
            my += r[1];
            n += 1;
        }
    }
    if n < 2 {
        return (f64::NAN, n);
    }
    let mut theta = 0.5 * (2.0 * sxy).atan2(sxx - syy);
    if theta.cos() * mx + theta.sin() * my < 0.0 {
        theta += std::f64::consts::PI;
    }
    let deg = theta.to_degrees();
    (if deg > 180.0 { deg - 360.0 } else { deg }, n)
}

/// The pure mode II kink with each breakage strategy (bond-based, W/Δx = 60,
/// m = 3): whether the event strategy's order of breaks sets the angle.
fn kink_strategies() {
    let mut csv = String::from("strategy,cells,m,kink_deg,bonds_in_fit,broken,seconds\n");
    for strategy in ["event", "all", "most_critical"] {
        let mut case = Sent::new("bond_based", 60, 3.015);
        case.loading = Loading::Shear;
        case.strategy = strategy;
        if strategy != "event" {
            case.stepping = "steps = 1000".into();
        }
        case.max_load_factor = 10.0;
        case.stop_after_peak = Some(0.5);
        case.output_every = Some(1_000_000);
        let o = run(&case);
        let (angle, fitted) = kink_angle(
            &o.solution,
            [NOTCH, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            case.horizon(),
        );
        let broken = o.solution.records.last().map_or(0, |r| r.broken_total);
        println!(
            "{strategy}: kink {angle:.1}° from {fitted} bonds, {broken} bonds, {:.1} s",
            o.seconds
        );
        let _ = writeln!(
            csv,
            "{strategy},60,3.015,{},{fitted},{broken},{:.2}",
            csv_angle(angle),
            o.seconds
        );
    }
    write("kink_strategies.csv", &csv);
}

/// A kink angle for a CSV field: empty where too few bonds broke to fit one.
fn csv_angle(angle: f64) -> String {
    if angle.is_finite() {
        format!("{angle:.3}")
    } else {
        String::new()
    }
}

/// Damage per point (x, y, damage) for the damage maps.
fn write_damage(name: &str, s: &QuasiStaticSolution) {
    let mut t = String::from("x,y,damage\n");
    for (p, d) in s.disc.points.x.iter().zip(&s.damage) {
        let _ = writeln!(t, "{:.6e},{:.6e},{:.4}", p[0], p[1], d);
    }
    write(&format!("damage_{name}.csv"), &t);
}

/// A 3D notched bar: the peak load per unit depth against the 3D FEM reference
/// of the same bar and grips (`fem/reference_sent3d.json`, scikit-fem P2
/// tetrahedra), bond-based (ν = 1/4) and shear (ν = 1/3), with the continuum and
/// the dissipation calibration (3D bond-based: `D` of the 3D strip).
fn three_d(quick: bool, only: Option<&str>) {
    let json: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string("validation/fracture/fem/reference_sent3d.json").unwrap(),
    )
    .unwrap();
    let fem = |depth: f64, nu: &str| {
        json["results"][format!("T_{depth}")][nu]["P_c_per_depth"]
            .as_f64()
            .unwrap_or_else(|| panic!("no FEM reference for depth {depth}, {nu}"))
    };
    let mut csv = String::from(
        "model,calibration,cells,depth,points,peak_per_depth,fem_3d,error,first_bond_critical_per_depth,seconds\n",
    );
    let grid: &[(&str, &str, usize, f64)] = if quick {
        &[("bond_based", "dissipation", 20, 0.02)]
    } else {
        &[
            ("bond_based", "continuum", 20, 0.02),
            ("bond_based", "dissipation", 20, 0.02),
            ("bond_based", "continuum", 20, 0.04),
            ("bond_based", "dissipation", 20, 0.04),
            ("bond_based", "continuum", 30, 0.03),
            ("bond_based", "dissipation", 30, 0.03),
            ("shear", "continuum", 20, 0.02),
        ]
    };
    let file = only.map_or(String::from("three_d.csv"), |o| format!("three_d_{o}.csv"));
    for &(model, calibration, cells, depth) in grid {
        // `3d continuum`, `3d dissipation`, `3d shear`: one part of the table,
        // in its own file.
        if only.is_some_and(|o| o != calibration && o != model) {
            continue;
        }
        let mut case = Sent::new(model, cells, 3.015);
        case.depth = Some(depth);
        case.calibration = calibration;
        case.stop_after_peak = Some(0.7);
        let o = run(&case);
        let reference = fem(depth, if model == "shear" { "nu_1/3" } else { "nu_1/4" });
        let per_depth = o.peak / depth;
        println!(
            "3D {model} {calibration} W/Δx = {cells}, depth {depth} m: {} points, peak {per_depth:.4e} N/m \
             ({:+.1} % of the 3D FEM {reference:.4e}), {:.1} s",
            o.points,
            100.0 * (per_depth / reference - 1.0),
            o.seconds
        );
        let _ = writeln!(
            csv,
            "{model},{calibration},{cells},{depth},{},{per_depth:.6e},{reference:.6e},{:.5},{:.6e},{:.2}",
            o.points,
            per_depth / reference - 1.0,
            o.first_break / depth,
            o.seconds
        );
        write(&file, &csv);
    }
}

/// The scene files of every case the report shows.
fn scenes() {
    let dir = Path::new("validation/fracture/scenes");
    std::fs::create_dir_all(dir).unwrap();
    let mut cases = Vec::new();
    for (model, cells, m) in [
        ("bond_based", 30, 3.015),
        ("bond_based", 40, 4.015),
        ("bond_based", 60, 3.015),
        ("bond_based", 80, 4.015),
        ("bond_based", 120, 3.015),
        ("bond_based", 160, 4.015),
        ("shear", 30, 3.015),
        ("shear", 40, 4.015),
        ("shear", 60, 3.015),
        ("shear", 80, 4.015),
    ] {
        let mut case = Sent::new(model, cells, m);
        case.output_every = Some(50);
        cases.push(case);
    }
    // The other specimens of the peak-load study (both models where measured).
    for mut case in specimens("bond_based", false)
        .into_iter()
        .chain(specimens("shear", false))
        .filter(|c| c.notch != NOTCH || c.centre_crack.is_some())
    {
        case.stop_after_peak = None;
        case.output_every = Some(50);
        cases.push(case);
    }
    let mut banded = Sent::new("bond_based", 80, 3.015);
    banded.fine_band = Some(12.0 * banded.spacing());
    let mut constant = banded.clone();
    constant.horizons = "constant";
    cases.push(banded);
    cases.push(constant);
    for (strategy, stepping) in [("all", "steps = 100"), ("most_critical", "steps = 100")] {
        let mut case = Sent::new("bond_based", 40, 3.015);
        case.strategy = strategy;
        case.stepping = stepping.into();
        cases.push(case);
    }
    // The 3D bars of Sec. 7.
    for (model, cells, depth) in [
        ("bond_based", 20, 0.02),
        ("bond_based", 20, 0.04),
        ("bond_based", 30, 0.03),
        ("shear", 20, 0.02),
    ] {
        let mut bar = Sent::new(model, cells, 3.015);
        bar.depth = Some(depth);
        cases.push(bar);
    }
    for &(model, cells, m, lattice) in SHEAR_GRIP_SWEEP {
        let mut case = Sent::new(model, cells, m);
        case.loading = Loading::Shear;
        case.lattice_angle = lattice;
        case.max_load_factor = 10.0;
        case.output_every = Some(20);
        cases.push(case);
    }
    for strategy in ["all", "most_critical"] {
        let mut case = Sent::new("bond_based", 60, 3.015);
        case.loading = Loading::Shear;
        case.strategy = strategy;
        case.stepping = "steps = 1000".into();
        case.max_load_factor = 10.0;
        case.output_every = Some(20);
        cases.push(case);
    }
    for (model, cells) in [("shear", 40), ("bond_based", 60)] {
        let mut case = Sent::new(model, cells, 3.015);
        case.inclined = true;
        case.max_load_factor = 10.0;
        case.output_every = Some(20);
        cases.push(case);
    }
    for case in cases {
        let path = case.write(dir).unwrap();
        println!("wrote {}", path.display());
    }
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let quick = args.iter().any(|a| a == "quick");
    let model = if args.iter().any(|a| a == "shear") {
        "shear"
    } else {
        "bond_based"
    };
    let _ = FemReference::from_json; // the static references live in dhpd::reference
    match args.first().map(String::as_str) {
        Some("lefm") => lefm(model, quick),
        Some("energy") => energy(model, quick),
        Some("band") => band(quick),
        Some("strategies") => strategies(quick),
        Some("kink") => kink(
            quick,
            args.iter()
                .find_map(|a| a.strip_prefix("from=")?.parse().ok())
                .unwrap_or(0),
        ),
        Some("kink_strategies") => kink_strategies(),
        Some("3d") => three_d(quick, args.get(1).map(String::as_str)),
        Some("scenes") => scenes(),
        _ => eprintln!("usage: fracture_study lefm|energy|band|strategies|kink|kink_strategies|3d|scenes [bond_based|shear] [quick]"),
    }
}
