//! Adaptive dynamic relaxation (Kilic & Madenci 2010; module docs of
//! [`super`]): fictitious masses from the tangent's row sums, the adaptive
//! damping from the local diagonal stiffness, steps until the out-of-balance
//! force is `dynamics.tolerance` of the applied force or the reaction.

use super::history::{probe_values, set_sums, wants_snapshot, Record};
use super::kernels::ForceField;
use super::setup::{self, Explicit};
use super::{first_non_finite, DynamicsSolution, DynamicsTimings, Outcome};
use crate::discretization::Discretization;
use crate::drivers::{Observer, Progress, Snapshot};
use crate::error::{Error, NumericalError};
use crate::notes::Notes;
use crate::scene::{RunLength, Scene};
use crate::solve::norm2;
use rayon::prelude::*;
use std::time::Instant;

/// A dynamic relaxation.
pub(super) struct Relaxation<'a> {
    scene: &'a Scene,
    kernel: Box<dyn ForceField>,
    /// Fictitious mass of every component, `¼ Σ_c |K_rc|`.
    lambda: Vec<[f64; 3]>,
    explicit: Explicit,
    steps: usize,
    tolerance: f64,
    /// The loads at full value.
    f_ext: Vec<[f64; 3]>,
}

/// The state of a relaxation between steps.
struct State {
    u: Vec<[f64; 3]>,
    v: Vec<[f64; 3]>,
    /// Out-of-balance force `F_int + f_ext`.
    force: Vec<[f64; 3]>,
    /// The force of the step before.
    previous: Vec<[f64; 3]>,
}

impl<'a> Relaxation<'a> {
    /// The fictitious masses and the force field of `scene` on `disc`.
    pub(super) fn new(
        scene: &'a Scene,
        explicit: Explicit,
        disc: Discretization,
        notes: &mut Notes,
    ) -> Result<Self, Error> {
        let dy = scene.dynamics.as_ref().expect("a dynamics scene");
        let rows = setup::tangent_row_sums(scene, &disc)?;
        let mut f_ext = vec![[0.0; 3]; disc.points.len()];
        explicit.loads.add_into(0.0, &mut f_ext);
        let kernel = setup::kernel(scene, disc, notes)?;
        let steps = match dy.length {
            RunLength::Steps(s) => s,
            RunLength::Time(_) => unreachable!("validated: relaxation takes steps"),
        };
        Ok(Relaxation {
            scene,
            kernel,
            lambda: rows.iter().map(|r| r.map(|v| 0.25 * v)).collect(),
            explicit,
            steps,
            tolerance: dy.tolerance,
            f_ext,
        })
    }

    /// Out-of-balance force on the free components, relative to the larger of
    /// the applied force and the reaction.
    fn residual(&self, force: &[[f64; 3]], applied: f64) -> f64 {
        let free = &self.explicit.free;
        // Scaled norms: forces of 1e160 N keep a finite residual.
        let r = norm2(
            force
                .iter()
                .enumerate()
                .flat_map(|(i, f)| (0..3).filter(move |&c| free[i][c]).map(move |c| f[c])),
        );
        let reaction = norm2(
            self.explicit
                .constrained
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

    /// `F_int(u) + f_ext` into `force`.
    fn evaluate(&mut self, u: &[[f64; 3]], force: &mut [[f64; 3]]) {
        self.kernel.forces(u, force);
        force
            .par_iter_mut()
            .zip(self.f_ext.par_iter())
            .for_each(|(f, e)| (0..3).for_each(|c| f[c] += e[c]));
    }

    /// Runs the steps until the tolerance or the last step; `observer` sees
    /// the progress and the snapshots.
    pub(super) fn relax(mut self, observer: &mut dyn Observer) -> Result<DynamicsSolution, Error> {
        let dy = self.scene.dynamics.as_ref().expect("a dynamics scene");
        let free = &self.explicit.free;
        let applied = norm2(
            self.f_ext
                .iter()
                .zip(free)
                .flat_map(|(f, free)| (0..3).filter(|&c| free[c]).map(|c| f[c])),
        );
        let mut s = self.start();
        let start = Instant::now();
        let mut output_seconds = 0.0;
        let mut residual = self.residual(&s.force, applied);
        let mut records = Vec::new();
        let mut step = 0;
        let outcome = loop {
            let converged = residual < self.tolerance;
            let last = converged || step == self.steps;
            let clock = Instant::now();
            if step % dy.record_every == 0 || last {
                records.push(self.record(&s, step, residual));
            }
            if wants_snapshot(self.scene, step, last) {
                let damage = self.kernel.damage();
                let stress = self.kernel.stress(&s.u).transpose()?;
                observer.snapshot(&Snapshot {
                    step,
                    timestep: step as f64,
                    disc: self.kernel.disc(),
                    u: &s.u,
                    velocity: Some(&s.v),
                    damage: &damage,
                    stress: stress.as_deref(),
                    bond_counts: None,
                })?;
            }
            output_seconds += clock.elapsed().as_secs_f64();
            if converged {
                break Outcome::Converged { residual };
            }
            if step == self.steps {
                break Outcome::NotConverged { residual };
            }
            step += 1;
            residual = self.step(&mut s, applied, step)?;
            observer.progress(&Progress::Relaxation {
                step,
                steps: self.steps,
            });
        };
        let timings = DynamicsTimings {
            setup: 0.0,
            integration: start.elapsed().as_secs_f64() - output_seconds,
            forces: 0.0,
            output: output_seconds,
        };
        self.solution(s, step, outcome, records, timings)
    }

    /// The prescribed displacements, the forces and the first velocities.
    fn start(&mut self) -> State {
        let n = self.lambda.len();
        let mut u = vec![[0.0; 3]; n];
        for c in &self.explicit.constrained {
            u[c.point as usize][c.component as usize] = c.value;
        }
        let mut force = vec![[0.0; 3]; n];
        self.evaluate(&u, &mut force);
        let mut v = vec![[0.0; 3]; n];
        let (lambda, free) = (&self.lambda, &self.explicit.free);
        v.par_iter_mut().enumerate().for_each(|(i, vi)| {
            for c in 0..3 {
                if free[i][c] && lambda[i][c] > 0.0 {
                    vi[c] = 0.5 * force[i][c] / lambda[i][c];
                }
            }
        });
        State {
            u,
            v,
            force,
            previous: vec![[0.0; 3]; n],
        }
    }

    /// One step: the displacements, the new forces, the adaptive damping
    /// and the velocities; returns the new residual (a non-finite one is a
    /// divergence, found at the step it happens).
    fn step(&mut self, s: &mut State, applied: f64, step: usize) -> Result<f64, Error> {
        s.u.par_iter_mut().zip(s.v.par_iter()).for_each(|(ui, vi)| {
            (0..3).for_each(|c| ui[c] += vi[c]);
        });
        std::mem::swap(&mut s.previous, &mut s.force);
        self.evaluate(&s.u, &mut s.force);
        let c_damp = self.damping(s);
        let (lambda, free, force) = (&self.lambda, &self.explicit.free, &s.force);
        s.v.par_iter_mut().enumerate().for_each(|(i, vi)| {
            for c in 0..3 {
                if free[i][c] && lambda[i][c] > 0.0 {
                    vi[c] = ((2.0 - c_damp) * vi[c] + 2.0 * force[i][c] / lambda[i][c])
                        / (2.0 + c_damp);
                }
            }
        });
        let residual = self.residual(&s.force, applied);
        // Checked every step: the residual reduces every force.
        if !residual.is_finite() {
            let point = first_non_finite(&s.u, &s.v)
                .or_else(|| {
                    s.force
                        .iter()
                        .position(|f| f.iter().any(|x| !x.is_finite()))
                })
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
        Ok(residual)
    }

    /// The adaptive damping `c = 2 sqrt(uᵀ ¹K u / uᵀu)` from the local
    /// diagonal stiffness (module docs of [`super`]).
    fn damping(&self, s: &State) -> f64 {
        let (lambda, free) = (&self.lambda, &self.explicit.free);
        let (u, v, force, previous) = (&s.u, &s.v, &s.force, &s.previous);
        let (num, den) = (0..self.lambda.len())
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
        if num > 0.0 && den > 0.0 {
            (2.0 * (num / den).sqrt()).min(1.999)
        } else {
            0.0
        }
    }

    /// The record of `step`.
    fn record(&self, s: &State, step: usize, residual: f64) -> Record {
        let e = &self.explicit;
        let support: Vec<f64> = e
            .constrained
            .iter()
            .map(|c| -s.force[c.point as usize][c.component as usize])
            .collect();
        Record {
            step,
            time: step as f64,
            kinetic: 0.0,
            strain: self.kernel.strain_energy(&s.u).unwrap_or(0.0),
            broken_energy: 0.0,
            damping: 0.0,
            external_work: 0.0,
            balance_error: 0.0,
            broken_bonds: 0,
            residual,
            reactions: set_sums(&e.constrained, e.sets, &support),
            probes: probe_values(&e.probes, self.kernel.disc(), &s.u, &s.v),
        }
    }

    /// The solution at the end of the run.
    fn solution(
        self,
        s: State,
        step: usize,
        outcome: Outcome,
        records: Vec<Record>,
        timings: DynamicsTimings,
    ) -> Result<DynamicsSolution, Error> {
        let damage = self.kernel.damage();
        let kernel = setup::kernel_description(self.scene, self.kernel.as_ref());
        let mut log = Vec::new();
        if let Outcome::NotConverged { residual } = outcome {
            log.push(format!(
                "dynamic relaxation did not converge: relative out-of-balance force {residual:.3e} \
                 after {step} steps (tolerance {:.1e}); raise dynamics.steps",
                self.tolerance
            ));
        }
        let stress = self.kernel.stress(&s.u).transpose()?;
        Ok(DynamicsSolution {
            stress,
            bond_counts: None,
            disc: self.kernel.into_disc(),
            u: s.u,
            v: s.v,
            damage,
            steps: step,
            time_step: 1.0,
            stable_time_step: None,
            time: step as f64,
            records,
            set_names: Vec::new(),
            loads: Vec::new(),
            outcome,
            timings,
            bonds: 0,
            bonds_held: None,
            bond_updates_per_second: 0.0,
            max_balance_error: 0.0,
            kernel,
            log,
            plan: Default::default(),
        })
    }
}
