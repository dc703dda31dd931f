//! A body discretised over the processes of a distributed run: each process
//! searches the bonds of its own points and of the layer around them that
//! its own rows of `K` and its own points' forces need, not the whole body's.
//!
//! Let `R = max δ + the partial-volume reach of the largest spacing`, the
//! longest bond the scene can have. Row `p` of the tangent (and the internal
//! force on `p`) sums the terms of every owner `o` with `p ∈ {o} ∪ H_o`
//! (`assembly::stiffness`: an owner's family terms reach the owner and its
//! family), all within `R` of `p`, each needing `o`'s complete family. So a
//! static solve searches the families of the points within one bond length
//! of its own points: its own rows of `K` (in the columns of its own and
//! ghost points), the right-hand side, reactions, recovered stresses and
//! counts of bonds of its own points are then complete; the other rows of
//! its ghost columns are not, and nothing reads them. An explicit run
//! evaluates the same terms with the displacements of the owners' families:
//! within `R` of an own point for the bond-based pair forces, `2R` for the
//! shear model's owner kinematics and `3R` for its breakage test (a bond
//! `o → j` breaks in compression only if neither `θ_o` nor `θ_j` is
//! positive, and `θ_j` reads `j`'s family); these are the ghost points whose
//! displacements it receives each step ([`Halo`]), so the shear model's
//! explicit run searches three bond lengths deep. Points themselves
//! (coordinates, volumes, horizons) stay on every process: the parts are cut
//! from them ([`parts`]) before any bond is searched. The fracture driver
//! decides every bond on every process, so a fracture scene searches them
//! all and shares only the parts.
//!
//! What is global is made so by collective calls (`crate::processes`): the count
//! of bonds touching a point is complete for own points only, so isolated
//! points are decided by each point's process and agreed by a sum.

use super::Points;
use crate::error::{Error, NumericalError};
use crate::processes::Processes;
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

/// The exchange of the ghost points' values each step of a distributed
/// explicit run: every process sends the values of its own points whose
/// families another process holds (`Share::searched`), and receives the
/// values of the points whose families it holds but another process owns.
/// Built once (the processes tell each other which points they need).
#[derive(Debug, Clone, PartialEq)]
pub struct Halo {
    /// Per process: the own points whose values it receives from this one, in order.
    send: Vec<Vec<usize>>,
    /// Per process: the points of it whose values this one receives, in order.
    receive: Vec<Vec<usize>>,
}

impl Halo {
    /// The halo of `share`: the points this process holds the families of
    /// but does not own, from their processes (a collective call).
    pub fn new(share: &Share, processes: &dyn Processes) -> Self {
        let mut receive = vec![Vec::new(); share.processes as usize];
        for (i, &p) in share.part.iter().enumerate() {
            if share.searched[i] && p != share.rank {
                receive[p as usize].push(i);
            }
        }
        let asked: Vec<Vec<f64>> = receive
            .iter()
            .map(|points| points.iter().map(|&i| i as f64).collect())
            .collect();
        let send = processes
            .all_to_all(&asked)
            .into_iter()
            .map(|points| points.into_iter().map(|i| i as usize).collect())
            .collect();
        Halo { send, receive }
    }

    /// Overwrites the ghost points' `values` with their processes' (a
    /// collective call).
    pub fn exchange(&self, processes: &dyn Processes, values: &mut [[f64; 3]]) {
        let send: Vec<Vec<f64>> = self
            .send
            .iter()
            .map(|points| points.iter().flat_map(|&i| values[i]).collect())
            .collect();
        for (points, received) in self.receive.iter().zip(processes.all_to_all(&send)) {
            for (&i, value) in points.iter().zip(received.chunks_exact(3)) {
                values[i].copy_from_slice(value);
            }
        }
    }
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
    /// Whether every bond was searched (a fracture scene): the process
    /// holds the whole body's bonds, and its answers are the whole body's.
    pub every_bond: bool,
    /// The points whose bonds (their families) this process holds: its own
    /// and those within the depth its columns of `K` need (module docs);
    /// every point when the driver needs every bond (fracture).
    pub searched: Vec<bool>,
}

impl Share {
    /// The share of this process among `points` (with `free` components
    /// each): its part ([`parts`]) and the points within `depth` bond lengths
    /// of it (`reach`: the largest partial-volume reach beyond a horizon;
    /// module docs), or every point (`depth` `None`).
    pub fn new(
        processes: &dyn Processes,
        points: &Points,
        free: &[usize],
        d: usize,
        depth: Option<f64>,
        reach: f64,
    ) -> Result<Self, Error> {
        let part = parts(points, free, d, processes.size())?;
        let rank = processes.rank() as u32;
        let own: Vec<bool> = part.iter().map(|&p| p == rank).collect();
        let bond = points.horizon.iter().copied().fold(0.0, f64::max) + reach;
        // A bond is strictly shorter than δ_i + r_j (or at most δ_i): a margin
        // of round-off keeps a point at exactly that distance.
        let searched = match (depth, d) {
            (None, _) => vec![true; points.len()],
            (Some(depth), 1) => within::<1>(points, &own, depth * bond * (1.0 + 1e-9))?,
            (Some(depth), 2) => within::<2>(points, &own, depth * bond * (1.0 + 1e-9))?,
            (Some(depth), _) => within::<3>(points, &own, depth * bond * (1.0 + 1e-9))?,
        };
        Ok(Share {
            part,
            rank,
            processes: processes.size() as u32,
            every_bond: depth.is_none(),
            searched,
        })
    }

    /// The bond lengths around its own points whose families a process
    /// searches for a scene (module docs): one for a static solve and the
    /// bond-based model's explicit run, three for the shear model's; every
    /// point's (`None`) for fracture.
    pub fn depth(scene: &crate::scene::Scene) -> Option<f64> {
        match (&scene.quasi_static, &scene.dynamics, scene.model.kind) {
            (Some(_), _, _) => None,
            (None, Some(_), ModelKind::Shear) => Some(3.0),
            _ => Some(1.0),
        }
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
/// within its horizon, itself included: its entries of `K` for the
/// bond-based model with equal horizons, and in proportion to them for the
/// shear model (whose rows reach two horizons).
fn row_lengths<const K: usize>(points: &Points, free: &[usize]) -> Result<Vec<f64>, Error> {
    let coords: Vec<[f64; K]> = points
        .x
        .iter()
        .map(|x| std::array::from_fn(|a| x[a]))
        .collect();
    let tree: ImmutableKdTree<f64, K> = ImmutableKdTree::new_from_slice(&coords).map_err(|e| {
        NumericalError::Solver(format!("cannot build the points' search tree: {e:?}"))
    })?;
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
fn within<const K: usize>(points: &Points, own: &[bool], radius: f64) -> Result<Vec<bool>, Error> {
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
