//! The memory guard (ground floor): every large structure (the bonds, the
//! stiffness pattern, a sparse factor) is checked against the memory it may
//! use before it is allocated, so that a run too large for the machine is
//! refused with the size it would need instead of aborting half-way.
//!
//! The limit is the smaller of 90 % of the memory available now (Linux
//! `MemAvailable`) and the scene's `solver.memory_limit_gib`.

use crate::error::{MemoryLimit, NumericalError};

/// Memory the operating system reports as available (Linux `MemAvailable`), if known.
pub fn available_memory_bytes() -> Option<usize> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: usize = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

/// Refuses to allocate `what` (`needed` bytes: the bonds, the stiffness
/// pattern, a sparse factor) when it needs more than 90 % of the memory
/// available now or more than the user's limit (`solver.memory_limit_gib`),
/// instead of letting the allocation abort the process half-way. Called before
/// each large structure is allocated; what earlier stages hold is no longer
/// available, so the system limit is cumulative.
pub fn check_memory(
    what: impl FnOnce() -> String,
    needed: f64,
    user_limit_bytes: Option<f64>,
) -> Result<(), NumericalError> {
    check_memory_against(what, needed, user_limit_bytes, available_memory_bytes())
}

/// The limit `check_memory` applies now, in bytes, and where it comes from
/// (`None`: no limit is known).
pub fn memory_limit(user_limit_bytes: Option<f64>) -> Option<(f64, MemoryLimit)> {
    limit_from(user_limit_bytes, available_memory_bytes())
}

fn limit_from(
    user_limit_bytes: Option<f64>,
    available: Option<usize>,
) -> Option<(f64, MemoryLimit)> {
    let system = available.map(|a| 0.9 * a as f64);
    match (user_limit_bytes, system) {
        (Some(user), Some(system)) if system < user => Some((system, MemoryLimit::Available)),
        (Some(user), _) => Some((user, MemoryLimit::User)),
        (None, Some(system)) => Some((system, MemoryLimit::Available)),
        (None, None) => None,
    }
}

fn check_memory_against(
    what: impl FnOnce() -> String,
    needed: f64,
    user_limit_bytes: Option<f64>,
    available: Option<usize>,
) -> Result<(), NumericalError> {
    match limit_from(user_limit_bytes, available) {
        Some((limit, source)) if needed > limit => Err(NumericalError::TooLarge {
            what: what(),
            needed_bytes: needed.min(usize::MAX as f64) as usize,
            limit_bytes: limit,
            limited_by: source,
        }),
        _ => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The smaller of the user's limit and 90 % of the available memory applies,
    /// and the error carries the size that would be needed.
    #[test]
    fn memory_guard_uses_the_tighter_limit() {
        let gib = 1usize << 30;
        let what = || "the test".to_string();
        let g = gib as f64;
        assert!(check_memory_against(what, g, None, None).is_ok());
        assert!(check_memory_against(what, g, None, Some(2 * gib)).is_ok());
        assert!(check_memory_against(what, g, Some(2.0 * g), Some(2 * gib)).is_ok());
        let refused = |user: Option<f64>, available: Option<usize>| match check_memory_against(
            what, g, user, available,
        ) {
            Err(NumericalError::TooLarge {
                needed_bytes,
                limit_bytes,
                limited_by,
                ..
            }) => (needed_bytes, limit_bytes, limited_by),
            other => panic!("expected a refusal, got {other:?}"),
        };
        assert_eq!(
            refused(None, Some(gib)),
            (gib, 0.9 * gib as f64, MemoryLimit::Available)
        );
        assert_eq!(
            refused(Some(0.5 * gib as f64), Some(4 * gib)),
            (gib, 0.5 * gib as f64, MemoryLimit::User)
        );
        assert_eq!(
            refused(Some(0.5 * gib as f64), None),
            (gib, 0.5 * gib as f64, MemoryLimit::User)
        );
        assert_eq!(
            refused(Some(8.0 * gib as f64), Some(gib)),
            (gib, 0.9 * gib as f64, MemoryLimit::Available)
        );
    }
}
