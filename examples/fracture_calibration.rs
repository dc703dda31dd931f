//! Measures the dissipation factor `D` of `damage::calibration`: the energy a
//! lattice dissipates per unit area of steady crack growth, over `G₀`, with the
//! continuum critical values of the papers.
//!
//! ```text
//! cargo run --release --example fracture_calibration -- table        # D(m), overlap partial volumes
//! cargo run --release --example fracture_calibration -- table none   # D at m = 3.015, 4.015 without correction
//! cargo run --release --example fracture_calibration -- table ramp   # the same with the ramp of 000 Eq. A.1
//! cargo run --release --example fracture_calibration -- independence # angle, height, E, G₀, spacing
//! cargo run --release --example fracture_calibration -- check        # dissipation calibration: D = 1
//! cargo run --release --example fracture_calibration -- 3d [m ...]    # bond-based 3D strip (default m = 3.015)
//! ```
//!
//! The specimen is `dhpd::validation::fracture::Strip`: a long strip split from an
//! edge pre-crack by the event strategy. Every event releases
//! `ΔE = Δ (R_critical − R_broken) / 2` at fixed grip displacement `Δ` (exact for
//! the sequentially linear analysis); `ΔE` is booked in equal shares at the
//! midpoints of the bonds the event broke. The energy booked between
//! `notch + 3δ` and `length − max(H, 4δ)`, away from the start of the crack and from
//! the end zone where the remaining ligament (shorter than about `H`) bends,
//! over `G₀ × that length`, is `D`. Results go to
//! `validation/fracture/results/calibration_*.csv`, the scenes to
//! `validation/fracture/scenes/calibration/`.

use dhpd::validation::fracture::{Loading, Strip, StripDissipation};
use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

const RESULTS: &str = "validation/fracture/results";
const SCENES: &str = "validation/fracture/scenes/calibration";

/// One measurement, with its profile written to the results.
fn measure(strip: &Strip) -> StripDissipation {
    let t = Instant::now();
    let r = strip
        .dissipation(Path::new(SCENES))
        .expect("the strip runs");
    let mut csv = String::from("x_over_spacing,dissipated_over_g0\n");
    for (k, v) in r.profile.iter().enumerate() {
        let _ = writeln!(csv, "{},{v:.6}", k as f64 + 0.5);
    }
    write(&format!("calibration_profile_{}.csv", strip.name()), &csv);
    println!(
        "{}: D = {:.4}, r = {:.4} (window {:.1}..{:.1} spacings), work to separation {:.4} G₀A, {} points, {} bonds broken, {:.1} s",
        strip.name(),
        r.d,
        r.trapping.unwrap_or(f64::NAN),
        r.window.0 / strip.spacing,
        r.window.1 / strip.spacing,
        r.work,
        r.points,
        r.bonds_broken,
        t.elapsed().as_secs_f64()
    );
    r
}

fn write(name: &str, text: &str) {
    std::fs::create_dir_all(RESULTS).expect("results directory");
    std::fs::write(Path::new(RESULTS).join(name), text).expect("results writable");
}

const HEADER: &str =
    "case,model,mode,m,volume_correction,angle,height_cells,youngs_modulus,fracture_energy,spacing,calibration,points,bonds_broken,D,trapping_ratio,work_over_g0a,seconds\n";

fn row(csv: &mut String, case: &str, s: &Strip, m: &StripDissipation) {
    let mode = if s.loading == Loading::Tension {
        "I"
    } else {
        "II"
    };
    let _ = writeln!(
        csv,
        "{case},{},{mode},{},{},{},{},{:e},{},{:e},{},{},{},{:.5},{},{:.5},{:.2}",
        s.model,
        s.horizon_factor,
        s.volume_correction,
        s.angle,
        s.height_cells,
        s.youngs_modulus,
        s.fracture_energy,
        s.spacing,
        s.calibration,
        m.points,
        m.bonds_broken,
        m.d,
        m.trapping.map_or(String::new(), |r| format!("{r:.5}")),
        m.work,
        m.seconds
    );
}

/// `D(m)` for the table in `src/damage/calibration.rs`.
fn table(model: &'static str, rule: &'static str, ms: &[f64]) {
    let mut csv = String::from(HEADER);
    let mut rust = format!("// {model}, {rule}\n");
    for &m in ms {
        let mut s = Strip::new(model, m);
        s.volume_correction = rule;
        let r = measure(&s);
        row(&mut csv, "table", &s, &r);
        let _ = writeln!(
            rust,
            "({m:.3}, {:.4}, {:.4}),",
            r.d,
            r.trapping.unwrap_or(f64::NAN)
        );
        write(&format!("calibration_table_{model}_{rule}.csv"), &csv);
    }
    println!("{rust}");
}

/// With the dissipation calibration the strips dissipate `G₀`: `D = 1` up to the
/// table's interpolation.
fn check(model: &'static str) {
    let mut csv = String::from(HEADER);
    for m in [3.015, 3.265, 4.015] {
        let mut s = Strip::new(model, m);
        s.calibration = "dissipation";
        let r = measure(&s);
        row(&mut csv, "check", &s, &r);
        write(&format!("calibration_check_{model}.csv"), &csv);
    }
}

/// `D` on other lattices and specimens: the crack at 45° and 30° to the grid,
/// a taller strip, other E, G₀ and spacing.
fn independence(model: &'static str, m: f64) {
    let mut csv = String::from(HEADER);
    let base = Strip::new(model, m);
    let mut cases: Vec<(&str, Strip)> = vec![("grid", base.clone())];
    for angle in [45.0, 30.0] {
        let mut s = base.clone();
        s.angle = angle;
        cases.push(("rotated", s));
    }
    let mut tall = base.clone();
    tall.height_cells = 50;
    cases.push(("taller", tall));
    let mut stiff = base.clone();
    stiff.youngs_modulus *= 7.0;
    stiff.fracture_energy *= 0.1;
    cases.push(("E x7 and G0 / 10", stiff));
    let mut fine = base.clone();
    fine.spacing *= 0.37;
    cases.push(("spacing x 0.37", fine));
    for (case, s) in &cases {
        let r = measure(s);
        row(&mut csv, case, s, &r);
    }
    write(&format!("calibration_independence_{model}.csv"), &csv);
}

/// The shear model's criteria in mode I and mode II (a shorter strip: every
/// shear-model event re-solves the broken owners' whole families).
fn modes(m: f64, only: Option<&str>) {
    let mut csv = String::from(HEADER);
    for criterion in ["deviatoric", "energy"] {
        for loading in [Loading::Tension, Loading::Shear] {
            if only.is_some_and(|c| c != criterion) {
                continue;
            }
            let mut s = Strip::new("shear", m);
            s.shear_criterion = criterion;
            s.loading = loading;
            s.length_cells = 70;
            s.height_cells = 20;
            s.notch_cells = 15;
            let r = measure(&s);
            row(&mut csv, criterion, &s, &r);
            write(
                &format!(
                    "calibration_modes_shear{}.csv",
                    only.map_or(String::new(), |c| format!("_{c}"))
                ),
                &csv,
            );
        }
    }
}

/// `D` of the bond-based model in 3D: a strip 14 spacings deep, `D` booked in
/// its bulk; the profile through the depth shows the faces.
fn three_d(ms: &[f64]) {
    let mut csv = String::from(HEADER);
    for &m in ms {
        let s = Strip::new_3d(m);
        let r = measure(&s);
        row(&mut csv, "3d", &s, &r);
        write("calibration_3d_bond_based.csv", &csv);
        let mut depth = String::from("z_over_spacing,dissipated_over_g0\n");
        for (k, v) in r.depth_profile.iter().enumerate() {
            let _ = writeln!(depth, "{},{v:.6}", k as f64 + 0.5);
        }
        write(
            &format!("calibration_depth_profile_{}.csv", s.name()),
            &depth,
        );
        println!("  through the depth (per spacing): {:.3?}", r.depth_profile);
    }
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let model: &'static str = if args.iter().any(|a| a == "shear") {
        "shear"
    } else {
        "bond_based"
    };
    match args.first().map(String::as_str) {
        Some("one") => {
            let m: f64 = args.get(1).and_then(|a| a.parse().ok()).unwrap_or(3.015);
            measure(&Strip::new(model, m));
        }
        Some("table") => match args.get(1).map(String::as_str) {
            Some("none") => table(model, "none", &[3.015, 4.015]),
            Some("ramp") => table(model, "ramp", &[3.015, 4.015]),
            _ => table(
                model,
                "overlap",
                &[2.015, 2.515, 3.015, 3.515, 4.015, 4.515, 5.015],
            ),
        },
        Some("check") => check(model),
        Some("modes") => modes(
            args.get(1).and_then(|a| a.parse().ok()).unwrap_or(3.015),
            args.get(2).map(String::as_str),
        ),
        Some("independence") => independence(model, 3.015),
        Some("3d") => {
            let ms: Vec<f64> = args[1..].iter().filter_map(|a| a.parse().ok()).collect();
            three_d(if ms.is_empty() { &[3.015] } else { &ms });
        }
        _ => eprintln!("usage: fracture_calibration one [m]|table [overlap|none|ramp]|independence|check [shear]|3d [m ...]"),
    }
}
