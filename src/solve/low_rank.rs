//! Exact re-solves after rank-one changes of a factorised matrix
//! (Sherman–Morrison–Woodbury), with the terms carried through the factor's
//! forward half only.
//!
//! A broken bond-based bond removes the rank-one term `k g gᵀ` from `K`
//! (formulation Sec. 3: `g` is `e` on the owner's free unknowns and `−e` on the
//! neighbour's). After `r` such terms since the factorisation
//! `M = Pᵀ L Lᵀ P`, `K = M − U D Uᵀ` (`U = [g₁ … g_r]`, `D = diag(k)`), and with
//! `W = L⁻¹ P U`
//!
//! ```text
//! K⁻¹ b = Pᵀ L⁻ᵀ (c + W S⁻¹ Wᵀ c),   c = L⁻¹ P b,   S = D⁻¹ − Wᵀ W
//! ```
//!
//! (`M⁻¹ U S⁻¹ Uᵀ M⁻¹ = Pᵀ L⁻ᵀ W S⁻¹ Wᵀ L⁻¹ P`). A term's `g` has the few
//! unknowns of two points, so its column of `W` is non-zero only on the
//! elimination-tree path above them ([`super::triangular`]): a new term costs a
//! sparse forward solve and a row of the Cholesky factor of `S` (dot products
//! of paths, which meet only at common ancestors); a re-solve costs one
//! backward half-solve and `O(nnz W)`. `S` is positive definite exactly when
//! `K` is, so a failing pivot of `S` flags a mechanism (the caller then
//! factorises afresh, which names the point).

use super::triangular::{Llt, PathColumn};
use rayon::prelude::*;

/// A rank-one term `k g gᵀ` removed from the matrix: `g` as `(free unknown, value)`.
#[derive(Debug, Clone, PartialEq)]
pub struct Term {
    /// The non-zero entries of `g`.
    pub entries: Vec<(usize, f64)>,
    /// `k > 0`.
    pub stiffness: f64,
}

/// Pivot of `S`, relative to its diagonal entry, below which `K` counts as singular.
const PIVOT_RATIO: f64 = 1e-12;

/// The terms removed since the last factorisation.
#[derive(Debug, Default)]
pub struct LowRank {
    terms: Vec<Term>,
    /// `W = L⁻¹ P U`, one path column per term.
    w: Vec<PathColumn>,
    /// Rows of the lower Cholesky factor of `S`.
    s_factor: Vec<Vec<f64>>,
}

impl LowRank {
    /// Number of terms.
    pub fn len(&self) -> usize {
        self.terms.len()
    }

    /// Whether no term was removed.
    pub fn is_empty(&self) -> bool {
        self.terms.is_empty()
    }

    /// Forgets every term (after a fresh factorisation).
    pub fn clear(&mut self) {
        self.terms.clear();
        self.w.clear();
        self.s_factor.clear();
    }

    /// Bytes held by `W` and the factor of `S`.
    pub fn bytes(&self) -> usize {
        let w: usize = self.w.iter().map(|c| c.len() * 8).sum();
        w + self.len() * (self.len() + 1) * 4
    }

    /// Adds `terms` removed from the matrix factorised as `factor`. Returns
    /// `false` (and keeps the previous state) when `S` stops being positive
    /// definite.
    pub fn extend(&mut self, terms: Vec<Term>, factor: Llt<'_>) -> bool {
        let before = self.len();
        let paths: Vec<PathColumn> = terms
            .par_iter()
            .map(|t| factor.forward_sparse(&t.entries))
            .collect();
        for (term, w) in terms.into_iter().zip(paths) {
            // Row of S for the new term: S_ca = δ_ca / k_c − w_aᵀ w_c.
            let s_row: Vec<f64> = self.w.par_iter().map(|wa| -wa.dot(&w)).collect();
            let mut row = Vec::with_capacity(s_row.len() + 1);
            for (a, s_ca) in s_row.into_iter().enumerate() {
                let partial: f64 = (0..a).map(|q| row[q] * self.s_factor[a][q]).sum();
                row.push((s_ca - partial) / self.s_factor[a][a]);
            }
            let s_cc = 1.0 / term.stiffness - w.dot(&w);
            let pivot = s_cc - row.iter().map(|v| v * v).sum::<f64>();
            if !(pivot > PIVOT_RATIO * (1.0 / term.stiffness)) {
                self.truncate(before);
                return false;
            }
            row.push(pivot.sqrt());
            self.terms.push(term);
            self.w.push(w);
            self.s_factor.push(row);
        }
        true
    }

    fn truncate(&mut self, len: usize) {
        self.terms.truncate(len);
        self.w.truncate(len);
        self.s_factor.truncate(len);
    }

    /// `K⁻¹ b` from `c = L⁻¹ P b` ([`Llt::forward`]): `Pᵀ L⁻ᵀ (c + W S⁻¹ Wᵀ c)`.
    pub fn apply(&self, factor: Llt<'_>, c: &[f64]) -> Vec<f64> {
        let k = self.len();
        let mut t: Vec<f64> = self.w.par_iter().map(|wa| wa.dot_dense(c)).collect();
        // S t' = t with S = F Fᵀ: forward, then backward substitution.
        for a in 0..k {
            let s: f64 = (0..a).map(|q| self.s_factor[a][q] * t[q]).sum();
            t[a] = (t[a] - s) / self.s_factor[a][a];
        }
        for a in (0..k).rev() {
            let s: f64 = (a + 1..k).map(|q| self.s_factor[q][a] * t[q]).sum();
            t[a] = (t[a] - s) / self.s_factor[a][a];
        }
        let mut c = c.to_vec();
        for (wa, &ta) in self.w.iter().zip(&t) {
            wa.add_to(ta, &mut c);
        }
        factor.backward(c)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solve::cholesky::Cholesky;
    use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};

    /// A dense SPD matrix minus rank-one terms, solved through the Woodbury
    /// form with the exact inverse of the original, equals the direct solve;
    /// removing a term that makes the matrix singular is refused.
    #[test]
    fn woodbury_matches_a_direct_solve_and_refuses_a_singular_update() {
        let n = 6;
        // M = tridiagonal springs between 0..n and fixed ends.
        let springs = [2.0, 1.0, 3.0, 1.5, 2.5, 1.0, 2.0];
        let matrix = |removed: &[(usize, f64)]| {
            let mut m = vec![vec![0.0; n]; n];
            for (s, &k) in springs.iter().enumerate() {
                let k = k - removed
                    .iter()
                    .filter(|r| r.0 == s)
                    .map(|r| r.1)
                    .sum::<f64>();
                let (a, b) = (s.checked_sub(1), (s < n).then_some(s));
                for (p, q, sign) in [(a, a, 1.0), (b, b, 1.0), (a, b, -1.0), (b, a, -1.0)] {
                    if let (Some(p), Some(q)) = (p, q) {
                        m[p][q] += sign * k;
                    }
                }
            }
            m
        };
        let solve = |m: &Vec<Vec<f64>>, b: &[f64]| {
            // Gaussian elimination (small, SPD).
            let mut a = m.clone();
            let mut x = b.to_vec();
            for c in 0..n {
                for r in c + 1..n {
                    let f = a[r][c] / a[c][c];
                    for q in c..n {
                        a[r][q] -= f * a[c][q];
                    }
                    x[r] -= f * x[c];
                }
            }
            for c in (0..n).rev() {
                let s: f64 = (c + 1..n).map(|q| a[c][q] * x[q]).sum();
                x[c] = (x[c] - s) / a[c][c];
            }
            x
        };
        // The factor of the original matrix (faer, AMD order).
        let m0 = matrix(&[]);
        let (mut col_ptr, mut row_idx, mut values) = (vec![0], Vec::new(), Vec::new());
        for c in 0..n {
            for (r, row) in m0.iter().enumerate() {
                if row[c] != 0.0 {
                    row_idx.push(r);
                    values.push(row[c]);
                }
            }
            col_ptr.push(row_idx.len());
        }
        let pattern = SymbolicSparseColMatRef::new_checked(n, n, &col_ptr, None, &row_idx);
        let mut chol = Cholesky::analyse(pattern, None).unwrap();
        chol.factorize(SparseColMatRef::new(pattern, &values))
            .unwrap();
        let llt = chol.double_factor().unwrap();
        // Spring s between unknowns s−1 and s: g = e_{s−1} − e_s.
        let term = |s: usize, k: f64| Term {
            entries: [(s.wrapping_sub(1), 1.0), (s, -1.0)]
                .into_iter()
                .filter(|&(i, _)| i < n)
                .collect(),
            stiffness: k,
        };
        let b: Vec<f64> = (0..n).map(|i| 1.0 + i as f64).collect();
        let mut low = LowRank::default();
        assert!(low.extend(vec![term(2, 1.0), term(4, 0.5)], llt));
        assert!(low.extend(vec![term(0, 1.5)], llt));
        let x = low.apply(llt, &llt.forward(&b));
        let direct = solve(&matrix(&[(2, 1.0), (4, 0.5), (0, 1.5)]), &b);
        for (a, c) in x.iter().zip(&direct) {
            assert!(
                (a - c).abs() < 1e-12 * c.abs().max(1.0),
                "{x:?} vs {direct:?}"
            );
        }
        // Removing all of spring 3 splits the chain... but both halves stay held
        // by the end springs; removing spring 0 entirely and spring 1 too leaves
        // unknown 0 held by nothing: singular, refused, state kept.
        assert!(!low.extend(vec![term(0, 0.5), term(1, 1.0)], llt));
        assert_eq!(low.len(), 3);
    }
}
