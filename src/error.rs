//! Typed errors, one enum per layer, and the process exit code each maps to.
//!
//! | exit code | meaning |
//! |---|---|
//! | 0 | success |
//! | 2 | input error: the scene or a point file is invalid (nothing was computed) |
//! | 3 | numerical failure: the problem is ill-posed or the solver failed |
//! | 4 | I/O failure while reading inputs or writing results |
//! | 130, 143 | interrupted by SIGINT, SIGTERM: partial results removed (`output::interrupt`) |

use std::path::PathBuf;
use thiserror::Error;

/// An invalid input: names the field (a dotted path such as `regions[1].spacing`)
/// and says what would be valid.
#[derive(Debug, Clone, Error, PartialEq)]
#[error("{field}: {message}")]
pub struct InputError {
    /// Dotted path of the offending field, e.g. `materials.steel.youngs_modulus`.
    pub field: String,
    /// What is wrong and what would be valid.
    pub message: String,
}

impl InputError {
    /// Creates an input error for `field`.
    pub fn new(field: impl Into<String>, message: impl Into<String>) -> Self {
        Self {
            field: field.into(),
            message: message.into(),
        }
    }
}

/// A numerical failure: the assembled problem cannot be solved as posed.
#[derive(Debug, Clone, Error, PartialEq)]
pub enum NumericalError {
    /// The Cholesky factorisation met a non-positive pivot.
    #[error(
        "the stiffness matrix is not positive definite: non-positive pivot at point {point} \
         (x = {position:?}), component {component}; the body is under-constrained or the point \
         is not held by enough bonds"
    )]
    NonPositivePivot {
        point: usize,
        component: usize,
        position: [f64; 3],
    },
    /// The Cholesky factorisation left almost nothing of an unknown's stiffness.
    #[error(
        "the stiffness matrix is singular to round-off at point {point} (x = {position:?}), \
         component {component} (pivot ratio {ratio:.1e}): that point can move without resistance \
         (a mechanism: too few bonds or bonds all along one line; or a stiff part held only \
         through a far softer one, stiffness contrast above about 1e10)"
    )]
    NearlySingular {
        point: usize,
        component: usize,
        position: [f64; 3],
        ratio: f64,
    },
    /// A shear-model owner whose intact bonds do not span the space.
    #[error(
        "the shape tensor of point {point} (x = {position:?}) is singular: its bonds do not span \
         the space (too few neighbours, or all on one line), so its deformation gradient is undefined"
    )]
    SingularShapeTensor { point: usize, position: [f64; 3] },
    /// The LU factorisation found a structurally singular matrix.
    #[error(
        "the stiffness matrix is structurally singular at point {point}, component {component}"
    )]
    StructurallySingular { point: usize, component: usize },
    /// A point has no intact bond in either direction.
    #[error(
        "{count} point(s) have no bond (first: point {first} at {position:?}); set \
         discretization.isolated_points = \"remove\" to drop them with a warning"
    )]
    IsolatedPoints {
        count: usize,
        first: usize,
        position: [f64; 3],
    },
    /// Prescribed displacements leave a rigid motion of a body free.
    #[error(
        "the body of {points} point(s) containing point {first} (x = {position:?}) is not held: \
         it can move freely by {motions}; prescribe displacements that stop this motion"
    )]
    RigidMotion {
        points: usize,
        first: usize,
        position: [f64; 3],
        motions: String,
    },
    /// The solution failed its residual check, after iterative refinement.
    #[error(
        "solve rejected: relative residual {residual:.3e} exceeds {threshold:.1e} after \
         {refinement_steps} step(s) of iterative refinement; the system is too ill-conditioned \
         for double precision (a near-mechanism or an extreme stiffness contrast), or the \
         factorisation lost accuracy (try solver.method = \"lu\")"
    )]
    ResidualTooLarge {
        residual: f64,
        threshold: f64,
        refinement_steps: usize,
    },
    /// A non-finite number appeared in a result.
    #[error("non-finite value in {what}")]
    NonFinite { what: String },
    /// The linear system has no free degree of freedom.
    #[error("every degree of freedom is prescribed: nothing to solve")]
    NothingToSolve,
    /// A large structure (the bonds, the stiffness pattern, the sparse factor)
    /// would not fit in memory; known before it is allocated.
    #[error(
        "{what} would need {}, more than the {} allowed by {limited_by}; \
         use a coarser spacing or a smaller horizon factor",
        human_bytes(*needed_bytes as f64),
        human_bytes(*limit_bytes)
    )]
    TooLarge {
        /// What would be allocated, with its size in its own terms.
        what: String,
        needed_bytes: usize,
        limit_bytes: f64,
        limited_by: MemoryLimit,
    },
    /// An explicit run produced a non-finite state.
    #[error(
        "the explicit run diverged at step {step} (t = {time:e} s): point {point} (x = {position:?}) \
         has a non-finite displacement or velocity; the time step is too large for the stiffest \
         point (forced above the stable one?) or a load grows without bound"
    )]
    Diverged {
        step: usize,
        time: f64,
        point: usize,
        position: [f64; 3],
    },
    /// An explicit run lost its energy balance.
    #[error(
        "the explicit run lost its energy balance at step {step} (t = {time:e} s): the error \
         E_kin + E_strain + E_broken + E_damping − W_ext − E_0 is {error:.3e} of the largest \
         energy, above dynamics.balance_tolerance = {tolerance:e}; the time step is too large \
         (forced above the stable one?) or the forces are not the gradient of an energy (the \
         shear model with heavy breakage, the traditional horizons); raise \
         dynamics.balance_tolerance to accept the run"
    )]
    EnergyBalance {
        step: usize,
        time: f64,
        error: f64,
        tolerance: f64,
    },
    /// faer reported an allocation or other generic failure.
    #[error("linear solver failure: {0}")]
    Solver(String),
}

/// A size in B, KiB, MiB or GiB with three significant digits.
pub fn human_bytes(bytes: f64) -> String {
    let units = ["B", "KiB", "MiB", "GiB", "TiB"];
    let mut value = bytes;
    let mut unit = 0;
    while value >= 1024.0 && unit + 1 < units.len() {
        value /= 1024.0;
        unit += 1;
    }
    format!("{value:.3} {}", units[unit])
}

/// Where the limit on a factor's size comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MemoryLimit {
    /// 90 % of the memory available (`MemAvailable` in /proc/meminfo).
    Available,
    /// The scene's `solver.memory_limit_gib`.
    User,
}

impl std::fmt::Display for MemoryLimit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            MemoryLimit::Available => "90 % of the available memory",
            MemoryLimit::User => "solver.memory_limit_gib",
        })
    }
}

/// Any failure of a dhpd run.
#[derive(Debug, Error)]
pub enum Error {
    /// Invalid scene or point file.
    #[error("input error: {0}")]
    Input(#[from] InputError),
    /// Ill-posed problem or solver failure.
    #[error("numerical failure: {0}")]
    Numerical(#[from] NumericalError),
    /// Reading or writing a file failed.
    #[error("I/O error on {path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
}

impl Error {
    /// Wraps an I/O error with the path it concerns.
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Self::Io {
            path: path.into(),
            source,
        }
    }

    /// The process exit code for this error (see the module table).
    pub fn exit_code(&self) -> i32 {
        match self {
            Error::Input(_) => 2,
            Error::Numerical(_) => 3,
            Error::Io { .. } => 4,
        }
    }
}

/// Result alias for dhpd.
pub type Result<T, E = Error> = std::result::Result<T, E>;
