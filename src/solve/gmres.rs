//! Restarted GMRES with right preconditioning (Saad, Iterative Methods for Sparse
//! Linear Systems, Alg. 9.5), used to solve the non-symmetric tangent of the
//! shear model with the Cholesky factor of its symmetric part as preconditioner.

/// Outcome of an iterative solve.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct GmresReport {
    /// Matrix-vector products (= preconditioner applications).
    pub iterations: usize,
    /// Final `‖b − A x‖ / ‖b‖` as tracked by the iteration.
    pub relative_residual: f64,
    /// Whether the tolerance was reached.
    pub converged: bool,
    /// Whether it stopped because a restart cycle no longer reduced the true
    /// residual (the round-off floor `~ cond · ε` above the tolerance).
    pub stagnated: bool,
}

/// A restart cycle must reduce the true residual below this fraction of its
/// value at the previous restart, or the iteration stops as stagnated.
const STAGNATION_FACTOR: f64 = 0.5;

/// Solves `A x = b` from `x` (initial guess), with `apply(v) = A v` and
/// `precondition(v) ≈ A⁻¹ v` in place, restart length `restart`, until the
/// relative residual is below `tol` or `max_iterations` products were spent.
pub fn gmres(
    apply: &dyn Fn(&[f64]) -> Vec<f64>,
    precondition: &dyn Fn(&mut [f64]),
    b: &[f64],
    x: &mut [f64],
    tol: f64,
    restart: usize,
    max_iterations: usize,
) -> GmresReport {
    gmres_with_checkpoint(
        apply,
        precondition,
        b,
        x,
        tol,
        restart,
        max_iterations,
        None,
    )
    .0
}

/// [`gmres`] that also returns the first iterate whose residual (as the
/// iteration tracks it) is at most `checkpoint · ‖b‖` (`checkpoint > tol`;
/// `None` if no iteration ran): its distance from the final iterate estimates
/// the final error from above, as in [`super::cg::pcg_with_checkpoint`]. Forming
/// it within a cycle costs one preconditioner application.
#[allow(clippy::too_many_arguments)]
pub fn gmres_with_checkpoint(
    apply: &dyn Fn(&[f64]) -> Vec<f64>,
    precondition: &dyn Fn(&mut [f64]),
    b: &[f64],
    x: &mut [f64],
    tol: f64,
    restart: usize,
    max_iterations: usize,
    checkpoint: Option<f64>,
) -> (GmresReport, Option<Vec<f64>>) {
    let norm = |v: &[f64]| super::norm2(v.iter().copied());
    let b_norm = norm(b);
    if b_norm == 0.0 {
        x.iter_mut().for_each(|v| *v = 0.0);
        let report = GmresReport {
            iterations: 0,
            relative_residual: 0.0,
            converged: true,
            stagnated: false,
        };
        return (report, None);
    }
    let mut earlier: Option<Vec<f64>> = None;
    let mut iterations = 0;
    let mut previous = f64::INFINITY;
    loop {
        let ax = apply(x);
        let r: Vec<f64> = b.iter().zip(&ax).map(|(bi, ai)| bi - ai).collect();
        let beta = norm(&r);
        let relative = beta / b_norm;
        // A cycle that did not halve the true residual has reached the accuracy
        // that round-off allows (the recurrence's residual then keeps claiming
        // convergence while the true one stays put): stop instead of cycling.
        let stagnated = relative > STAGNATION_FACTOR * previous;
        if earlier.is_none() && checkpoint.is_some_and(|c| relative <= c) {
            earlier = Some(x.to_vec());
        }
        if relative <= tol || iterations >= max_iterations || stagnated {
            let report = GmresReport {
                iterations,
                relative_residual: relative,
                converged: relative <= tol,
                stagnated: stagnated && relative > tol,
            };
            return (report, earlier.filter(|_| iterations > 0));
        }
        previous = relative;
        let mut basis: Vec<Vec<f64>> = vec![r.iter().map(|v| v / beta).collect()];
        let mut h = vec![vec![0.0; restart]; restart + 1];
        let (mut cs, mut sn) = (vec![0.0; restart], vec![0.0; restart]);
        let mut g = vec![0.0; restart + 1];
        g[0] = beta;
        let mut k_used = 0;
        for k in 0..restart {
            let mut z = basis[k].clone();
            precondition(&mut z);
            let mut w = apply(&z);
            iterations += 1;
            for (j, v) in basis.iter().enumerate() {
                let hjk: f64 = w.iter().zip(v).map(|(a, c)| a * c).sum();
                h[j][k] = hjk;
                w.iter_mut().zip(v).for_each(|(a, c)| *a -= hjk * c);
            }
            let wn = norm(&w);
            h[k + 1][k] = wn;
            for j in 0..k {
                let t = cs[j] * h[j][k] + sn[j] * h[j + 1][k];
                h[j + 1][k] = -sn[j] * h[j][k] + cs[j] * h[j + 1][k];
                h[j][k] = t;
            }
            let d = (h[k][k] * h[k][k] + h[k + 1][k] * h[k + 1][k]).sqrt();
            (cs[k], sn[k]) = if d == 0.0 {
                (1.0, 0.0)
            } else {
                (h[k][k] / d, h[k + 1][k] / d)
            };
            h[k][k] = d;
            h[k + 1][k] = 0.0;
            g[k + 1] = -sn[k] * g[k];
            g[k] *= cs[k];
            k_used = k + 1;
            let tracked = g[k + 1].abs() / b_norm;
            if earlier.is_none() && checkpoint.is_some_and(|c| tracked <= c) && tracked > tol {
                let update = krylov_update(&h, &g, &basis, k_used, precondition);
                earlier = Some(x.iter().zip(&update).map(|(xi, ui)| xi + ui).collect());
            }
            if tracked <= tol || wn == 0.0 || iterations >= max_iterations {
                break;
            }
            basis.push(w.iter().map(|v| v / wn).collect());
        }
        let update = krylov_update(&h, &g, &basis, k_used, precondition);
        x.iter_mut().zip(&update).for_each(|(xi, ui)| *xi += ui);
    }
}

/// The correction `M⁻¹ V y` of a cycle after `k_used` steps: back substitution
/// for the Krylov coefficients `y` in the rotated Hessenberg system.
fn krylov_update(
    h: &[Vec<f64>],
    g: &[f64],
    basis: &[Vec<f64>],
    k_used: usize,
    precondition: &dyn Fn(&mut [f64]),
) -> Vec<f64> {
    let mut y = vec![0.0; k_used];
    for i in (0..k_used).rev() {
        let s: f64 = (i + 1..k_used).map(|j| h[i][j] * y[j]).sum();
        y[i] = (g[i] - s) / h[i][i];
    }
    let mut update = vec![0.0; basis[0].len()];
    for (j, yj) in y.iter().enumerate() {
        update
            .iter_mut()
            .zip(&basis[j])
            .for_each(|(u, v)| *u += yj * v);
    }
    precondition(&mut update);
    update
}

#[cfg(test)]
mod tests {
    use super::gmres;

    /// A non-symmetric tridiagonal system, solved without and with a
    /// (diagonal) preconditioner; the answer satisfies the system.
    #[test]
    fn solves_a_nonsymmetric_system() {
        let n = 200;
        let apply = |v: &[f64]| -> Vec<f64> {
            (0..n)
                .map(|i| {
                    4.0 * v[i]
                        - if i > 0 { 1.5 * v[i - 1] } else { 0.0 }
                        - if i + 1 < n { 0.5 * v[i + 1] } else { 0.0 }
                })
                .collect()
        };
        let b: Vec<f64> = (0..n).map(|i| (i as f64 * 0.1).cos()).collect();
        for scale in [1.0, 0.25] {
            let mut x = vec![0.0; n];
            let report = gmres(
                &apply,
                &|v: &mut [f64]| v.iter_mut().for_each(|a| *a *= scale),
                &b,
                &mut x,
                1e-12,
                10,
                500,
            );
            assert!(report.converged);
            let r = apply(&x);
            let err = r
                .iter()
                .zip(&b)
                .map(|(a, c)| (a - c).powi(2))
                .sum::<f64>()
                .sqrt();
            assert!(err < 1e-10, "residual {err}");
        }
    }

    /// A product with a relative error of ~1e-9 (a stand-in for round-off in an
    /// ill-conditioned product) puts a floor under the true residual; with a
    /// tolerance below that floor GMRES must stop as stagnated after a few
    /// restarts instead of spending its whole budget.
    #[test]
    fn stops_at_the_round_off_floor() {
        let n = 100;
        let calls = std::cell::Cell::new(0u64);
        let apply = |v: &[f64]| -> Vec<f64> {
            calls.set(calls.get() + 1);
            let c = calls.get();
            (0..n)
                .map(|i| {
                    let exact = 3.0 * v[i] - if i > 0 { v[i - 1] } else { 0.0 };
                    let noise = (((i as u64 + 7) * (c + 13)) % 97) as f64 / 97.0 - 0.5;
                    exact * (1.0 + 2e-9 * noise)
                })
                .collect()
        };
        let b: Vec<f64> = (0..n).map(|i| 1.0 + (i % 3) as f64).collect();
        let mut x = vec![0.0; n];
        let report = gmres(&apply, &|_: &mut [f64]| {}, &b, &mut x, 1e-15, 10, 10_000);
        assert!(report.stagnated && !report.converged, "{report:?}");
        assert!(report.relative_residual < 1e-7, "{report:?}");
        assert!(report.iterations < 200, "{report:?}");
    }
}
