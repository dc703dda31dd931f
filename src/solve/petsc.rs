//! PETSc as the linear solver of an MPI run (`solver.method = "petsc"`, in a
//! build with the `mpi` feature): a thin FFI over the functions used, owners
//! of PETSc's objects that destroy them when dropped, and the solve.
//!
//! **What is distributed: the assembly and the linear solve.** Every process
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
//! work in progress, builds its bindings with bindgen and rsmpi); the ~40 C
//! functions used here are stable API. Their declarations follow PETSc 3.18's
//! headers (`petscsys.h`, `petscvec.h`, `petscmat.h`, `petscksp.h`,
//! `petscpc.h`) as Debian's `petsc-dev` builds it: `PetscInt` 32-bit,
//! `PetscScalar` `f64`, and Open MPI, whose `MPI_Comm` is a pointer. Every
//! error code is checked and returned as [`NumericalError::Petsc`] naming the
//! call; destroy functions' codes, in `Drop`, cannot be returned and are
//! ignored.

use super::pipeline::{GMRES_RESTART, ITERATIVE_BUDGET};
use super::{Layout, GMRES_TOLERANCE};
use crate::assembly::dofs::{DofMap, PRESCRIBED};
use crate::assembly::pattern::Pattern;
use crate::error::{Error, InputError, NumericalError};
use crate::scene::solver::PetscSolver;
use serde::Serialize;
use std::ffi::{c_char, c_int, CStr, CString};
use std::path::{Path, PathBuf};
use std::ptr::{null, null_mut};

/// The C declarations (PETSc 3.18, Open MPI 4.1).
#[allow(
    non_snake_case,
    non_camel_case_types,
    non_upper_case_globals,
    clippy::upper_case_acronyms
)]
mod ffi {
    use std::ffi::{c_char, c_int, c_void};

    pub type PetscErrorCode = c_int;
    pub type PetscInt = i32;
    pub type PetscScalar = f64;
    pub type PetscReal = f64;
    /// `enum { PETSC_FALSE, PETSC_TRUE }`.
    pub type PetscBool = c_int;
    /// Open MPI's `MPI_Comm` (`struct ompi_communicator_t *`).
    pub type MPI_Comm = *mut c_void;

    /// Opaque PETSc objects, each behind a pointer.
    #[repr(C)]
    pub struct Opaque {
        _private: [u8; 0],
    }
    pub type Mat = *mut Opaque;
    pub type Vec = *mut Opaque;
    pub type VecScatter = *mut Opaque;
    pub type MatNullSpace = *mut Opaque;
    pub type KSP = *mut Opaque;
    pub type PC = *mut Opaque;

    /// `InsertMode::INSERT_VALUES`.
    pub const INSERT_VALUES: c_int = 1;
    /// `ScatterMode::SCATTER_FORWARD`.
    pub const SCATTER_FORWARD: c_int = 0;
    /// `KSPNormType::KSP_NORM_UNPRECONDITIONED`.
    pub const KSP_NORM_UNPRECONDITIONED: c_int = 2;
    /// `PCSide::PC_RIGHT`.
    pub const PC_RIGHT: c_int = 1;
    /// `NormType::NORM_2`.
    pub const NORM_2: c_int = 1;
    /// `PETSC_DEFAULT` (a tolerance left at PETSc's default).
    pub const PETSC_DEFAULT: PetscReal = -2.0;

    extern "C" {
        pub static PETSC_COMM_WORLD: MPI_Comm;
        /// Indexed by `KSPConvergedReason`, negative values included.
        pub static KSPConvergedReasons: *const *const c_char;

        /// Open MPI's predefined handles (`MPI_DOUBLE`, `MPI_BYTE` and `MPI_SUM` are
        /// their addresses).
        pub static ompi_mpi_double: Opaque;
        pub static ompi_mpi_byte: Opaque;
        pub static ompi_mpi_op_sum: Opaque;

        pub fn MPI_Comm_rank(comm: MPI_Comm, rank: *mut c_int) -> c_int;
        pub fn MPI_Comm_size(comm: MPI_Comm, size: *mut c_int) -> c_int;
        pub fn MPI_Allreduce(
            send: *const c_void,
            receive: *mut c_void,
            count: c_int,
            datatype: *const Opaque,
            op: *const Opaque,
            comm: MPI_Comm,
        ) -> c_int;
        pub fn MPI_Bcast(
            buffer: *mut c_void,
            count: c_int,
            datatype: *const Opaque,
            root: c_int,
            comm: MPI_Comm,
        ) -> c_int;

        pub fn PetscInitialize(
            argc: *mut c_int,
            args: *mut *mut *mut c_char,
            file: *const c_char,
            help: *const c_char,
        ) -> PetscErrorCode;
        pub fn PetscFinalize() -> PetscErrorCode;
        pub fn PetscInitialized(initialized: *mut PetscBool) -> PetscErrorCode;
        pub fn PetscErrorMessage(
            code: c_int,
            text: *mut *const c_char,
            specific: *mut *mut c_char,
        ) -> PetscErrorCode;

        pub fn MatCreate(comm: MPI_Comm, mat: *mut Mat) -> PetscErrorCode;
        pub fn MatSetSizes(
            mat: Mat,
            m: PetscInt,
            n: PetscInt,
            big_m: PetscInt,
            big_n: PetscInt,
        ) -> PetscErrorCode;
        pub fn MatSetBlockSize(mat: Mat, bs: PetscInt) -> PetscErrorCode;
        pub fn MatSetType(mat: Mat, kind: *const c_char) -> PetscErrorCode;
        pub fn MatSeqAIJSetPreallocationCSR(
            mat: Mat,
            i: *const PetscInt,
            j: *const PetscInt,
            v: *const PetscScalar,
        ) -> PetscErrorCode;
        pub fn MatMPIAIJSetPreallocationCSR(
            mat: Mat,
            i: *const PetscInt,
            j: *const PetscInt,
            v: *const PetscScalar,
        ) -> PetscErrorCode;
        pub fn MatCreateVecs(mat: Mat, right: *mut Vec, left: *mut Vec) -> PetscErrorCode;
        pub fn MatSetNearNullSpace(mat: Mat, space: MatNullSpace) -> PetscErrorCode;
        pub fn MatDestroy(mat: *mut Mat) -> PetscErrorCode;
        pub fn MatMult(mat: Mat, x: Vec, y: Vec) -> PetscErrorCode;
        pub fn MatNullSpaceCreateRigidBody(
            coords: Vec,
            space: *mut MatNullSpace,
        ) -> PetscErrorCode;
        pub fn MatNullSpaceDestroy(space: *mut MatNullSpace) -> PetscErrorCode;

        pub fn VecGetArray(v: Vec, a: *mut *mut PetscScalar) -> PetscErrorCode;
        pub fn VecRestoreArray(v: Vec, a: *mut *mut PetscScalar) -> PetscErrorCode;
        pub fn VecGetArrayRead(v: Vec, a: *mut *const PetscScalar) -> PetscErrorCode;
        pub fn VecRestoreArrayRead(v: Vec, a: *mut *const PetscScalar) -> PetscErrorCode;
        pub fn VecDestroy(v: *mut Vec) -> PetscErrorCode;
        pub fn VecDuplicate(v: Vec, copy: *mut Vec) -> PetscErrorCode;
        pub fn VecAYPX(y: Vec, beta: PetscScalar, x: Vec) -> PetscErrorCode;
        pub fn VecNorm(x: Vec, kind: c_int, value: *mut PetscReal) -> PetscErrorCode;
        pub fn VecScatterCreateToAll(
            v: Vec,
            scatter: *mut VecScatter,
            all: *mut Vec,
        ) -> PetscErrorCode;
        pub fn VecScatterBegin(
            scatter: VecScatter,
            x: Vec,
            y: Vec,
            insert: c_int,
            mode: c_int,
        ) -> PetscErrorCode;
        pub fn VecScatterEnd(
            scatter: VecScatter,
            x: Vec,
            y: Vec,
            insert: c_int,
            mode: c_int,
        ) -> PetscErrorCode;
        pub fn VecScatterDestroy(scatter: *mut VecScatter) -> PetscErrorCode;

        pub fn KSPCreate(comm: MPI_Comm, ksp: *mut KSP) -> PetscErrorCode;
        pub fn KSPSetOperators(ksp: KSP, a: Mat, p: Mat) -> PetscErrorCode;
        pub fn KSPSetType(ksp: KSP, kind: *const c_char) -> PetscErrorCode;
        pub fn KSPGetType(ksp: KSP, kind: *mut *const c_char) -> PetscErrorCode;
        pub fn KSPGetPC(ksp: KSP, pc: *mut PC) -> PetscErrorCode;
        pub fn PCSetType(pc: PC, kind: *const c_char) -> PetscErrorCode;
        pub fn PCGetType(pc: PC, kind: *mut *const c_char) -> PetscErrorCode;
        pub fn PCFactorSetMatSolverType(pc: PC, kind: *const c_char) -> PetscErrorCode;
        pub fn KSPSetTolerances(
            ksp: KSP,
            rtol: PetscReal,
            abstol: PetscReal,
            dtol: PetscReal,
            maxits: PetscInt,
        ) -> PetscErrorCode;
        pub fn KSPSetNormType(ksp: KSP, norm: c_int) -> PetscErrorCode;
        pub fn KSPSetPCSide(ksp: KSP, side: c_int) -> PetscErrorCode;
        pub fn KSPGMRESSetRestart(ksp: KSP, restart: PetscInt) -> PetscErrorCode;
        pub fn KSPSetFromOptions(ksp: KSP) -> PetscErrorCode;
        pub fn KSPSetUp(ksp: KSP) -> PetscErrorCode;
        pub fn KSPSolve(ksp: KSP, b: Vec, x: Vec) -> PetscErrorCode;
        pub fn KSPGetIterationNumber(ksp: KSP, its: *mut PetscInt) -> PetscErrorCode;
        pub fn KSPGetConvergedReason(ksp: KSP, reason: *mut c_int) -> PetscErrorCode;
        pub fn KSPDestroy(ksp: *mut KSP) -> PetscErrorCode;
    }
}

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

/// PETSc (and MPI) initialised for the life of this value: `PetscInitialize`
/// on [`Petsc::init`], `PetscFinalize` on drop. One per process; the command
/// line holds it for the whole run.
pub struct Petsc {
    /// The arguments PETSc was given; it keeps pointers to them until
    /// `PetscFinalize`.
    _args: Box<Arguments>,
}

/// `argc`/`argv` as C wants them, kept alive while PETSc is initialised.
struct Arguments {
    _strings: Vec<CString>,
    pointers: Vec<*mut c_char>,
    argc: c_int,
    argv: *mut *mut c_char,
}

impl Petsc {
    /// Initialises PETSc and MPI with PETSc `options` (`-ksp_monitor`, …) in
    /// its options database. PETSc's own signal handlers are turned off
    /// (`-no_signal_handler`): dhpd's handle SIGINT and SIGTERM.
    pub fn init(options: &[String]) -> Result<Self, Error> {
        if initialized()? {
            return Err(NumericalError::Solver("PETSc is already initialised".into()).into());
        }
        let strings = ["dhpd", "-no_signal_handler"]
            .into_iter()
            .map(String::from)
            .chain(options.iter().cloned())
            .map(|s| {
                CString::new(s).map_err(|_| {
                    InputError::new("PETSc options", "an option holds a NUL character")
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        let mut pointers: Vec<*mut c_char> = strings.iter().map(|s| s.as_ptr().cast_mut()).collect();
        pointers.push(null_mut());
        let mut args = Box::new(Arguments {
            argc: strings.len() as c_int,
            argv: null_mut(),
            _strings: strings,
            pointers,
        });
        args.argv = args.pointers.as_mut_ptr();
        let Arguments { argc, argv, .. } = &mut *args;
        call!(PetscInitialize(argc, argv, null(), null()))?;
        Ok(Petsc { _args: args })
    }

    /// This process's rank in `PETSC_COMM_WORLD` (0 prints and writes).
    pub fn rank(&self) -> usize {
        comm_query(ffi::MPI_Comm_rank)
    }

    /// The number of processes.
    pub fn size(&self) -> usize {
        comm_query(ffi::MPI_Comm_size)
    }
}

impl Drop for Petsc {
    fn drop(&mut self) {
        // SAFETY: initialised by `init`. PETSc objects live in a `Solver`,
        // which a static solve drops before it returns.
        unsafe { ffi::PetscFinalize() };
    }
}

/// `MPI_Comm_rank` or `MPI_Comm_size` of `PETSC_COMM_WORLD` (0 on failure,
/// which MPI's default error handler does not return from).
fn comm_query(query: unsafe extern "C" fn(ffi::MPI_Comm, *mut c_int) -> c_int) -> usize {
    let mut value = 0;
    // SAFETY: PETSc is initialised (the caller holds a `Petsc`, or checked).
    unsafe { query(ffi::PETSC_COMM_WORLD, &mut value) };
    value as usize
}

/// Whether PETSc is initialised in this process.
fn initialized() -> Result<bool, Error> {
    let mut flag: ffi::PetscBool = 0;
    call!(PetscInitialized(&mut flag))?;
    Ok(flag != 0)
}

/// The sum of `value` over every process (`MPI_Allreduce`; a collective
/// call). On a process where PETSc is not initialised (a library caller's
/// single process), `value` itself.
pub(crate) fn sum_over_processes(value: f64) -> f64 {
    let mut sum = [value];
    sum_each_over_processes(&mut sum);
    sum[0]
}

/// Every entry of `values` summed over the processes, in place (a collective
/// call with the same length on every process).
fn sum_each_over_processes(values: &mut [f64]) {
    if !initialized().unwrap_or(false) || values.is_empty() {
        return;
    }
    let mine = values.to_vec();
    // SAFETY: MPI is initialised; `values.len()` doubles in, as many out;
    // MPI's default error handler aborts the run instead of returning a code.
    unsafe {
        ffi::MPI_Allreduce(
            mine.as_ptr().cast(),
            values.as_mut_ptr().cast(),
            c_int::try_from(values.len()).unwrap_or(c_int::MAX),
            &raw const ffi::ompi_mpi_double,
            &raw const ffi::ompi_mpi_op_sum,
            ffi::PETSC_COMM_WORLD,
        );
    }
}

/// Rank 0's `path` on every process (a collective call; the other ranks
/// pass `None`): where they write their pieces of rank 0's results.
pub fn share_path(path: Option<&Path>) -> Result<PathBuf, Error> {
    use std::os::unix::ffi::{OsStrExt, OsStringExt};
    ensure_initialized()?;
    let mut bytes = path.map_or_else(Vec::new, |p| p.as_os_str().as_bytes().to_vec());
    let mut length = (bytes.len() as u64).to_le_bytes();
    // SAFETY: MPI is initialised; every process passes buffers of the
    // broadcast's size (the length first); MPI's default error handler aborts.
    unsafe {
        let byte = &raw const ffi::ompi_mpi_byte;
        ffi::MPI_Bcast(length.as_mut_ptr().cast(), 8, byte, 0, ffi::PETSC_COMM_WORLD);
        bytes.resize(u64::from_le_bytes(length) as usize, 0);
        let count = c_int::try_from(bytes.len()).unwrap_or(c_int::MAX);
        ffi::MPI_Bcast(bytes.as_mut_ptr().cast(), count, byte, 0, ffi::PETSC_COMM_WORLD);
    }
    Ok(PathBuf::from(std::ffi::OsString::from_vec(bytes)))
}

/// `result` on every process when every process has `Ok`; otherwise this
/// process's error, or on a process that had none an error naming how many
/// failed (a collective call: a process must not go on alone into PETSc's
/// collective calls while another stops).
pub fn on_every_process<T>(result: Result<T, Error>) -> Result<T, Error> {
    let failed = sum_over_processes(f64::from(u8::from(result.is_err())));
    match result {
        Ok(_) if failed > 0.0 => Err(NumericalError::Solver(format!(
            "{failed} other process(es) of this MPI run stopped with an error (printed by \
             their rank)"
        ))
        .into()),
        result => result,
    }
}

/// The point columns of `K` this process assembles (`pattern`: the point
/// level): those of its own points ([`Numbering`]) and of every point coupled
/// to them (its ghost points: within a horizon for the bond-based model, two
/// for the shear model), whose columns hold the rest of its own rows.
pub(crate) fn assembled_columns(
    pattern: &Pattern,
    dofs: &DofMap,
    x: &[[f64; 3]],
) -> Result<Vec<bool>, Error> {
    ensure_initialized()?;
    let (rank, processes) = (
        comm_query(ffi::MPI_Comm_rank),
        comm_query(ffi::MPI_Comm_size),
    );
    let numbering = Numbering::new(pattern, dofs, x, processes)?;
    let mut keep = vec![false; pattern.row_offsets.len() - 1];
    for &q in &numbering.points[numbering.bounds[rank]..numbering.bounds[rank + 1]] {
        pattern.rows(q).iter().for_each(|&p| keep[p as usize] = true);
    }
    Ok(keep)
}

/// `‖K − Kᵀ‖_F / ‖K‖_F` of a distributed `K` (`values` on this process's
/// columns, [`assembled_columns`]): each process sums over its own columns,
/// whose transposed entries lie in its ghost columns (a collective call).
pub(crate) fn asymmetry(pattern: &Pattern, values: &[f64], layout: Layout) -> Result<f64, Error> {
    ensure_initialized()?;
    let (rank, processes) = (
        comm_query(ffi::MPI_Comm_rank),
        comm_query(ffi::MPI_Comm_size),
    );
    let dofs = layout.dofs;
    let numbering = Numbering::new(pattern, dofs, layout.x, processes)?;
    let (mut skew, mut total) = (0.0, 0.0);
    // Own columns k in increasing order (a part's points are in point order):
    // row k of every column r is reached in increasing order too, so a cursor
    // per column finds it by moving forward (past the rows of other
    // processes' points), as a transposition.
    let mut cursor = pattern.col_ptr.clone();
    for &q in &numbering.points[numbering.bounds[rank]..numbering.bounds[rank + 1]] {
        for c in 0..dofs.d {
            let k = dofs.free_index[3 * q + c];
            if k == PRESCRIBED {
                continue;
            }
            let k = k as usize;
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
    }
    let (skew, total) = (sum_over_processes(skew), sum_over_processes(total));
    Ok(if total > 0.0 { (skew / total).sqrt() } else { 0.0 })
}

/// An error unless PETSc is initialised.
fn ensure_initialized() -> Result<(), Error> {
    if initialized()? {
        return Ok(());
    }
    Err(NumericalError::Solver(
        "solver.method = \"petsc\" needs PETSc initialised (dhpd's command line in a \
         build with the mpi feature does it; a library caller holds a dhpd::mpi::Petsc)"
            .into(),
    )
    .into())
}

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
    x: Vector,
    b: Vector,
    matrix: Matrix,
    /// PETSc's rows in all.
    global_rows: usize,
    /// PETSc's row of every free unknown of dhpd.
    rows: Vec<PetscInt>,
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
        let numbering = Numbering::new(pattern, layout.dofs, layout.x, processes)?;
        let d = layout.d();
        let (first, last) = (
            numbering.bounds[rank] * d,
            numbering.bounds[rank + 1] * d,
        );
        let LocalRows {
            offsets,
            columns,
            values: entries,
            owned,
            stored,
        } = on_every_process(local_rows(
            pattern,
            values,
            layout,
            &numbering,
            first..last,
        ))?;
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
        let mut krylov = Krylov(null_mut());
        call!(KSPCreate(comm, &mut krylov.0))?;
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
            x,
            b,
            matrix,
            global_rows: numbering.points.len() * d,
            rows: numbering.rows,
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
        let owned = &self.owned;
        let value = |r: usize| match owned[r] {
            PRESCRIBED => 0.0,
            k => rhs[k as usize],
        };
        self.b.write(value, owned.len())?;
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
        let (mut scatter, mut all) = (Scatter(null_mut()), Vector(null_mut()));
        call!(VecScatterCreateToAll(self.x.0, &mut scatter.0, &mut all.0))?;
        let mode = (ffi::INSERT_VALUES, ffi::SCATTER_FORWARD);
        call!(VecScatterBegin(scatter.0, self.x.0, all.0, mode.0, mode.1))?;
        call!(VecScatterEnd(scatter.0, self.x.0, all.0, mode.0, mode.1))?;
        let mut data: *const f64 = null();
        call!(VecGetArrayRead(all.0, &mut data))?;
        if self.global_rows > 0 {
            // SAFETY: the gathered vector holds every row.
            let all = unsafe { std::slice::from_raw_parts(data, self.global_rows) };
            x.iter_mut()
                .zip(&self.rows)
                .for_each(|(v, &r)| *v = all[r as usize]);
        }
        call!(VecRestoreArrayRead(all.0, &mut data))
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

/// `n` as a `PetscInt`, or an error naming `what` (32-bit indices).
fn petsc_int(n: usize, what: &str) -> Result<PetscInt, Error> {
    PetscInt::try_from(n).map_err(|_| {
        NumericalError::Solver(format!(
            "{n} {what} exceed the 32-bit indices of this PETSc (a 64-bit-index build, \
             Debian's libpetsc64-real-dev, would need dhpd's PetscInt changed to i64)"
        ))
        .into()
    })
}

/// PETSc's numbering: `d` rows per point with a free component, the points
/// split into one part per process by recursive coordinate bisection
/// ([`bisect`]), balanced by the stored entries of `K` in their rows; PETSc's
/// blocks are the parts in turn, each in dhpd's point order.
struct Numbering {
    /// The points with a free component (PETSc's block `s` is `points[s]`).
    points: Vec<usize>,
    /// PETSc's row of every free unknown.
    rows: Vec<PetscInt>,
    /// Process `r` owns the blocks `bounds[r]..bounds[r + 1]`.
    bounds: Vec<usize>,
}

impl Numbering {
    /// The numbering of `dofs` on the points at `x` split over `processes`
    /// (`pattern`: its point level is enough, so that a process knows its
    /// points before it assembles). Every process computes the same one.
    fn new(
        pattern: &Pattern,
        dofs: &DofMap,
        x: &[[f64; 3]],
        processes: usize,
    ) -> Result<Self, Error> {
        let d = dofs.d;
        let mut points: Vec<usize> = Vec::new();
        for &(i, _) in &dofs.free_dofs {
            // Free unknowns are numbered point by point (`DofMap::new`).
            if points.last() != Some(&(i as usize)) {
                points.push(i as usize);
            }
        }
        petsc_int(points.len() * d, "rows")?;
        // Balance by stored entries of K (an identity row counts one): a free
        // component's row has the free components of the points coupled to it.
        let mut weight = vec![0; x.len()];
        for &i in &points {
            let row: usize = pattern
                .rows(i)
                .iter()
                .map(|&p| dofs.free_count(p as usize))
                .sum();
            weight[i] = (0..d)
                .map(|c| match dofs.free_index[3 * i + c] {
                    PRESCRIBED => 1,
                    _ => row,
                })
                .sum();
        }
        let mut sizes = Vec::with_capacity(processes);
        bisect(&mut points, &weight, x, processes.max(1), &mut sizes);
        let mut bounds = vec![0];
        for size in sizes {
            bounds.push(bounds.last().expect("started") + size);
        }
        let mut block = vec![0; x.len()];
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

/// Splits `points` into `parts` parts of about equal `weight` (by point) by
/// recursive coordinate bisection: the longest side of their bounding box is
/// cut where the weight below reaches the share of the parts on that side
/// (`⌊parts/2⌋` of `parts`), ties in the coordinate broken by the point's
/// index, so that every process finds the same parts. The parts end up in
/// turn in `points`, each in increasing point order, their sizes pushed to
/// `sizes`. A cut across the body's longest side is the smallest of the
/// straight cuts of a box, and with it the ghost layer of each process.
fn bisect(points: &mut [usize], weight: &[usize], x: &[[f64; 3]], parts: usize, sizes: &mut Vec<usize>) {
    if parts == 1 {
        points.sort_unstable();
        sizes.push(points.len());
        return;
    }
    let extent = |axis: usize| {
        let (low, high) = points.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &i| {
            (l.min(x[i][axis]), h.max(x[i][axis]))
        });
        high - low
    };
    let axis = (0..3)
        .max_by(|&a, &b| extent(a).total_cmp(&extent(b)).then(b.cmp(&a)))
        .expect("three axes");
    points.sort_unstable_by(|&i, &j| x[i][axis].total_cmp(&x[j][axis]).then(i.cmp(&j)));
    let lower = parts / 2;
    let total: usize = points.iter().map(|&i| weight[i]).sum();
    let mut below = 0;
    let mut cut = points.len();
    for (m, &i) in points.iter().enumerate() {
        if below * parts >= total * lower {
            cut = m;
            break;
        }
        below += weight[i];
    }
    let (low, high) = points.split_at_mut(cut);
    bisect(low, weight, x, lower, sizes);
    bisect(high, weight, x, parts - lower, sizes);
}

/// One process's rows of `K` in CSR form with PETSc's column numbers.
struct LocalRows {
    offsets: Vec<PetscInt>,
    columns: Vec<PetscInt>,
    values: Vec<f64>,
    /// The free unknown of each row (`PRESCRIBED`: an identity row).
    owned: Vec<u32>,
    /// Entries of `K` among them (identity rows left out).
    stored: usize,
}

/// PETSc's rows `range` of `K` (module docs: identity rows for prescribed
/// components, scaled by the mean diagonal over all processes), gathered from
/// the columns this process assembled: row `k` of `K` has an entry in the
/// column of every unknown coupled to `k` (the pattern is structurally
/// symmetric), and the columns, walked in PETSc's order, give each row its
/// entries sorted.
fn local_rows(
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
    let identity =
        sum_over_processes(diagonal) / sum_over_processes(free_rows as f64).max(1.0);
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
