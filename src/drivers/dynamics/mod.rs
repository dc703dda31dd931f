//! Explicit dynamics on the bond kernels of the implicit path (formulation Sec. 8).
//!
//! **Velocity Verlet** with mass `m_i = ρ_i V_i` and mass-proportional damping
//! `−α m v` (001 Eq. 42), the damped form being
//!
//! ```text
//! v½ = v_n + Δt/2 (a_n − α v_n),   u_{n+1} = u_n + Δt v½,
//! a_{n+1} = (F_int(u_{n+1}) + f_ext(t_{n+1})) / m,   v_{n+1} = (v½ + Δt/2 a_{n+1}) / (1 + α Δt/2)
//! ```
//!
//! on free components. **Damping bound**: for one mode `ü + α u̇ + ω² u = 0`,
//! with `w = ωΔt`, `a = αΔt/2` and the state `(u, Δt v)`, one step is the matrix
//!
//! ```text
//! A = [ 1 − w²/2                     1 − a                  ]
//!     [ −w²(1 − w²/4)/(1 + a)        (1 − a)(1 − w²/2)/(1 + a) ]
//! tr A = 2 (1 − w²/2)/(1 + a),   det A = (1 − a)/(1 + a)
//! ```
//!
//! Its eigenvalues stay in the unit disc (`|det A| ≤ 1`, `|tr A| ≤ 1 + det A`)
//! iff `w ≤ 2`, whatever `α ≥ 0`: damping never makes the step unstable in that
//! sense. But for the slow modes (`w → 0`) the eigenvalues are `1` and
//! `(1 − αΔt/2)/(1 + αΔt/2)`, the factor applied to the velocity each step where
//! the equation decays it by `e^{−αΔt}`. For `αΔt > 2` it is negative: velocities
//! flip sign every step instead of decaying, and as `αΔt → ∞` it tends to −1, an
//! undamped numerical oscillation (`α = 1e12`, `αΔt = 9e6`: energies oscillate,
//! a balance error of 4.5e8). So `α Δt ≤ 2` is required (at `αΔt = 2` one step
//! stops the damped motion, the discrete critical damping); a larger `damping`
//! is refused with `2/Δt`. A run whose energy balance error exceeds
//! `dynamics.balance_tolerance` (default 0.2) fails at the record that finds it,
//! from step 10 on.
//!
//! **Divergence** is checked every step, for the cost of one sum: the second
//! half kick adds up `m |v|²` as it updates the velocities (relaxation: its
//! residual reduces every force), and a non-finite sum stops the run at that
//! step, naming the point and the cause (the forced time step when it is above
//! the stable one, else the magnitudes of the input). The initial state
//! (initial conditions, prescribed values at t = 0) is checked before the
//! first step: a kinetic energy, displacement or internal force beyond double
//! precision is an input error naming its `initial_conditions` entry.
//!
//! Prescribed components follow `value · g(t)`
//! (displacement) or `value · ∫g` (velocity). **Stable step**: bond-based,
//! `Δt_i = sqrt(2 m_i / Σ w_b/|ξ_b|)` over every bond touching `i`, owned or
//! not (formulation Sec. 8; the same as Gershgorin's bound on the assembled
//! tangent in 1D); shear model, `Δt_i = 2 sqrt(m_i / Σ_c |K_rc|)` (Gershgorin's
//! bound on the largest eigenvalue of `M⁻¹K`). `Δt = safety × min_i Δt_i`.
//!
//! **Energy** (every `record_every` steps): kinetic `½ Σ m v²`; strain energy
//! (bond-based `Σ_pairs ½ (w_ij + w_ji) |ξ| s²`, linearised `½ uᵀKu`; the
//! shear model has none in closed form, so its "strain" column is the work of
//! the internal forces, `−∫ F_int · du`, which includes what broken bonds
//! held); energy of the bonds when they broke; damping `∫ α m v² dt`; external
//! work `∫ (f_ext + R) · du` with `R` the support reactions (trapezoidal). The
//! balance error is `E_kin + E_strain + E_broken + E_damping − W_ext − E_0`,
//! relative to the largest energy seen. It is O(Δt²) while no bond breaks; a
//! bond breaks after the force evaluation that found it over its limit (its
//! force acts for that step, as in Peridigm and EMU), a force discontinuity that
//! adds an error shrinking only slowly with Δt (tests/dynamics.rs measures both).
//!
//! **Adaptive dynamic relaxation** (Kilic & Madenci 2010): fictitious diagonal
//! mass `λ_r = ¼ Σ_c |K_rc|` (Δt = 1), damping `c_n = 2 sqrt(uᵀ ¹K u / uᵀu)` with
//! the local diagonal stiffness `¹K_rr = −(F_r^n − F_r^{n−1}) / (λ_r v_r^{n−½})`,
//! and `v^{n+½} = ((2 − c_n) v^{n−½} + 2 F^n/λ) / (2 + c_n)`, until the
//! out-of-balance force on the free components is `tolerance` times the larger
//! of the applied force and the reaction.

pub mod kernels;

mod history;
mod relaxation;
mod setup;
mod verlet;

pub use history::Record;

use super::setup::Setup;
use super::{forward, Observer};
use crate::assembly::loads::AppliedLoad;
use crate::discretization::Discretization;
use crate::drivers::setup::Plan;
use crate::error::Error;
use crate::notes::Notes;
use crate::scene::{DynamicsMethod, Scene};
use rayon::prelude::*;
use relaxation::Relaxation;
use setup::Explicit;
use std::time::Instant;
use verlet::Verlet;

/// How a run ended.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "snake_case", tag = "kind")]
pub enum Outcome {
    /// Verlet ran all its steps.
    Completed,
    /// Relaxation reached its tolerance.
    Converged { residual: f64 },
    /// Relaxation used all its steps without reaching its tolerance.
    NotConverged { residual: f64 },
}

/// Where the time went.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize)]
pub struct DynamicsTimings {
    /// Points, bonds, kernels, stable time step (s).
    pub setup: f64,
    /// The steps, without output (s).
    pub integration: f64,
    /// Of which internal force evaluations (Verlet) (s).
    pub forces: f64,
    /// Records and snapshots (s).
    pub output: f64,
}

/// Result of an explicit run.
pub struct DynamicsSolution {
    /// Points and bonds (final intact flags).
    pub disc: Discretization,
    /// Final displacement.
    pub u: Vec<[f64; 3]>,
    /// Final velocity.
    pub v: Vec<[f64; 3]>,
    /// Final damage.
    pub damage: Vec<f64>,
    /// Final recovered stress per point, when the scene asks for it.
    pub stress: Option<Vec<crate::model::Block>>,
    /// The bonds each process held, on several processes.
    pub bonds_held: Option<Vec<usize>>,
    /// Intact bonds touching each point, when `disc` does not hold every bond
    /// (on several processes: gathered); `None`: counted from `disc`.
    pub bond_counts: Option<Vec<u32>>,
    /// Steps taken.
    pub steps: usize,
    /// Time step (s; relaxation: 1).
    pub time_step: f64,
    /// Stable time step (s; relaxation: none).
    pub stable_time_step: Option<f64>,
    /// Final time.
    pub time: f64,
    /// History rows.
    pub records: Vec<Record>,
    /// Names of the constrained sets (reaction columns).
    pub set_names: Vec<String>,
    /// Loads applied.
    pub loads: Vec<AppliedLoad>,
    /// How it ended.
    pub outcome: Outcome,
    /// Timings.
    pub timings: DynamicsTimings,
    /// Directed bonds at the start (one update of each per step).
    pub bonds: usize,
    /// Directed bond updates per second of integration.
    pub bond_updates_per_second: f64,
    /// Largest |balance error| over the records.
    pub max_balance_error: f64,
    /// Which force field ran (and its vector path).
    pub kernel: String,
    /// Log lines.
    pub log: Vec<String>,
    /// The points the outputs read.
    pub plan: Plan,
}

/// Runs the scene's explicit dynamics or dynamic relaxation from its `setup`
/// (the histories of the points of `setup.plan.probes` are recorded);
/// `observer` sees the progress, the snapshots the scene asks for and the notes.
pub fn run(
    scene: &Scene,
    setup: Setup,
    observer: &mut dyn Observer,
) -> Result<DynamicsSolution, Error> {
    let mut notes = Notes::default();
    let result = run_with(scene, setup, observer, &mut notes);
    forward(&mut notes, observer);
    result
}

fn run_with(
    scene: &Scene,
    setup: Setup,
    observer: &mut dyn Observer,
    notes: &mut Notes,
) -> Result<DynamicsSolution, Error> {
    let dy = scene.dynamics.as_ref().expect("a dynamics scene");
    let start = Instant::now();
    let Setup {
        disc,
        dofs,
        load_forces,
        loads,
        plan,
        timings,
        processes,
        ..
    } = setup;
    let probes = plan.probes.iter().map(|p| p.1).collect();
    let explicit = Explicit::new(scene, &disc, &dofs, load_forces, probes);
    let set_names: Vec<String> = dofs.sets.iter().map(|s| s.name.clone()).collect();
    let bonds = crate::drivers::shares::total_bonds(&disc);
    let bonds_held = crate::drivers::shares::bonds_held(&disc);
    // The setup (points, bonds, kernels, stable time step) ends here.
    let setup_seconds = |start: Instant| {
        timings.discretization + timings.neighbour_search + start.elapsed().as_secs_f64()
    };
    let mut solution = match dy.method {
        DynamicsMethod::Verlet => {
            let run = Verlet::new(scene, explicit, disc, processes.as_deref(), notes)?;
            forward(notes, observer);
            let setup = setup_seconds(start);
            let mut solution = run.integrate(observer, notes)?;
            solution.timings.setup = setup;
            solution
        }
        DynamicsMethod::Relaxation => {
            let run = Relaxation::new(scene, explicit, disc, notes)?;
            forward(notes, observer);
            let setup = setup_seconds(start);
            let mut solution = run.relax(observer)?;
            solution.timings.setup = setup;
            solution
        }
    };
    solution.set_names = set_names;
    solution.loads = loads;
    solution.bonds = bonds;
    solution.bonds_held = bonds_held;
    solution.bond_updates_per_second =
        bonds as f64 * solution.steps as f64 / solution.timings.integration.max(1e-12);
    solution.plan = plan;
    Ok(solution)
}

/// The point with the first non-finite displacement or velocity, if any.
fn first_non_finite(u: &[[f64; 3]], v: &[[f64; 3]]) -> Option<usize> {
    u.par_iter()
        .zip(v.par_iter())
        .position_first(|(a, b)| a.iter().chain(b).any(|x| !x.is_finite()))
}

/// The point to name when a state diverged: the first with a non-finite
/// displacement or velocity, else the one with the largest `m |v|²` (a kinetic
/// energy that overflowed while every velocity is finite).
fn diverged_point(u: &[[f64; 3]], v: &[[f64; 3]], mass: &[f64]) -> usize {
    first_non_finite(u, v).unwrap_or_else(|| {
        (0..v.len())
            .max_by(|&a, &b| {
                let e = |i: usize| mass[i] * crate::vector::magnitude(&v[i]).powi(2);
                e(a).total_cmp(&e(b))
            })
            .unwrap_or(0)
    })
}
