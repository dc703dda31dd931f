//! The scene files of the validation reports, written from the same functions
//! the tests and examples solve, so that every case a report talks about runs
//! with `dhpd run FILE`. `cargo run --release --example write_scenes` writes
//! them; `tests/scene_files.rs` checks that the committed files are current.

use super::{plate_tension_text, Bimaterial, HoleLoad, PlateWithHole};

/// A scene file: its path from the repository root and its text.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneFile {
    /// Path relative to the repository root.
    pub path: String,
    /// The file's text (comment header first).
    pub text: String,
}

/// Every generated scene file.
pub fn catalogue() -> Vec<SceneFile> {
    let mut files = Vec::new();
    let mut add = |path: String, header: String, text: String| {
        files.push(SceneFile {
            path,
            text: file_text(&header, &text),
        })
    };

    let bar = "validation/bimaterial_bar";
    for (dl, dr, tag) in [(0.01, 0.005, "coarse_left"), (0.005, 0.01, "fine_left")] {
        for constant in [false, true] {
            let case = Bimaterial {
                dx_left: dl,
                dx_right: dr,
                constant_horizon: constant,
                strip: false,
                surface_correction: true,
            };
            let horizons = if constant { "constant" } else { "dual" };
            add(
                format!("{bar}/scenes/bar1d_{tag}_{horizons}.toml"),
                format!(
                    "1D bimaterial bar (000 Sec. 5.1): E = 1 | 2, spacing {dl} | {dr} m, {horizons} \
                     horizons, right end moved 1e-4 m; against the series-spring solution. Report: \
                     {bar}/README.md"
                ),
                case.text(),
            );
        }
    }
    for r in [1.0, 3.0, 5.0] {
        let case = Bimaterial {
            dx_left: 0.01 / r,
            dx_right: 0.005 / r,
            constant_horizon: false,
            strip: true,
            surface_correction: true,
        };
        add(
            format!("{bar}/scenes/strip2d_r{r}.toml"),
            format!(
                "2D bimaterial strip 1 x 0.1 m, refinement r = {r} (spacing {} | {} m), bond-based \
                 DH-PD; against the scikit-fem reference fem/reference.json. Report: {bar}/README.md",
                0.01 / r,
                0.005 / r
            ),
            case.text(),
        );
    }

    let hole = "validation/plate_with_hole";
    let plate = |spacing: f64, m: f64, shear: bool, load: HoleLoad| PlateWithHole {
        spacing,
        horizon_factor: m,
        shear,
        load,
    };
    let model_name = |shear: bool| if shear { "shear" } else { "bond_based" };
    for spacing in [0.02, 0.01, 0.005] {
        for m in [2.015, 3.015, 4.015] {
            for shear in [false, true] {
                add(
                    format!("{hole}/scenes/uniaxial_{}_dx{spacing}_m{m}.toml", model_name(shear)),
                    format!(
                        "Plate with a hole (001 Sec. 6.3), uniaxial tension 1 MPa, {} model, \
                         spacing {spacing} m, m = {m}; against fem/reference.json (compare with \
                         `cargo run --release --example plate_with_hole`). Report: {hole}/README.md",
                        model_name(shear)
                    ),
                    plate(spacing, m, shear, HoleLoad::Uniaxial).text(
                        "plane_stress",
                        1.0 / 3.0,
                        false,
                    ),
                );
            }
        }
        for shear in [false, true] {
            add(
                format!(
                    "{hole}/scenes/tension_compression_{}_dx{spacing}_m3.015.toml",
                    model_name(shear)
                ),
                format!(
                    "Plate with a hole, the paper's loading (tension on the left and right edges, \
                     compression on the top and bottom), {} model, spacing {spacing} m; against \
                     fem/reference_tension_compression.json. Report: {hole}/README.md",
                    model_name(shear)
                ),
                plate(spacing, 3.015, shear, HoleLoad::TensionCompression).text(
                    "plane_stress",
                    1.0 / 3.0,
                    false,
                ),
            );
        }
        add(
            format!("{hole}/scenes/uniaxial_shear_gradient_dx{spacing}_m3.015.toml"),
            format!(
                "Plate with a hole, uniaxial, shear model with the gradient dilatation, spacing \
                 {spacing} m; against fem/reference.json. Report: {hole}/README.md"
            ),
            plate(spacing, 3.015, true, HoleLoad::Uniaxial).text("plane_stress", 1.0 / 3.0, true),
        );
    }

    let stability = "validation/stability";
    for nu in ["0.3", "0.45", "0.49", "0.499", "0.4999"] {
        for gradient in [false, true] {
            let dilatation = if gradient { "gradient" } else { "weighted" };
            add(
                format!("{stability}/scenes/incompressible_nu{nu}_{dilatation}.toml"),
                format!(
                    "Near incompressibility: the plate with a hole in plane strain, nu = {nu}, shear \
                     model, {dilatation} dilatation, spacing 0.005 m; against \
                     fem/reference_nu{nu}.json (Taylor-Hood). Report: {stability}/README.md"
                ),
                plate(0.005, 3.015, true, HoleLoad::Uniaxial).text(
                    "plane_strain",
                    nu.parse().expect("a number"),
                    gradient,
                ),
            );
        }
    }

    let tension = "validation/plate_tension";
    for shear in [false, true] {
        for n in [2, 3, 4, 5] {
            add(
                format!("{tension}/scenes/{}_n{n}.toml", model_name(shear)),
                format!(
                    "Plate under tension with two regions (004 Sec. 5.1), {} model, delta = {n} \
                     spacings of each region (0.005 | 0.01 m); against fem/reference.json \
                     (`cargo run --release --example plate_tension`). Report: {tension}/README.md",
                    model_name(shear)
                ),
                plate_tension_text(model_name(shear), n as f64, 3),
            );
        }
    }
    files
}

/// The header as comment lines, then the scene without its fixed `name` (so
/// each file's results go to `dhpd-out/<file stem>`) and without indentation.
fn file_text(header: &str, text: &str) -> String {
    let mut out = String::new();
    let mut line = String::from("#");
    for word in header.split_whitespace() {
        if line.len() + word.len() + 1 > 88 {
            out += &line;
            out.push('\n');
            line = String::from("#");
        }
        line.push(' ');
        line += word;
    }
    out += &line;
    out += "\n# Generated by `cargo run --release --example write_scenes`.\n";
    for l in text.lines().map(str::trim) {
        if l.is_empty() || l.starts_with("name = ") && !out.contains("\n[") {
            continue;
        }
        out += l;
        out.push('\n');
    }
    out
}
