//! The reduced system `K u = f` in Matrix Market format (`K.mtx` via sprs, `f.mtx` as an array).

use crate::drivers::static_solve::LinearSystem;
use crate::error::Error;
use std::fmt::Write;
use std::path::Path;

/// Writes `K.mtx` and `f.mtx` into `dir`.
pub fn write(dir: &Path, system: &LinearSystem) -> Result<(), Error> {
    let n = system.stiffness.n;
    let k = sprs::CsMat::new_csc(
        (n, n),
        system.pattern.col_ptr.clone(),
        system.pattern.row_idx.clone(),
        system.stiffness.values.clone(),
    );
    let path = dir.join("K.mtx");
    sprs::io::write_matrix_market(&path, &k).map_err(|e| Error::io(&path, e))?;
    let mut t = format!("%%MatrixMarket matrix array real general\n{n} 1\n");
    for v in &system.rhs {
        let _ = writeln!(t, "{v:e}");
    }
    super::write_file(&dir.join("f.mtx"), &t)
}
