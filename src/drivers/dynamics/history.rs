//! The history of an explicit run (`history.csv`, `probes.csv`): one
//! [`Record`] every `record_every` steps, and the energy books of a Verlet run
//! whose balance error is checked at each record (module docs of [`super`]).

use super::setup::Constrained;
use crate::discretization::Discretization;
use crate::scene::Scene;
use rayon::prelude::*;

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

/// The energies of a Verlet run so far.
pub(super) struct Books {
    /// Energy at the start, kinetic plus strain.
    pub(super) e0: f64,
    /// Work of the loads and supports.
    pub(super) w_ext: f64,
    /// Work of the internal forces, `−∫ F_int · du` (the shear model's strain column).
    pub(super) w_int: f64,
    /// Energy dissipated by damping.
    pub(super) damping_work: f64,
    /// Energy of the bonds when they broke.
    pub(super) broken_energy: f64,
    /// Bonds broken so far.
    pub(super) broken_bonds: usize,
    /// Largest energy seen (the scale of the balance error).
    pub(super) scale: f64,
    /// Largest |balance error| of the records so far.
    pub(super) max_balance: f64,
    /// The field has no strain energy in closed form: the strain column is `w_int`.
    pub(super) uses_work: bool,
}

/// The balance of one record: the energies of its columns and its error.
pub(super) struct Balance {
    pub(super) kinetic: f64,
    pub(super) strain: f64,
    pub(super) broken: f64,
    /// `E_kin + E_strain + E_broken + E_damping − W_ext − E_0` relative to
    /// the largest energy seen (None: an energy left double precision).
    pub(super) relative: Option<f64>,
}

impl Books {
    /// The number of [`Books::shares`].
    pub(super) const SHARES: usize = 6;

    /// The sums a process keeps over its own points on several processes:
    /// `e0`, `w_ext`, `w_int`, the damping work, the broken energy and bonds.
    pub(super) fn shares(&self) -> [f64; Self::SHARES] {
        [
            self.e0,
            self.w_ext,
            self.w_int,
            self.damping_work,
            self.broken_energy,
            self.broken_bonds as f64,
        ]
    }

    /// These books with the sums of [`Books::shares`] set to `sums` (the
    /// processes' shares summed).
    pub(super) fn with_shares(&self, sums: &[f64]) -> Books {
        Books {
            e0: sums[0],
            w_ext: sums[1],
            w_int: sums[2],
            damping_work: sums[3],
            broken_energy: sums[4],
            broken_bonds: sums[5] as usize,
            scale: self.scale,
            max_balance: self.max_balance,
            uses_work: self.uses_work,
        }
    }

    /// The balance at a record, with the kinetic energy and (when the field
    /// has one) the stored strain energy; raises the scale.
    pub(super) fn balance(&mut self, kinetic: f64, stored: Option<f64>) -> Balance {
        let strain = if self.uses_work {
            self.w_int
        } else {
            stored.unwrap_or(0.0)
        };
        let broken = if self.uses_work {
            0.0
        } else {
            self.broken_energy
        };
        self.scale = self
            .scale
            .max(kinetic)
            .max(strain.abs())
            .max((kinetic + strain).abs())
            .max(self.w_ext.abs());
        let balance = kinetic + strain + broken + self.damping_work - self.w_ext - self.e0;
        let relative = (balance.is_finite() && self.scale.is_finite()).then(|| {
            if self.scale > 0.0 {
                balance / self.scale
            } else {
                0.0
            }
        });
        if let Some(r) = relative {
            self.max_balance = self.max_balance.max(r.abs());
        }
        Balance {
            kinetic,
            strain,
            broken,
            relative,
        }
    }
}

/// Kinetic energy `½ Σ m v²`.
pub(super) fn kinetic(v: &[[f64; 3]], mass: &[f64]) -> f64 {
    v.par_iter()
        .zip(mass.par_iter())
        .map(|(vi, m)| 0.5 * m * (vi[0] * vi[0] + vi[1] * vi[1] + vi[2] * vi[2]))
        .sum()
}

/// Whether the scene's output asks for a snapshot at `step` (`output.every`,
/// which includes the last step, or `output.steps`).
pub(super) fn wants_snapshot(scene: &Scene, step: usize, last: bool) -> bool {
    scene.output.every.is_some_and(|e| step % e == 0 || last) || scene.output.steps.contains(&step)
}

/// Reaction of every set, `Σ R` over its prescribed components, from the
/// support force `R = m a − (F_int + f_ext)` of each.
pub(super) fn set_sums(constrained: &[Constrained], sets: usize, support: &[f64]) -> Vec<[f64; 3]> {
    let mut r = vec![[0.0; 3]; sets];
    for (c, s) in constrained.iter().zip(support) {
        r[c.set as usize][c.component as usize] += s;
    }
    r
}

/// Displacement, velocity and damage of each probe point.
pub(super) fn probe_values(
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
