//! Point clouds from text files, one point per line (like Peridigm's text
//! discretisation):
//!
//! ```text
//! # comment lines start with '#'
//! x y [z] volume [horizon] [material]
//! ```
//!
//! Columns are separated by commas and/or white space. A file has `d + 1`
//! columns (positions and volume), `d + 2` (plus the horizon radius) or `d + 3`
//! (plus a material name from the scene). The volume includes the thickness
//! (2D) or the area (1D). Without a horizon column a point's horizon is
//! `horizon_factor × (volume / thickness)^(1/d)`. A leading UTF-8 byte-order
//! mark is skipped, as in scenes and meshes.

use super::grid::{RawPoint, Source};
use crate::error::{approx, echo, echo_list, num, InputError};
use crate::scene::{Material, PointFile};

/// Parses point-file text; `index` is the file's position in the scene.
pub fn parse(
    text: &str,
    file: &PointFile,
    index: usize,
    d: usize,
    thickness: f64,
    materials: &[Material],
) -> Result<Vec<RawPoint>, InputError> {
    // A UTF-8 byte-order mark is not part of the first row (as for scenes).
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut points = Vec::new();
    let mut width = None;
    for (n, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let row = Row {
            cols: line
                .split(|c: char| c == ',' || c.is_whitespace())
                .filter(|s| !s.is_empty())
                .collect(),
            file,
            line: n + 1,
        };
        row.check_width(d, &mut width)?;
        let (x, volume, spacing) = row.position_and_volume(d, thickness)?;
        let horizon = row.horizon(d, spacing)?;
        let material = row.material(d, materials)?;
        points.push(RawPoint {
            x,
            volume,
            spacing,
            horizon,
            material: material as u32,
            source: Source::File {
                file: index as u32,
                line: n as u32 + 1,
            },
        });
    }
    if points.is_empty() {
        return Err(InputError::new(
            format!("{}.path", file.field),
            format!("{} contains no point", file.path.display()),
        ));
    }
    Ok(points)
}

/// One row of a point file.
struct Row<'a> {
    cols: Vec<&'a str>,
    file: &'a PointFile,
    /// 1-based line number.
    line: usize,
}

impl Row<'_> {
    /// An error naming the file and the line.
    fn error(&self, message: String) -> InputError {
        InputError::new(
            format!(
                "{} ({}, line {})",
                self.file.field,
                self.file.path.display(),
                self.line
            ),
            message,
        )
    }

    /// Refuses a row of `d + 1` to `d + 3` columns that differs from the
    /// earlier rows' `width`.
    fn check_width(&self, d: usize, width: &mut Option<usize>) -> Result<(), InputError> {
        let n = self.cols.len();
        if n < d + 1 || n > d + 3 {
            return Err(self.error(format!(
                "{n} columns; a {d}D point file has {} (x.. volume), {} (+ horizon) or {} (+ material)",
                d + 1, d + 2, d + 3)));
        }
        if let Some(w) = *width {
            if w != n {
                return Err(self.error(format!(
                    "{n} columns where earlier lines have {w}; every row needs the same columns"
                )));
            }
        }
        *width = Some(n);
        Ok(())
    }

    /// Column `k` as a finite number (`what` names it in errors).
    fn number(&self, k: usize, what: &str) -> Result<f64, InputError> {
        let v: f64 = self.cols[k].parse().map_err(|_| {
            self.error(format!("{what} \"{}\" is not a number", echo(self.cols[k])))
        })?;
        if v.is_finite() {
            Ok(v)
        } else {
            Err(self.error(format!(
                "{what} is {}; only finite numbers are valid",
                num(v)
            )))
        }
    }

    /// The position, the (positive) volume and the equivalent spacing
    /// `(volume / thickness)^(1/d)`.
    fn position_and_volume(
        &self,
        d: usize,
        thickness: f64,
    ) -> Result<([f64; 3], f64, f64), InputError> {
        let mut x = [0.0; 3];
        for (a, name) in ["x", "y", "z"].iter().enumerate().take(d) {
            x[a] = self.number(a, name)?;
        }
        let volume = self.number(d, "volume")?;
        if volume <= 0.0 {
            return Err(self.error(format!("volume {} must be positive", num(volume))));
        }
        let spacing = (volume / if d < 3 { thickness } else { 1.0 }).powf(1.0 / d as f64);
        if !(spacing.is_finite() && spacing > 0.0) {
            return Err(self.error(format!(
                "volume {} gives an equivalent spacing (volume / thickness)^(1/{d}) = {} \
                 outside the floating-point range",
                num(volume),
                num(spacing)
            )));
        }
        Ok((x, volume, spacing))
    }

    /// The horizon column, or the file's factor times the spacing; at most
    /// [`MAX_HORIZON_FACTOR`](crate::scene::fields::MAX_HORIZON_FACTOR) spacings.
    fn horizon(&self, d: usize, spacing: f64) -> Result<f64, InputError> {
        let horizon = if self.cols.len() >= d + 2 {
            let h = self.number(d + 1, "horizon")?;
            if h <= 0.0 {
                return Err(self.error(format!("horizon {} must be positive", num(h))));
            }
            h
        } else {
            self.file.horizon_factor * spacing
        };
        if !horizon.is_finite() {
            return Err(self.error(format!(
                "the horizon ({} × spacing {}) overflows",
                num(self.file.horizon_factor),
                num(spacing)
            )));
        }
        let factor = crate::scene::fields::MAX_HORIZON_FACTOR;
        if horizon > factor * spacing {
            return Err(self.error(format!(
                "horizon {} is {} times the point's equivalent spacing {} \
                 ((volume / thickness)^(1/{d})): implausibly large (above {factor}); typical \
                 horizons are 2 to 5 spacings",
                num(horizon),
                approx(horizon / spacing),
                num(spacing)
            )));
        }
        Ok(horizon)
    }

    /// The material column, or the file's material.
    fn material(&self, d: usize, materials: &[Material]) -> Result<usize, InputError> {
        if self.cols.len() == d + 3 {
            let name = self.cols[d + 2];
            materials
                .iter()
                .position(|m| m.name == name)
                .ok_or_else(|| {
                    let known: Vec<_> = materials.iter().map(|m| m.name.as_str()).collect();
                    self.error(format!(
                        "unknown material \"{name}\"; defined: {}",
                        echo_list(known)
                    ))
                })
        } else {
            self.file.material.ok_or_else(|| {
                self.error("no material column and no `material` in the scene for this file".into())
            })
        }
    }
}
