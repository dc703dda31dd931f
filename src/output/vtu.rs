//! A VTK unstructured-grid file (XML, ASCII) of the points as vertex cells, which
//! ParaView opens: displacement, volume, horizon, material, bond count, and the
//! stress and damage when present; and the `.pvd` collection that lists a
//! series of them by load factor.

use super::PointData;
use crate::error::Error;
use std::fmt::Write;
use std::path::Path;

/// Writes one VTU file of the points.
pub fn write(path: &Path, s: &PointData) -> Result<(), Error> {
    let p = &s.disc.points;
    let n = p.len();
    let bonds = s.disc.bonds.touch_counts(n);
    let mut t = String::with_capacity(n * 160);
    t.push_str("<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n<UnstructuredGrid>\n");
    let _ = writeln!(t, "<Piece NumberOfPoints=\"{n}\" NumberOfCells=\"{n}\">");
    t.push_str(
        "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n",
    );
    for x in &p.x {
        let _ = writeln!(t, "{:e} {:e} {:e}", x[0], x[1], x[2]);
    }
    t.push_str("</DataArray>\n</Points>\n<Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n");
    join_into(&mut t, 0..n);
    t.push_str("</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n");
    join_into(&mut t, 1..=n);
    t.push_str("</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n");
    join_into(&mut t, std::iter::repeat_n(1, n));
    t.push_str("</DataArray>\n</Cells>\n<PointData Vectors=\"displacement\">\n");
    t.push_str("<DataArray type=\"Float64\" Name=\"displacement\" NumberOfComponents=\"3\" format=\"ascii\">\n");
    for u in s.u {
        let _ = writeln!(t, "{:e} {:e} {:e}", u[0], u[1], u[2]);
    }
    t.push_str("</DataArray>\n");
    if let Some(stress) = s.stress {
        t.push_str("<DataArray type=\"Float64\" Name=\"stress\" NumberOfComponents=\"9\" format=\"ascii\">\n");
        for sigma in stress {
            let row: Vec<String> = sigma.iter().flatten().map(|v| format!("{v:e}")).collect();
            let _ = writeln!(t, "{}", row.join(" "));
        }
        t.push_str("</DataArray>\n");
    }
    scalar(
        &mut t,
        "Float64",
        "volume",
        p.volume.iter().map(|v| format!("{v:e}")),
    );
    scalar(
        &mut t,
        "Float64",
        "horizon",
        p.horizon.iter().map(|v| format!("{v:e}")),
    );
    scalar(
        &mut t,
        "Int32",
        "material",
        p.material.iter().map(|v| v.to_string()),
    );
    scalar(
        &mut t,
        "Int32",
        "bond_count",
        bonds.iter().map(|v| v.to_string()),
    );
    if let Some(damage) = s.damage {
        scalar(
            &mut t,
            "Float64",
            "damage",
            damage.iter().map(|v| format!("{v:e}")),
        );
    }
    t.push_str("</PointData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n");
    super::write_file(path, &t)
}

fn join_into<T: std::fmt::Display>(t: &mut String, items: impl Iterator<Item = T>) {
    for (k, v) in items.enumerate() {
        let _ = write!(t, "{v}{}", if k % 16 == 15 { '\n' } else { ' ' });
    }
    t.push('\n');
}

fn scalar(t: &mut String, ty: &str, name: &str, values: impl Iterator<Item = String>) {
    let _ = writeln!(
        t,
        "<DataArray type=\"{ty}\" Name=\"{name}\" format=\"ascii\">"
    );
    join_into(t, values);
    t.push_str("</DataArray>\n");
}

/// Writes a ParaView collection (`.pvd`) listing `(time, file)` pairs; the
/// time is the load factor.
pub fn write_collection(path: &Path, entries: &[(f64, String)]) -> Result<(), Error> {
    let mut t = String::from(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n<Collection>\n",
    );
    for (time, file) in entries {
        let _ = writeln!(
            t,
            "<DataSet timestep=\"{time:e}\" group=\"\" part=\"0\" file=\"{file}\"/>"
        );
    }
    t.push_str("</Collection>\n</VTKFile>\n");
    super::write_file(path, &t)
}
