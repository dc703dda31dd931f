//! Filling the stiffness values on a fixed [`Pattern`], in parallel by column point.
//!
//! Column point `q` gathers the blocks `K[p][q]` from every owner that touches
//! it (`q` itself, [`Column::Owner`], and the owners of the bonds ending at `q`,
//! [`Column::Neighbour`], from the bonds' transpose); its columns are a contiguous slice of the value array,
//! so threads never write to the same memory.

use super::dofs::{DofMap, PRESCRIBED};
use super::pattern::Pattern;
use crate::csr::split_at_offsets;
use crate::discretization::Discretization;
use crate::model::{Block, Column, Model};
use faer::sparse::SparseColMatRef;
use rayon::prelude::*;

/// The reduced stiffness matrix on the free unknowns, in CSC form (both triangles stored).
#[derive(Debug, Clone, PartialEq)]
pub struct Stiffness {
    /// Number of free unknowns.
    pub n: usize,
    /// Values, aligned with the pattern's `row_idx`.
    pub values: Vec<f64>,
}

impl Stiffness {
    /// Allocates and fills `K` for `model`.
    pub fn assemble<M: Model>(
        model: &M,
        disc: &Discretization,
        dofs: &DofMap,
        pattern: &Pattern,
    ) -> Self {
        let mut values = vec![0.0; pattern.nnz()];
        fill(model, disc, dofs, pattern, &mut values);
        Stiffness {
            n: dofs.n_free(),
            values,
        }
    }

    /// A faer view of the matrix.
    pub fn view<'a>(&'a self, pattern: &'a Pattern) -> SparseColMatRef<'a, usize, f64> {
        debug_assert_eq!(pattern.col_ptr.len(), self.n + 1);
        SparseColMatRef::new(pattern.symbolic(), &self.values)
    }

    /// Position of the transposed entry of every stored entry (the pattern is
    /// structurally symmetric: both models couple points symmetrically).
    pub fn transpose_positions(pattern: &Pattern) -> Vec<usize> {
        let n = pattern.col_ptr.len() - 1;
        let mut next = pattern.col_ptr.clone();
        // Walking columns in order visits each row's entries in column order, which is
        // the order of that row's entries inside the transposed column.
        let mut position = vec![0usize; pattern.nnz()];
        for col in 0..n {
            for k in pattern.col_ptr[col]..pattern.col_ptr[col + 1] {
                let row = pattern.row_idx[k];
                position[k] = next[row];
                next[row] += 1;
            }
        }
        position
    }

    /// Holds the free unknowns flagged in `pinned` (by free index): their rows
    /// and columns are zeroed and their diagonal set to `diagonal`, so with a
    /// zero right-hand side they solve to zero. Exact for the other unknowns
    /// when the pinned ones are coupled to no other (no intact bond to them).
    /// `columns` (by free unknown) restricts the pass to those columns, which
    /// must include every column with an entry in a newly pinned row.
    pub fn pin(
        &mut self,
        pattern: &Pattern,
        pinned: &[bool],
        diagonal: f64,
        columns: Option<&[bool]>,
    ) {
        use rayon::prelude::*;
        crate::csr::split_at_offsets(&mut self.values, &pattern.col_ptr)
            .into_par_iter()
            .enumerate()
            .for_each(|(col, values)| {
                if columns.is_some_and(|c| !c[col]) {
                    return;
                }
                let rows = &pattern.row_idx[pattern.col_ptr[col]..pattern.col_ptr[col + 1]];
                for (v, &row) in values.iter_mut().zip(rows) {
                    if pinned[col] || pinned[row] {
                        *v = if row == col { diagonal } else { 0.0 };
                    }
                }
            });
    }

    /// A point whose stiffness left the floating-point range, with the value:
    /// a non-finite entry, or a point with intact bonds none of whose free
    /// components has a normal diagonal entry (the sum of its bonds' positive
    /// stiffnesses underflowed; a mechanism leaves some component positive).
    /// Every input passed its checks, so this is a scale at which the model's
    /// own quantities leave double precision. `columns` (by point) restricts
    /// the search to the point columns refilled since the last check; empty
    /// columns (not assembled on this process) are skipped.
    pub fn out_of_range(
        &self,
        pattern: &Pattern,
        dofs: &DofMap,
        disc: &Discretization,
        columns: Option<&[bool]>,
    ) -> Option<(usize, f64)> {
        let column = |c: usize| pattern.col_ptr[c]..pattern.col_ptr[c + 1];
        let point = |c: usize| dofs.free_dofs[c].0 as usize;
        // An empty column was not assembled here (a distributed solve's other
        // processes hold it); an assembled one holds at least its diagonal.
        // A process holding only some bonds checks its own points' columns,
        // whose entries in its own rows are complete (every column is some
        // process's own).
        let in_scope = |c: usize| {
            !column(c).is_empty()
                && columns.is_none_or(|cols| cols[point(c)])
                && disc.reports(point(c))
        };
        if let Some((c, v)) = (0..self.n).filter(|&c| in_scope(c)).find_map(|c| {
            let v = self.values[column(c)].iter().find(|v| !v.is_finite())?;
            Some((c, *v))
        }) {
            return Some((point(c), v));
        }
        let diagonal = |c: usize| column(c).find(|&p| pattern.row_idx[p] == c);
        let mut normal = vec![false; disc.points.len()];
        for c in (0..self.n).filter(|&c| in_scope(c)) {
            if diagonal(c).is_some_and(|p| self.values[p].is_normal()) {
                normal[point(c)] = true;
            }
        }
        let suspects: Vec<usize> = (0..self.n)
            .filter(|&c| in_scope(c))
            .map(point)
            .filter(|&i| !normal[i])
            .collect();
        if suspects.is_empty() {
            return None;
        }
        let touches = disc.bonds.touch_counts(disc.points.len());
        let point_out = suspects.into_iter().find(|&i| touches[i] > 0)?;
        let c = (0..self.n).find(|&c| point(c) == point_out)?;
        Some((point_out, diagonal(c).map_or(0.0, |p| self.values[p])))
    }

    /// `(K + Kᵀ)/2` on the same pattern.
    pub fn symmetric_part(&self, transpose: &[usize]) -> Stiffness {
        let values = self
            .values
            .iter()
            .enumerate()
            .map(|(k, v)| 0.5 * (v + self.values[transpose[k]]))
            .collect();
        Stiffness { n: self.n, values }
    }

    /// The entries of this matrix (on `pattern`) at the positions of `sub`, a
    /// pattern whose columns hold subsets of `pattern`'s rows.
    pub fn restrict(&self, pattern: &Pattern, sub: &Pattern) -> Stiffness {
        let mut values = vec![0.0; sub.nnz()];
        for col in 0..self.n {
            let mut k = pattern.col_ptr[col];
            for s in sub.col_ptr[col]..sub.col_ptr[col + 1] {
                while pattern.row_idx[k] < sub.row_idx[s] {
                    k += 1;
                }
                values[s] = self.values[k];
            }
        }
        Stiffness { n: self.n, values }
    }

    /// `‖K − Kᵀ‖_F / ‖K‖_F`.
    pub fn asymmetry(&self, transpose: &[usize]) -> f64 {
        let skew: f64 = self
            .values
            .iter()
            .enumerate()
            .map(|(k, v)| (v - self.values[transpose[k]]).powi(2))
            .sum();
        let total: f64 = self.values.iter().map(|v| v * v).sum();
        (skew / total).sqrt()
    }

    /// `y = K x`, in parallel. A symmetric `K` is read row by row (row `c` is
    /// column `c`): one dot product per unknown. Otherwise the columns are
    /// split into one contiguous chunk per thread, each scattering into its own
    /// `y`, and the partial sums are added: the values are read in storage
    /// order either way (reading rows of a non-symmetric `K` through the
    /// transposed positions gathers from all over memory, and was 3-5× slower).
    pub fn mul_parallel(&self, pattern: &Pattern, symmetric: bool, x: &[f64]) -> Vec<f64> {
        use rayon::prelude::*;
        let n = self.n;
        if symmetric {
            return (0..n)
                .into_par_iter()
                .map(|c| {
                    (pattern.col_ptr[c]..pattern.col_ptr[c + 1])
                        .map(|k| self.values[k] * x[pattern.row_idx[k]])
                        .sum()
                })
                .collect();
        }
        let chunks = rayon::current_num_threads().max(1);
        let per = n.div_ceil(chunks).max(1);
        let partial: Vec<Vec<f64>> = (0..n)
            .step_by(per)
            .collect::<Vec<_>>()
            .into_par_iter()
            .map(|start| {
                let mut y = vec![0.0; n];
                for c in start..(start + per).min(n) {
                    let xc = x[c];
                    for k in pattern.col_ptr[c]..pattern.col_ptr[c + 1] {
                        y[pattern.row_idx[k]] += self.values[k] * xc;
                    }
                }
                y
            })
            .collect();
        let mut y = vec![0.0; n];
        y.par_iter_mut().enumerate().for_each(|(i, yi)| {
            *yi = partial.iter().map(|p| p[i]).sum();
        });
        y
    }

    /// `b − K x` carried in double-double precision (each product split
    /// exactly by an FMA, the sums compensated) and rounded once, so it is
    /// accurate to about ε of the result rather than ε of `|K||x|`: what
    /// iterative refinement needs when the residual of a double-precision
    /// product is all round-off (the solver's extended refinement).
    pub fn residual_extended(&self, pattern: &Pattern, x: &[f64], b: &[f64]) -> Vec<f64> {
        // Each row's sum as an unevaluated pair (hi, lo).
        let mut hi = b.to_vec();
        let mut lo = vec![0.0; self.n];
        for (col, &xc) in x.iter().enumerate() {
            for k in pattern.col_ptr[col]..pattern.col_ptr[col + 1] {
                let row = pattern.row_idx[k];
                let p = self.values[k] * xc;
                let p_err = self.values[k].mul_add(xc, -p);
                // hi − p exactly as s + e (Knuth's two-sum).
                let s = hi[row] - p;
                let v = s - hi[row];
                let e = (hi[row] - (s - v)) + (-p - v);
                hi[row] = s;
                lo[row] += e - p_err;
            }
        }
        hi.iter().zip(&lo).map(|(h, l)| h + l).collect()
    }

    /// `y = K x`.
    pub fn mul(&self, pattern: &Pattern, x: &[f64]) -> Vec<f64> {
        let mut y = vec![0.0; self.n];
        for (col, &xc) in x.iter().enumerate() {
            for k in pattern.col_ptr[col]..pattern.col_ptr[col + 1] {
                y[pattern.row_idx[k]] += self.values[k] * xc;
            }
        }
        y
    }
}

/// Overwrites `values` with the tangent of `model` (all entries of the pattern are written).
pub fn fill<M: Model>(
    model: &M,
    disc: &Discretization,
    dofs: &DofMap,
    pattern: &Pattern,
    values: &mut [f64],
) {
    fill_columns(model, disc, dofs, pattern, values, None);
}

/// Overwrites the columns of the point columns flagged in `columns` (every
/// column when `None`) with the tangent of `model`: after bonds break, only
/// the columns they touch change.
pub fn fill_columns<M: Model>(
    model: &M,
    disc: &Discretization,
    dofs: &DofMap,
    pattern: &Pattern,
    values: &mut [f64],
    columns: Option<&[bool]>,
) {
    let offsets = pattern.point_value_offsets(dofs);
    split_at_offsets(values, &offsets)
        .into_par_iter()
        .enumerate()
        .for_each_init(
            // Per thread: the slot of each row point in the current column (u32::MAX = none).
            || vec![u32::MAX; disc.points.len()],
            |slot, (q, out)| {
                if out.is_empty() || columns.is_some_and(|c| !c[q]) {
                    return;
                }
                let rows = pattern.rows(q);
                for (k, &p) in rows.iter().enumerate() {
                    slot[p as usize] = k as u32;
                }
                let mut acc: Vec<Block> = vec![[[0.0; 3]; 3]; rows.len()];
                let d = dofs.d;
                let mut add = |p: usize, block: &Block| {
                    let k = slot[p] as usize;
                    debug_assert!(k < rows.len(), "pattern holds every coupled point");
                    for r in 0..d {
                        for c in 0..d {
                            acc[k][r][c] += block[r][c];
                        }
                    }
                };
                column_blocks(model, disc, q, &mut add);
                let mut pos = 0;
                for c in (0..dofs.d).filter(|&c| dofs.free_index[3 * q + c] != PRESCRIBED) {
                    for (k, &p) in rows.iter().enumerate() {
                        for r in (0..dofs.d)
                            .filter(|&r| dofs.free_index[3 * p as usize + r] != PRESCRIBED)
                        {
                            out[pos] = acc[k][r][c];
                            pos += 1;
                        }
                    }
                }
                for &p in rows {
                    slot[p as usize] = u32::MAX;
                }
            },
        );
}

/// Every block `K_pq` of point column `q` of the tangent, as `add(p, block)`
/// (a row point may come several times: the blocks sum): the terms of `q`'s own
/// family and those of every bond by which another owner reaches `q`.
fn column_blocks<M: Model>(
    model: &M,
    disc: &Discretization,
    q: usize,
    add: &mut dyn FnMut(usize, &Block),
) {
    model.tangent_column(disc, q, Column::Owner, add);
    for &(owner, bond) in disc.bonds.incoming(q) {
        model.tangent_column(disc, owner as usize, Column::Neighbour(bond as usize), add);
    }
}

/// Gershgorin bound of the tangent of `model` on every degree of freedom (no
/// constraints): `Σ_c |K_rc|` per point and component, without storing `K`.
///
/// The columns are built point by point as in [`fill_columns`] and their
/// absolute values scattered into per-thread row sums, so memory stays at a few
/// vectors of the point count (the assembled tangent of a 3D shear-model body,
/// which couples neighbours of neighbours, takes tens of GiB).
pub fn row_abs_sums<M: Model>(model: &M, disc: &Discretization) -> Vec<[f64; 3]> {
    let n = disc.points.len();
    let d = disc.d;
    let chunk = n.div_ceil(4 * rayon::current_num_threads()).max(1);
    let starts: Vec<usize> = (0..n).step_by(chunk).collect();
    starts
        .into_par_iter()
        .map(|start| {
            let mut sums = vec![[0.0; 3]; n];
            // The slot of each row point in the current column (u32::MAX = none).
            let mut slot = vec![u32::MAX; n];
            let mut rows: Vec<usize> = Vec::new();
            let mut acc: Vec<Block> = Vec::new();
            for q in start..(start + chunk).min(n) {
                let mut add = |p: usize, block: &Block| {
                    if slot[p] == u32::MAX {
                        slot[p] = rows.len() as u32;
                        rows.push(p);
                        acc.push([[0.0; 3]; 3]);
                    }
                    let k = slot[p] as usize;
                    for r in 0..d {
                        for c in 0..d {
                            acc[k][r][c] += block[r][c];
                        }
                    }
                };
                column_blocks(model, disc, q, &mut add);
                for (k, &p) in rows.iter().enumerate() {
                    for r in 0..d {
                        sums[p][r] += (0..d).map(|c| acc[k][r][c].abs()).sum::<f64>();
                    }
                    slot[p] = u32::MAX;
                }
                rows.clear();
                acc.clear();
            }
            sums
        })
        .reduce_with(|mut a, b| {
            for (x, y) in a.iter_mut().zip(&b) {
                for c in 0..3 {
                    x[c] += y[c];
                }
            }
            a
        })
        .unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `1 − 3 · fl(1/3)` is 2⁻⁵⁴; a double-precision product rounds it to 0.
    #[test]
    fn extended_residual_keeps_what_a_double_product_rounds_away() {
        let pattern = Pattern {
            row_offsets: Vec::new(),
            row_points: Vec::new(),
            col_ptr: vec![0, 1],
            row_idx: vec![0],
        };
        let k = Stiffness {
            n: 1,
            values: vec![3.0],
        };
        let x = [1.0 / 3.0];
        assert_eq!(k.mul(&pattern, &x), vec![1.0]);
        assert_eq!(
            k.residual_extended(&pattern, &x, &[1.0]),
            vec![2f64.powi(-54)]
        );
    }
}
