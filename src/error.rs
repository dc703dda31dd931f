//! Typed errors, one enum per layer, and the process exit code each maps to.
//!
//! | exit code | meaning |
//! |---|---|
//! | 0 | success |
//! | 2 | input error: the scene or a point file is invalid (nothing was computed) |
//! | 3 | numerical failure: the problem is ill-posed or the solver failed |
//! | 4 | I/O failure while reading inputs or writing results |
//! | 130, 143 | interrupted by SIGINT, SIGTERM: partial results removed (`output::interrupt`) |
//!
//! Messages clip the user text they echo ([`echo`], [`echo_list`]; applied to
//! every [`InputError`] by its constructor as a safety net) and print numbers
//! in a bounded form ([`num`] for given values, [`approx`] for computed ones).

use std::borrow::Cow;
use std::path::{Path, PathBuf};
use thiserror::Error;

/// Longest user text (a key, a name, a value, a point-file row) echoed whole in
/// a message, in characters; longer text is clipped by [`echo`].
pub const ECHO_CHARS: usize = 80;

/// Characters kept on each side of the ellipsis of a clipped echo.
const ECHO_SIDE: usize = ECHO_CHARS / 2 - 2;

/// `text` as echoed in a message: whole up to [`ECHO_CHARS`] characters, else
/// its first and last 38 characters around an ellipsis (a 10 MiB key is not
/// echoed whole; both ends stay, so a long path keeps its file name).
pub fn echo(text: &str) -> Cow<'_, str> {
    let count = text.chars().count();
    if count <= ECHO_CHARS {
        return Cow::Borrowed(text);
    }
    let head: String = text.chars().take(ECHO_SIDE).collect();
    let tail: String = text.chars().skip(count - ECHO_SIDE).collect();
    Cow::Owned(format!("{head}…{tail}"))
}

/// A number as a message shows it: its shortest exact form (`0.01`, `3.015`,
/// `1e9`, `1e-300`), in exponent form outside [1e-3, 1e6), so that no value
/// prints as a run of hundreds of digits (`{}` prints 1e300 with 301).
pub fn num(x: f64) -> String {
    if x == 0.0 || !x.is_finite() || (1e-3..1e6).contains(&x.abs()) {
        format!("{x:?}")
    } else {
        format!("{x:e}")
    }
}

/// Most names a message lists (valid materials, groups) before it says how many
/// there are in all.
const LISTED: usize = 10;

/// Names as a message lists them: the first ten, each [`echo`]ed, joined by
/// commas, then how many there are in all; `none` for an empty list.
pub fn echo_list<'a>(names: impl IntoIterator<Item = &'a str>) -> String {
    let names: Vec<&str> = names.into_iter().collect();
    if names.is_empty() {
        return "none".into();
    }
    let shown: Vec<Cow<'_, str>> = names.iter().take(LISTED).map(|n| echo(n)).collect();
    let mut text = shown.join(", ");
    if names.len() > LISTED {
        text.push_str(&format!(", … ({} in all)", names.len()));
    }
    text
}

/// A computed number (a ratio, a count of spacings) as a message shows it:
/// four decimals in [1e-3, 1e6), else three in exponent form (`1.000e152`).
pub fn approx(x: f64) -> String {
    if x == 0.0 || !x.is_finite() || (1e-3..1e6).contains(&x.abs()) {
        format!("{x:.4}")
    } else {
        format!("{x:.3e}")
    }
}

/// A path as echoed in a message ([`echo`] of its display form).
pub fn echo_path(path: &Path) -> String {
    echo(&path.display().to_string()).into_owned()
}

/// Clips the user text a message may echo: every span between backticks or
/// double quotes longer than [`ECHO_CHARS`] characters, and every run without
/// white space longer than twice that (an unquoted path), by [`echo`].
fn clip_echoes(message: &str) -> Cow<'_, str> {
    if message.chars().count() <= ECHO_CHARS {
        return Cow::Borrowed(message);
    }
    // Quoted spans: each quote character opens a span closed by the next one.
    let mut quoted = String::with_capacity(message.len().min(1 << 16));
    let mut rest = message;
    while let Some(open) = rest.find(['`', '"']) {
        let q = rest[open..].chars().next().expect("a quote");
        let inner_start = open + q.len_utf8();
        let Some(len) = rest[inner_start..].find(q) else {
            break;
        };
        quoted.push_str(&rest[..inner_start]);
        quoted.push_str(&echo(&rest[inner_start..inner_start + len]));
        quoted.push(q);
        rest = &rest[inner_start + len + q.len_utf8()..];
    }
    quoted.push_str(rest);
    // Unquoted runs.
    let mut out = String::with_capacity(quoted.len());
    let mut run = String::new();
    let flush = |run: &mut String, out: &mut String| {
        if run.chars().count() > 2 * ECHO_CHARS {
            out.push_str(&echo(run));
        } else {
            out.push_str(run);
        }
        run.clear();
    };
    for c in quoted.chars() {
        if c.is_whitespace() {
            flush(&mut run, &mut out);
            out.push(c);
        } else {
            run.push(c);
        }
    }
    flush(&mut run, &mut out);
    Cow::Owned(out)
}

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
    /// Creates an input error for `field`. User text the field or the message
    /// echoes is clipped ([`echo`]): each dotted part of the field, and in the
    /// message every quoted span longer than [`ECHO_CHARS`] characters and every
    /// unquoted run without white space longer than twice that.
    pub fn new(field: impl Into<String>, message: impl Into<String>) -> Self {
        let (field, message) = (field.into(), message.into());
        let field = if field.chars().count() > ECHO_CHARS {
            field.split('.').map(echo).collect::<Vec<_>>().join(".")
        } else {
            field
        };
        let message = clip_echoes(&message).into_owned();
        Self { field, message }
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
         {refinement_steps} step(s) of iterative refinement; {hint}"
    )]
    ResidualTooLarge {
        residual: f64,
        threshold: f64,
        refinement_steps: usize,
        /// Why, and which route (if any) does better.
        hint: String,
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
    /// An explicit run produced a non-finite state (checked every step).
    #[error(
        "the explicit run diverged at step {step} (t = {time:e} s): point {point} (x = {position:?}) \
         has a non-finite displacement or velocity, or a kinetic energy beyond double precision; \
         {cause}; nothing was written"
    )]
    Diverged {
        step: usize,
        time: f64,
        point: usize,
        position: [f64; 3],
        /// What made it diverge, as far as the driver can tell (the forced
        /// time step, or the magnitudes of the input).
        cause: String,
    },
    /// An explicit run lost its energy balance.
    #[error(
        "the explicit run lost its energy balance at step {step} (t = {time:e} s): the error \
         E_kin + E_strain + E_broken + E_damping − W_ext − E_0 is {error:.3e} of the largest \
         energy, above dynamics.balance_tolerance = {tolerance:e}; {cause}; raise \
         dynamics.balance_tolerance to accept the run"
    )]
    EnergyBalance {
        step: usize,
        time: f64,
        error: f64,
        tolerance: f64,
        /// The likely cause (the forced time step, or forces without an energy).
        cause: String,
    },
    /// faer reported an allocation or other generic failure.
    #[error("linear solver failure: {0}")]
    Solver(String),
    /// Another process of an MPI run stopped with an error (this one stops too).
    #[error(
        "{count} other process(es) of this MPI run stopped with an error (printed by their rank)"
    )]
    OtherProcesses { count: usize },
    /// A PETSc call failed (the `mpi` build): the function, its error code
    /// and PETSc's text for it (PETSc prints its own trace on stderr).
    #[cfg(feature = "mpi")]
    #[error("PETSc's {call} failed with error code {code} ({message})")]
    Petsc {
        call: &'static str,
        code: i32,
        message: String,
    },
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
    #[error("I/O error on {}: {source}", echo_path(path))]
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
