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

use crate::drivers::quasi_static::{self, StateKind, StepRecord};
use crate::drivers::{self, Observer, Snapshot};
use crate::error::Error;
use crate::scene::{parse_spec, Scene};
use std::fmt::Write;
use std::path::Path;
use std::time::Instant;

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
    /// Edge notch length `a` (m; [`NOTCH`] by default).
    pub notch: f64,
    /// Instead of the edge notch, a straight centre crack on `y = 0` from
    /// `W/2 − c` to `W/2 + c` with this half-length `c` (centre-cracked tension).
    pub centre_crack: Option<f64>,
    /// `fracture.calibration` (`"dissipation"`, the default, or `"continuum"`).
    pub calibration: &'static str,
    /// `fracture.shear_criterion` (shear model: `"energy"`, the default, or `"deviatoric"`).
    pub shear_criterion: &'static str,
    /// A square lattice of the same spacing rotated by this angle (degrees), written
    /// as a point file ([`Sent::write`]), instead of the grid (uniform 2D plates only).
    pub lattice_angle: f64,
    /// The surface-true defaults (`true`), or the earlier models: no surface
    /// correction (bond-based) and the paper's force (shear).
    pub surfaces: bool,
}

/// The `[model]` and `[discretization]` lines that choose the earlier models
/// when `surfaces` is off (nothing otherwise).
fn surface_lines(model: &str, surfaces: bool) -> (&'static str, &'static str) {
    match (surfaces, model) {
        (true, _) => ("", ""),
        (false, "shear") => ("formulation = \"paper\"\n", ""),
        (false, _) => ("", "surface_correction = \"none\"\n"),
    }
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
            notch: NOTCH,
            centre_crack: None,
            calibration: "dissipation",
            shear_criterion: "energy",
            lattice_angle: 0.0,
            surfaces: true,
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
        if let Some(c) = self.centre_crack {
            let _ = write!(name, "_centre{:.0}mm", 1e3 * c);
        } else if self.notch != NOTCH {
            let _ = write!(name, "_notch{:.0}mm", 1e3 * self.notch);
        }
        if self.calibration != "dissipation" {
            let _ = write!(name, "_{}", self.calibration);
        }
        if self.model == "shear" && self.shear_criterion != "energy" {
            let _ = write!(name, "_{}", self.shear_criterion);
        }
        if let Some(depth) = self.depth {
            let _ = write!(name, "_3d_depth{}mm", (depth * 1e3).round());
        }
        if self.lattice_angle != 0.0 {
            let _ = write!(name, "_lattice{}deg", self.lattice_angle);
        }
        if !self.surfaces {
            name.push_str("_uncorrected");
        }
        name.replace('.', "p")
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
             clamped grips,\n# {}; {setting}; spacing W/{}, m = {}.\n\
             name = \"{}\"\n\n[model]\ndimension = \"{dimension}\"\nkind = \"{}\"\n\
             horizons = \"{}\"\n{}\n[discretization]\nhorizon_factor = {}\n{}\n\
             [materials.plate]\nyoungs_modulus = {YOUNGS_MODULUS:e}\n{}fracture_energy = {FRACTURE_ENERGY}\n",
            match (self.centre_crack, self.inclined) {
                (Some(c), _) => format!("centre crack of half-length {c} m along y = 0"),
                (None, true) => String::from("inclined centre crack"),
                (None, false) => format!("edge notch a = {} m along y = 0", self.notch),
            },
            self.cells,
            self.horizon_factor,
            self.name(),
            self.model,
            self.horizons,
            surface_lines(self.model, self.surfaces).0,
            self.horizon_factor,
            surface_lines(self.model, self.surfaces).1,
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
            None if self.lattice_angle != 0.0 => {
                let _ = writeln!(
                    t,
                    "[[point_files]]\npath = \"{}.points\"\nmaterial = \"plate\"\n",
                    self.name()
                );
            }
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
        let crack = match (self.depth, self.inclined, self.centre_crack) {
            (Some(z), _, _) => format!(
                "origin = [0.0, 0.0, 0.0]\nedge1 = [{:e}, 0.0, 0.0]\nedge2 = [0.0, 0.0, {z:e}]",
                self.notch
            ),
            (None, _, Some(c)) => format!(
                "from = [{:e}, 0.0]\nto = [{:e}, 0.0]",
                0.5 * WIDTH - c,
                0.5 * WIDTH + c
            ),
            (None, true, None) => format!(
                "from = [{:e}, {:e}]\nto = [{:e}, {:e}]",
                lower[0], lower[1], upper[0], upper[1]
            ),
            (None, false, None) => format!("from = [0.0, 0.0]\nto = [{:e}, 0.0]", self.notch),
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
             [fracture]\ncalibration = \"{}\"\n{}no_fail = [\n  {{ box = {} }},\n  {{ box = {} }},\n]\n\n\
             [quasi_static]\nstrategy = \"{}\"\nmax_load_factor = {}",
            slab(bottom, -0.5 * LENGTH),
            slab(0.5 * LENGTH, top),
            self.calibration,
            if self.model == "shear" {
                format!("shear_criterion = \"{}\"\n", self.shear_criterion)
            } else {
                String::new()
            },
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

    /// The point-file text of the rotated lattice (`None` on the grid).
    pub fn point_file(&self) -> Option<String> {
        let top = 0.5 * LENGTH + self.horizon_factor.ceil() * self.spacing();
        (self.lattice_angle != 0.0)
            .then(|| rotated_lattice(self.spacing(), self.lattice_angle, WIDTH, top))
    }

    /// Writes the scene (and its point file) into `dir`; returns the scene's path.
    pub fn write(&self, dir: &Path) -> std::io::Result<std::path::PathBuf> {
        std::fs::create_dir_all(dir)?;
        if let Some(text) = self.point_file() {
            std::fs::write(dir.join(format!("{}.points", self.name())), text)?;
        }
        let path = dir.join(format!("{}.toml", self.name()));
        std::fs::write(&path, self.toml())?;
        Ok(path)
    }

    /// The validated scene (on the grid; a rotated lattice needs its point file:
    /// [`Sent::write`] and `scene::load`).
    pub fn scene(&self) -> Scene {
        assert_eq!(
            self.lattice_angle, 0.0,
            "a rotated lattice is read from its point file"
        );
        let spec = parse_spec(&self.toml(), false).expect("the SENT scene parses");
        Scene::try_from_spec(spec, Path::new("."), "sent").expect("the SENT scene is valid")
    }
}

/// **The calibration strip** (`damage::calibration`, `examples/fracture_calibration.rs`):
/// a long strip `x ∈ [0, length]`, free height `H` between clamped grips at
/// `y = ±H/2`, pre-cracked along `y = 0` from the edge `x = 0` to `x = notch`. The
/// top grip moves along `y` (mode I) or `x` (mode II), the crack grows along `y = 0`
/// to the far edge, and the energy each event releases is booked at the midpoints
/// of the bonds it broke: away from the notch and the far edge this is the energy
/// the lattice dissipates per unit area of steady crack growth, `D G₀`.
///
/// The lattice is the scene's regular grid (`angle = 0`) or a square lattice of the
/// same spacing rotated by `angle` degrees, written as a point file, to measure `D`
/// for cracks that do not run along a grid line. Sizes are in spacings.
#[derive(Debug, Clone, PartialEq)]
pub struct Strip {
    /// `"bond_based"` or `"shear"`.
    pub model: &'static str,
    /// `m = δ/Δx`.
    pub horizon_factor: f64,
    /// Rotation of the lattice against the crack, degrees.
    pub angle: f64,
    /// `discretization.volume_correction`.
    pub volume_correction: &'static str,
    /// `fracture.calibration`.
    pub calibration: &'static str,
    /// `model.dimension` (`"plane_stress"` or `"plane_strain"`).
    pub dimension: &'static str,
    /// Poisson ratio (shear model only).
    pub poisson_ratio: f64,
    /// `fracture.shear_criterion` (shear model only).
    pub shear_criterion: &'static str,
    /// Grip motion.
    pub loading: Loading,
    /// Spacing (m).
    pub spacing: f64,
    /// Strip length in spacings.
    pub length_cells: usize,
    /// Free height between the grips in spacings.
    pub height_cells: usize,
    /// Notch length in spacings.
    pub notch_cells: usize,
    /// Young's modulus (Pa).
    pub youngs_modulus: f64,
    /// Fracture energy G₀ (J/m²).
    pub fracture_energy: f64,
    /// 3D: the strip's depth along `z` in spacings (the pre-crack runs through
    /// it; `D` counts only bonds whose midpoints lie in the bulk, away from the
    /// faces `z = 0` and `z = depth`, on the regular grid); `0`: 2D.
    pub depth_cells: usize,
    /// The surface-true defaults, or the earlier models ([`Sent::surfaces`]).
    pub surfaces: bool,
}

impl Strip {
    /// A bond-based strip on the regular grid, mode I, continuum calibration,
    /// 120 × 30 spacings with a 20-spacing notch, `Δx = 1 mm`.
    pub fn new(model: &'static str, horizon_factor: f64) -> Self {
        Self {
            model,
            horizon_factor,
            angle: 0.0,
            volume_correction: "overlap",
            calibration: "continuum",
            dimension: "plane_stress",
            poisson_ratio: 1.0 / 3.0,
            shear_criterion: "energy",
            loading: Loading::Tension,
            spacing: 1.0e-3,
            length_cells: 120,
            height_cells: 30,
            notch_cells: 20,
            youngs_modulus: YOUNGS_MODULUS,
            fracture_energy: FRACTURE_ENERGY,
            depth_cells: 0,
            surfaces: true,
        }
    }

    /// A bond-based 3D strip, mode I, continuum calibration: 48 × 12 spacings
    /// with a 10-spacing notch, 14 spacings deep (`Δx = 1 mm`).
    pub fn new_3d(horizon_factor: f64) -> Self {
        Self {
            dimension: "3d",
            length_cells: 48,
            height_cells: 12,
            notch_cells: 10,
            depth_cells: 14,
            ..Self::new("bond_based", horizon_factor)
        }
    }

    /// Strip depth (m; 0 in 2D).
    pub fn depth(&self) -> f64 {
        self.depth_cells as f64 * self.spacing
    }

    /// The bulk along `z` where energy is booked, `[start, end)`: in 3D, whole
    /// spacings more than 1.5 horizons from both faces (a bond's end is then more
    /// than a horizon from them), edges a quarter spacing off the bond midpoints;
    /// `None` in 2D.
    fn bulk(&self) -> Option<(f64, f64)> {
        (self.depth_cells > 0).then(|| {
            let (h, margin) = (self.spacing, 1.5 * self.horizon());
            let start = ((margin / h).ceil() + 0.25) * h;
            (
                start,
                start + ((self.depth() - margin - start) / h).floor() * h,
            )
        })
    }

    /// Strip length (m).
    pub fn length(&self) -> f64 {
        self.length_cells as f64 * self.spacing
    }

    /// Free height between the grips (m).
    pub fn height(&self) -> f64 {
        self.height_cells as f64 * self.spacing
    }

    /// Notch length (m).
    pub fn notch(&self) -> f64 {
        self.notch_cells as f64 * self.spacing
    }

    /// Horizon (m).
    pub fn horizon(&self) -> f64 {
        self.horizon_factor * self.spacing
    }

    /// Scene name.
    pub fn name(&self) -> String {
        let mode = match self.loading {
            Loading::Tension => "mode1",
            Loading::Shear => "mode2",
        };
        let mut name = format!(
            "strip_{}_{mode}_m{:.3}_{}_{}deg_{}x{}",
            self.model,
            self.horizon_factor,
            self.volume_correction,
            self.angle,
            self.length_cells,
            self.height_cells
        );
        if self.model == "shear" {
            let _ = write!(name, "_{}", self.shear_criterion);
        }
        if self.youngs_modulus != YOUNGS_MODULUS || self.fracture_energy != FRACTURE_ENERGY {
            let _ = write!(
                name,
                "_E{:e}_G{:e}",
                self.youngs_modulus, self.fracture_energy
            );
        }
        if self.spacing != 1.0e-3 {
            let _ = write!(name, "_h{:e}", self.spacing);
        }
        if self.calibration != "continuum" {
            let _ = write!(name, "_{}", self.calibration);
        }
        if self.depth_cells > 0 {
            let _ = write!(name, "_3d_depth{}", self.depth_cells);
        }
        if !self.surfaces {
            name.push_str("_uncorrected");
        }
        name.replace('.', "p")
    }

    /// Grip depth: whole spacings, at least a horizon and one spacing.
    fn grip(&self) -> f64 {
        (self.horizon_factor.ceil() + 1.0) * self.spacing
    }

    /// The point-file text of the rotated lattice (`None` on the regular grid).
    pub fn point_file(&self) -> Option<String> {
        (self.angle != 0.0 && self.depth_cells == 0).then(|| {
            rotated_lattice(
                self.spacing,
                self.angle,
                self.length(),
                0.5 * self.height_cells as f64 * self.spacing + self.grip(),
            )
        })
    }

    /// The scene file text; `points` is the point file's path relative to the
    /// scene (rotated lattice only).
    pub fn toml(&self, points: &str) -> String {
        let h = self.spacing;
        let half = 0.5 * self.height_cells as f64 * h;
        let (top, bottom) = (half + self.grip(), -half - self.grip());
        let depth = self.depth();
        let three_d = self.depth_cells > 0;
        let slab = |y0: f64, y1: f64| {
            if three_d {
                format!(
                    "{{ min = [-1.0, {y0:e}, -1.0], max = [{:e}, {y1:e}, {:e}] }}",
                    self.length() + 1.0,
                    depth + 1.0
                )
            } else {
                format!(
                    "{{ min = [-1.0, {y0:e}], max = [{:e}, {y1:e}] }}",
                    self.length() + 1.0
                )
            }
        };
        // Beyond G₀ D with D ≤ 4 at λ = 1: G = E' ε² H / 2 of the uncracked strip.
        let grip_displacement =
            (2.0 * 4.0 * self.fracture_energy * 2.0 * half / self.youngs_modulus).sqrt();
        let (gx, gy) = match self.loading {
            Loading::Tension => (0.0, grip_displacement),
            Loading::Shear => (grip_displacement, 0.0),
        };
        let mut t = String::new();
        let _ = writeln!(
            t,
            "# Calibration strip (damage::calibration): {} x {} spacings of {h:e} m, edge \
             pre-crack of {} spacings along y = 0,\n# lattice rotated by {}°.\n\
             name = \"{}\"\n\n[model]\ndimension = \"{}\"\nkind = \"{}\"\n{}\n\
             [discretization]\nhorizon_factor = {}\nvolume_correction = \"{}\"\n{}\n\
             [materials.strip]\nyoungs_modulus = {:e}\n{}fracture_energy = {}\n",
            self.length_cells,
            self.height_cells,
            self.notch_cells,
            self.angle,
            self.name(),
            self.dimension,
            self.model,
            surface_lines(self.model, self.surfaces).0,
            self.horizon_factor,
            self.volume_correction,
            surface_lines(self.model, self.surfaces).1,
            self.youngs_modulus,
            if self.model == "shear" {
                format!("poisson_ratio = {}\n", self.poisson_ratio)
            } else {
                String::new()
            },
            self.fracture_energy,
        );
        if three_d {
            let _ = writeln!(
                t,
                "[[regions]]\nmaterial = \"strip\"\nspacing = {h:e}\nbox = {{ min = [0.0, {bottom:e}, 0.0], max = [{:e}, {top:e}, {depth:e}] }}\n",
                self.length()
            );
        } else if self.angle == 0.0 {
            let _ = writeln!(
                t,
                "[[regions]]\nmaterial = \"strip\"\nspacing = {h:e}\nbox = {{ min = [0.0, {bottom:e}], max = [{:e}, {top:e}] }}\n",
                self.length()
            );
        } else {
            let _ = writeln!(
                t,
                "[[point_files]]\npath = \"{points}\"\nmaterial = \"strip\"\n"
            );
        }
        let guard = 0.5 * half;
        let (crack, held, pulled) = if three_d {
            (
                format!(
                    "origin = [{:e}, 0.0, -1.0]\nedge1 = [{:e}, 0.0, 0.0]\nedge2 = [0.0, 0.0, {:e}]",
                    -h,
                    self.notch() + h,
                    depth + 2.0
                ),
                String::from("x = 0.0, y = 0.0, z = 0.0"),
                format!("x = {gx:e}, y = {gy:e}, z = 0.0"),
            )
        } else {
            (
                format!("from = [{:e}, 0.0]\nto = [{:e}, 0.0]", -h, self.notch()),
                String::from("x = 0.0, y = 0.0"),
                format!("x = {gx:e}, y = {gy:e}"),
            )
        };
        let _ = writeln!(
            t,
            "[[cracks]]\n{crack}\n\n\
             [[boundary]]\nname = \"bottom\"\nbox = {}\ndisplacement = {{ {held} }}\n\n\
             [[boundary]]\nname = \"top\"\nbox = {}\ndisplacement = {{ {pulled} }}\n\n\
             [fracture]\ncalibration = \"{}\"\n{}no_fail = [\n  {{ box = {} }},\n  {{ box = {} }},\n]\n\n\
             [quasi_static]\nstrategy = \"event\"\nmax_load_factor = {}",
            slab(2.0 * bottom, -half),
            slab(half, 2.0 * top),
            self.calibration,
            if self.model == "shear" {
                format!("shear_criterion = \"{}\"\n", self.shear_criterion)
            } else {
                String::new()
            },
            slab(2.0 * bottom, -guard),
            slab(guard, 2.0 * top),
            // Shear: G = μ γ² H / 2 with μ ≥ E/3, so three times the displacement.
            match self.loading {
                Loading::Tension => 1.0,
                Loading::Shear => 3.0,
            },
        );
        t
    }

    /// Writes the scene (and its point file) into `dir`; returns the scene's path.
    pub fn write(&self, dir: &Path) -> std::io::Result<std::path::PathBuf> {
        std::fs::create_dir_all(dir)?;
        let points = format!("{}.points", self.name());
        if let Some(text) = self.point_file() {
            std::fs::write(dir.join(&points), text)?;
        }
        let path = dir.join(format!("{}.toml", self.name()));
        std::fs::write(&path, self.toml(&points))?;
        Ok(path)
    }
}

/// The point-file text (`x y volume` per row) of a square lattice of spacing `h`
/// rotated by `angle` degrees, filling `0 ≤ x < x_max`, `|y| < y_max`; offset so
/// that no point lies on `y = 0` (the crack line) or on the box's edges.
fn rotated_lattice(h: f64, angle: f64, x_max: f64, y_max: f64) -> String {
    let (s, c) = angle.to_radians().sin_cos();
    let origin = [0.5 * x_max + 0.3183 * h, 0.4142 * h];
    let reach = ((x_max * x_max + 4.0 * y_max * y_max).sqrt() / h).ceil() as i64 + 2;
    let mut text = String::from("# x y volume (rotated square lattice)\n");
    for i in -reach..=reach {
        for j in -reach..=reach {
            let (a, b) = (i as f64 * h, j as f64 * h);
            let x = origin[0] + c * a - s * b;
            let y = origin[1] + s * a + c * b;
            if (0.0..x_max).contains(&x) && y.abs() < y_max {
                let _ = writeln!(text, "{x:.12e} {y:.12e} {:.12e}", h * h);
            }
        }
    }
    text
}

/// What a calibration strip dissipated ([`Strip::dissipation`]).
#[derive(Debug, Clone, PartialEq)]
pub struct StripDissipation {
    /// Energy booked in the steady window over `G₀ ×` its length: the dissipation factor.
    pub d: f64,
    /// Work of the grip to separation over `G₀ × (length − notch)`.
    pub work: f64,
    /// The steady window `[start, end)` along `x` (m).
    pub window: (f64, f64),
    /// Energy booked per spacing along the strip, over `G₀ × spacing` (per unit
    /// depth of the bulk in 3D).
    pub profile: Vec<f64>,
    /// 3D: energy booked in the steady window per spacing of depth, over `G₀ ×`
    /// that area (the bulk's value is `D`; the faces show the skin); empty in 2D.
    pub depth_profile: Vec<f64>,
    /// The lattice trapping ratio `r`: in the steady window, the largest critical
    /// grip displacement of the events over the energy-equivalent one (the median
    /// over windows of four spacings; [`trapping_ratio`]).
    pub trapping: Option<f64>,
    /// Points of the strip.
    pub points: usize,
    /// Directed bonds broken.
    pub bonds_broken: usize,
    /// Wall time of the run (s).
    pub seconds: f64,
}

/// One event of a strip run ([`Booking`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StripEvent {
    /// The crack front after the event: the largest `x` of the midpoint of a bond
    /// broken so far (m). Events are placed by the front, not by where their own
    /// bonds are: a bond in the wake that breaks late belongs to the cycle of the
    /// front at that time, whose loads it shares.
    pub x: f64,
    /// Grip displacement at the critical state (m).
    pub displacement: f64,
    /// Stiffness of the strip the event removed, `(R_critical − R_broken)/Δ` (N/m).
    pub stiffness_drop: f64,
}

/// The lattice trapping ratio of steady growth: in each window of `width`
/// along the crack inside `[start, end)`, the largest critical grip displacement
/// over the energy-equivalent one `ū = sqrt(Σ Δ_k² ΔK_k / Σ ΔK_k)` (the events
/// release `Δ_k² ΔK_k / 2`, so `ū` is the constant displacement that would
/// release the same energy); the median over the windows, which start a spacing
/// apart. At fixed grip displacement a long strip's energy release rate is
/// `G = Δ² |dK/da| / 2`, so `r²` is the largest energy release rate that steady
/// growth needs over the energy it dissipates: the peak load of a sharp crack
/// exceeds the LEFM load of the dissipated energy by `r`. `None` when no window
/// holds an event.
pub fn trapping_ratio(
    events: &[StripEvent],
    start: f64,
    end: f64,
    width: f64,
    step: f64,
) -> Option<f64> {
    let mut ratios = Vec::new();
    let mut lo = start;
    while lo + width <= end + 1e-12 * width {
        let inside = events.iter().filter(|e| (lo..lo + width).contains(&e.x));
        let (mut num, mut den, mut max) = (0.0, 0.0, 0.0_f64);
        for e in inside {
            num += e.displacement * e.displacement * e.stiffness_drop;
            den += e.stiffness_drop;
            max = max.max(e.displacement);
        }
        if den > 0.0 {
            ratios.push(max / (num / den).sqrt());
        }
        lo += step;
    }
    if ratios.is_empty() {
        return None;
    }
    ratios.sort_by(f64::total_cmp);
    let n = ratios.len();
    Some(if n % 2 == 1 {
        ratios[n / 2]
    } else {
        0.5 * (ratios[n / 2 - 1] + ratios[n / 2])
    })
}

/// Books every event's released energy at the midpoints of the bonds it broke.
struct Booking {
    /// Reaction component of the moving grip (1: mode I, 0: mode II).
    axis: usize,
    /// Intact flags after the previous event.
    intact: Vec<bool>,
    /// Grip displacement and reaction at the last critical state.
    critical: Option<(f64, f64)>,
    /// The critical state and the reaction after the break, until the
    /// snapshot of the broken state arrives.
    broken: Option<((f64, f64), f64)>,
    /// `(x, z of the bond's midpoint, energy)` of every broken bond.
    booked: Vec<(f64, f64, f64)>,
    /// Every event: the crack front after it, its critical grip displacement and
    /// the stiffness it removed, `ΔR/Δ`.
    events: Vec<StripEvent>,
    /// The crack front: the largest `x` of a broken bond's midpoint so far.
    front: f64,
    /// Work of the grip, `Σ ΔE`.
    total: f64,
}

impl Observer for Booking {
    fn record(&mut self, record: &StepRecord) -> Result<(), Error> {
        // The moving grip is the scene's second boundary set ("top").
        let reaction = record.reactions[1][self.axis];
        self.broken = None;
        match record.state {
            StateKind::Critical => self.critical = Some((record.displacement, reaction)),
            StateKind::Broken => self.broken = self.critical.take().map(|c| (c, reaction)),
            _ => {}
        }
        Ok(())
    }

    /// The state after an event's break (every record has a snapshot).
    fn snapshot(&mut self, snap: &Snapshot) -> Result<(), Error> {
        if let Some(((u, r_critical), reaction)) = self.broken.take() {
            {
                let released = 0.5 * u * (r_critical - reaction);
                let (x, bonds) = (&snap.disc.points.x, &snap.disc.bonds);
                let mut midpoints = Vec::new();
                for i in 0..x.len() {
                    for b in bonds.owned_by(i) {
                        if self.intact[b] && !bonds.intact[b] {
                            let j = bonds.neighbour[b] as usize;
                            midpoints.push([0.5 * (x[i][0] + x[j][0]), 0.5 * (x[i][2] + x[j][2])]);
                            self.intact[b] = false;
                        }
                    }
                }
                self.front = midpoints.iter().fold(self.front, |f, m| f.max(m[0]));
                if !midpoints.is_empty() && u > 0.0 {
                    self.events.push(StripEvent {
                        x: self.front,
                        displacement: u,
                        stiffness_drop: (r_critical - reaction) / u,
                    });
                }
                let share = released / midpoints.len().max(1) as f64;
                self.booked
                    .extend(midpoints.into_iter().map(|m| (m[0], m[1], share)));
                self.total += released;
            }
        }
        Ok(())
    }
}

impl Strip {
    /// Runs the strip (its scene written into `dir`) with the event strategy to
    /// separation and books the energy of every event at the midpoints of the
    /// bonds it broke, `Δ (R_critical − R_broken) / 2`. The steady window runs
    /// from `notch + 3δ` to `length − max(H, 4δ)` (beyond it the remaining
    /// ligament bends), in whole spacings with edges a quarter spacing off the
    /// lattice's bond midpoints.
    pub fn dissipation(&self, dir: &Path) -> Result<StripDissipation, Error> {
        let path = self.write(dir).map_err(|e| Error::io(dir, e))?;
        let mut scene = crate::scene::load(&path)?;
        scene.output.every = Some(1);
        let start_time = Instant::now();
        let setup = drivers::check(&scene, &mut ())?;
        let points = setup.disc.points.len();
        let mut booking = Booking {
            axis: match self.loading {
                Loading::Tension => 1,
                Loading::Shear => 0,
            },
            intact: setup.disc.bonds.intact.clone(),
            critical: None,
            broken: None,
            booked: Vec::new(),
            events: Vec::new(),
            front: f64::NEG_INFINITY,
            total: 0.0,
        };
        quasi_static::run(&scene, setup, &mut booking)?;
        let h = self.spacing;
        let start = (((self.notch() + 3.0 * self.horizon()) / h).ceil() + 0.25) * h;
        let last = self.length() - self.height().max(4.0 * self.horizon());
        let end = start + ((last - start) / h).floor() * h;
        let g0 = self.fracture_energy;
        // In 3D: per unit depth of the bulk (the whole depth for the work).
        let (z0, z1) = self.bulk().unwrap_or((f64::NEG_INFINITY, f64::INFINITY));
        let (bulk_depth, depth) = match self.bulk() {
            Some((z0, z1)) => (z1 - z0, self.depth()),
            None => (1.0, 1.0),
        };
        let in_bulk = |z: f64| (z0..z1).contains(&z);
        let in_window: f64 = booking
            .booked
            .iter()
            .filter(|&&(x, z, _)| (start..end).contains(&x) && in_bulk(z))
            .map(|(_, _, e)| e)
            .sum();
        let mut profile = vec![0.0; self.length_cells];
        for &(x, _, e) in booking.booked.iter().filter(|b| in_bulk(b.1)) {
            let k = ((x / h).floor().max(0.0) as usize).min(self.length_cells - 1);
            profile[k] += e / (g0 * h * bulk_depth);
        }
        // Energy per spacing of depth in the steady window, over G₀ × its area.
        let mut depth_profile = vec![0.0; self.depth_cells];
        for &(x, z, e) in booking.booked.iter().filter(|_| self.depth_cells > 0) {
            if (start..end).contains(&x) {
                let k = ((z / h).floor().max(0.0) as usize).min(self.depth_cells - 1);
                depth_profile[k] += e / (g0 * h * (end - start));
            }
        }
        Ok(StripDissipation {
            d: in_window / (g0 * (end - start) * bulk_depth),
            work: booking.total / (g0 * (self.length() - self.notch()) * depth),
            window: (start, end),
            profile,
            depth_profile,
            trapping: trapping_ratio(&booking.events, start, end, 4.0 * h, h),
            points,
            bonds_broken: booking.booked.len(),
            seconds: start_time.elapsed().as_secs_f64(),
        })
    }
}
