//! A two-level preconditioner whose memory grows linearly with the points:
//! Chebyshev smoothing on `K` and a coarse space of rigid motions of small
//! aggregates of points (unsmoothed aggregation; Vaněk, Mandel and Brezina,
//! Computing 56, 1996, with the rigid-body candidates of elasticity).
//!
//! **Aggregates.** Points are grouped greedily: a point whose near neighbours
//! (coupled to it in `K` and within [`AGGREGATE_REACH`] spacings) are all free
//! of an aggregate starts one with them; the points left join the aggregate of
//! a near neighbour, or start their own. On a grid an aggregate is a block of
//! 3 × 3 (× 3) points.
//!
//! **Coarse space.** `P` maps `k_a ≤ 6` coarse unknowns per aggregate to the
//! free unknowns of its points: the translations and the infinitesimal
//! rotations about the aggregate's centroid, restricted to the free
//! components and orthonormalised (modified Gram–Schmidt; a candidate that the
//! constraints make dependent is dropped). The coarse matrix
//! `K_c = Pᵀ K_sym P`, with `K_sym` the symmetric part of `K`, is factorised
//! by sparse Cholesky: it has about 1/27 (3D) or 1/9 (2D) of the unknowns.
//!
//! **Cycle** (symmetric, so that CG may use it): with `S` the Chebyshev
//! polynomial of degree [`SMOOTHING_DEGREE`] in `D⁻¹K` on
//! `[λ_max/CHEBYSHEV_RATIO, λ_max]` (`D` the diagonal of `K`, `λ_max` from
//! power iterations),
//!
//! ```text
//! x = S b;   x += P K_c⁻¹ Pᵀ (b − K x);   x += S (b − K x)
//! ```
//!
//! Smoothing damps the errors that vary from point to point (on which the
//! peridynamic `K` is close to its diagonal: a point's stiffness comes from
//! many bonds); what it leaves varies slowly over an aggregate and is close to
//! a rigid motion there, which the coarse solve removes. Both statements hold
//! at every size for a fixed `δ/Δx`, so the iteration count does not grow with
//! the number of points (measured in `validation/solver/README.md`).

use super::cholesky::{Cholesky, FactorError};
use super::Layout;
use crate::assembly::dofs::PRESCRIBED;
use crate::assembly::pattern::Pattern;
use crate::error::NumericalError;
use crate::vector::{norm, sub};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use rayon::prelude::*;

/// Near neighbours of an aggregate's seed: within this many of its spacings.
pub const AGGREGATE_REACH: f64 = 1.5;

/// Degree of the Chebyshev smoother before and after the coarse correction.
pub const SMOOTHING_DEGREE: usize = 2;

/// The smoother targets the eigenvalues of `D⁻¹K` in `[λ_max/ratio, λ_max]`.
pub const CHEBYSHEV_RATIO: f64 = 8.0;

/// Power iterations for `λ_max(D⁻¹K)` (the estimate is raised by 10 %).
const POWER_ITERATIONS: usize = 12;

/// Most coarse unknowns per aggregate (3 translations and 3 rotations).
const MAX_MODES: usize = 6;

/// Marker for "no aggregate" / "no slot".
const NONE: u32 = u32::MAX;

/// The two-level preconditioner of one matrix `K`.
pub struct TwoLevel {
    /// Aggregate of each free unknown.
    aggregate: Vec<u32>,
    /// Row of `P` at each free unknown (its aggregate's columns).
    rows: Vec<[f64; MAX_MODES]>,
    /// Free unknowns of each aggregate, CSR.
    members_offsets: Vec<usize>,
    members: Vec<u32>,
    /// Coarse unknowns of each aggregate: `coarse_offsets[a]..coarse_offsets[a+1]`.
    coarse_offsets: Vec<usize>,
    coarse: Cholesky,
    inverse_diagonal: Vec<f64>,
    lambda_max: f64,
}

impl TwoLevel {
    /// Builds the aggregates, `P`, the coarse factor and the smoother bounds for
    /// `K` (`values` on `pattern`; `product` is `v ↦ K v`).
    pub fn new(
        layout: Layout,
        pattern: &Pattern,
        values: &[f64],
        product: &dyn Fn(&[f64]) -> Vec<f64>,
    ) -> Result<Self, NumericalError> {
        let dofs = layout.dofs;
        let point_aggregate = aggregate_points(layout, pattern);
        let n_aggregates = point_aggregate.iter().max().map_or(0, |&a| a as usize + 1);
        let n = dofs.n_free();
        let aggregate: Vec<u32> = dofs
            .free_dofs
            .iter()
            .map(|&(p, _)| point_aggregate[p as usize])
            .collect();
        let (members_offsets, members) = group(&aggregate, n_aggregates);
        let (rows, coarse_offsets) = rigid_modes(layout, &aggregate, &members_offsets, &members);
        let (col_ptr, row_idx, coarse_values) = coarse_matrix(
            pattern,
            values,
            &aggregate,
            &rows,
            &coarse_offsets,
            &members_offsets,
            &members,
        );
        let n_coarse = coarse_offsets[n_aggregates];
        let structure =
            SymbolicSparseColMatRef::new_checked(n_coarse, n_coarse, &col_ptr, None, &row_idx);
        let mut coarse = Cholesky::analyse(structure, None)?;
        coarse
            .factorize(SparseColMatRef::new(structure, &coarse_values))
            .map_err(|e| {
                NumericalError::Solver(match e {
                    FactorError::NonPositivePivot(_) | FactorError::NearlySingular(..) => {
                        "the coarse matrix of the two-level preconditioner (the rigid motions \
                         of small point groups) is not positive definite: the symmetric part of \
                         K is indefinite (the gradient dilatation near ν = 1/2) or the body is \
                         under-constrained; use solver.method = \"gmres\" or \"lu\""
                            .into()
                    }
                    _ => "the coarse factorisation of the two-level preconditioner failed".into(),
                })
            })?;
        let inverse_diagonal: Vec<f64> = (0..n)
            .map(|c| {
                let range = pattern.col_ptr[c]..pattern.col_ptr[c + 1];
                let k = range
                    .clone()
                    .find(|&k| pattern.row_idx[k] == c)
                    .expect("the pattern holds the diagonal");
                1.0 / values[k]
            })
            .collect();
        let lambda_max = 1.1 * largest_eigenvalue(product, &inverse_diagonal);
        Ok(Self {
            aggregate,
            rows,
            members_offsets,
            members,
            coarse_offsets,
            coarse,
            inverse_diagonal,
            lambda_max,
        })
    }

    /// Coarse unknowns (columns of `P`).
    pub fn coarse_size(&self) -> usize {
        *self.coarse_offsets.last().unwrap_or(&0)
    }

    /// Stored entries of the coarse factor.
    pub fn nnz_coarse_factor(&self) -> usize {
        self.coarse.nnz_l()
    }

    /// `v ← M⁻¹ v`: one symmetric two-level cycle (module docs).
    pub fn apply(&self, product: &dyn Fn(&[f64]) -> Vec<f64>, v: &mut [f64]) {
        let b = v.to_vec();
        let mut x = vec![0.0; b.len()];
        let mut r = b.clone();
        self.smooth(product, &mut x, &mut r, true);
        let mut e = self.restrict(&r);
        self.coarse.solve_in_place(&mut e);
        let correction = self.prolong(&e);
        let kc = product(&correction);
        x.par_iter_mut()
            .zip(&correction)
            .for_each(|(xi, ci)| *xi += ci);
        r.par_iter_mut().zip(&kc).for_each(|(ri, ki)| *ri -= ki);
        self.smooth(product, &mut x, &mut r, false);
        v.copy_from_slice(&x);
    }

    /// Chebyshev smoothing of `K x = b` from `x` with residual `r`
    /// (Saad, Alg. 12.1, on `D⁻¹K`); `r` is kept current only when asked.
    fn smooth(
        &self,
        product: &dyn Fn(&[f64]) -> Vec<f64>,
        x: &mut [f64],
        r: &mut [f64],
        keep_residual: bool,
    ) {
        let (upper, lower) = (self.lambda_max, self.lambda_max / CHEBYSHEV_RATIO);
        let theta = 0.5 * (upper + lower);
        let delta = 0.5 * (upper - lower);
        let sigma = theta / delta;
        let mut rho = 1.0 / sigma;
        let mut d: Vec<f64> = r
            .par_iter()
            .zip(&self.inverse_diagonal)
            .map(|(ri, di)| ri * di / theta)
            .collect();
        for step in 0..SMOOTHING_DEGREE {
            x.par_iter_mut().zip(&d).for_each(|(xi, di)| *xi += di);
            let last = step + 1 == SMOOTHING_DEGREE;
            if last && !keep_residual {
                break;
            }
            let kd = product(&d);
            r.par_iter_mut().zip(&kd).for_each(|(ri, ki)| *ri -= ki);
            if last {
                break;
            }
            let rho_next = 1.0 / (2.0 * sigma - rho);
            let (a, c) = (rho_next * rho, 2.0 * rho_next / delta);
            d.par_iter_mut()
                .zip(r.par_iter())
                .zip(&self.inverse_diagonal)
                .for_each(|((di, ri), wi)| *di = a * *di + c * wi * ri);
            rho = rho_next;
        }
    }

    /// `Pᵀ r`, by aggregate.
    fn restrict(&self, r: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; self.coarse_size()];
        let parts: Vec<&mut [f64]> = crate::csr::split_at_offsets(&mut out, &self.coarse_offsets);
        parts.into_par_iter().enumerate().for_each(|(a, part)| {
            for &dof in &self.members[self.members_offsets[a]..self.members_offsets[a + 1]] {
                let row = &self.rows[dof as usize];
                for (m, p) in part.iter_mut().enumerate() {
                    *p += row[m] * r[dof as usize];
                }
            }
        });
        out
    }

    /// `P e`.
    fn prolong(&self, e: &[f64]) -> Vec<f64> {
        (0..self.aggregate.len())
            .into_par_iter()
            .map(|dof| {
                let a = self.aggregate[dof] as usize;
                let cols = &e[self.coarse_offsets[a]..self.coarse_offsets[a + 1]];
                cols.iter().zip(&self.rows[dof]).map(|(c, p)| c * p).sum()
            })
            .collect()
    }
}

/// Greedy aggregation of the points (module docs); points without a free
/// unknown are aggregated too (they contribute no row of `P`).
fn aggregate_points(layout: Layout, pattern: &Pattern) -> Vec<u32> {
    let x = layout.x;
    let n = x.len();
    let near = |q: usize| {
        let reach = AGGREGATE_REACH * layout.spacing[q];
        pattern
            .rows(q)
            .iter()
            .map(|&r| r as usize)
            .filter(move |&r| r != q && norm(&sub(&x[r], &x[q])) <= reach)
    };
    let mut aggregate = vec![NONE; n];
    let mut count = 0u32;
    for q in 0..n {
        if aggregate[q] == NONE && near(q).all(|r| aggregate[r] == NONE) {
            aggregate[q] = count;
            near(q).for_each(|r| aggregate[r] = count);
            count += 1;
        }
    }
    let seeded = aggregate.clone();
    for q in 0..n {
        if aggregate[q] == NONE {
            let joined = near(q)
                .filter(|&r| seeded[r] != NONE)
                .min_by(|&a, &b| {
                    let da = norm(&sub(&x[a], &x[q]));
                    let db = norm(&sub(&x[b], &x[q]));
                    da.total_cmp(&db)
                })
                .map(|r| seeded[r]);
            if let Some(a) = joined {
                aggregate[q] = a;
            }
        }
    }
    for q in 0..n {
        if aggregate[q] == NONE {
            aggregate[q] = count;
            let free: Vec<usize> = near(q).filter(|&r| aggregate[r] == NONE).collect();
            free.into_iter().for_each(|r| aggregate[r] = count);
            count += 1;
        }
    }
    aggregate
}

/// CSR of the free unknowns of each aggregate.
fn group(aggregate: &[u32], n_aggregates: usize) -> (Vec<usize>, Vec<u32>) {
    let mut offsets = vec![0usize; n_aggregates + 1];
    aggregate.iter().for_each(|&a| offsets[a as usize + 1] += 1);
    for a in 0..n_aggregates {
        offsets[a + 1] += offsets[a];
    }
    let mut next = offsets.clone();
    let mut members = vec![0u32; aggregate.len()];
    for (dof, &a) in aggregate.iter().enumerate() {
        members[next[a as usize]] = dof as u32;
        next[a as usize] += 1;
    }
    (offsets, members)
}

/// Orthonormalised rigid motions of each aggregate at its free unknowns: the
/// rows of `P` and the coarse offsets.
fn rigid_modes(
    layout: Layout,
    aggregate: &[u32],
    members_offsets: &[usize],
    members: &[u32],
) -> (Vec<[f64; MAX_MODES]>, Vec<usize>) {
    let (d, dofs) = (layout.d(), layout.dofs);
    let n_aggregates = members_offsets.len() - 1;
    let candidates = match d {
        1 => 1,
        2 => 3,
        _ => 6,
    };
    let per_aggregate: Vec<Vec<Vec<f64>>> = (0..n_aggregates)
        .into_par_iter()
        .map(|a| {
            let dofs_a = &members[members_offsets[a]..members_offsets[a + 1]];
            let position = |dof: u32| {
                let (point, c) = layout.unknown(dof as usize);
                (layout.x[point], c)
            };
            let mut centroid = [0.0; 3];
            for &dof in dofs_a {
                let (x, _) = position(dof);
                (0..3).for_each(|k| centroid[k] += x[k] / dofs_a.len() as f64);
            }
            let value = |mode: usize, dof: u32| {
                let (x, c) = position(dof);
                let y = sub(&x, &centroid);
                match (mode, c) {
                    (m, c) if m < d => f64::from(m == c),
                    // Rotations about z (2D and 3D), then x and y (3D).
                    (m, 0) if m == d => -y[1],
                    (m, 1) if m == d => y[0],
                    (4, 1) => -y[2],
                    (4, 2) => y[1],
                    (5, 0) => y[2],
                    (5, 2) => -y[0],
                    _ => 0.0,
                }
            };
            let mut basis: Vec<Vec<f64>> = Vec::new();
            for mode in 0..candidates {
                let mut v: Vec<f64> = dofs_a.iter().map(|&dof| value(mode, dof)).collect();
                let before = v.iter().map(|x| x * x).sum::<f64>().sqrt();
                for b in &basis {
                    let dot: f64 = v.iter().zip(b).map(|(x, y)| x * y).sum();
                    v.iter_mut().zip(b).for_each(|(x, y)| *x -= dot * y);
                }
                let after = v.iter().map(|x| x * x).sum::<f64>().sqrt();
                if before > 0.0 && after > 1e-8 * before {
                    v.iter_mut().for_each(|x| *x /= after);
                    basis.push(v);
                }
            }
            basis
        })
        .collect();
    let mut coarse_offsets = vec![0usize; n_aggregates + 1];
    let mut rows = vec![[0.0; MAX_MODES]; aggregate.len()];
    for (a, basis) in per_aggregate.iter().enumerate() {
        coarse_offsets[a + 1] = coarse_offsets[a] + basis.len();
        let dofs_a = &members[members_offsets[a]..members_offsets[a + 1]];
        for (m, column) in basis.iter().enumerate() {
            for (&dof, &v) in dofs_a.iter().zip(column) {
                rows[dof as usize][m] = v;
            }
        }
    }
    debug_assert!(dofs.free_index.iter().filter(|&&i| i != PRESCRIBED).count() == aggregate.len());
    (rows, coarse_offsets)
}

/// `K_c = Pᵀ K_sym P` in CSC form (both triangles), by coarse column block.
#[allow(clippy::too_many_arguments)]
fn coarse_matrix(
    pattern: &Pattern,
    values: &[f64],
    aggregate: &[u32],
    rows: &[[f64; MAX_MODES]],
    coarse_offsets: &[usize],
    members_offsets: &[usize],
    members: &[u32],
) -> (Vec<usize>, Vec<usize>, Vec<f64>) {
    let n_aggregates = coarse_offsets.len() - 1;
    // Column block of aggregate a: the row aggregates it meets and their blocks,
    // accumulated as full 6 × 6 arrays (rows of P beyond k are zero), so that the
    // inner product runs in vector lanes; entry (m, l) at m * 6 + l.
    type Block = [f64; MAX_MODES * MAX_MODES];
    let blocks: Vec<Vec<(u32, Block)>> = (0..n_aggregates)
        .into_par_iter()
        .map_init(
            // Per thread: the slot of each row aggregate in `found` (NONE: not met yet).
            || vec![NONE; n_aggregates],
            |slot, a| {
                let mut found: Vec<(u32, Block)> = Vec::new();
                for &col in &members[members_offsets[a]..members_offsets[a + 1]] {
                    let pc = &rows[col as usize];
                    for k in pattern.col_ptr[col as usize]..pattern.col_ptr[col as usize + 1] {
                        let row = pattern.row_idx[k];
                        let b = aggregate[row] as usize;
                        if slot[b] == NONE {
                            slot[b] = found.len() as u32;
                            found.push((b as u32, [0.0; MAX_MODES * MAX_MODES]));
                        }
                        let block = &mut found[slot[b] as usize].1;
                        let pr = &rows[row];
                        let v = values[k];
                        for m in 0..MAX_MODES {
                            let t = pr[m] * v;
                            for l in 0..MAX_MODES {
                                block[m * MAX_MODES + l] += t * pc[l];
                            }
                        }
                    }
                }
                found.iter().for_each(|(b, _)| slot[*b as usize] = NONE);
                found.sort_unstable_by_key(|(b, _)| *b);
                found
            },
        )
        .collect();
    // Symmetric part: K_c[b,a] and K_c[a,b]ᵀ averaged.
    let lookup = |b: usize, a: usize| -> Option<&Block> {
        let list = &blocks[b];
        list.binary_search_by_key(&(a as u32), |(x, _)| *x)
            .ok()
            .map(|i| &list[i].1)
    };
    let mut col_ptr = vec![0usize];
    let mut row_idx = Vec::new();
    let mut out = Vec::new();
    for a in 0..n_aggregates {
        let ka = coarse_offsets[a + 1] - coarse_offsets[a];
        for l in 0..ka {
            for (b, block) in &blocks[a] {
                let b = *b as usize;
                let kb = coarse_offsets[b + 1] - coarse_offsets[b];
                let mirror = lookup(b, a);
                for m in 0..kb {
                    let here = block[m * MAX_MODES + l];
                    let there = mirror.map_or(here, |t| t[l * MAX_MODES + m]);
                    row_idx.push(coarse_offsets[b] + m);
                    out.push(0.5 * (here + there));
                }
            }
            col_ptr.push(row_idx.len());
        }
    }
    (col_ptr, row_idx, out)
}

/// `λ_max(D⁻¹K)` by power iterations from a fixed, non-symmetric start.
fn largest_eigenvalue(product: &dyn Fn(&[f64]) -> Vec<f64>, inverse_diagonal: &[f64]) -> f64 {
    let n = inverse_diagonal.len();
    let mut v: Vec<f64> = (0..n)
        .map(|i| 1.0 + ((i * 7919) % 13) as f64 / 13.0)
        .collect();
    let mut lambda = 0.0;
    for _ in 0..POWER_ITERATIONS {
        let norm_v = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        v.iter_mut().for_each(|x| *x /= norm_v);
        let kv = product(&v);
        let w: Vec<f64> = kv
            .iter()
            .zip(inverse_diagonal)
            .map(|(k, d)| k * d)
            .collect();
        lambda = w.iter().map(|x| x * x).sum::<f64>().sqrt();
        v = w;
    }
    lambda
}
