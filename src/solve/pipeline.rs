//! One solver pipeline for every driver: the route chosen and its symbolic
//! analysis done once per pattern ([`super::route`]), then the state machine of
//! the solves: numeric factorisation, solve with iterative refinement and a
//! residual check, and re-solves after a small change of `K` (bonds broke)
//! with the previous factor.
//!
//! **Residual check.** A solve is accepted when its relative residual is at
//! most [`RESIDUAL_THRESHOLD`]. A direct solve is first refined with its own
//! factor ([`super::refine::refine`]); if its residual stays above the
//! threshold, it is refined again with a more accurate residual
//! ([`super::refine::refine_extended`]): the caller's (static solves: the
//! model's bond forces, [`Pipeline::solve_with_residual`]) or `K x` in extended
//! precision. When those corrections contract below
//! [`super::refine::REFINED_ACCURACY`] of the answer, the residual is the
//! round-off floor of an ill-conditioned system (a 10⁶-point 1D bar:
//! `κ ≈ 4e11`, residual 2.1e-8, answer to 5e-12), accepted with a note;
//! otherwise the system is singular to double precision and the solve is
//! refused, with the route that does better where there is one.
//!
//! **Mixed precision.** A single-precision Cholesky factor is refined to full
//! accuracy by CG (bond-based) or GMRES preconditioned by it; a factorisation
//! that fails, or a CG that does not reach [`MIXED_ACCEPT`] within
//! [`MIXED_ITERATIONS`], falls back to double precision with a note.
//!
//! **Re-solves.** The pattern never changes when bonds break (broken bonds keep
//! their slots), so the symbolic analysis is done once. If `k` bonds broke
//! since the factorisation, `K_new = K_old − ΔK` with `ΔK` of low rank and the
//! preconditioned operator has few distinct eigenvalues: CG converges in about
//! `rank(ΔK) + 1` iterations (a bond-based bond is a rank-one term), and a
//! Cholesky factor can be updated exactly by those terms
//! ([`Pipeline::resolve_update`], [`super::low_rank`]). On the `gmres` route
//! (the shear model) the terms are those of the bond-based surrogate: its
//! factor is updated the same way, so the preconditioner stays the surrogate
//! of the current bonds and the GMRES re-solve meets only `K`'s own change
//! (at 5,400 points: 20 iterations instead of 27). Past a threshold of
//! iterations the matrix is factorised afresh: by default the number of
//! iterations that costs as much as half a fresh factorisation and solve, both
//! measured in this run (`solver.refactor_iterations` overrides it).

use super::cg::{pcg, pcg_with_checkpoint};
use super::cholesky::{FactorError, PivotStats};
use super::gmres::{gmres, gmres_with_checkpoint, GmresReport};
use super::low_rank::{LowRank, Term};
use super::lu::SparseLu;
use super::refine::{refine, refine_extended};
use super::route::{self, Factor, Hints, OrderingReport, Source, LU_MAX_UNKNOWNS};
use super::two_level::TwoLevel;
use super::{
    norm2, relative_residual, Layout, Matrices, GMRES_RESTART, GMRES_TOLERANCE, ITERATIVE_BUDGET,
};
use crate::assembly::pattern::Pattern;
use crate::assembly::stiffness::Stiffness;
use crate::error::{Error, NumericalError};
use crate::notes::Notes;
use crate::scene::solver::{Precision, SolverMethod, SolverSettings};
use serde::Serialize;
use std::time::Instant;

/// Largest relative residual accepted from any solve.
pub const RESIDUAL_THRESHOLD: f64 = 1e-8;

/// GMRES iterations allowed with the caller's surrogate before switching to
/// the symmetric part of `K`.
const SURROGATE_BUDGET: usize = 120;

/// GMRES iterations allowed with the factor of the symmetric part.
const SYMMETRIC_PART_BUDGET: usize = 600;

/// Largest memory for the columns of the low-rank update (bytes), unless the
/// factor itself is larger.
const UPDATE_MEMORY: usize = 256 << 20;

/// Bounds of the automatic refactorisation threshold (iterations).
const AUTO_REFACTOR_MIN: usize = 4;
const AUTO_REFACTOR_MAX: usize = 1000;

/// Largest relative residual a mixed-precision solve is accepted with, when
/// CG stops at the round-off floor above [`GMRES_TOLERANCE`]; above it the
/// solve falls back to a double-precision factor.
const MIXED_ACCEPT: f64 = 1e-10;

/// CG iterations a mixed-precision solve may take before it falls back to a
/// double-precision factor (it needs about 3-6 when `κ(K) ε₃₂ ≪ 1`).
const MIXED_ITERATIONS: usize = 60;

/// How a solve was done.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Route {
    /// A fresh numeric factorisation, then the solve.
    Factor,
    /// A Krylov solve preconditioned by the previous factor.
    Reuse,
    /// The previous factor updated by the rank-one terms of the broken bonds
    /// (Sherman–Morrison–Woodbury, `solve::low_rank`): exact, no iteration.
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
    /// An earlier iterate of a Krylov solve, the first whose residual fell
    /// below [`CHECKPOINT_FACTOR`] times the tolerance: while the iteration
    /// converges steadily its error is about that factor larger than `x`'s, so
    /// its distance from `x` bounds `x`'s error from above. `None` for direct
    /// solves and where no iteration ran.
    pub earlier: Option<Vec<f64>>,
}

/// Ratio of the residual of [`Solved::earlier`] to the solve's tolerance.
pub const CHECKPOINT_FACTOR: f64 = 100.0;

/// A Krylov run's report, and whether it was GMRES.
struct KrylovRun {
    krylov: GmresReport,
    gmres: Option<GmresReport>,
}

/// How the first solve after a factorisation went (before the checks).
struct Fresh {
    residual: f64,
    refinement_steps: usize,
    /// A direct solve refined in extended precision to the answer rounded to
    /// double precision, with a residual at the round-off floor.
    at_floor: bool,
    /// The Krylov report, when a Krylov method ran.
    krylov: Option<GmresReport>,
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

/// The solver pipeline of one system.
pub struct Pipeline {
    settings: SolverSettings,
    pattern: Pattern,
    /// The pattern of the caller's surrogate, while the route factorises it.
    surrogate: Option<Pattern>,
    /// Transposed positions of `K`'s entries (non-symmetric `K`, symmetric part).
    transpose: Option<Vec<usize>>,
    source: Source,
    factor: Factor,
    factored: bool,
    symmetric: bool,
    costs: Costs,
    /// Rank-one terms removed since the factorisation (bond-based re-solves).
    low_rank: LowRank,
    /// The last right-hand side of an update and the old factor's forward
    /// half-solve of it, `L⁻¹ P b` (kept while the factor and `b` are unchanged).
    factor_forward: Option<(Vec<f64>, Vec<f64>)>,
    /// The updates have cost more than a fresh solve: factorise next time.
    refactor_next: bool,
    /// Fastest update since the factorisation, and what the updates cost
    /// above it in all (s): the part of their cost that grows with the terms.
    update_floor: f64,
    update_excess: f64,
    /// The tolerance of Krylov re-solves when the driver asks for a looser
    /// one than [`GMRES_TOLERANCE`] ([`Pipeline::set_resolve_tolerance`]).
    resolve_tolerance: Option<f64>,
    /// Symbolic analysis time (s).
    pub symbolic_seconds: f64,
    /// The Cholesky factor's ordering (None for LU).
    pub ordering: Option<OrderingReport>,
}

impl Pipeline {
    /// Chooses the route for `K`'s `pattern` and runs its symbolic analysis,
    /// before any value is assembled, so that a factor too large for memory is
    /// refused early (or replaced by the `iterative` route). `surrogate` is the
    /// pattern of the symmetric positive definite matrix the `gmres` route
    /// factorises when [`route::wants_surrogate`]; its values come with each
    /// solve ([`Matrices`]).
    pub fn analyse(
        pattern: Pattern,
        surrogate: Option<Pattern>,
        layout: Layout,
        mut settings: SolverSettings,
        hints: Hints,
        notes: &mut Notes,
    ) -> Result<Self, Error> {
        route::check_size(&settings, layout.dofs.n_free())?;
        if hints.fracture {
            // Fracture re-solves update the factor exactly (low-rank terms),
            // which needs it in double precision.
            settings.precision = Precision::Double;
        }
        let t = Instant::now();
        let chosen = route::choose(
            &pattern,
            surrogate.as_ref(),
            layout,
            &settings,
            hints,
            notes,
        )?;
        Ok(Self {
            settings,
            transpose: None,
            symmetric: hints.symmetric,
            pattern,
            surrogate: surrogate.filter(|_| chosen.surrogate),
            source: chosen.source,
            factor: chosen.factor,
            factored: false,
            costs: Costs::default(),
            low_rank: LowRank::default(),
            factor_forward: None,
            refactor_next: false,
            update_floor: f64::INFINITY,
            update_excess: 0.0,
            resolve_tolerance: None,
            symbolic_seconds: t.elapsed().as_secs_f64(),
            ordering: chosen.ordering,
        })
    }

    /// The pattern of `K` (assemble on it).
    pub fn pattern(&self) -> &Pattern {
        &self.pattern
    }

    /// The pattern of the surrogate whose values every solve needs
    /// ([`Matrices::surrogate`]), while the route factorises one.
    pub fn surrogate_pattern(&self) -> Option<&Pattern> {
        self.surrogate.as_ref()
    }

    /// Gives the pattern back (for export after the last solve).
    pub fn into_pattern(self) -> Pattern {
        self.pattern
    }

    /// The route this pipeline solves by (`iterative` when it replaced a factor).
    pub fn method(&self) -> SolverMethod {
        match (self.source, &self.factor) {
            (Source::TwoLevel, _) => SolverMethod::Iterative,
            #[cfg(feature = "mpi")]
            (Source::Petsc, _) => SolverMethod::Petsc,
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
            _ => None,
        }
    }

    /// What the last PETSc solve used and did (the `petsc` route).
    #[cfg(feature = "mpi")]
    pub fn petsc_report(&self) -> Option<&super::petsc::PetscReport> {
        match &self.factor {
            Factor::Petsc(Some(solver)) => solver.report.as_ref(),
            _ => None,
        }
    }

    /// Pivot statistics of the last Cholesky factorisation.
    pub fn pivot_stats(&self) -> Option<PivotStats> {
        match &self.factor {
            Factor::Cholesky(c) => c.pivot_stats(),
            _ => None,
        }
    }

    /// `‖K − Kᵀ‖_F / ‖K‖_F` (a collective call on the `petsc` route).
    #[cfg_attr(not(feature = "mpi"), allow(unused_variables))]
    pub fn asymmetry(&mut self, k: &Stiffness, layout: Layout) -> Result<f64, Error> {
        #[cfg(feature = "mpi")]
        if self.source == Source::Petsc {
            // Each process holds its own columns and its ghosts' only.
            return super::petsc::asymmetry(&self.pattern, &k.values, layout);
        }
        Ok(k.asymmetry(self.transpose()))
    }

    /// The mean `|K_kk|` over the free unknowns (the stiffness scale given to
    /// unknowns a driver pins; a collective call on the `petsc` route).
    #[cfg_attr(not(feature = "mpi"), allow(unused_variables))]
    pub fn mean_diagonal(&self, k: &Stiffness, layout: Layout) -> Result<f64, Error> {
        #[cfg(feature = "mpi")]
        if self.source == Source::Petsc {
            return super::petsc::mean_diagonal(&self.pattern, &k.values, layout);
        }
        let pattern = &self.pattern;
        let sum: f64 = (0..k.n)
            .filter_map(|c| {
                (pattern.col_ptr[c]..pattern.col_ptr[c + 1]).find(|&p| pattern.row_idx[p] == c)
            })
            .map(|p| k.values[p].abs())
            .sum();
        Ok(if sum > 0.0 && k.n > 0 {
            sum / k.n as f64
        } else {
            1.0
        })
    }

    /// The stored entries of `K` (on all processes, for the `petsc` route,
    /// whose pattern here holds this process's columns only).
    pub fn stored_entries(&self) -> usize {
        #[cfg(feature = "mpi")]
        if let Factor::Petsc(Some(solver)) = &self.factor {
            return solver.stored_entries;
        }
        self.pattern.nnz()
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

    /// Numeric factorisation of the current source for `m`.
    fn factorize(&mut self, layout: Layout, m: Matrices) -> Result<(), Error> {
        self.factored = false;
        if self.source == Source::TwoLevel {
            let product = |v: &[f64]| self.product(m.k, v);
            let two_level = TwoLevel::new(layout, &self.pattern, &m.k.values, &product)?;
            self.factor = Factor::TwoLevel(Some(two_level));
            self.factored = true;
            return Ok(());
        }
        #[cfg(feature = "mpi")]
        if self.source == Source::Petsc {
            // The old set-up goes before the new one is built.
            self.factor = Factor::Petsc(None);
            let solver = super::petsc::Solver::new(
                &self.pattern,
                &m.k.values,
                layout,
                self.symmetric,
                self.settings.petsc_solver,
            )?;
            self.factor = Factor::Petsc(Some(solver));
            self.factored = true;
            return Ok(());
        }
        let symmetric_values;
        let matrix = match self.source {
            Source::SymmetricPart => {
                symmetric_values = m.k.symmetric_part(self.transpose());
                symmetric_values.view(&self.pattern)
            }
            Source::Surrogate => {
                let pattern = self.surrogate.as_ref().expect("surrogate route");
                let values = m
                    .surrogate
                    .expect("the caller passes the surrogate the pipeline asked for");
                values.view(pattern)
            }
            _ => m.k.view(&self.pattern),
        };
        let result = match &mut self.factor {
            Factor::Cholesky(c) => c.factorize(matrix),
            Factor::Lu(l) => l.factorize(matrix),
            _ => unreachable!("built above"),
        };
        result.map_err(|e| factor_error(e, layout))?;
        self.factored = true;
        Ok(())
    }

    /// Stores the Cholesky factor in double precision from now on (after a
    /// single-precision factor failed), checking that it fits in memory.
    fn use_double_precision(&mut self, notes: &mut Notes) -> Result<(), Error> {
        self.settings.precision = Precision::Double;
        let nnz_k = match (&self.surrogate, self.source) {
            (Some(s), Source::Surrogate) => s.nnz(),
            _ => self.pattern.nnz(),
        };
        if let Factor::Cholesky(chol) = &mut self.factor {
            chol.use_double_precision();
            route::choose_precision(chol, nnz_k, &self.settings, notes)?;
        }
        Ok(())
    }

    /// Switches the `gmres` route from its current factor to the next one:
    /// surrogate → symmetric part → LU of `K`.
    fn fall_back(&mut self, layout: Layout, m: Matrices, notes: &mut Notes) -> Result<(), Error> {
        if self.source == Source::Surrogate {
            let (mut chol, report) =
                route::analyse_cholesky(&self.pattern, layout, self.settings.ordering, None)?;
            self.ordering = Some(report);
            route::choose_precision(&mut chol, self.pattern.nnz(), &self.settings, notes)?;
            let full = m.k.symmetric_part(self.transpose());
            match chol.factorize(full.view(&self.pattern)) {
                Ok(()) => {
                    self.surrogate = None;
                    self.source = Source::SymmetricPart;
                    self.factor = Factor::Cholesky(chol);
                    self.factored = true;
                    return Ok(());
                }
                Err(FactorError::NonPositivePivot(_) | FactorError::NearlySingular(..)) => {
                    // Possible with the gradient dilatation near ν = 1/2: K is
                    // regular but its symmetric part is indefinite.
                    notes.push(
                        "note: the symmetric part of the tangent is not positive definite; \
                         solving with sparse LU instead",
                    );
                }
                Err(e) => return Err(factor_error(e, layout)),
            }
        }
        self.surrogate = None;
        self.source = Source::Matrix;
        self.factor = Factor::Lu(SparseLu::analyse(self.pattern.symbolic())?);
        self.symmetric = false;
        self.factorize(layout, m)
    }

    /// Factorises `m` afresh and solves `K x = rhs`, with refinement (direct
    /// routes) and the residual check.
    pub fn solve(
        &mut self,
        layout: Layout,
        m: Matrices,
        rhs: &[f64],
        notes: &mut Notes,
    ) -> Result<Solved, Error> {
        self.solve_refined(layout, m, rhs, None, notes)
    }

    /// [`Pipeline::solve`] with the caller's own residual `rhs − K x`
    /// (`exact_residual`; static solves: from the internal forces of the
    /// bonds) for the refinement of a direct solve whose residual stays above
    /// the threshold. The bond forces balance exactly, so that residual is
    /// free of the rounding of `K`'s diagonal (each a sum of bond
    /// stiffnesses), which acts like springs to the ground: identical in every
    /// row of a uniform chain, it moved the answer of a 10⁶-point 1D bar by 3e-5.
    pub fn solve_with_residual(
        &mut self,
        layout: Layout,
        m: Matrices,
        rhs: &[f64],
        exact_residual: &dyn Fn(&[f64]) -> Vec<f64>,
        notes: &mut Notes,
    ) -> Result<Solved, Error> {
        self.solve_refined(layout, m, rhs, Some(exact_residual), notes)
    }

    fn solve_refined(
        &mut self,
        layout: Layout,
        m: Matrices,
        rhs: &[f64],
        exact_residual: Option<&dyn Fn(&[f64]) -> Vec<f64>>,
        notes: &mut Notes,
    ) -> Result<Solved, Error> {
        let t = Instant::now();
        if let Err(e) = self.factorize(layout, m) {
            if !self.factor.is_single() {
                return Err(e);
            }
            // A pivot lost to single-precision round-off: the matrix is too
            // ill-conditioned for a single-precision factor.
            notes.push(format!(
                "note: the single-precision factorisation failed ({e}); factorising in double \
                 precision"
            ));
            self.use_double_precision(notes)?;
            self.factorize(layout, m)?;
        }
        let factor_seconds = t.elapsed().as_secs_f64();
        let t = Instant::now();
        let mut x = vec![0.0; rhs.len()];
        let fresh = self.first_solve(layout, m, rhs, &mut x, exact_residual, notes)?;
        let solve_seconds = t.elapsed().as_secs_f64();
        if let (Source::TwoLevel, Some(r)) = (self.source, &fresh.krylov) {
            // Large systems stop at the round-off floor of their products.
            if !(r.relative_residual <= MIXED_ACCEPT) {
                notes.push(format!(
                    "note: the iterative route reached a relative residual of {:.1e} after {} \
                     iterations (budget {ITERATIVE_BUDGET}): no Krylov method goes below the \
                     round-off floor of an ill-conditioned system (a stiff part carried by a \
                     far softer one, a slender body in bending, a long 1D chain), and the \
                     two-level preconditioner is also weak near incompressibility; \
                     solver.method = \"cholesky\" solves directly",
                    r.relative_residual, r.iterations
                ));
            }
        }
        self.accept(&x, fresh.residual, fresh.refinement_steps, fresh.at_floor)?;
        self.low_rank.clear();
        self.refactor_next = false;
        self.update_floor = f64::INFINITY;
        self.update_excess = 0.0;
        self.factor_forward = None;
        self.costs.fresh_seconds = factor_seconds + solve_seconds;
        self.costs.fresh_residual = fresh.residual;
        if self.costs.iteration_seconds == 0.0 {
            self.costs.iteration_seconds = self.measure_iteration(m.k, rhs);
        }
        Ok(Solved {
            x,
            report: SolveReport {
                route: Route::Factor,
                iterations: fresh.krylov.map_or(0, |r| r.iterations),
                refinement_steps: fresh.refinement_steps,
                residual: fresh.residual,
                factor_seconds,
                solve_seconds,
                gmres: fresh.krylov,
            },
            earlier: None,
        })
    }

    /// The solve right after a factorisation, by the current source.
    fn first_solve(
        &mut self,
        layout: Layout,
        m: Matrices,
        rhs: &[f64],
        x: &mut [f64],
        exact_residual: Option<&dyn Fn(&[f64]) -> Vec<f64>>,
        notes: &mut Notes,
    ) -> Result<Fresh, Error> {
        if self.source == Source::Matrix && self.factor.is_single() {
            if let Some(fresh) = self.solve_mixed(layout, m, rhs, x, notes)? {
                return Ok(fresh);
            }
        }
        match self.source {
            Source::Matrix => Ok(self.solve_direct(m.k, rhs, x, exact_residual, notes)),
            Source::TwoLevel if self.symmetric => self.solve_two_level(m.k, rhs, x),
            #[cfg(feature = "mpi")]
            Source::Petsc => self.solve_petsc(rhs, x),
            _ => self.solve_krylov(layout, m, rhs, x, notes),
        }
    }

    /// PETSc's solve (`solve::petsc`), its residual checked with PETSc's
    /// product on the rows dhpd assembled (no process holds all of `K`).
    #[cfg(feature = "mpi")]
    fn solve_petsc(&mut self, rhs: &[f64], x: &mut [f64]) -> Result<Fresh, Error> {
        let Factor::Petsc(Some(solver)) = &mut self.factor else {
            unreachable!("set up by factorize")
        };
        let t = Instant::now();
        let (iterations, residual) = solver.solve(rhs, x)?;
        // Measured here: the pipeline's own measure applies dhpd's factors.
        self.costs.iteration_seconds =
            (t.elapsed().as_secs_f64() / iterations.max(1) as f64).max(f64::MIN_POSITIVE);
        self.costs.fresh_iterations = iterations;
        // MUMPS's factor applied once is a direct solve, not a Krylov run.
        let direct = self.settings.petsc_solver == crate::scene::solver::PetscSolver::Mumps;
        Ok(Fresh {
            residual,
            refinement_steps: 0,
            at_floor: false,
            krylov: (!direct).then_some(GmresReport {
                iterations,
                relative_residual: residual,
                converged: true,
                stagnated: false,
            }),
        })
    }

    /// Mixed precision: CG on `K` preconditioned by the single-precision
    /// factor, to the residual the direct routes reach. None, with the matrix
    /// factorised again in double precision, when the factor was not good
    /// enough.
    fn solve_mixed(
        &mut self,
        layout: Layout,
        m: Matrices,
        rhs: &[f64],
        x: &mut [f64],
        notes: &mut Notes,
    ) -> Result<Option<Fresh>, Error> {
        let cg = {
            let apply = |v: &[f64]| self.product(m.k, v);
            let precondition = |v: &mut [f64]| self.factor.solve_in_place(v);
            pcg(
                &apply,
                &precondition,
                rhs,
                x,
                GMRES_TOLERANCE,
                MIXED_ITERATIONS,
            )
        };
        // Large systems stop at the round-off floor of their products (2e-12
        // at a million points), which the direct route would accept after
        // refinement too; anything higher means the single-precision factor is
        // not good enough.
        if cg.relative_residual <= MIXED_ACCEPT {
            self.costs.fresh_iterations = 0;
            return Ok(Some(Fresh {
                residual: cg.relative_residual,
                refinement_steps: 0,
                at_floor: false,
                krylov: Some(cg),
            }));
        }
        notes.push(format!(
            "note: CG with the single-precision factor reached {:.1e} after {} \
             iterations (the matrix is too ill-conditioned for single precision); \
             factorising in double precision",
            cg.relative_residual, cg.iterations
        ));
        self.use_double_precision(notes)?;
        self.factorize(layout, m)?;
        Ok(None)
    }

    /// A direct solve with the factor of `K`, refined with the factor and, if
    /// its residual stays above the threshold, with a more accurate residual
    /// (module docs).
    fn solve_direct(
        &mut self,
        k: &Stiffness,
        rhs: &[f64],
        x: &mut [f64],
        exact_residual: Option<&dyn Fn(&[f64]) -> Vec<f64>>,
        notes: &mut Notes,
    ) -> Fresh {
        self.costs.fresh_iterations = 0;
        x.copy_from_slice(rhs);
        self.factor.solve_in_place(x);
        let apply = |v: &[f64]| self.product(k, v);
        let solve = |v: &mut [f64]| self.factor.solve_in_place(v);
        let (mut residual, mut refinement_steps) = refine(&apply, &solve, rhs, x);
        let mut at_floor = false;
        if !(residual <= RESIDUAL_THRESHOLD) {
            // The residual of a double-precision product may be all round-off
            // (ε ‖|K||x|‖ above 1e-8 ‖f‖: a long 1D chain): refine with the
            // caller's residual, else with `K`'s in extended precision.
            let pattern = &self.pattern;
            let extended_k = |v: &[f64]| k.residual_extended(pattern, v, rhs);
            let exact = exact_residual.unwrap_or(&extended_k);
            let extended = refine_extended(exact, &solve, rhs, x);
            refinement_steps += extended.steps;
            residual = extended.residual;
            at_floor = extended.converged;
            if at_floor && !(residual <= RESIDUAL_THRESHOLD) {
                let of = if exact_residual.is_some() {
                    "the residual of the bond forces (which balance exactly)"
                } else {
                    "the residual of the assembled stiffness in extended precision (the \
                     answer is exact for it; its rounding, ε per entry, may move the answer \
                     by up to κ(K) ε)"
                };
                notes.push(format!(
                    "note: the relative residual {residual:.3e} is above \
                     {RESIDUAL_THRESHOLD:.0e} but at the round-off floor of this system \
                     (ε ‖|K||u|‖ / ‖f‖ = {:.3e}, the residual of the answer rounded to \
                     double precision): iterative refinement with {of} converged in {} \
                     step(s), the last changing the answer by {:.1e} of its size (an \
                     ill-conditioned system, e.g. a long 1D chain, whose condition number \
                     grows like n²)",
                    f64::EPSILON * self.round_off_scale(k, x, rhs),
                    extended.steps,
                    extended.accuracy
                ));
            }
        }
        Fresh {
            residual,
            refinement_steps,
            at_floor,
            krylov: None,
        }
    }

    /// CG on a symmetric `K` preconditioned by the two-level cycle.
    fn solve_two_level(
        &mut self,
        k: &Stiffness,
        rhs: &[f64],
        x: &mut [f64],
    ) -> Result<Fresh, Error> {
        let apply = |v: &[f64]| self.product(k, v);
        let precondition = |v: &mut [f64]| self.precondition(k, v);
        let cg = pcg(
            &apply,
            &precondition,
            rhs,
            x,
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
        Ok(Fresh {
            residual: cg.relative_residual,
            refinement_steps: 0,
            at_floor: false,
            krylov: Some(cg),
        })
    }

    /// GMRES on `K` preconditioned by the current factor; when the surrogate
    /// stalls, continued with the next factor ([`Pipeline::fall_back`]).
    fn solve_krylov(
        &mut self,
        layout: Layout,
        m: Matrices,
        rhs: &[f64],
        x: &mut [f64],
        notes: &mut Notes,
    ) -> Result<Fresh, Error> {
        let mut first = self.gmres(m.k, rhs, x, self.budget());
        if !first.converged && self.source == Source::Surrogate {
            // Near incompressibility the bond-based surrogate (which has no
            // Poisson ratio) stalls: continue with the symmetric part.
            notes.push(format!(
                "note: GMRES with the bond-based preconditioner stopped at residual {:.1e} \
                 after {} iterations; continuing with the Cholesky factor of the symmetric part",
                first.relative_residual, first.iterations
            ));
            self.fall_back(layout, m, notes)?;
            let second = if self.source == Source::Matrix {
                self.correct_with_lu(m.k, rhs, x)
            } else {
                self.gmres(m.k, rhs, x, self.budget())
            };
            first = GmresReport {
                iterations: first.iterations + second.iterations,
                ..second
            };
        }
        self.costs.fresh_iterations = first.iterations;
        Ok(Fresh {
            residual: relative_residual(&self.product(m.k, x), rhs),
            refinement_steps: 0,
            at_floor: false,
            krylov: Some(first),
        })
    }

    /// After falling back to LU: one correction of the GMRES iterate `x` with
    /// the LU factor, then refinement.
    fn correct_with_lu(&self, k: &Stiffness, rhs: &[f64], x: &mut [f64]) -> GmresReport {
        let ax = self.product(k, x);
        let mut dx: Vec<f64> = rhs.iter().zip(&ax).map(|(b, a)| b - a).collect();
        self.factor.solve_in_place(&mut dx);
        x.iter_mut().zip(&dx).for_each(|(xi, di)| *xi += di);
        let apply = |v: &[f64]| self.product(k, v);
        let solve = |v: &mut [f64]| self.factor.solve_in_place(v);
        let (r, _) = refine(&apply, &solve, rhs, x);
        GmresReport {
            iterations: 0,
            relative_residual: r,
            converged: r <= GMRES_TOLERANCE,
            stagnated: false,
        }
    }

    /// Re-solves `K x = rhs` after `K` changed a little, from the initial guess
    /// `x0`, with the previous factor as preconditioner (CG for a symmetric `K`
    /// factorised by Cholesky, GMRES otherwise). Past the refactorisation
    /// threshold it factorises afresh ([`Pipeline::solve`]).
    pub fn resolve(
        &mut self,
        layout: Layout,
        m: Matrices,
        rhs: &[f64],
        x0: &[f64],
        notes: &mut Notes,
    ) -> Result<Solved, Error> {
        if !self.factored {
            return self.solve(layout, m, rhs, notes);
        }
        #[cfg(feature = "mpi")]
        if self.source == Source::Petsc {
            return self.resolve_petsc(layout, m, rhs, x0, notes);
        }
        let cap = self.refactor_threshold();
        let tolerance = self
            .resolve_tolerance
            .unwrap_or(0.0)
            .max(self.full_tolerance());
        let t = Instant::now();
        let mut x = x0.to_vec();
        let (report, earlier) = self.krylov(m.k, rhs, &mut x, tolerance, cap);
        let cg = report.gmres.is_none();
        let report = report.krylov;
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
                earlier,
            });
        }
        let mut fresh = self.solve(layout, m, rhs, notes)?;
        fresh.report.solve_seconds += elapsed;
        fresh.report.iterations += report.iterations;
        Ok(fresh)
    }

    /// [`Pipeline::resolve`] on the `petsc` route: the new values of `K`
    /// handed to PETSc in place, its Krylov method warm-started from `x0`
    /// with the preconditioner (GAMG's hierarchy) built for an earlier `K`,
    /// keeping the checkpoint iterate ([`Solved::earlier`]) on the way; past the
    /// refactorisation threshold (or a true residual above the tolerance),
    /// PETSc sets everything up afresh.
    #[cfg(feature = "mpi")]
    fn resolve_petsc(
        &mut self,
        layout: Layout,
        m: Matrices,
        rhs: &[f64],
        x0: &[f64],
        notes: &mut Notes,
    ) -> Result<Solved, Error> {
        let cap = self.agreed_refactor_threshold();
        let tolerance = self
            .resolve_tolerance
            .unwrap_or(0.0)
            .max(self.full_tolerance());
        let Factor::Petsc(Some(solver)) = &mut self.factor else {
            unreachable!("set up by factorize")
        };
        let t = Instant::now();
        solver.update(&self.pattern, &m.k.values, layout, m.changed)?;
        let solving = Instant::now();
        let mut x = x0.to_vec();
        let checkpoint = Some(CHECKPOINT_FACTOR * tolerance);
        let run = solver.solve_from(rhs, &mut x, tolerance, cap, checkpoint)?;
        if run.iterations > 0 {
            self.costs.iteration_seconds = solving.elapsed().as_secs_f64() / run.iterations as f64;
        }
        let elapsed = t.elapsed().as_secs_f64();
        if !run.converged {
            let mut fresh = self.solve(layout, m, rhs, notes)?;
            fresh.report.solve_seconds += elapsed;
            fresh.report.iterations += run.iterations;
            return Ok(fresh);
        }
        let report = GmresReport {
            iterations: run.iterations,
            relative_residual: run.residual,
            converged: true,
            stagnated: false,
        };
        Ok(Solved {
            x,
            report: SolveReport {
                route: Route::Reuse,
                iterations: run.iterations,
                refinement_steps: 0,
                residual: run.residual,
                factor_seconds: 0.0,
                solve_seconds: elapsed,
                gmres: (!self.symmetric).then_some(report),
            },
            earlier: run.earlier,
        })
    }

    /// [`Pipeline::refactor_threshold`] agreed by the processes (their
    /// mean, rounded down): it comes from times each measured, and PETSc's
    /// processes must stop their Krylov iterations at the same count.
    #[cfg(feature = "mpi")]
    fn agreed_refactor_threshold(&self) -> usize {
        let processes = super::petsc::sum_over_processes(1.0);
        let sum = super::petsc::sum_over_processes(self.refactor_threshold() as f64);
        (sum / processes).floor() as usize
    }

    /// Krylov iterations on `K` from `x` to `tolerance` with the current
    /// factor or cycle as preconditioner (CG where `K` is symmetric and the
    /// preconditioner is of `K` itself, GMRES otherwise), keeping the
    /// checkpoint of [`Solved::earlier`].
    fn krylov(
        &self,
        k: &Stiffness,
        rhs: &[f64],
        x: &mut [f64],
        tolerance: f64,
        cap: usize,
    ) -> (KrylovRun, Option<Vec<f64>>) {
        let cg = self.symmetric
            && matches!(self.source, Source::Matrix | Source::TwoLevel)
            && !matches!(self.factor, Factor::Lu(_));
        let apply = |v: &[f64]| self.product(k, v);
        let precondition = |v: &mut [f64]| self.precondition(k, v);
        let checkpoint = Some(CHECKPOINT_FACTOR * tolerance);
        let (report, earlier) = if cg {
            pcg_with_checkpoint(&apply, &precondition, rhs, x, tolerance, cap, checkpoint)
        } else {
            gmres_with_checkpoint(
                &apply,
                &precondition,
                rhs,
                x,
                tolerance,
                GMRES_RESTART,
                cap,
                checkpoint,
            )
        };
        let run = KrylovRun {
            krylov: report,
            gmres: (!cg).then_some(report),
        };
        (run, earlier)
    }

    /// The relative residual a re-solve aims at by default: the usual
    /// tolerance, or the round-off floor that the fresh solve of this system
    /// reached if that is higher.
    pub fn full_tolerance(&self) -> f64 {
        GMRES_TOLERANCE.max(10.0 * self.costs.fresh_residual)
    }

    /// Lets Krylov re-solves stop at the relative residual `tolerance`
    /// (`None`: [`Pipeline::full_tolerance`]): for a driver that checks the
    /// decisions it takes from the answer against the answer's error
    /// ([`Solved::earlier`]) and improves it where they are not decided.
    pub fn set_resolve_tolerance(&mut self, tolerance: Option<f64>) {
        self.resolve_tolerance = tolerance;
    }

    /// Improves a re-solve's `x` by Krylov iterations with the current
    /// preconditioner until its residual is `target` or, without one,
    /// [`CHECKPOINT_FACTOR`] times smaller (`K` and `rhs` unchanged): the
    /// tighter solve when the bonds' ratios are too close to decide which are
    /// critical. `None` when no preconditioner is at hand or the iteration
    /// made no progress (the round-off floor); an error from PETSc's solve
    /// (the `petsc` route).
    pub fn improve(
        &mut self,
        m: Matrices,
        rhs: &[f64],
        x: &[f64],
        target: Option<f64>,
    ) -> Result<Option<Solved>, Error> {
        if !self.factored {
            return Ok(None);
        }
        #[cfg(feature = "mpi")]
        if self.source == Source::Petsc {
            return self.improve_petsc(rhs, x, target);
        }
        let t = Instant::now();
        let before = relative_residual(&self.product(m.k, x), rhs);
        let tolerance = target.unwrap_or(before / CHECKPOINT_FACTOR);
        let mut improved = x.to_vec();
        let (run, _) = self.krylov(
            m.k,
            rhs,
            &mut improved,
            tolerance,
            self.refactor_threshold(),
        );
        let report = run.krylov;
        let progress = report.relative_residual < 0.5 * before;
        if !(progress && improved.iter().all(|v| v.is_finite())) {
            return Ok(None);
        }
        Ok(Some(Solved {
            x: improved,
            report: SolveReport {
                route: Route::Reuse,
                iterations: report.iterations,
                refinement_steps: 0,
                residual: report.relative_residual,
                factor_seconds: 0.0,
                solve_seconds: t.elapsed().as_secs_f64(),
                gmres: run.gmres,
            },
            earlier: Some(x.to_vec()),
        }))
    }

    /// [`Pipeline::improve`] on the `petsc` route (`K` already in PETSc):
    /// progress is kept even when the iterations stop at the cap.
    #[cfg(feature = "mpi")]
    fn improve_petsc(
        &mut self,
        rhs: &[f64],
        x: &[f64],
        target: Option<f64>,
    ) -> Result<Option<Solved>, Error> {
        let cap = self.agreed_refactor_threshold();
        let Factor::Petsc(Some(solver)) = &mut self.factor else {
            unreachable!("set up by factorize")
        };
        let t = Instant::now();
        let before = solver.residual_of(rhs, x)?;
        let tolerance = target.unwrap_or(before / CHECKPOINT_FACTOR);
        let mut improved = x.to_vec();
        let run = solver.solve_from(rhs, &mut improved, tolerance, cap, None)?;
        let progress = run.residual < 0.5 * before;
        if !(progress && improved.iter().all(|v| v.is_finite())) {
            return Ok(None);
        }
        let report = GmresReport {
            iterations: run.iterations,
            relative_residual: run.residual,
            converged: run.converged,
            stagnated: false,
        };
        Ok(Some(Solved {
            x: improved,
            report: SolveReport {
                route: Route::Reuse,
                iterations: run.iterations,
                refinement_steps: 0,
                residual: run.residual,
                factor_seconds: 0.0,
                solve_seconds: t.elapsed().as_secs_f64(),
                gmres: (!self.symmetric).then_some(report),
            },
            earlier: Some(x.to_vec()),
        }))
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
        if let (Factor::Cholesky(c), false) = (&self.factor, self.low_rank.is_empty()) {
            // Terms are only ever added to a double-precision factor.
            if let Some(llt) = c.double_factor() {
                let x = self.low_rank.apply(llt, &llt.forward(v));
                v.copy_from_slice(&x);
                return;
            }
        }
        match &self.factor {
            Factor::TwoLevel(Some(t)) => t.apply(&|x: &[f64]| self.product(k, x), v),
            factor => factor.solve_in_place(v),
        }
    }

    /// Re-solves after `K` lost the rank-one `terms` (bonds that broke) since
    /// the last solve, updating the old Cholesky factor exactly (module docs of
    /// [`super::low_rank`]). On the `gmres` route the terms are the
    /// surrogate's: its factor is updated and GMRES re-solves with it.
    /// Falls back to [`Pipeline::resolve`] when the route
    /// has no Cholesky factor of `K`, when the updates since the factorisation
    /// have cost more than a fresh one (refactorises instead), or when its
    /// answer misses the tolerance.
    pub fn resolve_update(
        &mut self,
        layout: Layout,
        m: Matrices,
        rhs: &[f64],
        x0: &[f64],
        terms: Vec<Term>,
        notes: &mut Notes,
    ) -> Result<Solved, Error> {
        if let (Factor::Cholesky(c), Source::Surrogate, true) =
            (&self.factor, self.source, self.factored)
        {
            // The preconditioner follows the surrogate's broken bonds exactly.
            if let Some(llt) = c.double_factor() {
                if self.low_rank.bytes() <= UPDATE_MEMORY.max(llt.nnz() * 8) {
                    let _ = self.low_rank.extend(terms, llt);
                }
            }
            return self.resolve(layout, m, rhs, x0, notes);
        }
        let llt = match (&self.factor, self.source, self.factored) {
            (Factor::Cholesky(c), Source::Matrix, true) if self.symmetric => c.double_factor(),
            _ => None,
        };
        let Some(llt) = llt else {
            return self.resolve(layout, m, rhs, x0, notes);
        };
        let memory = UPDATE_MEMORY.max(llt.nnz() * 8);
        if self.refactor_next || self.low_rank.bytes() > memory {
            return self.solve(layout, m, rhs, notes);
        }
        let t = Instant::now();
        if !self.low_rank.extend(terms, llt) {
            // K is no longer positive definite: a fresh factorisation names the point.
            return self.solve(layout, m, rhs, notes);
        }
        let c = match &self.factor_forward {
            Some((b, c)) if b.as_slice() == rhs => c,
            _ => {
                let c = llt.forward(rhs);
                &self.factor_forward.insert((rhs.to_vec(), c)).1
            }
        };
        let x = self.low_rank.apply(llt, c);
        let residual = relative_residual(&self.product(m.k, &x), rhs);
        let elapsed = t.elapsed().as_secs_f64();
        let tolerance = self.full_tolerance();
        if !(residual <= tolerance && x.iter().all(|v| v.is_finite())) {
            let mut fallback = self.resolve(layout, m, rhs, &x, notes)?;
            fallback.report.solve_seconds += elapsed;
            return Ok(fallback);
        }
        // Rent or buy: an update's cost grows with the terms carried (their
        // paths, S); once what the updates cost above the fastest of them adds
        // up to a fresh factorisation and solve, the next re-solve factorises.
        self.update_floor = self.update_floor.min(elapsed);
        self.update_excess += elapsed - self.update_floor;
        self.refactor_next = self.update_excess > self.costs.fresh_seconds;
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
            earlier: None,
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

    /// `‖|K||x|‖ / ‖b‖`: ε times it is the round-off floor of a relative
    /// residual computed in double precision.
    fn round_off_scale(&self, k: &Stiffness, x: &[f64], b: &[f64]) -> f64 {
        let abs = Stiffness {
            n: k.n,
            values: k.values.iter().map(|v| v.abs()).collect(),
        };
        let ax: Vec<f64> = x.iter().map(|v| v.abs()).collect();
        let kx = abs.mul_parallel(&self.pattern, self.symmetric, &ax);
        norm2(kx.into_iter()) / norm2(b.iter().copied())
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
        if residual <= RESIDUAL_THRESHOLD || at_floor {
            return Ok(());
        }
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
            #[cfg(feature = "mpi")]
            Source::Petsc => "PETSc's Krylov method measures its own residual, which \
                differs from dhpd's by round-off; tighten it (-ksp_rtol) or solve directly \
                (solver.method = \"cholesky\") on one process"
                .to_string(),
        };
        Err(NumericalError::ResidualTooLarge {
            residual,
            threshold: RESIDUAL_THRESHOLD,
            refinement_steps,
            hint,
        }
        .into())
    }
}

/// Maps a factorisation failure at a free unknown to the point it belongs to.
pub fn factor_error(e: FactorError, layout: Layout) -> Error {
    match e {
        FactorError::NonPositivePivot(k) => {
            let (point, component) = layout.unknown(k);
            NumericalError::NonPositivePivot {
                point,
                component,
                position: layout.x[point],
            }
            .into()
        }
        FactorError::Singular(k) => {
            let (point, component) = layout.unknown(k);
            NumericalError::StructurallySingular { point, component }.into()
        }
        FactorError::NearlySingular(k, ratio) => {
            let (point, component) = layout.unknown(k);
            NumericalError::NearlySingular {
                point,
                component,
                position: layout.x[point],
                ratio,
            }
            .into()
        }
        FactorError::Generic => {
            NumericalError::Solver("factorisation failed (out of memory?)".into()).into()
        }
    }
}
