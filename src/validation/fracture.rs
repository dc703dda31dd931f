//! The fracture validation cases (`validation/fracture`) as scene builders,
//! shared by the tests (coarse), the study example (sweeps) and the committed
//! scene files.
//!
//! **Single-edge-notched tension (SENT)**, plane stress, per unit thickness:
//! a plate `x ∈ [0, W]`, free length `L` between clamped grips (`y = ±L/2`),
//! an edge notch of length `a` along `y = 0` (a pre-crack no bond crosses).
//! The grips are bands of whole spacings beyond `±L/2`, at least a horizon
//! deep; the bottom one is held, the top one moved by `Δ` along `y` (`x`
//! held), or along `x` for the shear loading. No bond breaks within `W/10` of
//! the grips. `W = 0.1 m`, `L = 0.2 m`, `a = 0.05 m` (`a/W = 0.5`),
//! `E = 30 GPa`, `ν = 1/3`, `G₀ = 200 J/m²`. The finite-element reference for
//! this exact geometry and these grips is in `validation/fracture/fem`.

use crate::scene::{parse_spec, Scene};
use std::fmt::Write;
use std::path::Path;

/// Plate width `W` (m).
pub const WIDTH: f64 = 0.1;
/// Free length between the grips `L` (m).
pub const LENGTH: f64 = 0.2;
/// Notch length `a` (m).
pub const NOTCH: f64 = 0.05;
/// Young's modulus (Pa).
pub const YOUNGS_MODULUS: f64 = 3.0e10;
/// Fracture energy (J/m²).
pub const FRACTURE_ENERGY: f64 = 200.0;
/// Grip displacement at load factor 1 (m).
pub const GRIP_DISPLACEMENT: f64 = 1.0e-4;

/// How the top grip moves.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Loading {
    /// Along `y` (mode I for the edge notch).
    Tension,
    /// Along `x` (in-plane shear of the notched section).
    Shear,
}

/// A SENT specimen and how to run it.
#[derive(Debug, Clone, PartialEq)]
pub struct Sent {
    /// `"bond_based"` or `"shear"`.
    pub model: &'static str,
    /// Spacing `W / cells` of the (fine) grid.
    pub cells: usize,
    /// `m = δ/Δx`.
    pub horizon_factor: f64,
    /// `"event"`, `"all"` or `"most_critical"`.
    pub strategy: &'static str,
    /// Further `[quasi_static]` lines (e.g. `steps = 50`).
    pub stepping: String,
    /// A fine band `|y| ≤ half height` around the crack path with the grid
    /// spacing, and twice the spacing elsewhere (DH-PD where it matters).
    pub fine_band: Option<f64>,
    /// `"dual"` (DH-PD) or `"constant"` (every point takes the largest horizon).
    pub horizons: &'static str,
    /// Grip motion.
    pub loading: Loading,
    /// `quasi_static.stop_after_peak`.
    pub stop_after_peak: Option<f64>,
    /// `output.every`.
    pub output_every: Option<usize>,
    /// `quasi_static.max_load_factor` (the grip moves `GRIP_DISPLACEMENT` at 1).
    pub max_load_factor: f64,
    /// 3D: the plate's depth along `z` (the notch runs through it); `None`:
    /// plane stress per unit thickness.
    pub depth: Option<f64>,
    /// Instead of the edge notch, a centre crack through `(W/2, 0)` at 45° to
    /// `x`, half-length [`INCLINED_HALF_LENGTH`] (mixed mode under tension).
    pub inclined: bool,
}

/// Half-length of the inclined centre crack (m).
pub const INCLINED_HALF_LENGTH: f64 = 0.015;

/// The tips of the inclined centre crack: `(W/2 ± c cos45°, ± c sin45°)`.
pub fn inclined_tips() -> [[f64; 3]; 2] {
    let h = INCLINED_HALF_LENGTH * std::f64::consts::FRAC_1_SQRT_2;
    [[0.5 * WIDTH + h, h, 0.0], [0.5 * WIDTH - h, -h, 0.0]]
}

impl Sent {
    /// A uniform plate with `cells` spacings across, event strategy, tension.
    pub fn new(model: &'static str, cells: usize, horizon_factor: f64) -> Self {
        Self {
            model,
            cells,
            horizon_factor,
            strategy: "event",
            stepping: String::new(),
            fine_band: None,
            horizons: "dual",
            loading: Loading::Tension,
            stop_after_peak: None,
            output_every: None,
            max_load_factor: 1.0,
            depth: None,
            inclined: false,
        }
    }

    /// Grid spacing of the fine region.
    pub fn spacing(&self) -> f64 {
        WIDTH / self.cells as f64
    }

    /// Horizon of the fine region.
    pub fn horizon(&self) -> f64 {
        self.horizon_factor * self.spacing()
    }

    /// Scene name.
    pub fn name(&self) -> String {
        let mut name = format!(
            "sent_{}_{}_n{}_m{}",
            self.model,
            self.strategy,
            self.cells,
            self.horizon_factor.floor()
        );
        if let Some(h) = self.fine_band {
            let _ = write!(name, "_band{}", (h / self.spacing()).round());
        }
        if self.horizons == "constant" {
            name.push_str("_constant");
        }
        if self.loading == Loading::Shear {
            name.push_str("_shear_loading");
        }
        if self.inclined {
            name.push_str("_inclined");
        }
        if self.depth.is_some() {
            name.push_str("_3d");
        }
        name
    }

    /// The scene file text.
    pub fn toml(&self) -> String {
        let h = self.spacing();
        let coarse = if self.fine_band.is_some() { 2.0 * h } else { h };
        // Grip bands: whole coarse spacings, at least a horizon deep.
        let grip = self.horizon_factor.ceil() * coarse;
        let (top, bottom) = (0.5 * LENGTH + grip, -0.5 * LENGTH - grip);
        // A box over the whole width (and depth, in 3D) between y0 and y1.
        let slab = |y0: f64, y1: f64| match self.depth {
            None => format!("{{ min = [0.0, {y0:e}], max = [{WIDTH}, {y1:e}] }}"),
            Some(z) => format!("{{ min = [0.0, {y0:e}, 0.0], max = [{WIDTH}, {y1:e}, {z:e}] }}"),
        };
        let (dimension, setting) = match self.depth {
            None => (
                "plane_stress",
                String::from("plane stress, per unit thickness"),
            ),
            Some(z) => ("3d", format!("3D, depth {z} m")),
        };
        let mut t = String::new();
        let _ = writeln!(
            t,
            "# SENT plate (validation/fracture): W = {WIDTH} m, free length L = {LENGTH} m between \
             clamped grips,\n# edge notch a = {NOTCH} m along y = 0; {setting}; spacing W/{}, m = {}.\n\
             name = \"{}\"\n\n[model]\ndimension = \"{dimension}\"\nkind = \"{}\"\n\
             horizons = \"{}\"\n\n[discretization]\nhorizon_factor = {}\n\n\
             [materials.plate]\nyoungs_modulus = {YOUNGS_MODULUS:e}\n{}fracture_energy = {FRACTURE_ENERGY}\n",
            self.cells,
            self.horizon_factor,
            self.name(),
            self.model,
            self.horizons,
            self.horizon_factor,
            if self.model == "shear" {
                "poisson_ratio = 0.3333333333333333\n"
            } else {
                ""
            }
        );
        let region = |t: &mut String, spacing: f64, y0: f64, y1: f64| {
            let _ = writeln!(
                t,
                "[[regions]]\nmaterial = \"plate\"\nspacing = {spacing:e}\nbox = {}\n",
                slab(y0, y1)
            );
        };
        match self.fine_band {
            None => region(&mut t, h, bottom, top),
            Some(band) => {
                region(&mut t, h, -band, band);
                region(&mut t, coarse, band, top);
                region(&mut t, coarse, bottom, -band);
            }
        }
        let (gx, gy) = match self.loading {
            Loading::Tension => (0.0, GRIP_DISPLACEMENT),
            Loading::Shear => (GRIP_DISPLACEMENT, 0.0),
        };
        let guard = 0.5 * LENGTH - 0.1 * WIDTH;
        let [upper, lower] = inclined_tips();
        let crack = match (self.depth, self.inclined) {
            (Some(z), _) => format!(
                "origin = [0.0, 0.0, 0.0]\nedge1 = [{NOTCH}, 0.0, 0.0]\nedge2 = [0.0, 0.0, {z:e}]"
            ),
            (None, true) => format!(
                "from = [{:e}, {:e}]\nto = [{:e}, {:e}]",
                lower[0], lower[1], upper[0], upper[1]
            ),
            (None, false) => format!("from = [0.0, 0.0]\nto = [{NOTCH}, 0.0]"),
        };
        let held = if self.depth.is_some() {
            "x = 0.0, y = 0.0, z = 0.0"
        } else {
            "x = 0.0, y = 0.0"
        };
        let pulled = match self.depth {
            None => format!("x = {gx:e}, y = {gy:e}"),
            Some(_) => format!("x = {gx:e}, y = {gy:e}, z = 0.0"),
        };
        let _ = writeln!(
            t,
            "[[cracks]]\n{crack}\n\n\
             [[boundary]]\nname = \"bottom\"\nbox = {}\ndisplacement = {{ {held} }}\n\n\
             [[boundary]]\nname = \"top\"\nbox = {}\ndisplacement = {{ {pulled} }}\n\n\
             [fracture]\nno_fail = [\n  {{ box = {} }},\n  {{ box = {} }},\n]\n\n\
             [quasi_static]\nstrategy = \"{}\"\nmax_load_factor = {}",
            slab(bottom, -0.5 * LENGTH),
            slab(0.5 * LENGTH, top),
            slab(bottom, -guard),
            slab(guard, top),
            self.strategy,
            self.max_load_factor
        );
        if !self.stepping.is_empty() {
            let _ = writeln!(t, "{}", self.stepping);
        }
        if let Some(f) = self.stop_after_peak {
            let _ = writeln!(t, "stop_after_peak = {f}");
        }
        if let Some(n) = self.output_every {
            let _ = writeln!(t, "\n[output]\nevery = {n}");
        }
        t
    }

    /// The validated scene.
    pub fn scene(&self) -> Scene {
        let spec = parse_spec(&self.toml(), false).expect("the SENT scene parses");
        Scene::try_from_spec(spec, Path::new("."), "sent").expect("the SENT scene is valid")
    }
}
