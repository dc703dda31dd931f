//! The strategies of the quasi-static driver (module docs of [`super`]): the
//! event loop, the stepped loop, the ratios of every bond at a load factor, the
//! records and the end of a run.

use super::ranking::INTERMEDIATE_TOLERANCE;
use super::*;

impl Run<'_> {
    /// The event strategy (module docs). Returns the outcome and the final load factor.
    pub(super) fn events(
        &mut self,
        observer: &mut dyn Observer,
        records: &mut Vec<StepRecord>,
    ) -> Result<(Outcome, f64), Error> {
        let mut load_factor = 0.0;
        for event in 1..=self.settings.max_events {
            self.update_ratios(1.0);
            self.decide_ranking(event)?;
            let largest = self.ratios.iter().fold(0.0f64, |m, &r| m.max(r));
            let critical = if largest > 0.0 {
                1.0 / largest
            } else {
                f64::INFINITY
            };
            if critical > self.settings.max_load_factor {
                let max = self.settings.max_load_factor;
                let record = self.record(event, StateKind::Equilibrium, max, 0, &[]);
                self.observe(observer, &record)?;
                records.push(record);
                let outcome = if largest > 0.0 {
                    Outcome::Completed
                } else {
                    Outcome::NothingToBreak
                };
                return Ok((outcome, max));
            }
            load_factor = critical;
            let before = self.record(event, StateKind::Critical, load_factor, 0, &[]);
            self.observe(observer, &before)?;
            records.push(before);
            let threshold = (1.0 - self.settings.tolerance) * largest;
            let chosen: Vec<usize> = (0..self.ratios.len())
                .filter(|&b| self.ratios[b] > 0.0 && self.ratios[b] >= threshold)
                .collect();
            let (broken_before, first_solve) = (self.broken_total, self.solves.len());
            self.break_bonds(&chosen);
            let ended = self.settle(event, load_factor)?;
            let solves = self.solves[first_solve..].to_vec();
            let broken = self.broken_total - broken_before;
            let record = self.record(event, StateKind::Broken, load_factor, broken, &solves);
            self.observe(observer, &record)?;
            records.push(record);
            if let Some(outcome) = ended {
                return Ok((outcome, load_factor));
            }
            if let Some(outcome) = self.ended(event, load_factor) {
                return Ok((outcome, load_factor));
            }
        }
        Ok((Outcome::EventCap, load_factor))
    }

    /// The `all` and `most_critical` strategies (module docs).
    pub(super) fn stepped(
        &mut self,
        observer: &mut dyn Observer,
        records: &mut Vec<StepRecord>,
    ) -> Result<(Outcome, f64), Error> {
        let max = self.settings.max_load_factor;
        let uniform = max / self.settings.steps as f64;
        let smallest = uniform * self.settings.min_step_fraction;
        let mut step_size = uniform;
        let mut load_factor = 0.0;
        let mut step = 0;
        while load_factor < max * (1.0 - 1e-12) {
            let target = (load_factor + step_size).min(max);
            if self.too_many_over(target) && step_size > smallest {
                step_size = (0.5 * step_size).max(smallest);
                continue;
            }
            // Every accepted step must raise λ (the validated smallest step does):
            // the loop ends after at most steps / min_step_fraction steps.
            if target <= load_factor {
                return Err(crate::error::InputError::new(
                    "quasi_static.min_step_fraction",
                    format!(
                        "a step of {step_size:e} no longer changes the load factor {load_factor:e}; \
                         give a larger min_step_fraction"
                    ),
                )
                .into());
            }
            step += 1;
            load_factor = target;
            let first_solve = self.solves.len();
            let broken_before = self.broken_total;
            let (outcome, settled) = self.break_until_settled(step, load_factor)?;
            let solves = self.solves[first_solve..].to_vec();
            let record = self.record(
                step,
                if settled {
                    StateKind::Equilibrium
                } else {
                    StateKind::Unsettled
                },
                load_factor,
                self.broken_total - broken_before,
                &solves,
            );
            self.observe(observer, &record)?;
            records.push(record);
            if let Some(outcome) = outcome {
                return Ok((outcome, load_factor));
            }
            if let Some(outcome) = self.ended(step, load_factor) {
                return Ok((outcome, load_factor));
            }
            step_size = (2.0 * step_size).min(uniform);
        }
        Ok((Outcome::Completed, load_factor))
    }

    /// With `max_broken_per_step`: whether a step to `target` would find more
    /// bonds over their critical value (the step is then halved).
    fn too_many_over(&mut self, target: f64) -> bool {
        let Some(limit) = self.settings.max_broken_per_step else {
            return false;
        };
        self.update_ratios(target);
        self.ratios.iter().filter(|&&r| r >= 1.0).count() > limit
    }

    /// At load step `step`, breaks the bonds over their critical value
    /// (`all`; `most_critical`: those within `tolerance` of the largest) and
    /// re-solves, until none is over (or `max_resolves`, logged). Returns an
    /// outcome when the run must end, and whether the step settled (no bond
    /// left over its critical value).
    ///
    /// The reactions are checked against `stop_after_peak` after every
    /// re-solve: at a fixed grip displacement a broken bond only softens the
    /// body, so once every reaction is below the fraction of its peak it stays
    /// there for the rest of the step, and the run ends without growing the
    /// crack further (the record says the step did not settle).
    fn break_until_settled(
        &mut self,
        step: usize,
        load_factor: f64,
    ) -> Result<(Option<Outcome>, bool), Error> {
        // `all` re-solves to a looser tolerance between breaks and checks its
        // decisions against the error (module docs of `ranking`).
        let loose = self.settings.strategy == Strategy::All;
        let mut resolves = 0;
        // Whether the current solution is such an intermediate re-solve's.
        let mut intermediate = false;
        loop {
            self.update_ratios(load_factor);
            if intermediate {
                self.decide_threshold(step, load_factor)?;
            }
            let largest = self.ratios.iter().fold(0.0f64, |m, &r| m.max(r));
            let past = (resolves > 0)
                .then(|| self.ended(step, load_factor))
                .flatten()
                .filter(|o| matches!(o, Outcome::PastPeak { .. }));
            let last = resolves == self.settings.max_resolves;
            if intermediate && (largest < 1.0 || past.is_some() || last) {
                // The state the step ends in: to the full tolerance, decided again.
                self.complete_solution(step)?;
                intermediate = false;
                continue;
            }
            if largest < 1.0 {
                return Ok((None, true));
            }
            if past.is_some() {
                return Ok((past, false));
            }
            if last {
                self.log.push(format!(
                    "step {step}: stopped re-solving after quasi_static.max_resolves = {} \
                     re-solves with bonds still over their critical value",
                    self.settings.max_resolves
                ));
                return Ok((None, false));
            }
            let threshold = match self.settings.strategy {
                Strategy::MostCritical => (1.0 - self.settings.tolerance) * largest,
                _ => 1.0,
            };
            let chosen: Vec<usize> = (0..self.ratios.len())
                .filter(|&b| self.ratios[b] >= threshold.max(1.0))
                .collect();
            // The body carried λ R₁ of its bonds before these break: a
            // first step that breaks it apart still has that peak, and ends
            // as a separation instead of running to max_load_factor.
            self.note_peak(load_factor);
            self.break_bonds(&chosen);
            resolves += 1;
            let tolerance = loose.then_some(INTERMEDIATE_TOLERANCE);
            self.system.pipeline.set_resolve_tolerance(tolerance);
            let outcome = self.settle(step, load_factor);
            self.system.pipeline.set_resolve_tolerance(None);
            let outcome = outcome?;
            intermediate = loose && self.solves.last().is_some_and(|s| s.report.iterations > 0);
            if outcome.is_some() || self.separated() {
                if intermediate {
                    self.complete_solution(step)?;
                }
                let settled = outcome.is_none();
                return Ok((outcome, settled));
            }
        }
    }

    /// Improves an intermediate re-solve's solution to the full tolerance
    /// (a state that will be recorded).
    fn complete_solution(&mut self, step: usize) -> Result<(), Error> {
        let target = self.system.pipeline.full_tolerance();
        self.improve_solution(step, Some(target)).map(|_| ())
    }

    /// The ratio of every bond at `load_factor` for the current bonds.
    pub(super) fn update_ratios(&mut self, load_factor: f64) {
        let u = self.unit_displacement();
        self.criterion
            .ratios(&self.model, &self.disc, &u, true, &mut self.ratios);
        if load_factor != 1.0 {
            self.ratios.iter_mut().for_each(|r| *r *= load_factor);
        }
    }

    /// A record of the current bonds at `load_factor`; updates the peak reaction.
    pub(super) fn record(
        &mut self,
        step: usize,
        state: StateKind,
        load_factor: f64,
        broken_in_step: usize,
        solves: &[ResolveRecord],
    ) -> StepRecord {
        let reactions: Vec<[f64; 3]> = self
            .unit_reactions
            .iter()
            .map(|r| r.force.map(|f| load_factor * f))
            .collect();
        self.note_peak(load_factor);
        self.recorded_peak = reactions
            .iter()
            .map(crate::vector::magnitude)
            .fold(self.recorded_peak, f64::max);
        use crate::solve::pipeline::Route;
        let routes: Vec<&str> = [Route::Factor, Route::Update, Route::Reuse]
            .into_iter()
            .filter(|&route| solves.iter().any(|s| s.report.route == route))
            .map(Route::name)
            .collect();
        let route = if routes.is_empty() {
            "-".to_string()
        } else {
            routes.join("+")
        };
        StepRecord {
            step,
            state,
            load_factor,
            displacement: load_factor * self.reference_displacement,
            reactions,
            broken_in_step,
            broken_total: self.broken_total,
            resolves: solves.len(),
            route,
            iterations: solves.iter().map(|s| s.report.iterations).sum(),
            residual: solves.last().map_or(0.0, |s| s.report.residual),
            wall_time: self.start.elapsed().as_secs_f64(),
        }
    }

    /// Raises the peak reaction to that of the current bonds at `load_factor`.
    fn note_peak(&mut self, load_factor: f64) {
        for r in &self.unit_reactions {
            let f = load_factor * crate::vector::magnitude(&r.force);
            self.peak_reaction = self.peak_reaction.max(f);
        }
    }

    /// Hands a record to the observer (with the notes so far and the
    /// progress), and a snapshot when the scene asks for one. On the `petsc`
    /// route only rank 0 writes: a failed write there stops every process.
    pub(super) fn observe(
        &mut self,
        observer: &mut dyn Observer,
        record: &StepRecord,
    ) -> Result<(), Error> {
        let observed = self.observe_here(observer, record);
        agreed(&self.scene.solver, observed)
    }

    /// [`Run::observe`] on this process.
    fn observe_here(
        &mut self,
        observer: &mut dyn Observer,
        record: &StepRecord,
    ) -> Result<(), Error> {
        forward(&mut self.notes, observer);
        let settings = self.settings;
        observer.progress(&Progress::Fracture {
            step: record.step,
            steps: (settings.strategy != Strategy::Event).then_some(settings.steps),
            load_factor: record.load_factor,
            max_load_factor: settings.max_load_factor,
            broken: record.broken_total,
        });
        observer.record(record)?;
        let output = &self.scene.output;
        let due = output.every.is_some_and(|n| record.step % n == 0)
            || output.steps.contains(&record.step);
        // For an event, the snapshot shows the state after the break.
        if !due || record.state == StateKind::Critical {
            return Ok(());
        }
        let u = self.displacement(record.load_factor);
        let damage = damage::damage(&self.disc);
        let stress = self.stress(&u)?;
        observer.snapshot(&Snapshot {
            step: record.step,
            timestep: record.load_factor,
            disc: &self.disc,
            u: &u,
            velocity: None,
            damage: &damage,
            stress: stress.as_deref(),
            bond_counts: None,
        })
    }

    /// Whether the run ends after this state: separated, or past the peak of
    /// the recorded states as `stop_after_peak` asks (`load_factor`: that of
    /// the current bonds' state).
    pub(super) fn ended(&self, step: usize, load_factor: f64) -> Option<Outcome> {
        if self.separated() {
            return Some(Outcome::Separated { step });
        }
        let fraction = self.settings.stop_after_peak?;
        let largest = self
            .unit_reactions
            .iter()
            .map(|r| load_factor * crate::vector::magnitude(&r.force))
            .fold(0.0, f64::max);
        (self.recorded_peak > 0.0 && largest < fraction * self.recorded_peak)
            .then_some(Outcome::PastPeak { step })
    }

    /// Whether every reaction has fallen below [`SEPARATED`] of its peak.
    pub(super) fn separated(&self) -> bool {
        let largest = self
            .unit_reactions
            .iter()
            .map(|r| crate::vector::magnitude(&r.force))
            .fold(0.0, f64::max);
        self.peak_reaction > 0.0
            && largest * self.settings.max_load_factor <= SEPARATED * self.peak_reaction
    }
}
