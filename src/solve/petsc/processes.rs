//! The processes of an MPI run as dhpd sees them: PETSc and MPI initialised
//! for the life of a [`Petsc`], this process's rank, and the few collective
//! calls dhpd makes itself (a sum over the processes, rank 0's path shared,
//! an error on one process made an error on all), through MPI's C API
//! (`MPI_Allreduce`, `MPI_Bcast`) rather than the `mpi` crate, whose bindgen
//! build needs libclang for three functions.

use super::{check, ffi};
use crate::error::{Error, InputError, NumericalError};
use std::ffi::{c_char, c_int, CString};
use std::path::{Path, PathBuf};
use std::ptr::{null, null_mut};

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
        let mut pointers: Vec<*mut c_char> =
            strings.iter().map(|s| s.as_ptr().cast_mut()).collect();
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
        // which the static and fracture drivers drop before they return.
        unsafe { ffi::PetscFinalize() };
    }
}

/// `MPI_Comm_rank` or `MPI_Comm_size` of `PETSC_COMM_WORLD` (0 on failure,
/// which MPI's default error handler does not return from).
pub(super) fn comm_query(query: unsafe extern "C" fn(ffi::MPI_Comm, *mut c_int) -> c_int) -> usize {
    let mut value = 0;
    // SAFETY: PETSc is initialised (the caller holds a `Petsc`, or checked).
    unsafe { query(ffi::PETSC_COMM_WORLD, &mut value) };
    value as usize
}

/// Whether PETSc is initialised in this process.
pub(super) fn initialized() -> Result<bool, Error> {
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
pub(crate) fn sum_each_over_processes(values: &mut [f64]) {
    reduce_each_over_processes(values, &raw const ffi::ompi_mpi_op_sum);
}

/// Every entry of `values` reduced by `op` (`MPI_SUM`, `MPI_MIN`) over the
/// processes, in place (a collective call with the same length on every
/// process).
fn reduce_each_over_processes(values: &mut [f64], op: *const ffi::Opaque) {
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
            op,
            ffi::PETSC_COMM_WORLD,
        );
    }
}

/// `send[r]` to process `r`, for every `r`; returns what every process sent
/// this one, by sender (`MPI_Alltoall` of the counts, then `MPI_Alltoallv`:
/// a collective call; most lists are empty in a halo exchange).
pub(crate) fn all_to_all(send: &[Vec<f64>]) -> Vec<Vec<f64>> {
    let count = |n: usize| c_int::try_from(n).unwrap_or(c_int::MAX);
    let send_counts: Vec<c_int> = send.iter().map(|s| count(s.len())).collect();
    let mut receive_counts = vec![0 as c_int; send.len()];
    let offsets = |counts: &[c_int]| -> Vec<c_int> {
        let mut at = 0;
        counts
            .iter()
            .map(|&c| {
                let o = at;
                at += c;
                o
            })
            .collect()
    };
    let flat: Vec<f64> = send.iter().flatten().copied().collect();
    // SAFETY: MPI is initialised (a `Processes` exists only then); one count
    // per process each way, buffers of the counts' sums; MPI's default
    // error handler aborts the run instead of returning a code.
    unsafe {
        let int = &raw const ffi::ompi_mpi_int;
        ffi::MPI_Alltoall(
            send_counts.as_ptr().cast(),
            1,
            int,
            receive_counts.as_mut_ptr().cast(),
            1,
            int,
            ffi::PETSC_COMM_WORLD,
        );
    }
    let total: usize = receive_counts.iter().map(|&c| c as usize).sum();
    let mut received = vec![0.0; total];
    let (send_offsets, receive_offsets) = (offsets(&send_counts), offsets(&receive_counts));
    // SAFETY: as above; the offsets lie within the flat buffers.
    unsafe {
        let double = &raw const ffi::ompi_mpi_double;
        ffi::MPI_Alltoallv(
            flat.as_ptr().cast(),
            send_counts.as_ptr(),
            send_offsets.as_ptr(),
            double,
            received.as_mut_ptr().cast(),
            receive_counts.as_ptr(),
            receive_offsets.as_ptr(),
            double,
            ffi::PETSC_COMM_WORLD,
        );
    }
    receive_counts
        .iter()
        .zip(&receive_offsets)
        .map(|(&c, &o)| received[o as usize..(o + c) as usize].to_vec())
        .collect()
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
        ffi::MPI_Bcast(
            length.as_mut_ptr().cast(),
            8,
            byte,
            0,
            ffi::PETSC_COMM_WORLD,
        );
        bytes.resize(u64::from_le_bytes(length) as usize, 0);
        let count = c_int::try_from(bytes.len()).unwrap_or(c_int::MAX);
        ffi::MPI_Bcast(
            bytes.as_mut_ptr().cast(),
            count,
            byte,
            0,
            ffi::PETSC_COMM_WORLD,
        );
    }
    Ok(PathBuf::from(std::ffi::OsString::from_vec(bytes)))
}

/// `result` on every process when every process has `Ok`; otherwise this
/// process's error, or on a process that had none an error naming how many
/// failed (a collective call: a process must not go on alone into PETSc's
/// collective calls while another stops).
pub fn on_every_process<T>(result: Result<T, Error>) -> Result<T, Error> {
    crate::processes::agreed(Some(&Processes), result)
}

/// The processes of this MPI run as the discretisation sees them
/// ([`crate::processes::Processes`]): their number, this one's rank, and
/// the sums and minima over the processes.
pub struct Processes;

impl Processes {
    /// The processes of this run when there are several (PETSc initialised
    /// and more than one process); `None` on one.
    pub fn of_run() -> Option<Self> {
        (initialized().unwrap_or(false) && comm_query(ffi::MPI_Comm_size) > 1).then_some(Processes)
    }
}

impl crate::processes::Processes for Processes {
    fn size(&self) -> usize {
        comm_query(ffi::MPI_Comm_size)
    }

    fn rank(&self) -> usize {
        comm_query(ffi::MPI_Comm_rank)
    }

    fn sum(&self, values: &mut [f64]) {
        sum_each_over_processes(values);
    }

    fn min(&self, values: &mut [f64]) {
        reduce_each_over_processes(values, &raw const ffi::ompi_mpi_op_min);
    }

    fn all_to_all(&self, send: &[Vec<f64>]) -> Vec<Vec<f64>> {
        all_to_all(send)
    }
}

/// An error unless PETSc is initialised.
pub(super) fn ensure_initialized() -> Result<(), Error> {
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
