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
//! from step 10 on ([`BALANCE_FROM_STEP`]).
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

use crate::assembly::dofs::{DofMap, PRESCRIBED};
use crate::assembly::loads::{external_forces, AppliedLoad};
use crate::damage::Criterion;
use crate::discretization::{self, Discretization};
use crate::error::{Error, InputError, NumericalError};
use crate::model::bond_based::BondBased;
use crate::model::shear::Shear;
use crate::scene::{
    DynamicsMethod, ForceKernel, HorizonMode, ModelKind, Motion, RunLength, Scene, TimeFunction,
};
use kernels::{Breaks, FamilyKernel, ForceField, PairKernel, TangentKernel};
use rayon::prelude::*;
use std::time::Instant;

/// Largest `α Δt` of the damped Verlet step (module docs).
const MAX_DAMPING_STEP: f64 = 2.0;

/// First step whose energy balance is checked against `dynamics.balance_tolerance`:
/// a load applied suddenly at t = 0 gives the first steps a start-up error of
/// the trapezoidal work relative to the then tiny energies (0.07 at step 1 on
/// the base plate, 0.23 with α Δt = 1.9; 0.006 and 0.024 from step 10 on).
const BALANCE_FROM_STEP: usize = 10;

/// What the driver reports while it runs.
pub trait Observer {
    /// Called after every step (cheap; for progress).
    fn progress(&mut self, step: usize, steps: usize, time: f64, broken: usize);
    /// A state the scene asked to keep (`output.every`, `output.steps`, the last one).
    fn snapshot(&mut self, snapshot: &Snapshot) -> Result<(), Error>;
}

/// A state of the run.
pub struct Snapshot<'a> {
    /// Step number.
    pub step: usize,
    /// Simulated time (relaxation: the step number).
    pub time: f64,
    /// Points and bonds.
    pub disc: &'a Discretization,
    /// Displacements.
    pub u: &'a [[f64; 3]],
    /// Velocities.
    pub v: &'a [[f64; 3]],
    /// Damage.
    pub damage: &'a [f64],
}

/// One row of the history (`history.csv`).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Record {
    /// Step.
    pub step: usize,
    /// Time in s (relaxation: step).
    pub time: f64,
    /// Kinetic energy (J).
    pub kinetic: f64,
    /// Strain energy (J), or the work of the internal forces (module docs).
    pub strain: f64,
    /// Energy of the bonds when they broke (J).
    pub broken_energy: f64,
    /// Energy dissipated by damping (J).
    pub damping: f64,
    /// Work of the loads and supports (J).
    pub external_work: f64,
    /// Balance error relative to the largest energy so far.
    pub balance_error: f64,
    /// Bonds broken so far.
    pub broken_bonds: usize,
    /// Relaxation: relative out-of-balance force; Verlet: 0.
    pub residual: f64,
    /// Reaction of each constrained set (N).
    pub reactions: Vec<[f64; 3]>,
    /// Per probe: displacement, velocity, damage.
    pub probes: Vec<([f64; 3], [f64; 3], f64)>,
}

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
}

/// A prescribed component: point, component, set.
#[derive(Debug, Clone, Copy)]
struct Constrained {
    point: u32,
    component: u8,
    set: u16,
    value: f64,
}

/// The external forces of each load, with its time function.
struct Loads {
    per_load: Vec<(Vec<(usize, [f64; 3])>, TimeFunction)>,
}

impl Loads {
    fn add_into(&self, t: f64, out: &mut [[f64; 3]]) {
        for (forces, g) in &self.per_load {
            let s = g.value(t);
            for &(i, f) in forces {
                for c in 0..3 {
                    out[i][c] += s * f[c];
                }
            }
        }
    }

    /// `Σ f_ext(t) · du` over the loaded points.
    fn power(&self, t: f64, du: &[[f64; 3]]) -> f64 {
        let mut w = 0.0;
        for (forces, g) in &self.per_load {
            let s = g.value(t);
            for &(i, f) in forces {
                w += s * (f[0] * du[i][0] + f[1] * du[i][1] + f[2] * du[i][2]);
            }
        }
        w
    }
}

fn builds_kernel(scene: &Scene, disc: Discretization) -> Result<Box<dyn ForceField>, Error> {
    let dy = scene.dynamics.as_ref().expect("a dynamics scene");
    let criterion = scene
        .materials
        .iter()
        .any(|m| m.fracture.is_some())
        .then(|| {
            let (criterion, report) = Criterion::with_report(scene, &disc);
            report.notes().iter().for_each(|n| eprintln!("note: {n}"));
            criterion
        });
    Ok(match (scene.model, dy.kernel) {
        (ModelKind::BondBased, ForceKernel::Nonlinear) => {
            let model = BondBased::new(&disc, scene.dimension, &scene.materials, scene.thickness);
            let traditional = scene.horizons == HorizonMode::Traditional;
            Box::new(PairKernel::new(disc, &model, criterion, traditional))
        }
        (ModelKind::BondBased, ForceKernel::Linearised) => {
            let model = BondBased::new(&disc, scene.dimension, &scene.materials, scene.thickness);
            Box::new(TangentKernel::new(
                disc,
                &model,
                scene.solver.memory_limit_bytes,
            )?)
        }
        (ModelKind::Shear, kernel) => {
            let model = Shear::new(
                &disc,
                scene.dimension,
                &scene.materials,
                scene.gradient_dilatation,
            )?;
            if kernel == ForceKernel::Linearised {
                Box::new(TangentKernel::new(
                    disc,
                    &model,
                    scene.solver.memory_limit_bytes,
                )?)
            } else {
                Box::new(FamilyKernel::new(disc, model, false, criterion))
            }
        }
    })
}

fn kernel_description(scene: &Scene, field: &dyn ForceField) -> String {
    match field.simd() {
        Some(simd) => format!("{}, {simd:?} vector path", kernel_name(scene)),
        None => kernel_name(scene).to_string(),
    }
}

fn kernel_name(scene: &Scene) -> &'static str {
    let dy = scene.dynamics.as_ref().expect("a dynamics scene");
    match (scene.model, dy.kernel, scene.horizons) {
        (_, ForceKernel::Linearised, _) => "assembled tangent (linearised)",
        (ModelKind::BondBased, _, HorizonMode::Traditional) => {
            "bond-based pairs, traditional horizons"
        }
        (ModelKind::BondBased, _, _) => "bond-based pairs (nonlinear)",
        (ModelKind::Shear, _, _) => "shear families (nonlinear, polar rotation)",
    }
}

/// Gershgorin row sums `Σ_c |K_rc|` of the scene's assembled tangent, per point and component.
fn tangent_row_sums(scene: &Scene, disc: &Discretization) -> Result<Vec<[f64; 3]>, Error> {
    let copy = disc.clone();
    Ok(match scene.model {
        ModelKind::BondBased => {
            let model = BondBased::new(disc, scene.dimension, &scene.materials, scene.thickness);
            TangentKernel::new(copy, &model, scene.solver.memory_limit_bytes)?.row_sums()
        }
        ModelKind::Shear => {
            let model = Shear::new(
                disc,
                scene.dimension,
                &scene.materials,
                scene.gradient_dilatation,
            )?;
            TangentKernel::new(copy, &model, scene.solver.memory_limit_bytes)?.row_sums()
        }
    })
}

/// The largest stable time step of every point (module docs).
fn stable_time_steps(
    scene: &Scene,
    disc: &Discretization,
    mass: &[f64],
) -> Result<Vec<f64>, Error> {
    let n = disc.points.len();
    if scene.model == ModelKind::BondBased {
        let model = BondBased::new(disc, scene.dimension, &scene.materials, scene.thickness);
        let traditional = scene.horizons == HorizonMode::Traditional;
        let (p, bonds) = (&disc.points, &disc.bonds);
        let mut k = vec![0.0; n];
        for i in 0..n {
            for b in bonds.owned_by(i) {
                let j = bonds.neighbour[b] as usize;
                let len = crate::vector::norm(&crate::vector::sub(&p.x[j], &p.x[i]));
                let w = model.bond_weight(disc, i, b) / len;
                if traditional {
                    k[i] += 2.0 * w;
                } else {
                    k[i] += w;
                    k[j] += w;
                }
            }
        }
        Ok((0..n)
            .map(|i| (2.0 * mass[i] / k[i]).sqrt())
            .collect::<Vec<_>>())
    } else {
        let rows = tangent_row_sums(scene, disc)?;
        Ok((0..n)
            .map(|i| {
                (0..disc.d)
                    .map(|c| 2.0 * (mass[i] / rows[i][c]).sqrt())
                    .fold(f64::INFINITY, f64::min)
            })
            .collect())
    }
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

/// Runs the scene's explicit dynamics or dynamic relaxation; `probes` are the
/// points whose histories are recorded.
pub fn run(
    scene: &Scene,
    probes: &[usize],
    observer: &mut dyn Observer,
) -> Result<DynamicsSolution, Error> {
    let dy = scene.dynamics.as_ref().expect("a dynamics scene");
    let setup = Instant::now();
    let disc = discretization::build(scene)?;
    let n = disc.points.len();
    let d = disc.d;
    let dofs = DofMap::new(&disc, &scene.boundaries)?;
    dofs.overlap_notes().iter().for_each(|n| eprintln!("{n}"));
    let mut per_load = Vec::new();
    let mut loads = Vec::new();
    for (k, load) in scene.loads.iter().enumerate() {
        let (f, applied) = external_forces(&disc, std::slice::from_ref(load)).map_err(|e| {
            // The single-load call numbers it 0; name the scene's entry.
            InputError::new(
                e.field.replacen("loads[0]", &format!("loads[{k}]"), 1),
                e.message,
            )
        })?;
        let forces: Vec<(usize, [f64; 3])> = f
            .into_iter()
            .enumerate()
            .filter(|(_, v)| v.iter().any(|&c| c != 0.0))
            .collect();
        per_load.push((forces, dy.load_time[k].clone()));
        loads.extend(applied);
    }
    let loads_field = Loads { per_load };
    // Each prescribed component once, in the set that owns it (`ConstrainedSet`).
    let mut constrained = Vec::new();
    for (k, set) in dofs.sets.iter().enumerate() {
        for &(point, component) in &set.owned {
            if let Some(value) = scene.boundaries[k].values[component as usize] {
                constrained.push(Constrained {
                    point,
                    component,
                    set: k as u16,
                    value,
                });
            }
        }
    }
    let set_names: Vec<String> = dofs.sets.iter().map(|s| s.name.clone()).collect();
    let free: Vec<[bool; 3]> = (0..n)
        .map(|i| std::array::from_fn(|c| c < d && dofs.free_index[3 * i + c] != PRESCRIBED))
        .collect();
    let bonds = disc.bonds.len();

    match dy.method {
        DynamicsMethod::Verlet => {
            let mass: Vec<f64> = (0..n)
                .map(|i| dy.density[disc.points.material[i] as usize] * disc.points.volume[i])
                .collect();
            let stable = stable_time_steps(scene, &disc, &mass)?;
            let (critical_point, stable_dt) = stable
                .iter()
                .copied()
                .enumerate()
                .min_by(|a, b| a.1.total_cmp(&b.1))
                .unwrap_or((0, f64::INFINITY));
            if !(stable_dt.is_finite() && stable_dt > 0.0) {
                // Bond stiffnesses that under- or overflowed at this scale.
                return Err(crate::discretization::beyond_double_precision(
                    &disc,
                    critical_point,
                    "the stable time step",
                    stable_dt,
                )
                .into());
            }
            let dt = match dy.time_step {
                Some(t) if t > stable_dt && !dy.force_time_step => {
                    return Err(InputError::new(
                        "dynamics.time_step",
                        format!(
                            "{t:e} s is above the stable time step {stable_dt:e} s (point \
                             {critical_point} at {:?}); give at most that, omit time_step for \
                             {} × it, or set force_time_step = true",
                            disc.points.x[critical_point], dy.safety_factor
                        ),
                    )
                    .into())
                }
                Some(t) => t,
                None => dy.safety_factor * stable_dt,
            };
            if dy.damping * dt > MAX_DAMPING_STEP {
                return Err(InputError::new(
                    "dynamics.damping",
                    format!(
                        "α Δt = {:.3e} (α = {:e} 1/s, Δt = {dt:e} s) is above {MAX_DAMPING_STEP}: \
                         the damped Verlet step multiplies velocities by (1 − αΔt/2)/(1 + αΔt/2) \
                         < 0, so they flip sign every step instead of decaying; give a damping \
                         of at most {:.4e} 1/s (2/Δt) or a smaller time step",
                        dy.damping * dt,
                        dy.damping,
                        MAX_DAMPING_STEP / dt
                    ),
                )
                .into());
            }
            let steps = match dy.length {
                RunLength::Steps(s) => s,
                RunLength::Time(t) => {
                    let s = (t / dt - 1e-9).ceil().max(1.0);
                    if s > crate::scene::MAX_DYNAMICS_STEPS as f64 {
                        return Err(InputError::new(
                            "dynamics.end_time",
                            format!(
                                "{t:e} s takes {s:.3e} steps of {dt:e} s; at most {} are allowed",
                                crate::scene::MAX_DYNAMICS_STEPS
                            ),
                        )
                        .into());
                    }
                    s as usize
                }
            };
            let kernel = builds_kernel(scene, disc)?;
            let run = Verlet {
                scene,
                kernel,
                mass,
                free,
                constrained,
                loads: loads_field,
                probes,
                dt,
                stable_dt,
                steps,
                sets: set_names.len(),
            };
            let setup_seconds = setup.elapsed().as_secs_f64();
            let mut solution = run.integrate(observer)?;
            solution.timings.setup = setup_seconds;
            solution.stable_time_step = Some(stable_dt);
            solution.set_names = set_names;
            solution.loads = loads;
            solution.bonds = bonds;
            solution.bond_updates_per_second =
                bonds as f64 * solution.steps as f64 / solution.timings.integration.max(1e-12);
            Ok(solution)
        }
        DynamicsMethod::Relaxation => {
            // Relaxation seeks the static equilibrium: a body free to move
            // rigidly has none (it would run every step), as in a static solve.
            crate::assembly::rigid_modes::check(&disc, &dofs)?;
            let rows = tangent_row_sums(scene, &disc)?;
            let kernel = builds_kernel(scene, disc)?;
            let steps = match dy.length {
                RunLength::Steps(s) => s,
                RunLength::Time(_) => unreachable!("validated: relaxation takes steps"),
            };
            let run = Relaxation {
                kernel,
                lambda: rows.iter().map(|r| r.map(|v| 0.25 * v)).collect(),
                free,
                constrained,
                loads: loads_field,
                probes,
                steps,
                tolerance: dy.tolerance,
                scene,
                sets: set_names.len(),
            };
            let setup_seconds = setup.elapsed().as_secs_f64();
            let mut solution = run.relax(observer)?;
            solution.timings.setup = setup_seconds;
            solution.set_names = set_names;
            solution.loads = loads;
            solution.bonds = bonds;
            solution.bond_updates_per_second =
                bonds as f64 * solution.steps as f64 / solution.timings.integration.max(1e-12);
            Ok(solution)
        }
    }
}

/// Whether the scene's output asks for a snapshot at `step` (`output.every`,
/// which includes the last step, or `output.steps`).
fn wants_snapshot(scene: &Scene, step: usize, last: bool) -> bool {
    scene.output.every.is_some_and(|e| step % e == 0 || last) || scene.output.steps.contains(&step)
}

/// Reaction of every set, `Σ R` over its prescribed components, from the
/// support force `R = m a − (F_int + f_ext)` of each.
fn set_sums(constrained: &[Constrained], sets: usize, support: &[f64]) -> Vec<[f64; 3]> {
    let mut r = vec![[0.0; 3]; sets];
    for (c, s) in constrained.iter().zip(support) {
        r[c.set as usize][c.component as usize] += s;
    }
    r
}

fn probe_values(
    probes: &[usize],
    disc: &Discretization,
    u: &[[f64; 3]],
    v: &[[f64; 3]],
) -> Vec<([f64; 3], [f64; 3], f64)> {
    probes
        .iter()
        .map(|&i| (u[i], v[i], crate::damage::point_damage(disc, i)))
        .collect()
}

struct Verlet<'a> {
    scene: &'a Scene,
    kernel: Box<dyn ForceField>,
    mass: Vec<f64>,
    free: Vec<[bool; 3]>,
    constrained: Vec<Constrained>,
    loads: Loads,
    probes: &'a [usize],
    dt: f64,
    /// The stable time step (`dt` above it only with `force_time_step`).
    stable_dt: f64,
    steps: usize,
    sets: usize,
}

impl Verlet<'_> {
    /// Whether the scene forced a time step above the stable one.
    fn forced(&self) -> bool {
        self.dt > self.stable_dt
    }

    /// What the forced step does, for the failures it causes.
    fn forced_cause(&self) -> String {
        format!(
            "the time step {:.4e} s is above the stable {:.4e} s (dynamics.force_time_step = \
             true), which makes the scheme unstable: give at most the stable step",
            self.dt, self.stable_dt
        )
    }

    /// The error of a state that left double precision at `step`.
    fn diverged(&self, step: usize, time: f64, u: &[[f64; 3]], v: &[[f64; 3]]) -> Error {
        let point = diverged_point(u, v, &self.mass);
        let cause = if self.forced() {
            self.forced_cause()
        } else {
            format!(
                "the time step {:.4e} s is within the stable {:.4e} s, so the state itself left \
                 double precision: a load, prescribed motion or initial condition too large for \
                 this body, or points driven through each other (a bond of zero length has no \
                 direction)",
                self.dt, self.stable_dt
            )
        };
        NumericalError::Diverged {
            step,
            time,
            point,
            position: self.kernel.disc().points.x[point],
            cause,
        }
        .into()
    }

    /// Refuses an initial state (initial conditions, prescribed values at
    /// t = 0) whose displacement, velocity, kinetic energy or internal forces
    /// are beyond double precision, naming the entry that set the point: the
    /// run could not take a step (a velocity of 1e300 m/s was reported as a
    /// time step too large).
    fn check_initial_state(
        &self,
        u: &[[f64; 3]],
        v: &[[f64; 3]],
        f_int: &[[f64; 3]],
    ) -> Result<(), Error> {
        let dy = self.scene.dynamics.as_ref().expect("a dynamics scene");
        let kinetic = |i: usize| 0.5 * self.mass[i] * crate::vector::dot(&v[i], &v[i]);
        let moving = (0..v.len()).find(|&i| !kinetic(i).is_finite());
        let total: f64 = (0..v.len()).map(kinetic).sum();
        let moving =
            moving.or_else(|| (!total.is_finite()).then(|| diverged_point(u, v, &self.mass)));
        // A non-finite displacement, else the largest displacement when a
        // force overflowed (the point whose displacement caused it).
        let strained = (0..u.len())
            .find(|&i| u[i].iter().any(|x| !x.is_finite()))
            .or_else(|| {
                f_int.iter().flatten().any(|x| !x.is_finite()).then(|| {
                    (0..u.len())
                        .max_by(|&a, &b| {
                            crate::vector::magnitude(&u[a])
                                .total_cmp(&crate::vector::magnitude(&u[b]))
                        })
                        .unwrap_or(0)
                })
            });
        let (point, velocity) = match (moving, strained) {
            (Some(i), _) => (i, true),
            (None, Some(i)) => (i, false),
            (None, None) => return Ok(()),
        };
        if !velocity && crate::vector::magnitude(&u[point]) == 0.0 {
            // Forces that are not finite without any displacement: the
            // model's quantities at this scale leave double precision.
            let i = f_int
                .iter()
                .position(|f| f.iter().any(|x| !x.is_finite()))
                .unwrap_or(point);
            return Err(crate::discretization::beyond_double_precision(
                self.kernel.disc(),
                i,
                "the internal force at rest",
                f_int[i]
                    .iter()
                    .copied()
                    .find(|x| !x.is_finite())
                    .unwrap_or(0.0),
            )
            .into());
        }
        let x = self.kernel.disc().points.x[point];
        let what = if velocity {
            format!(
                "a velocity of {} m/s: its kinetic energy ½ m v² (the run's total: {total:.3e} J) \
                 is beyond double precision",
                crate::error::num(crate::vector::magnitude(&v[point]))
            )
        } else {
            format!(
                "a displacement of {} m: it or the internal forces it causes are beyond double \
                 precision",
                crate::error::num(crate::vector::magnitude(&u[point]))
            )
        };
        // The entry that set the point: an initial condition, else a support.
        let key = if velocity { "velocity" } else { "displacement" };
        let field = dy
            .initial
            .iter()
            .enumerate()
            .find_map(|(k, ic)| {
                if ic.bounds.as_ref().is_some_and(|b| !b.contains(&x)) {
                    return None;
                }
                let sets = |c: &[Option<f64>; 3]| c.iter().any(|v| v.is_some_and(|v| v != 0.0));
                match (velocity, &ic.gaussian) {
                    (true, _) if sets(&ic.velocity) => {
                        Some(format!("initial_conditions[{k}].velocity"))
                    }
                    (false, _) if sets(&ic.displacement) => {
                        Some(format!("initial_conditions[{k}].displacement"))
                    }
                    (false, Some(g)) if g.at(&x).iter().any(|&a| a != 0.0) => {
                        Some(format!("initial_conditions[{k}].gaussian"))
                    }
                    _ => None,
                }
            })
            .or_else(|| {
                self.constrained
                    .iter()
                    .find(|c| c.point as usize == point)
                    .map(|c| format!("boundary[{}].{key}", c.set))
            })
            .unwrap_or_else(|| "initial_conditions".to_string());
        Err(InputError::new(
            field,
            format!(
                "gives point {point} (x = {x:?}) {what}, so the run cannot take a step; give a \
                 smaller value (or rescale the units)"
            ),
        )
        .into())
    }
    /// Prescribed displacement and velocity of a constrained component at `t`.
    fn prescribed(&self, c: &Constrained, t: f64) -> (f64, f64) {
        let dy = self.scene.dynamics.as_ref().expect("a dynamics scene");
        let g = &dy.boundary_time[c.set as usize];
        match dy.motion[c.set as usize] {
            Motion::Displacement => {
                let h = self.dt;
                (
                    c.value * g.value(t),
                    c.value * (g.value(t + 0.5 * h) - g.value(t - 0.5 * h)) / h,
                )
            }
            Motion::Velocity => (c.value * g.integral(t), c.value * g.value(t)),
        }
    }

    fn integrate(mut self, observer: &mut dyn Observer) -> Result<DynamicsSolution, Error> {
        let dy = self.scene.dynamics.as_ref().expect("a dynamics scene");
        let n = self.mass.len();
        let (dt, alpha) = (self.dt, dy.damping);
        let mut u = vec![[0.0; 3]; n];
        let mut v = vec![[0.0; 3]; n];
        {
            let points = &self.kernel.disc().points;
            let x = &points.x;
            for (k, g) in dy
                .initial
                .iter()
                .enumerate()
                .filter_map(|(k, ic)| Some((k, ic.gaussian.as_ref()?)))
            {
                // Legitimate, but a pulse narrower than the spacing is not
                // resolved: it moves the point(s) nearest its centre only.
                let spacing = points.spacing.iter().copied().fold(f64::INFINITY, f64::min);
                if g.width < spacing {
                    let peak = g.amplitude.iter().fold(0.0f64, |m, a| m.max(a.abs()));
                    let moved = x
                        .iter()
                        .filter(|xi| g.at(xi).iter().any(|a| a.abs() >= 1e-3 * peak))
                        .count();
                    eprintln!(
                        "warning: initial_conditions[{k}].gaussian.width = {} m is below the \
                         spacing ({} m): the pulse is not resolved and displaces {moved} \
                         point(s) by more than 1e-3 of its amplitude",
                        crate::error::num(g.width),
                        crate::error::num(spacing)
                    );
                }
            }
            for ic in &dy.initial {
                for i in 0..n {
                    if ic.bounds.as_ref().is_some_and(|b| !b.contains(&x[i])) {
                        continue;
                    }
                    for c in 0..3 {
                        u[i][c] += ic.displacement[c].unwrap_or(0.0);
                        v[i][c] += ic.velocity[c].unwrap_or(0.0);
                    }
                    if let Some(g) = &ic.gaussian {
                        let p = g.at(&x[i]);
                        (0..3).for_each(|c| u[i][c] += p[c]);
                    }
                }
            }
        }
        for c in &self.constrained {
            let (uc, vc) = self.prescribed(c, 0.0);
            u[c.point as usize][c.component as usize] = uc;
            v[c.point as usize][c.component as usize] = vc;
        }
        let mut f_int = vec![[0.0; 3]; n];
        let mut force = vec![[0.0; 3]; n];
        let mut a = vec![[0.0; 3]; n];
        let mut du = vec![[0.0; 3]; n];
        let broken = self.kernel.forces(&u, &mut f_int);
        self.check_initial_state(&u, &v, &f_int)?;
        let total = |f_int: &[[f64; 3]], force: &mut [[f64; 3]], t: f64, loads: &Loads| {
            force.copy_from_slice(f_int);
            loads.add_into(t, force);
        };
        total(&f_int, &mut force, 0.0, &self.loads);
        let (mass, free) = (&self.mass, &self.free);
        a.par_iter_mut().enumerate().for_each(|(i, ai)| {
            *ai = std::array::from_fn(|c| {
                if free[i][c] {
                    force[i][c] / mass[i]
                } else {
                    0.0
                }
            })
        });
        let kinetic = |v: &[[f64; 3]]| -> f64 {
            v.par_iter()
                .zip(mass.par_iter())
                .map(|(vi, m)| 0.5 * m * (vi[0] * vi[0] + vi[1] * vi[1] + vi[2] * vi[2]))
                .sum()
        };
        let uses_work = self.kernel.strain_energy(&u).is_none();
        let initial_strain = self.kernel.strain_energy(&u).unwrap_or(0.0);
        let e0 = kinetic(&v) + initial_strain;
        let (mut w_ext, mut w_int, mut damping_work) = (0.0, 0.0, 0.0);
        let mut broken_energy = broken.energy;
        let mut broken_bonds = broken.bonds;
        let mut scale = e0.abs();
        let mut records = Vec::new();
        let mut max_balance: f64 = 0.0;
        let mut support: Vec<f64> = self
            .constrained
            .iter()
            .map(|c| -force[c.point as usize][c.component as usize])
            .collect();
        let mut v_prescribed_old = vec![0.0; self.constrained.len()];
        let mut output_seconds = 0.0;
        let mut force_seconds = 0.0;
        let start = Instant::now();
        let mut t = 0.0;
        let record_every = dy.record_every;

        for step in 0..=self.steps {
            if step > 0 {
                let t1 = step as f64 * dt;
                // Half kick and drift.
                u.par_iter_mut()
                    .zip(v.par_iter_mut())
                    .zip(du.par_iter_mut())
                    .zip(a.par_iter())
                    .enumerate()
                    .for_each(|(i, (((ui, vi), dui), ai))| {
                        for c in 0..3 {
                            if free[i][c] {
                                vi[c] += 0.5 * dt * (ai[c] - alpha * vi[c]);
                                dui[c] = dt * vi[c];
                                ui[c] += dui[c];
                            } else {
                                dui[c] = 0.0;
                            }
                        }
                    });
                for (k, c) in self.constrained.iter().enumerate() {
                    v_prescribed_old[k] = v[c.point as usize][c.component as usize];
                }
                for c in &self.constrained {
                    let (i, k) = (c.point as usize, c.component as usize);
                    let (uc, vc) = self.prescribed(c, t1);
                    du[i][k] = uc - u[i][k];
                    u[i][k] = uc;
                    v[i][k] = vc;
                }
                // Work of the loads over the step (trapezoidal), before the new forces.
                w_ext += 0.5 * (self.loads.power(t, &du) + self.loads.power(t1, &du));
                let power_int_old: f64 = f_int
                    .par_iter()
                    .zip(du.par_iter())
                    .map(|(f, d)| f[0] * d[0] + f[1] * d[1] + f[2] * d[2])
                    .sum();
                let clock = Instant::now();
                let breaks: Breaks = self.kernel.forces(&u, &mut f_int);
                force_seconds += clock.elapsed().as_secs_f64();
                broken_bonds += breaks.bonds;
                broken_energy += breaks.energy;
                total(&f_int, &mut force, t1, &self.loads);
                let power_int_new: f64 = f_int
                    .par_iter()
                    .zip(du.par_iter())
                    .map(|(f, d)| f[0] * d[0] + f[1] * d[1] + f[2] * d[2])
                    .sum();
                w_int -= 0.5 * (power_int_old + power_int_new);
                // Second half kick.
                // The same pass sums `m |v|²` of the new velocities: a
                // non-finite sum is a divergence, found at the step it happens.
                let factor = 1.0 / (1.0 + 0.5 * alpha * dt);
                let (damping_step, twice_kinetic) = a
                    .par_iter_mut()
                    .zip(v.par_iter_mut())
                    .enumerate()
                    .map(|(i, (ai, vi))| {
                        let mut p = 0.0;
                        for c in 0..3 {
                            if free[i][c] {
                                ai[c] = force[i][c] / mass[i];
                                let half = vi[c];
                                vi[c] = (half + 0.5 * dt * ai[c]) * factor;
                                let mid = 0.5 * (half + vi[c]);
                                p += alpha * mass[i] * half * mid;
                            }
                        }
                        (
                            p * dt,
                            mass[i] * (vi[0] * vi[0] + vi[1] * vi[1] + vi[2] * vi[2]),
                        )
                    })
                    .reduce(|| (0.0, 0.0), |x, y| (x.0 + y.0, x.1 + y.1));
                if !(twice_kinetic.is_finite() && damping_step.is_finite()) {
                    return Err(self.diverged(step, t1, &u, &v));
                }
                damping_work += damping_step;
                // Supports: trapezoidal work of the reactions R = m a − F.
                for (k, c) in self.constrained.iter().enumerate() {
                    let (i, comp) = (c.point as usize, c.component as usize);
                    let acc = (v[i][comp] - v_prescribed_old[k]) / dt;
                    let r_new = mass[i] * acc - force[i][comp];
                    w_ext += 0.5 * (support[k] + r_new) * du[i][comp];
                    support[k] = r_new;
                }
                t = t1;
                observer.progress(step, self.steps, t, broken_bonds);
            }
            let last = step == self.steps;
            if step % record_every == 0 || last {
                let clock = Instant::now();
                let e_kin = kinetic(&v);
                let e_strain = if uses_work {
                    w_int
                } else {
                    self.kernel.strain_energy(&u).unwrap_or(0.0)
                };
                let broken_part = if uses_work { 0.0 } else { broken_energy };
                scale = scale
                    .max(e_kin)
                    .max(e_strain.abs())
                    .max((e_kin + e_strain).abs())
                    .max(w_ext.abs());
                let balance = e_kin + e_strain + broken_part + damping_work - w_ext - e0;
                if !(balance.is_finite() && scale.is_finite()) {
                    // Every velocity is finite (checked each step), but an
                    // energy or a work left double precision.
                    return Err(self.diverged(step, t, &u, &v));
                }
                let relative = if scale > 0.0 { balance / scale } else { 0.0 };
                max_balance = max_balance.max(relative.abs());
                if step >= BALANCE_FROM_STEP && relative.abs() > dy.balance_tolerance {
                    return Err(NumericalError::EnergyBalance {
                        step,
                        time: t,
                        error: relative,
                        tolerance: dy.balance_tolerance,
                        cause: if self.forced() {
                            self.forced_cause()
                        } else {
                            "the forces are not the gradient of an energy (the shear model \
                             with heavy breakage, the traditional horizons)"
                                .to_string()
                        },
                    }
                    .into());
                }
                records.push(Record {
                    step,
                    time: t,
                    kinetic: e_kin,
                    strain: e_strain,
                    broken_energy: broken_part,
                    damping: damping_work,
                    external_work: w_ext,
                    balance_error: relative,
                    broken_bonds,
                    residual: 0.0,
                    reactions: set_sums(&self.constrained, self.sets, &support),
                    probes: probe_values(self.probes, self.kernel.disc(), &u, &v),
                });
                output_seconds += clock.elapsed().as_secs_f64();
            }
            if wants_snapshot(self.scene, step, last) {
                let clock = Instant::now();
                let damage = self.kernel.damage();
                observer.snapshot(&Snapshot {
                    step,
                    time: t,
                    disc: self.kernel.disc(),
                    u: &u,
                    v: &v,
                    damage: &damage,
                })?;
                output_seconds += clock.elapsed().as_secs_f64();
            }
        }
        let integration = start.elapsed().as_secs_f64() - output_seconds;
        let damage = self.kernel.damage();
        let description = kernel_description(self.scene, self.kernel.as_ref());
        let kernel = self.kernel;
        Ok(DynamicsSolution {
            disc: kernel.into_disc(),
            u,
            v,
            damage,
            steps: self.steps,
            time_step: dt,
            stable_time_step: None,
            time: t,
            records,
            set_names: Vec::new(),
            loads: Vec::new(),
            outcome: Outcome::Completed,
            timings: DynamicsTimings {
                setup: 0.0,
                integration,
                forces: force_seconds,
                output: output_seconds,
            },
            bonds: 0,
            bond_updates_per_second: 0.0,
            max_balance_error: max_balance,
            kernel: description,
            log: Vec::new(),
        })
    }
}

struct Relaxation<'a> {
    scene: &'a Scene,
    kernel: Box<dyn ForceField>,
    lambda: Vec<[f64; 3]>,
    free: Vec<[bool; 3]>,
    constrained: Vec<Constrained>,
    loads: Loads,
    probes: &'a [usize],
    steps: usize,
    tolerance: f64,
    sets: usize,
}

impl Relaxation<'_> {
    /// Out-of-balance force on the free components, relative to the larger of
    /// the applied force and the reaction.
    fn residual(&self, force: &[[f64; 3]], applied: f64) -> f64 {
        // Scaled norms: forces of 1e160 N keep a finite residual.
        let r = crate::solve::norm2(
            force
                .iter()
                .enumerate()
                .flat_map(|(i, f)| (0..3).filter(move |&c| self.free[i][c]).map(move |c| f[c])),
        );
        let reaction = crate::solve::norm2(
            self.constrained
                .iter()
                .map(|c| force[c.point as usize][c.component as usize]),
        );
        let scale = applied.max(reaction);
        if scale > 0.0 {
            r / scale
        } else {
            r
        }
    }

    fn relax(mut self, observer: &mut dyn Observer) -> Result<DynamicsSolution, Error> {
        let n = self.lambda.len();
        let dy = self.scene.dynamics.as_ref().expect("a dynamics scene");
        let mut u = vec![[0.0; 3]; n];
        for c in &self.constrained {
            u[c.point as usize][c.component as usize] = c.value;
        }
        let mut f_ext = vec![[0.0; 3]; n];
        self.loads.add_into(0.0, &mut f_ext);
        let applied = crate::solve::norm2(
            f_ext
                .iter()
                .zip(&self.free)
                .flat_map(|(f, free)| (0..3).filter(|&c| free[c]).map(|c| f[c])),
        );
        let mut force = vec![[0.0; 3]; n];
        let mut previous = vec![[0.0; 3]; n];
        let mut v = vec![[0.0; 3]; n];
        let evaluate =
            |kernel: &mut Box<dyn ForceField>, u: &[[f64; 3]], force: &mut [[f64; 3]]| {
                kernel.forces(u, force);
                force
                    .par_iter_mut()
                    .zip(f_ext.par_iter())
                    .for_each(|(f, e)| (0..3).for_each(|c| f[c] += e[c]));
            };
        evaluate(&mut self.kernel, &u, &mut force);
        let (lambda, free) = (&self.lambda, &self.free);
        v.par_iter_mut().enumerate().for_each(|(i, vi)| {
            for c in 0..3 {
                if free[i][c] && lambda[i][c] > 0.0 {
                    vi[c] = 0.5 * force[i][c] / lambda[i][c];
                }
            }
        });
        let start = Instant::now();
        let mut output_seconds = 0.0;
        let mut residual = self.residual(&force, applied);
        let mut records = Vec::new();
        let mut step = 0;
        let outcome;
        loop {
            let converged = residual < self.tolerance;
            let last = converged || step == self.steps;
            if step % dy.record_every == 0 || last {
                let clock = Instant::now();
                records.push(Record {
                    step,
                    time: step as f64,
                    kinetic: 0.0,
                    strain: self.kernel.strain_energy(&u).unwrap_or(0.0),
                    broken_energy: 0.0,
                    damping: 0.0,
                    external_work: 0.0,
                    balance_error: 0.0,
                    broken_bonds: 0,
                    residual,
                    reactions: set_sums(
                        &self.constrained,
                        self.sets,
                        &self
                            .constrained
                            .iter()
                            .map(|c| -force[c.point as usize][c.component as usize])
                            .collect::<Vec<_>>(),
                    ),
                    probes: probe_values(self.probes, self.kernel.disc(), &u, &v),
                });
                output_seconds += clock.elapsed().as_secs_f64();
            }
            if wants_snapshot(self.scene, step, last) {
                let clock = Instant::now();
                let damage = self.kernel.damage();
                observer.snapshot(&Snapshot {
                    step,
                    time: step as f64,
                    disc: self.kernel.disc(),
                    u: &u,
                    v: &v,
                    damage: &damage,
                })?;
                output_seconds += clock.elapsed().as_secs_f64();
            }
            if converged {
                outcome = Outcome::Converged { residual };
                break;
            }
            if step == self.steps {
                outcome = Outcome::NotConverged { residual };
                break;
            }
            step += 1;
            u.par_iter_mut().zip(v.par_iter()).for_each(|(ui, vi)| {
                (0..3).for_each(|c| ui[c] += vi[c]);
            });
            std::mem::swap(&mut previous, &mut force);
            evaluate(&mut self.kernel, &u, &mut force);
            // Adaptive damping from the local diagonal stiffness.
            let (num, den) = (0..n)
                .into_par_iter()
                .map(|i| {
                    let (mut num, mut den) = (0.0, 0.0);
                    for c in 0..3 {
                        if free[i][c] && lambda[i][c] > 0.0 {
                            if v[i][c] != 0.0 {
                                let k = -(force[i][c] - previous[i][c]) / (lambda[i][c] * v[i][c]);
                                num += u[i][c] * k * u[i][c];
                            }
                            den += u[i][c] * u[i][c];
                        }
                    }
                    (num, den)
                })
                .reduce(|| (0.0, 0.0), |a, b| (a.0 + b.0, a.1 + b.1));
            let c_damp = if num > 0.0 && den > 0.0 {
                (2.0 * (num / den).sqrt()).min(1.999)
            } else {
                0.0
            };
            v.par_iter_mut().enumerate().for_each(|(i, vi)| {
                for c in 0..3 {
                    if free[i][c] && lambda[i][c] > 0.0 {
                        vi[c] = ((2.0 - c_damp) * vi[c] + 2.0 * force[i][c] / lambda[i][c])
                            / (2.0 + c_damp);
                    }
                }
            });
            residual = self.residual(&force, applied);
            // Checked every step: the residual reduces every force.
            if !residual.is_finite() {
                let point = first_non_finite(&u, &v)
                    .or_else(|| force.iter().position(|f| f.iter().any(|x| !x.is_finite())))
                    .unwrap_or(0);
                return Err(NumericalError::Diverged {
                    step,
                    time: step as f64,
                    point,
                    position: self.kernel.disc().points.x[point],
                    cause: "dynamic relaxation's out-of-balance force left double precision: \
                            the loads or prescribed displacements are too large for this body"
                        .to_string(),
                }
                .into());
            }
            observer.progress(step, self.steps, step as f64, 0);
        }
        let integration = start.elapsed().as_secs_f64() - output_seconds;
        let damage = self.kernel.damage();
        let description = kernel_description(self.scene, self.kernel.as_ref());
        let kernel = self.kernel;
        let mut log = Vec::new();
        if let Outcome::NotConverged { residual } = outcome {
            log.push(format!(
                "dynamic relaxation did not converge: relative out-of-balance force {residual:.3e} \
                 after {step} steps (tolerance {:.1e}); raise dynamics.steps",
                self.tolerance
            ));
        }
        Ok(DynamicsSolution {
            disc: kernel.into_disc(),
            u,
            v,
            damage,
            steps: step,
            time_step: 1.0,
            stable_time_step: None,
            time: step as f64,
            records,
            set_names: Vec::new(),
            loads: Vec::new(),
            outcome,
            timings: DynamicsTimings {
                setup: 0.0,
                integration,
                forces: 0.0,
                output: output_seconds,
            },
            bonds: 0,
            bond_updates_per_second: 0.0,
            max_balance_error: 0.0,
            kernel: description,
            log,
        })
    }
}
