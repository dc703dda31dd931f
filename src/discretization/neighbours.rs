//! Neighbour search with a k-d tree (kiddo), one radius query per point in parallel.

use super::partial_volume::PartialVolume;
use super::{Bonds, Points};
use crate::error::{Error, InputError};
use crate::geometry::crosses;
use crate::memory::{check_memory, memory_limit};
use crate::scene::{Crack, VolumeCorrection};
use crate::vector::{norm, sub};
use kiddo::{ImmutableKdTree, SquaredEuclidean};
use rayon::prelude::*;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Bytes a bond costs while the bonds are found: the stored neighbour (4),
/// partial-volume factor (8) and intact flag (1), and the per-owner list the
/// search builds them in (16).
pub const BYTES_PER_BOND: f64 = 29.0;

/// Finds every bond `i → j` with a positive partial-volume factor (for the
/// `overlap` rule: `|x_j − x_i| < δ_i + r_j`, otherwise `≤ δ_i`) that crosses no
/// crack; each owner's bonds are sorted by neighbour index.
///
/// Memory is checked before it is used (`solver.memory_limit_gib` or 90 % of
/// the available memory): first against an estimate of the bonds from each
/// point's horizon and spacing, then, during the search, against the bonds
/// found so far, so a horizon that bonds far more points than the estimate
/// (a coarse horizon over a fine region) is refused before the lists grow.
///
/// With `searched`, only the families of the points it flags are searched
/// (a process's share of a distributed body); the others are left empty.
pub fn find_bonds(
    points: &Points,
    d: usize,
    cracks: &[Crack],
    rule: VolumeCorrection,
    user_memory_limit: Option<f64>,
    searched: Option<&[bool]>,
) -> Result<Bonds, Error> {
    let pv = PartialVolume { rule, d };
    let estimate = estimated_bonds(points, d, pv, searched);
    check_memory(
        || {
            format!(
                "the bonds (an estimated {estimate:.3e} from the horizons and spacings, {:.0} per \
                 point)",
                estimate / searched_count(points.len(), searched) as f64
            )
        },
        estimate * BYTES_PER_BOND,
        user_memory_limit,
    )?;
    let limit = memory_limit(user_memory_limit).map(|(bytes, _)| bytes);
    let budget = Budget {
        max_bonds: limit.map_or(usize::MAX, |b| (b / BYTES_PER_BOND) as usize),
        user_memory_limit,
        points: points.len(),
        found: AtomicUsize::new(0),
    };
    let families = match d {
        1 => families::<1>(points, cracks, pv, &budget, searched),
        2 => families::<2>(points, cracks, pv, &budget, searched),
        _ => families::<3>(points, cracks, pv, &budget, searched),
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
        intact: vec![true; total],
        neighbour,
        volume_factor,
        in_offsets: Vec::new(),
        in_bonds: Vec::new(),
    })
}

/// Expected number of bonds: each point's ball of radius `δ_i + reach`
/// filled at its own spacing (boundaries ignored, so an over-estimate on
/// uniform grids; a coarse horizon over finer points is caught by the count).
fn estimated_bonds(points: &Points, d: usize, pv: PartialVolume, searched: Option<&[bool]>) -> f64 {
    let ball = match d {
        1 => 2.0,
        2 => std::f64::consts::PI,
        _ => 4.0 / 3.0 * std::f64::consts::PI,
    };
    (0..points.len())
        .filter(|&i| searched.is_none_or(|s| s[i]))
        .map(|i| {
            let h = points.spacing[i];
            ball * ((points.horizon[i] + pv.reach(h)) / h).powi(d as i32)
        })
        .sum()
}

/// The number of points whose families are searched.
fn searched_count(n: usize, searched: Option<&[bool]>) -> usize {
    searched
        .map_or(n, |s| s.iter().filter(|&&f| f).count())
        .max(1)
}

/// The running count of bonds found against the memory limit.
struct Budget {
    max_bonds: usize,
    user_memory_limit: Option<f64>,
    points: usize,
    found: AtomicUsize,
}

impl Budget {
    /// Adds `bonds` to the count; refuses once the count exceeds the limit.
    fn charge(&self, bonds: usize) -> Result<(), Error> {
        let total = self.found.fetch_add(bonds, Ordering::Relaxed) + bonds;
        if total <= self.max_bonds {
            return Ok(());
        }
        check_memory(
            || {
                format!(
                    "the bonds (more than {total} found before the search over {} points ended)",
                    self.points
                )
            },
            total as f64 * BYTES_PER_BOND,
            self.user_memory_limit,
        )?;
        Ok(())
    }
}

type Family = Vec<(u32, f64)>;

/// Distance, relative to the spacing, below which two points are duplicates to
/// round-off: the stretch of a bond between them has no meaningful direction.
const NEAR_DUPLICATE: f64 = 1e-9;

/// The error for points `i` and `j` closer than [`NEAR_DUPLICATE`] spacings:
/// names where both come from (a region, a point-file line, a mesh element)
/// and their distance (exact duplicates are refused before the search).
fn near_duplicate(points: &Points, i: usize, j: usize) -> InputError {
    let (a, b) = (i.min(j), i.max(j));
    let distance = crate::vector::magnitude(&sub(&points.x[b], &points.x[a]));
    InputError::new(
        points.source[b].to_string(),
        format!(
            "the point at {:?} lies {distance:.3e} m from the point of {} at {:?}, within \
             {NEAR_DUPLICATE:e} of the spacing {:.3e} m: the two are duplicates to round-off \
             (a bond between them has no direction); remove one or move it",
            points.x[b], points.source[a], points.x[a], points.spacing[i]
        ),
    )
}

fn families<const K: usize>(
    points: &Points,
    cracks: &[Crack],
    pv: PartialVolume,
    budget: &Budget,
    searched: Option<&[bool]>,
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
            if searched.is_some_and(|s| !s[i]) {
                return Ok(Vec::new());
            }
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
                if r <= NEAR_DUPLICATE * points.spacing[i] {
                    return Err(near_duplicate(points, i, j).into());
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
            budget.charge(family.len())?;
            family.sort_unstable_by_key(|&(j, _)| j);
            Ok(family)
        })
        .collect()
}
