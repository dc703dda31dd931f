//! How `K` is split over the processes: PETSc's numbering from the points'
//! parts (`Layout::part`, cut by the setup before any bond is
//! searched; [`Numbering`]),
//! the columns a process assembles (its own points' and its ghost points'),
//! its rows gathered from them for PETSc ([`local_rows`]), and the asymmetry
//! of the distributed `K`.

use super::ffi::{self, PetscInt};
use super::processes::{comm_query, ensure_initialized, sum_over_processes};
use super::Layout;
use crate::assembly::dofs::PRESCRIBED;
use crate::assembly::pattern::Pattern;
use crate::error::{Error, NumericalError};

/// The numbering of the free unknowns over the processes of the run and this
/// process's rank (every process computes the same numbering).
fn this_part(layout: Layout) -> Result<(Numbering, usize), Error> {
    ensure_initialized()?;
    let (rank, processes) = (
        comm_query(ffi::MPI_Comm_rank),
        comm_query(ffi::MPI_Comm_size),
    );
    Ok((Numbering::new(layout, processes)?, rank))
}

/// The free unknowns of this process's points, in increasing order.
fn own_unknowns(layout: Layout) -> Result<Vec<usize>, Error> {
    let dofs = layout.dofs;
    let (numbering, rank) = this_part(layout)?;
    Ok(numbering
        .part(rank)
        .iter()
        .flat_map(|&q| (0..dofs.d).map(move |c| dofs.free_index[3 * q + c]))
        .filter(|&k| k != PRESCRIBED)
        .map(|k| k as usize)
        .collect())
}

/// The point columns of `K` this process assembles (`pattern`: the point
/// level): those of its own points ([`Numbering`]) and of every point coupled
/// to them (its ghost points: within a bond length for the bond-based model,
/// two for the shear model), whose columns hold the rest of its own rows.
pub(crate) fn assembled_columns(pattern: &Pattern, layout: Layout) -> Result<Vec<bool>, Error> {
    let (numbering, rank) = this_part(layout)?;
    let mut keep = vec![false; pattern.row_offsets.len() - 1];
    for &q in numbering.part(rank) {
        pattern
            .rows(q)
            .iter()
            .for_each(|&p| keep[p as usize] = true);
    }
    Ok(keep)
}

/// `‖K − Kᵀ‖_F / ‖K‖_F` of a distributed `K` (`values` on this process's
/// columns, [`assembled_columns`]): each process sums over its own columns,
/// whose transposed entries lie in its ghost columns (a collective call).
pub(crate) fn asymmetry(pattern: &Pattern, values: &[f64], layout: Layout) -> Result<f64, Error> {
    let own = own_unknowns(layout)?;
    let (mut skew, mut total) = (0.0, 0.0);
    // Own columns k in increasing order (a part's points are in point order):
    // row k of every column r is reached in increasing order too, so a cursor
    // per column finds it by moving forward (past the rows of other
    // processes' points), as a transposition.
    let mut cursor = pattern.col_ptr.clone();
    for k in own {
        for p in pattern.col_ptr[k]..pattern.col_ptr[k + 1] {
            let r = pattern.row_idx[p];
            let (t, end) = (&mut cursor[r], pattern.col_ptr[r + 1]);
            while *t < end && pattern.row_idx[*t] < k {
                *t += 1;
            }
            if *t == end || pattern.row_idx[*t] != k {
                return Err(NumericalError::Solver(format!(
                    "column {r} of K lacks row {k} on this process (a defect of the \
                     partition's ghost points)"
                ))
                .into());
            }
            skew += (values[p] - values[*t]).powi(2);
            total += values[p] * values[p];
        }
    }
    let (skew, total) = (sum_over_processes(skew), sum_over_processes(total));
    Ok(if total > 0.0 {
        (skew / total).sqrt()
    } else {
        0.0
    })
}

/// The mean `|K_kk|` over the free unknowns of a distributed `K` (`values`
/// on this process's columns, [`assembled_columns`]), each process summing
/// its own points' columns (a collective call).
pub(crate) fn mean_diagonal(
    pattern: &Pattern,
    values: &[f64],
    layout: Layout,
) -> Result<f64, Error> {
    let own = own_unknowns(layout)?;
    let sum: f64 = own
        .iter()
        .map(|&k| {
            (pattern.col_ptr[k]..pattern.col_ptr[k + 1])
                .find(|&p| pattern.row_idx[p] == k)
                .map_or(0.0, |p| values[p].abs())
        })
        .sum();
    let (sum, count) = (
        sum_over_processes(sum),
        sum_over_processes(own.len() as f64),
    );
    Ok(if sum > 0.0 && count > 0.0 {
        sum / count
    } else {
        1.0
    })
}

/// `n` as a `PetscInt`, or an error naming `what` (32-bit indices).
pub(super) fn petsc_int(n: usize, what: &str) -> Result<PetscInt, Error> {
    PetscInt::try_from(n).map_err(|_| {
        NumericalError::Solver(format!(
            "{n} {what} exceed the 32-bit indices of this PETSc (a 64-bit-index build, \
             Debian's libpetsc64-real-dev, would need dhpd's PetscInt changed to i64)"
        ))
        .into()
    })
}

/// PETSc's numbering: `d` rows per point with a free component, the points
/// split into one part per process (`Layout::part`); PETSc's blocks are the
/// parts in turn, each in dhpd's point order.
pub(super) struct Numbering {
    /// The points with a free component (PETSc's block `s` is `points[s]`).
    pub(super) points: Vec<usize>,
    /// PETSc's row of every free unknown.
    pub(super) rows: Vec<PetscInt>,
    /// Process `r` owns the blocks `bounds[r]..bounds[r + 1]`.
    pub(super) bounds: Vec<usize>,
}

impl Numbering {
    /// The points of process `rank`, in point order.
    pub(super) fn part(&self, rank: usize) -> &[usize] {
        &self.points[self.bounds[rank]..self.bounds[rank + 1]]
    }

    /// The numbering of the free unknowns of `layout` split over `processes`
    /// by its parts (all on one process without them). Every process computes
    /// the same one.
    pub(super) fn new(layout: Layout, processes: usize) -> Result<Self, Error> {
        let dofs = layout.dofs;
        let d = dofs.d;
        let n = layout.x.len();
        let part_of = |i: usize| layout.part.map_or(0, |p| p[i] as usize);
        if layout.part.is_none() && processes > 1 {
            return Err(NumericalError::Solver(format!(
                "the points were not split over the {processes} processes of this run: the \
                 setup splits them when PETSc is initialised, so a library caller holds a \
                 dhpd::mpi::Petsc before it calls dhpd::check or dhpd::run"
            ))
            .into());
        }
        let mut by_part = vec![Vec::new(); processes.max(1)];
        for i in (0..n).filter(|&i| dofs.free_count(i) > 0) {
            by_part[part_of(i)].push(i);
        }
        let mut points: Vec<usize> = Vec::with_capacity(n);
        let mut bounds = vec![0];
        for part in by_part {
            points.extend(part);
            bounds.push(points.len());
        }
        petsc_int(points.len() * d, "rows")?;
        let mut block = vec![0; layout.x.len()];
        for (s, &i) in points.iter().enumerate() {
            block[i] = s;
        }
        let rows = dofs
            .free_dofs
            .iter()
            .map(|&(i, c)| (block[i as usize] * d + c as usize) as PetscInt)
            .collect();
        Ok(Numbering {
            points,
            rows,
            bounds,
        })
    }
}

/// One process's rows of `K` in CSR form with PETSc's column numbers.
pub(super) struct LocalRows {
    pub(super) offsets: Vec<PetscInt>,
    pub(super) columns: Vec<PetscInt>,
    pub(super) values: Vec<f64>,
    /// The free unknown of each row (`PRESCRIBED`: an identity row).
    pub(super) owned: Vec<u32>,
    /// Entries of `K` among them (identity rows left out).
    pub(super) stored: usize,
}

/// PETSc's rows `range` of `K` (module docs: identity rows for prescribed
/// components, scaled by the mean diagonal over all processes), gathered from
/// the columns this process assembled: row `k` of `K` has an entry in the
/// column of every unknown coupled to `k` (the pattern is structurally
/// symmetric), and the columns, walked in PETSc's order, give each row its
/// entries sorted.
pub(super) fn local_rows(
    pattern: &Pattern,
    values: &[f64],
    layout: Layout,
    numbering: &Numbering,
    range: std::ops::Range<usize>,
) -> Result<LocalRows, Error> {
    let d = layout.d();
    let free_index = &layout.dofs.free_index;
    let owned: Vec<u32> = range
        .clone()
        .map(|row| free_index[3 * numbering.points[row / d] + row % d])
        .collect();
    let length = |k: u32| match k {
        PRESCRIBED => 1,
        k => pattern.col_ptr[k as usize + 1] - pattern.col_ptr[k as usize],
    };
    let mut offsets = Vec::with_capacity(owned.len() + 1);
    offsets.push(0usize);
    for &k in &owned {
        offsets.push(offsets.last().expect("started") + length(k));
    }
    let entries = *offsets.last().expect("started");
    let stored = entries - owned.iter().filter(|&&k| k == PRESCRIBED).count();
    let mut columns = vec![0 as PetscInt; entries];
    let mut local_values = vec![0.0; entries];
    // The next free slot of each row, and the local row of each owned unknown.
    let mut next = offsets.clone();
    let mut local_row = vec![u32::MAX; numbering.rows.len()];
    let (mut diagonal, mut free_rows) = (0.0, 0usize);
    for (r, &k) in owned.iter().enumerate() {
        if k == PRESCRIBED {
            // In range: `Numbering::new` checked the rows' count.
            columns[offsets[r]] = (range.start + r) as PetscInt;
        } else {
            local_row[k as usize] = r as u32;
            free_rows += 1;
        }
    }
    // The columns in PETSc's order, so that each row's entries come sorted.
    let columns_in_order = numbering.points.iter().flat_map(|&i| {
        (0..d)
            .map(move |c| free_index[3 * i + c])
            .filter(|&k| k != PRESCRIBED)
            .map(|k| k as usize)
    });
    for column in columns_in_order {
        let petsc_column = numbering.rows[column];
        for p in pattern.col_ptr[column]..pattern.col_ptr[column + 1] {
            let row = pattern.row_idx[p];
            let r = local_row[row] as usize;
            if r == u32::MAX as usize {
                continue;
            }
            if row == column {
                diagonal += values[p].abs();
            }
            columns[next[r]] = petsc_column;
            local_values[next[r]] = values[p];
            next[r] += 1;
        }
    }
    let identity = sum_over_processes(diagonal) / sum_over_processes(free_rows as f64).max(1.0);
    for (r, &k) in owned.iter().enumerate() {
        if k == PRESCRIBED {
            local_values[offsets[r]] = identity;
        } else if next[r] != offsets[r + 1] {
            return Err(NumericalError::Solver(format!(
                "row {} of K is incomplete on this process: its ghost columns are missing \
                 (a defect of the partition)",
                range.start + r
            ))
            .into());
        }
    }
    Ok(LocalRows {
        offsets: offsets
            .iter()
            .map(|&o| petsc_int(o, "entries on one process"))
            .collect::<Result<_, _>>()?,
        columns,
        values: local_values,
        owned,
        stored,
    })
}

/// Some of this process's rows of `K` with PETSc's column numbers, each as
/// `values[offsets[r]..offsets[r + 1]]` at `columns[..]` of PETSc's row
/// `rows[r]` (unsorted).
pub(super) struct SomeRows {
    pub(super) rows: Vec<PetscInt>,
    pub(super) offsets: Vec<usize>,
    pub(super) columns: Vec<PetscInt>,
    pub(super) values: Vec<f64>,
}

/// The rows among PETSc's rows `range` (this process's) that hold an entry in
/// a `changed` point column of `K`: those of the points coupled to a changed
/// point (the pattern is structurally symmetric), each read from the columns
/// this process assembled. A superset: a broken bond changes only the rows
/// of changed points (its ends, or its owner's family), and a point the
/// driver holds has no intact bond left when it is held; the coupled rows
/// keep the update right whatever changes a column. Identity rows
/// (prescribed components) never change and are left out.
pub(super) fn changed_rows(
    pattern: &Pattern,
    values: &[f64],
    layout: Layout,
    numbering: &Numbering,
    range: std::ops::Range<usize>,
    changed: &[bool],
) -> Result<SomeRows, Error> {
    let d = layout.d();
    let free_index = &layout.dofs.free_index;
    let own = &numbering.points[range.start / d..range.end / d];
    let mut some = SomeRows {
        rows: Vec::new(),
        offsets: vec![0],
        columns: Vec::new(),
        values: Vec::new(),
    };
    for (s, &p) in own.iter().enumerate() {
        let coupled = pattern.rows(p);
        if !coupled.iter().any(|&q| changed[q as usize]) {
            continue;
        }
        for c in 0..d {
            let k = free_index[3 * p + c];
            if k == PRESCRIBED {
                continue;
            }
            for &q in coupled {
                for kk in (0..d).map(|c| free_index[3 * q as usize + c]) {
                    if kk == PRESCRIBED {
                        continue;
                    }
                    let kk = kk as usize;
                    let column = &pattern.row_idx[pattern.col_ptr[kk]..pattern.col_ptr[kk + 1]];
                    let Ok(at) = column.binary_search(&(k as usize)) else {
                        return Err(NumericalError::Solver(format!(
                            "column {kk} of K lacks row {k} on this process (a defect of \
                             the partition's ghost points)"
                        ))
                        .into());
                    };
                    some.columns.push(numbering.rows[kk]);
                    some.values.push(values[pattern.col_ptr[kk] + at]);
                }
            }
            some.rows.push(petsc_int(range.start + s * d + c, "rows")?);
            some.offsets.push(some.columns.len());
        }
    }
    Ok(some)
}
