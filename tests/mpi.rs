//! MPI runs through PETSc (`solver.method = "petsc"`, the `mpi` feature):
//! every static scene of `tests/mpi/scenes` solved on 1, 2 and 3 processes
//! (oversubscribed on a 2-core machine) gives the displacement of the default
//! single-process route (Cholesky, or GMRES for the shear model) to 1e-8 of
//! max|u| at every point, every fracture scene breaks the same bonds at the
//! same load factors, and rank 0 alone writes the results.
//!
//! `cargo test --profile ci --features mpi --test mpi` (needs `mpirun` on
//! PATH: Debian's `petsc-dev` brings Open MPI).
#![cfg(feature = "mpi")]

use std::path::{Path, PathBuf};
use std::process::Command;

/// Largest difference from the single-process answer, relative to its max|u|.
const AGREEMENT: f64 = 1e-8;

/// Seconds after which `mpirun` kills a run (each takes a few): processes
/// that disagree on a collective call wait for each other forever, and the
/// test should fail rather than hang.
const MPI_TIMEOUT: &str = "300";

/// The scenes, each small enough to solve in about a second.
const SCENES: [&str; 5] = [
    "plate_hole",
    "plate_hole_fine",
    "cracked_plate",
    "block3d",
    "shear_hole",
];

fn scene_path(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("tests/mpi/scenes/{name}.toml"))
}

/// Runs `dhpd run scene --out out`, on `processes` MPI processes when given.
fn run(scene: &Path, out: &Path, processes: Option<usize>) {
    let dhpd = env!("CARGO_BIN_EXE_dhpd");
    let mut command = match processes {
        Some(n) => {
            let mut c = Command::new("mpirun");
            c.args([
                "--allow-run-as-root",
                "--oversubscribe",
                "--bind-to",
                "none",
                "--timeout",
                MPI_TIMEOUT,
            ])
            .args(["-np", &n.to_string(), dhpd]);
            c
        }
        None => Command::new(dhpd),
    };
    // One thread per process: up to three processes share two cores.
    let output = command
        .env("RAYON_NUM_THREADS", "1")
        .arg("run")
        .arg(scene)
        .arg("--out")
        .arg(out)
        .output()
        .expect("mpirun and dhpd start");
    assert!(
        output.status.success(),
        "{} on {processes:?} processes failed:\n{}\n{}",
        scene.display(),
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
}

/// The displacement of every point, from `points.csv` (the `u_*` columns).
fn displacements(out: &Path) -> Vec<Vec<f64>> {
    point_columns(out, |name| name.starts_with("u_"))
}

/// The columns of `points.csv` whose names `wanted` picks, per point.
fn point_columns(out: &Path, wanted: impl Fn(&str) -> bool) -> Vec<Vec<f64>> {
    let text = std::fs::read_to_string(out.join("points.csv")).expect("points.csv");
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().expect("a header").split(',').collect();
    let columns: Vec<usize> = (0..header.len()).filter(|&c| wanted(header[c])).collect();
    lines
        .map(|line| {
            let fields: Vec<&str> = line.split(',').collect();
            columns
                .iter()
                .map(|&c| fields[c].parse().expect("a number"))
                .collect()
        })
        .collect()
}

/// Runs the scene `name` with the default single-process route (its
/// `method = "petsc"` removed) into `dir`; returns the output directory.
fn run_reference(dir: &Path, name: &str) -> PathBuf {
    let text = std::fs::read_to_string(scene_path(name)).unwrap();
    let reference_scene = dir.join(format!("{name}_reference.toml"));
    std::fs::write(&reference_scene, text.replace("method = \"petsc\"", "")).unwrap();
    let reference_out = dir.join(format!("{name}_reference"));
    run(&reference_scene, &reference_out, None);
    reference_out
}

fn summary(out: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(out.join("summary.json")).expect("summary.json");
    serde_json::from_str(&text).expect("JSON")
}

#[test]
fn petsc_on_one_two_and_three_processes_matches_the_single_process_solve() {
    let dir = std::env::temp_dir().join(format!("dhpd-mpi-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut failures = Vec::new();
    for name in SCENES {
        let scene = scene_path(name);
        // The reference: the same scene with the default route.
        let reference_out = run_reference(&dir, name);
        let reference = displacements(&reference_out);
        let reference_counts = summary(&reference_out)["counts"].clone();
        for processes in [1, 2, 3] {
            let out = dir.join(format!("{name}_np{processes}"));
            run(&scene, &out, Some(processes));
            let (difference, max_u) = difference(&displacements(&out), &reference);
            assert!(max_u > 0.0, "{name}: the reference moves");
            let s = summary(&out);
            let petsc = &s["counts"]["petsc"];
            eprintln!(
                "{name} on {processes} process(es): {} {} {} iterations, residual {:.1e}, \
                 max difference {:.1e} of max|u| = {max_u:.4e}",
                petsc["ksp"],
                petsc["pc"],
                petsc["iterations"],
                s["relative_residual"].as_f64().unwrap_or(f64::NAN),
                difference / max_u
            );
            assert_eq!(petsc["processes"], processes, "{name}: processes reported");
            // Recursive bisection cuts each part within one point's entries of
            // its share (a point holds < 1 % of a part's here): balanced to 5 %.
            let entries: Vec<f64> = petsc["entries_per_process"]
                .as_array()
                .expect("entries per process")
                .iter()
                .map(|e| e.as_f64().expect("a count"))
                .collect();
            let mean = entries.iter().sum::<f64>() / processes as f64;
            assert!(
                entries.len() == processes
                    && entries.iter().all(|&e| (e - mean).abs() <= 0.05 * mean),
                "{name} on {processes} process(es): unbalanced parts {entries:?}"
            );
            // Each process assembles its own columns and its ghosts': together
            // they are the single-process K, entry for entry.
            let counts = &s["counts"];
            assert_eq!(
                counts["nnz_k"], reference_counts["nnz_k"],
                "{name} on {processes} process(es): stored entries of K"
            );
            let asymmetry = |c: &serde_json::Value| c["asymmetry"].as_f64().expect("asymmetry");
            // The same squares summed in another order: the sums of N < 1e6
            // positive terms agree to N ε ≈ 1e-10 relative.
            let (a, b) = (asymmetry(counts), asymmetry(&reference_counts));
            assert!(
                (a - b).abs() <= 1e-10 * b.abs(),
                "{name} on {processes} process(es): asymmetry {a:e} against {b:e}"
            );
            if !(difference <= AGREEMENT * max_u) {
                failures.push(format!(
                    "{name} on {processes} process(es): differs by {:.2e} of max|u|",
                    difference / max_u
                ));
            }
            // Each process searched only the bonds its part needs; the
            // whole body's counts, bonds per point, stresses and reactions
            // are summed from the processes' own points.
            failures.extend(same_answers_from_shares(
                &format!("{name} on {processes} process(es)"),
                (&out, &s),
                (&reference_out, &summary(&reference_out)),
                processes,
            ));
        }
    }
    std::fs::remove_dir_all(&dir).ok();
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// What differs between a run discretised over `processes` and the
/// single-process reference, beyond the displacement: the count of bonds
/// (exactly), each point's count of bonds (exactly), the stresses where the
/// scene asks for them and the reactions (to [`AGREEMENT`] of their largest:
/// linear in the answer); and the bonds each process held: on several
/// processes each fewer than the body's (the bodies here are a few
/// horizons longer than a part's ghost layers), together at least all.
fn same_answers_from_shares(
    run: &str,
    (out, s): (&Path, &serde_json::Value),
    (reference_out, reference): (&Path, &serde_json::Value),
    processes: usize,
) -> Vec<String> {
    let mut failures = Vec::new();
    let bonds = reference["counts"]["bonds"].as_u64().expect("bonds");
    if s["counts"]["bonds"].as_u64() != Some(bonds) {
        failures.push(format!(
            "{run}: {} bonds, not {bonds}",
            s["counts"]["bonds"]
        ));
    }
    let held: Vec<u64> = s["counts"]["bonds_held"]
        .as_array()
        .map(|a| a.iter().filter_map(|b| b.as_u64()).collect())
        .unwrap_or_default();
    let shared = held.len() == processes
        && held.iter().all(|&h| h < bonds)
        && held.iter().sum::<u64>() >= bonds;
    if processes > 1 && !shared {
        failures.push(format!("{run}: bonds held {held:?} of {bonds}"));
    }
    let counts = |o: &Path| point_columns(o, |c| c == "bond_count");
    if counts(out) != counts(reference_out) {
        failures.push(format!("{run}: the bonds per point differ"));
    }
    let is_stress = |c: &str| matches!(c, "sxx" | "syy" | "szz" | "syz" | "sxz" | "sxy");
    let (stress, expected) = (
        point_columns(out, is_stress),
        point_columns(reference_out, is_stress),
    );
    let (largest_difference, largest) = difference(&stress, &expected);
    if !(largest_difference <= AGREEMENT * largest) {
        failures.push(format!(
            "{run}: stress differs by {largest_difference:e} of {largest:e}"
        ));
    }
    let forces = |v: &serde_json::Value| -> Vec<Vec<f64>> {
        v["reactions"]
            .as_array()
            .expect("reactions")
            .iter()
            .map(|r| {
                r["force"]
                    .as_array()
                    .expect("a force")
                    .iter()
                    .map(|f| f.as_f64().expect("a number"))
                    .collect()
            })
            .collect()
    };
    let (largest_difference, largest) = difference(&forces(s), &forces(reference));
    if !(largest > 0.0 && largest_difference <= AGREEMENT * largest) {
        failures.push(format!(
            "{run}: reactions differ by {largest_difference:e} of {largest:e}"
        ));
    }
    failures
}

/// The largest difference between two displacement fields, and the largest
/// displacement of the second.
fn difference(u: &[Vec<f64>], reference: &[Vec<f64>]) -> (f64, f64) {
    assert_eq!(u.len(), reference.len(), "the same points");
    let max_u = reference
        .iter()
        .map(|u| u.iter().map(|v| v * v).sum::<f64>().sqrt())
        .fold(0.0, f64::max);
    let largest = u
        .iter()
        .zip(reference)
        .flat_map(|(a, b)| a.iter().zip(b).map(|(x, y)| (x - y).abs()))
        .fold(0.0, f64::max);
    (largest, max_u)
}

#[test]
fn mumps_on_one_and_two_processes_matches_the_single_process_solve() {
    let dir = std::env::temp_dir().join(format!("dhpd-mpi-mumps-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // Partial constraints (identity rows) and a non-symmetric K.
    for name in ["plate_hole", "shear_hole"] {
        let text = std::fs::read_to_string(scene_path(name)).unwrap();
        let reference = displacements(&run_reference(&dir, name));
        let scene = dir.join(format!("{name}_mumps.toml"));
        let mumps = "method = \"petsc\"\npetsc_solver = \"mumps\"";
        std::fs::write(&scene, text.replace("method = \"petsc\"", mumps)).unwrap();
        for processes in [1, 2] {
            let out = dir.join(format!("{name}_mumps_np{processes}"));
            run(&scene, &out, Some(processes));
            let (difference, max_u) = difference(&displacements(&out), &reference);
            let s = summary(&out);
            let petsc = &s["counts"]["petsc"];
            eprintln!(
                "{name} by MUMPS on {processes} process(es): {} {}, residual {:.1e}, max \
                 difference {:.1e} of max|u|",
                petsc["ksp"],
                petsc["pc"],
                s["relative_residual"].as_f64().unwrap_or(f64::NAN),
                difference / max_u
            );
            assert_eq!(petsc["pc"], "lu", "{name}: PETSc's LU");
            assert!(
                difference <= AGREEMENT * max_u,
                "{name} by MUMPS on {processes} process(es): differs by {:.2e} of max|u|",
                difference / max_u
            );
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// The quasi-static fracture scenes, each a few seconds to separation (the
/// last frees a piece, which the driver holds: pinned rows in PETSc).
const FRACTURE_SCENES: [&str; 4] = [
    "sent_event",
    "sent_all",
    "sent_shear_event",
    "bar_free_piece",
];

/// Explicit dynamics on several processes: a pulse in a free plate (the
/// shear model's owner kernels, and its linearised kernel `F = −K u`),
/// dynamic mode I fracture (bond-based pairs, 2,700 bonds break) and a
/// shear-model strip breaking in compression.
const DYNAMICS_SCENES: [&str; 4] = [
    "dynamics_wave_shear",
    "dynamics_wave_linearised",
    "dynamics_mode_one",
    "dynamics_shear_compression",
];

/// Agreement of an explicit run on several processes with one: the forces
/// on a point are the same bond terms summed in another order, so the runs
/// differ by round-off (1e-16 per step, growing at most with the 150-390
/// steps here): 1e-10 of the largest value leaves room and still fails on
/// any missing or stale ghost displacement (a whole bond force).
const DYNAMICS_AGREEMENT: f64 = 1e-10;

/// Verlet on 1, 2 and 3 processes, each stepping its own points and
/// receiving its ghosts' displacements before every force evaluation,
/// against the default single-process run: every point's displacement and
/// velocity, every probe value and every record's energies, works and
/// reactions to [`DYNAMICS_AGREEMENT`] of their largest; the bonds broken at
/// every record, each point's damage and count of bonds exactly; on several
/// processes each held fewer bonds than the body.
#[test]
fn verlet_on_one_two_and_three_processes_matches_the_single_process_run() {
    let dir = std::env::temp_dir().join(format!("dhpd-mpi-dynamics-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut failures = Vec::new();
    for name in DYNAMICS_SCENES {
        let reference_out = run_reference(&dir, name);
        let reference_history = rows(&reference_out, "history.csv");
        for processes in [1, 2, 3] {
            let run_name = format!("{name} on {processes} process(es)");
            let out = dir.join(format!("{name}_np{processes}"));
            run(&scene_path(name), &out, Some(processes));
            let s = summary(&out);
            let reference_summary = summary(&reference_out);
            let bonds = reference_summary["bonds"].as_u64().expect("bonds");
            assert_eq!(s["bonds"], bonds, "{run_name}: bonds");
            if processes > 1 {
                let held: Vec<u64> = s["bonds_held"]
                    .as_array()
                    .map(|a| a.iter().filter_map(|b| b.as_u64()).collect())
                    .unwrap_or_default();
                assert!(
                    held.len() == processes && held.iter().all(|&h| h < bonds),
                    "{run_name}: bonds held {held:?} of {bonds}"
                );
            }
            let state = |o: &Path| point_columns(o, |c| c.starts_with("u_") || c.starts_with("v_"));
            let (d, largest) = difference(&state(&out), &state(&reference_out));
            if !(largest > 0.0 && d <= DYNAMICS_AGREEMENT * largest) {
                failures.push(format!(
                    "{run_name}: the state differs by {d:e} of {largest:e}"
                ));
            }
            let exact = |o: &Path| point_columns(o, |c| c == "damage" || c == "bond_count");
            if exact(&out) != exact(&reference_out) {
                failures.push(format!("{run_name}: damage or bonds per point differ"));
            }
            let history = rows(&out, "history.csv");
            if history.len() != reference_history.len() {
                failures.push(format!("{run_name}: {} records", history.len()));
                continue;
            }
            for column in reference_history[0].keys() {
                let values = |h: &[std::collections::HashMap<String, String>]| -> Vec<Vec<f64>> {
                    h.iter()
                        .map(|r| vec![r[column].parse().expect("a number")])
                        .collect()
                };
                let (d, largest) = difference(&values(&history), &values(&reference_history));
                let exactly = matches!(column.as_str(), "step" | "broken_bonds");
                // The balance error is a difference of energies: its round-off
                // is that of the energies.
                let scale = match column.as_str() {
                    "balance_error" => 1.0,
                    _ => largest,
                };
                if (exactly && d != 0.0) || !(d <= DYNAMICS_AGREEMENT * scale) {
                    failures.push(format!(
                        "{run_name}: {column} differs by {d:e} of {largest:e}"
                    ));
                }
            }
            if reference_out.join("probes.csv").exists() {
                let probes = |o: &Path| -> Vec<Vec<f64>> {
                    rows(o, "probes.csv")
                        .iter()
                        .map(|r| {
                            let mut columns: Vec<_> = r.iter().collect();
                            columns.sort();
                            columns
                                .into_iter()
                                .map(|(_, v)| v.parse().expect("a number"))
                                .collect()
                        })
                        .collect()
                };
                let (d, largest) = difference(&probes(&out), &probes(&reference_out));
                if !(largest > 0.0 && d <= DYNAMICS_AGREEMENT * largest) {
                    failures.push(format!("{run_name}: probes differ by {d:e} of {largest:e}"));
                }
            }
        }
    }
    std::fs::remove_dir_all(&dir).ok();
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The rows of `load_displacement.csv`, each a map from column to field.
fn records(out: &Path) -> Vec<std::collections::HashMap<String, String>> {
    rows(out, "load_displacement.csv")
}

/// The rows of the CSV file `file` in `out`, each a map from column to field.
fn rows(out: &Path, file: &str) -> Vec<std::collections::HashMap<String, String>> {
    let text = std::fs::read_to_string(out.join(file)).expect(file);
    let mut lines = text.lines();
    let header: Vec<String> = lines
        .next()
        .expect("a header")
        .split(',')
        .map(String::from)
        .collect();
    lines
        .map(|line| {
            header
                .iter()
                .cloned()
                .zip(line.split(',').map(String::from))
                .collect()
        })
        .collect()
}

/// Quasi-static fracture on PETSc: on 1, 2 and 3 processes the same bonds
/// break at the same load factors as on the default single-process route
/// (Cholesky with exact factor updates, or GMRES with the surrogate), record
/// for record, with every reaction within 1e-8 of the peak and every load
/// factor within 1e-8 of itself (the solves reach relative residuals of
/// 1e-12; the ratios and reactions are linear in the answer). The last
/// record, the separation, has the same step and state; its count of bonds
/// may be smaller on PETSc: a factorisation names a point that became a
/// mechanism and the driver breaks its last bonds, which PETSc's Krylov
/// method, converging on the rest, does not report.
#[test]
fn petsc_fracture_breaks_the_same_bonds_on_one_two_and_three_processes() {
    let dir = std::env::temp_dir().join(format!("dhpd-mpi-fracture-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut failures = Vec::new();
    for name in FRACTURE_SCENES {
        let scene = scene_path(name);
        let reference_out = run_reference(&dir, name);
        let reference = records(&reference_out);
        let reference_outcome = summary(&reference_out)["outcome"].clone();
        let number = |r: &std::collections::HashMap<String, String>, key: &str| -> f64 {
            r[key].parse().expect("a number")
        };
        let reaction_columns: Vec<String> = reference[0]
            .keys()
            .filter(|k| k.starts_with("reaction_"))
            .cloned()
            .collect();
        let peak = reference
            .iter()
            .flat_map(|r| reaction_columns.iter().map(|k| number(r, k).abs()))
            .fold(0.0, f64::max);
        assert!(
            peak > 0.0 && reference.len() > 10,
            "{name}: the reference breaks"
        );
        for processes in [1, 2, 3] {
            let out = dir.join(format!("{name}_np{processes}"));
            run(&scene, &out, Some(processes));
            let s = summary(&out);
            assert_eq!(s["counts"]["solver"], "petsc", "{name}: PETSc solved");
            assert_eq!(s["counts"]["petsc"]["processes"], processes, "{name}");
            assert_eq!(
                s["outcome"], reference_outcome,
                "{name} on {processes}: outcome"
            );
            let rows = records(&out);
            assert_eq!(
                rows.len(),
                reference.len(),
                "{name} on {processes}: records"
            );
            let (mut reaction_error, mut load_error) = (0.0f64, 0.0f64);
            let last = rows.len() - 1;
            for (k, (row, expected)) in rows.iter().zip(&reference).enumerate() {
                let same = ["step", "state"]
                    .iter()
                    .all(|key| row[*key] == expected[*key])
                    && (k == last || row["broken_total"] == expected["broken_total"]);
                if !same {
                    failures.push(format!(
                        "{name} on {processes}: record {k} is step {} {} with {} bonds broken, \
                         the reference's step {} {} with {}",
                        row["step"],
                        row["state"],
                        row["broken_total"],
                        expected["step"],
                        expected["state"],
                        expected["broken_total"]
                    ));
                    break;
                }
                let lambda = number(expected, "load_factor");
                load_error = load_error
                    .max((number(row, "load_factor") - lambda).abs() / lambda.max(1e-300));
                for key in &reaction_columns {
                    let error = (number(row, key) - number(expected, key)).abs();
                    reaction_error = reaction_error.max(error / peak);
                }
            }
            let broken = |r: &std::collections::HashMap<String, String>| number(r, "broken_total");
            eprintln!(
                "{name} on {processes} process(es): {} records, largest reaction difference \
                 {reaction_error:.1e} of the peak, load factor {load_error:.1e}; bonds broken \
                 {} (reference {}), {} re-solves",
                rows.len(),
                broken(&rows[last]),
                broken(&reference[last]),
                s["reuses"]["count"]
            );
            assert!(
                broken(&rows[last]) <= broken(&reference[last]),
                "{name}: no extra bonds"
            );
            if !(reaction_error <= AGREEMENT && load_error <= AGREEMENT) {
                failures.push(format!(
                    "{name} on {processes} process(es): reactions differ by {reaction_error:.2e} \
                     of the peak, load factors by {load_error:.2e}"
                ));
            }
        }
    }
    std::fs::remove_dir_all(&dir).ok();
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The values of the ASCII data array `name` in the VTU text `vtu`.
fn vtu_array(vtu: &str, name: &str) -> Vec<f64> {
    let start = vtu
        .find(&format!("Name=\"{name}\""))
        .unwrap_or_else(|| panic!("array {name}"));
    let body = &vtu[start..];
    let body = &body[body.find('>').expect("tag") + 1..body.find("</DataArray>").expect("end")];
    body.split_whitespace()
        .map(|v| v.parse().expect("a number"))
        .collect()
}

#[test]
fn every_process_writes_its_piece_of_the_parallel_vtk_file() {
    let dir = std::env::temp_dir().join(format!("dhpd-mpi-pvtu-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let text = std::fs::read_to_string(scene_path("plate_hole")).unwrap();
    let scene = dir.join("plate_hole.toml");
    std::fs::write(&scene, text.replace("vtu = false", "vtu = true")).unwrap();
    let one = dir.join("one");
    run(&scene, &one, Some(1));
    let three = dir.join("three");
    run(&scene, &three, Some(3));
    let read = |path: &Path| std::fs::read_to_string(path).unwrap_or_default();
    let whole = read(&one.join("points.vtu"));
    let parallel = read(&three.join("points.pvtu"));
    let single_written_too = three.join("points.vtu").exists();
    let pieces: Vec<String> = (0..3)
        .map(|k| read(&three.join(format!("points_{k}.vtu"))))
        .collect();
    std::fs::remove_dir_all(&dir).ok();
    assert!(!single_written_too, "points.pvtu replaces points.vtu");
    for k in 0..3 {
        assert!(
            parallel.contains(&format!("<Piece Source=\"points_{k}.vtu\"/>")),
            "{parallel}"
        );
    }
    assert!(parallel.contains("Name=\"displacement\" NumberOfComponents=\"3\""));
    // The pieces, in order, are the single-process file's points and values.
    for name in ["points", "displacement", "volume", "bond_count"] {
        let expected = vtu_array(&whole, name);
        let joined: Vec<f64> = pieces.iter().flat_map(|p| vtu_array(p, name)).collect();
        assert_eq!(joined.len(), expected.len(), "{name}: every point once");
        let scale = expected.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let difference = joined
            .iter()
            .zip(&expected)
            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        assert!(
            difference <= AGREEMENT * scale,
            "{name}: pieces differ by {difference:e} (scale {scale:e})"
        );
    }
    assert!(pieces.iter().all(|p| !vtu_array(p, "volume").is_empty()));
}

/// `scene` run by `mpirun -np 2`: its exit status and standard error.
fn run_on_two(scene: &Path, out: &Path) -> (bool, String) {
    run_on(2, scene, out)
}

/// Runs `scene` on `processes` processes (1: without mpirun); whether it
/// succeeded, and what it printed on stderr.
fn run_on(processes: usize, scene: &Path, out: &Path) -> (bool, String) {
    let dhpd = env!("CARGO_BIN_EXE_dhpd");
    let mut command = Command::new(if processes == 1 { dhpd } else { "mpirun" });
    if processes > 1 {
        command
            .args([
                "--allow-run-as-root",
                "--oversubscribe",
                "--bind-to",
                "none",
                "--timeout",
                MPI_TIMEOUT,
            ])
            .args(["-np", &processes.to_string(), dhpd]);
    }
    let output = command
        .env("RAYON_NUM_THREADS", "1")
        .arg("run")
        .arg(scene)
        .arg("--out")
        .arg(out)
        .output()
        .expect("mpirun and dhpd start");
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    (output.status.success(), stderr)
}

/// The decisions that need the whole body, made together by processes that
/// each hold a share of its bonds (`unheld_piece`: a held bar, a piece more
/// than a horizon away and a lone point): the lone point is removed with the
/// warning, and the piece the supports leave free is named, as on one
/// process; with the piece held, the same answer as on one process.
#[test]
fn processes_sharing_the_bonds_find_isolated_points_and_free_bodies_together() {
    let dir = std::env::temp_dir().join(format!("dhpd-mpi-bodies-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let scene = scene_path("unheld_piece");
    let named = |stderr: &str| -> String {
        let at = stderr
            .find("the body of")
            .unwrap_or_else(|| panic!("no free body named:\n{stderr}"));
        stderr[at..].lines().next().unwrap_or_default().to_string()
    };
    let removed = "warning: removing 1 point(s) without any bond (first at [1.81, 0.01, 0.0])";
    let (success, single) = run_on(1, &scene, &dir.join("free_np1"));
    assert!(!success && single.contains(removed), "{single}");
    for processes in [2, 3] {
        let out = dir.join(format!("free_np{processes}"));
        let (success, several) = run_on(processes, &scene, &out);
        assert!(!success, "{processes} processes: the free piece is refused");
        assert!(
            several.contains(removed),
            "{processes} processes:\n{several}"
        );
        assert_eq!(named(&several), named(&single), "{processes} processes");
        assert!(!out.exists(), "no half-written output");
    }
    let text = std::fs::read_to_string(&scene).unwrap();
    let held = dir.join("held.toml");
    std::fs::write(
        &held,
        text.replace("{ x = 1.0e-4 }", "{ x = 1.0e-4, y = 0.0 }"),
    )
    .unwrap();
    let reference_scene = dir.join("held_reference.toml");
    std::fs::write(
        &reference_scene,
        std::fs::read_to_string(&held)
            .unwrap()
            .replace("method = \"petsc\"", ""),
    )
    .unwrap();
    let reference_out = dir.join("held_reference");
    run(&reference_scene, &reference_out, None);
    let reference = displacements(&reference_out);
    for processes in [2, 3] {
        let out = dir.join(format!("held_np{processes}"));
        run(&held, &out, Some(processes));
        let (difference, max_u) = difference(&displacements(&out), &reference);
        assert!(
            max_u > 0.0 && difference <= AGREEMENT * max_u,
            "{processes} processes: differs by {difference:e} of {max_u:e}"
        );
        assert_eq!(summary(&out)["counts"]["removed_points"], 1);
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn several_processes_refuse_a_route_that_would_solve_on_each() {
    let dir = std::env::temp_dir().join(format!("dhpd-mpi-refuse-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let text = std::fs::read_to_string(scene_path("plate_hole")).unwrap();
    let scene = dir.join("cholesky.toml");
    std::fs::write(&scene, text.replace("\"petsc\"", "\"cholesky\"")).unwrap();
    let (success, stderr) = run_on_two(&scene, &dir.join("out"));
    assert!(!success);
    assert!(
        stderr.contains("solver.method: this run has 2 processes"),
        "{stderr}"
    );
    // No process holds all of K, so none can export it.
    let scene = dir.join("export.toml");
    std::fs::write(
        &scene,
        text.replace("vtu = false", "vtu = false\nmatrix_market = true"),
    )
    .unwrap();
    let (success, stderr) = run_on_two(&scene, &dir.join("export"));
    let written = dir.join("export").exists();
    std::fs::remove_dir_all(&dir).ok();
    assert!(!success);
    assert!(
        stderr.contains("output.matrix_market: this run has 2 processes"),
        "{stderr}"
    );
    assert!(!written, "no half-written output");
}
