//! Neighbour search with a k-d tree (kiddo), one radius query per point in parallel.

use super::{Bonds, Points};
use crate::error::{Error, InputError};
use crate::geometry::{crosses, norm, sub};
use crate::scene::Crack;
use kiddo::{ImmutableKdTree, SquaredEuclidean};
use rayon::prelude::*;

/// Finds every bond `i → j` with `|x_j − x_i| ≤ δ_i` that crosses no crack, with
/// its partial-volume factor; each owner's bonds are sorted by neighbour index.
pub fn find_bonds(
    points: &Points,
    d: usize,
    cracks: &[Crack],
    volume_correction: bool,
) -> Result<Bonds, Error> {
    let families = match d {
        1 => families::<1>(points, cracks, volume_correction),
        2 => families::<2>(points, cracks, volume_correction),
        _ => families::<3>(points, cracks, volume_correction),
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
    volume_correction: bool,
) -> Result<Vec<Family>, Error> {
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
            let found = tree
                .query(xi)
                .within::<SquaredEuclidean<f64>>(delta * delta)
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
                if r > delta
                    || cracks
                        .iter()
                        .any(|c| crosses(c, &points.x[i], &points.x[j]))
                {
                    continue;
                }
                let factor = if volume_correction {
                    partial_volume(r, delta, 0.5 * points.spacing[j])
                } else {
                    1.0
                };
                if factor > 0.0 {
                    family.push((j as u32, factor));
                }
            }
            family.sort_unstable_by_key(|&(j, _)| j);
            Ok(family)
        })
        .collect()
}

/// Partial-volume factor of 000 Eq. (A.1): 1 inside `δ − r_j`, a linear ramp from
/// 1 to 1/2 up to `δ`, 0 beyond.
pub fn partial_volume(distance: f64, horizon: f64, half_spacing: f64) -> f64 {
    if distance <= horizon - half_spacing {
        1.0
    } else if distance <= horizon {
        (horizon + half_spacing - distance) / (2.0 * half_spacing)
    } else {
        0.0
    }
}
