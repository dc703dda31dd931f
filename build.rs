//! Links PETSc and MPI for the `mpi` feature, where pkg-config finds them
//! (`PETSc`, and Open MPI's `mpi`: Debian's `petsc-dev` installs both); does
//! nothing in the default build.

use std::process::Command;

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-env-changed=PKG_CONFIG_PATH");
    if std::env::var_os("CARGO_FEATURE_MPI").is_none() {
        return;
    }
    for package in ["PETSc", "mpi"] {
        let output = Command::new("pkg-config")
            .args(["--libs", package])
            .output()
            .unwrap_or_else(|e| panic!("the mpi feature needs pkg-config ({e})"));
        if !output.status.success() {
            panic!(
                "the mpi feature needs {package} known to pkg-config (Debian: apt-get install \
                 petsc-dev): {}",
                String::from_utf8_lossy(&output.stderr)
            );
        }
        for flag in String::from_utf8_lossy(&output.stdout).split_whitespace() {
            if let Some(dir) = flag.strip_prefix("-L") {
                println!("cargo:rustc-link-search=native={dir}");
            } else if let Some(lib) = flag.strip_prefix("-l") {
                println!("cargo:rustc-link-lib={lib}");
            }
        }
    }
}
