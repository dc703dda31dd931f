//! A body discretised over the processes of a distributed run: each process
//! searches the bonds of its own points and of the layer around them that
//! its rows of `K` need, not the whole body's.
//!
//! Column `q` of the tangent (`assembly::stiffness`) sums the terms of `q`'s
//! own family and of every owner whose family holds `q` (its dual horizon):
//! it needs the complete families of `q` and of the owners within one bond
//! length `R` of it (`R = max δ + the partial-volume reach of the largest
//! spacing`, the longest bond the scene can have). A process assembles the
//! columns of its own points and of their ghost points (those coupled to them:
//! within `R` for the bond-based model, `2R` for the shear model, whose owner
//! couples every pair of its family), so it searches the families of every
//! point within `2R` (bond-based) or `3R` (shear) of its own points. The
//! internal force and stress of an own point, and its count of bonds, need
//! less. Points themselves (coordinates, volumes, horizons) stay on every
//! process: the parts are cut from them ([`parts`]) before any bond is
//! searched. The fracture driver decides every bond on every process, so a
//! fracture scene searches them all and shares only the parts.
//!
//! What is global is made so by collective calls ([`Processes`]): the count
//! of bonds touching a point is complete for own points only, so isolated
//! points are decided by each point's process and agreed by a sum.

use super::Points;
use crate::error::{Error, NumericalError};
use crate::scene::ModelKind;
use kiddo::{ImmutableKdTree, SquaredEuclidean};
use rayon::prelude::*;

/// A body to discretise over several processes: the processes, and the free
/// components of every point of a body without bonds yet (its degrees of
/// freedom: the rows of `K` it has), by which the parts are balanced.
pub struct Distribution<'a> {
    /// The processes of the run.
    pub processes: &'a dyn Processes,
    /// The free components of every point of a body (bonds not searched).
    pub free_components: &'a dyn Fn(&super::Discretization) -> Result<Vec<usize>, Error>,
}

/// The processes of a distributed run as the discretisation sees them (the
/// MPI build gives them): their number, this one's rank and the collective
/// calls that make local answers global. Every process calls every method in
/// the same order.
pub trait Processes {
    /// The number of processes.
    fn size(&self) -> usize;
    /// This process's rank.
    fn rank(&self) -> usize;
    /// Every entry of `values` summed over the processes, in place.
    fn sum(&self, values: &mut [f64]);
    /// Every entry of `values` the least over the processes, in place.
    fn min(&self, values: &mut [f64]);
}

/// This process's share of a body discretised over several processes.
#[derive(Debug, Clone, PartialEq)]
pub struct Share {
    /// The process (part) of every point ([`parts`]): the same on every process.
    pub part: Vec<u32>,
    /// This process's rank.
    pub rank: u32,
    /// The number of processes.
    pub processes: u32,
    /// The points whose bonds (their families) this process holds: its own
    /// and those within the depth its columns of `K` need (module docs);
    /// every point when the driver needs every bond (fracture).
    pub searched: Vec<bool>,
}

impl Share {
    /// The share of this process among `points` (with `free` components
    /// each): its part ([`parts`]) and the points within `depth` bond lengths
    /// of it (`reach`: the largest partial-volume reach beyond a horizon), or
    /// every point with `every_bond`.
    pub fn new(
        processes: &dyn Processes,
        points: &Points,
        free: &[usize],
        d: usize,
        kind: ModelKind,
        reach: f64,
        every_bond: bool,
    ) -> Result<Self, Error> {
        let part = parts(points, free, d, processes.size())?;
        let rank = processes.rank() as u32;
        let own: Vec<bool> = part.iter().map(|&p| p == rank).collect();
        let bond = points.horizon.iter().copied().fold(0.0, f64::max) + reach;
        let depth = match kind {
            ModelKind::BondBased => 2.0,
            ModelKind::Shear => 3.0,
        };
        // A bond is strictly shorter than δ_i + r_j (or at most δ_i): a margin
        // of round-off keeps a point at exactly that distance.
        let radius = depth * bond * (1.0 + 1e-9);
        let searched = match (every_bond, d) {
            (true, _) => vec![true; points.len()],
            (false, 1) => within::<1>(points, &own, radius)?,
            (false, 2) => within::<2>(points, &own, radius)?,
            (false, _) => within::<3>(points, &own, radius)?,
        };
        Ok(Share {
            part,
            rank,
            processes: processes.size() as u32,
            searched,
        })
    }

    /// Whether `i` is one of this process's points.
    pub fn owns(&self, i: usize) -> bool {
        self.part[i] == self.rank
    }

    /// Whether this process holds the family of `i`.
    pub fn holds(&self, i: usize) -> bool {
        self.searched[i]
    }
}

/// The process of every point: the points split into `processes` parts of
/// about equal work by recursive coordinate bisection ([`bisect`]), each
/// point weighted by its `free` components times those of the points within
/// its horizon (its rows of `K` and their length, shorter at a surface or a
/// support). From the points alone, so that a process knows its part before
/// any bond is searched.
pub fn parts(
    points: &Points,
    free: &[usize],
    d: usize,
    processes: usize,
) -> Result<Vec<u32>, Error> {
    let weight = match d {
        1 => row_lengths::<1>(points, free)?,
        2 => row_lengths::<2>(points, free)?,
        _ => row_lengths::<3>(points, free)?,
    };
    let mut order: Vec<usize> = (0..points.len()).collect();
    let mut sizes = Vec::with_capacity(processes);
    bisect(&mut order, &weight, &points.x, processes.max(1), &mut sizes);
    let mut part = vec![0u32; points.len()];
    let mut start = 0;
    for (p, size) in sizes.into_iter().enumerate() {
        order[start..start + size]
            .iter()
            .for_each(|&i| part[i] = p as u32);
        start += size;
    }
    Ok(part)
}

/// Each point's `free` components times the free components of the points
/// within its horizon, itself included: its entries of `K` when the horizons
/// are equal.
fn row_lengths<const K: usize>(points: &Points, free: &[usize]) -> Result<Vec<f64>, Error> {
    let coords: Vec<[f64; K]> = points
        .x
        .iter()
        .map(|x| std::array::from_fn(|a| x[a]))
        .collect();
    let tree: ImmutableKdTree<f64, K> = ImmutableKdTree::new_from_slice(&coords)
        .map_err(|e| NumericalError::Solver(format!("cannot build the points' search tree: {e:?}")))?;
    Ok(coords
        .par_iter()
        .enumerate()
        .map(|(i, x)| {
            if free[i] == 0 {
                return 0.0;
            }
            let delta = points.horizon[i];
            let coupled: usize = tree
                .query(x)
                .within::<SquaredEuclidean<f64>>(delta * delta)
                .unsorted()
                .execute()
                .iter()
                .map(|n| free[n.item as usize])
                .sum();
            (free[i] * coupled) as f64
        })
        .collect())
}

/// Splits `points` into `parts` parts of about equal `weight` (by point) by
/// recursive coordinate bisection: the longest side of their bounding box is
/// cut where the weight below reaches the share of the parts on that side
/// (`⌊parts/2⌋` of `parts`), ties in the coordinate broken by the point's
/// index, so that every process finds the same parts. The parts end up in
/// turn in `points`, their sizes pushed to `sizes`. A cut across the body's
/// longest side is the smallest of the straight cuts of a box, and with it
/// the ghost layer of each process.
fn bisect(
    points: &mut [usize],
    weight: &[f64],
    x: &[[f64; 3]],
    parts: usize,
    sizes: &mut Vec<usize>,
) {
    if parts == 1 {
        sizes.push(points.len());
        return;
    }
    let extent = |axis: usize| {
        let (low, high) = points
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &i| {
                (l.min(x[i][axis]), h.max(x[i][axis]))
            });
        high - low
    };
    let axis = (0..3)
        .max_by(|&a, &b| extent(a).total_cmp(&extent(b)).then(b.cmp(&a)))
        .expect("three axes");
    points.sort_unstable_by(|&i, &j| x[i][axis].total_cmp(&x[j][axis]).then(i.cmp(&j)));
    let lower = parts / 2;
    let total: f64 = points.iter().map(|&i| weight[i]).sum();
    let mut below = 0.0;
    let mut cut = points.len();
    for (m, &i) in points.iter().enumerate() {
        if below * parts as f64 >= total * lower as f64 {
            cut = m;
            break;
        }
        below += weight[i];
    }
    let (low, high) = points.split_at_mut(cut);
    bisect(low, weight, x, lower, sizes);
    bisect(high, weight, x, parts - lower, sizes);
}

/// Whether each point lies within `radius` of a point that `own` flags.
fn within<const K: usize>(
    points: &Points,
    own: &[bool],
    radius: f64,
) -> Result<Vec<bool>, Error> {
    let coords = |i: usize| -> [f64; K] { std::array::from_fn(|a| points.x[i][a]) };
    let mine: Vec<[f64; K]> = (0..points.len()).filter(|&i| own[i]).map(coords).collect();
    if mine.is_empty() {
        return Ok(vec![false; points.len()]);
    }
    let tree: ImmutableKdTree<f64, K> = ImmutableKdTree::new_from_slice(&mine).map_err(|e| {
        NumericalError::Solver(format!(
            "cannot build the search tree of this process's points: {e:?}"
        ))
    })?;
    let r2 = radius * radius;
    Ok((0..points.len())
        .into_par_iter()
        .map(|i| {
            own[i]
                || tree
                    .query(&coords(i))
                    .nearest_one::<SquaredEuclidean<f64>>()
                    .execute()
                    .distance
                    <= r2
        })
        .collect())
}

/// `result` on this process, unless another failed: then an error here too
/// (a collective call: no process goes on alone into the next collective).
pub fn agreed<T>(processes: Option<&dyn Processes>, result: Result<T, Error>) -> Result<T, Error> {
    let Some(processes) = processes else {
        return result;
    };
    let mut failed = [f64::from(u8::from(result.is_err()))];
    processes.sum(&mut failed);
    match result {
        Ok(_) if failed[0] > 0.0 => Err(NumericalError::Solver(format!(
            "{} other process(es) of this MPI run stopped with an error (printed by their rank)",
            failed[0]
        ))
        .into()),
        result => result,
    }
}
