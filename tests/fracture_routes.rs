//! The iterative fracture route (issue 19): a notched plate grown with the
//! event strategy breaks the same bonds at the same events, and reaches the
//! same peak, whether its re-solves factorise `K` (Cholesky for the bond-based
//! model, GMRES with a factorised surrogate for the shear model) or only iterate
//! with the two-level preconditioner (`solver.method = "iterative"`), because
//! the event strategy decides which bonds are critical beyond the error of a
//! Krylov re-solve (module docs of `drivers::quasi_static::ranking`).

mod common;

use common::scene;
use dhpd::drivers::quasi_static::{self, QuasiStaticSolution, StepRecord};
use dhpd::drivers::static_solve;
use dhpd::drivers::{Observer, Snapshot};
use dhpd::error::Error;
use dhpd::validation::fracture::Sent;

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

fn run(case: &Sent, method: &str) -> (QuasiStaticSolution, Events) {
    let text = format!("{}\n[solver]\nmethod = \"{method}\"\n", case.toml());
    let scene = scene(&text);
    let prepared = static_solve::prepare(&scene).expect("the scene prepares");
    let mut events = Events::default();
    let solution = quasi_static::run(&scene, prepared, &mut events).expect("the run succeeds");
    (solution, events)
}

/// Relative difference of two load factors.
fn relative(a: f64, b: f64) -> f64 {
    (a - b).abs() / a.abs().max(b.abs()).max(f64::MIN_POSITIVE)
}

/// Runs the plate both ways to half its peak and compares event by event:
/// the same bonds broken after every event (compared flag by flag), the same
/// critical load factors and the same peak reaction to 1e-8 (the re-solves'
/// residual is 1e-12 and the ratios inherit at most a few orders of magnitude
/// of conditioning; a different bond breaking moves the load by the per-bond
/// stiffness change, 1e-4 or more).
fn same_events(model: &'static str, cells: usize, direct: &str) {
    let mut case = Sent::new(model, cells, 3.015);
    case.output_every = Some(1);
    case.stop_after_peak = Some(0.5);
    let (a, ea) = run(&case, direct);
    let (b, eb) = run(&case, "iterative");
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
            relative(ra.load_factor, rb.load_factor) < 1e-8,
            "{model}: step {}: load factor {} (direct) against {} (iterative)",
            ra.step,
            ra.load_factor,
            rb.load_factor
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
    let top = a.set_names.iter().position(|n| n == "top").unwrap();
    let (pa, pb) = (a.peak(top).unwrap(), b.peak(top).unwrap());
    assert_eq!(pa.step, pb.step);
    assert!(
        relative(pa.reactions[top][1], pb.reactions[top][1]) < 1e-8,
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
    same_events("bond_based", 30, "cholesky");
}

#[test]
fn the_iterative_route_breaks_the_same_bonds_shear() {
    same_events("shear", 20, "gmres");
}
