//! The linear system of the current bond set at load factor 1: the stiffness
//! refilled where bonds broke, held unknowns pinned, and the solve through the
//! pipeline (fresh, low-rank update or Krylov re-solve).

use super::*;

impl Run<'_> {
    /// Displacements at λ = 1 (held points at zero: they do not deform).
    pub(super) fn unit_displacement(&self) -> Vec<[f64; 3]> {
        self.unit_displacement_of(&self.x)
    }

    /// Displacements at λ = 1 of the free unknowns `x` (held points at zero).
    pub(super) fn unit_displacement_of(&self, x: &[f64]) -> Vec<[f64; 3]> {
        let mut u = self.dofs.expand(x);
        for (i, h) in self.held.iter().enumerate() {
            if h.is_some() {
                u[i] = [0.0; 3];
            }
        }
        u
    }

    /// Displacements at `load_factor`, held points where they are held.
    pub(super) fn displacement(&self, load_factor: f64) -> Vec<[f64; 3]> {
        let mut u = self.dofs.expand(&self.x);
        for (i, ui) in u.iter_mut().enumerate() {
            *ui = match self.held[i] {
                Some(h) => h,
                None => ui.map(|v| load_factor * v),
            };
        }
        u
    }

    /// The rank-one terms `k g gᵀ` that the bonds broken since the last solve
    /// removed from `K` (one per broken pair of points), when the model's bonds
    /// are rank-one ([`Model::bond_stiffness`]) and no point was newly held.
    pub(super) fn low_rank_terms(&self) -> Option<Vec<Term>> {
        if !self.newly_held.is_empty() {
            return None;
        }
        let bonds = &self.disc.bonds;
        let mut pairs: std::collections::BTreeMap<(usize, usize), (f64, [f64; 3])> =
            Default::default();
        for &b in &self.recent {
            let owner = bonds.offsets.partition_point(|&o| o <= b) - 1;
            let j = bonds.neighbour[b] as usize;
            // The model's own term, or the bond-based surrogate's (its factor
            // preconditions the shear model's re-solves).
            let (k, e) = match &self.system.surrogate {
                Some((surrogate, _)) => surrogate.bond_stiffness(&self.disc, owner, b)?,
                None => self.model.bond_stiffness(&self.disc, owner, b)?,
            };
            // Oriented from the lower to the higher point index.
            let (key, e) = if owner < j {
                ((owner, j), e)
            } else {
                ((j, owner), e.map(|v| -v))
            };
            pairs.entry(key).or_insert((0.0, e)).0 += k;
        }
        let d = self.disc.d;
        let free = |i: usize, c: usize| {
            let k = self.dofs.free_index[3 * i + c];
            (k != crate::assembly::dofs::PRESCRIBED).then_some(k as usize)
        };
        Some(
            pairs
                .into_iter()
                .map(|((a, b), (stiffness, e))| Term {
                    entries: (0..d)
                        .filter_map(|c| free(a, c).map(|k| (k, e[c])))
                        .chain((0..d).filter_map(|c| free(b, c).map(|k| (k, -e[c]))))
                        .filter(|&(_, v)| v != 0.0)
                        .collect(),
                    stiffness,
                })
                .filter(|t| !t.entries.is_empty())
                .collect(),
        )
    }

    /// The point columns of `K` that changed since the last solve: the ends of
    /// the broken bonds (star coupling) or every point of the families of their
    /// owners (family coupling), and the newly held points. `None`: all.
    pub(super) fn changed_columns(&mut self, first: bool) -> Option<Vec<bool>> {
        let recent = std::mem::take(&mut self.recent);
        let held = std::mem::take(&mut self.newly_held);
        if first {
            return None;
        }
        let bonds = &self.disc.bonds;
        let mut columns = vec![false; self.disc.points.len()];
        for &b in &recent {
            let owner = bonds.offsets.partition_point(|&o| o <= b) - 1;
            columns[owner] = true;
            columns[bonds.neighbour[b] as usize] = true;
            if self.model.coupling() == Coupling::Family {
                for k in bonds.owned_by(owner) {
                    columns[bonds.neighbour[k] as usize] = true;
                }
            }
        }
        for i in held {
            columns[i] = true;
        }
        Some(columns)
    }

    /// Refills the point `columns` of `K` (and of the surrogate) that changed
    /// (`None`: all), pins the held unknowns, checks the refilled columns'
    /// range and returns the right-hand side at λ = 1 (held unknowns at zero).
    fn refill(&mut self, columns: Option<&[bool]>) -> Result<Vec<f64>, Error> {
        let pattern = self.system.pipeline.pattern();
        stiffness::fill_columns(
            &self.model,
            &self.disc,
            &self.dofs,
            pattern,
            &mut self.system.stiffness.values,
            columns,
        );
        match (
            &mut self.system.surrogate,
            self.system.pipeline.surrogate_pattern(),
        ) {
            // Just assembled with the system for the first solve.
            (Some(_), Some(_)) if columns.is_none() => {}
            (Some((model, values)), Some(p)) => stiffness::fill_columns(
                model,
                &self.disc,
                &self.dofs,
                p,
                &mut values.values,
                columns,
            ),
            // The route no longer factorises a surrogate.
            (surrogate, _) => *surrogate = None,
        }
        let prescribed_changed = columns
            .is_none_or(|c| (0..c.len()).any(|i| c[i] && self.dofs.free_count(i) < self.disc.d));
        if prescribed_changed {
            self.rhs = right_hand_side(&self.model, &self.disc, &self.dofs, &self.f_ext, 1.0);
        }
        let mut rhs = self.rhs.clone();
        let pinned: Vec<bool> = self
            .dofs
            .free_dofs
            .iter()
            .map(|&(i, _)| self.held[i as usize].is_some())
            .collect();
        if pinned.iter().any(|&p| p) {
            let dof_columns: Option<Vec<bool>> = columns.map(|c| {
                self.dofs
                    .free_dofs
                    .iter()
                    .map(|&(i, _)| c[i as usize])
                    .collect()
            });
            let dof_columns = dof_columns.as_deref();
            self.system
                .stiffness
                .pin(pattern, &pinned, self.pin_diagonal, dof_columns);
            if let (Some((_, values)), Some(p)) = (
                &mut self.system.surrogate,
                self.system.pipeline.surrogate_pattern(),
            ) {
                values.pin(p, &pinned, self.pin_diagonal, dof_columns);
            }
            for (r, &p) in rhs.iter_mut().zip(&pinned) {
                if p {
                    *r = 0.0;
                }
            }
        }
        let in_range = check_range(
            &self.system.stiffness,
            pattern,
            &self.dofs,
            &self.disc,
            columns,
        );
        agreed(&self.scene.solver, in_range)?;
        Ok(rhs)
    }

    /// Assembles `K` and `b` for the current bonds (held unknowns pinned) and
    /// solves at λ = 1: afresh for the first solve, else reusing the factor.
    /// Only the columns of `K` that bonds broken since the last solve touch are
    /// refilled, and `b` only when those include a prescribed point.
    pub(super) fn solve(&mut self, step: usize, first: bool) -> Result<(), Error> {
        let terms = if first { None } else { self.low_rank_terms() };
        let columns = self.changed_columns(first);
        let rhs = self.refill(columns.as_deref())?;
        let layout = layout(&self.disc, &self.dofs);
        let (pipeline, mut m) = self.system.parts();
        m.changed = columns.as_deref();
        let notes = &mut self.notes;
        let solved = match terms {
            _ if first => pipeline.solve(layout, m, &rhs, notes),
            Some(terms) => pipeline.resolve_update(layout, m, &rhs, &self.x, terms, notes),
            None => pipeline.resolve(layout, m, &rhs, &self.x, notes),
        };
        let Solved { x, report, earlier } = solved?;
        self.x = x;
        self.earlier = earlier;
        self.solve_rhs = rhs;
        let u = self.unit_displacement();
        self.unit_reactions = reactions(&self.model, &self.disc, &self.dofs, &self.f_ext, &u, 1.0);
        self.solves.push(ResolveRecord {
            step,
            bonds_broken: self.pending,
            report,
        });
        self.pending = 0;
        Ok(())
    }
}
