//! The point data one file shows (positions, displacement, velocity, volume,
//! spacing, horizon, material, bonds, damage, stress), checked finite before
//! any file is written, and the point files, profiles and probes of a state.

use super::{csv, vtu};
use crate::discretization::Discretization;
use crate::drivers::setup::Plan;
use crate::drivers::static_solve::StaticSolution;
use crate::error::{Error, NumericalError};
use crate::model::Block;
use crate::scene::Scene;
use std::path::Path;

/// The point fields one output file shows.
pub struct PointData<'a> {
    /// Points and bonds (the bond count is of the intact bonds).
    pub disc: &'a Discretization,
    /// Displacement of every point.
    pub u: &'a [[f64; 3]],
    /// Velocity of every point, for dynamics runs.
    pub velocity: Option<&'a [[f64; 3]]>,
    /// Recovered stress, when computed.
    pub stress: Option<&'a [Block]>,
    /// Damage per point, for fracture runs.
    pub damage: Option<&'a [f64]>,
    /// Intact bonds touching each point, when counted already (a body
    /// discretised over several processes: summed over them); `None`:
    /// counted from `disc`, which holds every bond.
    pub bond_counts: Option<&'a [u32]>,
}

impl PointData<'_> {
    /// The intact bonds touching each point, as owner or as neighbour.
    pub fn bond_counts(&self) -> std::borrow::Cow<'_, [u32]> {
        match self.bond_counts {
            Some(counts) => counts.into(),
            None => self.disc.bonds.touch_counts(self.disc.points.len()).into(),
        }
    }

    /// Refuses to write `file` when a number it would hold is not finite,
    /// naming the field and the first such point: every writer of point data
    /// calls this, so no `NaN` or `inf` reaches a result.
    pub fn ensure_finite(&self, file: &Path) -> Result<(), Error> {
        let p = &self.disc.points;
        let vectors = [
            ("position", Some(&p.x[..])),
            ("displacement", Some(self.u)),
            ("velocity", self.velocity),
        ];
        let mut bad = vectors
            .iter()
            .filter_map(|(name, v)| Some((*name, (*v)?)))
            .find_map(|(name, v)| {
                v.iter()
                    .position(|x| x.iter().any(|c| !c.is_finite()))
                    .map(|i| (name, i))
            });
        let scalars = [
            ("volume", Some(&p.volume[..])),
            ("spacing", Some(&p.spacing[..])),
            ("horizon", Some(&p.horizon[..])),
            ("damage", self.damage),
        ];
        bad = bad.or_else(|| {
            scalars
                .iter()
                .filter_map(|(name, v)| Some((*name, (*v)?)))
                .find_map(|(name, v)| v.iter().position(|c| !c.is_finite()).map(|i| (name, i)))
        });
        bad = bad.or_else(|| {
            self.stress?
                .iter()
                .position(|b| b.iter().flatten().any(|c| !c.is_finite()))
                .map(|i| ("stress", i))
        });
        match bad {
            None => Ok(()),
            Some((name, i)) => Err(NumericalError::NonFinite {
                what: format!(
                    "the {name} of point {i} (x = {:?}) to be written to {}; nothing was written",
                    p.x[i],
                    file.display()
                ),
            }
            .into()),
        }
    }
}

impl StaticSolution {
    /// The fields of a static solution.
    pub fn point_data(&self) -> PointData<'_> {
        PointData {
            disc: &self.disc,
            u: &self.u,
            velocity: None,
            stress: self.stress.as_deref(),
            damage: None,
            bond_counts: Some(&self.bond_counts),
        }
    }
}

/// Writes the point files, profiles and probes of one state into `dir`;
/// with several `vtu_pieces` (the processes of an MPI run), `points.pvtu`
/// and the first piece instead of `points.vtu` ([`write_vtu_piece`] writes
/// the others).
pub(crate) fn write_points(
    dir: &Path,
    scene: &Scene,
    plan: &Plan,
    data: &PointData,
    vtu_pieces: usize,
) -> Result<(), Error> {
    data.ensure_finite(dir)?;
    if scene.output.vtu && vtu_pieces > 1 {
        let names: Vec<String> = (0..vtu_pieces).map(piece_name).collect();
        vtu::write_parallel(&dir.join("points.pvtu"), data, &names)?;
        write_vtu_piece(dir, data, 0, vtu_pieces)?;
    } else if scene.output.vtu {
        vtu::write(&dir.join("points.vtu"), data)?;
    }
    if scene.output.points_csv {
        csv::write_points(&dir.join("points.csv"), scene, data)?;
    }
    for (name, pts) in &plan.profiles {
        csv::write_profile(&dir.join(format!("profile_{name}.csv")), data, pts)?;
    }
    if !plan.probes.is_empty() {
        csv::write_probes(&dir.join("probes.csv"), data, &plan.probes)?;
    }
    Ok(())
}

/// The file of piece `piece` of `points.pvtu`.
fn piece_name(piece: usize) -> String {
    format!("points_{piece}.vtu")
}

/// Writes piece `piece` of `pieces` of `points.pvtu` into `dir` (its share of
/// the point order, [`vtu::piece_range`]).
pub(crate) fn write_vtu_piece(
    dir: &Path,
    data: &PointData,
    piece: usize,
    pieces: usize,
) -> Result<(), Error> {
    let range = vtu::piece_range(data.disc.points.len(), piece, pieces);
    vtu::write_piece(&dir.join(piece_name(piece)), data, range)
}
