//! What breaking does to the system (module docs of [`super`]): bonds broken,
//! owners that can no longer carry their bonds, mechanisms, points left without
//! bonds and pieces broken free of every support, each logged.

use super::*;

impl Run<'_> {
    /// Breaks `bonds`; returns how many were intact. Their owners and
    /// neighbours are remembered for [`Run::consequences`].
    pub(super) fn break_bonds(&mut self, bonds: &[usize]) -> usize {
        let mut count = 0;
        for &b in bonds {
            if self.disc.bonds.intact[b] {
                self.disc.bonds.intact[b] = false;
                let owner = self.disc.bonds.offsets.partition_point(|&o| o <= b) - 1;
                self.touched.push(owner);
                self.touched.push(self.disc.bonds.neighbour[b] as usize);
                self.recent.push(b);
                if let Some(unsearched) = &mut self.unsearched {
                    unsearched.push(b);
                }
                count += 1;
            }
        }
        self.broken_total += count;
        self.pending += count;
        count
    }

    /// Brings the system up to date after bonds broke (module docs) and
    /// re-solves. Returns an outcome when the run must end.
    pub(super) fn settle(
        &mut self,
        step: usize,
        load_factor: f64,
    ) -> Result<Option<Outcome>, Error> {
        let mut releases = 0;
        loop {
            self.consequences(step, load_factor);
            if let Some(reason) = self.hold_free_pieces(step, load_factor) {
                return Ok(Some(Outcome::Failed { step, reason }));
            }
            match self.solve(step, false) {
                Ok(()) => return Ok(None),
                Err(Error::Numerical(
                    NumericalError::NonPositivePivot { point, .. }
                    | NumericalError::NearlySingular { point, .. }
                    | NumericalError::StructurallySingular { point, .. },
                )) if releases < MAX_RELEASES && self.held[point].is_none() => {
                    releases += 1;
                    let count = self.release(point);
                    self.log.push(format!(
                        "step {step}: point {point} (x = {:?}) is a mechanism (singular in the \
                         factorisation); its {count} remaining bond(s) broke",
                        self.disc.points.x[point]
                    ));
                }
                Err(e) => return Err(e),
            }
        }
    }

    /// Breaks every intact bond touching `point`; returns how many.
    pub(super) fn release(&mut self, point: usize) -> usize {
        let mut touching: Vec<usize> = self.disc.bonds.owned_by(point).collect();
        touching.extend(
            self.disc
                .bonds
                .incoming(point)
                .iter()
                .map(|&(_, b)| b as usize),
        );
        self.break_bonds(&touching)
    }

    /// Shear-model owners that can no longer carry their bonds, and bond-based
    /// mechanisms, until none is left; then points without bonds are held.
    pub(super) fn consequences(&mut self, step: usize, load_factor: f64) {
        while !self.touched.is_empty() {
            let mut touched = std::mem::take(&mut self.touched);
            touched.sort_unstable();
            touched.dedup();
            for i in self.model.refresh_owners(&self.disc, &touched) {
                let bonds: Vec<usize> = self.disc.bonds.owned_by(i).collect();
                let count = self.break_bonds(&bonds);
                self.log.push(format!(
                    "step {step}: the bonds of point {i} (x = {:?}) no longer span the space \
                     (singular shape tensor); its {count} remaining bond(s) broke",
                    self.disc.points.x[i]
                ));
            }
            if self.model.coupling() == Coupling::Star {
                for i in self.unsupported(&touched) {
                    let count = self.release(i);
                    self.log.push(format!(
                        "step {step}: point {i} (x = {:?}) is held by bonds along one line or \
                         plane only (a mechanism); its {count} remaining bond(s) broke",
                        self.disc.points.x[i]
                    ));
                }
            }
            let u = self.displacement(load_factor);
            for &i in &touched {
                // A point that carries an applied load is not held: the free-piece
                // check ends the run instead (the body has failed).
                let loaded = self.f_ext[i].iter().any(|&f| f != 0.0);
                if self.held[i].is_none()
                    && self.dofs.free_count(i) > 0
                    && !loaded
                    && !self.has_bond(i)
                {
                    self.held[i] = Some(u[i]);
                    self.newly_held.push(i);
                    self.log.push(format!(
                        "step {step}: point {i} (x = {:?}) has no intact bond left; held at its \
                         displacement",
                        self.disc.points.x[i]
                    ));
                }
            }
        }
    }

    /// Whether any intact bond touches `i`.
    pub(super) fn has_bond(&self, i: usize) -> bool {
        let bonds = &self.disc.bonds;
        bonds.owned_by(i).any(|b| bonds.intact[b])
            || bonds
                .incoming(i)
                .iter()
                .any(|&(_, b)| bonds.intact[b as usize])
    }

    /// The points of `candidates` with intact bonds whose directions do not span the space.
    pub(super) fn unsupported(&self, candidates: &[usize]) -> Vec<usize> {
        let d = self.disc.d;
        let p = &self.disc.points;
        let bonds = &self.disc.bonds;
        candidates
            .iter()
            .copied()
            .filter(|&i| {
                let mut t = [[0.0f64; 3]; 3];
                let mut any = false;
                let mut add = |j: usize| {
                    let e = crate::vector::sub(&p.x[j], &p.x[i]);
                    let len2 = crate::vector::dot(&e, &e);
                    for r in 0..3 {
                        for c in 0..3 {
                            t[r][c] += e[r] * e[c] / len2;
                        }
                    }
                    any = true;
                };
                for b in bonds.owned_by(i).filter(|&b| bonds.intact[b]) {
                    add(bonds.neighbour[b] as usize);
                }
                for &(o, b) in bonds.incoming(i) {
                    if bonds.intact[b as usize] {
                        add(o as usize);
                    }
                }
                any && !spans(&t, d)
            })
            .collect()
    }

    /// Whether the two ends of every bond in `broken` are still linked through
    /// intact bonds, directly (the other end's bond) or through a common
    /// neighbour. Then no piece broke off: removing a link whose ends stay
    /// connected leaves the connected pieces as they were, whatever the order
    /// of removal. A `false` only means that the whole search must run.
    fn still_linked(&self, broken: &[usize]) -> bool {
        let bonds = &self.disc.bonds;
        let linked = |i: usize| {
            bonds
                .owned_by(i)
                .filter(|&b| bonds.intact[b])
                .map(|b| bonds.neighbour[b] as usize)
                .chain(
                    bonds
                        .incoming(i)
                        .iter()
                        .filter(|&&(_, b)| bonds.intact[b as usize])
                        .map(|&(o, _)| o as usize),
                )
        };
        broken.iter().all(|&b| {
            let i = bonds.offsets.partition_point(|&o| o <= b) - 1;
            let j = bonds.neighbour[b] as usize;
            let mut near: Vec<usize> = linked(i).collect();
            near.sort_unstable();
            linked(j).any(|k| k == i || near.binary_search(&k).is_ok())
        })
    }

    /// Holds the pieces that no support holds any more; returns the reason to
    /// stop when such a piece carries an applied load.
    pub(super) fn hold_free_pieces(&mut self, step: usize, load_factor: f64) -> Option<String> {
        match self.unsearched.replace(Vec::new()) {
            Some(broken) if self.still_linked(&broken) => return None,
            _ => {}
        }
        let u = self.displacement(load_factor);
        for piece in rigid_modes::unheld_bodies(&self.disc, &self.dofs) {
            // Fully prescribed points need no holding (a lone one has a
            // "free" rotation about itself only).
            if piece
                .iter()
                .all(|&i| self.held[i].is_some() || self.dofs.free_count(i) == 0)
            {
                continue;
            }
            let loaded = piece
                .iter()
                .any(|&i| self.f_ext[i].iter().any(|&f| f != 0.0));
            if loaded {
                return Some(format!(
                    "a piece of {} point(s) containing point {} (x = {:?}) carries an applied \
                     load and no support holds it any more",
                    piece.len(),
                    piece[0],
                    self.disc.points.x[piece[0]]
                ));
            }
            for &i in &piece {
                if self.held[i].is_none() && self.dofs.free_count(i) > 0 {
                    self.held[i] = Some(u[i]);
                    self.newly_held.push(i);
                }
            }
            if piece.len() > 1 {
                self.log.push(format!(
                    "step {step}: a piece of {} point(s) containing point {} (x = {:?}) broke \
                     free of every support; held where it is",
                    piece.len(),
                    piece[0],
                    self.disc.points.x[piece[0]]
                ));
            }
        }
        None
    }
}

/// Whether the direction tensor `t` (sum of `e ⊗ e` over unit bond directions)
/// spans the first `d` dimensions (smallest eigenvalue above 1e-8 of the trace).
fn spans(t: &[[f64; 3]; 3], d: usize) -> bool {
    let trace: f64 = (0..d).map(|a| t[a][a]).sum();
    match d {
        1 => trace > 0.0,
        2 => {
            let det = t[0][0] * t[1][1] - t[0][1] * t[1][0];
            // λ_min ≈ det / trace for a 2 × 2 tensor.
            det > 1e-8 * trace * trace
        }
        _ => {
            let m = nalgebra::Matrix3::from_fn(|r, c| t[r][c]);
            let eig = m.symmetric_eigenvalues();
            eig.min() > 1e-8 * trace
        }
    }
}
