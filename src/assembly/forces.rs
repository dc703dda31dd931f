//! Matrix-free internal forces from the same bond kernels as the stiffness.
//!
//! `F_int,i = Σ_{b owned by i} f_b − Σ_{b ending at i} f_b`, where `f_b` is the
//! force bond `b` puts on its owner (formulation Sec. 2).

use crate::csr::split_at_offsets;
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

/// Internal force on each of `points` only, for displacements `u`: the forces
/// of the bonds owned by those points and of the bonds ending at them. Costs
/// the families of those owners, each computed once, not the whole body.
pub fn internal_forces_on<M: Model>(
    model: &M,
    disc: &Discretization,
    u: &[[f64; 3]],
    linear: bool,
    points: &[usize],
) -> Vec<[f64; 3]> {
    let bonds = &disc.bonds;
    let incoming = |q: usize| bonds.incoming(q);
    let mut owners: Vec<usize> = points.to_vec();
    for &q in points {
        owners.extend(incoming(q).iter().map(|&(o, _)| o as usize));
    }
    owners.sort_unstable();
    owners.dedup();
    let forces: Vec<Vec<[f64; 3]>> = owners
        .par_iter()
        .map(|&o| {
            let mut out = vec![[0.0; 3]; bonds.owned_by(o).len()];
            model.owner_forces(disc, o, u, linear, &mut out);
            out
        })
        .collect();
    let of = |o: usize| &forces[owners.binary_search(&o).expect("owner computed")];
    points
        .iter()
        .map(|&q| {
            let mut f = [0.0; 3];
            for force in of(q) {
                (0..3).for_each(|c| f[c] += force[c]);
            }
            for &(o, b) in incoming(q) {
                let force = of(o as usize)[b as usize - bonds.offsets[o as usize]];
                (0..3).for_each(|c| f[c] -= force[c]);
            }
            f
        })
        .collect()
}
