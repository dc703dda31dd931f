//! Which bonds are critical, decided beyond the error of an iterative re-solve.
//!
//! The event strategy breaks the bonds whose ratio at λ = 1 lies within the
//! relative `tolerance` τ of the largest, `r_b ≥ (1 − τ) max_c r_c`. After a
//! Krylov re-solve (the iterative route, or CG/GMRES with an old factor) the
//! ratios carry the solve's error: with `r̃_b` computed from the solution and
//! `|r̃_b − r_b| ≤ η_b`, the true largest ratio `M` lies in
//! `[max(r̃ − η), max(r̃ + η)] = [M_lo, M_hi]`, and bond `b` is
//!
//! ```text
//! surely critical      r̃_b − η_b ≥ (1 − τ) M_hi
//! surely not critical  r̃_b + η_b < (1 − τ) M_lo
//! ```
//!
//! The ranking is decided when every bond is one or the other. The error
//! estimate comes from the solve itself: its checkpoint iterate
//! ([`crate::solve::pipeline::Solved::earlier`]) has a residual
//! [`crate::solve::pipeline::CHECKPOINT_FACTOR`] times larger, and while the iteration converges
//! steadily its error is about that factor larger, so `η_b = |r_b(x_earlier) −
//! r_b(x)|` overestimates the error of `r_b(x)` about as much. When a bond is
//! undecided, the solution is improved by Krylov iterations (residual
//! [`crate::solve::pipeline::CHECKPOINT_FACTOR`] times smaller, the previous solution becoming the
//! estimate) until it is decided, up to [`MAX_TIGHTENING`] rounds or the
//! round-off floor; a ranking still undecided then is broken as computed and
//! counted in the run's log. Direct solves and exact factor updates are
//! decided at round-off (ties within τ break together by construction).
//! Checked in `tests/fracture.rs`: the iterative and direct routes
//! break the same bonds at the same events on a notched plate.
//!
//! **The `all` strategy** breaks every bond over its critical value at the
//! step's load factor λ, `λ r_b ≥ 1`, and re-solves until none is. Its
//! intermediate re-solves (those after which bonds break again) serve only
//! that decision, so on a Krylov route they stop at the looser relative
//! residual [`INTERMEDIATE_TOLERANCE`] and the decision is checked instead:
//! bond `b` is surely over when `λ (r̃_b − η_b) ≥ 1` and surely under when
//! `λ (r̃_b + η_b) < 1`, the solution improved as above until every bond is
//! one or the other. The state a step ends in (settled, or past
//! `stop_after_peak`) is improved to the full tolerance before it is checked
//! again and recorded, so every recorded state is as accurate as before.

use super::*;

/// Relative residual of the `all` strategy's intermediate Krylov re-solves
/// (module docs): four orders of magnitude above the full tolerance, the
/// decisions checked against the error.
pub(super) const INTERMEDIATE_TOLERANCE: f64 = 1e-8;

/// Rounds of tighter re-solves spent on one undecided ranking.
pub(super) const MAX_TIGHTENING: usize = 4;

/// How the decisions taken after Krylov re-solves were made (the event
/// strategy's rankings; the `all` strategy's bonds over their critical value).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub struct RankingStats {
    /// Rankings that followed a Krylov re-solve (and so were checked).
    pub checked: usize,
    /// Of those, rankings that needed tighter re-solves to be decided.
    pub tightened: usize,
    /// Rankings still undecided at the round-off floor or after
    /// [`MAX_TIGHTENING`] rounds (broken as computed).
    pub undecided: usize,
}

impl Run<'_> {
    /// Makes the current ratios decide which bonds are critical (module
    /// docs): after a Krylov re-solve, improves the solution until they do.
    /// The tighter re-solves are recorded at `step`.
    pub(super) fn decide_ranking(&mut self, step: usize) -> Result<(), Error> {
        let tolerance = self.settings.tolerance;
        self.decide(step, 1.0, |ratios, estimate| {
            decided(ratios, estimate, tolerance)
        })
    }

    /// The `all` strategy's decision at `load_factor` (module docs): every
    /// bond surely over its critical value (`λ (r̃_b − η_b) ≥ 1`) or surely
    /// under it (`λ (r̃_b + η_b) < 1`); improves the solution until it is.
    pub(super) fn decide_threshold(&mut self, step: usize, load_factor: f64) -> Result<(), Error> {
        self.decide(step, load_factor, decided_threshold)
    }

    /// Improves the solution of the last Krylov re-solve until `decided(ratios,
    /// estimate)` holds for the ratios at `load_factor` of the solution and of
    /// the estimate of its error; counted in [`RankingStats`].
    fn decide(
        &mut self,
        step: usize,
        load_factor: f64,
        decided: impl Fn(&[f64], &[f64]) -> bool,
    ) -> Result<(), Error> {
        let earlier = self.earlier.take();
        let krylov = self.solves.last().is_some_and(|s| s.report.iterations > 0);
        if !krylov {
            return Ok(());
        }
        self.ranking.checked += 1;
        let mut earlier = earlier;
        for round in 0..=MAX_TIGHTENING {
            if let Some(e) = earlier.take() {
                let estimate: Vec<f64> =
                    self.ratios_of(&e).iter().map(|r| r * load_factor).collect();
                if decided(&self.ratios, &estimate) {
                    if round > 0 {
                        self.ranking.tightened += 1;
                    }
                    return Ok(());
                }
                if round == MAX_TIGHTENING {
                    break;
                }
            }
            match self.improve_solution(step, None)? {
                Some(e) => earlier = e,
                None => break,
            }
            self.update_ratios(load_factor);
        }
        self.ranking.undecided += 1;
        Ok(())
    }

    /// Improves the current solution by Krylov iterations to the relative
    /// residual `target` (`None`: [`crate::solve::pipeline::CHECKPOINT_FACTOR`]
    /// times smaller), recorded as a solve at `step`; the reactions follow.
    /// Returns the previous solution (the new error estimate), or `None` when
    /// no improvement was possible.
    pub(super) fn improve_solution(
        &mut self,
        step: usize,
        target: Option<f64>,
    ) -> Result<Option<Option<Vec<f64>>>, Error> {
        let (pipeline, m) = self.system.parts();
        let Some(improved) = pipeline.improve(m, &self.solve_rhs, &self.x, target)? else {
            return Ok(None);
        };
        self.x = improved.x;
        let u = self.unit_displacement();
        self.unit_reactions = reactions(&self.model, &self.disc, &self.dofs, &self.f_ext, &u, 1.0);
        self.solves.push(ResolveRecord {
            step,
            bonds_broken: 0,
            report: improved.report,
        });
        Ok(Some(improved.earlier))
    }

    /// The ratios at λ = 1 of the free unknowns `x`.
    fn ratios_of(&self, x: &[f64]) -> Vec<f64> {
        let u = self.unit_displacement_of(x);
        let mut ratios = vec![0.0; self.ratios.len()];
        self.criterion
            .ratios(&self.model, &self.disc, &u, true, &mut ratios);
        ratios
    }
}

/// Whether every bond is surely critical or surely not (module docs), with
/// `ratios` from the solution, errors `|ratios − estimate|` and the relative
/// tie tolerance `tau`. Bonds whose ratio is zero (broken, or unstretched)
/// take no part.
fn decided(ratios: &[f64], estimate: &[f64], tau: f64) -> bool {
    let error = |b: usize| (ratios[b] - estimate[b]).abs();
    let live = || (0..ratios.len()).filter(|&b| ratios[b] > 0.0);
    let high = live().map(|b| ratios[b] + error(b)).fold(0.0, f64::max);
    let low = live().map(|b| ratios[b] - error(b)).fold(0.0, f64::max);
    let (surely_in, surely_out) = ((1.0 - tau) * high, (1.0 - tau) * low);
    live().all(|b| {
        let (r, e) = (ratios[b], error(b));
        r - e >= surely_in || r + e < surely_out
    })
}

/// Whether every bond is surely over its critical value or surely under it
/// (`ratios` and `estimate` at the step's load factor, errors
/// `|ratios − estimate|`). Bonds whose ratio is zero take no part.
fn decided_threshold(ratios: &[f64], estimate: &[f64]) -> bool {
    ratios.iter().zip(estimate).all(|(&r, &e)| {
        let error = (r - e).abs();
        r == 0.0 || r - error >= 1.0 || r + error < 1.0
    })
}

#[cfg(test)]
mod tests {
    use super::{decided, decided_threshold};

    /// Two bonds a relative 1e-5 apart, tolerance 1e-6: decided while the
    /// errors are far below the gap, undecided once they reach it; a bond tied
    /// with the largest (within the tolerance) is decided as long as the
    /// errors leave it inside the tie.
    #[test]
    fn a_ranking_is_decided_only_beyond_its_errors() {
        let ratios = [1.0, 1.0 - 1e-5, 0.5, 0.0];
        let off = |e: f64| ratios.map(|r| if r > 0.0 { r + e } else { r });
        assert!(decided(&ratios, &off(1e-9), 1e-6));
        assert!(!decided(&ratios, &off(5e-6), 1e-6));
        let tied = [1.0, 1.0 - 1e-8, 0.5];
        assert!(decided(&tied, &tied.map(|r| r - 1e-10), 1e-6));
        assert!(!decided(&tied, &tied.map(|r| r - 1e-6), 1e-6));
        // The exact answer (no error) is always decided.
        assert!(decided(&ratios, &ratios, 1e-6));
    }

    /// A bond 1e-6 below its critical value is decided while the error is
    /// smaller than that, and undecided once it reaches it; so is one above.
    #[test]
    fn a_threshold_is_decided_only_beyond_its_errors() {
        let ratios = [1.0 - 1e-6, 1.0 + 1e-6, 0.3, 0.0];
        let off = |e: f64| ratios.map(|r| if r > 0.0 { r + e } else { r });
        assert!(decided_threshold(&ratios, &off(1e-7)));
        assert!(decided_threshold(&ratios, &off(-1e-7)));
        assert!(!decided_threshold(&ratios, &off(2e-6)));
        assert!(!decided_threshold(&ratios, &off(-2e-6)));
        assert!(decided_threshold(&ratios, &ratios));
    }
}
