//! Independent references for validation: closed forms and finite-element
//! results sampled on a regular grid (the JSON files under `validation/`,
//! produced by committed scikit-fem scripts). The default run compares with
//! one of them; the tests and studies (feature `fixtures`) use the rest.
#![cfg_attr(not(feature = "fixtures"), allow(dead_code))]

use serde::Deserialize;
use std::collections::BTreeMap;

/// A field sampled on a regular grid; `None` marks samples outside the body.
#[derive(Debug, Clone, Deserialize)]
pub struct Grid {
    /// First sample abscissa.
    pub x0: f64,
    /// Sample spacing along x.
    pub dx: f64,
    /// Number of samples along x.
    pub nx: usize,
    /// First sample ordinate.
    pub y0: f64,
    /// Sample spacing along y.
    pub dy: f64,
    /// Number of samples along y.
    pub ny: usize,
    /// Fields by name, rows indexed by y: `field[iy][ix]`.
    #[serde(flatten)]
    pub fields: BTreeMap<String, Vec<Vec<Option<f64>>>>,
}

impl Grid {
    /// Bilinear interpolation of `field` at `(x, y)`; `None` outside the grid,
    /// next to a missing sample, or for an unknown field.
    pub fn interpolate(&self, field: &str, x: f64, y: f64) -> Option<f64> {
        let f = self.fields.get(field)?;
        let (sx, sy) = ((x - self.x0) / self.dx, (y - self.y0) / self.dy);
        let eps = 1e-9;
        if sx < -eps
            || sy < -eps
            || sx > (self.nx - 1) as f64 + eps
            || sy > (self.ny - 1) as f64 + eps
        {
            return None;
        }
        let ix = (sx.floor().max(0.0) as usize).min(self.nx - 2);
        let iy = (sy.floor().max(0.0) as usize).min(self.ny - 2);
        let (tx, ty) = (sx - ix as f64, sy - iy as f64);
        let v = |i: usize, j: usize| f.get(j).and_then(|row| row.get(i)).copied().flatten();
        Some(
            (1.0 - tx) * (1.0 - ty) * v(ix, iy)?
                + tx * (1.0 - ty) * v(ix + 1, iy)?
                + (1.0 - tx) * ty * v(ix, iy + 1)?
                + tx * ty * v(ix + 1, iy + 1)?,
        )
    }
}

/// A finite-element reference file (only the parts dhpd reads).
#[derive(Debug, Clone, Deserialize)]
pub struct FemReference {
    /// The sampled solution.
    pub grid: Grid,
    /// Reaction force along x at the loaded edge, when the problem has one.
    pub reaction_x: Option<f64>,
    /// Estimated discretisation error of `reaction_x` (difference to the previous mesh).
    pub reaction_x_est_error: Option<f64>,
    /// Line profiles: name → column → values.
    pub profiles: Option<BTreeMap<String, BTreeMap<String, Vec<f64>>>>,
    /// Largest displacement magnitude, when the reference states it.
    pub max_abs_u: Option<f64>,
}

impl FemReference {
    /// Linear interpolation of column `field` of profile `name` at abscissa
    /// `s` of column `along`; `None` outside the profile or if absent.
    pub fn profile_at(&self, name: &str, along: &str, field: &str, s: f64) -> Option<f64> {
        let profile = self.profiles.as_ref()?.get(name)?;
        let (xs, ys) = (profile.get(along)?, profile.get(field)?);
        let k = xs.windows(2).position(|w| w[0] <= s && s <= w[1])?;
        let t = (s - xs[k]) / (xs[k + 1] - xs[k]);
        Some((1.0 - t) * ys[k] + t * ys[k + 1])
    }
}

impl FemReference {
    /// Reads a reference JSON file.
    pub fn from_file(path: &std::path::Path) -> Result<Self, String> {
        let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
        Self::from_json(&text).map_err(|e| format!("{}: {e}", path.display()))
    }

    /// Parses a reference JSON document.
    pub fn from_json(text: &str) -> Result<Self, serde_json::Error> {
        serde_json::from_str(text)
    }
}

/// The 2D bimaterial strip's FEM reference, embedded for the default run:
/// clamped at x = 0.03, the face of the held cells (the surface correction's
/// grip, `model::surface`), u_x prescribed at x = 0.9725.
pub const BIMATERIAL_STRIP_FEM: &str =
    include_str!("../validation/bimaterial_bar/fem/reference_clamp_face.json");

/// Closed-form displacement of a bar of two materials in series (uniaxial, 1D):
/// fixed at `a`, displaced by `u_end` at `b`, interface at `x_i`, moduli `e1`
/// left and `e2` right. Strains satisfy `E1 ε1 = E2 ε2`.
pub fn series_bar(x: f64, a: f64, b: f64, x_i: f64, e1: f64, e2: f64, u_end: f64) -> f64 {
    let compliance = (x_i - a) / e1 + (b - x_i) / e2;
    let stress = u_end / compliance;
    if x <= a {
        0.0
    } else if x >= b {
        u_end
    } else if x <= x_i {
        stress * (x - a) / e1
    } else {
        stress * ((x_i - a) / e1 + (x - x_i) / e2)
    }
}

/// Error statistics of computed against reference values.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize)]
pub struct ErrorStats {
    /// Number of compared samples.
    pub count: usize,
    /// Largest |computed − reference| divided by `scale`.
    pub max_relative: f64,
    /// Root mean square of (computed − reference) divided by `scale`.
    pub rms_relative: f64,
}

impl ErrorStats {
    /// Compares pairs `(computed, reference)`, normalised by `scale` (for
    /// example the largest reference magnitude).
    pub fn of(pairs: impl IntoIterator<Item = (f64, f64)>, scale: f64) -> Self {
        let (mut count, mut max, mut sq) = (0, 0.0f64, 0.0);
        for (c, r) in pairs {
            let e = (c - r).abs() / scale;
            count += 1;
            max = max.max(e);
            sq += e * e;
        }
        Self {
            count,
            max_relative: max,
            rms_relative: if count > 0 {
                (sq / count as f64).sqrt()
            } else {
                0.0
            },
        }
    }
}
