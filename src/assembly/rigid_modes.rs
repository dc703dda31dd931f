//! Detection of rigid motions left free by the prescribed displacements.
//!
//! Each connected body (points linked by intact bonds) has `d(d+1)/2` rigid
//! motions, `u(x) = t + ω × (x − c)` (in 1D only the translation). They are all
//! removed exactly when no non-zero combination vanishes on every prescribed
//! component, i.e. when the Gram matrix `G_kl = Σ_{prescribed (i,c)} φ_k(x_i)_c φ_l(x_i)_c`
//! of the rigid basis `φ_k` is non-singular. A singular `G` means the stiffness
//! matrix is singular whatever the material: the run stops and the free motion
//! is named (its null vector, as a translation direction or a rotation axis
//! through a point), before any factorisation.

use super::dofs::{DofMap, PRESCRIBED};
use crate::discretization::Discretization;
use crate::error::NumericalError;
use crate::processes::Processes;

/// Errors if a connected body can move rigidly without changing any
/// prescribed value. A body discretised over `processes` (each holding some
/// families) has its bodies found together ([`shared_bodies`]).
pub fn check(
    disc: &Discretization,
    dofs: &DofMap,
    processes: Option<&dyn Processes>,
) -> Result<(), NumericalError> {
    let bodies = match processes {
        Some(processes) if disc.partial_share().is_some() => shared_bodies(disc, processes),
        _ => bodies(disc),
    };
    for points in bodies {
        check_body(disc, dofs, &points)?;
    }
    Ok(())
}

/// The connected bodies (points linked by intact bonds) that some rigid motion
/// moves without changing any prescribed value, each as its points.
pub fn unheld_bodies(disc: &Discretization, dofs: &DofMap) -> Vec<Vec<usize>> {
    bodies(disc)
        .into_iter()
        .filter(|points| check_body(disc, dofs, points).is_err())
        .collect()
}

/// The connected components of the intact-bond graph.
fn bodies(disc: &Discretization) -> Vec<Vec<usize>> {
    let mut roots = local_roots(disc);
    let n = disc.points.len();
    let root: Vec<usize> = (0..n).map(|i| find(&mut roots, i)).collect();
    // Labelled by their least point, as [`shared_bodies`] labels them, so
    // that one process and several name the same body first.
    let mut least = vec![usize::MAX; n];
    for i in 0..n {
        least[root[i]] = least[root[i]].min(i);
    }
    group(&root.iter().map(|&r| least[r]).collect::<Vec<_>>())
}

/// The connected components of the intact-bond graph of a body whose
/// families are spread over `processes` (a collective call): every bond is
/// held by the process of its owner, so the union of the processes' graphs is
/// the body's. Each process labels every point with the least point of its
/// component among the bonds it holds; the processes take the least label of
/// every point and relabel each local component by its least member's label,
/// until no label changes (as often as a component crosses processes, plus one).
fn shared_bodies(disc: &Discretization, processes: &dyn Processes) -> Vec<Vec<usize>> {
    let n = disc.points.len();
    let mut roots = local_roots(disc);
    let root: Vec<usize> = (0..n).map(|i| find(&mut roots, i)).collect();
    let mut label: Vec<f64> = (0..n).map(|i| i as f64).collect();
    loop {
        processes.min(&mut label);
        let mut least = vec![f64::INFINITY; n];
        for i in 0..n {
            least[root[i]] = least[root[i]].min(label[i]);
        }
        let mut changed = [0.0];
        for i in 0..n {
            if least[root[i]] < label[i] {
                label[i] = least[root[i]];
                changed[0] += 1.0;
            }
        }
        processes.sum(&mut changed);
        if changed[0] == 0.0 {
            break;
        }
    }
    // Labels are point indices, exact in a double.
    group(&label.iter().map(|&l| l as usize).collect::<Vec<_>>())
}

/// The union-find forest of the intact bonds this process holds.
fn local_roots(disc: &Discretization) -> Vec<usize> {
    let n = disc.points.len();
    let mut parent: Vec<usize> = (0..n).collect();
    for i in 0..n {
        for b in disc.bonds.owned_by(i) {
            if disc.bonds.intact[b] {
                let (a, c) = (
                    find(&mut parent, i),
                    find(&mut parent, disc.bonds.neighbour[b] as usize),
                );
                parent[a] = c;
            }
        }
    }
    parent
}

/// The root of `i` in a union-find forest (halving the path).
fn find(parent: &mut [usize], mut i: usize) -> usize {
    while parent[i] != i {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    i
}

/// The points grouped by `label`, groups in order of their labels.
fn group(label: &[usize]) -> Vec<Vec<usize>> {
    let mut members: std::collections::BTreeMap<usize, Vec<usize>> = Default::default();
    for (i, &l) in label.iter().enumerate() {
        members.entry(l).or_default().push(i);
    }
    members.into_values().collect()
}

fn check_body(
    disc: &Discretization,
    dofs: &DofMap,
    points: &[usize],
) -> Result<(), NumericalError> {
    let d = disc.d;
    let x = &disc.points.x;
    let mut c = [0.0; 3];
    for &i in points {
        for a in 0..3 {
            c[a] += x[i][a] / points.len() as f64;
        }
    }
    let size = points
        .iter()
        .map(|&i| crate::vector::norm(&crate::vector::sub(&x[i], &c)))
        .fold(0.0, f64::max)
        .max(f64::MIN_POSITIVE);
    let modes = match d {
        1 => 1,
        2 => 3,
        _ => 6,
    };
    // φ_k(x)_comp for the basis: translations, then rotations about z (2D) or x, y, z (3D), scaled by the body size.
    let basis = |k: usize, p: &[f64; 3], comp: usize| -> f64 {
        if k < d {
            return f64::from(k == comp);
        }
        let r = [
            (p[0] - c[0]) / size,
            (p[1] - c[1]) / size,
            (p[2] - c[2]) / size,
        ];
        let axis = if d == 2 { 2 } else { k - d };
        let mut w = [0.0; 3];
        w[axis] = 1.0;
        crate::vector::cross(&w, &r)[comp]
    };
    let mut gram = [[0.0; 6]; 6];
    for &i in points {
        for comp in 0..d {
            if dofs.free_index[3 * i + comp] == PRESCRIBED {
                for k in 0..modes {
                    let pk = basis(k, &x[i], comp);
                    for l in 0..modes {
                        gram[k][l] += pk * basis(l, &x[i], comp);
                    }
                }
            }
        }
    }
    let (values, vectors) = symmetric_eigen(&gram, modes);
    let largest = values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let free: Vec<usize> = (0..modes)
        .filter(|&k| largest == 0.0 || values[k] <= 1e-10 * largest)
        .collect();
    if free.is_empty() {
        return Ok(());
    }
    let description: Vec<String> = free
        .iter()
        .map(|&k| describe(&vectors[k], d, &c, size))
        .collect();
    Err(NumericalError::RigidMotion {
        points: points.len(),
        first: points[0],
        position: x[points[0]],
        motions: description.join("; "),
    })
}

/// Names a rigid motion given by its basis coefficients.
fn describe(v: &[f64; 6], d: usize, c: &[f64; 3], size: f64) -> String {
    let fmt = |a: &[f64]| {
        a.iter()
            .map(|x| {
                let x = if x.abs() < 5e-4 { 0.0 } else { *x };
                // Directions are unit vectors; a centre of rotation far from the
                // origin (coordinates of 1e100 m) is shown in exponent form.
                if x.abs() < 1e6 {
                    format!("{x:.3}")
                } else {
                    format!("{x:.3e}")
                }
            })
            .collect::<Vec<_>>()
            .join(", ")
    };
    let t: Vec<f64> = v[..d].to_vec();
    match d {
        1 => "translation along x".into(),
        2 => {
            let w = v[2] / size;
            if v[2].abs() < 1e-6 {
                format!("translation along ({})", fmt(&t))
            } else {
                let p = [c[0] - t[1] / w, c[1] + t[0] / w];
                format!("rotation about z through ({})", fmt(&p))
            }
        }
        _ => {
            let w = [v[3] / size, v[4] / size, v[5] / size];
            let wn = crate::vector::norm(&w);
            if wn * size < 1e-6 {
                format!("translation along ({})", fmt(&t))
            } else {
                let tt = [t[0], t[1], t[2]];
                let shift = crate::vector::cross(&w, &tt);
                let p: Vec<f64> = (0..3).map(|a| c[a] + shift[a] / (wn * wn)).collect();
                format!(
                    "rotation about axis ({}) through ({})",
                    fmt(&w.map(|x| x / wn)),
                    fmt(&p)
                )
            }
        }
    }
}

/// Eigenvalues and eigenvectors (rows of the second result) of the leading
/// `m × m` block of a symmetric matrix (nalgebra's symmetric eigensolver).
fn symmetric_eigen(a: &[[f64; 6]; 6], m: usize) -> ([f64; 6], [[f64; 6]; 6]) {
    let eigen = nalgebra::DMatrix::from_fn(m, m, |r, c| a[r][c]).symmetric_eigen();
    let mut values = [0.0; 6];
    let mut vectors = [[0.0; 6]; 6];
    for k in 0..m {
        values[k] = eigen.eigenvalues[k];
        for r in 0..m {
            vectors[k][r] = eigen.eigenvectors[(r, k)];
        }
    }
    (values, vectors)
}

#[cfg(test)]
mod tests {
    use super::symmetric_eigen;

    #[test]
    fn eigenpairs_of_a_symmetric_matrix() {
        let mut a = [[0.0; 6]; 6];
        let m = [[4.0, 1.0, 0.5], [1.0, 3.0, 0.2], [0.5, 0.2, 1.0]];
        for r in 0..3 {
            a[r][..3].copy_from_slice(&m[r]);
        }
        let (values, vectors) = symmetric_eigen(&a, 3);
        for k in 0..3 {
            for r in 0..3 {
                let av: f64 = (0..3).map(|c| m[r][c] * vectors[k][c]).sum();
                assert!((av - values[k] * vectors[k][r]).abs() < 1e-12);
            }
        }
    }
}
