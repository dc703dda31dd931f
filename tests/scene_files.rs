//! Every scene file shipped with the reports stays valid (issue 10, "scene files
//! for every validation case"):
//!
//! - the generated ones (`dhpd::validation::scenes`) equal what the generators,
//!   which the tests and examples solve, write today;
//! - every `.toml` under `validation/` passes `dhpd check` (the scene, its point
//!   files and meshes, the selections and supports: everything short of
//!   assembling the stiffness).

use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn generated_scene_files_are_current() {
    for file in dhpd::validation::scenes::catalogue() {
        let committed = std::fs::read_to_string(root().join(&file.path)).unwrap_or_else(|e| {
            panic!(
                "{}: {e}; run `cargo run --release --example write_scenes`",
                file.path
            )
        });
        assert!(
            committed == file.text,
            "{} differs from its generator; run `cargo run --release --example write_scenes`",
            file.path
        );
    }
}

fn scene_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap().flatten() {
        let path = entry.path();
        if path.is_dir() {
            // Study scratch folders are not shipped.
            if path.file_name().is_some_and(|n| n != "work") {
                scene_files(&path, out);
            }
        } else if path.extension().is_some_and(|e| e == "toml") {
            out.push(path);
        }
    }
}

#[test]
fn every_validation_scene_passes_check() {
    let mut files = Vec::new();
    scene_files(&root().join("validation"), &mut files);
    files.sort();
    assert!(files.len() > 100, "{} scene files found", files.len());
    let mut failures = Vec::new();
    for path in &files {
        let out = Command::new(env!("CARGO_BIN_EXE_dhpd"))
            .arg("check")
            .arg(path)
            .output()
            .expect("run dhpd check");
        if !out.status.success() {
            failures.push(format!(
                "{}: {}",
                path.display(),
                String::from_utf8_lossy(&out.stderr).trim()
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
