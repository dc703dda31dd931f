//! The C declarations dhpd calls (PETSc 3.18 as Debian's `petsc-dev` builds
//! it, Open MPI 4.1): `PetscInt` 32-bit, `PetscScalar` `f64`, Open MPI's
//! `MPI_Comm` a pointer and its predefined handles the addresses of globals.

#![allow(
    non_snake_case,
    non_camel_case_types,
    non_upper_case_globals,
    clippy::upper_case_acronyms
)]

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

/// A Krylov monitor: called with the iteration and the residual norm of the
/// convergence test after every iteration (and before the first).
pub type Monitor = unsafe extern "C" fn(KSP, PetscInt, PetscReal, *mut c_void) -> PetscErrorCode;

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
/// `MatAssemblyType::MAT_FINAL_ASSEMBLY`.
pub const MAT_FINAL_ASSEMBLY: c_int = 0;
/// `PETSC_TRUE`.
pub const PETSC_TRUE: PetscBool = 1;
/// `PETSC_DEFAULT` (a tolerance left at PETSc's default).
pub const PETSC_DEFAULT: PetscReal = -2.0;

extern "C" {
    pub static PETSC_COMM_WORLD: MPI_Comm;
    /// Indexed by `KSPConvergedReason`, negative values included.
    pub static KSPConvergedReasons: *const *const c_char;

    /// Open MPI's predefined handles (`MPI_DOUBLE`, `MPI_INT`, `MPI_BYTE`, `MPI_SUM` and
    /// `MPI_MIN` are their addresses).
    pub static ompi_mpi_double: Opaque;
    pub static ompi_mpi_int: Opaque;
    pub static ompi_mpi_byte: Opaque;
    pub static ompi_mpi_op_sum: Opaque;
    pub static ompi_mpi_op_min: Opaque;

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
    pub fn MPI_Alltoall(
        send: *const c_void,
        send_count: c_int,
        send_type: *const Opaque,
        receive: *mut c_void,
        receive_count: c_int,
        receive_type: *const Opaque,
        comm: MPI_Comm,
    ) -> c_int;
    pub fn MPI_Alltoallv(
        send: *const c_void,
        send_counts: *const c_int,
        send_offsets: *const c_int,
        send_type: *const Opaque,
        receive: *mut c_void,
        receive_counts: *const c_int,
        receive_offsets: *const c_int,
        receive_type: *const Opaque,
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
    pub fn MatSetValues(
        mat: Mat,
        m: PetscInt,
        rows: *const PetscInt,
        n: PetscInt,
        columns: *const PetscInt,
        values: *const PetscScalar,
        insert: c_int,
    ) -> PetscErrorCode;
    pub fn MatAssemblyBegin(mat: Mat, kind: c_int) -> PetscErrorCode;
    pub fn MatAssemblyEnd(mat: Mat, kind: c_int) -> PetscErrorCode;
    pub fn MatCreateVecs(mat: Mat, right: *mut Vec, left: *mut Vec) -> PetscErrorCode;
    pub fn MatSetNearNullSpace(mat: Mat, space: MatNullSpace) -> PetscErrorCode;
    pub fn MatDestroy(mat: *mut Mat) -> PetscErrorCode;
    pub fn MatMult(mat: Mat, x: Vec, y: Vec) -> PetscErrorCode;
    pub fn MatNullSpaceCreateRigidBody(coords: Vec, space: *mut MatNullSpace) -> PetscErrorCode;
    pub fn MatNullSpaceDestroy(space: *mut MatNullSpace) -> PetscErrorCode;

    pub fn VecGetArray(v: Vec, a: *mut *mut PetscScalar) -> PetscErrorCode;
    pub fn VecRestoreArray(v: Vec, a: *mut *mut PetscScalar) -> PetscErrorCode;
    pub fn VecGetArrayRead(v: Vec, a: *mut *const PetscScalar) -> PetscErrorCode;
    pub fn VecRestoreArrayRead(v: Vec, a: *mut *const PetscScalar) -> PetscErrorCode;
    pub fn VecDestroy(v: *mut Vec) -> PetscErrorCode;
    pub fn VecDuplicate(v: Vec, copy: *mut Vec) -> PetscErrorCode;
    pub fn VecAYPX(y: Vec, beta: PetscScalar, x: Vec) -> PetscErrorCode;
    pub fn VecNorm(x: Vec, kind: c_int, value: *mut PetscReal) -> PetscErrorCode;
    pub fn VecScatterCreateToAll(v: Vec, scatter: *mut VecScatter, all: *mut Vec)
        -> PetscErrorCode;
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
    pub fn KSPSetInitialGuessNonzero(ksp: KSP, nonzero: PetscBool) -> PetscErrorCode;
    pub fn KSPMonitorSet(
        ksp: KSP,
        monitor: Monitor,
        context: *mut c_void,
        destroy: Option<unsafe extern "C" fn(*mut *mut c_void) -> PetscErrorCode>,
    ) -> PetscErrorCode;
    pub fn KSPBuildSolution(ksp: KSP, v: Vec, solution: *mut Vec) -> PetscErrorCode;
    pub fn KSPSetReusePreconditioner(ksp: KSP, reuse: PetscBool) -> PetscErrorCode;
    pub fn KSPSetFromOptions(ksp: KSP) -> PetscErrorCode;
    pub fn KSPSetUp(ksp: KSP) -> PetscErrorCode;
    pub fn KSPSolve(ksp: KSP, b: Vec, x: Vec) -> PetscErrorCode;
    pub fn KSPGetIterationNumber(ksp: KSP, its: *mut PetscInt) -> PetscErrorCode;
    pub fn KSPGetConvergedReason(ksp: KSP, reason: *mut c_int) -> PetscErrorCode;
    pub fn KSPDestroy(ksp: *mut KSP) -> PetscErrorCode;
}
