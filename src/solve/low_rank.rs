//! Exact re-solves after rank-one changes of a factorised matrix
//! (Sherman–Morrison–Woodbury).
//!
//! A broken bond-based bond removes the rank-one term `k g gᵀ` from `K`
//! (formulation Sec. 3: `g` is `e` on the owner's free unknowns and `−e` on the
//! neighbour's). After `r` such terms since the factorisation `M = L Lᵀ`,
//! `K = M − U D Uᵀ` (`U = [g₁ … g_r]`, `D = diag(k)`), and
//!
//! ```text
//! K⁻¹ b = y + Z S⁻¹ Uᵀ y,   y = M⁻¹ b,   Z = M⁻¹ U,   S = D⁻¹ − Uᵀ Z
//! ```
//!
//! Each new term costs one solve with the old factor (for its column of `Z`,
//! several terms in one blocked solve) and a row of the Cholesky factor of `S`;
//! a re-solve costs `O(n r)`. `S` is positive definite exactly when `K` is, so a
//! failing pivot of `S` flags a mechanism (the caller then factorises afresh,
//! which names the point).

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

/// Rows of `x = y + Z w` one thread updates at a time (32 KiB of `x`).
const APPLY_CHUNK: usize = 4096;

/// The terms removed since the last factorisation and what their solves cost.
#[derive(Debug, Default)]
pub struct LowRank {
    terms: Vec<Term>,
    /// `Z = M⁻¹ U`, one column of length `n` per term.
    z: Vec<Vec<f64>>,
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
        self.z.clear();
        self.s_factor.clear();
    }

    /// Bytes held by `Z`.
    pub fn bytes(&self) -> usize {
        self.z.iter().map(|c| c.len() * 8).sum()
    }

    /// Adds `terms`; `solve_block(v, m)` applies `M⁻¹` in place to the `m`
    /// columns of length `n` stored one after the other in `v`. Returns `false`
    /// (and keeps the previous state) when `S` stops being positive definite.
    pub fn extend(
        &mut self,
        terms: Vec<Term>,
        n: usize,
        solve_block: &dyn Fn(&mut [f64], usize),
    ) -> bool {
        if terms.is_empty() {
            return true;
        }
        let m = terms.len();
        let mut block = vec![0.0; n * m];
        for (c, term) in terms.iter().enumerate() {
            for &(i, v) in &term.entries {
                block[c * n + i] = v;
            }
        }
        solve_block(&mut block, m);
        let before = self.len();
        for (c, term) in terms.into_iter().enumerate() {
            let z = block[c * n..(c + 1) * n].to_vec();
            // Row of S for the new term: S_ca = δ_ca / k_c − u_aᵀ z_c.
            let k = self.terms.len();
            let mut row = Vec::with_capacity(k + 1);
            for a in 0..k {
                let s_ca = -dot_sparse(&self.terms[a].entries, &z);
                let partial: f64 = (0..a).map(|q| row[q] * self.s_factor[a][q]).sum();
                row.push((s_ca - partial) / self.s_factor[a][a]);
            }
            let s_cc = 1.0 / term.stiffness - dot_sparse(&term.entries, &z);
            let pivot = s_cc - row.iter().map(|v| v * v).sum::<f64>();
            if !(pivot > PIVOT_RATIO * (1.0 / term.stiffness)) {
                self.truncate(before);
                return false;
            }
            row.push(pivot.sqrt());
            self.terms.push(term);
            self.z.push(z);
            self.s_factor.push(row);
        }
        true
    }

    fn truncate(&mut self, len: usize) {
        self.terms.truncate(len);
        self.z.truncate(len);
        self.s_factor.truncate(len);
    }

    /// `K⁻¹ b` from `y = M⁻¹ b`: `y + Z S⁻¹ Uᵀ y`.
    pub fn apply(&self, y: &[f64]) -> Vec<f64> {
        let k = self.len();
        let mut w: Vec<f64> = self
            .terms
            .iter()
            .map(|t| dot_sparse(&t.entries, y))
            .collect();
        // S w' = w with S = F Fᵀ: forward, then backward substitution.
        for a in 0..k {
            let s: f64 = (0..a).map(|q| self.s_factor[a][q] * w[q]).sum();
            w[a] = (w[a] - s) / self.s_factor[a][a];
        }
        for a in (0..k).rev() {
            let s: f64 = (a + 1..k).map(|q| self.s_factor[q][a] * w[q]).sum();
            w[a] = (w[a] - s) / self.s_factor[a][a];
        }
        // x = y + Z w, by chunks of rows in parallel; every entry sums the
        // columns in order, as a sequential loop would.
        let mut x = y.to_vec();
        x.par_chunks_mut(APPLY_CHUNK)
            .enumerate()
            .for_each(|(c, chunk)| {
                let start = c * APPLY_CHUNK;
                for (column, &wa) in self.z.iter().zip(&w) {
                    let z = &column[start..start + chunk.len()];
                    chunk.iter_mut().zip(z).for_each(|(xi, zi)| *xi += wa * zi);
                }
            });
        x
    }
}

fn dot_sparse(entries: &[(usize, f64)], dense: &[f64]) -> f64 {
    entries.iter().map(|&(i, v)| v * dense[i]).sum()
}

#[cfg(test)]
mod tests {
    use super::*;

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
        let m0 = matrix(&[]);
        let solve_block = |v: &mut [f64], cols: usize| {
            for c in 0..cols {
                let x = solve(&m0, &v[c * n..(c + 1) * n]);
                v[c * n..(c + 1) * n].copy_from_slice(&x);
            }
        };
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
        assert!(low.extend(vec![term(2, 1.0), term(4, 0.5)], n, &solve_block));
        assert!(low.extend(vec![term(0, 1.5)], n, &solve_block));
        let x = low.apply(&solve(&m0, &b));
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
        assert!(!low.extend(vec![term(0, 0.5), term(1, 1.0)], n, &solve_block));
        assert_eq!(low.len(), 3);
    }
}
