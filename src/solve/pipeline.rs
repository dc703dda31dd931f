//! One solver pipeline for every driver: the symbolic analysis once per
//! pattern, numeric factorisation, solve with iterative refinement and a
//! residual check, and re-solves after a small change of `K` (bonds broke) with
//! the previous factor as preconditioner.
//!
//! Routes (`solver.method`):
//!
//! | method | fresh solve | re-solve with the old factor |
//! |---|---|---|
//! | `cholesky` | `K = L Lᵀ`, triangular solves, refinement | CG preconditioned by the old `L Lᵀ` |
//! | `lu` | `K = L U`, triangular solves, refinement | GMRES preconditioned by the old `L U` |
//! | `gmres` | GMRES on `K` preconditioned by the Cholesky factor of a symmetric surrogate | GMRES with the old surrogate factor |
//! | `iterative` | CG on `K` (GMRES if not symmetric) preconditioned by a two-level cycle ([`super::two_level`]): no factor of `K` | the same with the old cycle |
//!
//! The surrogate of the `gmres` route is the bond-based stiffness on the bonded
//! pairs (shear model: its pattern is the bond graph, far sparser than `K`'s
//! neighbours-of-neighbours pattern), or `(K + Kᵀ)/2`. When the bond-based
//! surrogate stalls (near incompressibility it has no Poisson ratio), the route
//! switches to the Cholesky factor of `(K + Kᵀ)/2`, and to LU when that is not
//! positive definite; the switch is kept for later solves and said on stderr.
//!
//! **Automatic route.** Unless the scene names a method (or runs fracture,
//! whose re-solves update a factor exactly), a direct factor is replaced by the
//! `iterative` route when the symbolic analysis predicts more than
//! [`ITERATIVE_FROM_FLOPS_PER_ENTRY`] operations per stored entry of `K` (the
//! factor's cost grows faster than the iterations'; 3D bodies cross it early).
//! Any route whose factor does not fit in memory in either precision becomes
//! `iterative`, with a note.
//!
//! When the factor of the `cholesky` or `gmres` route does not fit in memory
//! in either precision, the route becomes `iterative`, with a note.
//!
//! **Residual check.** A solve is accepted when its relative residual is at
//! most [`RESIDUAL_THRESHOLD`]. A direct solve is first refined with its own
//! factor ([`super::refine`]); if its residual stays above the threshold, it is
//! refined again with a more accurate residual ([`super::refine_extended`]):
//! the model's bond forces ([`Pipeline::solve_with_residual`], static solves)
//! or `K x` in extended precision. When those corrections contract below
//! [`super::REFINED_ACCURACY`] of the answer, the residual is the round-off
//! floor of an ill-conditioned system (a 10⁶-point 1D bar: `κ ≈ 4e11`,
//! residual 2.1e-8, answer to 5e-12), accepted with a note; otherwise the
//! system is singular to double precision and the solve is refused, with the
//! route that does better where there is one.
//!
//! **Re-solves.** The pattern never changes when bonds break (broken bonds keep
//! their slots), so the symbolic analysis is done once. If `k` bonds broke
//! since the factorisation, `K_new = K_old − ΔK` with `ΔK` of low rank and the
//! preconditioned operator has few distinct eigenvalues: CG converges in about
//! `rank(ΔK) + 1` iterations (a bond-based bond is a rank-one term). Past a
//! threshold of iterations the matrix is factorised afresh: by default the
//! number of iterations that costs as much as half a fresh factorisation and
//! solve, both measured in this run (`solver.refactor_iterations` overrides it).

use super::cg::pcg;
use super::gmres::{gmres, GmresReport};
use super::low_rank::{LowRank, Term};
use super::ordering::{nested_dissection, Dissection};
use super::two_level::TwoLevel;
use super::{
    refine, refine_extended, relative_residual, Cholesky, FactorError, PivotStats, SparseLu,
    GMRES_TOLERANCE,
};
use crate::assembly::dofs::DofMap;
use crate::assembly::pattern::Pattern;
use crate::assembly::stiffness::Stiffness;
use crate::discretization::Discretization;
use crate::error::{Error, InputError, NumericalError};
use crate::memory::check_memory;
use crate::model::bond_based::BondBased;
use crate::model::Coupling;
use crate::scene::solver::{Ordering, Precision, SolverMethod, SolverSettings};
use serde::Serialize;
use std::time::Instant;

/// Largest relative residual accepted from any solve.
pub const RESIDUAL_THRESHOLD: f64 = 1e-8;

/// GMRES iterations allowed with the bond-based surrogate before switching to
/// the symmetric part of the shear tangent.
const SURROGATE_BUDGET: usize = 120;

/// GMRES iterations allowed with the factor of the symmetric part.
const SYMMETRIC_PART_BUDGET: usize = 600;

/// Largest number of free unknowns `solver.method = "lu"` accepts: faer's
/// sparse LU (whose fill is not known before the numeric factorisation) took
/// 0.64 s and 189 MiB at 4,896 unknowns, 6.4 s and 1.3 GiB at 19,796 and
/// 90 s and 10 GiB at 79,596 (shear model, plane stress, m = 3.015), where the
/// `gmres` and `iterative` routes take 2-3 s.
pub const LU_MAX_UNKNOWNS: usize = 20_000;

/// Krylov iterations allowed with the two-level preconditioner (it needs
/// 15-25 on the bodies measured, independent of their size).
pub const ITERATIVE_BUDGET: usize = 2000;

/// Predicted factorisation operations per stored entry of `K` above which the
/// automatic route is iterative. Measured (two threads): at 4.6e3 (2D,
/// 40,000 points) a direct solve and the two-level iterations cost the same;
/// 3D bodies reach 1e5 at 50,000 points, where the iterations are 8× faster.
/// The margin keeps the direct route, whose cost does not depend on the
/// conditioning and whose failures name the point of a mechanism, wherever it
/// is not clearly slower.
pub const ITERATIVE_FROM_FLOPS_PER_ENTRY: f64 = 2e4;

/// GMRES restart length.
const GMRES_RESTART: usize = 60;

/// An update solve that costs more than this fraction of a fresh factorisation
/// and solve makes the next re-solve factorise afresh.
const UPDATE_BUDGET: f64 = 0.2;

/// Largest memory for the columns of the low-rank update (bytes), unless the
/// factor itself is larger.
const UPDATE_MEMORY: usize = 256 << 20;

/// Bounds of the automatic refactorisation threshold (iterations).
const AUTO_REFACTOR_MIN: usize = 4;
const AUTO_REFACTOR_MAX: usize = 1000;

/// What the driver knows about the system that its matrix does not say.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Hints {
    /// A fracture run: re-solves update a direct factor exactly (low-rank
    /// terms), which needs it in double precision, and the route stays direct.
    pub fracture: bool,
    /// A nearly incompressible body, where the two-level preconditioner is
    /// weak: cost alone never selects it.
    pub near_incompressible: bool,
}

/// Factor size from which `auto` factorises in single precision: measured on
/// the 2D square (bond-based, δ = 3.015Δx, one thread), single precision halves
/// the numeric factorisation (9.3 → 4.7 s at 160,000 points, nnz(L) 2.0e8) but
/// its CG iterations cost about what it saves at 40,000 points (nnz(L) 4.0e7).
pub const MIXED_FROM_NNZ_L: usize = 100_000_000;

/// Largest relative residual a mixed-precision solve is accepted with, when
/// CG stops at the round-off floor above [`GMRES_TOLERANCE`]; above it the
/// solve falls back to a double-precision factor.
const MIXED_ACCEPT: f64 = 1e-10;

/// CG iterations a mixed-precision solve may take before it falls back to a
/// double-precision factor (it needs about 3-6 when `κ(K) ε₃₂ ≪ 1`).
const MIXED_ITERATIONS: usize = 60;

/// Stores `chol` in the precision `settings` ask for, and refuses a factor
/// that does not fit in memory (`auto`: single precision when only that fits).
fn choose_precision(
    chol: &mut Cholesky,
    nnz_k: usize,
    settings: &SolverSettings,
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
                eprintln!(
                    "note: {double}; factorising in single precision instead \
                     (solver.precision = \"mixed\"), refined to full accuracy"
                );
            }
        }
    }
    Ok(())
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

/// Size of `K` (stored entries) up to which `auto` analyses both orderings.
/// Above it AMD's own analysis becomes costly (15 s at a million 2D points,
/// a quarter of the factorisation) while nested dissection needs half its flops
/// on every bulky body measured, so `auto` analyses nested dissection alone
/// (`solver.ordering = "amd"` still forces AMD, e.g. for long thin bodies).
pub const AUTO_AMD_UP_TO_NNZ_K: usize = 50_000_000;

/// Symbolic Cholesky analysis of `pattern` with the ordering asked for
/// (`auto`: AMD and nested dissection both analysed, the one whose numeric
/// factorisation needs fewer operations kept; nested dissection alone above
/// [`AUTO_AMD_UP_TO_NNZ_K`]).
fn analyse_cholesky(
    pattern: &Pattern,
    disc: &Discretization,
    dofs: &DofMap,
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
                None => nested_dissection(&disc.points.x, dofs, pattern).order,
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

/// How a solve was done.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Route {
    /// A fresh numeric factorisation, then the solve.
    Factor,
    /// A Krylov solve preconditioned by the previous factor.
    Reuse,
    /// The previous factor updated by the rank-one terms of the broken bonds
    /// (Sherman–Morrison–Woodbury, [`super::low_rank`]): exact, no iteration.
    Update,
}

impl Route {
    /// The name used in reports.
    pub fn name(self) -> &'static str {
        match self {
            Route::Factor => "factor",
            Route::Reuse => "reuse",
            Route::Update => "update",
        }
    }
}

/// What one solve did and cost.
#[derive(Debug, Clone, Serialize)]
pub struct SolveReport {
    /// Fresh factorisation or reuse of the old factor.
    pub route: Route,
    /// Krylov iterations (0 for a direct solve).
    pub iterations: usize,
    /// Iterative-refinement steps after a direct solve.
    pub refinement_steps: usize,
    /// `‖K x − b‖ / ‖b‖`.
    pub residual: f64,
    /// Numeric factorisation time (s), 0 for a reuse.
    pub factor_seconds: f64,
    /// Solve time (s): triangular solves, Krylov iterations, refinement,
    /// residual; for a reuse that fell back to a factorisation, the failed
    /// attempt too.
    pub solve_seconds: f64,
    /// The GMRES report, when GMRES ran.
    pub gmres: Option<GmresReport>,
}

/// A solution of the reduced system and how it was obtained.
#[derive(Debug, Clone)]
pub struct Solved {
    /// Free unknowns.
    pub x: Vec<f64>,
    /// What the solve did.
    pub report: SolveReport,
}

/// What the current factor is a factor of.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Source {
    /// `K` itself (Cholesky or LU).
    Matrix,
    /// `(K + Kᵀ)/2` (GMRES).
    SymmetricPart,
    /// The bond-based stiffness on the bond pattern (GMRES on the shear model).
    Surrogate,
    /// `K` itself, through the two-level preconditioner (the `iterative` route).
    TwoLevel,
}

/// The bond-based stiffness on the bonds of `K`, which the `gmres` route
/// assembles itself and factorises as a preconditioner.
struct Surrogate {
    pattern: Pattern,
    model: BondBased,
}

enum Factor {
    Cholesky(Cholesky),
    Lu(SparseLu),
    /// Built at the numeric stage, from the values of `K`.
    TwoLevel(Option<TwoLevel>),
}

impl Factor {
    /// A direct factor's solve (the two-level cycle goes through
    /// [`Pipeline::precondition`], which has `K`).
    fn solve_in_place(&self, b: &mut [f64]) {
        match self {
            Factor::Cholesky(c) => c.solve_in_place(b),
            Factor::Lu(l) => l.solve_in_place(b),
            Factor::TwoLevel(_) => unreachable!("the two-level cycle needs K"),
        }
    }

    fn is_single(&self) -> bool {
        matches!(self, Factor::Cholesky(c) if c.is_single())
    }
}

/// Measured costs that decide when a re-solve should refactorise.
#[derive(Debug, Clone, Copy, Default)]
struct Costs {
    /// Last fresh factorisation plus its solve (s).
    fresh_seconds: f64,
    /// One Krylov iteration (product and preconditioner), last measured (s).
    iteration_seconds: f64,
    /// GMRES iterations a fresh surrogate factor needed (0 for direct routes).
    fresh_iterations: usize,
    /// Residual the last fresh solve reached (the round-off floor of this system).
    fresh_residual: f64,
}

/// The solver pipeline of one discretisation.
pub struct Pipeline {
    settings: SolverSettings,
    pattern: Pattern,
    /// Transposed positions of `K`'s entries (non-symmetric `K`, symmetric part).
    transpose: Option<Vec<usize>>,
    surrogate: Option<Surrogate>,
    source: Source,
    factor: Factor,
    factored: bool,
    symmetric: bool,
    costs: Costs,
    /// Free unknowns held at zero (fracture runs) and the diagonal they get.
    pinned: Option<(Vec<bool>, f64)>,
    /// Rank-one terms removed since the factorisation (bond-based re-solves).
    low_rank: LowRank,
    /// The last right-hand side and `M⁻¹` of it (the old factor's solve).
    factor_solution: Option<(Vec<f64>, Vec<f64>)>,
    /// An update cost more than [`UPDATE_BUDGET`] of a fresh solve: factorise next time.
    refactor_next: bool,
    /// Symbolic analysis time (s).
    pub symbolic_seconds: f64,
    /// Sparsity pattern time (s).
    pub pattern_seconds: f64,
    /// The Cholesky factor's ordering (None for LU).
    pub ordering: Option<OrderingReport>,
}

impl Pipeline {
    /// Builds the pattern of `K` for `coupling` and runs the symbolic analysis of
    /// the route, before any value is assembled, so that a factor too large for
    /// memory is refused early (or replaced by the `iterative` route). `surrogate`
    /// is the bond-based model the `gmres` route factorises for a `Family` coupling.
    pub fn analyse(
        disc: &Discretization,
        dofs: &DofMap,
        coupling: Coupling,
        mut settings: SolverSettings,
        hints: Hints,
        surrogate: Option<BondBased>,
    ) -> Result<Self, Error> {
        if hints.fracture {
            // Fracture re-solves update the factor exactly (low-rank terms),
            // which needs it in double precision.
            settings.precision = Precision::Double;
        }
        if settings.method == SolverMethod::Lu && dofs.n_free() > LU_MAX_UNKNOWNS {
            return Err(InputError::new(
                "solver.method",
                format!(
                    "sparse LU is offered up to {LU_MAX_UNKNOWNS} free unknowns and this body \
                     has {}: its fill is not predicted and grows fast (measured on the shear \
                     model: 6.4 s and 1.3 GiB at 19,796 unknowns, 90 s and 10 GiB at 79,596); \
                     leave solver.method out (Cholesky for the bond-based model, GMRES for the \
                     shear model) or use \"iterative\"",
                    dofs.n_free()
                ),
            )
            .into());
        }
        let t = Instant::now();
        let limit = settings.memory_limit_bytes;
        let pattern = Pattern::new(disc, dofs, coupling, limit)?;
        let mut surrogate = match (settings.method, coupling, surrogate) {
            (SolverMethod::Gmres, Coupling::Family, Some(model)) => Some(Surrogate {
                pattern: Pattern::new(disc, dofs, Coupling::Star, limit)?,
                model,
            }),
            _ => None,
        };
        let pattern_seconds = t.elapsed().as_secs_f64();
        let t = Instant::now();
        let mut ordering = None;
        let iterative = (Source::TwoLevel, Factor::TwoLevel(None));
        let (source, factor) = match settings.method {
            SolverMethod::Lu => (
                Source::Matrix,
                Factor::Lu(SparseLu::analyse(pattern.symbolic())?),
            ),
            SolverMethod::Iterative => iterative,
            SolverMethod::Cholesky | SolverMethod::Gmres => 'route: {
                let (source, structure) = match (&surrogate, settings.method) {
                    (Some(s), _) => (Source::Surrogate, &s.pattern),
                    (None, SolverMethod::Gmres) => (Source::SymmetricPart, &pattern),
                    _ => (Source::Matrix, &pattern),
                };
                // Where nested dissection is the only candidate, its root
                // separator bounds the factor's cost from below: past the
                // threshold the symbolic analysis is not worth running.
                let nd_only = settings.ordering == Ordering::NestedDissection
                    || (settings.ordering == Ordering::Auto
                        && structure.nnz() > AUTO_AMD_UP_TO_NNZ_K);
                let dissection =
                    nd_only.then(|| nested_dissection(&disc.points.x, dofs, structure));
                let per_entry_bound = dissection
                    .as_ref()
                    .map_or(0.0, |d| d.root_flops() / pattern.nnz().max(1) as f64);
                if settings.automatic
                    && !hints.fracture
                    && !hints.near_incompressible
                    && per_entry_bound > ITERATIVE_FROM_FLOPS_PER_ENTRY
                {
                    eprintln!(
                        "note: the root separator of a nested-dissection factor ({} unknowns, a \
                         dense block) alone would cost {:.1e} operations ({per_entry_bound:.1e} \
                         per entry of K); solving iteratively instead (set solver.method to \
                         factorise)",
                        dissection.as_ref().map_or(0, |d| d.root_separator),
                        dissection.as_ref().map_or(0.0, Dissection::root_flops),
                    );
                    surrogate = None;
                    break 'route iterative;
                }
                let (mut chol, report) =
                    analyse_cholesky(structure, disc, dofs, settings.ordering, dissection)?;
                let per_entry = chol.flops() / pattern.nnz().max(1) as f64;
                match choose_precision(&mut chol, structure.nnz(), &settings) {
                    Ok(())
                        if settings.automatic
                            && !hints.fracture
                            && !hints.near_incompressible
                            && per_entry > ITERATIVE_FROM_FLOPS_PER_ENTRY =>
                    {
                        eprintln!(
                            "note: a direct factor would cost {:.1e} operations ({per_entry:.1e} \
                             per entry of K); solving iteratively instead (set solver.method \
                             to factorise)",
                            chol.flops()
                        );
                        surrogate = None;
                        iterative
                    }
                    Ok(()) => {
                        ordering = Some(report);
                        (source, Factor::Cholesky(chol))
                    }
                    Err(Error::Numerical(e @ NumericalError::TooLarge { .. }))
                        if settings.automatic =>
                    {
                        eprintln!(
                            "note: {e}; solving iteratively instead (solver.method = \
                             \"iterative\": Krylov iterations with a two-level preconditioner, \
                             no factor of K)"
                        );
                        surrogate = None;
                        iterative
                    }
                    Err(e) => {
                        if matches!(e, Error::Numerical(NumericalError::TooLarge { .. })) {
                            eprintln!(
                                "note: solver.method = \"iterative\" (the default when \
                                 solver.method is left out) stores no factor of K"
                            );
                        }
                        return Err(e);
                    }
                }
            }
        };
        Ok(Self {
            settings,
            transpose: None,
            symmetric: coupling == Coupling::Star,
            pattern,
            surrogate,
            source,
            factor,
            factored: false,
            costs: Costs::default(),
            pinned: None,
            low_rank: LowRank::default(),
            factor_solution: None,
            refactor_next: false,
            symbolic_seconds: t.elapsed().as_secs_f64(),
            pattern_seconds,
            ordering,
        })
    }

    /// Free unknowns (by free index) that every factorised matrix holds at zero:
    /// the caller pins them in `K` ([`Stiffness::pin`]); the pipeline does the
    /// same in the surrogate it assembles itself.
    pub fn set_pinned(&mut self, pinned: Vec<bool>, diagonal: f64) {
        self.pinned = Some((pinned, diagonal));
    }

    /// The pattern of `K` (assemble on it).
    pub fn pattern(&self) -> &Pattern {
        &self.pattern
    }

    /// Gives the pattern back (for export after the last solve).
    pub fn into_pattern(self) -> Pattern {
        self.pattern
    }

    /// The route this pipeline solves by (`iterative` when it replaced a factor).
    pub fn method(&self) -> SolverMethod {
        match (self.source, &self.factor) {
            (Source::TwoLevel, _) => SolverMethod::Iterative,
            (_, Factor::Lu(_)) => SolverMethod::Lu,
            (Source::Surrogate | Source::SymmetricPart, _) => SolverMethod::Gmres,
            _ => SolverMethod::Cholesky,
        }
    }

    /// Stored entries of the current factor (Cholesky), if known.
    pub fn nnz_factor(&self) -> Option<usize> {
        match &self.factor {
            Factor::Cholesky(c) => Some(c.nnz_l()),
            Factor::TwoLevel(t) => t.as_ref().map(TwoLevel::nnz_coarse_factor),
            Factor::Lu(_) => None,
        }
    }

    /// Pivot statistics of the last Cholesky factorisation.
    pub fn pivot_stats(&self) -> Option<PivotStats> {
        match &self.factor {
            Factor::Cholesky(c) => c.pivot_stats,
            _ => None,
        }
    }

    /// `‖K − Kᵀ‖_F / ‖K‖_F`.
    pub fn asymmetry(&mut self, k: &Stiffness) -> f64 {
        k.asymmetry(self.transpose())
    }

    fn transpose(&mut self) -> &[usize] {
        if self.transpose.is_none() {
            self.transpose = Some(Stiffness::transpose_positions(&self.pattern));
        }
        self.transpose.as_deref().expect("just computed")
    }

    /// `K x`, in parallel.
    fn product(&self, k: &Stiffness, x: &[f64]) -> Vec<f64> {
        k.mul_parallel(&self.pattern, self.symmetric, x)
    }

    /// Numeric factorisation of the current source for `k`.
    fn factorize(
        &mut self,
        disc: &Discretization,
        dofs: &DofMap,
        k: &Stiffness,
    ) -> Result<(), Error> {
        self.factored = false;
        if self.source == Source::TwoLevel {
            let product = |v: &[f64]| self.product(k, v);
            let two_level = TwoLevel::new(disc, dofs, &self.pattern, &k.values, &product)?;
            self.factor = Factor::TwoLevel(Some(two_level));
            self.factored = true;
            return Ok(());
        }
        let surrogate_values;
        let symmetric_values;
        let matrix = match self.source {
            Source::Matrix | Source::TwoLevel => k.view(&self.pattern),
            Source::SymmetricPart => {
                symmetric_values = k.symmetric_part(self.transpose());
                symmetric_values.view(&self.pattern)
            }
            Source::Surrogate => {
                let s = self.surrogate.as_ref().expect("surrogate route");
                let mut values = Stiffness::assemble(&s.model, disc, dofs, &s.pattern);
                if let Some((pinned, diagonal)) = &self.pinned {
                    values.pin(&s.pattern, pinned, *diagonal, None);
                }
                surrogate_values = values;
                surrogate_values.view(&s.pattern)
            }
        };
        let result = match &mut self.factor {
            Factor::Cholesky(c) => c.factorize(matrix),
            Factor::Lu(l) => l.factorize(matrix),
            Factor::TwoLevel(_) => unreachable!("built above"),
        };
        result.map_err(|e| factor_error(e, dofs, disc))?;
        self.factored = true;
        Ok(())
    }

    /// Stores the Cholesky factor in double precision from now on (after a
    /// single-precision factor failed), checking that it fits in memory.
    fn use_double_precision(&mut self) -> Result<(), Error> {
        self.settings.precision = Precision::Double;
        let nnz_k = match (&self.surrogate, self.source) {
            (Some(s), Source::Surrogate) => s.pattern.nnz(),
            _ => self.pattern.nnz(),
        };
        if let Factor::Cholesky(chol) = &mut self.factor {
            chol.use_double_precision();
            choose_precision(chol, nnz_k, &self.settings)?;
        }
        Ok(())
    }

    /// Switches the `gmres` route from its current factor to the next one:
    /// surrogate → symmetric part → LU of `K`.
    fn fall_back(
        &mut self,
        disc: &Discretization,
        dofs: &DofMap,
        k: &Stiffness,
    ) -> Result<(), Error> {
        if self.source == Source::Surrogate {
            let (mut chol, report) =
                analyse_cholesky(&self.pattern, disc, dofs, self.settings.ordering, None)?;
            self.ordering = Some(report);
            choose_precision(&mut chol, self.pattern.nnz(), &self.settings)?;
            let full = k.symmetric_part(self.transpose());
            match chol.factorize(full.view(&self.pattern)) {
                Ok(()) => {
                    self.source = Source::SymmetricPart;
                    self.factor = Factor::Cholesky(chol);
                    self.factored = true;
                    return Ok(());
                }
                Err(FactorError::NonPositivePivot(_) | FactorError::NearlySingular(..)) => {
                    // Possible with the gradient dilatation near ν = 1/2: K is
                    // regular but its symmetric part is indefinite.
                    eprintln!(
                        "note: the symmetric part of the tangent is not positive definite; \
                         solving with sparse LU instead"
                    );
                }
                Err(e) => return Err(factor_error(e, dofs, disc)),
            }
        }
        self.source = Source::Matrix;
        self.factor = Factor::Lu(SparseLu::analyse(self.pattern.symbolic())?);
        self.symmetric = false;
        self.factorize(disc, dofs, k)
    }

    /// Factorises `k` afresh and solves `K x = rhs`, with refinement (direct
    /// routes) and the residual check.
    pub fn solve(
        &mut self,
        disc: &Discretization,
        dofs: &DofMap,
        k: &Stiffness,
        rhs: &[f64],
    ) -> Result<Solved, Error> {
        self.solve_refined(disc, dofs, k, rhs, None)
    }

    /// [`Pipeline::solve`] with the model's own residual `rhs − K x`
    /// (`model_residual`, from the internal forces of the bonds) for the
    /// refinement of a direct solve whose residual stays above the threshold.
    /// The bond forces balance exactly, so the model's residual is free of the
    /// rounding of `K`'s diagonal (each a sum of bond stiffnesses), which acts
    /// like springs to the ground: identical in every row of a uniform chain,
    /// it moved the answer of a 10⁶-point 1D bar by 3e-5.
    pub fn solve_with_residual(
        &mut self,
        disc: &Discretization,
        dofs: &DofMap,
        k: &Stiffness,
        rhs: &[f64],
        model_residual: &dyn Fn(&[f64]) -> Vec<f64>,
    ) -> Result<Solved, Error> {
        self.solve_refined(disc, dofs, k, rhs, Some(model_residual))
    }

    fn solve_refined(
        &mut self,
        disc: &Discretization,
        dofs: &DofMap,
        k: &Stiffness,
        rhs: &[f64],
        model_residual: Option<&dyn Fn(&[f64]) -> Vec<f64>>,
    ) -> Result<Solved, Error> {
        if let Some((point, value)) = self.out_of_range(disc, dofs, k) {
            return Err(crate::discretization::beyond_double_precision(
                disc,
                point,
                "a stiffness entry",
                value,
            )
            .into());
        }
        let t = Instant::now();
        if let Err(e) = self.factorize(disc, dofs, k) {
            if !self.factor.is_single() {
                return Err(e);
            }
            // A pivot lost to single-precision round-off: the matrix is too
            // ill-conditioned for a single-precision factor.
            eprintln!("note: the single-precision factorisation failed ({e}); factorising in double precision");
            self.use_double_precision()?;
            self.factorize(disc, dofs, k)?;
        }
        let factor_seconds = t.elapsed().as_secs_f64();
        let t = Instant::now();
        let mut x = vec![0.0; rhs.len()];
        let mut report = None;
        let (mut residual, mut refinement_steps);
        // A direct solve refined in extended precision to the answer rounded
        // to double precision, with a residual at the round-off floor.
        let mut at_floor = false;
        // Mixed precision: CG on K preconditioned by the single-precision
        // factor, to the residual the direct routes reach; None when there is
        // no single-precision factor or it was not good enough (then the
        // matrix is factorised again in double precision).
        let mixed = if self.source == Source::Matrix && self.factor.is_single() {
            let cg = {
                let apply = |v: &[f64]| self.product(k, v);
                let precondition = |v: &mut [f64]| self.factor.solve_in_place(v);
                pcg(
                    &apply,
                    &precondition,
                    rhs,
                    &mut x,
                    GMRES_TOLERANCE,
                    MIXED_ITERATIONS,
                )
            };
            // Large systems stop at the round-off floor of their products
            // (2e-12 at a million points), which the direct route would accept
            // after refinement too; anything higher means the single-precision
            // factor is not good enough.
            if cg.relative_residual <= MIXED_ACCEPT {
                Some(cg)
            } else {
                eprintln!(
                    "note: CG with the single-precision factor reached {:.1e} after {} \
                     iterations (the matrix is too ill-conditioned for single precision); \
                     factorising in double precision",
                    cg.relative_residual, cg.iterations
                );
                self.use_double_precision()?;
                self.factorize(disc, dofs, k)?;
                None
            }
        } else {
            None
        };
        if let Some(cg) = mixed {
            residual = cg.relative_residual;
            refinement_steps = 0;
            report = Some(cg);
            self.costs.fresh_iterations = 0;
        } else if self.source == Source::Matrix {
            x.copy_from_slice(rhs);
            self.factor.solve_in_place(&mut x);
            let apply = |v: &[f64]| self.product(k, v);
            let solve = |v: &mut [f64]| self.factor.solve_in_place(v);
            (residual, refinement_steps) = refine(&apply, &solve, rhs, &mut x);
            if !(residual <= RESIDUAL_THRESHOLD) {
                // The residual of a double-precision product may be all
                // round-off (ε ‖|K||x|‖ above 1e-8 ‖f‖: a long 1D chain):
                // refine with the model's residual, else with `K`'s in
                // extended precision.
                let pattern = &self.pattern;
                let extended_k = |v: &[f64]| k.residual_extended(pattern, v, rhs);
                let exact = model_residual.unwrap_or(&extended_k);
                let extended = refine_extended(exact, &solve, rhs, &mut x);
                refinement_steps += extended.steps;
                residual = extended.residual;
                at_floor = extended.converged;
                if at_floor && !(residual <= RESIDUAL_THRESHOLD) {
                    let of = if model_residual.is_some() {
                        "the residual of the bond forces (which balance exactly)"
                    } else {
                        "the residual of the assembled stiffness in extended precision (the \
                         answer is exact for it; its rounding, ε per entry, may move the answer \
                         by up to κ(K) ε)"
                    };
                    eprintln!(
                        "note: the relative residual {residual:.3e} is above \
                         {RESIDUAL_THRESHOLD:.0e} but at the round-off floor of this system \
                         (ε ‖|K||u|‖ / ‖f‖ = {:.3e}, the residual of the answer rounded to \
                         double precision): iterative refinement with {of} converged in {} \
                         step(s), the last changing the answer by {:.1e} of its size (an \
                         ill-conditioned system, e.g. a long 1D chain, whose condition number \
                         grows like n²)",
                        f64::EPSILON * self.round_off_scale(k, &x, rhs),
                        extended.steps,
                        extended.accuracy
                    );
                }
            }
            self.costs.fresh_iterations = 0;
        } else if self.source == Source::TwoLevel && self.symmetric {
            let apply = |v: &[f64]| self.product(k, v);
            let precondition = |v: &mut [f64]| self.precondition(k, v);
            let cg = pcg(
                &apply,
                &precondition,
                rhs,
                &mut x,
                GMRES_TOLERANCE,
                ITERATIVE_BUDGET,
            );
            if cg.stagnated {
                return Err(NumericalError::Solver(format!(
                    "the stiffness matrix is not positive definite: CG met a direction of zero \
                     or negative stiffness after {} iterations (a mechanism: a point held by \
                     too few bonds or by bonds all along one line); solver.method = \
                     \"cholesky\" names the point",
                    cg.iterations
                ))
                .into());
            }
            self.costs.fresh_iterations = cg.iterations;
            residual = cg.relative_residual;
            refinement_steps = 0;
            report = Some(cg);
        } else {
            let mut first = self.gmres(k, rhs, &mut x, self.budget());
            if !first.converged && self.source == Source::Surrogate {
                // Near incompressibility the bond-based surrogate (which has no
                // Poisson ratio) stalls: continue with the symmetric part.
                eprintln!(
                    "note: GMRES with the bond-based preconditioner stopped at residual {:.1e} \
                     after {} iterations; continuing with the Cholesky factor of the symmetric part",
                    first.relative_residual, first.iterations
                );
                self.fall_back(disc, dofs, k)?;
                let second = if self.source == Source::Matrix {
                    let ax = self.product(k, &x);
                    let mut dx: Vec<f64> = rhs.iter().zip(&ax).map(|(b, a)| b - a).collect();
                    self.factor.solve_in_place(&mut dx);
                    x.iter_mut().zip(&dx).for_each(|(xi, di)| *xi += di);
                    let apply = |v: &[f64]| self.product(k, v);
                    let solve = |v: &mut [f64]| self.factor.solve_in_place(v);
                    let (r, _) = refine(&apply, &solve, rhs, &mut x);
                    GmresReport {
                        iterations: 0,
                        relative_residual: r,
                        converged: r <= GMRES_TOLERANCE,
                        stagnated: false,
                    }
                } else {
                    self.gmres(k, rhs, &mut x, self.budget())
                };
                first = GmresReport {
                    iterations: first.iterations + second.iterations,
                    ..second
                };
            }
            self.costs.fresh_iterations = first.iterations;
            residual = relative_residual(&self.product(k, &x), rhs);
            refinement_steps = 0;
            report = Some(first);
        }
        let solve_seconds = t.elapsed().as_secs_f64();
        if let (Source::TwoLevel, Some(r)) = (self.source, &report) {
            // Large systems stop at the round-off floor of their products.
            if !(r.relative_residual <= MIXED_ACCEPT) {
                eprintln!(
                    "note: the iterative route reached a relative residual of {:.1e} after {} \
                     iterations (budget {ITERATIVE_BUDGET}): no Krylov method goes below the \
                     round-off floor of an ill-conditioned system (a stiff part carried by a \
                     far softer one, a slender body in bending, a long 1D chain), and the \
                     two-level preconditioner is also weak near incompressibility; \
                     solver.method = \"cholesky\" solves directly",
                    r.relative_residual, r.iterations
                );
            }
        }
        self.accept(&x, residual, refinement_steps, at_floor)?;
        self.low_rank.clear();
        self.refactor_next = false;
        self.factor_solution = (self.source == Source::Matrix).then(|| (rhs.to_vec(), x.clone()));
        self.costs.fresh_seconds = factor_seconds + solve_seconds;
        self.costs.fresh_residual = residual;
        if self.costs.iteration_seconds == 0.0 {
            self.costs.iteration_seconds = self.measure_iteration(k, rhs);
        }
        Ok(Solved {
            x,
            report: SolveReport {
                route: Route::Factor,
                iterations: report.map_or(0, |r| r.iterations),
                refinement_steps,
                residual,
                factor_seconds,
                solve_seconds,
                gmres: report,
            },
        })
    }

    /// Re-solves `K x = rhs` after `K` changed a little, from the initial guess
    /// `x0`, with the previous factor as preconditioner (CG for a symmetric `K`
    /// factorised by Cholesky, GMRES otherwise). Past the refactorisation
    /// threshold it factorises afresh ([`Pipeline::solve`]).
    pub fn resolve(
        &mut self,
        disc: &Discretization,
        dofs: &DofMap,
        k: &Stiffness,
        rhs: &[f64],
        x0: &[f64],
    ) -> Result<Solved, Error> {
        if !self.factored {
            return self.solve(disc, dofs, k, rhs);
        }
        let cap = self.refactor_threshold();
        // A re-solve aims at the usual tolerance, or at the round-off floor that
        // the fresh solve of this system reached if that is higher.
        let tolerance = GMRES_TOLERANCE.max(10.0 * self.costs.fresh_residual);
        let t = Instant::now();
        let mut x = x0.to_vec();
        let cg = self.symmetric
            && matches!(self.source, Source::Matrix | Source::TwoLevel)
            && !matches!(self.factor, Factor::Lu(_));
        let report = if cg {
            let apply = |v: &[f64]| self.product(k, v);
            let precondition = |v: &mut [f64]| self.precondition(k, v);
            pcg(&apply, &precondition, rhs, &mut x, tolerance, cap)
        } else {
            self.gmres_to(k, rhs, &mut x, cap, tolerance)
        };
        let elapsed = t.elapsed().as_secs_f64();
        if report.iterations > 0 {
            self.costs.iteration_seconds = elapsed / report.iterations as f64;
        }
        let residual = report.relative_residual;
        if report.converged && x.iter().all(|v| v.is_finite()) {
            return Ok(Solved {
                x,
                report: SolveReport {
                    route: Route::Reuse,
                    iterations: report.iterations,
                    refinement_steps: 0,
                    residual,
                    factor_seconds: 0.0,
                    solve_seconds: elapsed,
                    gmres: (!cg).then_some(report),
                },
            });
        }
        let mut fresh = self.solve(disc, dofs, k, rhs)?;
        fresh.report.solve_seconds += elapsed;
        fresh.report.iterations += report.iterations;
        Ok(fresh)
    }

    /// GMRES on `K` preconditioned by the current factor, from `x`.
    fn gmres(&self, k: &Stiffness, rhs: &[f64], x: &mut [f64], budget: usize) -> GmresReport {
        self.gmres_to(k, rhs, x, budget, GMRES_TOLERANCE)
    }

    fn gmres_to(
        &self,
        k: &Stiffness,
        rhs: &[f64],
        x: &mut [f64],
        budget: usize,
        tolerance: f64,
    ) -> GmresReport {
        let apply = |v: &[f64]| self.product(k, v);
        let precondition = |v: &mut [f64]| self.precondition(k, v);
        gmres(
            &apply,
            &precondition,
            rhs,
            x,
            tolerance,
            GMRES_RESTART,
            budget,
        )
    }

    /// The old factor's solve, corrected by the low-rank terms removed since.
    fn precondition(&self, k: &Stiffness, v: &mut [f64]) {
        match &self.factor {
            Factor::TwoLevel(Some(t)) => t.apply(&|x: &[f64]| self.product(k, x), v),
            factor => factor.solve_in_place(v),
        }
        if !self.low_rank.is_empty() {
            let x = self.low_rank.apply(v);
            v.copy_from_slice(&x);
        }
    }

    /// Re-solves after `K` lost the rank-one `terms` (bonds that broke) since
    /// the last solve, updating the old Cholesky factor exactly (module docs of
    /// [`super::low_rank`]); falls back to [`Pipeline::resolve`] when the route
    /// has no Cholesky factor of `K`, when the update would cost more than a
    /// fresh factorisation is worth, or when its answer misses the tolerance.
    pub fn resolve_update(
        &mut self,
        disc: &Discretization,
        dofs: &DofMap,
        k: &Stiffness,
        rhs: &[f64],
        x0: &[f64],
        terms: Vec<Term>,
    ) -> Result<Solved, Error> {
        let chol = match (&self.factor, self.source, self.factored) {
            (Factor::Cholesky(c), Source::Matrix, true) if self.symmetric => c,
            _ => return self.resolve(disc, dofs, k, rhs, x0),
        };
        let memory = UPDATE_MEMORY.max(chol.nnz_l() * 8);
        let grown = self.low_rank.bytes() + terms.len() * rhs.len() * 8;
        if self.refactor_next || grown > memory {
            return self.solve(disc, dofs, k, rhs);
        }
        let t = Instant::now();
        let n = rhs.len();
        if !self.low_rank.extend(terms, n, &|v: &mut [f64], m| {
            chol.solve_columns_in_place(v, m)
        }) {
            // K is no longer positive definite: a fresh factorisation names the point.
            return self.solve(disc, dofs, k, rhs);
        }
        let y = match &self.factor_solution {
            Some((b, y)) if b.as_slice() == rhs => y.clone(),
            _ => {
                let mut y = rhs.to_vec();
                chol.solve_in_place(&mut y);
                self.factor_solution = Some((rhs.to_vec(), y.clone()));
                y
            }
        };
        let x = self.low_rank.apply(&y);
        let residual = relative_residual(&self.product(k, &x), rhs);
        let elapsed = t.elapsed().as_secs_f64();
        let tolerance = GMRES_TOLERANCE.max(10.0 * self.costs.fresh_residual);
        if !(residual <= tolerance && x.iter().all(|v| v.is_finite())) {
            let mut fallback = self.resolve(disc, dofs, k, rhs, &x)?;
            fallback.report.solve_seconds += elapsed;
            return Ok(fallback);
        }
        self.refactor_next = elapsed > UPDATE_BUDGET * self.costs.fresh_seconds;
        Ok(Solved {
            x,
            report: SolveReport {
                route: Route::Update,
                iterations: 0,
                refinement_steps: 0,
                residual,
                factor_seconds: 0.0,
                solve_seconds: elapsed,
                gmres: None,
            },
        })
    }

    fn budget(&self) -> usize {
        match self.source {
            Source::Surrogate => SURROGATE_BUDGET,
            Source::TwoLevel => ITERATIVE_BUDGET,
            _ => SYMMETRIC_PART_BUDGET,
        }
    }

    /// Iterations a re-solve may spend before the matrix is factorised afresh.
    pub fn refactor_threshold(&self) -> usize {
        let extra = match self.settings.refactor_iterations {
            Some(n) => n,
            None => {
                let c = &self.costs;
                let break_even = if c.iteration_seconds > 0.0 {
                    0.5 * c.fresh_seconds / c.iteration_seconds
                } else {
                    AUTO_REFACTOR_MIN as f64
                };
                (break_even as usize).clamp(AUTO_REFACTOR_MIN, AUTO_REFACTOR_MAX)
            }
        };
        // A GMRES route needs its fresh iteration count even with a new factor.
        self.costs.fresh_iterations + extra
    }

    /// Time of one Krylov iteration: a product with `K` and a preconditioner solve.
    fn measure_iteration(&self, k: &Stiffness, rhs: &[f64]) -> f64 {
        let t = Instant::now();
        let mut v = self.product(k, rhs);
        self.precondition(k, &mut v);
        t.elapsed().as_secs_f64()
    }

    /// A point whose stiffness left the floating-point range, with the value:
    /// a non-finite entry, or a point with intact bonds none of whose free
    /// components has a normal diagonal entry (the sum of its bonds' positive
    /// stiffnesses underflowed; a mechanism leaves some component positive).
    /// Every input passed its checks, so this is a scale at which the model's
    /// own quantities leave double precision.
    fn out_of_range(
        &self,
        disc: &Discretization,
        dofs: &DofMap,
        k: &Stiffness,
    ) -> Option<(usize, f64)> {
        let column = |c: usize| self.pattern.col_ptr[c]..self.pattern.col_ptr[c + 1];
        if let Some((c, v)) = (0..k.n).find_map(|c| {
            let v = k.values[column(c)].iter().find(|v| !v.is_finite())?;
            Some((c, *v))
        }) {
            return Some((dofs.free_dofs[c].0 as usize, v));
        }
        let mut normal = vec![false; disc.points.len()];
        for c in 0..k.n {
            let p = column(c).find(|&p| self.pattern.row_idx[p] == c);
            if p.is_some_and(|p| k.values[p].is_normal()) {
                normal[dofs.free_dofs[c].0 as usize] = true;
            }
        }
        let suspects: Vec<usize> = dofs
            .free_dofs
            .iter()
            .map(|&(i, _)| i as usize)
            .filter(|&i| !normal[i])
            .collect();
        if suspects.is_empty() {
            return None;
        }
        let touches = disc.bonds.touch_counts(disc.points.len());
        let point = suspects.into_iter().find(|&i| touches[i] > 0)?;
        let c = dofs
            .free_dofs
            .iter()
            .position(|&(i, _)| i as usize == point)?;
        let p = column(c).find(|&p| self.pattern.row_idx[p] == c);
        Some((point, p.map_or(0.0, |p| k.values[p])))
    }

    /// `‖|K||x|‖ / ‖b‖`: ε times it is the round-off floor of a relative
    /// residual computed in double precision.
    fn round_off_scale(&self, k: &Stiffness, x: &[f64], b: &[f64]) -> f64 {
        let abs = Stiffness {
            n: k.n,
            values: k.values.iter().map(|v| v.abs()).collect(),
        };
        let ax: Vec<f64> = x.iter().map(|v| v.abs()).collect();
        let kx = abs.mul_parallel(&self.pattern, self.symmetric, &ax);
        super::norm2(kx.into_iter()) / super::norm2(b.iter().copied())
    }

    /// The checks every solution passes: finite, residual below the threshold
    /// (or, `at_floor`, a direct solve refined to working precision in
    /// extended precision).
    fn accept(
        &self,
        x: &[f64],
        residual: f64,
        refinement_steps: usize,
        at_floor: bool,
    ) -> Result<(), Error> {
        if x.iter().any(|v| !v.is_finite()) {
            return Err(NumericalError::NonFinite {
                what: "the displacement solution".into(),
            }
            .into());
        }
        if !(residual <= RESIDUAL_THRESHOLD || at_floor) {
            let hint = match self.source {
                Source::Matrix => "iterative refinement with a more accurate residual (the \
                    bond forces', or K's in extended precision) did not converge either, so the \
                    system is singular to double precision (a near-mechanism, or an extreme \
                    stiffness contrast); no solver route does better: remove the mechanism or \
                    the contrast"
                    .to_string(),
                Source::TwoLevel => "the iterative route stops at the round-off floor of its \
                    products; solver.method = \"cholesky\" solves directly and refines the \
                    answer to working precision where that floor is above the threshold"
                    .to_string(),
                Source::Surrogate | Source::SymmetricPart => format!(
                    "solver.method = \"lu\" factorises K itself (up to {LU_MAX_UNKNOWNS} free \
                     unknowns) and refines the answer to working precision"
                ),
            };
            return Err(NumericalError::ResidualTooLarge {
                residual,
                threshold: RESIDUAL_THRESHOLD,
                refinement_steps,
                hint,
            }
            .into());
        }
        Ok(())
    }
}

/// Maps a factorisation failure at a free unknown to the point it belongs to.
pub fn factor_error(e: FactorError, dofs: &DofMap, disc: &Discretization) -> Error {
    let locate = |k: usize| {
        let (i, c) = dofs.free_dofs[k];
        (i as usize, c as usize)
    };
    match e {
        FactorError::NonPositivePivot(k) => {
            let (point, component) = locate(k);
            NumericalError::NonPositivePivot {
                point,
                component,
                position: disc.points.x[point],
            }
            .into()
        }
        FactorError::Singular(k) => {
            let (point, component) = locate(k);
            NumericalError::StructurallySingular { point, component }.into()
        }
        FactorError::NearlySingular(k, ratio) => {
            let (point, component) = locate(k);
            NumericalError::NearlySingular {
                point,
                component,
                position: disc.points.x[point],
                ratio,
            }
            .into()
        }
        FactorError::Generic => {
            NumericalError::Solver("factorisation failed (out of memory?)".into()).into()
        }
    }
}
