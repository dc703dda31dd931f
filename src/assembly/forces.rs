//! Matrix-free internal forces from the same bond kernels as the stiffness.
//!
//! `F_int,i = Σ_{b owned by i} f_b − Σ_{b ending at i} f_b`, where `f_b` is the
//! force bond `b` puts on its owner (formulation Sec. 2).

use super::split_at_offsets;
use crate::discretization::Discretization;
use crate::model::Model;
use rayon::prelude::*;

/// Internal force on every point for displacements `u`; `linear` selects the
/// linearised kernel (then `F_int = −K u`).
pub fn internal_forces<M: Model>(
    model: &M,
    disc: &Discretization,
    u: &[[f64; 3]],
    linear: bool,
) -> Vec<[f64; 3]> {
    let bonds = &disc.bonds;
    let mut bond_force = vec![[0.0; 3]; bonds.len()];
    split_at_offsets(&mut bond_force, &bonds.offsets)
        .into_par_iter()
        .enumerate()
        .for_each(|(i, out)| model.owner_forces(disc, i, u, linear, out));
    let mut f = vec![[0.0; 3]; disc.points.len()];
    for i in 0..disc.points.len() {
        for b in bonds.owned_by(i) {
            let j = bonds.neighbour[b] as usize;
            for c in 0..3 {
                f[i][c] += bond_force[b][c];
                f[j][c] -= bond_force[b][c];
            }
        }
    }
    f
}
