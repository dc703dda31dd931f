//! The recovered stress of every point (`output.stress`), the same for the
//! static, quasi-static and explicit drivers: each model's own definition
//! ([`crate::model::Model::stress`]; bond-based: the flux of the owner's bonds,
//! `model::bond_based`; shear: 001 Eq. 32 or the energy formulation's Hooke
//! stress, `model::shear`), linearised about the reference configuration.

use super::shares::sum_shares;
use crate::discretization::Discretization;
use crate::error::{Error, NumericalError};
use crate::model::{Block, Model};

/// Every point's stress for displacements `u`, refused (naming the point) if
/// one is not finite. On a body discretised over several processes each
/// recovers its own points' and the processes' fields are summed: a
/// collective call, and every process then refuses or accepts the same field.
pub(crate) fn field<M: Model + Sync>(
    model: &M,
    disc: &Discretization,
    u: &[[f64; 3]],
) -> Result<Vec<Block>, Error> {
    use rayon::prelude::*;
    let mut stress: Vec<Block> = (0..disc.points.len())
        .into_par_iter()
        .map(|i| match disc.reports(i) {
            true => model.stress(disc, i, u).unwrap_or_default(),
            false => Block::default(),
        })
        .collect();
    if disc.partial_share().is_some() {
        let mut flat: Vec<f64> = stress.iter().flatten().flatten().copied().collect();
        sum_shares(disc, &mut flat);
        for (block, values) in stress.iter_mut().zip(flat.chunks(9)) {
            for (r, row) in block.iter_mut().enumerate() {
                row.copy_from_slice(&values[3 * r..3 * r + 3]);
            }
        }
    }
    match stress
        .iter()
        .position(|b| b.iter().flatten().any(|v| !v.is_finite()))
    {
        Some(i) => Err(NumericalError::NonFinite {
            what: format!(
                "the recovered stress of point {i} (x = {:?}); nothing was written",
                disc.points.x[i]
            ),
        }
        .into()),
        None => Ok(stress),
    }
}
