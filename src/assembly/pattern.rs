//! The sparsity pattern of `K`, built once per discretisation.
//!
//! At point level, column `q` holds the row points that any owner's tangent
//! couples to `q`. Owners that touch `q` are `q` itself and the owners of the
//! bonds that end at `q` (its dual horizon,
//! [`crate::discretization::Bonds::incoming`]).
//! - Star coupling (bond-based): rows(q) = {q} ∪ H_q ∪ H'_q.
//! - Family coupling (state-based): rows(q) = ∪_{o ∈ {q} ∪ H'_q} ({o} ∪ H_o).
//!
//! At degree-of-freedom level the pattern is the point pattern expanded by the
//! free components of each point. Broken bonds keep their slots, so the
//! pattern (and the symbolic factorisation) never changes when bonds break.

use super::dofs::DofMap;
use crate::csr::split_at_offsets;
use crate::discretization::Discretization;
use crate::error::NumericalError;
use crate::memory::{check_memory, memory_limit};
use crate::model::Coupling;
use faer::sparse::SymbolicSparseColMatRef;
use rayon::prelude::*;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Bytes per coupled pair of points while the pattern is built (the row list
/// and its copy in `row_points`).
const BYTES_PER_POINT_ENTRY: f64 = 8.0;

/// Bytes per matrix entry: its row index here and its value in the stiffness.
const BYTES_PER_DOF_ENTRY: f64 = 16.0;

/// The pattern at point level and at degree-of-freedom level.
#[derive(Debug, Clone, PartialEq)]
pub struct Pattern {
    /// `row_offsets[q]..row_offsets[q+1]` index `row_points` for column point q.
    pub row_offsets: Vec<usize>,
    /// Sorted row points of each column point.
    pub row_points: Vec<u32>,
    /// Degree-of-freedom CSC column pointers over the free unknowns.
    pub col_ptr: Vec<usize>,
    /// Degree-of-freedom CSC row indices.
    pub row_idx: Vec<usize>,
}

impl Pattern {
    /// The sorted row points of column point `q`.
    #[inline]
    pub fn rows(&self, q: usize) -> &[u32] {
        &self.row_points[self.row_offsets[q]..self.row_offsets[q + 1]]
    }

    /// Number of stored entries of `K`.
    pub fn nnz(&self) -> usize {
        self.row_idx.len()
    }

    /// The degree-of-freedom structure as a faer symbolic matrix (for the
    /// symbolic factorisation, before any value is assembled).
    pub fn symbolic(&self) -> SymbolicSparseColMatRef<'_, usize> {
        let n = self.col_ptr.len() - 1;
        // Built with sorted, in-range, duplicate-free row indices.
        unsafe { SymbolicSparseColMatRef::new_unchecked(n, n, &self.col_ptr, None, &self.row_idx) }
    }

    /// Builds the pattern for `coupling` on the free unknowns of `dofs`.
    ///
    /// The point-level rows are counted as they are found, and the run is
    /// refused (`solver.memory_limit_gib` or 90 % of the available memory) as
    /// soon as the entries found so far, expanded to `d × d` blocks of row
    /// indices and values, would not fit: a neighbours-of-neighbours pattern of
    /// large horizons is refused before it is built.
    pub fn new(
        disc: &Discretization,
        dofs: &DofMap,
        coupling: Coupling,
        user_memory_limit: Option<f64>,
    ) -> Result<Self, NumericalError> {
        let charge = BYTES_PER_POINT_ENTRY + (dofs.d * dofs.d) as f64 * BYTES_PER_DOF_ENTRY;
        let (row_offsets, row_points) =
            point_rows(disc, dofs.d, coupling, user_memory_limit, charge)?;
        let (col_ptr, row_idx) = dof_columns(dofs, &row_offsets, &row_points, None);
        Ok(Pattern {
            row_offsets,
            row_points,
            col_ptr,
            row_idx,
        })
    }

    /// The point level whole, the degree-of-freedom level only in the point
    /// columns that `columns` flags, given the point level (a process of a
    /// distributed solve assembles its own columns and those of its ghost
    /// points): the other columns are empty, so [`Pattern::point_value_offsets`]
    /// and the assembly skip them. The memory check charges the point level
    /// and the flagged columns.
    pub fn with_columns<E: From<NumericalError>>(
        disc: &Discretization,
        dofs: &DofMap,
        coupling: Coupling,
        user_memory_limit: Option<f64>,
        columns: impl FnOnce(&Pattern) -> Result<Vec<bool>, E>,
    ) -> Result<Self, E> {
        let (row_offsets, row_points) = point_rows(
            disc,
            dofs.d,
            coupling,
            user_memory_limit,
            BYTES_PER_POINT_ENTRY,
        )?;
        let mut pattern = Pattern {
            row_offsets,
            row_points,
            col_ptr: Vec::new(),
            row_idx: Vec::new(),
        };
        let keep = columns(&pattern)?;
        let kept: usize = (0..keep.len())
            .filter(|&q| keep[q])
            .map(|q| pattern.rows(q).len())
            .sum();
        let d2 = (dofs.d * dofs.d) as f64;
        check_memory(
            || format!("this process's columns of the stiffness ({kept} coupled point pairs)"),
            pattern.row_points.len() as f64 * BYTES_PER_POINT_ENTRY
                + kept as f64 * d2 * BYTES_PER_DOF_ENTRY,
            user_memory_limit,
        )?;
        let (col_ptr, row_idx) =
            dof_columns(dofs, &pattern.row_offsets, &pattern.row_points, Some(&keep));
        pattern.col_ptr = col_ptr;
        pattern.row_idx = row_idx;
        Ok(pattern)
    }

    /// Offsets into the value array of each point's block of columns.
    pub fn point_value_offsets(&self, dofs: &DofMap) -> Vec<usize> {
        let n = self.row_offsets.len() - 1;
        let mut offsets = Vec::with_capacity(n + 1);
        offsets.push(0);
        let mut col = 0;
        for q in 0..n {
            col += dofs.free_count(q);
            offsets.push(self.col_ptr[col]);
        }
        offsets
    }
}

/// The point-level pattern (CSR: offsets and sorted rows of each column
/// point), its entries charged against the memory limit as they are found.
fn point_rows(
    disc: &Discretization,
    d: usize,
    coupling: Coupling,
    user_memory_limit: Option<f64>,
    bytes_per_entry: f64,
) -> Result<(Vec<usize>, Vec<u32>), NumericalError> {
    let n = disc.points.len();
    let bonds = &disc.bonds;
    let family = |o: usize| bonds.neighbour[bonds.owned_by(o)].iter().copied();
    let max_entries = memory_limit(user_memory_limit)
        .map_or(usize::MAX, |(limit, _)| (limit / bytes_per_entry) as usize);
    let found = AtomicUsize::new(0);
    let charge = |entries: usize| {
        let total = found.fetch_add(entries, Ordering::Relaxed) + entries;
        if total <= max_entries {
            return Ok(());
        }
        check_memory(
            || {
                format!(
                    "the stiffness pattern (more than {total} coupled point pairs, up to {} \
                     matrix entries, found before the pattern over {n} points was complete)",
                    total * d * d
                )
            },
            total as f64 * bytes_per_entry,
            user_memory_limit,
        )
    };
    // A per-thread marker array (one flag per point) deduplicates in O(1).
    let rows: Vec<Vec<u32>> = (0..n)
        .into_par_iter()
        .map_init(
            || vec![false; n],
            |seen, q| {
                let mut r: Vec<u32> = Vec::new();
                let mut push = |p: u32| {
                    if !seen[p as usize] {
                        seen[p as usize] = true;
                        r.push(p);
                    }
                };
                push(q as u32);
                family(q).for_each(&mut push);
                for &(o, _) in bonds.incoming(q) {
                    push(o);
                    if coupling == Coupling::Family {
                        family(o as usize).for_each(&mut push);
                    }
                }
                for &p in &r {
                    seen[p as usize] = false;
                }
                charge(r.len())?;
                r.sort_unstable();
                Ok(r)
            },
        )
        .collect::<Result<_, NumericalError>>()?;
    let mut row_offsets = Vec::with_capacity(n + 1);
    row_offsets.push(0);
    for r in &rows {
        row_offsets.push(row_offsets.last().unwrap() + r.len());
    }
    Ok((row_offsets, rows.into_iter().flatten().collect()))
}

/// The degree-of-freedom level (CSC column pointers and row indices): column
/// point `q` has `free_count(q)` columns, each with `Σ_{p ∈ rows(q)}
/// free_count(p)` rows (none outside the columns `keep` flags).
fn dof_columns(
    dofs: &DofMap,
    row_offsets: &[usize],
    row_points: &[u32],
    keep: Option<&[bool]>,
) -> (Vec<usize>, Vec<usize>) {
    let n = row_offsets.len() - 1;
    let free_count: Vec<usize> = (0..n).map(|i| dofs.free_count(i)).collect();
    let entries_per_column: Vec<usize> = (0..n)
        .into_par_iter()
        .map(|q| {
            if keep.is_some_and(|k| !k[q]) {
                return 0;
            }
            row_points[row_offsets[q]..row_offsets[q + 1]]
                .iter()
                .map(|&p| free_count[p as usize])
                .sum()
        })
        .collect();
    let mut col_ptr = Vec::with_capacity(dofs.n_free() + 1);
    col_ptr.push(0);
    let mut point_value_offsets = Vec::with_capacity(n + 1);
    point_value_offsets.push(0);
    for q in 0..n {
        for _ in 0..free_count[q] {
            col_ptr.push(col_ptr.last().unwrap() + entries_per_column[q]);
        }
        point_value_offsets.push(*col_ptr.last().unwrap());
    }
    let mut row_idx = vec![0usize; *col_ptr.last().unwrap()];
    split_at_offsets(&mut row_idx, &point_value_offsets)
        .into_par_iter()
        .enumerate()
        .for_each(|(q, chunk)| {
            if chunk.is_empty() {
                return;
            }
            let column: Vec<usize> = row_points[row_offsets[q]..row_offsets[q + 1]]
                .iter()
                .flat_map(|&p| (0..dofs.d).map(move |r| dofs.free_index[3 * p as usize + r]))
                .filter(|&k| k != super::dofs::PRESCRIBED)
                .map(|k| k as usize)
                .collect();
            for dest in chunk.chunks_mut(column.len().max(1)) {
                dest.copy_from_slice(&column[..dest.len()]);
            }
        });
    (col_ptr, row_idx)
}
