//! Preconditioned conjugate gradients (Saad, Iterative Methods for Sparse Linear
//! Systems, Alg. 9.1) for symmetric positive definite systems, used to re-solve
//! after bonds broke with the previous Cholesky factor as preconditioner.
//!
//! If `K = M − ΔK` with `ΔK` of rank `k`, the preconditioned operator `M⁻¹K`
//! has at most `k + 1` distinct eigenvalues, so CG converges in at most `k + 1`
//! iterations in exact arithmetic.

use super::gmres::GmresReport as KrylovReport;

/// Solves `A x = b` from the initial guess `x`, with `apply(v) = A v` and
/// `precondition(v) ≈ A⁻¹ v` in place, until `‖b − A x‖ ≤ tol ‖b‖` or
/// `max_iterations` products were spent. The true residual is recomputed at
/// the end (it is what the report gives). `stagnated` reports a breakdown:
/// a search direction `p` with `pᵀ A p ≤ 0`, so `A` is not positive definite
/// (a mechanism) unless round-off at convergence caused it.
pub fn pcg(
    apply: &dyn Fn(&[f64]) -> Vec<f64>,
    precondition: &dyn Fn(&mut [f64]),
    b: &[f64],
    x: &mut [f64],
    tol: f64,
    max_iterations: usize,
) -> KrylovReport {
    pcg_with_checkpoint(apply, precondition, b, x, tol, max_iterations, None).0
}

/// [`pcg`] that also returns the first iterate whose recursive residual is at
/// most `checkpoint · ‖b‖` (`checkpoint > tol`; the initial guess if it already
/// is, `None` if no iteration ran). While the iteration converges steadily, that
/// iterate's distance from the final one estimates the final error from above
/// (its own error is about `checkpoint / tol` times larger): the event strategy
/// uses it to certify which bonds are critical.
pub fn pcg_with_checkpoint(
    apply: &dyn Fn(&[f64]) -> Vec<f64>,
    precondition: &dyn Fn(&mut [f64]),
    b: &[f64],
    x: &mut [f64],
    tol: f64,
    max_iterations: usize,
    checkpoint: Option<f64>,
) -> (KrylovReport, Option<Vec<f64>>) {
    let dot = |a: &[f64], c: &[f64]| a.iter().zip(c).map(|(p, q)| p * q).sum::<f64>();
    let norm = |v: &[f64]| super::norm2(v.iter().copied());
    let b_norm = norm(b);
    if b_norm == 0.0 {
        x.iter_mut().for_each(|v| *v = 0.0);
        let report = KrylovReport {
            iterations: 0,
            relative_residual: 0.0,
            converged: true,
            stagnated: false,
        };
        return (report, None);
    }
    let ax = apply(x);
    let mut r: Vec<f64> = b.iter().zip(&ax).map(|(bi, ai)| bi - ai).collect();
    let mut iterations = 0;
    let mut z = r.clone();
    precondition(&mut z);
    let mut p = z.clone();
    let mut rz = dot(&r, &z);
    let mut broke_down = false;
    let mut earlier = None;
    loop {
        let r_norm = norm(&r);
        if earlier.is_none() && checkpoint.is_some_and(|c| r_norm <= c * b_norm) {
            earlier = Some(x.to_vec());
        }
        if r_norm <= tol * b_norm || iterations >= max_iterations {
            break;
        }
        let ap = apply(&p);
        iterations += 1;
        let pap = dot(&p, &ap);
        if !(pap > 0.0) {
            // Not positive definite along p (or round-off at convergence): stop.
            broke_down = true;
            break;
        }
        let alpha = rz / pap;
        x.iter_mut().zip(&p).for_each(|(xi, pi)| *xi += alpha * pi);
        r.iter_mut().zip(&ap).for_each(|(ri, ai)| *ri -= alpha * ai);
        z.copy_from_slice(&r);
        precondition(&mut z);
        let rz_new = dot(&r, &z);
        let beta = rz_new / rz;
        rz = rz_new;
        p.iter_mut()
            .zip(&z)
            .for_each(|(pi, zi)| *pi = zi + beta * *pi);
    }
    let ax = apply(x);
    let true_residual = super::norm2(b.iter().zip(&ax).map(|(bi, ai)| bi - ai)) / b_norm;
    let report = KrylovReport {
        iterations,
        relative_residual: true_residual,
        converged: true_residual <= tol,
        stagnated: broke_down && true_residual > tol,
    };
    (report, earlier.filter(|_| iterations > 0))
}

#[cfg(test)]
mod tests {
    use super::pcg;

    /// A 1D Laplacian (SPD) preconditioned by the exact inverse of a matrix that
    /// differs from it in `k` rank-one terms: CG converges in at most k + 1 iterations.
    #[test]
    fn a_rank_k_change_takes_at_most_k_plus_one_iterations() {
        let n = 60;
        let springs = |removed: &[usize]| -> Vec<f64> {
            (0..=n)
                .map(|s| if removed.contains(&s) { 0.5 } else { 1.0 })
                .collect()
        };
        // Springs s = 0..=n connect node s−1 and s (nodes −1 and n are fixed).
        let apply_with = |k: Vec<f64>| {
            move |v: &[f64]| -> Vec<f64> {
                (0..n)
                    .map(|i| {
                        let left = if i > 0 { v[i - 1] } else { 0.0 };
                        let right = if i + 1 < n { v[i + 1] } else { 0.0 };
                        (k[i] + k[i + 1]) * v[i] - k[i] * left - k[i + 1] * right
                    })
                    .collect()
            }
        };
        // Exact inverse of the unchanged operator by a tridiagonal (Thomas) solve.
        let k0 = springs(&[]);
        let inverse = |v: &mut [f64]| {
            let (mut c, mut d) = (vec![0.0; n], vec![0.0; n]);
            for i in 0..n {
                let a = if i > 0 { -k0[i] } else { 0.0 };
                let diag = k0[i] + k0[i + 1] - if i > 0 { a * c[i - 1] } else { 0.0 };
                c[i] = -k0[i + 1] / diag;
                d[i] = (v[i] - if i > 0 { a * d[i - 1] } else { 0.0 }) / diag;
            }
            for i in (0..n).rev() {
                v[i] = d[i] - if i + 1 < n { c[i] * v[i + 1] } else { 0.0 };
            }
        };
        let b: Vec<f64> = (0..n).map(|i| 1.0 + (i as f64).sin()).collect();
        for removed in [vec![7], vec![3, 20, 41], vec![1, 2, 30, 31, 50]] {
            let apply = apply_with(springs(&removed));
            let mut x = vec![0.0; n];
            let report = pcg(&apply, &inverse, &b, &mut x, 1e-12, 100);
            assert!(report.converged, "{report:?}");
            assert!(
                report.iterations <= removed.len() + 1,
                "{} changes, {} iterations",
                removed.len(),
                report.iterations
            );
        }
    }
}
