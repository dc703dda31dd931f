//! The processes of a distributed run as the layers above see them: their
//! number, this one's rank and the few collective calls that make local
//! answers global ([`Processes`]), and an error on one process made an error
//! on all ([`agreed`]). The MPI build implements them (`solve::petsc`); the
//! discretisation, the rigid-motion check and the explicit driver use them
//! without knowing MPI.

use crate::error::{Error, NumericalError};

/// The processes of a distributed run (the MPI build gives them): their
/// number, this one's rank and the collective calls that make local answers
/// global. Every process calls every method in the same order.
pub trait Processes {
    /// The number of processes.
    fn size(&self) -> usize;
    /// This process's rank.
    fn rank(&self) -> usize;
    /// Every entry of `values` summed over the processes, in place.
    fn sum(&self, values: &mut [f64]);
    /// Every entry of `values` the least over the processes, in place.
    fn min(&self, values: &mut [f64]);
    /// `send[r]` to process `r`, for every `r`; what every process sent this
    /// one, by sender.
    fn all_to_all(&self, send: &[Vec<f64>]) -> Vec<Vec<f64>>;
}

/// `result` on this process, unless another failed: then an error here too
/// (a collective call: no process goes on alone into the next collective).
pub fn agreed<T>(processes: Option<&dyn Processes>, result: Result<T, Error>) -> Result<T, Error> {
    let Some(processes) = processes else {
        return result;
    };
    let mut failed = [f64::from(u8::from(result.is_err()))];
    processes.sum(&mut failed);
    match result {
        Ok(_) if failed[0] > 0.0 => Err(NumericalError::OtherProcesses {
            count: failed[0] as usize,
        }
        .into()),
        result => result,
    }
}
