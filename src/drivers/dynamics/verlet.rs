//! Velocity Verlet with mass-proportional damping (module docs of [`super`]):
//! the time step and its checks, the initial state, the steps, the energy
//! books and the records.
//!
//! **On several processes** (`solver.method = "petsc"` in an MPI run; the body
//! discretised over them: [`crate::discretization::share`]) each process
//! steps only its own points, from forces that its own and ghost bonds give
//! them: the force on a point needs the bonds touching it and the
//! displacements within a bond length (the bond-based model) or three (the
//! shear model: its owners' kinematics reach two, and a bond's breakage test
//! reads its neighbour's dilatation, a family further), all within the
//! families a process holds.
//! Before every force evaluation the ghost points' displacements come from
//! their processes ([`Halo`]); a bond is broken by every process that holds it,
//! from the same displacements, and counted by its owner's. The energy books,
//! the reactions and the probes are each process's own points' and are summed
//! at a record; the divergence check sums its two numbers every step, so that
//! every process stops at the same step; snapshots and the final state are
//! gathered on every process.

use super::history::{kinetic, probe_values, set_sums, wants_snapshot, Books, Record};
use super::kernels::ForceField;
use super::setup::{self, Constrained, Explicit, Loads};
use super::{diverged_point, DynamicsSolution, DynamicsTimings, Outcome};
use crate::discretization::share::Halo;
use crate::discretization::Discretization;
use crate::drivers::{forward, Observer, Progress, Snapshot};
use crate::error::{Error, InputError, NumericalError};
use crate::notes::Notes;
use crate::processes::{agreed, Processes};
use crate::scene::{Dynamics, Motion, RunLength, Scene};
use rayon::prelude::*;
use std::time::Instant;

/// Largest `α Δt` of the damped Verlet step (module docs of [`super`]).
const MAX_DAMPING_STEP: f64 = 2.0;

/// First step whose energy balance is checked against `dynamics.balance_tolerance`:
/// a load applied suddenly at t = 0 gives the first steps a start-up error of
/// the trapezoidal work relative to the then tiny energies (0.07 at step 1 on
/// the base plate, 0.23 with α Δt = 1.9; 0.006 and 0.024 from step 10 on).
const BALANCE_FROM_STEP: usize = 10;

/// A Verlet run.
pub(super) struct Verlet<'a> {
    scene: &'a Scene,
    dy: &'a Dynamics,
    kernel: Box<dyn ForceField>,
    mass: Vec<f64>,
    explicit: Explicit,
    dt: f64,
    /// The stable time step (`dt` above it only with `force_time_step`).
    pub(super) stable_dt: f64,
    steps: usize,
    /// The processes the points are shared with (module docs), when several.
    shared: Option<Shared<'a>>,
}

/// The processes of a distributed run and this one's ghost points.
struct Shared<'a> {
    processes: &'a dyn Processes,
    halo: Halo,
    /// Whether each point is this process's.
    own: Vec<bool>,
}

/// The state of a Verlet run between steps.
struct State {
    u: Vec<[f64; 3]>,
    v: Vec<[f64; 3]>,
    a: Vec<[f64; 3]>,
    du: Vec<[f64; 3]>,
    f_int: Vec<[f64; 3]>,
    /// `F_int + f_ext`.
    force: Vec<[f64; 3]>,
    /// Support force `R = m a − F` of each constrained component.
    support: Vec<f64>,
    /// Prescribed velocity of each constrained component before the step.
    v_prescribed_old: Vec<f64>,
    t: f64,
}

impl<'a> Verlet<'a> {
    /// The masses, the stable and the actual time step (each checked), the
    /// number of steps and the force field of `scene` on `disc`.
    pub(super) fn new(
        scene: &'a Scene,
        mut explicit: Explicit,
        disc: Discretization,
        processes: Option<&'a dyn Processes>,
        notes: &mut Notes,
    ) -> Result<Self, Error> {
        let dy = scene.dynamics.as_ref().expect("a dynamics scene");
        let p = &disc.points;
        let mass: Vec<f64> = (0..p.len())
            .map(|i| {
                let material = &scene.materials[p.material[i] as usize];
                material
                    .density
                    .expect("validated: Verlet has every density")
                    * p.volume[i]
            })
            .collect();
        let shared = match (processes, disc.partial_share()) {
            (Some(processes), Some(share)) => Some(Shared {
                processes,
                halo: Halo::new(share, processes),
                own: (0..p.len()).map(|i| share.owns(i)).collect(),
            }),
            _ => None,
        };
        if let Some(shared) = &shared {
            // Only own points are stepped; the ghosts' come from their processes.
            for (free, &own) in explicit.free.iter_mut().zip(&shared.own) {
                if !own {
                    *free = [false; 3];
                }
            }
            explicit
                .constrained
                .retain(|c| shared.own[c.point as usize]);
        }
        let own = |i: usize| shared.as_ref().is_none_or(|s| s.own[i]);
        let stable_dt = stable_time_step(scene, &disc, &mass, dy, &own, processes)?;
        let dt = match dy.time_step {
            Some(t) => t,
            None => dy.safety_factor * stable_dt,
        };
        check_damping(dy, dt)?;
        let steps = steps(dy, dt)?;
        // The linearised kernel's pattern is refused by a memory check that
        // counts this process's own entries: one may refuse while the others
        // go on (a collective call).
        let kernel = agreed(processes, setup::kernel(scene, disc, notes))?;
        Ok(Verlet {
            scene,
            dy,
            kernel,
            mass,
            explicit,
            dt,
            stable_dt,
            steps,
            shared,
        })
    }

    /// Whether point `i` is this process's.
    fn owns(&self, i: usize) -> bool {
        self.shared.as_ref().is_none_or(|s| s.own[i])
    }

    /// Every entry of `values` summed over the processes (a collective call).
    fn sum(&self, values: &mut [f64]) {
        if let Some(s) = &self.shared {
            s.processes.sum(values);
        }
    }

    /// `result` here, unless another process failed (a collective call).
    fn agreed<T>(&self, result: Result<T, Error>) -> Result<T, Error> {
        agreed(self.shared.as_ref().map(|s| s.processes), result)
    }

    /// The ghost points' displacements from their processes (a collective call).
    fn exchange(&self, u: &mut [[f64; 3]]) {
        if let Some(s) = &self.shared {
            s.halo.exchange(s.processes, u);
        }
    }

    /// Every point's `values` from its process (a collective call).
    fn gather<const K: usize>(&self, values: &[[f64; K]]) -> Vec<[f64; K]> {
        let Some(s) = &self.shared else {
            return values.to_vec();
        };
        let mut flat: Vec<f64> = values
            .iter()
            .zip(&s.own)
            .flat_map(|(v, &own)| v.map(|x| if own { x } else { 0.0 }))
            .collect();
        s.processes.sum(&mut flat);
        flat.chunks_exact(K)
            .map(|c| std::array::from_fn(|k| c[k]))
            .collect()
    }

    /// Every point's count of intact bonds from its process, on several
    /// processes (a collective call); `None` on one, where the
    /// discretisation holds every bond.
    fn bond_counts(&self) -> Option<Vec<u32>> {
        self.shared
            .as_ref()
            .map(|_| crate::drivers::shares::bond_counts(self.kernel.disc()))
    }

    /// Every point's damage from its process (a collective call).
    fn damage(&self) -> Vec<f64> {
        let damage: Vec<[f64; 1]> = self.kernel.damage().into_iter().map(|d| [d]).collect();
        self.gather(&damage).into_iter().map(|[d]| d).collect()
    }

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
    /// time step too large). Only the points `own` flags (this process's).
    fn check_initial_state(
        &self,
        u: &[[f64; 3]],
        v: &[[f64; 3]],
        f_int: &[[f64; 3]],
        own: &dyn Fn(usize) -> bool,
    ) -> Result<(), Error> {
        let kinetic = |i: usize| 0.5 * self.mass[i] * crate::vector::dot(&v[i], &v[i]);
        let moving = (0..v.len())
            .filter(|&i| own(i))
            .find(|&i| !kinetic(i).is_finite());
        let total: f64 = (0..v.len()).filter(|&i| own(i)).map(kinetic).sum();
        let moving =
            moving.or_else(|| (!total.is_finite()).then(|| diverged_point(u, v, &self.mass)));
        // A non-finite displacement, else the largest displacement when a
        // force overflowed (the point whose displacement caused it).
        let strained = (0..u.len())
            .filter(|&i| own(i))
            .find(|&i| u[i].iter().any(|x| !x.is_finite()))
            .or_else(|| {
                let overflowed = |i: usize| f_int[i].iter().any(|x| !x.is_finite());
                (0..u.len()).any(|i| own(i) && overflowed(i)).then(|| {
                    (0..u.len())
                        .filter(|&i| own(i))
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
            let i = (0..f_int.len())
                .find(|&i| own(i) && f_int[i].iter().any(|x| !x.is_finite()))
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
        let field = self.blame(point, velocity);
        Err(InputError::new(
            field,
            format!(
                "gives point {point} (x = {x:?}) {what}, so the run cannot take a step; give a \
                 smaller value (or rescale the units)"
            ),
        )
        .into())
    }
    /// The entry that set `point`'s initial velocity (`velocity`) or
    /// displacement: an initial condition, else a support.
    fn blame(&self, point: usize, velocity: bool) -> String {
        let x = self.kernel.disc().points.x[point];
        let key = if velocity { "velocity" } else { "displacement" };
        self.scene
            .initial_conditions
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
                self.explicit
                    .constrained
                    .iter()
                    .find(|c| c.point as usize == point)
                    .map(|c| format!("boundary[{}].{key}", c.set))
            })
            .unwrap_or_else(|| "initial_conditions".to_string())
    }

    /// Prescribed displacement and velocity of a constrained component at `t`.
    fn prescribed(&self, c: &Constrained, t: f64) -> (f64, f64) {
        let boundary = &self.scene.boundaries[c.set as usize];
        let g = &boundary.time;
        match boundary.motion {
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

    /// Runs the steps; `observer` sees the progress, the snapshots and the notes.
    pub(super) fn integrate(
        mut self,
        observer: &mut dyn Observer,
        notes: &mut Notes,
    ) -> Result<DynamicsSolution, Error> {
        let (mut u, mut v) = self.initial_state(notes);
        if let Some(s) = &self.shared {
            // Ghosts move with their processes; their own velocities stay there.
            v.iter_mut()
                .zip(&s.own)
                .filter(|(_, &own)| !own)
                .for_each(|(vi, _)| *vi = [0.0; 3]);
        }
        self.exchange(&mut u);
        forward(notes, observer);
        let (mut state, mut books) = self.start(u, v)?;
        let mut records = Vec::new();
        let (mut output_seconds, mut force_seconds) = (0.0, 0.0);
        let start = Instant::now();
        for step in 0..=self.steps {
            if step > 0 {
                force_seconds += self.step(&mut state, &mut books, step)?;
                observer.progress(&Progress::Dynamics {
                    step,
                    steps: self.steps,
                    time: state.t,
                    broken: books.broken_bonds,
                });
            }
            let last = step == self.steps;
            let clock = Instant::now();
            if step % self.dy.record_every == 0 || last {
                records.push(self.record(&state, &mut books, step)?);
            }
            if wants_snapshot(self.scene, step, last) {
                let damage = self.damage();
                let (u, v) = (self.gather(&state.u), self.gather(&state.v));
                let counts = self.bond_counts();
                let stress = self.kernel.stress(&u).transpose()?;
                let written = observer.snapshot(&Snapshot {
                    step,
                    timestep: state.t,
                    disc: self.kernel.disc(),
                    u: &u,
                    velocity: Some(&v),
                    damage: &damage,
                    stress: stress.as_deref(),
                    bond_counts: counts.as_deref(),
                });
                self.agreed(written)?;
            }
            output_seconds += clock.elapsed().as_secs_f64();
        }
        let timings = DynamicsTimings {
            setup: 0.0,
            integration: start.elapsed().as_secs_f64() - output_seconds,
            forces: force_seconds,
            output: output_seconds,
        };
        self.solution(state, books, records, timings)
    }

    /// The displacements and velocities of the initial conditions (a
    /// warning for a Gaussian pulse narrower than the spacing), with the
    /// prescribed values at t = 0.
    fn initial_state(&self, notes: &mut Notes) -> (Vec<[f64; 3]>, Vec<[f64; 3]>) {
        let n = self.mass.len();
        let mut u = vec![[0.0; 3]; n];
        let mut v = vec![[0.0; 3]; n];
        let points = &self.kernel.disc().points;
        let x = &points.x;
        let initial = &self.scene.initial_conditions;
        for (k, g) in initial
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
                notes.push(format!(
                    "warning: initial_conditions[{k}].gaussian.width = {} m is below the \
                     spacing ({} m): the pulse is not resolved and displaces {moved} \
                     point(s) by more than 1e-3 of its amplitude",
                    crate::error::num(g.width),
                    crate::error::num(spacing)
                ));
            }
        }
        for ic in initial {
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
        for c in &self.explicit.constrained {
            let (uc, vc) = self.prescribed(c, 0.0);
            u[c.point as usize][c.component as usize] = uc;
            v[c.point as usize][c.component as usize] = vc;
        }
        (u, v)
    }

    /// The forces and accelerations of the initial state (refused when it is
    /// beyond double precision) and the books at t = 0.
    fn start(&mut self, u: Vec<[f64; 3]>, v: Vec<[f64; 3]>) -> Result<(State, Books), Error> {
        let n = self.mass.len();
        let mut f_int = vec![[0.0; 3]; n];
        let mut force = vec![[0.0; 3]; n];
        let mut a = vec![[0.0; 3]; n];
        let broken = self.kernel.forces(&u, &mut f_int);
        let own = |i: usize| self.owns(i);
        let checked = self.check_initial_state(&u, &v, &f_int, &own);
        self.agreed(checked)?;
        total(&f_int, &mut force, 0.0, &self.explicit.loads);
        let (mass, free) = (&self.mass, &self.explicit.free);
        a.par_iter_mut().enumerate().for_each(|(i, ai)| {
            *ai = std::array::from_fn(|c| {
                if free[i][c] {
                    force[i][c] / mass[i]
                } else {
                    0.0
                }
            })
        });
        let uses_work = self.kernel.strain_energy(&u).is_none();
        let initial_strain = self.kernel.strain_energy(&u).unwrap_or(0.0);
        let e0 = kinetic(&v, mass) + initial_strain;
        // The scale of the balance error starts from the whole body's energy.
        let mut whole = [e0];
        self.sum(&mut whole);
        let books = Books {
            e0,
            w_ext: 0.0,
            w_int: 0.0,
            damping_work: 0.0,
            broken_energy: broken.energy,
            broken_bonds: broken.bonds,
            scale: whole[0].abs(),
            max_balance: 0.0,
            uses_work,
        };
        let constrained = &self.explicit.constrained;
        let state = State {
            support: constrained
                .iter()
                .map(|c| -force[c.point as usize][c.component as usize])
                .collect(),
            v_prescribed_old: vec![0.0; constrained.len()],
            du: vec![[0.0; 3]; n],
            u,
            v,
            a,
            f_int,
            force,
            t: 0.0,
        };
        Ok((state, books))
    }

    /// One damped Verlet step to `step`; returns the time of its force evaluation.
    fn step(&mut self, s: &mut State, books: &mut Books, step: usize) -> Result<f64, Error> {
        let t1 = step as f64 * self.dt;
        self.kick_and_drift(s);
        for (k, c) in self.explicit.constrained.iter().enumerate() {
            s.v_prescribed_old[k] = s.v[c.point as usize][c.component as usize];
        }
        for c in &self.explicit.constrained {
            let (i, k) = (c.point as usize, c.component as usize);
            let (uc, vc) = self.prescribed(c, t1);
            s.du[i][k] = uc - s.u[i][k];
            s.u[i][k] = uc;
            s.v[i][k] = vc;
        }
        // Work of the loads over the step (trapezoidal), before the new forces.
        let loads = &self.explicit.loads;
        books.w_ext += 0.5 * (loads.power(s.t, &s.du) + loads.power(t1, &s.du));
        let power_int_old = power(&s.f_int, &s.du);
        let clock = Instant::now();
        self.exchange(&mut s.u);
        let breaks = self.kernel.forces(&s.u, &mut s.f_int);
        let force_seconds = clock.elapsed().as_secs_f64();
        books.broken_bonds += breaks.bonds;
        books.broken_energy += breaks.energy;
        total(&s.f_int, &mut s.force, t1, &self.explicit.loads);
        let power_int_new = power(&s.f_int, &s.du);
        books.w_int -= 0.5 * (power_int_old + power_int_new);
        let (damping_step, twice_kinetic) = self.second_kick(s);
        // Summed over the processes: a non-finite one makes the sum so on all.
        let mut check = [damping_step, twice_kinetic];
        self.sum(&mut check);
        if !(check[0].is_finite() && check[1].is_finite()) {
            return Err(self.diverged(step, t1, &s.u, &s.v));
        }
        books.damping_work += damping_step;
        // Supports: trapezoidal work of the reactions R = m a − F.
        for (k, c) in self.explicit.constrained.iter().enumerate() {
            let (i, comp) = (c.point as usize, c.component as usize);
            let acc = (s.v[i][comp] - s.v_prescribed_old[k]) / self.dt;
            let r_new = self.mass[i] * acc - s.force[i][comp];
            books.w_ext += 0.5 * (s.support[k] + r_new) * s.du[i][comp];
            s.support[k] = r_new;
        }
        s.t = t1;
        Ok(force_seconds)
    }

    /// Half kick and drift of the free components.
    fn kick_and_drift(&self, s: &mut State) {
        let (dt, alpha, free) = (self.dt, self.dy.damping, &self.explicit.free);
        s.u.par_iter_mut()
            .zip(s.v.par_iter_mut())
            .zip(s.du.par_iter_mut())
            .zip(s.a.par_iter())
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
    }

    /// The second half kick of the free components; returns the work of the
    /// damping over the step and `Σ m |v|²` of the new velocities (a
    /// non-finite sum is a divergence, found at the step it happens).
    fn second_kick(&self, s: &mut State) -> (f64, f64) {
        let (dt, alpha) = (self.dt, self.dy.damping);
        let (mass, free, force) = (&self.mass, &self.explicit.free, &s.force);
        let factor = 1.0 / (1.0 + 0.5 * alpha * dt);
        s.a.par_iter_mut()
            .zip(s.v.par_iter_mut())
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
            .reduce(|| (0.0, 0.0), |x, y| (x.0 + y.0, x.1 + y.1))
    }

    /// The record of `step`, its energy balance checked (from step
    /// [`BALANCE_FROM_STEP`] on).
    fn record(&self, s: &State, books: &mut Books, step: usize) -> Result<Record, Error> {
        let e_kin = kinetic(&s.v, &self.mass);
        let stored = if books.uses_work {
            None
        } else {
            self.kernel.strain_energy(&s.u)
        };
        let e = &self.explicit;
        let mut reactions = set_sums(&e.constrained, e.sets, &s.support);
        let mut probes = probe_values(&e.probes, self.kernel.disc(), &s.u, &s.v);
        let (e_kin, stored, mut whole) = match &self.shared {
            None => (e_kin, stored, None),
            Some(_) => {
                // Each process's own points' shares, summed.
                let mut sums = vec![e_kin, stored.unwrap_or(0.0)];
                sums.extend(books.shares());
                sums.extend(reactions.iter().flatten());
                for (&i, (u, v, damage)) in e.probes.iter().zip(&probes) {
                    let own = f64::from(u8::from(self.owns(i)));
                    sums.extend(u.iter().chain(v).chain([damage]).map(|x| own * x));
                }
                self.sum(&mut sums);
                let (shares, rest) = sums[2..].split_at(Books::SHARES);
                let whole = books.with_shares(shares);
                let (sets, rest) = rest.split_at(3 * reactions.len());
                for (r, f) in reactions.iter_mut().zip(sets.chunks_exact(3)) {
                    r.copy_from_slice(f);
                }
                for (p, values) in probes.iter_mut().zip(rest.chunks_exact(7)) {
                    *p = (
                        std::array::from_fn(|c| values[c]),
                        std::array::from_fn(|c| values[3 + c]),
                        values[6],
                    );
                }
                (sums[0], stored.map(|_| sums[1]), Some(whole))
            }
        };
        // The whole body's books: summed over the processes, whose largest
        // energy and balance error this process keeps.
        let (balance, books) = match whole.as_mut() {
            Some(whole) => {
                let balance = whole.balance(e_kin, stored);
                (books.scale, books.max_balance) = (whole.scale, whole.max_balance);
                (balance, &*whole)
            }
            None => (books.balance(e_kin, stored), &*books),
        };
        let Some(relative) = balance.relative else {
            // Every velocity is finite (checked each step), but an energy or
            // a work left double precision.
            return Err(self.diverged(step, s.t, &s.u, &s.v));
        };
        if step >= BALANCE_FROM_STEP && relative.abs() > self.dy.balance_tolerance {
            return Err(NumericalError::EnergyBalance {
                step,
                time: s.t,
                error: relative,
                tolerance: self.dy.balance_tolerance,
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
        Ok(Record {
            step,
            time: s.t,
            kinetic: balance.kinetic,
            strain: balance.strain,
            broken_energy: balance.broken,
            damping: books.damping_work,
            external_work: books.w_ext,
            balance_error: relative,
            broken_bonds: books.broken_bonds,
            residual: 0.0,
            reactions,
            probes,
        })
    }

    /// The solution at the end of the run.
    fn solution(
        self,
        s: State,
        books: Books,
        records: Vec<Record>,
        timings: DynamicsTimings,
    ) -> Result<DynamicsSolution, Error> {
        let damage = self.damage();
        let (u, v) = (self.gather(&s.u), self.gather(&s.v));
        let bond_counts = self.bond_counts();
        let stress = self.kernel.stress(&u).transpose()?;
        let kernel = setup::kernel_description(self.scene, self.kernel.as_ref());
        Ok(DynamicsSolution {
            stress,
            bond_counts,
            disc: self.kernel.into_disc(),
            u,
            v,
            damage,
            steps: self.steps,
            time_step: self.dt,
            stable_time_step: Some(self.stable_dt),
            time: s.t,
            records,
            set_names: Vec::new(),
            loads: Vec::new(),
            outcome: Outcome::Completed,
            timings,
            bonds: 0,
            bonds_held: None,
            bond_updates_per_second: 0.0,
            max_balance_error: books.max_balance,
            kernel,
            log: Vec::new(),
            plan: Default::default(),
        })
    }
}

/// `F_int + f_ext(t)` into `force`.
fn total(f_int: &[[f64; 3]], force: &mut [[f64; 3]], t: f64, loads: &Loads) {
    force.copy_from_slice(f_int);
    loads.add_into(t, force);
}

/// `Σ f · du`.
fn power(f: &[[f64; 3]], du: &[[f64; 3]]) -> f64 {
    f.par_iter()
        .zip(du.par_iter())
        .map(|(f, d)| f[0] * d[0] + f[1] * d[1] + f[2] * d[2])
        .sum()
}

/// The stable time step of `scene` on `disc` (module docs of [`super`]),
/// refused when it left the floating-point range; a given `dynamics.time_step`
/// above it is refused unless forced.
///
/// On several processes, each over its `own` points (whose bonds it all
/// holds), the least over the processes (a collective call).
fn stable_time_step(
    scene: &Scene,
    disc: &Discretization,
    mass: &[f64],
    dy: &Dynamics,
    own: &dyn Fn(usize) -> bool,
    processes: Option<&dyn Processes>,
) -> Result<f64, Error> {
    let stable = agreed(processes, setup::stable_time_steps(scene, disc, mass))?;
    let (mut critical_point, mut stable_dt) = stable
        .iter()
        .copied()
        .enumerate()
        .filter(|&(i, _)| own(i))
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .unwrap_or((0, f64::INFINITY));
    if let Some(processes) = processes {
        // The least step over the processes, and the least point that has it.
        let mut least = [stable_dt];
        processes.min(&mut least);
        let mut point = [match stable_dt.to_bits() == least[0].to_bits() {
            true => critical_point as f64,
            false => f64::INFINITY,
        }];
        processes.min(&mut point);
        (stable_dt, critical_point) = (least[0], point[0] as usize);
    }
    if !(stable_dt.is_finite() && stable_dt > 0.0) {
        // Bond stiffnesses that under- or overflowed at this scale.
        return Err(crate::discretization::beyond_double_precision(
            disc,
            critical_point,
            "the stable time step",
            stable_dt,
        )
        .into());
    }
    match dy.time_step {
        Some(t) if t > stable_dt && !dy.force_time_step => Err(InputError::new(
            "dynamics.time_step",
            format!(
                "{t:e} s is above the stable time step {stable_dt:e} s (point \
                 {critical_point} at {:?}); give at most that, omit time_step for \
                 {} × it, or set force_time_step = true",
                disc.points.x[critical_point], dy.safety_factor
            ),
        )
        .into()),
        _ => Ok(stable_dt),
    }
}

/// Refuses a damping the damped step cannot hold, `α Δt` above
/// [`MAX_DAMPING_STEP`] (module docs of [`super`]).
fn check_damping(dy: &Dynamics, dt: f64) -> Result<(), Error> {
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
    Ok(())
}

/// The number of steps of `dt` the run takes.
fn steps(dy: &Dynamics, dt: f64) -> Result<usize, Error> {
    Ok(match dy.length {
        RunLength::Steps(s) => s,
        RunLength::Time(t) => {
            let s = (t / dt - 1e-9).ceil().max(1.0);
            if s > crate::scene::dynamics::MAX_STEPS as f64 {
                return Err(InputError::new(
                    "dynamics.end_time",
                    format!(
                        "{t:e} s takes {s:.3e} steps of {dt:e} s; at most {} are allowed",
                        crate::scene::dynamics::MAX_STEPS
                    ),
                )
                .into());
            }
            s as usize
        }
    })
}
