//! Which route a system takes, decided from its pattern before any value is
//! assembled, so that a factor too large for memory is refused early (or
//! replaced by the iterative route).
//!
//! Routes (`solver.method`):
//!
//! | method | fresh solve | re-solve with the old factor |
//! |---|---|---|
//! | `cholesky` | `K = L Lᵀ`, triangular solves, refinement | CG preconditioned by the old `L Lᵀ` |
//! | `lu` | `K = L U`, triangular solves, refinement | GMRES preconditioned by the old `L U` |
//! | `gmres` | GMRES on `K` preconditioned by the Cholesky factor of a symmetric surrogate | GMRES with the old surrogate factor |
//! | `iterative` | CG on `K` (GMRES if not symmetric) preconditioned by a two-level cycle ([`super::two_level`]): no factor of `K` | the same with the old cycle |
//! | `petsc` | PETSc's CG (GMRES) with algebraic multigrid, on the processes of an MPI run (`solve::petsc`, `mpi` feature) | the same, warm-started, with the old multigrid hierarchy |
//!
//! The surrogate of the `gmres` route is a symmetric positive definite matrix
//! on a sparser pattern that the caller provides ([`wants_surrogate`]; the
//! bond-based stiffness on the bonded pairs for the shear model, whose `K`
//! couples neighbours of neighbours), or else `(K + Kᵀ)/2`. When the surrogate
//! stalls (near incompressibility the bond-based stiffness has no Poisson
//! ratio), the pipeline switches to the Cholesky factor of `(K + Kᵀ)/2`, and to
//! LU when that is not positive definite; the switch is kept for later solves
//! and noted.
//!
//! **Automatic route.** Unless the scene names a method, a direct factor is
//! replaced by the `iterative` route when the symbolic analysis predicts more
//! than [`ITERATIVE_FROM_FLOPS_PER_ENTRY`] operations per stored entry of `K`
//! (the factor's cost grows faster than the iterations'; 3D bodies cross it
//! early), or [`ITERATIVE_FRACTURE_FROM_FLOPS_PER_ENTRY`] in a fracture run,
//! whose re-solves reuse the factor.
//! Where nested dissection is the only candidate ordering, its dense root
//! separator alone can decide, before any symbolic analysis. Any route whose
//! factor does not fit in memory in either precision becomes `iterative`, with
//! a note.

use super::cholesky::Cholesky;
use super::lu::SparseLu;
use super::ordering::{nested_dissection, Dissection};
use super::two_level::TwoLevel;
use super::Layout;
use crate::assembly::pattern::Pattern;
use crate::error::{Error, InputError, NumericalError};
use crate::memory::check_memory;
use crate::notes::Notes;
use crate::scene::solver::{Ordering, Precision, SolverMethod, SolverSettings};
use serde::Serialize;
use std::time::Instant;

/// What the driver knows about the system that its pattern does not say.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Hints {
    /// `K` is symmetric (the bond-based model): CG instead of GMRES.
    pub symmetric: bool,
    /// A fracture run: re-solves update a direct factor exactly (low-rank
    /// terms), which needs it in double precision, and the route stays direct.
    pub fracture: bool,
    /// A nearly incompressible body, where the two-level preconditioner is
    /// weak: cost alone never selects it.
    pub near_incompressible: bool,
}

/// Largest number of free unknowns `solver.method = "lu"` accepts: faer's
/// sparse LU (whose fill is not known before the numeric factorisation) took
/// 0.64 s and 189 MiB at 4,896 unknowns, 6.4 s and 1.3 GiB at 19,796 and
/// 90 s and 10 GiB at 79,596 (shear model, plane stress, m = 3.015), where the
/// `gmres` and `iterative` routes take 2-3 s.
pub const LU_MAX_UNKNOWNS: usize = 20_000;

/// Predicted factorisation operations per stored entry of `K` above which the
/// automatic route is iterative. Measured (two threads): at 4.6e3 (2D,
/// 40,000 points) a direct solve and the two-level iterations cost the same;
/// 3D bodies reach 1e5 at 50,000 points, where the iterations are 8× faster.
/// The margin keeps the direct route, whose cost does not depend on the
/// conditioning and whose failures name the point of a mechanism, wherever it
/// is not clearly slower.
pub const ITERATIVE_FROM_FLOPS_PER_ENTRY: f64 = 2e4;

/// [`ITERATIVE_FROM_FLOPS_PER_ENTRY`] for fracture runs, whose factor serves
/// every re-solve (exact low-rank updates, or the preconditioner of a few
/// Krylov iterations) while the iterative route pays its iterations at each:
/// only a factor far costlier than the static break-even is replaced.
pub const ITERATIVE_FRACTURE_FROM_FLOPS_PER_ENTRY: f64 = 1e5;

/// Factor size from which `auto` factorises in single precision: measured on
/// the 2D square (bond-based, δ = 3.015Δx, one thread), single precision halves
/// the numeric factorisation (9.3 → 4.7 s at 160,000 points, nnz(L) 2.0e8) but
/// its CG iterations cost about what it saves at 40,000 points (nnz(L) 4.0e7).
pub const MIXED_FROM_NNZ_L: usize = 100_000_000;

/// Size of `K` (stored entries) up to which `auto` analyses both orderings.
/// Above it AMD's own analysis becomes costly (15 s at a million 2D points,
/// a quarter of the factorisation) while nested dissection needs half its flops
/// on every bulky body measured, so `auto` analyses nested dissection alone
/// (`solver.ordering = "amd"` still forces AMD, e.g. for long thin bodies).
pub const AUTO_AMD_UP_TO_NNZ_K: usize = 50_000_000;

/// Whether the route factorises a surrogate that the caller provides: the
/// `gmres` route on a non-symmetric `K`.
pub fn wants_surrogate(settings: &SolverSettings, hints: Hints) -> bool {
    settings.method == SolverMethod::Gmres && !hints.symmetric
}

/// Refuses a route that cannot take a system of `n_free` unknowns (sparse LU
/// above [`LU_MAX_UNKNOWNS`]), before its pattern is built.
pub fn check_size(settings: &SolverSettings, n_free: usize) -> Result<(), Error> {
    if settings.method == SolverMethod::Lu && n_free > LU_MAX_UNKNOWNS {
        return Err(InputError::new(
            "solver.method",
            format!(
                "sparse LU is offered up to {LU_MAX_UNKNOWNS} free unknowns and this body \
                 has {n_free}: its fill is not predicted and grows fast (measured on the shear \
                 model: 6.4 s and 1.3 GiB at 19,796 unknowns, 90 s and 10 GiB at 79,596); \
                 leave solver.method out (Cholesky or CG for a symmetric tangent, GMRES for \
                 the shear model's paper force) or use \"iterative\""
            ),
        )
        .into());
    }
    Ok(())
}

/// What the current factor is a factor of.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Source {
    /// `K` itself (Cholesky or LU).
    Matrix,
    /// `(K + Kᵀ)/2` (GMRES).
    SymmetricPart,
    /// The caller's surrogate on its own pattern (GMRES).
    Surrogate,
    /// `K` itself, through the two-level preconditioner (the `iterative` route).
    TwoLevel,
    /// `K` itself, handed to PETSc (the `petsc` route).
    #[cfg(feature = "mpi")]
    Petsc,
}

/// The preconditioner or factor of a route.
pub(super) enum Factor {
    Cholesky(Cholesky),
    Lu(SparseLu),
    /// Built at the numeric stage, from the values of `K`.
    TwoLevel(Option<TwoLevel>),
    /// `K` set up in PETSc at the numeric stage.
    #[cfg(feature = "mpi")]
    Petsc(Option<super::petsc::Solver>),
}

impl Factor {
    /// A direct factor's solve (the two-level cycle goes through the
    /// pipeline's preconditioner, which has `K`).
    pub(super) fn solve_in_place(&self, b: &mut [f64]) {
        match self {
            Factor::Cholesky(c) => c.solve_in_place(b),
            Factor::Lu(l) => l.solve_in_place(b),
            _ => unreachable!("the two-level cycle needs K; PETSc solves by itself"),
        }
    }

    pub(super) fn is_single(&self) -> bool {
        matches!(self, Factor::Cholesky(c) if c.is_single())
    }
}

/// Which fill-reducing ordering the Cholesky factor uses, and the factor sizes
/// of the orderings analysed.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct OrderingReport {
    /// The ordering kept.
    pub chosen: Ordering,
    /// nnz(L) with AMD, when analysed.
    pub nnz_l_amd: Option<usize>,
    /// nnz(L) with the nested dissection, when analysed.
    pub nnz_l_nested_dissection: Option<usize>,
    /// Factorisation flops (`Σ c_j²`) with AMD, when analysed.
    pub flops_amd: Option<f64>,
    /// Factorisation flops with the nested dissection, when analysed.
    pub flops_nested_dissection: Option<f64>,
    /// Time of the nested dissection itself (s).
    pub dissection_seconds: f64,
}

/// The route chosen for a system.
pub(super) struct Chosen {
    pub(super) source: Source,
    pub(super) factor: Factor,
    /// The Cholesky factor's ordering (None for LU and the iterative route).
    pub(super) ordering: Option<OrderingReport>,
    /// The route factorises the caller's surrogate (it was given one and
    /// did not become iterative).
    pub(super) surrogate: bool,
}

impl Chosen {
    fn iterative() -> Self {
        Chosen {
            source: Source::TwoLevel,
            factor: Factor::TwoLevel(None),
            ordering: None,
            surrogate: false,
        }
    }

    /// The `petsc` route, in a build with the `mpi` feature.
    fn petsc() -> Result<Self, Error> {
        #[cfg(feature = "mpi")]
        return Ok(Chosen {
            source: Source::Petsc,
            factor: Factor::Petsc(None),
            ordering: None,
            surrogate: false,
        });
        #[cfg(not(feature = "mpi"))]
        Err(InputError::new(
            "solver.method",
            "\"petsc\" needs dhpd built with the mpi feature",
        )
        .into())
    }
}

/// Chooses the route of `settings` for `K`'s `pattern` (and the `surrogate`'s,
/// when [`wants_surrogate`]) and runs its symbolic analysis (module docs).
pub(super) fn choose(
    pattern: &Pattern,
    surrogate: Option<&Pattern>,
    layout: Layout,
    settings: &SolverSettings,
    hints: Hints,
    notes: &mut Notes,
) -> Result<Chosen, Error> {
    match settings.method {
        SolverMethod::Lu => Ok(Chosen {
            source: Source::Matrix,
            factor: Factor::Lu(SparseLu::analyse(pattern.symbolic())?),
            ordering: None,
            surrogate: false,
        }),
        SolverMethod::Iterative => Ok(Chosen::iterative()),
        SolverMethod::Petsc => Chosen::petsc(),
        SolverMethod::Cholesky | SolverMethod::Gmres => {
            choose_factor(pattern, surrogate, layout, settings, hints, notes)
        }
    }
}

/// The Cholesky factor of the `cholesky` or `gmres` route, or the iterative
/// route when the scene left the choice and the factor costs too much or does
/// not fit (module docs).
fn choose_factor(
    pattern: &Pattern,
    surrogate: Option<&Pattern>,
    layout: Layout,
    settings: &SolverSettings,
    hints: Hints,
    notes: &mut Notes,
) -> Result<Chosen, Error> {
    let (source, structure) = match (surrogate, settings.method) {
        (Some(s), _) => (Source::Surrogate, s),
        (None, SolverMethod::Gmres) => (Source::SymmetricPart, pattern),
        _ => (Source::Matrix, pattern),
    };
    let may_switch = settings.automatic && !hints.near_incompressible;
    let threshold = if hints.fracture {
        ITERATIVE_FRACTURE_FROM_FLOPS_PER_ENTRY
    } else {
        ITERATIVE_FROM_FLOPS_PER_ENTRY
    };
    // Where nested dissection is the only candidate, its root separator
    // bounds the factor's cost from below: past the threshold the symbolic
    // analysis is not worth running.
    let nd_only = settings.ordering == Ordering::NestedDissection
        || (settings.ordering == Ordering::Auto && structure.nnz() > AUTO_AMD_UP_TO_NNZ_K);
    let dissection = nd_only.then(|| nested_dissection(layout.x, layout.dofs, structure));
    let per_entry_bound = dissection
        .as_ref()
        .map_or(0.0, |d| d.root_flops() / pattern.nnz().max(1) as f64);
    if may_switch && per_entry_bound > threshold {
        notes.push(format!(
            "note: the root separator of a nested-dissection factor ({} unknowns, a \
             dense block) alone would cost {:.1e} operations ({per_entry_bound:.1e} \
             per entry of K); solving iteratively instead (set solver.method to \
             factorise)",
            dissection.as_ref().map_or(0, |d| d.root_separator),
            dissection.as_ref().map_or(0.0, Dissection::root_flops),
        ));
        return Ok(Chosen::iterative());
    }
    let (mut chol, report) = analyse_cholesky(structure, layout, settings.ordering, dissection)?;
    let per_entry = chol.flops() / pattern.nnz().max(1) as f64;
    match choose_precision(&mut chol, structure.nnz(), settings, notes) {
        Ok(()) if may_switch && per_entry > threshold => {
            notes.push(format!(
                "note: a direct factor would cost {:.1e} operations ({per_entry:.1e} \
                 per entry of K); solving iteratively instead (set solver.method \
                 to factorise)",
                chol.flops()
            ));
            Ok(Chosen::iterative())
        }
        Ok(()) => Ok(Chosen {
            source,
            factor: Factor::Cholesky(chol),
            ordering: Some(report),
            surrogate: source == Source::Surrogate,
        }),
        Err(Error::Numerical(e @ NumericalError::TooLarge { .. })) if settings.automatic => {
            notes.push(format!(
                "note: {e}; solving iteratively instead (solver.method = \
                 \"iterative\": Krylov iterations with a two-level preconditioner, \
                 no factor of K)"
            ));
            Ok(Chosen::iterative())
        }
        Err(e) => {
            if matches!(e, Error::Numerical(NumericalError::TooLarge { .. })) {
                notes.push(
                    "note: solver.method = \"iterative\" (the default when \
                     solver.method is left out) stores no factor of K",
                );
            }
            Err(e)
        }
    }
}

/// Stores `chol` in the precision `settings` ask for, and refuses a factor
/// that does not fit in memory (`auto`: single precision when only that fits).
pub(super) fn choose_precision(
    chol: &mut Cholesky,
    nnz_k: usize,
    settings: &SolverSettings,
    notes: &mut Notes,
) -> Result<(), Error> {
    let limit = settings.memory_limit_bytes;
    let check = |chol: &Cholesky| {
        let what = if chol.is_single() {
            "the sparse factor in single precision"
        } else {
            "the sparse factor"
        };
        check_memory(|| what.into(), chol.factor_bytes(nnz_k) as f64, limit)
    };
    match settings.precision {
        Precision::Double => check(chol)?,
        Precision::Mixed => {
            chol.use_single_precision();
            check(chol)?;
        }
        Precision::Auto if chol.nnz_l() >= MIXED_FROM_NNZ_L => {
            chol.use_single_precision();
            check(chol)?;
        }
        Precision::Auto => {
            if let Err(double) = check(chol) {
                chol.use_single_precision();
                if check(chol).is_err() {
                    return Err(double.into());
                }
                notes.push(format!(
                    "note: {double}; factorising in single precision instead \
                     (solver.precision = \"mixed\"), refined to full accuracy"
                ));
            }
        }
    }
    Ok(())
}

/// Symbolic Cholesky analysis of `pattern` with the ordering asked for
/// (`auto`: AMD and nested dissection both analysed, the one whose numeric
/// factorisation needs fewer operations kept; nested dissection alone above
/// [`AUTO_AMD_UP_TO_NNZ_K`]); `dissection` is a nested dissection already done.
pub(super) fn analyse_cholesky(
    pattern: &Pattern,
    layout: Layout,
    ordering: Ordering,
    dissection: Option<Dissection>,
) -> Result<(Cholesky, OrderingReport), Error> {
    let mut report = OrderingReport {
        chosen: ordering,
        nnz_l_amd: None,
        nnz_l_nested_dissection: None,
        flops_amd: None,
        flops_nested_dissection: None,
        dissection_seconds: 0.0,
    };
    let large = pattern.nnz() > AUTO_AMD_UP_TO_NNZ_K;
    let amd = match ordering {
        Ordering::Auto if large => None,
        Ordering::Amd | Ordering::Auto => {
            let chol = Cholesky::analyse(pattern.symbolic(), None)?;
            report.nnz_l_amd = Some(chol.nnz_l());
            report.flops_amd = Some(chol.flops());
            Some(chol)
        }
        Ordering::NestedDissection => None,
    };
    let nd = match ordering {
        Ordering::NestedDissection | Ordering::Auto => {
            let t = Instant::now();
            let order = match dissection {
                Some(done) => done.order,
                None => nested_dissection(layout.x, layout.dofs, pattern).order,
            };
            report.dissection_seconds = t.elapsed().as_secs_f64();
            let chol = Cholesky::analyse(pattern.symbolic(), Some(&order))?;
            report.nnz_l_nested_dissection = Some(chol.nnz_l());
            report.flops_nested_dissection = Some(chol.flops());
            Some(chol)
        }
        Ordering::Amd => None,
    };
    let chol = match (amd, nd) {
        // The factor that costs less to compute (and, nearly always, to store).
        (Some(a), Some(n)) if n.flops() < a.flops() => {
            report.chosen = Ordering::NestedDissection;
            n
        }
        (Some(a), _) => {
            report.chosen = Ordering::Amd;
            a
        }
        (None, Some(n)) => {
            report.chosen = Ordering::NestedDissection;
            n
        }
        (None, None) => unreachable!("every ordering analyses at least one"),
    };
    Ok((chol, report))
}
