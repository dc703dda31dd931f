//! Peridynamic models: the bond kernels shared by every driver.
//!
//! A model answers, for one owner `o` and its family of bonds: the force each
//! bond puts on the owner (`+f_oj V_o V_j`; Newton's third law puts the opposite
//! on `j`, formulation Sec. 2), and the derivatives of those forces with respect
//! to the displacements involved, delivered one column point at a time so that
//! the assembly can fill the global stiffness column by column without races.
//!
//! Sign convention: `K = −∂F_int/∂u`, so the static problem reads `K u = f_ext`.

pub mod bond_based;
pub mod shear;
pub mod surface;

use crate::discretization::Discretization;
use crate::error::NumericalError;
use crate::scene::{ModelKind, Scene};
use bond_based::BondBased;
use shear::Shear;

/// A 3 × 3 block (only the leading d × d part is used).
pub type Block = [[f64; 3]; 3];

/// Which points one owner's tangent couples.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Coupling {
    /// Owner with each neighbour (bond-based): the global pattern is the bond graph.
    Star,
    /// Every pair of points in `{o} ∪ H_o` (state-based models): neighbours of neighbours.
    Family,
}

/// The column point of an owner's tangent block.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Column {
    /// Derivatives with respect to the owner's displacement.
    Owner,
    /// Derivatives with respect to the neighbour of this bond.
    Neighbour(usize),
}

/// A bond kernel: forces and tangent of one owner's family.
pub trait Model: Sync + Send {
    /// The coupling pattern of an owner's tangent.
    fn coupling(&self) -> Coupling;

    /// Writes, for each bond `b` owned by `owner`, the force it puts on the owner
    /// into `out[b − first bond of owner]`, for displacements `u`. `linear`
    /// selects the linearised force (exactly `−K u` restricted to this family).
    fn owner_forces(
        &self,
        disc: &Discretization,
        owner: usize,
        u: &[[f64; 3]],
        linear: bool,
        out: &mut [[f64; 3]],
    );

    /// The strain each bond of `owner` puts to the model's damage rule
    /// (formulation Sec. 5), into `out` (0 for broken bonds): the stretch `s`
    /// (bond-based) or the deviatoric bond strain `|ε^d|` (shear model). Returns
    /// the owner's dilatation θ when the rule has a tension check, else `None`.
    fn bond_strains(
        &self,
        disc: &Discretization,
        owner: usize,
        u: &[[f64; 3]],
        linear: bool,
        out: &mut [f64],
    ) -> Option<f64>;

    /// Brings the model's per-owner data up to date after bonds of `owners`
    /// broke; returns the owners that can no longer carry their own bonds
    /// (whose remaining bonds the caller must break). Default: nothing to update.
    fn refresh_owners(&mut self, _disc: &Discretization, _owners: &[usize]) -> Vec<usize> {
        Vec::new()
    }

    /// For a model whose tangent contribution of bond `b` (owned by `owner`) is
    /// the rank-one `k e ⊗ e` on `(owner, neighbour)` blocks (`+` on the
    /// diagonal blocks, `−` off them): `(k, e)`. Lets a solver update its factor
    /// exactly when the bond breaks. `None` otherwise (default).
    fn bond_stiffness(
        &self,
        _disc: &Discretization,
        _owner: usize,
        _b: usize,
    ) -> Option<(f64, [f64; 3])> {
        None
    }

    /// Recovered stress at `owner` for displacements `u` (linearised), if the model
    /// defines one.
    fn stress(&self, _disc: &Discretization, _owner: usize, _u: &[[f64; 3]]) -> Option<Block> {
        None
    }

    /// Calls `add(row_point, block)` with the blocks `K[row_point][column]`
    /// contributed by `owner`'s bonds to the stiffness column of `column`.
    fn tangent_column(
        &self,
        disc: &Discretization,
        owner: usize,
        column: Column,
        add: &mut dyn FnMut(usize, &Block),
    );
}

/// The scene's model on a discretisation: the one place a model kind becomes
/// a model ([`AnyModel::new`]); it forwards every kernel to that model.
#[derive(Debug, Clone)]
pub enum AnyModel {
    /// Bond-based DH-PD.
    BondBased(BondBased),
    /// The shear-deformation DH-PD.
    Shear(Shear),
}

impl AnyModel {
    /// The model `scene` names, with every owner's data on `disc` (an error
    /// names a shear-model owner whose bonds do not span the space).
    pub fn new(scene: &Scene, disc: &Discretization) -> Result<Self, NumericalError> {
        Ok(match scene.model.kind {
            ModelKind::BondBased => AnyModel::BondBased(BondBased::of(scene, disc)),
            ModelKind::Shear => AnyModel::Shear(Shear::of(scene, disc)?),
        })
    }
}

impl AnyModel {
    /// What the user should know about the model's set-up: owners the surface
    /// correction could not match (their families cannot reach a full one's
    /// moments, e.g. a body one point thick), left uncorrected, and pre-crack
    /// faces corrected for want of memory.
    pub fn warnings(&self) -> Vec<String> {
        let mut warnings = Vec::new();
        if let AnyModel::BondBased(m) = self {
            if m.unmatched_owners > 0 {
                warnings.push(format!(
                    "warning: the surface correction left {} point(s) uncorrected: their bonds \
                     cannot reach the stiffness of a full family (a body thinner than about two \
                     spacings?)",
                    m.unmatched_owners
                ));
            }
            if m.crack_faces_corrected {
                warnings.push(String::from(
                    "warning: the bonds of the body without its pre-cracks could not be \
                     searched (memory); the pre-crack faces were corrected as free surfaces, \
                     which raises the fracture loads above the calibration's",
                ));
            }
        }
        warnings
    }
}

/// Forwards a kernel call to the model inside an [`AnyModel`].
macro_rules! forward {
    ($model:expr, $m:ident => $call:expr) => {
        match $model {
            AnyModel::BondBased($m) => $call,
            AnyModel::Shear($m) => $call,
        }
    };
}

impl Model for AnyModel {
    fn coupling(&self) -> Coupling {
        forward!(self, m => m.coupling())
    }

    fn owner_forces(
        &self,
        disc: &Discretization,
        owner: usize,
        u: &[[f64; 3]],
        linear: bool,
        out: &mut [[f64; 3]],
    ) {
        forward!(self, m => m.owner_forces(disc, owner, u, linear, out))
    }

    fn bond_strains(
        &self,
        disc: &Discretization,
        owner: usize,
        u: &[[f64; 3]],
        linear: bool,
        out: &mut [f64],
    ) -> Option<f64> {
        forward!(self, m => m.bond_strains(disc, owner, u, linear, out))
    }

    fn refresh_owners(&mut self, disc: &Discretization, owners: &[usize]) -> Vec<usize> {
        forward!(self, m => m.refresh_owners(disc, owners))
    }

    fn bond_stiffness(
        &self,
        disc: &Discretization,
        owner: usize,
        b: usize,
    ) -> Option<(f64, [f64; 3])> {
        forward!(self, m => m.bond_stiffness(disc, owner, b))
    }

    fn stress(&self, disc: &Discretization, owner: usize, u: &[[f64; 3]]) -> Option<Block> {
        forward!(self, m => m.stress(disc, owner, u))
    }

    fn tangent_column(
        &self,
        disc: &Discretization,
        owner: usize,
        column: Column,
        add: &mut dyn FnMut(usize, &Block),
    ) {
        forward!(self, m => m.tangent_column(disc, owner, column, add))
    }
}
