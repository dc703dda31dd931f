//! Internal forces for the explicit driver, from the same bond kernels as the
//! implicit path, in parallel without races and without per-step allocation
//! of force arrays.
//!
//! Three force fields:
//!
//! - [`PairKernel`] (bond-based), pair by pair. Bond `i→j` puts `+w_ij s n` on
//!   `i` and bond `j→i` puts `−w_ji s n_ji = +w_ji s n` on `i` (formulation Sec.
//!   2-3): the two bonds of a pair share the stretch `s` and direction `n`, so the
//!   pair acts on `i` with `W s n` and on `j` with `−W s n`, `W = w_ij + w_ji`
//!   (each term only while its bond is intact; `w = C_owner V_i V_j ν`). Each pair
//!   is evaluated once, in the row of its smaller index, and its force added to
//!   both points in the buffer of a fixed block of rows (no two threads write the
//!   same memory); the buffers are summed in a fixed order, so the result does
//!   not depend on the number of threads. The stretch is
//!   `s = (2 ξ·η + η·η) / ((|ξ+η| + |ξ|) |ξ|)`, equal to `(|ξ+η| − |ξ|)/|ξ|`
//!   without its cancellation at small strain. With `traditional` horizons a
//!   point feels only the bonds in its own horizon, `W = 2 w_ij` (the
//!   constant-horizon micromodulus; ghost forces where horizons differ), and
//!   gathers over them.
//! - [`FamilyKernel`] (any model, here the shear model): each owner's bond forces
//!   ([`Model::owner_forces`], nonlinear with the polar rotation) into a per-bond
//!   buffer, then each point sums its own bonds and subtracts the bonds ending at it.
//! - [`TangentKernel`]: `F = −K u` with the assembled tangent of the implicit
//!   solver on every degree of freedom, for the linearised run `M ü + K u = f`.
//!
//! Bonds break by the criteria of [`crate::damage`] (one implementation for every
//! driver): after a force evaluation, each bond whose value reached its limit is
//! broken and carries no force from the next evaluation on.

use crate::assembly::dofs::DofMap;
use crate::assembly::pattern::Pattern;
use crate::assembly::stiffness::Stiffness;
use crate::csr::split_at_offsets;
use crate::damage::{self, Criterion};
use crate::discretization::Discretization;
use crate::error::Error;
use crate::model::bond_based::BondBased;
use crate::model::{Block as Tensor, Model};
use rayon::prelude::*;

/// Whether the bonds owned by point `i` are counted here (energies, breaks):
/// every point's on one process, this process's own on several, where the
/// bonds of other points are held to compute the forces on its own.
fn counts(disc: &Discretization, i: usize) -> bool {
    disc.reports(i)
}

/// What a force evaluation broke.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Breaks {
    /// Bonds broken.
    pub bonds: usize,
    /// Energy the broken bonds stored when they broke, when the model defines it.
    pub energy: f64,
}

/// A force field of the explicit driver.
pub trait ForceField: Send {
    /// Writes the internal force on every point for displacements `u` into `out`,
    /// then breaks the bonds that reached their limit.
    fn forces(&mut self, u: &[[f64; 3]], out: &mut [[f64; 3]]) -> Breaks;

    /// Stored strain energy for displacements `u`, where the field has one.
    fn strain_energy(&self, u: &[[f64; 3]]) -> Option<f64>;

    /// Points and bonds (with the current intact flags).
    fn disc(&self) -> &Discretization;

    /// Hands the discretisation back at the end of a run.
    fn into_disc(self: Box<Self>) -> Discretization;

    /// Damage of every point.
    fn damage(&self) -> Vec<f64> {
        damage::damage(self.disc())
    }

    /// The vector path of the force loop, where it has a choice.
    fn simd(&self) -> Option<Simd> {
        None
    }

    /// The recovered stress of every point for displacements `u`
    /// (`output.stress`; `drivers::stress`), when the field carries a model
    /// for it; `None` otherwise.
    fn stress(&self, _u: &[[f64; 3]]) -> Option<Result<Vec<Tensor>, Error>> {
        None
    }
}

/// A force field with the model its stress is recovered from: the pair and
/// tangent kernels keep only their per-pair weights or their matrix, and
/// their models do not change during a run (bond-based factors are frozen,
/// a broken bond is an intact flag of the discretisation), so the model built
/// at set-up answers for every state.
pub struct WithStress<M: Model + Sync + Send> {
    /// The force field.
    pub field: Box<dyn ForceField>,
    /// Its model.
    pub model: M,
}

impl<M: Model + Sync + Send> ForceField for WithStress<M> {
    fn forces(&mut self, u: &[[f64; 3]], out: &mut [[f64; 3]]) -> Breaks {
        self.field.forces(u, out)
    }

    fn strain_energy(&self, u: &[[f64; 3]]) -> Option<f64> {
        self.field.strain_energy(u)
    }

    fn disc(&self) -> &Discretization {
        self.field.disc()
    }

    fn into_disc(self: Box<Self>) -> Discretization {
        self.field.into_disc()
    }

    fn damage(&self) -> Vec<f64> {
        self.field.damage()
    }

    fn simd(&self) -> Option<Simd> {
        self.field.simd()
    }

    fn stress(&self, u: &[[f64; 3]]) -> Option<Result<Vec<Tensor>, Error>> {
        Some(crate::drivers::stress::field(
            &self.model,
            self.field.disc(),
            u,
        ))
    }
}

/// The screen's margin: a pair is examined exactly when `num ≥ limit × den × SCREEN`.
const SCREEN: f64 = 1.0 - 1e-12;

/// Marks an entry's directed bond as absent.
const NONE: u32 = u32::MAX;

/// Number of force buffers of the dual-horizon pair loop, fixed so that the
/// sums (and so the results) do not depend on the number of threads.
const BLOCKS: usize = 8;

/// One pair as its row sees it (24 bytes: the only per-bond data read in the
/// force loop; positions and displacements are per point and stay in cache).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Pair {
    /// `W`: force per unit stretch along the current bond direction.
    weight: f64,
    /// `|ξ|` (stored: a square root is the costliest operation of the loop).
    length: f64,
    /// Smallest limit of the pair's intact bonds, rounded down to `f32` (a
    /// screen; the exact comparison follows), ∞ when none may break.
    limit: f32,
    /// The other point.
    neighbour: u32,
}

/// A contiguous range of rows and the forces they produce (dual horizons).
struct Block {
    rows: std::ops::Range<usize>,
    force: Vec<[f64; 3]>,
    flagged: Vec<u32>,
}

/// The bond-based model, pair by pair (module docs).
pub struct PairKernel {
    disc: Discretization,
    start: Vec<usize>,
    pairs: Vec<Pair>,
    /// Per entry: the bond owned by the row's point, or [`NONE`].
    owned: Vec<u32>,
    /// Per entry: the bond owned by the other point, ending at the row's point, or [`NONE`].
    incoming: Vec<u32>,
    /// `w_b` of every directed bond.
    bond_weight: Vec<f64>,
    criterion: Option<Criterion>,
    traditional: bool,
    /// Dual horizons: the blocks of rows. Traditional: one flag per row.
    blocks: Vec<Block>,
    flagged: Vec<bool>,
    /// Vector path of the dual-horizon force loop.
    simd: Simd,
}

/// `(s, y, |y|)` of a pair from `x_i, x_j, u_i, u_j`; bitwise the same both ways.
#[inline(always)]
fn stretch(xi: &[f64; 3], xj: &[f64; 3], ui: &[f64; 3], uj: &[f64; 3]) -> (f64, [f64; 3], f64) {
    let d = [xj[0] - xi[0], xj[1] - xi[1], xj[2] - xi[2]];
    let e = [uj[0] - ui[0], uj[1] - ui[1], uj[2] - ui[2]];
    let y = [d[0] + e[0], d[1] + e[1], d[2] + e[2]];
    let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    let yl = (y[0] * y[0] + y[1] * y[1] + y[2] * y[2]).sqrt();
    let de = d[0] * e[0] + d[1] * e[1] + d[2] * e[2];
    let ee = e[0] * e[0] + e[1] * e[1] + e[2] * e[2];
    ((2.0 * de + ee) / ((yl + l) * l), y, yl)
}

/// The force coefficient `c` (the pair's force on the row's point is `c y`) and
/// whether the pair passes the breakage screen (module docs): `stretch` written
/// out with one division, `s = num/den`, `W s y/|y| = W num/(den |y|) y`.
#[inline(always)]
fn pair_force(
    p: &Pair,
    xi: &[f64; 3],
    xj: &[f64; 3],
    ui: &[f64; 3],
    uj: &[f64; 3],
) -> (f64, [f64; 3], bool) {
    let d = [xj[0] - xi[0], xj[1] - xi[1], xj[2] - xi[2]];
    let e = [uj[0] - ui[0], uj[1] - ui[1], uj[2] - ui[2]];
    let y = [d[0] + e[0], d[1] + e[1], d[2] + e[2]];
    let l = p.length;
    let yl = (y[0] * y[0] + y[1] * y[1] + y[2] * y[2]).sqrt();
    let num =
        2.0 * (d[0] * e[0] + d[1] * e[1] + d[2] * e[2]) + (e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
    let den = (yl + l) * l;
    let over = num >= f64::from(p.limit) * den * SCREEN;
    let c = if yl > 0.0 {
        p.weight * num / (den * yl)
    } else {
        0.0
    };
    (c, y, over)
}

/// Pairs per batch of the dual-horizon force loop: gathered, then their square
/// roots and divisions computed together (in as many lanes as the CPU offers),
/// then scattered.
const BATCH: usize = 32;

/// The vector instructions of the bond-based force loop, chosen at run time:
/// the widest the CPU offers, or a narrower one named by the environment
/// variable `DHPD_SIMD` (`baseline`, `avx2`, `avx512`; for benchmarks). Every
/// path computes the same IEEE operations in the same order (no fused
/// multiply-add), so the forces are bitwise the same on every path.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Simd {
    /// Two lanes (SSE2 on every x86-64; the target's default elsewhere).
    Baseline,
    /// Four lanes (AVX2).
    Avx2,
    /// Eight lanes (AVX-512F).
    Avx512,
}

impl Simd {
    /// The paths this CPU can run, narrowest first.
    pub fn available() -> Vec<Simd> {
        let mut paths = vec![Simd::Baseline];
        #[cfg(target_arch = "x86_64")]
        {
            if std::is_x86_feature_detected!("avx2") {
                paths.push(Simd::Avx2);
            }
            if std::is_x86_feature_detected!("avx512f") {
                paths.push(Simd::Avx512);
            }
        }
        paths
    }

    /// The widest available path, or the one `DHPD_SIMD` names if available.
    pub fn detect() -> Self {
        let paths = Self::available();
        let requested = std::env::var("DHPD_SIMD").ok().and_then(|name| {
            paths
                .iter()
                .copied()
                .find(|p| format!("{p:?}").eq_ignore_ascii_case(&name))
        });
        requested.unwrap_or(*paths.last().expect("the baseline is always available"))
    }

    /// [`block_forces`] compiled for these lanes.
    #[allow(clippy::too_many_arguments)]
    fn block_forces(
        self,
        rows: std::ops::Range<usize>,
        start: &[usize],
        pairs: &[Pair],
        x: &[[f64; 3]],
        u: &[[f64; 3]],
        force: &mut [[f64; 3]],
        flagged: &mut Vec<u32>,
    ) {
        match self {
            // SAFETY: a kernel holds only a path from `available`, which the
            // CPU reported it supports.
            #[cfg(target_arch = "x86_64")]
            Simd::Avx2 => unsafe { block_forces_avx2(rows, start, pairs, x, u, force, flagged) },
            #[cfg(target_arch = "x86_64")]
            Simd::Avx512 => unsafe {
                block_forces_avx512(rows, start, pairs, x, u, force, flagged)
            },
            _ => block_forces(rows, start, pairs, x, u, force, flagged),
        }
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[allow(clippy::too_many_arguments)]
unsafe fn block_forces_avx2(
    rows: std::ops::Range<usize>,
    start: &[usize],
    pairs: &[Pair],
    x: &[[f64; 3]],
    u: &[[f64; 3]],
    force: &mut [[f64; 3]],
    flagged: &mut Vec<u32>,
) {
    block_forces(rows, start, pairs, x, u, force, flagged)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
#[allow(clippy::too_many_arguments)]
unsafe fn block_forces_avx512(
    rows: std::ops::Range<usize>,
    start: &[usize],
    pairs: &[Pair],
    x: &[[f64; 3]],
    u: &[[f64; 3]],
    force: &mut [[f64; 3]],
    flagged: &mut Vec<u32>,
) {
    block_forces(rows, start, pairs, x, u, force, flagged)
}

/// The forces of the pairs of `rows` into `force` (both ends of each pair),
/// the rows whose pairs passed the breakage screen into `flagged`. Each row's
/// pairs go in batches: gather `y = ξ + η` and the stretch numerator, compute the
/// force coefficients of the whole batch (the square roots and divisions, in
/// vector lanes), scatter. Same operations as [`pair_force`], same results.
#[inline(always)]
fn block_forces(
    rows: std::ops::Range<usize>,
    start: &[usize],
    pairs: &[Pair],
    x: &[[f64; 3]],
    u: &[[f64; 3]],
    force: &mut [[f64; 3]],
    flagged: &mut Vec<u32>,
) {
    let mut y = [[0.0f64; BATCH]; 3];
    let (mut num, mut length, mut weight, mut limit, mut coef) = (
        [0.0f64; BATCH],
        [0.0f64; BATCH],
        [0.0f64; BATCH],
        [0.0f64; BATCH],
        [0.0f64; BATCH],
    );
    let mut over = [false; BATCH];
    for i in rows {
        let (xi, ui) = (x[i], u[i]);
        let mut acc = [0.0; 3];
        let mut any = false;
        for batch in pairs[start[i]..start[i + 1]].chunks(BATCH) {
            let n = batch.len();
            for (k, p) in batch.iter().enumerate() {
                let j = p.neighbour as usize;
                let d = [x[j][0] - xi[0], x[j][1] - xi[1], x[j][2] - xi[2]];
                let e = [u[j][0] - ui[0], u[j][1] - ui[1], u[j][2] - ui[2]];
                y[0][k] = d[0] + e[0];
                y[1][k] = d[1] + e[1];
                y[2][k] = d[2] + e[2];
                num[k] = 2.0 * (d[0] * e[0] + d[1] * e[1] + d[2] * e[2])
                    + (e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
                length[k] = p.length;
                weight[k] = p.weight;
                limit[k] = f64::from(p.limit);
            }
            for k in 0..n.min(BATCH) {
                let yl = (y[0][k] * y[0][k] + y[1][k] * y[1][k] + y[2][k] * y[2][k]).sqrt();
                let den = (yl + length[k]) * length[k];
                over[k] = num[k] >= limit[k] * den * SCREEN;
                coef[k] = if yl > 0.0 {
                    weight[k] * num[k] / (den * yl)
                } else {
                    0.0
                };
            }
            for (k, p) in batch.iter().enumerate() {
                any |= over[k];
                let f = [coef[k] * y[0][k], coef[k] * y[1][k], coef[k] * y[2][k]];
                acc[0] += f[0];
                acc[1] += f[1];
                acc[2] += f[2];
                let fj = &mut force[p.neighbour as usize];
                fj[0] -= f[0];
                fj[1] -= f[1];
                fj[2] -= f[2];
            }
        }
        let fi = &mut force[i];
        fi[0] += acc[0];
        fi[1] += acc[1];
        fi[2] += acc[2];
        if any {
            flagged.push(i as u32);
        }
    }
}

fn round_down(v: f64) -> f32 {
    let r = v as f32;
    if (r as f64) > v {
        r.next_down()
    } else {
        r
    }
}

/// The pairs of `disc`'s bonds by row (CSR `start`), each with the bond owned
/// by the row's point and the one owned by the other (or [`NONE`]). Dual
/// horizons: one entry per pair of points sharing a bond in either direction,
/// in the row of the smaller index; traditional: one entry per owned bond, in
/// its owner's row.
fn pairs(disc: &Discretization, traditional: bool) -> (Vec<usize>, Vec<Pair>, Vec<u32>, Vec<u32>) {
    let (n, bonds, p) = (disc.points.len(), &disc.bonds, &disc.points);
    // (row, other point, owned by the row's point?, bond), sorted.
    let mut items: Vec<(u32, u32, bool, u32)> = Vec::with_capacity(bonds.len());
    for i in 0..n {
        for b in bonds.owned_by(i) {
            let j = bonds.neighbour[b];
            let (row, other) = if traditional || (i as u32) < j {
                (i as u32, j)
            } else {
                (j, i as u32)
            };
            items.push((row, other, row == i as u32, b as u32));
        }
    }
    items.par_sort_unstable_by_key(|t| (t.0, t.1, !t.2));
    let mut start = vec![0usize; n + 1];
    let (mut pairs, mut owned, mut incoming) = (Vec::new(), Vec::new(), Vec::new());
    let mut k = 0;
    while k < items.len() {
        let (row, other) = (items[k].0, items[k].1);
        let (mut o, mut inc) = (NONE, NONE);
        while k < items.len() && items[k].0 == row && items[k].1 == other {
            if items[k].2 {
                o = items[k].3;
            } else {
                inc = items[k].3;
            }
            k += 1;
        }
        start[row as usize + 1] += 1;
        let d = crate::vector::sub(&p.x[other as usize], &p.x[row as usize]);
        pairs.push(Pair {
            weight: 0.0,
            length: (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt(),
            limit: f32::INFINITY,
            neighbour: other,
        });
        owned.push(o);
        incoming.push(inc);
    }
    for i in 0..n {
        start[i + 1] += start[i];
    }
    (start, pairs, owned, incoming)
}

/// Contiguous blocks of rows holding about the same number of pairs each
/// ([`BLOCKS`] of them), each with its force buffer.
fn blocks(start: &[usize], pairs: usize) -> Vec<Block> {
    let n = start.len() - 1;
    let per_block = pairs.div_ceil(BLOCKS).max(1);
    let mut blocks = Vec::new();
    let mut first = 0;
    for i in 0..n {
        if start[i + 1] - start[first] >= per_block || i + 1 == n {
            blocks.push(Block {
                rows: first..i + 1,
                force: vec![[0.0; 3]; n],
                flagged: Vec::new(),
            });
            first = i + 1;
        }
    }
    blocks
}

impl PairKernel {
    /// Runs the force loop on `simd` (for comparisons); false, and no change,
    /// when this CPU does not offer it.
    #[cfg(feature = "fixtures")]
    pub fn set_simd(&mut self, simd: Simd) -> bool {
        let ok = Simd::available().contains(&simd);
        if ok {
            self.simd = simd;
        }
        ok
    }

    /// Gathers the bonds of `disc` into pairs; `criterion` breaks bonds when
    /// given. Dual horizons: one entry per pair of points sharing a bond in
    /// either direction, in the row of the smaller index; traditional: one
    /// entry per owned bond, in its owner's row.
    pub fn new(
        disc: Discretization,
        model: &BondBased,
        criterion: Option<Criterion>,
        traditional: bool,
    ) -> Self {
        let n = disc.points.len();
        let bonds = &disc.bonds;
        let mut bond_weight = vec![0.0; bonds.len()];
        for i in 0..n {
            for b in bonds.owned_by(i) {
                bond_weight[b] = model.bond_weight(&disc, i, b);
            }
        }
        let (start, pairs, owned, incoming) = pairs(&disc, traditional);
        let blocks = if traditional {
            Vec::new()
        } else {
            blocks(&start, pairs.len())
        };
        let mut kernel = PairKernel {
            disc,
            start,
            pairs,
            owned,
            incoming,
            bond_weight,
            criterion: None,
            traditional,
            blocks,
            flagged: vec![false; if traditional { n } else { 0 }],
            simd: Simd::detect(),
        };
        for i in 0..n {
            for e in kernel.start[i]..kernel.start[i + 1] {
                kernel.refresh(criterion.as_ref(), i, e);
            }
        }
        kernel.criterion = criterion;
        kernel
    }

    /// Recomputes entry `e` of row `i` from its bonds' intact flags.
    fn refresh(&mut self, criterion: Option<&Criterion>, i: usize, e: usize) {
        let j = self.pairs[e].neighbour as usize;
        let (mut weight, mut limit) = (0.0, f64::INFINITY);
        let scale = if self.traditional { 2.0 } else { 1.0 };
        for (b, owner, other) in [(self.owned[e], i, j), (self.incoming[e], j, i)] {
            if b != NONE && self.disc.bonds.intact[b as usize] {
                weight += scale * self.bond_weight[b as usize];
                if let Some(c) = criterion {
                    limit = limit.min(c.limit(owner, other));
                }
            }
        }
        self.pairs[e].weight = weight;
        self.pairs[e].limit = round_down(limit);
    }

    /// Breaks the bonds of the rows that passed the screen whose exact stretch
    /// reached their limit; returns what broke.
    fn break_rows(&mut self, rows: &[usize], u: &[[f64; 3]]) -> Breaks {
        let mut breaks = Breaks::default();
        let Some(criterion) = self.criterion.take() else {
            return breaks;
        };
        for &i in rows {
            for e in self.start[i]..self.start[i + 1] {
                let j = self.pairs[e].neighbour as usize;
                let x = &self.disc.points.x;
                let (s, _, _) = stretch(&x[i], &x[j], &u[i], &u[j]);
                if !((s as f32) >= self.pairs[e].limit) {
                    continue;
                }
                let length = self.pairs[e].length;
                let mut changed = false;
                for (b, owner, other) in [(self.owned[e], i, j), (self.incoming[e], j, i)] {
                    if b != NONE
                        && self.disc.bonds.intact[b as usize]
                        && s >= criterion.limit(owner, other)
                    {
                        self.disc.bonds.intact[b as usize] = false;
                        if counts(&self.disc, owner) {
                            breaks.bonds += 1;
                            breaks.energy += 0.5 * self.bond_weight[b as usize] * length * s * s;
                        }
                        changed = true;
                    }
                }
                if changed {
                    self.refresh(Some(&criterion), i, e);
                }
            }
        }
        self.criterion = Some(criterion);
        breaks
    }

    /// Dual horizons: each pair once, its force added to both points in the
    /// buffer of its block; the buffers summed in a fixed order.
    fn forces_dual(&mut self, u: &[[f64; 3]], out: &mut [[f64; 3]]) -> Vec<usize> {
        let x = &self.disc.points.x;
        let (start, pairs) = (&self.start, &self.pairs);
        let simd = self.simd;
        self.blocks.par_iter_mut().for_each(|block| {
            block.force.fill([0.0; 3]);
            block.flagged.clear();
            let rows = block.rows.clone();
            let (force, flagged) = (&mut block.force, &mut block.flagged);
            simd.block_forces(rows, start, pairs, x, u, force, flagged);
        });
        let blocks = &self.blocks;
        out.par_iter_mut()
            .enumerate()
            .with_min_len(256)
            .for_each(|(i, f)| {
                let mut acc = [0.0; 3];
                for block in blocks {
                    let g = &block.force[i];
                    acc[0] += g[0];
                    acc[1] += g[1];
                    acc[2] += g[2];
                }
                *f = acc;
            });
        self.blocks
            .iter()
            .flat_map(|b| b.flagged.iter().map(|&i| i as usize))
            .collect()
    }

    /// Traditional horizons: each point gathers over its own bonds.
    fn forces_traditional(&mut self, u: &[[f64; 3]], out: &mut [[f64; 3]]) -> Vec<usize> {
        let x = &self.disc.points.x;
        let (start, pairs) = (&self.start, &self.pairs);
        out.par_iter_mut()
            .zip(self.flagged.par_iter_mut())
            .enumerate()
            .with_min_len(64)
            .for_each(|(i, (f, flag))| {
                let (xi, ui) = (&x[i], &u[i]);
                let mut acc = [0.0; 3];
                let mut over = false;
                for p in &pairs[start[i]..start[i + 1]] {
                    let j = p.neighbour as usize;
                    let (c, y, screen) = pair_force(p, xi, &x[j], ui, &u[j]);
                    over |= screen;
                    acc[0] += c * y[0];
                    acc[1] += c * y[1];
                    acc[2] += c * y[2];
                }
                *f = acc;
                *flag = over;
            });
        self.flagged
            .iter()
            .enumerate()
            .filter_map(|(i, &f)| f.then_some(i))
            .collect()
    }
}

impl ForceField for PairKernel {
    fn forces(&mut self, u: &[[f64; 3]], out: &mut [[f64; 3]]) -> Breaks {
        let rows = if self.traditional {
            self.forces_traditional(u, out)
        } else {
            self.forces_dual(u, out)
        };
        if rows.is_empty() {
            Breaks::default()
        } else {
            self.break_rows(&rows, u)
        }
    }

    fn strain_energy(&self, u: &[[f64; 3]]) -> Option<f64> {
        // Dual: each pair once, ½ W |ξ| s². Traditional: not conservative; the
        // same sum over owned bonds with W = 2 w, halved.
        let x = &self.disc.points.x;
        let factor = if self.traditional { 0.25 } else { 0.5 };
        let energy: f64 = (0..x.len())
            .into_par_iter()
            .filter(|&i| counts(&self.disc, i))
            .map(|i| {
                self.pairs[self.start[i]..self.start[i + 1]]
                    .iter()
                    .map(|p| {
                        let j = p.neighbour as usize;
                        let (s, _, _) = stretch(&x[i], &x[j], &u[i], &u[j]);
                        factor * p.weight * p.length * s * s
                    })
                    .sum::<f64>()
            })
            .sum();
        Some(energy)
    }

    fn disc(&self) -> &Discretization {
        &self.disc
    }

    fn into_disc(self: Box<Self>) -> Discretization {
        self.disc
    }

    fn simd(&self) -> Option<Simd> {
        (!self.traditional).then_some(self.simd)
    }
}

/// Any model's owner kernels, bond forces buffered per bond (module docs).
pub struct FamilyKernel<M: Model> {
    disc: Discretization,
    model: M,
    linear: bool,
    bond_force: Vec<[f64; 3]>,
    criterion: Option<Criterion>,
    ratios: Vec<f64>,
}

impl<M: Model> FamilyKernel<M> {
    /// Prepares the buffers; `linear` selects the linearised kernel.
    pub fn new(disc: Discretization, model: M, linear: bool, criterion: Option<Criterion>) -> Self {
        let bonds = &disc.bonds;
        let m = bonds.len();
        FamilyKernel {
            disc,
            model,
            linear,
            bond_force: vec![[0.0; 3]; m],
            ratios: if criterion.is_some() {
                vec![0.0; m]
            } else {
                Vec::new()
            },
            criterion,
        }
    }

    fn break_bonds(&mut self, u: &[[f64; 3]]) -> Breaks {
        let Some(criterion) = &self.criterion else {
            return Breaks::default();
        };
        criterion.ratios(&self.model, &self.disc, u, self.linear, &mut self.ratios);
        // The owners whose bonds broke, with how many.
        let mut broken: Vec<(usize, usize)> = Vec::new();
        let bonds = &mut self.disc.bonds;
        for i in 0..bonds.offsets.len() - 1 {
            let mut count = 0;
            for b in bonds.offsets[i]..bonds.offsets[i + 1] {
                if bonds.intact[b] && self.ratios[b] >= 1.0 {
                    bonds.intact[b] = false;
                    count += 1;
                }
            }
            if count > 0 {
                broken.push((i, count));
            }
        }
        let mut breaks = Breaks {
            bonds: broken
                .iter()
                .filter(|&&(i, _)| counts(&self.disc, i))
                .map(|&(_, count)| count)
                .sum(),
            energy: 0.0,
        };
        let owners: Vec<usize> = broken.iter().map(|&(i, _)| i).collect();
        if !owners.is_empty() {
            for i in self.model.refresh_owners(&self.disc, &owners) {
                let counted = counts(&self.disc, i);
                for b in self.disc.bonds.owned_by(i) {
                    if self.disc.bonds.intact[b] {
                        self.disc.bonds.intact[b] = false;
                        breaks.bonds += usize::from(counted);
                    }
                }
            }
        }
        breaks
    }
}

impl<M: Model> ForceField for FamilyKernel<M> {
    fn forces(&mut self, u: &[[f64; 3]], out: &mut [[f64; 3]]) -> Breaks {
        let (disc, model, linear) = (&self.disc, &self.model, self.linear);
        split_at_offsets(&mut self.bond_force, &disc.bonds.offsets)
            .into_par_iter()
            .enumerate()
            .for_each(|(i, f)| model.owner_forces(disc, i, u, linear, f));
        let (bond_force, bonds) = (&self.bond_force, &disc.bonds);
        out.par_iter_mut()
            .enumerate()
            .with_min_len(64)
            .for_each(|(i, f)| {
                let mut acc = [0.0; 3];
                for bf in &bond_force[bonds.owned_by(i)] {
                    (0..3).for_each(|c| acc[c] += bf[c]);
                }
                for &(_, b) in bonds.incoming(i) {
                    let bf = &bond_force[b as usize];
                    (0..3).for_each(|c| acc[c] -= bf[c]);
                }
                *f = acc;
            });
        self.break_bonds(u)
    }

    fn strain_energy(&self, _u: &[[f64; 3]]) -> Option<f64> {
        None
    }

    fn disc(&self) -> &Discretization {
        &self.disc
    }

    fn into_disc(self: Box<Self>) -> Discretization {
        self.disc
    }

    fn stress(&self, u: &[[f64; 3]]) -> Option<Result<Vec<Tensor>, Error>> {
        Some(crate::drivers::stress::field(&self.model, &self.disc, u))
    }
}

/// `F = −K u` with the assembled tangent on every degree of freedom.
pub struct TangentKernel {
    disc: Discretization,
    dofs: DofMap,
    pattern: Pattern,
    stiffness: Stiffness,
    transpose: Vec<usize>,
    x: Vec<f64>,
}

impl TangentKernel {
    /// Assembles `K` of `model` without constraints (refused, like the implicit
    /// path's, when its pattern would not fit in memory).
    pub fn new<M: Model>(
        disc: Discretization,
        model: &M,
        user_memory_limit: Option<f64>,
    ) -> Result<Self, crate::Error> {
        let dofs = DofMap::new(&disc, &[])?;
        let pattern = Pattern::new(&disc, &dofs, model.coupling(), user_memory_limit)?;
        let stiffness = Stiffness::assemble(model, &disc, &dofs, &pattern);
        let transpose = Stiffness::transpose_positions(&pattern);
        let x = vec![0.0; dofs.n_free()];
        Ok(TangentKernel {
            disc,
            dofs,
            pattern,
            stiffness,
            transpose,
            x,
        })
    }
}

impl ForceField for TangentKernel {
    fn forces(&mut self, u: &[[f64; 3]], out: &mut [[f64; 3]]) -> Breaks {
        for (r, &(i, c)) in self.dofs.free_dofs.iter().enumerate() {
            self.x[r] = u[i as usize][c as usize];
        }
        let (p, k, t, x) = (&self.pattern, &self.stiffness, &self.transpose, &self.x);
        let free_dofs = &self.dofs.free_dofs;
        let d = self.disc.d;
        out.par_iter_mut().enumerate().for_each(|(i, f)| {
            *f = [0.0; 3];
            for c in 0..d {
                let r = i * d + c;
                debug_assert_eq!(free_dofs[r], (i as u32, c as u8));
                f[c] = -(p.col_ptr[r]..p.col_ptr[r + 1])
                    .map(|q| k.values[t[q]] * x[p.row_idx[q]])
                    .sum::<f64>();
            }
        });
        Breaks::default()
    }

    fn strain_energy(&self, u: &[[f64; 3]]) -> Option<f64> {
        let x: Vec<f64> = self
            .dofs
            .free_dofs
            .iter()
            .map(|&(i, c)| u[i as usize][c as usize])
            .collect();
        let kx = self.stiffness.mul(&self.pattern, &x);
        let free = &self.dofs.free_dofs;
        Some(
            0.5 * (0..x.len())
                .filter(|&r| counts(&self.disc, free[r].0 as usize))
                .map(|r| x[r] * kx[r])
                .sum::<f64>(),
        )
    }

    fn disc(&self) -> &Discretization {
        &self.disc
    }

    fn into_disc(self: Box<Self>) -> Discretization {
        self.disc
    }
}
