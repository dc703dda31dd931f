//! Neighbour search with a k-d tree (kiddo), one radius query per point in parallel.

use super::partial_volume::PartialVolume;
use super::{Bonds, Points};
use crate::error::{Error, InputError};
use crate::geometry::{crosses, norm, sub};
use crate::scene::{Crack, VolumeCorrection};
use kiddo::{ImmutableKdTree, SquaredEuclidean};
use rayon::prelude::*;

/// Finds every bond `i → j` with a positive partial-volume factor (for the
/// `overlap` rule: `|x_j − x_i| < δ_i + r_j`, otherwise `≤ δ_i`) that crosses no
/// crack; each owner's bonds are sorted by neighbour index.
pub fn find_bonds(
    points: &Points,
    d: usize,
    cracks: &[Crack],
    rule: VolumeCorrection,
) -> Result<Bonds, Error> {
    let pv = PartialVolume { rule, d };
    let families = match d {
        1 => families::<1>(points, cracks, pv),
        2 => families::<2>(points, cracks, pv),
        _ => families::<3>(points, cracks, pv),
    }?;
    let mut offsets = Vec::with_capacity(points.len() + 1);
    offsets.push(0);
    let total: usize = families.iter().map(Vec::len).sum();
    let mut neighbour = Vec::with_capacity(total);
    let mut volume_factor = Vec::with_capacity(total);
    for family in families {
        for (j, f) in family {
            neighbour.push(j);
            volume_factor.push(f);
        }
        offsets.push(neighbour.len());
    }
    Ok(Bonds {
        offsets,
        intact: vec![true; neighbour.len()],
        neighbour,
        volume_factor,
    })
}

type Family = Vec<(u32, f64)>;

fn families<const K: usize>(
    points: &Points,
    cracks: &[Crack],
    pv: PartialVolume,
) -> Result<Vec<Family>, Error> {
    let reach = points
        .spacing
        .iter()
        .map(|&h| pv.reach(h))
        .fold(0.0, f64::max);
    let coords: Vec<[f64; K]> = points
        .x
        .iter()
        .map(|x| std::array::from_fn(|a| x[a]))
        .collect();
    let tree: ImmutableKdTree<f64, K> = ImmutableKdTree::new_from_slice(&coords).map_err(|e| {
        InputError::new(
            "points",
            format!("cannot build the neighbour search tree: {e:?}"),
        )
    })?;
    coords
        .par_iter()
        .enumerate()
        .map(|(i, xi)| {
            let delta = points.horizon[i];
            let radius = delta + reach;
            let found = tree
                .query(xi)
                .within::<SquaredEuclidean<f64>>(radius * radius)
                .unsorted()
                .execute();
            let mut family: Family = Vec::with_capacity(found.len());
            for item in found {
                let j = item.item as usize;
                if j == i {
                    continue;
                }
                let r = norm(&sub(&points.x[j], &points.x[i]));
                if r <= 1e-9 * points.spacing[i] {
                    return Err(InputError::new(
                        "points",
                        format!(
                            "points {i} and {j} coincide at {:?}; remove duplicates",
                            points.x[i]
                        ),
                    )
                    .into());
                }
                let factor = pv.factor(r, delta, points.spacing[j]);
                if factor > 0.0
                    && !cracks
                        .iter()
                        .any(|c| crosses(c, &points.x[i], &points.x[j]))
                {
                    family.push((j as u32, factor));
                }
            }
            family.sort_unstable_by_key(|&(j, _)| j);
            Ok(family)
        })
        .collect()
}
