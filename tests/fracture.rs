//! Quasi-static fracture (issue 8): the damage rules, the three strategies,
//! the invariants of a run (bonds never heal, damage never decreases, the
//! reaction drops to zero when the crack crosses the ligament, the crack runs
//! straight in mode I), the re-solve with the old factor, the iterative route
//! against the direct one (issue 19), and what breaking does to the system
//! (points left without bonds, separation, failure).

mod common;

use common::scene;
use dhpd::assembly::pattern::Pattern;
use dhpd::assembly::stiffness::{self, Stiffness};
use dhpd::discretization::Discretization;
use dhpd::drivers::quasi_static::{self, Outcome, StateKind, StepRecord};
use dhpd::drivers::static_solve;
use dhpd::drivers::system::{self, right_hand_side};
use dhpd::drivers::{Observer, Snapshot};
use dhpd::error::Error;
use dhpd::model::bond_based::BondBased;
use dhpd::model::shear::Shear;
use dhpd::model::Coupling;
use dhpd::model::Model;
use dhpd::notes::Notes;
use dhpd::scene::Scene;
use dhpd::solve::low_rank::Term;
use dhpd::solve::pipeline::{Pipeline, Route};
use dhpd::solve::route;
use dhpd::solve::Matrices;
use dhpd::validation::fracture::Sent;

/// Collects what a run shows, checking bonds and damage at every snapshot.
#[derive(Default)]
struct Watch {
    records: Vec<StepRecord>,
    intact: Option<Vec<bool>>,
    damage: Option<Vec<f64>>,
    snapshots: usize,
}

impl Observer for Watch {
    fn record(&mut self, record: &StepRecord) -> Result<(), Error> {
        self.records.push(record.clone());
        Ok(())
    }

    fn snapshot(&mut self, s: &Snapshot) -> Result<(), Error> {
        {
            if let Some(before) = &self.intact {
                for (b, (&was, &is)) in before.iter().zip(&s.disc.bonds.intact).enumerate() {
                    assert!(was || !is, "bond {b} healed at step {}", s.step);
                }
            }
            if let Some(before) = &self.damage {
                for (i, (&was, &is)) in before.iter().zip(s.damage).enumerate() {
                    assert!(is >= was, "damage of point {i} fell at step {}", s.step);
                }
            }
            assert!(s.damage.iter().all(|&p| (0.0..=1.0).contains(&p)));
            assert!(s.u.iter().flatten().all(|v| v.is_finite()));
            self.intact = Some(s.disc.bonds.intact.clone());
            self.damage = Some(s.damage.to_vec());
            self.snapshots += 1;
        }
        Ok(())
    }
}

fn run(scene: &Scene) -> (quasi_static::QuasiStaticSolution, Watch) {
    let mut watch = Watch::default();
    let prepared = static_solve::prepare(scene).expect("the scene prepares");
    let solution = quasi_static::run(scene, prepared, &mut watch).expect("the run succeeds");
    (solution, watch)
}

/// The largest top-grip reaction (y) over a run and the load factor there.
fn peak(records: &[StepRecord], set: usize, axis: usize) -> (f64, f64) {
    records
        .iter()
        .map(|r| (r.reactions[set][axis].abs(), r.load_factor))
        .fold((0.0, 0.0), |a, b| if b.0 > a.0 { b } else { a })
}

/// A 1D bar whose points follow the linear field `u = ε x` (every point is
/// prescribed, one set per point): every bond has the stretch `ε`, so the first
/// event is at exactly `λ* = s₀ / ε` with `s₀ = sqrt(3 G₀ / (E δ))`
/// (formulation Sec. 3), every bond breaks there (a tie), and the bar falls
/// apart: no bond, every reaction zero (separation).
#[test]
fn a_uniformly_stretched_bar_breaks_at_the_critical_stretch() {
    let (e, g0, h, m, strain) = (2.0e11, 1.0e3, 0.01, 3.015, 1e-3);
    let mut text = format!(
        "[model]\ndimension = \"1d\"\n[discretization]\nhorizon_factor = {m}\n\
         [materials.steel]\nyoungs_modulus = {e:e}\nfracture_energy = {g0:e}\n\
         [[regions]]\nmaterial = \"steel\"\nspacing = {h}\nbox = {{ min = [0.0], max = [0.2] }}\n\
         [quasi_static]\nmax_load_factor = 10.0\n"
    );
    // Every point but one is prescribed on the linear field; the free one (in
    // the middle, with a full symmetric family) follows it exactly.
    for k in (0..20).filter(|&k| k != 10) {
        let x = (k as f64 + 0.5) * h;
        text += &format!(
            "[[boundary]]\nname = \"p{k}\"\nbox = {{ min = [{}], max = [{}] }}\ndisplacement = {{ x = {:e} }}\n",
            x - 0.1 * h,
            x + 0.1 * h,
            strain * x
        );
    }
    let scene = scene(&text);
    let s0 = (3.0 * g0 / (e * m * h)).sqrt();
    let expected = s0 / strain;
    let (solution, watch) = run(&scene);
    let first = watch
        .records
        .iter()
        .find(|r| r.state == StateKind::Critical)
        .expect("a bond breaks");
    assert!(
        (first.load_factor / expected - 1.0).abs() < 1e-12,
        "λ* = {}, s₀/ε = {expected}",
        first.load_factor
    );
    assert_eq!(
        solution.records.last().unwrap().broken_total,
        solution.bonds
    );
    assert!(solution.damage.iter().all(|&p| p == 1.0));
}

/// The largest distance from the line `y = 0`, over the columns of points
/// ahead of `x_tip`, of the centroid of the most damaged points of the column
/// (damage at least half the column's largest): where the crack runs.
fn crack_deviation(disc: &dhpd::discretization::Discretization, damage: &[f64], x_tip: f64) -> f64 {
    let x = &disc.points.x;
    let mut columns: Vec<f64> = x.iter().map(|p| p[0]).filter(|&c| c > x_tip).collect();
    columns.sort_by(f64::total_cmp);
    columns.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
    columns
        .iter()
        .filter_map(|&c| {
            let column: Vec<usize> = (0..x.len())
                .filter(|&i| (x[i][0] - c).abs() < 1e-9)
                .collect();
            let top = column.iter().map(|&i| damage[i]).fold(0.0, f64::max);
            (top > 0.0).then(|| {
                let cracked: Vec<usize> = column
                    .into_iter()
                    .filter(|&i| damage[i] >= 0.5 * top)
                    .collect();
                (cracked.iter().map(|&i| x[i][1]).sum::<f64>() / cracked.len() as f64).abs()
            })
        })
        .fold(0.0, f64::max)
}

/// A coarse SENT plate (bond-based, event strategy) run to complete
/// separation, with a snapshot at every step: bonds never heal, damage never
/// decreases (checked by [`Watch`]); the reaction rises to a peak and falls to
/// zero (below 1e-6 of the peak) once the crack has crossed the ligament; the
/// crack runs straight (mode I): in every column of points ahead of the notch,
/// the most damaged points are centred within one spacing of the notch line.
#[test]
fn a_mode_one_crack_runs_straight_and_separates_the_plate() {
    let mut case = Sent::new("bond_based", 20, 3.015);
    case.output_every = Some(1);
    let (solution, watch) = run(&case.scene());
    assert!(
        matches!(solution.outcome, Outcome::Separated { .. }),
        "{:?}",
        solution.outcome
    );
    assert!(watch.snapshots > 10);
    let top = solution.set_names.iter().position(|n| n == "top").unwrap();
    let (peak, _) = peak(&solution.records, top, 1);
    let last = solution.records.last().unwrap().reactions[top][1].abs();
    assert!(peak > 0.0 && last < 1e-6 * peak, "peak {peak}, last {last}");
    let deviation = crack_deviation(&solution.disc, &solution.damage, 0.05);
    assert!(
        deviation <= case.spacing(),
        "the crack leaves the notch line by {deviation} m"
    );
    // Every record is finite and the broken count never decreases.
    for w in solution.records.windows(2) {
        assert!(w[1].broken_total >= w[0].broken_total);
    }
}

/// `stop_after_peak` ends a load step whose crack runs as soon as every
/// reaction is below the fraction of its peak (breaking more bonds at the same
/// grip displacement only lowers them): with four large steps the crack runs
/// within one step; stopped at 0.9 the run ends in that step, its last row
/// `unsettled` below 0.9 of the peak of the rows before it, with fewer bonds
/// broken than the same step carried to its end, and every row before it is
/// the unstopped run's.
#[test]
fn stop_after_peak_ends_a_running_step() {
    let mut case = Sent::new("bond_based", 20, 3.015);
    case.strategy = "all";
    case.stepping = "steps = 4".into();
    let (full, _) = run(&case.scene());
    case.stop_after_peak = Some(0.9);
    let (stopped, _) = run(&case.scene());
    let top = full.set_names.iter().position(|n| n == "top").unwrap();
    // The peak of the states recorded before the stop (the peak the run reports).
    let reaction = |r: &StepRecord| r.reactions[top][1].abs();
    let before = &stopped.records[..stopped.records.len() - 1];
    let peak = before.iter().map(reaction).fold(0.0, f64::max);
    let last = stopped.records.last().unwrap();
    assert_eq!(last.state, StateKind::Unsettled, "{:?}", stopped.outcome);
    assert!(matches!(stopped.outcome, Outcome::PastPeak { step } if step == last.step));
    assert!(
        reaction(last) < 0.9 * peak,
        "{} against the peak {peak}",
        reaction(last)
    );
    let same_step = &full.records[stopped.records.len() - 1];
    assert_eq!(same_step.step, last.step);
    assert!(
        last.broken_total < same_step.broken_total,
        "{} bonds broken when stopped, {} at the end of the step",
        last.broken_total,
        same_step.broken_total
    );
    for (a, b) in full
        .records
        .iter()
        .zip(&stopped.records)
        .take(stopped.records.len() - 1)
    {
        assert_eq!(
            (a.step, a.state, a.broken_total),
            (b.step, b.state, b.broken_total)
        );
    }
}

/// After bonds break, the re-solve that iterates with the previous factor as
/// preconditioner (CG for the bond-based model, GMRES for the shear model)
/// gives the same answer as a fresh factorisation, to 1e-10, and takes few
/// iterations for a rank-k change.
#[test]
fn a_resolve_with_the_old_factor_equals_a_fresh_solve() {
    for model_kind in ["bond_based", "shear", "shear_paper"] {
        let case = Sent::new(
            if model_kind == "bond_based" {
                "bond_based"
            } else {
                "shear"
            },
            20,
            3.015,
        );
        // The paper's shear force (GMRES with the bond-based surrogate) and the
        // energy formulation (Cholesky; its re-solve iterates with the old factor).
        let text = if model_kind == "shear_paper" {
            case.toml().replace(
                "kind = \"shear\"",
                "kind = \"shear\"\nformulation = \"paper\"",
            )
        } else {
            case.toml()
        };
        assert!(model_kind != "shear_paper" || text.contains("formulation = \"paper\""));
        let scene = Scene::try_from_spec(
            dhpd::scene::parse_spec(&text, false).unwrap(),
            std::path::Path::new("."),
            "sent",
        )
        .unwrap();
        let prepared = static_solve::prepare(&scene).unwrap();
        let (mut disc, dofs, f_ext) = (prepared.disc, prepared.dofs, prepared.f_ext);
        let surrogate = BondBased::new(
            &disc,
            scene.model.dimension,
            &scene.materials,
            scene.model.thickness,
        );
        let mut notes = Notes::default();
        // A pipeline for `disc` as the drivers build one.
        let analyse = |disc: &Discretization, coupling: Coupling, notes: &mut Notes| {
            let hints = system::solver_hints(&scene, coupling);
            let pattern = Pattern::new(disc, &dofs, coupling, None).unwrap();
            let surrogate = route::wants_surrogate(&scene.solver, hints)
                .then(|| Pattern::new(disc, &dofs, Coupling::Star, None).unwrap());
            let layout = system::layout(disc, &dofs);
            Pipeline::analyse(pattern, surrogate, layout, scene.solver, hints, notes).unwrap()
        };
        let surrogate_values = |pipeline: &Pipeline, disc: &Discretization| {
            pipeline
                .surrogate_pattern()
                .map(|p| Stiffness::assemble(&surrogate, disc, &dofs, p))
        };
        // Bonds that cross the ligament right ahead of the notch tip.
        let ahead: Vec<usize> = (0..disc.points.len())
            .flat_map(|i| disc.bonds.owned_by(i).map(move |b| (i, b)))
            .filter(|&(i, b)| {
                let j = disc.bonds.neighbour[b] as usize;
                let (xi, xj) = (disc.points.x[i], disc.points.x[j]);
                xi[1] * xj[1] < 0.0 && xi[0] < 0.06 && xj[0] < 0.06
            })
            .map(|(_, b)| b)
            .collect();
        assert!(ahead.len() > 4);
        let (fresh, reused, iterations) = if model_kind == "bond_based" {
            let model = BondBased::new(
                &disc,
                scene.model.dimension,
                &scene.materials,
                scene.model.thickness,
            );
            let mut pipeline = analyse(&disc, model.coupling(), &mut notes);
            let mut k = Stiffness::assemble(&model, &disc, &dofs, pipeline.pattern());
            let b = right_hand_side(&model, &disc, &dofs, &f_ext, 1.0);
            let m = Matrices {
                k: &k,
                surrogate: None,
                changed: None,
            };
            let layout = system::layout(&disc, &dofs);
            let x0 = pipeline.solve(layout, m, &b, &mut notes).unwrap().x;
            for &bond in &ahead[..4] {
                disc.bonds.intact[bond] = false;
            }
            stiffness::fill(&model, &disc, &dofs, pipeline.pattern(), &mut k.values);
            let b = right_hand_side(&model, &disc, &dofs, &f_ext, 1.0);
            let layout = system::layout(&disc, &dofs);
            let m = Matrices {
                k: &k,
                surrogate: None,
                changed: None,
            };
            let mut other = analyse(&disc, model.coupling(), &mut notes);
            let fresh = other.solve(layout, m, &b, &mut notes).unwrap();
            // The exact low-rank update of the old factor (one term per broken bond).
            let mut updated = analyse(&disc, model.coupling(), &mut notes);
            let mut intact = disc.clone();
            intact.bonds.intact.iter_mut().for_each(|f| *f = true);
            let k0 = Stiffness::assemble(&model, &intact, &dofs, updated.pattern());
            let b0 = right_hand_side(&model, &intact, &dofs, &f_ext, 1.0);
            let m0 = Matrices {
                k: &k0,
                surrogate: None,
                changed: None,
            };
            updated.solve(layout, m0, &b0, &mut notes).unwrap();
            let free = |i: usize, c: usize| dofs.free_index[3 * i + c] as usize;
            let terms = ahead[..4]
                .iter()
                .map(|&bond| {
                    let owner = disc.bonds.offsets.partition_point(|&o| o <= bond) - 1;
                    let j = disc.bonds.neighbour[bond] as usize;
                    let (stiffness, e) = model.bond_stiffness(&disc, owner, bond).unwrap();
                    Term {
                        entries: (0..2)
                            .map(|c| (free(owner, c), e[c]))
                            .chain((0..2).map(|c| (free(j, c), -e[c])))
                            .collect(),
                        stiffness,
                    }
                })
                .collect();
            let update = updated
                .resolve_update(layout, m, &b, &x0, terms, &mut notes)
                .unwrap();
            assert_eq!(update.report.route, Route::Update);
            let norm = |v: &[f64]| v.iter().map(|a| a * a).sum::<f64>().sqrt();
            let diff: Vec<f64> = fresh.x.iter().zip(&update.x).map(|(a, c)| a - c).collect();
            let relative = norm(&diff) / norm(&fresh.x);
            assert!(
                relative < 1e-10,
                "the low-rank update differs by {relative:e}"
            );
            println!("bond_based: low-rank update after 4 broken bonds: difference {relative:.1e}");
            let reused = pipeline.resolve(layout, m, &b, &x0, &mut notes).unwrap();
            assert_eq!(reused.report.route, Route::Reuse);
            (fresh.x, reused.x, reused.report.iterations)
        } else {
            let mut model = Shear::of(&scene, &disc).unwrap();
            let mut pipeline = analyse(&disc, model.coupling(), &mut notes);
            let mut k = Stiffness::assemble(&model, &disc, &dofs, pipeline.pattern());
            let b = right_hand_side(&model, &disc, &dofs, &f_ext, 1.0);
            let s0 = surrogate_values(&pipeline, &disc);
            let m = Matrices {
                k: &k,
                surrogate: s0.as_ref(),
                changed: None,
            };
            let layout = system::layout(&disc, &dofs);
            let x0 = pipeline.solve(layout, m, &b, &mut notes).unwrap().x;
            let mut owners = Vec::new();
            for &bond in &ahead[..4] {
                disc.bonds.intact[bond] = false;
                owners.push(disc.bonds.offsets.partition_point(|&o| o <= bond) - 1);
            }
            assert!(model.refresh_owners(&disc, &owners).is_empty());
            stiffness::fill(&model, &disc, &dofs, pipeline.pattern(), &mut k.values);
            let b = right_hand_side(&model, &disc, &dofs, &f_ext, 1.0);
            let layout = system::layout(&disc, &dofs);
            let s1 = surrogate_values(&pipeline, &disc);
            let m = Matrices {
                k: &k,
                surrogate: s1.as_ref(),
                changed: None,
            };
            let reused = pipeline.resolve(layout, m, &b, &x0, &mut notes).unwrap();
            assert_eq!(reused.report.route, Route::Reuse);
            let mut other = analyse(&disc, model.coupling(), &mut notes);
            let s2 = surrogate_values(&other, &disc);
            let m = Matrices {
                k: &k,
                surrogate: s2.as_ref(),
                changed: None,
            };
            let fresh = other.solve(layout, m, &b, &mut notes).unwrap();
            (fresh.x, reused.x, reused.report.iterations)
        };
        let norm = |v: &[f64]| v.iter().map(|a| a * a).sum::<f64>().sqrt();
        let diff: Vec<f64> = fresh.iter().zip(&reused).map(|(a, b)| a - b).collect();
        let relative = norm(&diff) / norm(&fresh);
        assert!(
            relative < 1e-10,
            "{model_kind}: re-solve differs by {relative:e}"
        );
        println!("{model_kind}: re-solve after 4 broken bonds: {iterations} iterations, difference {relative:.1e}");
    }
}

/// The LEFM critical load of the SENT plate (a/W = 0.5, clamped grips, plane
/// stress ν = 1/3, G₀ = 200 J/m²) from the committed FEM reference
/// (validation/fracture/fem, J-integral and compliance agreeing to 4e-5).
fn lefm_critical_load() -> f64 {
    let text = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("validation/fracture/fem/reference_sent.json"),
    )
    .expect("the FEM reference is committed");
    let json: serde_json::Value = serde_json::from_str(&text).unwrap();
    let case = &json["materials"]["plane_stress_nu_1/3"];
    let k = case["a_over_W"]
        .as_array()
        .unwrap()
        .iter()
        .position(|v| (v.as_f64().unwrap() - 0.5).abs() < 1e-12)
        .unwrap();
    case["P_c"][k].as_f64().unwrap()
}

/// Energy and initiation on the SENT plate (bond-based, W/Δx = 30, m = 3,
/// δ/a = 0.2), run to complete separation with the event strategy:
///
/// - the energy of the bonds that cross the ligament line, each at its critical
///   stretch, is the discrete sum of the integral that defines `s₀`: within 5 %
///   of `G₀ × ligament` (the partial-volume sum; 0.955-0.98 measured over
///   W/Δx = 30-60, validation/fracture);
/// - the work of the grip `∫ P du` (the energy dropped at the events) is at
///   least the energy of the bonds that broke: removing a spring at fixed
///   displacement releases at least its own energy;
/// - the peak load is within 10 % of the LEFM load computed with the energy the
///   model actually dissipates, `P_LEFM sqrt(W / (G₀ A))`: at δ/a = 0.2 the
///   nonlocal zone lowers the peak by 6-7 % (both m = 3 and 4, validation/fracture).
/// With the continuum calibration (the papers' `s₀`, whose crossing integral is
/// what the first check is about).
#[test]
fn grip_work_and_peak_load_against_the_energy_the_bonds_carry() {
    let mut case = Sent::new("bond_based", 30, 3.015);
    case.calibration = "continuum";
    let scene = case.scene();
    let (s, _) = run(&scene);
    assert!(matches!(s.outcome, Outcome::Separated { .. }));
    let top = s.set_names.iter().position(|n| n == "top").unwrap();
    let work: f64 = s
        .records
        .windows(2)
        .filter(|w| w[0].state == StateKind::Critical && w[1].state == StateKind::Broken)
        .map(|w| 0.5 * w[1].displacement * (w[0].reactions[top][1] - w[1].reactions[top][1]))
        .sum();
    let model = BondBased::new(
        &s.disc,
        scene.model.dimension,
        &scene.materials,
        scene.model.thickness,
    );
    let criterion = dhpd::damage::Criterion::new(&scene, &s.disc);
    let (x, v, bonds) = (&s.disc.points.x, &s.disc.points.volume, &s.disc.bonds);
    let (mut crossing, mut broken) = (0.0, 0.0);
    for i in 0..x.len() {
        for b in bonds.owned_by(i) {
            let j = bonds.neighbour[b] as usize;
            let s0 = criterion.critical(i);
            let len = dhpd::vector::norm(&dhpd::vector::sub(&x[j], &x[i]));
            let energy =
                0.5 * model.micromodulus[i] * s0 * s0 * len * v[i] * v[j] * bonds.volume_factor[b];
            if x[i][1] * x[j][1] < 0.0 && {
                let t = x[i][1] / (x[i][1] - x[j][1]);
                x[i][0] + t * (x[j][0] - x[i][0]) > 0.05
            } {
                crossing += energy;
            }
            if !bonds.intact[b] {
                broken += energy;
            }
        }
    }
    let g0_area = 200.0 * 0.05;
    assert!(
        (crossing / g0_area - 1.0).abs() < 0.05,
        "crossing bonds carry {:.4} G0 A",
        crossing / g0_area
    );
    assert!(
        work >= broken * (1.0 - 1e-9),
        "work {work} below the broken bonds' {broken}"
    );
    let (peak, _) = peak(&s.records, top, 1);
    let lefm = lefm_critical_load() * (work / g0_area).sqrt();
    assert!(
        (peak / lefm - 1.0).abs() < 0.10,
        "peak {peak:.4e} against {lefm:.4e} (work {:.3} G0 A)",
        work / g0_area
    );
    println!(
        "crossing {:.4} G0 A, broken {:.4}, work {:.4}; peak {peak:.4e} = {:+.1} % of LEFM with that energy",
        crossing / g0_area,
        broken / g0_area,
        work / g0_area,
        100.0 * (peak / lefm - 1.0)
    );
}

/// `dhpd run` on a fracture scene writes the load-displacement table, the
/// damage in the point files, a VTU series with its `.pvd`, and a summary with
/// the outcome, every record and every solve.
#[test]
fn a_fracture_run_writes_its_series_and_records() {
    let dir = std::env::temp_dir().join(format!("dhpd_fracture_cli_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let mut case = Sent::new("bond_based", 20, 3.015);
    case.output_every = Some(100);
    std::fs::write(dir.join("scene.toml"), case.toml()).unwrap();
    let out = dir.join("out");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_dhpd"))
        .args(["run", "scene.toml", "--out", "out"])
        .current_dir(&dir)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("complete separation"), "{stdout}");
    let read = |name: &str| std::fs::read_to_string(out.join(name)).unwrap();
    let table = read("load_displacement.csv");
    let header = table.lines().next().unwrap();
    for column in [
        "step",
        "state",
        "load_factor",
        "displacement",
        "reaction_top_y",
        "reaction_bottom_x",
        "broken_in_step",
        "broken_total",
        "resolves",
        "route",
        "iterations",
        "residual",
        "wall_time",
    ] {
        assert!(
            header.split(',').any(|c| c == column),
            "{column} missing: {header}"
        );
    }
    assert!(table.lines().count() > 100);
    // Bond-based re-solves update the old factor.
    assert!(
        table.contains(",update,"),
        "no low-rank update in the routes"
    );
    assert!(read("points.csv")
        .lines()
        .next()
        .unwrap()
        .ends_with(",damage"));
    assert!(read("points.vtu").contains("Name=\"damage\""));
    let pvd = read("series.pvd");
    let files: Vec<&str> = pvd
        .split("file=\"")
        .skip(1)
        .map(|s| s.split('"').next().unwrap())
        .collect();
    assert!(files.len() >= 2, "{pvd}");
    for f in files {
        assert!(read(f).trim_end().ends_with("</VTKFile>"), "{f}");
    }
    let summary: serde_json::Value = serde_json::from_str(&read("summary.json")).unwrap();
    assert_eq!(summary["outcome"]["kind"], "separated");
    assert!(summary["solves"].as_array().unwrap().len() > 10);
    assert!(summary["steps"].as_array().unwrap().len() > 100);
    assert!(summary["peaks"][1]["magnitude"].as_f64().unwrap() > 0.0);
    let _ = std::fs::remove_dir_all(&dir);
}

/// The shear model's rule (001 Eq. 37) breaks a bond only if one of its ends
/// is in tension (θ ≥ 0): a block squeezed between its grips keeps every bond
/// however small the critical deviatoric strain, and the same block pulled
/// breaks.
#[test]
fn the_shear_rule_breaks_nothing_in_compression() {
    let block = |pull: f64| {
        format!(
            "[model]\ndimension = \"plane_stress\"\nkind = \"shear\"\n\
             [materials.rock]\nyoungs_modulus = 1.0e10\npoisson_ratio = 0.25\n\
             critical_deviatoric_strain = 1.0e-7\n\
             [[regions]]\nmaterial = \"rock\"\nspacing = 0.01\nbox = {{ min = [0.0, 0.0], max = [0.1, 0.14] }}\n\
             [[boundary]]\nname = \"bottom\"\nbox = {{ min = [0.0, 0.0], max = [0.1, 0.02] }}\n\
             displacement = {{ x = 0.0, y = 0.0 }}\n\
             [[boundary]]\nname = \"top\"\nbox = {{ min = [0.0, 0.12], max = [0.1, 0.14] }}\n\
             displacement = {{ x = 0.0, y = {pull:e} }}\n\
             [quasi_static]\nmax_load_factor = 1.0\n"
        )
    };
    let (squeezed, _) = run(&scene(&block(-1e-4)));
    assert_eq!(squeezed.records.last().unwrap().broken_total, 0);
    assert_eq!(squeezed.outcome, Outcome::NothingToBreak);
    let (pulled, _) = run(&scene(&block(1e-4)));
    assert!(pulled.records.last().unwrap().broken_total > 0);
}

/// A bar held at one end and pulled by a traction at the other: once it breaks
/// through, the pulled piece carries an applied load and nothing holds it, so
/// the run ends as a failure (cleanly, with the step), not with a singular
/// matrix or a NaN.
#[test]
fn a_loaded_piece_breaking_free_ends_the_run_as_a_failure() {
    let text = "[model]\ndimension = \"1d\"\n[materials.steel]\nyoungs_modulus = 2.0e11\n\
                fracture_energy = 1.0e3\n\
                [[regions]]\nmaterial = \"steel\"\nspacing = 0.01\nbox = { min = [0.0], max = [0.3] }\n\
                [[boundary]]\nname = \"left\"\nbox = { min = [0.0], max = [0.03] }\ndisplacement = { x = 0.0 }\n\
                [[loads]]\nname = \"pull\"\nkind = \"traction\"\nface = \"+x\"\nvalue = [1.0e9]\n\
                [quasi_static]\nmax_load_factor = 10.0\n";
    let (solution, _) = run(&scene(text));
    match &solution.outcome {
        Outcome::Failed { step, reason } => {
            assert!(*step >= 1);
            assert!(reason.contains("applied load"), "{reason}");
        }
        other => panic!("expected a failure, got {other:?}"),
    }
    assert!(solution.u.iter().flatten().all(|v| v.is_finite()));
}

// The iterative fracture route (issue 19): a notched plate grown with the
// event strategy (or `all`) breaks the same bonds at the same events, and reaches the
// same peak, whether its re-solves factorise `K` (Cholesky for the bond-based
// model, GMRES with a factorised surrogate for the shear model) or only iterate
// with the two-level preconditioner (`solver.method = "iterative"`), because
// the event strategy decides which bonds are critical beyond the error of a
// Krylov re-solve (module docs of `drivers::quasi_static::ranking`).

/// The intact flags after every event.
#[derive(Default)]
struct Events {
    intact: Vec<(usize, Vec<bool>)>,
}

impl Observer for Events {
    fn record(&mut self, _: &StepRecord) -> Result<(), Error> {
        Ok(())
    }

    fn snapshot(&mut self, s: &Snapshot) -> Result<(), Error> {
        self.intact.push((s.step, s.disc.bonds.intact.clone()));
        Ok(())
    }
}

fn run_with_method(case: &Sent, method: &str) -> (quasi_static::QuasiStaticSolution, Events) {
    let text = format!("{}\n[solver]\nmethod = \"{method}\"\n", case.toml());
    let scene = scene(&text);
    let prepared = static_solve::prepare(&scene).expect("the scene prepares");
    let mut events = Events::default();
    let solution = quasi_static::run(&scene, prepared, &mut events).expect("the run succeeds");
    (solution, events)
}

/// Relative difference of two load factors.
fn relative_difference(a: f64, b: f64) -> f64 {
    (a - b).abs() / a.abs().max(b.abs()).max(f64::MIN_POSITIVE)
}

/// Runs the plate both ways to half its peak and compares event by event:
/// the same bonds broken after every event (compared flag by flag), the same
/// critical load factors and the same peak reaction to 1e-8 (the re-solves'
/// residual is 1e-12 and the ratios inherit at most a few orders of magnitude
/// of conditioning; a different bond breaking moves the load by the per-bond
/// stiffness change, 1e-4 or more).
fn same_events(model: &'static str, cells: usize, direct: &str, strategy: &'static str) {
    let mut case = Sent::new(model, cells, 3.015);
    case.output_every = Some(1);
    case.stop_after_peak = Some(0.5);
    case.strategy = strategy;
    if strategy == "all" {
        case.stepping = "steps = 20".into();
    }
    let (a, ea) = run_with_method(&case, direct);
    let (b, eb) = run_with_method(&case, "iterative");
    assert!(
        b.solves.iter().skip(1).all(|s| s.report.iterations > 0),
        "the iterative route iterates at every re-solve"
    );
    assert_eq!(
        a.records.len(),
        b.records.len(),
        "{model}: number of records"
    );
    for (ra, rb) in a.records.iter().zip(&b.records) {
        assert_eq!(ra.step, rb.step);
        assert_eq!(ra.state, rb.state, "{model}: step {}", ra.step);
        assert_eq!(
            ra.broken_total, rb.broken_total,
            "{model}: bonds broken by step {}",
            ra.step
        );
        assert!(
            relative_difference(ra.load_factor, rb.load_factor) < 1e-8,
            "{model}: step {}: load factor {} (direct) against {} (iterative)",
            ra.step,
            ra.load_factor,
            rb.load_factor
        );
    }
    // Every recorded reaction, to 1e-8 of the peak (the intermediate re-solves
    // of `all` stop at 1e-8, the states they end in are completed to 1e-12).
    let top = a.set_names.iter().position(|n| n == "top").unwrap();
    let scale = a.peak(top).unwrap().reactions[top][1].abs();
    for (ra, rb) in a.records.iter().zip(&b.records) {
        let (fa, fb) = (ra.reactions[top][1], rb.reactions[top][1]);
        assert!(
            (fa - fb).abs() <= 1e-8 * scale,
            "{model}: step {}: reaction {fa} (direct) against {fb} (iterative)",
            ra.step
        );
    }
    assert_eq!(ea.intact.len(), eb.intact.len());
    for ((step, ia), (_, ib)) in ea.intact.iter().zip(&eb.intact) {
        let differ = ia.iter().zip(ib).filter(|(x, y)| x != y).count();
        assert_eq!(
            differ, 0,
            "{model}: {differ} bonds differ after step {step}"
        );
    }
    let (pa, pb) = (a.peak(top).unwrap(), b.peak(top).unwrap());
    assert_eq!(pa.step, pb.step);
    assert!(
        relative_difference(pa.reactions[top][1], pb.reactions[top][1]) < 1e-8,
        "{model}: peak {} (direct) against {} (iterative)",
        pa.reactions[top][1],
        pb.reactions[top][1]
    );
    assert!(
        a.records.last().unwrap().broken_total > 20,
        "{model}: the crack grew"
    );
}

#[test]
fn the_iterative_route_breaks_the_same_bonds_bond_based() {
    same_events("bond_based", 30, "cholesky", "event");
}

#[test]
fn the_iterative_route_breaks_the_same_bonds_shear() {
    same_events("shear", 20, "gmres", "event");
}

/// The `all` strategy in 20 steps, whose intermediate Krylov re-solves stop at
/// 1e-8 and check their decisions against the error instead (module docs of
/// `drivers::quasi_static::ranking`): the same bonds at every step as the
/// exact factor updates, through the step in which the crack runs and
/// `stop_after_peak` ends it.
#[test]
fn the_iterative_route_breaks_the_same_bonds_with_all() {
    same_events("bond_based", 30, "cholesky", "all");
}
