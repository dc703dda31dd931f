//! The answers of a body discretised over several processes, each process
//! holding only some bonds (`Discretization::partial_share`), made the whole
//! body's: sums over the processes of what each counts for its own points
//! (bonds, bonds per point, reactions, stresses). On one process, or where
//! every process holds every bond, the values stay as they are.

use crate::discretization::Discretization;

/// The sum of every entry of `values` over the processes of a body
/// discretised over several ([`Discretization::partial_share`]: each process's own points'
/// share of a sum), in place; on one process they stay as they are.
pub fn sum_shares(disc: &Discretization, values: &mut [f64]) {
    #[cfg(feature = "mpi")]
    if disc.partial_share().is_some() {
        crate::solve::petsc::sum_each_over_processes(values);
    }
    let _ = (disc, values);
}

/// The bonds of the whole body (summed over the processes of a body
/// discretised over several: each counts its own points' families).
pub fn total_bonds(disc: &Discretization) -> usize {
    if disc.partial_share().is_none() {
        return disc.bonds.len();
    }
    let own: usize = (0..disc.points.len())
        .filter(|&i| disc.reports(i))
        .map(|i| disc.bonds.owned_by(i).len())
        .sum();
    let mut total = [own as f64];
    sum_shares(disc, &mut total);
    total[0] as usize
}

/// The bonds each process holds, when the body is discretised over several
/// (its own points' families and those of the layers around them: a
/// collective call).
pub fn bonds_held(disc: &Discretization) -> Option<Vec<usize>> {
    let share = disc.partial_share()?;
    let mut held = vec![0.0; share.processes as usize];
    held[share.rank as usize] = disc.bonds.len() as f64;
    sum_shares(disc, &mut held);
    Some(held.iter().map(|&b| b as usize).collect())
}

/// The intact bonds touching each point, as owner or as neighbour (on a body
/// discretised over several processes, each counts its own points' and the
/// counts are summed: a collective call).
pub fn bond_counts(disc: &Discretization) -> Vec<u32> {
    let n = disc.points.len();
    let counts = disc.bonds.touch_counts(n);
    if disc.partial_share().is_none() {
        return counts;
    }
    let mut mine: Vec<f64> = (0..n)
        .map(|i| {
            if disc.reports(i) {
                f64::from(counts[i])
            } else {
                0.0
            }
        })
        .collect();
    sum_shares(disc, &mut mine);
    mine.iter().map(|&c| c as u32).collect()
}
