//! PETSc as the linear solver of an MPI run (`solver.method = "petsc"`, in a
//! build with the `mpi` feature): a thin FFI over the functions used, owners
//! of PETSc's objects that destroy them when dropped, and the solve.
//!
//! **What is distributed: the assembly and the linear solves** (static and
//! quasi-static fracture). Every process
//! reads the scene and discretises the whole body (replicated: points, bonds
//! and the point-level pattern, a few KB per point), then takes its part of
//! the points (recursive coordinate bisection, [`Numbering`], balanced by the
//! stored entries of `K` in their rows) and assembles only the columns of `K` of its
//! own points and of their ghost points, the points coupled to them (within
//! a horizon for the bond-based model, two for the shear model, whose bonds
//! couple neighbours of neighbours: [`assembled_columns`]). Its rows of `K`,
//! gathered from those columns, go to PETSc, which solves with CG (GMRES,
//! preconditioned on the right, for a non-symmetric `K`) and algebraic
//! multigrid (GAMG) given the rigid motions of the points as its near-null
//! space, to a relative true residual `‖b − K x‖/‖b‖` of [`GMRES_TOLERANCE`],
//! checked afterwards with PETSc's product on those rows. The solution is
//! gathered on every process
//! ([`VecScatterCreateToAll`](ffi::VecScatterCreateToAll)). A check that one
//! process fails ([`on_every_process`]) stops all of them, so that none goes
//! on alone into PETSc's collective calls.
//!
//! **Fracture re-solves.** After bonds break, the driver refills the changed
//! columns of `K` on every process (each its own and ghost columns); the new
//! values of this process's rows go into PETSc's matrix in place (the same
//! pattern: a broken bond leaves zeros, [`Solver::update`]), and the Krylov
//! method starts from the previous answer with the preconditioner built for
//! an earlier `K` (`KSPSetReusePreconditioner`, `KSPSetInitialGuessNonzero`),
//! and a monitor keeps the first iterate whose residual is below
//! [`CHECKPOINT_FACTOR`](super::pipeline::CHECKPOINT_FACTOR) times the
//! tolerance, the error estimate the fracture driver's decisions are checked
//! against ([`Solver::solve_from`]). PETSc's convergence test is relative to `‖b‖`
//! (its default), as dhpd's own. When a re-solve needs more iterations than
//! the pipeline's refactorisation threshold, everything is set up afresh.
//! Every process holds the same bonds and receives the same answer, so each
//! decides the same bonds to break.
//!
//! With `solver.petsc_solver = "mumps"` PETSc factorises instead, by MUMPS's
//! distributed sparse LU (an external package of Debian's PETSc), applied once
//! (`-ksp_type preonly`), its residual checked in the same way.
//!
//! **Unknowns.** PETSc's rows are `d` per point with a free component (block
//! size `d`, as GAMG's rigid-motion near-null space needs). A prescribed
//! component of such a point (a roller) is an identity row scaled by the mean
//! diagonal of `K`, with a zero right-hand side: decoupled, its answer is zero
//! and is dropped. Fully prescribed points have no row.
//!
//! **Options.** `KSPSetFromOptions` runs after dhpd's choices, so PETSc's
//! options database overrides them: `dhpd run scene.toml -- -ksp_monitor
//! -pc_gamg_threshold 0.02` (the options after `--` go to [`Petsc::init`]) or
//! the `PETSC_OPTIONS` environment variable.
//!
//! **Why an FFI.** No maintained Rust binding of PETSc exists (petsc-rs, a
//! work in progress, builds its bindings with bindgen and rsmpi); the ~55 C
//! functions used here are stable API. Their declarations follow PETSc 3.18's
//! headers (`petscsys.h`, `petscvec.h`, `petscmat.h`, `petscksp.h`,
//! `petscpc.h`) as Debian's `petsc-dev` builds it: `PetscInt` 32-bit,
//! `PetscScalar` `f64`, and Open MPI, whose `MPI_Comm` is a pointer. Every
//! error code is checked and returned as [`NumericalError::Petsc`] naming the
//! call; destroy functions' codes, in `Drop`, cannot be returned and are
//! ignored.

use super::{Layout, GMRES_TOLERANCE};
use super::{GMRES_RESTART, ITERATIVE_BUDGET};
use crate::assembly::dofs::PRESCRIBED;
use crate::assembly::pattern::Pattern;
use crate::error::{Error, NumericalError};
use crate::scene::solver::PetscSolver;
use serde::Serialize;
use std::cell::Cell;
use std::ffi::{c_char, c_int, CStr};
use std::ptr::{null, null_mut};

mod ffi;

use ffi::PetscInt;

/// Calls a PETSc (or MPI) function and turns a non-zero code into
/// [`NumericalError::Petsc`] naming it.
macro_rules! call {
    ($f:ident($($arg:expr),* $(,)?)) => {
        // SAFETY: the arguments are live PETSc objects owned here and
        // pointers to buffers of the sizes PETSc reads or writes.
        check(stringify!($f), unsafe { ffi::$f($($arg),*) })
    };
}

/// `Err` naming `call` for a non-zero PETSc error `code`, with PETSc's text.
fn check(call: &'static str, code: ffi::PetscErrorCode) -> Result<(), Error> {
    if code == 0 {
        return Ok(());
    }
    let mut text: *const c_char = null();
    // SAFETY: PETSc points `text` at a static string (or leaves it null).
    let known = unsafe { ffi::PetscErrorMessage(code, &mut text, null_mut()) } == 0;
    let message = if known && !text.is_null() {
        // SAFETY: a NUL-terminated static string.
        unsafe { CStr::from_ptr(text) }
            .to_string_lossy()
            .into_owned()
    } else {
        "no message".into()
    };
    Err(NumericalError::Petsc {
        call,
        code,
        message,
    }
    .into())
}

mod partition;
mod processes;

pub(crate) use partition::{assembled_columns, asymmetry, mean_diagonal};
use partition::{changed_rows, local_rows, petsc_int, LocalRows, Numbering, SomeRows};
use processes::{comm_query, ensure_initialized};
pub use processes::{on_every_process, share_path, Petsc};
pub(crate) use processes::{sum_each_over_processes, sum_over_processes, Processes};

/// What a PETSc solve used and did (`summary.json`).
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct PetscReport {
    /// MPI processes.
    pub processes: usize,
    /// PETSc's rows (`d` per point with a free component).
    pub rows: usize,
    /// Krylov method (after the options database).
    pub ksp: String,
    /// Preconditioner (after the options database).
    pub pc: String,
    /// Iterations.
    pub iterations: usize,
    /// `KSPConvergedReason`, as PETSc names it.
    pub converged_reason: String,
    /// The stored entries of `K` in each process's rows (identity rows
    /// included): the balance of the partition.
    pub entries_per_process: Vec<usize>,
}

/// What a re-solve from an initial guess did ([`Solver::solve_from`]).
pub(super) struct Resolved {
    pub(super) iterations: usize,
    /// `‖b − K x‖/‖b‖` of the last iterate.
    pub(super) residual: f64,
    /// Reached the tolerance within the iterations allowed.
    pub(super) converged: bool,
    /// The iterate at the checkpoint, when one was asked for.
    pub(super) earlier: Option<Vec<f64>>,
}

/// The distributed vector `v` (PETSc's `rows` rows) whole on every process,
/// in dhpd's unknowns (`numbering`), into `x`.
fn gather(v: ffi::Vec, rows: usize, numbering: &Numbering, x: &mut [f64]) -> Result<(), Error> {
    let (mut scatter, mut all) = (Scatter(null_mut()), Vector(null_mut()));
    call!(VecScatterCreateToAll(v, &mut scatter.0, &mut all.0))?;
    let mode = (ffi::INSERT_VALUES, ffi::SCATTER_FORWARD);
    call!(VecScatterBegin(scatter.0, v, all.0, mode.0, mode.1))?;
    call!(VecScatterEnd(scatter.0, v, all.0, mode.0, mode.1))?;
    let mut data: *const f64 = null();
    call!(VecGetArrayRead(all.0, &mut data))?;
    if rows > 0 {
        // SAFETY: the gathered vector holds every row.
        let all = unsafe { std::slice::from_raw_parts(data, rows) };
        x.iter_mut()
            .zip(&numbering.rows)
            .for_each(|(v, &r)| *v = all[r as usize]);
    }
    call!(VecRestoreArrayRead(all.0, &mut data))
}

/// What the Krylov monitor [`keep_checkpoint`] keeps: the first iterate
/// whose residual norm is at most `threshold` (absolute; negative: none is
/// wanted), copied into `iterate`.
///
/// PETSc holds a pointer to it while the solver exists, so its fields change
/// through shared references only (`Cell`).
struct Checkpoint {
    threshold: Cell<f64>,
    kept: Cell<bool>,
    iterate: Vector,
}

/// The Krylov monitor that keeps the checkpoint iterate ([`Checkpoint`]) in
/// the one run to the tolerance (CG updates its iterate at every step, GMRES
/// builds it from its basis: `KSPBuildSolution` does either).
unsafe extern "C" fn keep_checkpoint(
    ksp: ffi::KSP,
    _iteration: PetscInt,
    norm: f64,
    context: *mut std::ffi::c_void,
) -> ffi::PetscErrorCode {
    // SAFETY: `context` is the `Checkpoint` the solver owns, alive while its
    // KSP is, and PETSc calls the monitor from the solve on this thread only.
    let checkpoint = unsafe { &*(context as *const Checkpoint) };
    if checkpoint.kept.get() || !(norm <= checkpoint.threshold.get()) {
        return 0;
    }
    checkpoint.kept.set(true);
    // SAFETY: a live KSP in its solve and a vector of its layout.
    unsafe { ffi::KSPBuildSolution(ksp, checkpoint.iterate.0, null_mut()) }
}

/// The entry of dhpd's `values` in a PETSc row holding the free unknown `k`
/// (zero in an identity row).
fn of_row(values: &[f64], k: u32) -> f64 {
    match k {
        PRESCRIBED => 0.0,
        k => values[k as usize],
    }
}

/// Owns a `Mat`.
struct Matrix(ffi::Mat);
/// Owns a `Vec`.
struct Vector(ffi::Vec);
/// Owns a `KSP` (and through it its `PC`).
struct Krylov(ffi::KSP);
/// Owns a `MatNullSpace`.
struct NullSpace(ffi::MatNullSpace);
/// Owns a `VecScatter`.
struct Scatter(ffi::VecScatter);

macro_rules! destroy_on_drop {
    ($($owner:ident: $destroy:ident),*) => {$(
        impl Drop for $owner {
            fn drop(&mut self) {
                if !self.0.is_null() {
                    // SAFETY: created by PETSc and owned here alone.
                    unsafe { ffi::$destroy(&mut self.0) };
                }
            }
        }
    )*};
}

destroy_on_drop!(
    Matrix: MatDestroy,
    Vector: VecDestroy,
    Krylov: KSPDestroy,
    NullSpace: MatNullSpaceDestroy,
    Scatter: VecScatterDestroy
);

impl Vector {
    /// Writes this process's entries from `fill` (index local to the process).
    fn write(&mut self, fill: impl Fn(usize) -> f64, local: usize) -> Result<(), Error> {
        let mut data: *mut f64 = null_mut();
        call!(VecGetArray(self.0, &mut data))?;
        if local > 0 {
            // SAFETY: PETSc's array of this process's `local` entries.
            let slice = unsafe { std::slice::from_raw_parts_mut(data, local) };
            slice.iter_mut().enumerate().for_each(|(r, v)| *v = fill(r));
        }
        call!(VecRestoreArray(self.0, &mut data))
    }
}

/// A distributed system set up in PETSc: the matrix, the Krylov solver with
/// its multigrid built, and the vectors of the solve.
pub(super) struct Solver {
    krylov: Krylov,
    /// The monitor's state (dropped after the `KSP` that points to it).
    checkpoint: Box<Checkpoint>,
    x: Vector,
    b: Vector,
    matrix: Matrix,
    /// PETSc's rows in all.
    global_rows: usize,
    /// The points' parts and PETSc's row of every free unknown of dhpd.
    numbering: Numbering,
    /// This process's rows.
    range: std::ops::Range<usize>,
    /// The free unknown of each of this process's rows (`PRESCRIBED`: an
    /// identity row).
    owned: Vec<u32>,
    /// The stored entries of `K` on all processes (identity rows left out).
    pub(super) stored_entries: usize,
    /// The stored entries in each process's rows (identity rows included).
    entries_per_process: Vec<usize>,
    processes: usize,
    /// The last solve's report.
    pub(super) report: Option<PetscReport>,
}

impl Solver {
    /// Hands this process's rows of `K` (`values` on `pattern`, which holds
    /// at least the [`assembled_columns`]: PETSc wants rows where dhpd stores
    /// columns) to PETSc, and sets up CG (GMRES if not `symmetric`) with GAMG
    /// and the rigid motions of the points of `layout`, or MUMPS's LU
    /// (`solver`).
    pub(super) fn new(
        pattern: &Pattern,
        values: &[f64],
        layout: Layout,
        symmetric: bool,
        solver: PetscSolver,
    ) -> Result<Self, Error> {
        ensure_initialized()?;
        // SAFETY: PETSc is initialised, so this global is set.
        let comm = unsafe { ffi::PETSC_COMM_WORLD };
        let (rank, processes) = (
            comm_query(ffi::MPI_Comm_rank),
            comm_query(ffi::MPI_Comm_size),
        );
        let numbering = Numbering::new(layout, processes)?;
        let d = layout.d();
        let (first, last) = (numbering.bounds[rank] * d, numbering.bounds[rank + 1] * d);
        let LocalRows {
            offsets,
            columns,
            values: entries,
            owned,
            stored,
        } = on_every_process(local_rows(pattern, values, layout, &numbering, first..last))?;
        let stored_entries = sum_over_processes(stored as f64) as usize;
        let mut per_process = vec![0.0; processes];
        per_process[rank] = columns.len() as f64;
        sum_each_over_processes(&mut per_process);
        let entries_per_process = per_process.iter().map(|&e| e as usize).collect();
        let n_local = petsc_int(last - first, "rows")?;
        let n_global = petsc_int(numbering.points.len() * d, "rows")?;
        let mut matrix = Matrix(null_mut());
        call!(MatCreate(comm, &mut matrix.0))?;
        call!(MatSetSizes(matrix.0, n_local, n_local, n_global, n_global))?;
        call!(MatSetBlockSize(matrix.0, d as PetscInt))?;
        call!(MatSetType(matrix.0, c"aij".as_ptr()))?;
        // Each is a no-op for the other type (one process: sequential AIJ);
        // both copy the rows and assemble.
        let (i, j, v) = (offsets.as_ptr(), columns.as_ptr(), entries.as_ptr());
        call!(MatSeqAIJSetPreallocationCSR(matrix.0, i, j, v))?;
        call!(MatMPIAIJSetPreallocationCSR(matrix.0, i, j, v))?;
        drop((offsets, columns, entries));

        let mut coordinates = Vector(null_mut());
        call!(MatCreateVecs(matrix.0, &mut coordinates.0, null_mut()))?;
        let point = |r: usize| numbering.points[(first + r) / d];
        coordinates.write(|r| layout.x[point(r)][(first + r) % d], last - first)?;
        let mut rigid = NullSpace(null_mut());
        call!(MatNullSpaceCreateRigidBody(coordinates.0, &mut rigid.0))?;
        call!(MatSetNearNullSpace(matrix.0, rigid.0))?;

        let (mut x, mut b) = (Vector(null_mut()), Vector(null_mut()));
        call!(MatCreateVecs(matrix.0, &mut x.0, &mut b.0))?;
        let mut iterate = Vector(null_mut());
        call!(VecDuplicate(x.0, &mut iterate.0))?;
        let checkpoint = Box::new(Checkpoint {
            threshold: Cell::new(-1.0),
            kept: Cell::new(false),
            iterate,
        });
        let mut krylov = Krylov(null_mut());
        call!(KSPCreate(comm, &mut krylov.0))?;
        let context = &*checkpoint as *const Checkpoint as *mut std::ffi::c_void;
        call!(KSPMonitorSet(krylov.0, keep_checkpoint, context, None))?;
        call!(KSPSetOperators(krylov.0, matrix.0, matrix.0))?;
        if symmetric {
            call!(KSPSetType(krylov.0, c"cg".as_ptr()))?;
            call!(KSPSetNormType(krylov.0, ffi::KSP_NORM_UNPRECONDITIONED))?;
        } else {
            call!(KSPSetType(krylov.0, c"gmres".as_ptr()))?;
            call!(KSPSetPCSide(krylov.0, ffi::PC_RIGHT))?;
            call!(KSPGMRESSetRestart(krylov.0, GMRES_RESTART as PetscInt))?;
        }
        let mut pc = null_mut();
        call!(KSPGetPC(krylov.0, &mut pc))?;
        match solver {
            PetscSolver::Gamg => call!(PCSetType(pc, c"gamg".as_ptr()))?,
            PetscSolver::Mumps => {
                // The factor applied once; the residual check below says how
                // well (a Krylov method over it: -ksp_type gmres).
                call!(KSPSetType(krylov.0, c"preonly".as_ptr()))?;
                call!(PCSetType(pc, c"lu".as_ptr()))?;
                call!(PCFactorSetMatSolverType(pc, c"mumps".as_ptr()))?;
            }
        }
        call!(KSPSetTolerances(
            krylov.0,
            GMRES_TOLERANCE,
            ffi::PETSC_DEFAULT,
            ffi::PETSC_DEFAULT,
            ITERATIVE_BUDGET as PetscInt
        ))?;
        call!(KSPSetFromOptions(krylov.0))?;
        call!(KSPSetUp(krylov.0))?;
        Ok(Solver {
            krylov,
            checkpoint,
            x,
            b,
            matrix,
            global_rows: numbering.points.len() * d,
            numbering,
            range: first..last,
            owned,
            stored_entries,
            entries_per_process,
            processes,
            report: None,
        })
    }

    /// Solves `K x = rhs` (every process passes the whole `rhs` and receives
    /// the whole `x`); the iterations and the relative residual
    /// `‖b − K x‖/‖b‖` of PETSc's rows (its product with the rows dhpd
    /// assembled: no process holds all of `K`); an error when PETSc's Krylov
    /// method did not converge.
    pub(super) fn solve(&mut self, rhs: &[f64], x: &mut [f64]) -> Result<(usize, f64), Error> {
        self.write_rhs(rhs)?;
        call!(KSPSolve(self.krylov.0, self.b.0, self.x.0))?;
        let (mut iterations, mut reason) = (0, 0);
        call!(KSPGetIterationNumber(self.krylov.0, &mut iterations))?;
        call!(KSPGetConvergedReason(self.krylov.0, &mut reason))?;
        let report = self.report(iterations as usize, reason)?;
        if reason < 0 {
            return Err(NumericalError::Solver(format!(
                "PETSc's {} preconditioned by {} did not converge ({} after {} iterations, \
                 relative tolerance {GMRES_TOLERANCE:.0e}); PETSc's options (-ksp_monitor, \
                 -ksp_type, -pc_type) show or change what it does, and solver.method = \
                 \"iterative\" solves on one process",
                report.ksp, report.pc, report.converged_reason, report.iterations
            ))
            .into());
        }
        let residual = self.residual()?;
        self.gather(x)?;
        self.report = Some(report);
        Ok((iterations as usize, residual))
    }

    /// Hands new values of `K` (`values` on the same `pattern`: bonds that
    /// broke leave zeros where they were) to PETSc's matrix in place, row by
    /// row: the rows with an entry in a `changed` point column (`None`:
    /// every row). The preconditioner is left as it was built.
    pub(super) fn update(
        &mut self,
        pattern: &Pattern,
        values: &[f64],
        layout: Layout,
        changed: Option<&[bool]>,
    ) -> Result<(), Error> {
        let range = self.range.clone();
        let rows = on_every_process(match changed {
            Some(changed) => changed_rows(pattern, values, layout, &self.numbering, range, changed),
            None => {
                local_rows(pattern, values, layout, &self.numbering, range.clone()).map(|all| {
                    SomeRows {
                        rows: (range.start..range.end).map(|r| r as PetscInt).collect(),
                        offsets: all.offsets.iter().map(|&o| o as usize).collect(),
                        columns: all.columns,
                        values: all.values,
                    }
                })
            }
        })?;
        let set = (0..rows.rows.len()).try_for_each(|r| {
            let (a, b) = (rows.offsets[r], rows.offsets[r + 1]);
            call!(MatSetValues(
                self.matrix.0,
                1,
                &rows.rows[r],
                (b - a) as PetscInt,
                rows.columns[a..b].as_ptr(),
                rows.values[a..b].as_ptr(),
                ffi::INSERT_VALUES
            ))
        });
        // Every process reaches the collective assembly, or none does.
        on_every_process(set)?;
        call!(MatAssemblyBegin(self.matrix.0, ffi::MAT_FINAL_ASSEMBLY))?;
        call!(MatAssemblyEnd(self.matrix.0, ffi::MAT_FINAL_ASSEMBLY))
    }

    /// Re-solves `K x = rhs` from the initial guess `x` (the whole vector on
    /// every process, overwritten by the last iterate) with the
    /// preconditioner as it was built, to the relative residual `tolerance`
    /// within `cap` iterations: converged when PETSc's test passed and the
    /// true residual `‖b − K x‖/‖b‖` is within `tolerance`, as dhpd's own CG
    /// asks. With a `checkpoint` (above `tolerance`) it also keeps the first
    /// iterate whose relative residual is at most that ([`Resolved::earlier`];
    /// the initial guess if it already is, none if no iteration ran).
    pub(super) fn solve_from(
        &mut self,
        rhs: &[f64],
        x: &mut [f64],
        tolerance: f64,
        cap: usize,
        checkpoint: Option<f64>,
    ) -> Result<Resolved, Error> {
        self.write_rhs(rhs)?;
        self.write_x(x)?;
        let mut norm_b = 0.0;
        call!(VecNorm(self.b.0, ffi::NORM_2, &mut norm_b))?;
        let keep = &self.checkpoint;
        keep.threshold.set(checkpoint.map_or(-1.0, |c| c * norm_b));
        keep.kept.set(false);
        call!(KSPSetInitialGuessNonzero(self.krylov.0, ffi::PETSC_TRUE))?;
        call!(KSPSetReusePreconditioner(self.krylov.0, ffi::PETSC_TRUE))?;
        call!(KSPSetTolerances(
            self.krylov.0,
            tolerance,
            ffi::PETSC_DEFAULT,
            ffi::PETSC_DEFAULT,
            petsc_int(cap.max(1), "iterations")?
        ))?;
        let solved = call!(KSPSolve(self.krylov.0, self.b.0, self.x.0));
        keep.threshold.set(-1.0);
        solved?;
        let (mut iterations, mut reason) = (0, 0);
        call!(KSPGetIterationNumber(self.krylov.0, &mut iterations))?;
        call!(KSPGetConvergedReason(self.krylov.0, &mut reason))?;
        let iterations = iterations as usize;
        self.report = Some(self.report(iterations, reason)?);
        let earlier = match keep.kept.get() && iterations > 0 {
            true => {
                let mut at_checkpoint = vec![0.0; x.len()];
                let iterate = keep.iterate.0;
                gather(
                    iterate,
                    self.global_rows,
                    &self.numbering,
                    &mut at_checkpoint,
                )?;
                Some(at_checkpoint)
            }
            false => None,
        };
        let residual = self.residual()?;
        self.gather(x)?;
        Ok(Resolved {
            iterations,
            residual,
            converged: reason > 0 && residual <= tolerance,
            earlier,
        })
    }

    /// `‖rhs − K x‖/‖rhs‖` with PETSc's product.
    pub(super) fn residual_of(&mut self, rhs: &[f64], x: &[f64]) -> Result<f64, Error> {
        self.write_rhs(rhs)?;
        self.write_x(x)?;
        self.residual()
    }

    /// Writes this process's rows of `rhs` into `b` (zero in identity rows).
    fn write_rhs(&mut self, rhs: &[f64]) -> Result<(), Error> {
        let owned = &self.owned;
        self.b.write(|r| of_row(rhs, owned[r]), owned.len())
    }

    /// Writes this process's rows of `x` into PETSc's `x` (zero in identity rows).
    fn write_x(&mut self, x: &[f64]) -> Result<(), Error> {
        let owned = &self.owned;
        self.x.write(|r| of_row(x, owned[r]), owned.len())
    }

    /// `‖b − K x‖/‖b‖` of the last solve, with PETSc's product.
    fn residual(&self) -> Result<f64, Error> {
        let mut r = Vector(null_mut());
        call!(VecDuplicate(self.b.0, &mut r.0))?;
        call!(MatMult(self.matrix.0, self.x.0, r.0))?;
        call!(VecAYPX(r.0, -1.0, self.b.0))?;
        let (mut norm_r, mut norm_b) = (0.0, 0.0);
        call!(VecNorm(r.0, ffi::NORM_2, &mut norm_r))?;
        call!(VecNorm(self.b.0, ffi::NORM_2, &mut norm_b))?;
        Ok(if norm_b > 0.0 {
            norm_r / norm_b
        } else if norm_r == 0.0 {
            0.0
        } else {
            f64::INFINITY
        })
    }

    /// The whole solution on every process, in dhpd's unknowns.
    fn gather(&mut self, x: &mut [f64]) -> Result<(), Error> {
        gather(self.x.0, self.global_rows, &self.numbering, x)
    }

    /// The report of a solve that took `iterations` and stopped for `reason`.
    fn report(&self, iterations: usize, reason: c_int) -> Result<PetscReport, Error> {
        let (mut ksp, mut pc_type, mut pc) = (null(), null(), null_mut());
        call!(KSPGetType(self.krylov.0, &mut ksp))?;
        call!(KSPGetPC(self.krylov.0, &mut pc))?;
        call!(PCGetType(pc, &mut pc_type))?;
        let text = |s: *const c_char| {
            if s.is_null() {
                String::new()
            } else {
                // SAFETY: PETSc's NUL-terminated type names and reasons.
                unsafe { CStr::from_ptr(s) }.to_string_lossy().into_owned()
            }
        };
        // SAFETY: PETSc's table covers every KSPConvergedReason (it is
        // shifted so that negative reasons index before its start).
        let reason_name = unsafe { *ffi::KSPConvergedReasons.offset(reason as isize) };
        Ok(PetscReport {
            processes: self.processes,
            rows: self.global_rows,
            ksp: text(ksp),
            pc: text(pc_type),
            iterations,
            converged_reason: text(reason_name),
            entries_per_process: self.entries_per_process.clone(),
        })
    }
}
