//! Bad scenes through the real binary: every case must fail with the right exit
//! code (2 input error, 3 numerical failure, 4 I/O), name the offending field
//! (dotted path or key) on stderr, and leave neither the `--out` directory nor a
//! `.out.partial-*` sibling (nor any other file) behind.
//!
//! Each case is a small edit of [`BASE`] (a 0.2 m × 0.1 m plane-stress plate,
//! spacing 0.01 m, left edge clamped, right edge pulled by a traction), run in
//! its own temporary directory.
//!
//! Set `DHPD_BAD_SCENES_SHOW=1` to print the stderr of every case.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

/// The valid scene every case edits (also the positive control).
use common::PLATE_SCENE as BASE;

/// A 1D bar (for the 1D-only cases).
const BAR_1D: &str = r#"[model]
dimension = "1d"

[materials.bar]
youngs_modulus = 1.0
poisson_ratio = 0.25

[[regions]]
material = "bar"
spacing = 0.01
box = { min = [0.0], max = [0.1] }

[[boundary]]
name = "left"
box = { min = [0.0], max = [0.01] }
displacement = { x = 0.0 }
"#;

/// A coarse region whose horizon (19 spacings) covers a region ten times finer:
/// about three times the bonds an estimate from each point's own spacing
/// expects, more than the memory limit allows.
const COARSE_OVER_FINE: &str = r#"[model]
dimension = "plane_stress"
[materials.m]
youngs_modulus = 1e9
[[regions]]
material = "m"
spacing = 0.001
box = { min = [0.0, 0.0], max = [0.1, 0.1] }
[[regions]]
material = "m"
spacing = 0.01
horizon_factor = 19.0
box = { min = [0.1, 0.0], max = [0.2, 0.1] }
[[boundary]]
name = "left"
box = { min = [0.0, 0.0], max = [0.003, 0.1] }
displacement = { x = 0.0, y = 0.0 }
[solver]
memory_limit_gib = 0.02
"#;

/// A 16³-point cube whose bonds (18 MiB) and pattern (about 100 MiB) fit in
/// the limit and whose Cholesky factor (337 MiB) does not.
const CUBE_3D: &str = r#"[model]
dimension = "3d"
[materials.m]
youngs_modulus = 1e9
[[regions]]
material = "m"
spacing = 0.01
box = { min = [0.0, 0.0, 0.0], max = [0.16, 0.16, 0.16] }
[[boundary]]
name = "left"
box = { min = [0.0, 0.0, 0.0], max = [0.01, 0.16, 0.16] }
displacement = { x = 0.0, y = 0.0, z = 0.0 }
[[loads]]
name = "pull"
kind = "traction"
face = "+x"
value = [1.0e6, 0.0, 0.0]
[solver]
memory_limit_gib = 0.12
"#;

/// The bimaterial strip mesh ("soft" and "stiff" surfaces, "left" and "right"
/// curves), read with materials from its groups, clamped on `left`, pulled on `right`.
const MESH_STRIP: &str = concat!(
    "[model]\ndimension = \"plane_stress\"\n",
    "[materials.soft]\nyoungs_modulus = 1.0e9\n[materials.stiff]\nyoungs_modulus = 2.0e9\n",
    "[[meshes]]\npath = \"",
    env!("CARGO_MANIFEST_DIR"),
    "/validation/plate_with_hole/gmsh/bimaterial_strip.msh\"\n",
    "groups = { soft = \"soft\", stiff = \"stiff\" }\n",
    "[[boundary]]\nname = \"left\"\ngroup = \"left\"\ndisplacement = { x = 0.0, y = 0.0 }\n",
    "[[loads]]\nname = \"pull\"\nkind = \"traction\"\ngroup = \"right\"\nvalue = [1.0e6, 0.0]\n"
);

/// The strip mesh (0 ≤ x ≤ 1, 0 ≤ y ≤ 0.1) as a second body of one material.
const STRIP_MESH: &str = concat!(
    "\n[[meshes]]\npath = \"",
    env!("CARGO_MANIFEST_DIR"),
    "/validation/plate_with_hole/gmsh/bimaterial_strip.msh\"\nmaterial = \"soft\"\n"
);

/// The triangle mesh of the plate with a hole (|x|, |y| ≤ 0.5) as a second body.
const HOLE_MESH: &str = concat!(
    "\n[[meshes]]\npath = \"",
    env!("CARGO_MANIFEST_DIR"),
    "/validation/plate_with_hole/gmsh/plate_hole_tri_h0.02.msh\"\nmaterial = \"soft\"\n"
);

/// The strip mesh as an arbitrary file `pts.xyz` next to the scene.
const MESH_PTS: Edit = Rep("/validation/plate_with_hole/gmsh/bimaterial_strip.msh", "");

/// A point file `pts.xyz` next to the scene, default material `soft`.
const PF: &str = "\n[[point_files]]\npath = \"pts.xyz\"\nmaterial = \"soft\"\n";

/// The clamp of the base scene (removed by the under-constrained cases).
const LEFT_BC: &str = "[[boundary]]\nname = \"left\"\nbox = { min = [0.0, 0.0], max = [0.01, 0.1] }\ndisplacement = { x = 0.0, y = 0.0 }\n";

/// A traction on the left face balancing the base scene's pull.
const LEFT_PULL: &str = "\n[[loads]]\nname = \"pull_left\"\nkind = \"traction\"\nface = \"-x\"\nbox = { min = [0.0, 0.0], max = [0.01, 0.1] }\nvalue = [-1.0e6, 0.0]\n";

/// A quasi-static section (for the fracture cases).
const QS: &str = "\n[quasi_static]\nmax_load_factor = 1.0\n";

/// A dynamics section (for the explicit-dynamics cases).
const DY: &str = "\n[dynamics]\nsteps = 5\n";

/// Two valid rows (x y volume) to the right of the plate, touching nothing else.
const ROWS_OK: &str = "0.30 0.05 1e-6\n0.31 0.05 1e-6\n";

/// An edit of the base scene.
#[derive(Clone, Copy, Debug)]
enum Edit {
    /// Replace the only occurrence of the first string by the second.
    Rep(&'static str, &'static str),
    /// Append text at the end (new tables).
    Add(&'static str),
    /// Prepend text (top-level keys must precede the first table).
    Pre(&'static str),
    /// Use this text instead of the base scene.
    Whole(&'static str),
    /// Write the scene as `scene.json` instead of `scene.toml` (use with `Whole`).
    Json,
    /// Run `dhpd check SCENE` instead of `dhpd run SCENE --out DIR`.
    Check,
    /// Run `dhpd run SCENE` without `--out` (results would go to `dhpd-out/<name>`).
    NoOut,
}
use Edit::*;

/// One bad scene: name, edits of [`BASE`], `pts.xyz` contents, expected exit
/// code, and substrings stderr must contain (the field path or key first).
struct Case {
    name: &'static str,
    edits: &'static [Edit],
    points: Option<&'static str>,
    code: i32,
    expect: &'static [&'static str],
}

const fn c(
    name: &'static str,
    edits: &'static [Edit],
    points: Option<&'static str>,
    code: i32,
    expect: &'static [&'static str],
) -> Case {
    Case {
        name,
        edits,
        points,
        code,
        expect,
    }
}

#[rustfmt::skip]
const CASES: &[Case] = &[
    // --- syntax and structure ---
    c("toml_syntax_error", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = 1.0e9 GPa")], None, 2, &["scene", "line 12"]),
    c("toml_unclosed_table_header", &[Add("[[regions]\n")], None, 2, &["scene", "line 36"]),
    c("unknown_top_level_key", &[Pre("spacin = 0.01\n")], None, 2, &["spacin"]),
    c("unknown_key_in_region", &[Rep("spacing = 0.01", "spacin = 0.01")], None, 2, &["regions[0]", "spacin"]),
    c("unknown_key_in_model", &[Rep("thickness = 0.01", "thickness = 0.01\ndimensions = 2")], None, 2, &["model", "dimensions"]),
    c("unknown_key_in_boundary_displacement", &[Rep("{ x = 0.0, y = 0.0 }", "{ x = 0.0, w = 0.0 }")], None, 2, &["boundary[0].displacement", "`w`"]),
    c("unknown_output_key", &[Add("\n[output]\nvtk = true\n")], None, 2, &["output", "vtk"]),
    c("missing_model_section", &[Rep("[model]\ndimension = \"plane_stress\"\nthickness = 0.01\n", "")], None, 2, &["model"]),
    c("missing_dimension", &[Rep("dimension = \"plane_stress\"\n", "")], None, 2, &["model", "dimension"]),
    c("bad_dimension_string", &[Rep("\"plane_stress\"", "\"2d\"")], None, 2, &["model.dimension", "2d"]),
    c("unknown_model_kind", &[Rep("thickness = 0.01", "thickness = 0.01\nkind = \"state_based\"")], None, 2, &["model.kind", "state_based"]),
    c("youngs_modulus_as_string", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = \"1e9\"")], None, 2, &["materials.soft.youngs_modulus"]),
    c("region_missing_spacing", &[Rep("spacing = 0.01\n", "")], None, 2, &["regions[0]", "spacing"]),
    c("unknown_solver_method", &[Add("\n[solver]\nmethod = \"qr\"\n")], None, 2, &["solver.method", "qr"]),
    c("unknown_isolated_policy", &[Rep("horizon_factor = 3.015", "isolated_points = \"ignore\"")], None, 2, &["discretization.isolated_points", "ignore"]),
    c("unknown_volume_correction", &[Rep("horizon_factor = 3.015", "volume_correction = \"exact\"")], None, 2, &["discretization.volume_correction", "exact"]),
    c("json_unknown_key", &[Json, Whole(r#"{"model": {"dimension": "1d"}, "materials": {"bar": {"youngs_modulus": 1.0}},
        "regions": [{"material": "bar", "spacin": 0.01, "box": {"min": [0.0], "max": [0.1]}}]}"#)], None, 2, &["regions[0]", "spacin"]),
    c("json_syntax_error", &[Json, Whole(r#"{"model": {"dimension": "1d"},}"#)], None, 2, &["trailing comma", "line 1 column 31", "JSON"]),
    // A key twice (serde would keep the last) and a second value after the scene (issue 34).
    c("json_duplicate_material", &[Json, Whole(r#"{"model": {"dimension": "1d"}, "materials": {"soft": {"youngs_modulus": 1.0}, "soft": {"youngs_modulus": 5.0}},
        "regions": [{"material": "soft", "spacing": 0.01, "box": {"min": [0.0], "max": [0.1]}}]}"#)], None, 2, &["materials", "\"soft\" is given twice"]),
    c("json_trailing_scene", &[Json, Whole(r#"{"model": {"dimension": "1d"}, "materials": {"bar": {"youngs_modulus": 1.0}},
        "regions": [{"material": "bar", "spacing": 0.01, "box": {"min": [0.0], "max": [0.1]}}]}
        {"model": {"dimension": "1d"}}"#)], None, 2, &["scene", "text after the scene's JSON value"]),
    // --- model ---
    c("thickness_in_3d", &[Rep("\"plane_stress\"", "\"3d\"")], None, 2, &["model.thickness"]),
    c("area_in_2d", &[Rep("thickness = 0.01", "area = 0.01")], None, 2, &["model.area"]),
    c("negative_thickness", &[Rep("thickness = 0.01", "thickness = -0.01")], None, 2, &["model.thickness"]),
    c("thickness_in_1d", &[Whole(BAR_1D), Rep("dimension = \"1d\"", "dimension = \"1d\"\nthickness = 0.1"), Rep("poisson_ratio = 0.25\n", "")], None, 2, &["model.thickness"]),
    // --- materials ---
    c("negative_youngs_modulus", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = -1.0e9")], None, 2, &["materials.soft.youngs_modulus"]),
    c("zero_youngs_modulus", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = 0.0")], None, 2, &["materials.soft.youngs_modulus"]),
    c("nan_youngs_modulus", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = nan")], None, 2, &["materials.soft.youngs_modulus"]),
    c("infinite_youngs_modulus", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = inf")], None, 2, &["materials.soft.youngs_modulus"]),
    c("poisson_0_6_plane_strain", &[Rep("\"plane_stress\"", "\"plane_strain\""), Rep("0.3333333333333333", "0.6")], None, 2, &["materials.soft.poisson_ratio"]),
    c("poisson_minus_1_5", &[Rep("0.3333333333333333", "-1.5")], None, 2, &["materials.soft.poisson_ratio"]),
    c("poisson_nan", &[Rep("0.3333333333333333", "nan")], None, 2, &["materials.soft.poisson_ratio"]),
    c("poisson_0_3_plane_strain_bond_based", &[Rep("\"plane_stress\"", "\"plane_strain\""), Rep("0.3333333333333333", "0.3")], None, 2, &["materials.soft.poisson_ratio", "allow_any_poisson"]),
    c("poisson_in_1d", &[Whole(BAR_1D)], None, 2, &["materials.bar.poisson_ratio"]),
    c("no_materials", &[Rep("[materials.soft]\nyoungs_modulus = 1.0e9\npoisson_ratio = 0.3333333333333333\n", "")], None, 2, &["materials"]),
    c("material_missing_youngs_modulus", &[Rep("youngs_modulus = 1.0e9\n", "")], None, 2, &["materials.soft", "youngs_modulus"]),
    // --- discretization and regions ---
    c("global_horizon_factor_0_5", &[Rep("horizon_factor = 3.015", "horizon_factor = 0.5")], None, 2, &["discretization.horizon_factor"]),
    c("global_horizon_factor_100", &[Rep("horizon_factor = 3.015", "horizon_factor = 100.0")], None, 2, &["discretization.horizon_factor"]),
    c("region_horizon_factor_0_5", &[Rep("spacing = 0.01\n", "spacing = 0.01\nhorizon_factor = 0.5\n")], None, 2, &["regions[0].horizon_factor"]),
    c("region_horizon_below_spacing", &[Rep("spacing = 0.01\n", "spacing = 0.01\nhorizon = 0.005\n")], None, 2, &["regions[0].horizon"]),
    c("region_horizon_and_factor", &[Rep("spacing = 0.01\n", "spacing = 0.01\nhorizon = 0.03\nhorizon_factor = 3.0\n")], None, 2, &["regions[0].horizon"]),
    c("region_zero_spacing", &[Rep("spacing = 0.01", "spacing = 0.0")], None, 2, &["regions[0].spacing"]),
    c("region_negative_spacing", &[Rep("spacing = 0.01", "spacing = -0.01")], None, 2, &["regions[0].spacing"]),
    c("region_box_max_below_min", &[Rep("min = [0.0, 0.0], max = [0.2, 0.1]", "min = [0.0, 0.0], max = [0.2, -0.1]")], None, 2, &["regions[0].box"]),
    c("region_extent_not_multiple", &[Rep("min = [0.0, 0.0], max = [0.2, 0.1]", "min = [0.0, 0.0], max = [0.205, 0.1]")], None, 2, &["regions[0].box"]),
    c("region_box_three_coords_in_2d", &[Rep("min = [0.0, 0.0], max = [0.2, 0.1]", "min = [0.0, 0.0, 0.0], max = [0.2, 0.1]")], None, 2, &["regions[0].box.min"]),
    c("region_box_nan_coord", &[Rep("min = [0.0, 0.0], max = [0.2, 0.1]", "min = [0.0, 0.0], max = [0.2, nan]")], None, 2, &["regions[0].box.max"]),
    c("overlapping_regions", &[Add("\n[[regions]]\nmaterial = \"soft\"\nspacing = 0.01\nbox = { min = [0.1, 0.0], max = [0.3, 0.1] }\n")], None, 2, &["regions[1].box", "regions[0].box"]),
    c("unknown_region_material", &[Rep("material = \"soft\"", "material = \"steel\"")], None, 2, &["regions[0].material", "steel"]),
    c("no_regions_no_point_files", &[Rep("[[regions]]\nmaterial = \"soft\"\nspacing = 0.01\nbox = { min = [0.0, 0.0], max = [0.2, 0.1] }\n", "")], None, 2, &["regions"]),
    c("holes_remove_everything", &[Add("\n[[holes]]\ncenter = [0.1, 0.05]\nradius = 1.0\n")], None, 2, &["holes"]),
    c("traction_on_held_points_only", &[Add("\n[[boundary]]\nname = \"right\"\nbox = { min = [0.19, 0.0], max = [0.2, 0.1] }\ndisplacement = { x = 0.0 }\n")], None, 2, &["loads[0]", "\"pull\" acts only on prescribed"]),
    c("hole_removes_a_whole_region", &[Add("\n[[regions]]\nmaterial = \"soft\"\nspacing = 0.01\nbox = { min = [0.3, 0.0], max = [0.32, 0.02] }\n[[holes]]\ncenter = [0.31, 0.01]\nradius = 0.03\n")], None, 2, &["regions[1]", "inside a hole"]),
    c("hole_negative_radius", &[Add("\n[[holes]]\ncenter = [0.1, 0.05]\nradius = -0.02\n")], None, 2, &["holes[0].radius"]),
    c("crack_3d_keys_in_2d", &[Add("\n[[cracks]]\norigin = [0.1, 0.0]\nedge1 = [0.0, 0.05]\nedge2 = [0.0, 0.0]\n")], None, 2, &["cracks[0]"]),
    // --- boundary conditions ---
    c("boundary_box_selects_no_point", &[Rep("min = [0.0, 0.0], max = [0.01, 0.1]", "min = [0.5, 0.5], max = [0.6, 0.6]")], None, 2, &["boundary[0].box"]),
    c("boundary_no_component", &[Rep("displacement = { x = 0.0, y = 0.0 }", "displacement = {}")], None, 2, &["boundary[0].displacement"]),
    c("boundary_missing_displacement", &[Rep("displacement = { x = 0.0, y = 0.0 }\n", "")], None, 2, &["boundary[0]", "displacement"]),
    c("boundary_z_in_2d", &[Rep("{ x = 0.0, y = 0.0 }", "{ x = 0.0, y = 0.0, z = 0.0 }")], None, 2, &["boundary[0].displacement.z"]),
    c("boundary_nan_value", &[Rep("{ x = 0.0, y = 0.0 }", "{ x = nan, y = 0.0 }")], None, 2, &["boundary[0].displacement.x"]),
    c("boundary_box_three_coords_in_2d", &[Rep("min = [0.0, 0.0], max = [0.01, 0.1]", "min = [0.0, 0.0], max = [0.01, 0.1, 1.0]")], None, 2, &["boundary[0].box.max"]),
    c("boundary_conflicting_values", &[Add("\n[[boundary]]\nname = \"left2\"\nbox = { min = [0.0, 0.0], max = [0.02, 0.1] }\ndisplacement = { x = 1e-3 }\n")], None, 2, &["boundary[1].displacement", "boundary[0]"]),
    c("boundary_duplicate_name", &[Add("\n[[boundary]]\nname = \"left\"\nbox = { min = [0.19, 0.0], max = [0.2, 0.1] }\ndisplacement = { x = 1e-3 }\n")], None, 2, &["boundary[1].name", "left"]),
    c("boundary_name_with_space", &[Rep("name = \"left\"", "name = \"left edge\"")], None, 2, &["boundary[0].name"]),
    // --- loads ---
    c("traction_without_face", &[Rep("face = \"+x\"\n", "")], None, 2, &["loads[0].face"]),
    c("traction_face_plus_q", &[Rep("face = \"+x\"", "face = \"+q\"")], None, 2, &["loads[0].face", "+q"]),
    c("traction_face_z_in_2d", &[Rep("face = \"+x\"", "face = \"-z\"")], None, 2, &["loads[0].face", "-z"]),
    c("body_force_with_face", &[Rep("kind = \"traction\"", "kind = \"body_force\"")], None, 2, &["loads[0].face"]),
    c("unknown_load_kind", &[Rep("kind = \"traction\"", "kind = \"pressure\"")], None, 2, &["loads[0].kind", "pressure"]),
    c("load_box_selects_no_point", &[Rep("min = [0.19, 0.0], max = [0.2, 0.1]", "min = [0.5, 0.5], max = [0.6, 0.6]")], None, 2, &["loads[0].box"]),
    c("load_value_three_components_in_2d", &[Rep("value = [1.0e6, 0.0]", "value = [1.0e6, 0.0, 0.0]")], None, 2, &["loads[0].value"]),
    c("load_value_infinite", &[Rep("value = [1.0e6, 0.0]", "value = [inf, 0.0]")], None, 2, &["loads[0].value"]),
    c("load_empty_name", &[Rep("name = \"pull\"", "name = \"\"")], None, 2, &["loads[0].name"]),
    // --- output ---
    c("profile_selects_no_point", &[Rep("from = [0.0, 0.05]\nto = [0.2, 0.05]", "from = [0.5, 0.5]\nto = [0.6, 0.5]")], None, 2, &["output.profiles[0]"]),
    c("profile_from_equals_to", &[Rep("to = [0.2, 0.05]", "to = [0.0, 0.05]")], None, 2, &["output.profiles[0]"]),
    c("profile_bad_name", &[Rep("name = \"centerline\"", "name = \"../escape\"")], None, 2, &["output.profiles[0].name"]),
    c("profile_duplicate_name", &[Add("\n[[output.profiles]]\nname = \"centerline\"\nfrom = [0.0, 0.02]\nto = [0.2, 0.02]\n")], None, 2, &["output.profiles[1].name"]),
    c("probe_wrong_dimension", &[Add("\n[[output.probes]]\nname = \"tip\"\nat = [0.2]\n")], None, 2, &["output.probes[0].at"]),
    // --- point files ---
    c("point_file_nan", &[Add(PF)], Some("0.30 0.05 1e-6\n0.31 nan 1e-6\n"), 2, &["point_files[0]", "line 2"]),
    c("point_file_ragged_rows", &[Add(PF)], Some("0.30 0.05 1e-6\n0.31 0.05 1e-6 0.03\n"), 2, &["point_files[0]", "line 2"]),
    c("point_file_too_few_columns", &[Add(PF)], Some("# x y volume\n0.30 1e-6\n"), 2, &["point_files[0]", "line 2"]),
    c("point_file_negative_volume", &[Add(PF)], Some("0.30 0.05 1e-6\n0.31 0.05 -1e-6\n"), 2, &["point_files[0]", "line 2"]),
    c("point_file_zero_volume", &[Add(PF)], Some("0.30 0.05 0\n"), 2, &["point_files[0]", "line 1"]),
    c("point_file_non_numeric", &[Add(PF)], Some("0.30 0.05 1e-6\n0.31 abc 1e-6\n"), 2, &["point_files[0]", "line 2", "abc"]),
    c("point_file_negative_horizon", &[Add(PF)], Some("0.30 0.05 1e-6 -0.03\n"), 2, &["point_files[0]", "line 1"]),
    c("point_file_unknown_material_column", &[Add(PF)], Some("0.30 0.05 1e-6 0.03 steel\n"), 2, &["point_files[0]", "line 1", "steel"]),
    c("point_file_unknown_default_material", &[Add("\n[[point_files]]\npath = \"pts.xyz\"\nmaterial = \"steel\"\n")], Some(ROWS_OK), 2, &["point_files[0].material", "steel"]),
    c("point_file_no_material", &[Add("\n[[point_files]]\npath = \"pts.xyz\"\n")], Some(ROWS_OK), 2, &["point_files[0]", "line 1"]),
    c("point_file_only_comments", &[Add(PF)], Some("# x y volume\n\n"), 2, &["point_files[0].path"]),
    c("point_file_empty_path", &[Add("\n[[point_files]]\npath = \" \"\nmaterial = \"soft\"\n")], None, 2, &["point_files[0].path"]),
    c("point_file_horizon_factor_0_5", &[Add("\n[[point_files]]\npath = \"pts.xyz\"\nmaterial = \"soft\"\nhorizon_factor = 0.5\n")], Some(ROWS_OK), 2, &["point_files[0].horizon_factor"]),
    c("point_file_duplicate_points", &[Add(PF)], Some("0.30 0.05 1e-6\n0.30 0.05 1e-6\n"), 2, &["point_files[0]", "duplicates"]),
    c("point_file_missing", &[Add("\n[[point_files]]\npath = \"missing.xyz\"\nmaterial = \"soft\"\n")], None, 4, &["missing.xyz"]),
    // --- numerical failures (exit 3) ---
    // Rigid motions are found from the constrained components before factorising.
    c("no_boundary_condition", &[Rep(LEFT_BC, "")], None, 3, &["is not held", "rotation about z"]),
    c("no_boundary_condition_lu", &[Rep(LEFT_BC, ""), Add("\n[solver]\nmethod = \"lu\"\n")], None, 3, &["is not held"]),
    c("only_x_held_y_load_rigid_y_translation", &[Rep("{ x = 0.0, y = 0.0 }", "{ x = 0.0 }"), Rep("value = [1.0e6, 0.0]", "value = [1.0e6, 1.0e3]")], None, 3, &["translation along (0.000, 1.000)"]),
    c("every_dof_prescribed", &[Rep("min = [0.0, 0.0], max = [0.01, 0.1]", "min = [0.0, 0.0], max = [0.2, 0.1]")], None, 3, &["every degree of freedom is prescribed"]),
    c("isolated_point_default_policy", &[Add(PF)], Some("1.0 1.0 1e-6\n"), 3, &["discretization.isolated_points", "point"]),
    c("point_held_by_a_single_bond", &[Rep("horizon_factor = 3.015", "horizon_factor = 3.015\nvolume_correction = \"none\""), Add(PF)], Some("0.235 0.055 1e-4 0.0405\n"), 3, &["non-positive pivot at point 200", "component 1"]),
    // The mixed-precision route falls back to double precision and reports the same point.
    c("point_held_by_a_single_bond_iterative", &[Add("\n[solver]\nmethod = \"iterative\"\n"), Rep("horizon_factor = 3.015", "horizon_factor = 3.015\nvolume_correction = \"none\""), Add(PF)], Some("0.235 0.055 1e-4 0.0405\n"), 3, &["not positive definite", "mechanism", "solver.method = \"cholesky\" names the point"]),
    c("point_held_by_a_single_bond_mixed_precision", &[Add("\n[solver]\nprecision = \"mixed\"\n"), Rep("horizon_factor = 3.015", "horizon_factor = 3.015\nvolume_correction = \"none\""), Add(PF)], Some("0.235 0.055 1e-4 0.0405\n"), 3, &["single-precision factorisation failed", "factorising in double precision", "non-positive pivot at point 200", "component 1"]),
    // Every large structure is checked before it is allocated: the bonds (an
    // estimate, then the running count), the stiffness pattern, the factor.
    c("bonds_above_memory_limit", &[Add("\n[solver]\nmemory_limit_gib = 1e-4\n")], None, 3, &["the bonds (an estimated", "would need", "solver.memory_limit_gib"]),
    c("bonds_counted_above_memory_limit", &[Whole(COARSE_OVER_FINE)], None, 3, &["the bonds (more than", "solver.memory_limit_gib"]),
    c("pattern_above_memory_limit", &[Add("\n[solver]\nmemory_limit_gib = 3e-4\n")], None, 3, &["the stiffness pattern", "solver.memory_limit_gib"]),
    c("factor_above_memory_limit", &[Whole(CUBE_3D), Rep("[solver]\n", "[solver]\nmethod = \"cholesky\"\n")], None, 3, &["the sparse factor would need", "solver.memory_limit_gib", "solver.method = \"iterative\""]),
    c("lu_on_a_large_body", &[Whole(CUBE_3D), Rep("spacing = 0.01", "spacing = 0.008"), Rep("[solver]\n", "[solver]\nmethod = \"lu\"\n")], None, 2, &["solver.method", "20000 free unknowns", "iterative"]),
    c("iterative_with_precision", &[Add("\n[solver]\nmethod = \"iterative\"\nprecision = \"mixed\"\n")], None, 2, &["solver.precision", "iterative"]),
    c("iterative_with_ordering", &[Add("\n[solver]\nmethod = \"iterative\"\nordering = \"amd\"\n")], None, 2, &["solver.ordering", "iterative"]),
    c("mixed_precision_in_a_fracture_run", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = 1.0e9\nfracture_energy = 100.0"), Add(QS), Add("\n[solver]\nprecision = \"mixed\"\n")], None, 2, &["solver.precision", "double precision"]),
    c("ordering_unknown", &[Add("\n[solver]\nordering = \"metis\"\n")], None, 2, &["solver.ordering", "metis"]),
    c("memory_limit_not_positive", &[Add("\n[solver]\nmemory_limit_gib = -1.0\n")], None, 2, &["solver.memory_limit_gib"]),
    c("memory_limit_nan_string", &[Add("\n[solver]\nmemory_limit_gib = \"lots\"\n")], None, 2, &["solver.memory_limit_gib"]),
    // --- `dhpd check` (validation only) rejects what it can see ---
    c("check_zero_youngs_modulus", &[Check, Rep("youngs_modulus = 1.0e9", "youngs_modulus = 0.0")], None, 2, &["materials.soft.youngs_modulus"]),
    c("check_unknown_key", &[Check, Rep("spacing = 0.01", "spacin = 0.01")], None, 2, &["regions[0].spacin"]),
    c("check_point_file_nan", &[Check, Add(PF)], Some("0.30 0.05 1e-6\n0.31 nan 1e-6\n"), 2, &["point_files[0]", "line 2"]),
    c("check_point_file_missing", &[Check, Add("\n[[point_files]]\npath = \"missing.xyz\"\nmaterial = \"soft\"\n")], None, 4, &["missing.xyz"]),
    c("check_empty_scene", &[Check, Whole("")], None, 2, &["scene", "model"]),
    // --- shear model ---
    c("shear_without_poisson_ratio", &[Rep("thickness = 0.01", "thickness = 0.01\nkind = \"shear\""), Rep("poisson_ratio = 0.3333333333333333\n", "")], None, 2, &["materials.soft.poisson_ratio", "shear"]),
    c("shear_in_1d", &[Whole(BAR_1D), Rep("dimension = \"1d\"", "dimension = \"1d\"\nkind = \"shear\"")], None, 2, &["model.kind"]),
    c("shear_single_row_singular_shape_tensor", &[Rep("thickness = 0.01", "thickness = 0.01\nkind = \"shear\""), Rep("max = [0.2, 0.1] }\n\n[[boundary]]", "max = [0.2, 0.01] }\n\n[[boundary]]"), Rep("min = [0.0, 0.0], max = [0.01, 0.1] }\ndisplacement", "min = [0.0, 0.0], max = [0.02, 0.01] }\ndisplacement"), Rep("box = { min = [0.19, 0.0], max = [0.2, 0.1] }", "box = { min = [0.19, 0.0], max = [0.2, 0.01] }"), Rep("from = [0.0, 0.05]\nto = [0.2, 0.05]", "from = [0.0, 0.005]\nto = [0.2, 0.005]")], None, 3, &["shape tensor of point"]),
    c("solver_method_unknown", &[Add("\n[solver]\nmethod = \"cg\"\n")], None, 2, &["solver.method"]),
    // Formerly known gaps, fixed: rigid motions named before factorising, JSON root field,
    // zero-extent boxes, a cap on the point count, `check` runs every pre-numerics check,
    // scene names safe as directory names, duplicates named by file and line.
    c("json_syntax_error_field", &[Json, Whole(r#"{"model": {"dimension": "1d"},}"#)], None, 2, &["scene:"]),
    c("only_x_held_rigid_y_translation", &[Rep("{ x = 0.0, y = 0.0 }", "{ x = 0.0 }")], None, 3, &["is not held", "translation along (0.000, 1.000)"]),
    c("no_boundary_condition_e_1", &[Rep(LEFT_BC, ""), Rep("youngs_modulus = 1.0e9", "youngs_modulus = 1.0")], None, 3, &["is not held"]),
    c("no_boundary_condition_balanced_loads", &[Rep(LEFT_BC, ""), Rep("youngs_modulus = 1.0e9", "youngs_modulus = 1.0"), Add(LEFT_PULL)], None, 3, &["is not held"]),
    c("no_boundary_condition_lu_message", &[Rep(LEFT_BC, ""), Add("\n[solver]\nmethod = \"lu\"\n")], None, 3, &["is not held", "point 0"]),
    c("point_file_duplicate_points_field", &[Add(PF)], Some("0.30 0.05 1e-6\n0.30 0.05 1e-6\n"), 2, &["point_files[0]", "line 2"]),
    c("region_zero_extent_box", &[Rep("min = [0.0, 0.0], max = [0.2, 0.1]", "min = [0.0, 0.0], max = [0.2, 0.0]")], None, 2, &["regions[0].box"]),
    c("region_spacing_too_fine", &[Rep("spacing = 0.01", "spacing = 1e-9")], None, 2, &["regions[0].spacing"]),
    c("check_boundary_box_selects_no_point", &[Check, Rep("min = [0.0, 0.0], max = [0.01, 0.1]", "min = [0.5, 0.5], max = [0.6, 0.6]")], None, 2, &["boundary[0].box"]),
    c("check_boundary_conflicting_values", &[Check, Add("\n[[boundary]]\nname = \"left2\"\nbox = { min = [0.0, 0.0], max = [0.02, 0.1] }\ndisplacement = { x = 1e-3 }\n")], None, 2, &["boundary[1].displacement"]),
    c("check_load_box_selects_no_point", &[Check, Rep("min = [0.19, 0.0], max = [0.2, 0.1]", "min = [0.5, 0.5], max = [0.6, 0.6]")], None, 2, &["loads[0].box"]),
    c("check_profile_selects_no_point", &[Check, Rep("from = [0.0, 0.05]\nto = [0.2, 0.05]", "from = [0.5, 0.5]\nto = [0.6, 0.5]")], None, 2, &["output.profiles[0]"]),
    c("check_point_file_duplicate_points", &[Check, Add(PF)], Some("0.30 0.05 1e-6\n0.30 0.05 1e-6\n"), 2, &["point_files[0]", "line 2"]),
    c("name_empty_default_out", &[NoOut, Rep("name = \"bad_scenes_base\"", "name = \"\"")], None, 2, &["name"]),
    c("name_parent_dir_default_out", &[NoOut, Rep("name = \"bad_scenes_base\"", "name = \"../escaped\"")], None, 2, &["name"]),
    // --- fracture (quasi-static) ---
    c("fracture_energy_in_a_static_scene", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = 1.0e9\nfracture_energy = 100.0")], None, 2, &["materials.soft.fracture_energy", "[quasi_static]"]),
    c("two_fracture_parameters", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = 1.0e9\nfracture_energy = 100.0\ncritical_stretch = 1e-3"), Add(QS)], None, 2, &["materials.soft.critical_stretch", "one fracture parameter"]),
    c("deviatoric_strain_for_bond_based", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = 1.0e9\ncritical_deviatoric_strain = 1e-3"), Add(QS)], None, 2, &["materials.soft.critical_deviatoric_strain", "stretch"]),
    c("critical_stretch_for_shear", &[Rep("thickness = 0.01", "thickness = 0.01\nkind = \"shear\""), Rep("youngs_modulus = 1.0e9", "youngs_modulus = 1.0e9\ncritical_stretch = 1e-3"), Add(QS)], None, 2, &["materials.soft.critical_stretch", "deviatoric"]),
    c("negative_fracture_energy", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = 1.0e9\nfracture_energy = -100.0"), Add(QS)], None, 2, &["materials.soft.fracture_energy", "finite positive"]),
    c("nan_critical_stretch", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = 1.0e9\ncritical_stretch = nan"), Add(QS)], None, 2, &["materials.soft.critical_stretch"]),
    c("quasi_static_without_fracture_parameter", &[Add(QS)], None, 2, &["quasi_static", "fracture parameter"]),
    c("quasi_static_without_max_load_factor", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = 1.0e9\nfracture_energy = 100.0"), Add("\n[quasi_static]\nstrategy = \"event\"\n")], None, 2, &["quasi_static", "max_load_factor"]),
    c("negative_max_load_factor", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = 1.0e9\nfracture_energy = 100.0"), Add("\n[quasi_static]\nmax_load_factor = -1.0\n")], None, 2, &["quasi_static.max_load_factor"]),
    c("unknown_strategy", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = 1.0e9\nfracture_energy = 100.0"), Add("\n[quasi_static]\nmax_load_factor = 1.0\nstrategy = \"arc_length\"\n")], None, 2, &["quasi_static.strategy", "arc_length"]),
    c("steps_with_event_strategy", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = 1.0e9\nfracture_energy = 100.0"), Add("\n[quasi_static]\nmax_load_factor = 1.0\nsteps = 10\n")], None, 2, &["quasi_static.steps", "applies to strategy"]),
    c("max_events_with_all", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = 1.0e9\nfracture_energy = 100.0"), Add("\n[quasi_static]\nmax_load_factor = 1.0\nstrategy = \"all\"\nmax_events = 10\n")], None, 2, &["quasi_static.max_events", "event"]),
    c("zero_steps", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = 1.0e9\nfracture_energy = 100.0"), Add("\n[quasi_static]\nmax_load_factor = 1.0\nstrategy = \"all\"\nsteps = 0\n")], None, 2, &["quasi_static.steps", "1..="]),
    c("tolerance_above_one", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = 1.0e9\nfracture_energy = 100.0"), Add("\n[quasi_static]\nmax_load_factor = 1.0\nstrategy = \"most_critical\"\ntolerance = 1.5\n")], None, 2, &["quasi_static.tolerance", "[0, 1)"]),
    c("stop_after_peak_above_one", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = 1.0e9\nfracture_energy = 100.0"), Add("\n[quasi_static]\nmax_load_factor = 1.0\nstop_after_peak = 2.0\n")], None, 2, &["quasi_static.stop_after_peak", "(0, 1)"]),
    c("quasi_static_with_nothing_loaded", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = 1.0e9\nfracture_energy = 100.0"), Rep("value = [1.0e6, 0.0]", "value = [0.0, 0.0]"), Add(QS)], None, 2, &["quasi_static", "zero"]),
    c("fracture_section_in_a_static_scene", &[Add("\n[fracture]\nshear_energy = \"pair\"\n")], None, 2, &["fracture", "[quasi_static]"]),
    c("unknown_shear_energy_counting", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = 1.0e9\nfracture_energy = 100.0"), Add(QS), Add("\n[fracture]\nshear_energy = \"both\"\n")], None, 2, &["fracture.shear_energy", "both"]),
    c("no_fail_box_with_three_coordinates", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = 1.0e9\nfracture_energy = 100.0"), Add(QS), Add("\n[[fracture.no_fail]]\nbox = { min = [0.0, 0.0, 0.0], max = [0.1, 0.1] }\n")], None, 2, &["fracture.no_fail[0].box.min", "needs 2"]),
    c("output_every_zero", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = 1.0e9\nfracture_energy = 100.0"), Add(QS), Add("\n[output]\nevery = 0\n")], None, 2, &["output.every"]),
    c("output_every_in_a_static_scene", &[Add("\n[output]\nevery = 5\n")], None, 2, &["output.every", "fracture and dynamics runs"]),
    c("refactor_iterations_in_a_static_scene", &[Add("\n[solver]\nrefactor_iterations = 5\n")], None, 2, &["solver.refactor_iterations", "fracture runs"]),
    // --- explicit dynamics ---
    c("density_in_a_static_scene", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = 1.0e9\ndensity = 1000.0")], None, 2, &["materials.soft.density", "[dynamics]"]),
    c("dynamics_without_density", &[Add(DY)], None, 2, &["materials.soft.density", "density"]),
    c("dynamics_without_length", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = 1.0e9\ndensity = 1000.0"), Add("\n[dynamics]\nsafety_factor = 0.5\n")], None, 2, &["dynamics", "steps or end_time"]),
    c("dynamics_steps_and_end_time", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = 1.0e9\ndensity = 1000.0"), Add("\n[dynamics]\nsteps = 5\nend_time = 1.0\n")], None, 2, &["dynamics.end_time", "not both"]),
    c("dynamics_time_step_above_stable", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = 1.0e9\ndensity = 1000.0"), Add("\n[dynamics]\nsteps = 5\ntime_step = 1.0\n")], None, 2, &["dynamics.time_step", "stable time step"]),
    c("dynamics_forced_unstable_diverges", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = 1.0e9\ndensity = 1000.0"), Add("\n[dynamics]\nsteps = 2000\ntime_step = 1e-4\nforce_time_step = true\nbalance_tolerance = inf\n")], None, 3, &["diverged", "point"]),
    // The same step fails early by its energy balance, before it diverges.
    c("dynamics_forced_unstable_loses_its_energy_balance", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = 1.0e9\ndensity = 1000.0"), Add("\n[dynamics]\nsteps = 2000\ntime_step = 1e-4\nforce_time_step = true\n")], None, 3, &["energy balance at step 10", "dynamics.balance_tolerance"]),
    c("dynamics_safety_factor_above_one", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = 1.0e9\ndensity = 1000.0"), Add("\n[dynamics]\nsteps = 5\nsafety_factor = 1.5\n")], None, 2, &["dynamics.safety_factor", "(0, 1]"]),
    c("dynamics_record_every_zero", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = 1.0e9\ndensity = 1000.0"), Add("\n[dynamics]\nsteps = 5\nrecord_every = 0\n")], None, 2, &["dynamics.record_every"]),
    c("dynamics_negative_damping", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = 1.0e9\ndensity = 1000.0"), Add("\n[dynamics]\nsteps = 5\ndamping = -1.0\n")], None, 2, &["dynamics.damping"]),
    c("dynamics_and_quasi_static", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = 1.0e9\ndensity = 1000.0\nfracture_energy = 100.0"), Add(QS), Add(DY)], None, 2, &["dynamics", "one driver"]),
    c("velocity_in_a_static_scene", &[Rep("displacement = { x = 0.0, y = 0.0 }", "velocity = { x = 0.0, y = 0.0 }")], None, 2, &["boundary[0].velocity", "[dynamics]"]),
    c("velocity_and_displacement", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = 1.0e9\ndensity = 1000.0"), Rep("displacement = { x = 0.0, y = 0.0 }", "displacement = { x = 0.0 }\nvelocity = { y = 0.0 }"), Add(DY)], None, 2, &["boundary[0].velocity", "not both"]),
    c("ramp_without_duration", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = 1.0e9\ndensity = 1000.0"), Rep("displacement = { x = 0.0, y = 0.0 }", "displacement = { x = 0.0, y = 0.0 }\ntime_function = { kind = \"ramp\" }"), Add(DY)], None, 2, &["boundary[0].time_function.duration"]),
    c("table_times_not_increasing", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = 1.0e9\ndensity = 1000.0"), Rep("value = [1.0e6, 0.0]", "value = [1.0e6, 0.0]\ntime_function = { kind = \"table\", times = [0.0, 2.0, 1.0], values = [0.0, 1.0, 1.0] }"), Add(DY)], None, 2, &["loads[0].time_function.times[2]", "increasing"]),
    c("time_function_in_a_static_scene", &[Rep("value = [1.0e6, 0.0]", "value = [1.0e6, 0.0]\ntime_function = { kind = \"constant\" }")], None, 2, &["loads[0].time_function", "[dynamics]"]),
    c("initial_condition_sets_nothing", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = 1.0e9\ndensity = 1000.0"), Add(DY), Add("\n[[initial_conditions]]\nbox = { min = [0.0, 0.0], max = [0.1, 0.1] }\n")], None, 2, &["initial_conditions[0]", "sets nothing"]),
    c("gaussian_amplitude_wrong_length", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = 1.0e9\ndensity = 1000.0"), Add(DY), Add("\n[[initial_conditions]]\ngaussian = { center = [0.1], width = 0.02, amplitude = [1e-6] }\n")], None, 2, &["initial_conditions[0].gaussian.amplitude", "give 2"]),
    c("initial_condition_box_selects_no_point", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = 1.0e9\ndensity = 1000.0"), Add(DY), Add("\n[[initial_conditions]]\nbox = { min = [5.0, 5.0], max = [6.0, 6.0] }\nvelocity = { x = 1.0 }\n")], None, 2, &["initial_conditions[0].box", "selects no point"]),
    c("initial_conditions_in_a_static_scene", &[Add("\n[[initial_conditions]]\nvelocity = { x = 1.0 }\n")], None, 2, &["initial_conditions", "[dynamics]"]),
    c("relaxation_with_density", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = 1.0e9\ndensity = 1000.0"), Add("\n[dynamics]\nmethod = \"relaxation\"\nsteps = 100\n")], None, 2, &["materials.soft.density", "fictitious"]),
    c("relaxation_with_time_step", &[Add("\n[dynamics]\nmethod = \"relaxation\"\nsteps = 100\ntime_step = 1e-6\n")], None, 2, &["dynamics.time_step", "verlet"]),
    c("relaxation_with_fracture", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = 1.0e9\nfracture_energy = 100.0"), Add("\n[dynamics]\nmethod = \"relaxation\"\nsteps = 100\n")], None, 2, &["dynamics.method", "breaks no bond"]),
    c("linearised_kernel_with_fracture", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = 1.0e9\ndensity = 1000.0\nfracture_energy = 100.0"), Add("\n[dynamics]\nsteps = 5\nkernel = \"linearised\"\n")], None, 2, &["dynamics.kernel", "nonlinear"]),
    c("traditional_horizons_in_a_static_scene", &[Rep("dimension = \"plane_stress\"", "dimension = \"plane_stress\"\nhorizons = \"traditional\"")], None, 2, &["model.horizons", "explicit dynamics"]),
    c("refactor_iterations_in_dynamics", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = 1.0e9\ndensity = 1000.0"), Add(DY), Add("\n[solver]\nrefactor_iterations = 5\n")], None, 2, &["solver.refactor_iterations", "quasi-static"]),
    // --- outside-in hardening ---
    c("explicit_horizon_too_large", &[Rep("spacing = 0.01", "spacing = 0.01\nhorizon = 10.0")], None, 2, &["regions[0].horizon", "implausibly large", "1000"]),
    c("horizon_as_wide_as_the_body", &[Rep("spacing = 0.01", "spacing = 0.01\nhorizon_factor = 20.0")], None, 2, &["regions[0].horizon_factor", "not smaller than the body"]),
    c("point_file_horizon_too_large", &[Add(PF)], Some("0.30 0.05 1e-6 1.0\n0.31 0.05 1e-6 1.0\n"), 2, &["point_files[0]", "implausibly large"]),
    c("probe_outside_the_body", &[Add("\n[[output.probes]]\nname = \"far\"\nat = [5.0, 5.0]\n")], None, 2, &["output.probes[0].at", "outside the body"]),
    c("output_name_too_long", &[NoOut, Rep("name = \"bad_scenes_base\"", "name = \"aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa\"")], None, 2, &["--out", "cannot create"]),
    c("youngs_modulus_overflows_the_stiffness", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = 1.0e308")], None, 2, &["materials.soft.youngs_modulus", "floating-point range"]),
    // --- mesh import ---
    c("mesh_group_unknown", &[Whole(MESH_STRIP), Rep("group = \"left\"", "group = \"lft\"")], None, 2, &["boundary[0].group", "no physical group \"lft\"", "left, right"]),
    c("group_without_meshes", &[Rep("box = { min = [0.0, 0.0], max = [0.01, 0.1] }\ndisplacement", "group = \"left\"\ndisplacement")], None, 2, &["boundary[0].group", "[[meshes]]"]),
    c("boundary_box_and_group", &[Whole(MESH_STRIP), Rep("group = \"left\"", "group = \"left\"\nbox = { min = [0.0, 0.0], max = [0.1, 0.1] }")], None, 2, &["boundary[0].group", "not both"]),
    c("boundary_without_box_or_group", &[Rep("box = { min = [0.0, 0.0], max = [0.01, 0.1] }\ndisplacement", "displacement")], None, 2, &["boundary[0].box", "missing"]),
    c("traction_on_a_surface_group", &[Whole(MESH_STRIP), Rep("group = \"right\"", "group = \"stiff\"")], None, 2, &["loads[0].group", "no 1D elements"]),
    c("traction_on_a_group_with_a_face", &[Whole(MESH_STRIP), Rep("group = \"right\"", "group = \"right\"\nface = \"+x\"")], None, 2, &["loads[0].face", "remove `face`"]),
    c("mesh_group_mapped_to_unknown_material", &[Whole(MESH_STRIP), Rep("stiff = \"stiff\"", "stiff = \"steel\"")], None, 2, &["meshes[0].groups.stiff", "steel"]),
    c("mesh_material_map_names_a_missing_group", &[Whole(MESH_STRIP), Rep("soft = \"soft\"", "sofft = \"soft\"")], None, 2, &["meshes[0].groups.sofft", "no 2D physical group", "soft, stiff"]),
    c("mesh_cells_without_material", &[Whole(MESH_STRIP), Rep(", stiff = \"stiff\"", "")], None, 2, &["meshes[0]", "in no group of `groups`"]),
    c("mesh_without_material_or_groups", &[Whole(MESH_STRIP), Rep("groups = { soft = \"soft\", stiff = \"stiff\" }\n", "")], None, 2, &["meshes[0].material", "missing"]),
    c("mesh_file_not_a_mesh", &[Whole(MESH_STRIP), MESH_PTS, Rep(concat!(env!("CARGO_MANIFEST_DIR"), "\""), "pts.xyz\"")], Some("0.30 0.05 1e-6\n"), 2, &["meshes[0].path", "pts.xyz"]),
    c("mesh_file_missing", &[Whole(MESH_STRIP), MESH_PTS, Rep(concat!(env!("CARGO_MANIFEST_DIR"), "\""), "missing.msh\"")], None, 4, &["missing.msh"]),
    c("mesh_3d_read_as_2d", &[Whole(MESH_STRIP), Rep("bimaterial_strip.msh", "cube_tet_h0.25.msh"), Rep("groups = { soft = \"soft\", stiff = \"stiff\" }", "material = \"soft\"")], None, 2, &["meshes[0].path", "3D elements"]),
    c("mesh_in_1d", &[Whole(MESH_STRIP), Rep("plane_stress", "1d")], None, 2, &["meshes[0]", "2D or 3D"]),
    // --- hardening round 3 (issue 17) ---
    // `face` shares a traction by grid spacing: on a triangle mesh it gave 1.414 × the force.
    c("traction_face_on_a_mesh", &[Whole(MESH_STRIP), Rep("group = \"right\"", "face = \"+x\"")], None, 2, &["loads[0].face", "meshes[0] (element", "`group`"]),
    c("traction_face_on_a_point_file", &[Add(PF), Rep("box = { min = [0.19, 0.0], max = [0.2, 0.1] }\nvalue", "value")], Some(ROWS_OK), 2, &["loads[0].face", "point_files[0] (line 2)", "regions"]),
    // Bodies of different sources covering the same space would double the material.
    c("mesh_overlaps_a_region", &[Add(STRIP_MESH)], None, 2, &["meshes[0]", "inside regions[0].box", "must not overlap"]),
    c("point_file_inside_a_region", &[Add(PF)], Some("0.1 0.05 1e-6\n"), 2, &["point_files[0]", "line 1", "inside regions[0].box"]),
    c("point_file_inside_a_mesh", &[Whole(MESH_STRIP), Add(PF)], Some("0.615 0.005 1e-6\n"), 2, &["point_files[0]", "line 1", "in the cell of meshes[0]"]),
    c("two_meshes_overlap", &[Whole(MESH_STRIP), Add(HOLE_MESH)], None, 2, &["meshes[0]", "in the cell of meshes[1]"]),
    // A load factor whose states overflow is refused after the first solve, naming it:
    // the largest unit quantity is the clamp's reaction, 1e6 Pa × 0.1 m × 0.01 m = 1e3 N,
    // so the bound is 1e250 / 1e3.
    c("max_load_factor_overflows_the_states", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = 1.0e9\nfracture_energy = 100.0"), Add("\n[quasi_static]\nmax_load_factor = 1e300\n")], None, 2, &["quasi_static.max_load_factor", "at most 1.000e247"]),
    c("max_load_factor_1e308", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = 1.0e9\nfracture_energy = 100.0"), Add("\n[quasi_static]\nmax_load_factor = 1e308\nstrategy = \"all\"\n")], None, 2, &["quasi_static.max_load_factor", "at most"]),
    // Damping beyond the damped Verlet's bound α Δt ≤ 2 (derived in src/drivers/dynamics).
    c("dynamics_damping_above_the_verlet_bound", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = 1.0e9\ndensity = 1000.0"), Add("\n[dynamics]\nsteps = 5\ndamping = 1e12\n")], None, 2, &["dynamics.damping", "α Δt", "2/Δt"]),
    c("dynamics_balance_tolerance_not_positive", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = 1.0e9\ndensity = 1000.0"), Add("\n[dynamics]\nsteps = 5\nbalance_tolerance = 0.0\n")], None, 2, &["dynamics.balance_tolerance", "positive"]),
    c("dynamics_energy_balance_above_tolerance", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = 1.0e9\ndensity = 1000.0"), Add("\n[dynamics]\nsteps = 50\nbalance_tolerance = 1e-15\n")], None, 3, &["energy balance", "dynamics.balance_tolerance"]),
    // Dynamic relaxation seeks a static equilibrium: a free body is refused before the run.
    c("relaxation_of_a_free_body", &[Rep(LEFT_BC, ""), Add("\n[dynamics]\nmethod = \"relaxation\"\nsteps = 20000\n")], None, 3, &["is not held", "rotation about z"]),
    c("check_relaxation_of_a_free_body", &[Check, Rep(LEFT_BC, ""), Add("\n[dynamics]\nmethod = \"relaxation\"\nsteps = 20000\n")], None, 3, &["is not held"]),
    // A smallest step that no longer changes λ looped for ever; refused (steps 100: at least 1e-10).
    c("min_step_fraction_below_double_resolution", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = 1.0e9\nfracture_energy = 100.0"), Add("\n[quasi_static]\nmax_load_factor = 1.0\nstrategy = \"all\"\nmax_broken_per_step = 1\nmin_step_fraction = 1e-300\n")], None, 2, &["quasi_static.min_step_fraction", "[1e-10, 1]", "never ends"]),
    // Names go into CSV columns and rows: restricted as scene names are, and unique.
    c("material_name_with_a_comma", &[Rep("[materials.soft]", "[materials.\"so,ft\"]"), Rep("material = \"soft\"", "material = \"so,ft\"")], None, 2, &["materials.so,ft", "letters, digits"]),
    c("material_name_with_a_newline", &[Rep("[materials.soft]", "[materials.\"so\\nft\"]"), Rep("material = \"soft\"", "material = \"so\\nft\"")], None, 2, &["materials.so", "letters, digits"]),
    c("probe_duplicate_name", &[Add("\n[[output.probes]]\nname = \"tip\"\nat = [0.195, 0.05]\n[[output.probes]]\nname = \"tip\"\nat = [0.105, 0.05]\n")], None, 2, &["output.probes[1].name", "used twice"]),
    c("no_fail_box_selects_no_point", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = 1.0e9\nfracture_energy = 100.0"), Add(QS), Add("\n[[fracture.no_fail]]\nbox = { min = [0.5, 0.5], max = [0.6, 0.6] }\n")], None, 2, &["fracture.no_fail[0].box", "selects no point"]),
    c("traction_overflows_the_forces", &[Rep("value = [1.0e6, 0.0]", "value = [1.7e308, 1.7e308]")], None, 2, &["loads[0].value", "not finite"]),
    // --- issue 17, items 10-12: messages that name the cause ---
    // Two rows 1e-13 m apart: a duplicate to round-off, named by both lines and the distance.
    c("point_file_rows_1e_13_apart", &[Add(PF)], Some("0.30 0.05 1e-6\n0.3000000000001 0.05 1e-6\n"), 2, &["point_files[0] (line 2)", "point_files[0] (line 1)", "e-13 m from", "duplicates to round-off"]),
    // 1e-300 m apart: the distance is measured without underflow, not called 0.
    c("point_file_rows_1e_300_apart", &[Add(PF)], Some("0.0 0.3 1e-6\n1e-300 0.3 1e-6\n"), 2, &["point_files[0] (line 2)", "1.000e-300 m from"]),
    // Lengths whose squares leave the normal doubles are refused, naming the field.
    c("region_spacing_below_the_length_range", &[Whole(BAR_1D), Rep("poisson_ratio = 0.25\n", ""), Rep("spacing = 0.01", "spacing = 1e-160"), Rep("max = [0.1]", "max = [1e-159]"), Rep("max = [0.01]", "max = [1e-160]")], None, 2, &["regions[0].spacing", "1e-160", "[1e-150, 1e150] m"]),
    c("region_box_beyond_the_length_range", &[Rep("min = [0.0, 0.0], max = [0.2, 0.1]", "min = [1e200, 0.0], max = [1e200, 0.1]")], None, 2, &["regions[0].box", "coordinate 1e200", "1e150"]),
    c("point_file_spacing_below_the_length_range", &[Add(PF)], Some("0.30 0.05 1e-305\n"), 2, &["point_files[0] (line 1)", "spacing", "[1e-150, 1e150] m"]),
    // A ratio of 1e152 spacings is printed in exponent form (it had 153 digits).
    c("horizon_ratio_in_exponent_form", &[Rep("spacing = 0.01", "spacing = 0.01\nhorizon = 1e150")], None, 2, &["regions[0].horizon", "horizon 1e150 is 1.000e152 spacings"]),
    c("point_file_value_is_clipped", &[Add(PF)], Some("0.30 0.05 1e-6\n0.31 aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa 1e-6\n"), 2, &["point_files[0]", "line 2", "aaaa…aaaa"]),
    // An initial state beyond double precision names its initial condition (it blamed the time step).
    c("initial_velocity_beyond_double_precision", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = 1.0e9\ndensity = 1000.0"), Add(DY), Add("\n[[initial_conditions]]\nvelocity = { x = 1e300 }\n")], None, 2, &["initial_conditions[0].velocity", "1e300 m/s", "kinetic energy"]),
    c("initial_gaussian_beyond_double_precision", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = 1.0e9\ndensity = 1000.0"), Add(DY), Add("\n[[initial_conditions]]\ngaussian = { center = [0.1, 0.05], width = 0.02, amplitude = [1e300, 0.0] }\n")], None, 2, &["initial_conditions[0].gaussian", "displacement"]),
    // A stable step that diverges blames the magnitudes, not the step.
    c("dynamics_load_beyond_double_precision", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = 1.0e9\ndensity = 1000.0"), Rep("value = [1.0e6, 0.0]", "value = [1.0e200, 0.0]"), Add("\n[dynamics]\nsteps = 400\nbalance_tolerance = inf\n")], None, 3, &["diverged at step", "within the stable", "a load"]),
    // A forced unstable step is named as the cause, at the step that diverged.
    // The iterative route stops at the round-off floor of a 400,000-point chain
    // (κ ≈ n²); the refusal names the direct route, which solves it.
    c("iterative_route_on_a_long_chain", &[Whole(BAR_1D), Rep("poisson_ratio = 0.25\n", ""), Rep("spacing = 0.01", "spacing = 2.5e-6"), Rep("max = [0.1]", "max = [1.0]"), Rep("max = [0.01]", "max = [2.5e-6]"), Add("[[loads]]\nname = \"pull\"\nkind = \"traction\"\nface = \"+x\"\nvalue = [1.0]\n[solver]\nmethod = \"iterative\"\n")], None, 3, &["solve rejected", "round-off floor", "solver.method = \"cholesky\" solves directly"]),
    c("dynamics_forced_unstable_names_the_step", &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = 1.0e9\ndensity = 1000.0"), Add("\n[dynamics]\nsteps = 2000\ntime_step = 1e-4\nforce_time_step = true\nbalance_tolerance = inf\nrecord_every = 1000\n\n[output]\nevery = 1\n")], None, 3, &["diverged at step", "has a non-finite displacement", "dynamics.force_time_step = true"]),

];
/// A per-case temporary directory, removed on drop.
struct TempDir(PathBuf);

impl TempDir {
    fn new(tag: &str) -> Self {
        let dir =
            std::env::temp_dir().join(format!("dhpd-bad-scenes-{}-{tag}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("create the case directory");
        TempDir(dir)
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// How to invoke the binary.
#[derive(Clone, Copy, PartialEq)]
enum Mode {
    Run,
    RunNoOut,
    Check,
}

/// Applies `edits` to [`BASE`]; returns the text and whether it is JSON.
fn scene_text(edits: &[Edit], case: &str) -> (String, bool) {
    let mut text = BASE.to_string();
    let mut json = false;
    for e in edits {
        match *e {
            Rep(from, to) => {
                let n = text.matches(from).count();
                assert_eq!(
                    n, 1,
                    "case {case}: {from:?} occurs {n} times in the scene, expected once"
                );
                text = text.replacen(from, to, 1);
            }
            Add(t) => text.push_str(t),
            Pre(t) => text.insert_str(0, t),
            Whole(t) => text = t.to_string(),
            Json => json = true,
            Check | NoOut => {}
        }
    }
    (text, json)
}

/// Files the harness writes into a case directory; anything else is output.
const INPUTS: &[&str] = &["scene.toml", "scene.json", "pts.xyz"];

/// What one run produced.
struct Outcome {
    code: Option<i32>,
    stdout: String,
    stderr: String,
    /// The `--out` directory exists afterwards.
    out_exists: bool,
    /// Leftover `.out.partial-*` siblings.
    partials: Vec<String>,
    /// Any other entry the run created in the case directory (its working directory).
    strays: Vec<String>,
}

fn run_scene(dir: &Path, text: &str, json: bool, points: Option<&str>, mode: Mode) -> Outcome {
    let scene = dir.join(if json { "scene.json" } else { "scene.toml" });
    std::fs::write(&scene, text).expect("write the scene");
    if let Some(p) = points {
        std::fs::write(dir.join("pts.xyz"), p).expect("write the point file");
    }
    let out = dir.join("out");
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_dhpd"));
    match mode {
        Mode::Run => cmd.arg("run").arg(&scene).arg("--out").arg(&out),
        Mode::RunNoOut => cmd.arg("run").arg(&scene),
        Mode::Check => cmd.arg("check").arg(&scene),
    };
    let o = cmd
        .current_dir(dir)
        .env_remove("DHPD_PROGRESS_SECONDS")
        .output()
        .expect("start dhpd");
    let entries: Vec<String> = std::fs::read_dir(dir)
        .expect("list the case directory")
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| !INPUTS.contains(&n.as_str()))
        .collect();
    let (partials, rest): (Vec<String>, Vec<String>) = entries
        .into_iter()
        .partition(|n| n.starts_with('.') && n.contains(".partial-"));
    Outcome {
        code: o.status.code(),
        stdout: String::from_utf8_lossy(&o.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&o.stderr).into_owned(),
        out_exists: out.exists(),
        partials,
        strays: rest.into_iter().filter(|n| n != "out").collect(),
    }
}

fn run_case(case: &Case) -> Outcome {
    let dir = TempDir::new(case.name);
    let (text, json) = scene_text(case.edits, case.name);
    let mode = if case.edits.iter().any(|e| matches!(e, Check)) {
        Mode::Check
    } else if case.edits.iter().any(|e| matches!(e, NoOut)) {
        Mode::RunNoOut
    } else {
        Mode::Run
    };
    run_scene(&dir.0, &text, json, case.points, mode)
}

/// Longest run of digits a message may print (a double in shortest form has 17).
const MAX_DIGITS: usize = 24;

/// Largest stderr of a failing case (echoed user text is clipped to 80 characters).
const MAX_STDERR_BYTES: usize = 4096;

/// Everything wrong with an outcome, empty when the case behaves as required.
fn problems(case: &Case, o: &Outcome) -> Vec<String> {
    let mut p = Vec::new();
    if o.code != Some(case.code) {
        p.push(format!("exit code {:?}, expected {}", o.code, case.code));
    }
    for s in case.expect {
        if !o.stderr.contains(s) {
            p.push(format!("stderr lacks {s:?}"));
        }
    }
    if o.stderr.contains("panicked") {
        p.push("the binary panicked".into());
    }
    // Numbers in messages are in shortest or exponent form (1e300 printed
    // with `{}` has 301 digits), and echoed user text is clipped.
    if let Some(run) = o
        .stderr
        .split(|c: char| !c.is_ascii_digit())
        .find(|run| run.len() > MAX_DIGITS)
    {
        p.push(format!("stderr holds a run of {} digits", run.len()));
    }
    if o.stderr.len() > MAX_STDERR_BYTES {
        p.push(format!("stderr holds {} bytes", o.stderr.len()));
    }
    if o.out_exists {
        p.push("the --out directory exists".into());
    }
    if !o.partials.is_empty() {
        p.push(format!("partial output left behind: {:?}", o.partials));
    }
    if !o.strays.is_empty() {
        p.push(format!("output written next to the scene: {:?}", o.strays));
    }
    p
}

fn show() -> bool {
    std::env::var_os("DHPD_BAD_SCENES_SHOW").is_some()
}

#[test]
fn bad_scenes_fail_cleanly_and_name_the_field() {
    let start = Instant::now();
    let mut names = std::collections::HashSet::new();
    let mut failures = Vec::new();
    for case in CASES {
        assert!(names.insert(case.name), "duplicate case name {}", case.name);
        let o = run_case(case);
        if show() {
            eprintln!("[{}] exit {:?}\n{}", case.name, o.code, o.stderr.trim_end());
        }
        let p = problems(case, &o);
        if !p.is_empty() {
            failures.push(format!(
                "{}: {}\n    stderr: {}\n    stdout: {}",
                case.name,
                p.join("; "),
                o.stderr.trim_end(),
                o.stdout.trim_end()
            ));
        }
    }
    eprintln!(
        "{} bad scenes in {:.2} s",
        CASES.len(),
        start.elapsed().as_secs_f64()
    );
    assert!(CASES.len() >= 30);
    assert!(
        failures.is_empty(),
        "{} of {} bad scenes misbehaved:\n{}",
        failures.len(),
        CASES.len(),
        failures.join("\n")
    );
}

/// Positive control: the unedited base scene solves and writes its results,
/// so a broken binary cannot pass the test above by failing everything.
#[test]
fn base_scene_runs() {
    let dir = TempDir::new("base");
    let o = run_scene(&dir.0, BASE, false, None, Mode::Run);
    assert_eq!(
        o.code,
        Some(0),
        "stderr: {}\nstdout: {}",
        o.stderr,
        o.stdout
    );
    assert!(
        dir.0.join("out").join("summary.json").is_file(),
        "no summary.json"
    );
    assert!(
        dir.0.join("out").join("profile_centerline.csv").is_file(),
        "no profile"
    );
    assert!(
        o.partials.is_empty(),
        "partial output left behind: {:?}",
        o.partials
    );
    assert!(
        o.strays.is_empty(),
        "output written next to the scene: {:?}",
        o.strays
    );
}

/// The point-file and 1D fixtures are themselves valid, so the cases built on them
/// fail only because of their one defect.
#[test]
fn fixtures_are_valid() {
    let dir = TempDir::new("fixture-pf");
    let (text, _) = scene_text(&[Add(PF)], "fixture-pf");
    let o = run_scene(&dir.0, &text, false, Some(ROWS_OK), Mode::Run);
    // The two rows sit apart from the plate, bonded only to each other: a free
    // body, so the run may fail numerically, but never on input.
    assert_ne!(o.code, Some(2), "stderr: {}", o.stderr);
    let dir = TempDir::new("fixture-1d");
    let (text, _) = scene_text(
        &[Whole(BAR_1D), Rep("poisson_ratio = 0.25\n", "")],
        "fixture-1d",
    );
    let o = run_scene(&dir.0, &text, false, None, Mode::Run);
    assert_eq!(o.code, Some(0), "stderr: {}", o.stderr);
}

/// A failed run must not touch an earlier result in `--out`.
#[test]
fn failed_run_keeps_previous_output() {
    let dir = TempDir::new("keep");
    let out = dir.0.join("out");
    std::fs::create_dir_all(&out).unwrap();
    std::fs::write(out.join("marker"), "previous").unwrap();
    let (text, _) = scene_text(
        &[Rep("youngs_modulus = 1.0e9", "youngs_modulus = 0.0")],
        "keep",
    );
    let scene = dir.0.join("scene.toml");
    std::fs::write(&scene, text).unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_dhpd"))
        .arg("run")
        .arg(&scene)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(
        std::fs::read_to_string(out.join("marker")).unwrap(),
        "previous"
    );
}

/// `--out` must never replace a directory that is not a dhpd result: not the
/// working directory (`.`), not its parent, not a non-empty foreign directory.
/// A previous result (holding `summary.json`) is replaced only by a successful run.
#[test]
fn output_directory_is_never_clobbered() {
    let dir = TempDir::new("clobber");
    let scene = dir.0.join("scene.toml");
    std::fs::write(&scene, BASE).unwrap();
    let foreign = dir.0.join("foreign");
    std::fs::create_dir_all(&foreign).unwrap();
    std::fs::write(foreign.join("thesis.tex"), "precious").unwrap();
    for target in [Path::new("."), Path::new(".."), foreign.as_path()] {
        let o = Command::new(env!("CARGO_BIN_EXE_dhpd"))
            .arg("run")
            .arg(&scene)
            .arg("--out")
            .arg(target)
            .current_dir(&dir.0)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(
            o.status.code(),
            Some(2),
            "--out {}: {stderr}",
            target.display()
        );
        assert!(
            stderr.contains("--out"),
            "--out {}: {stderr}",
            target.display()
        );
        assert!(scene.exists() && foreign.join("thesis.tex").exists());
    }
    let result = dir.0.join("result");
    for _ in 0..2 {
        let o = Command::new(env!("CARGO_BIN_EXE_dhpd"))
            .arg("run")
            .arg(&scene)
            .arg("--out")
            .arg(&result)
            .output()
            .unwrap();
        assert_eq!(
            o.status.code(),
            Some(0),
            "{}",
            String::from_utf8_lossy(&o.stderr)
        );
        assert!(result.join("summary.json").is_file());
    }
}

/// Inputs that are not regular UTF-8 files: a named pipe as a point file (would
/// block forever), a device as the scene (would never end), a UTF-16 scene. Each
/// is refused at once, naming the field, with exit code 2.
#[cfg(unix)]
#[test]
fn special_files_and_encodings_are_refused() {
    let dir = TempDir::new("special-files");
    let scene = dir.0.join("fifo.toml");
    std::fs::write(
        &scene,
        "[model]\ndimension = \"plane_stress\"\n[materials.m]\nyoungs_modulus = 1.0\n\
         [[point_files]]\npath = \"pipe.xyz\"\nmaterial = \"m\"\n",
    )
    .expect("write the scene");
    let made = Command::new("mkfifo")
        .arg(dir.0.join("pipe.xyz"))
        .status()
        .expect("mkfifo runs");
    assert!(made.success());
    let utf16 = dir.0.join("utf16.toml");
    let text: Vec<u8> = [0xFF, 0xFE]
        .into_iter()
        .chain(BASE.encode_utf16().flat_map(|c| c.to_le_bytes()))
        .collect();
    std::fs::write(&utf16, text).expect("write the UTF-16 scene");
    for (path, field, message) in [
        (scene.as_path(), "point_files[0].path", "not a regular file"),
        (Path::new("/dev/zero"), "scene", "not a regular file"),
        (utf16.as_path(), "scene", "UTF-16"),
    ] {
        let mut child = Command::new(env!("CARGO_BIN_EXE_dhpd"))
            .arg("check")
            .arg(path)
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .expect("dhpd starts");
        let start = Instant::now();
        let status = loop {
            if let Some(status) = child.try_wait().expect("wait") {
                break status;
            }
            if start.elapsed().as_secs() > 20 {
                let _ = child.kill();
                panic!("dhpd check {} did not return", path.display());
            }
            std::thread::sleep(std::time::Duration::from_millis(20));
        };
        let out = child.wait_with_output().expect("output");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(status.code(), Some(2), "{}: {stderr}", path.display());
        assert!(
            stderr.contains(field) && stderr.contains(message),
            "{}: {stderr}",
            path.display()
        );
    }
}

/// Issue 10: a traction of 1e160 Pa (forces of 1e157 N) solves like 1 Pa does:
/// the norms are scaled, so the residual is not lost to an overflow of the
/// squares (which reported a residual of 0 before), and the reaction balances
/// the load to round-off.
#[test]
fn huge_tractions_keep_their_residual_and_balance() {
    let text = BASE.replace("value = [1.0e6, 0.0]", "value = [1.0e160, 0.0]");
    let s = dhpd::drivers::static_solve::solve(&common::scene(&text)).expect("solves");
    assert!(
        s.residual > 0.0 && s.residual < 1e-10,
        "residual {}",
        s.residual
    );
    let left = s.reaction("left").expect("the clamp's reaction");
    let applied = 1e160 * 0.1 * 0.01;
    assert!(
        (left[0] / -applied - 1.0).abs() < 1e-10,
        "reaction {:e} vs {:e}",
        left[0],
        -applied
    );
}
