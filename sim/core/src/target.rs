//! Target model files (`scenarios/targets/*.toml`): read, then validated into a
//! [`tracker::TargetModel`].
//!
//! The format, which other tools read too:
//! ```toml
//! name = "nist-ten-segment"
//! nominal_range_m = 10.0                        # range at which scale = 1
//! corners_m = [[-0.8, 0.5], [0.8, 0.5], ...]    # x right, y up, metres from the target centre
//! segments = [[0, 1], [1, 2], ...]              # corner-index pairs, each horizontal or vertical
//! paint = "steps"                               # optional: "steps" (default) or "stripes"
//! ```
//! `paint` says how the segments are painted on the board (`tracker::paint`): `steps`, the
//! paper's, makes each segment one step edge between filled regions of different tone, and
//! needs every segment to bound a closed region; `stripes`, not the paper's, paints each
//! segment as a thin dark stripe with two edges.
//! Errors name the file, the line and column, and the field or segment at fault.

use serde::Deserialize;
use std::path::{Path, PathBuf};
use thiserror::Error;
use toml::Spanned;
use tracker::paint::{Paint, PaintError};
use tracker::{TargetError, TargetModel};

/// The file as written: parsed, not yet checked.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct TargetFile {
    name: String,
    nominal_range_m: Spanned<f64>,
    // Read as lists, so that a corner of more than two numbers, or a segment of more than
    // two corners, is refused, not cut short.
    corners_m: Vec<Spanned<Vec<f64>>>,
    segments: Vec<Spanned<Vec<usize>>>,
    paint: Option<Spanned<String>>,
}

/// Largest corner coordinate, metres from the target's centre: a board of up to 10 m × 10 m,
/// several times any vehicle's back (and far from the overflow of drawing it).
pub const MAX_CORNER_M: f64 = 5.0;
/// Nominal range bounds, metres: the range at which the model has scale 1, between the
/// closest and farthest following distances studied, with a margin.
pub const NOMINAL_RANGE_M: [f64; 2] = [1.0, 200.0];

/// A target file that could not be used.
#[derive(Debug, Error)]
pub enum TargetFileError {
    /// The file could not be read.
    #[error("{path}: cannot read target file: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// Not valid TOML, or not this format (unknown or missing field, wrong type).
    #[error("{path}:{line}:{column}: {message}")]
    Parse {
        /// The file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// The parser's message, naming the field.
        message: String,
    },
    /// A number outside its physical bounds.
    #[error("{path}:{line}:{column}: `{field}` {message}")]
    OutOfBounds {
        /// The file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// The field at fault.
        field: &'static str,
        /// The value and what is allowed.
        message: String,
    },
    /// Well-formed, but not a usable model.
    #[error("{path}:{line}:{column}: `{field}`: {source}")]
    Invalid {
        /// The file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// The field at fault.
        field: &'static str,
        /// What is wrong.
        source: TargetError,
    },
    /// `paint = "steps"` (the default), but a segment bounds no closed region.
    #[error("{path}:{line}:{column}: `segments`: {source}")]
    Unpaintable {
        /// The file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// Which segment.
        source: PaintError,
    },
}

/// The text of a target file holding `model`, opened by `comment` (its lines each made a
/// TOML comment): its numbers written with the digits that read back as the same `f64`,
/// so that [`parse`] of the text gives `model` again.
pub fn to_file_text(model: &TargetModel, comment: &str) -> String {
    let mut text = String::new();
    for line in comment.lines() {
        text.push_str(format!("# {line}").trim_end());
        text.push('\n');
    }
    text.push_str(&format!("name = {:?}\n", model.name()));
    text.push_str(&format!(
        "nominal_range_m = {:?}\n",
        model.nominal_range_m()
    ));
    text.push_str("corners_m = [\n");
    for (k, [x, y]) in model.corners_m().iter().enumerate() {
        text.push_str(&format!("    [{x:?}, {y:?}],  # {k}\n"));
    }
    text.push_str("]\nsegments = [\n");
    for [a, b] in model.segments() {
        text.push_str(&format!("    [{a}, {b}],\n"));
    }
    text.push_str(&format!("]\npaint = \"{}\"\n", model.paint().as_str()));
    text
}

/// 1-based (line, column) of a byte offset in `text`.
pub fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, column)
}

/// Reads and validates a target file.
pub fn load(path: &Path) -> Result<TargetModel, TargetFileError> {
    let text = std::fs::read_to_string(path).map_err(|source| TargetFileError::Io {
        path: path.to_owned(),
        source,
    })?;
    parse(&text, path)
}

/// Parses and validates the text of a target file; `path` is only used in errors.
pub fn parse(text: &str, path: &Path) -> Result<TargetModel, TargetFileError> {
    let raw: TargetFile = toml::from_str(text).map_err(|e| {
        let (line, column) = line_column(text, e.span().map_or(0, |s| s.start));
        TargetFileError::Parse {
            path: path.to_owned(),
            line,
            column,
            message: e.message().trim().to_string(),
        }
    })?;
    let out_of_bounds = |field: &'static str, span: std::ops::Range<usize>, message: String| {
        let (line, column) = line_column(text, span.start);
        TargetFileError::OutOfBounds {
            path: path.to_owned(),
            line,
            column,
            field,
            message,
        }
    };
    let range = *raw.nominal_range_m.get_ref();
    if !(NOMINAL_RANGE_M[0]..=NOMINAL_RANGE_M[1]).contains(&range) {
        return Err(out_of_bounds(
            "nominal_range_m",
            raw.nominal_range_m.span(),
            format!(
                "= {range:?}: must be {}–{} m",
                NOMINAL_RANGE_M[0], NOMINAL_RANGE_M[1]
            ),
        ));
    }
    let mut corners: Vec<[f64; 2]> = Vec::with_capacity(raw.corners_m.len());
    for (index, c) in raw.corners_m.iter().enumerate() {
        let [x, y] = match c.get_ref()[..] {
            [x, y] => [x, y],
            ref other => {
                return Err(out_of_bounds(
                    "corners_m",
                    c.span(),
                    format!(
                        "corner {index} = {other:?}: a corner is exactly two numbers, [x, y] \
                         in metres"
                    ),
                ))
            }
        };
        corners.push([x, y]);
        if !(x.abs() <= MAX_CORNER_M && y.abs() <= MAX_CORNER_M) {
            return Err(out_of_bounds(
                "corners_m",
                c.span(),
                format!(
                    "corner {index} = [{x:?}, {y:?}]: each coordinate must be within \
                     ±{MAX_CORNER_M} m of the target's centre"
                ),
            ));
        }
    }
    let mut segments: Vec<[usize; 2]> = Vec::with_capacity(raw.segments.len());
    for (index, s) in raw.segments.iter().enumerate() {
        match s.get_ref()[..] {
            [a, b] => segments.push([a, b]),
            ref other => {
                return Err(out_of_bounds(
                    "segments",
                    s.span(),
                    format!(
                        "segment {index} = {other:?}: a segment joins exactly two corners \
                         (their indices)"
                    ),
                ))
            }
        }
    }
    let paint = match &raw.paint {
        None => Paint::Steps,
        Some(p) => Paint::parse(p.get_ref()).ok_or_else(|| {
            out_of_bounds(
                "paint",
                p.span(),
                format!("= {:?}: must be \"steps\" or \"stripes\"", p.get_ref()),
            )
        })?,
    };
    let model = TargetModel::new(raw.name, *raw.nominal_range_m.get_ref(), corners, segments)
        .map_err(|source| {
            // Point at the item the error is about.
            let (field, span) = match &source {
                TargetError::BadNominalRange(_) => ("nominal_range_m", raw.nominal_range_m.span()),
                TargetError::NonFiniteCorner { index, .. } => {
                    ("corners_m", raw.corners_m[*index].span())
                }
                TargetError::IndexOutOfRange { segment, .. }
                | TargetError::Degenerate { segment, .. }
                | TargetError::NoLength { segment, .. }
                | TargetError::NotAxisAligned { segment, .. }
                | TargetError::Duplicate { segment, .. }
                | TargetError::Overlap { segment, .. } => {
                    ("segments", raw.segments[*segment].span())
                }
                TargetError::Underdetermined { .. } => {
                    ("segments", raw.segments.first().map_or(0..0, |s| s.span()))
                }
            };
            let (line, column) = line_column(text, span.start);
            TargetFileError::Invalid {
                path: path.to_owned(),
                line,
                column,
                field,
                source,
            }
        })?
        .with_paint(paint);
    if let Err(PaintError::NotABoundary { segment }) = tracker::paint::layout(&model) {
        let (line, column) = line_column(text, raw.segments[segment].span().start);
        return Err(TargetFileError::Unpaintable {
            path: path.to_owned(),
            line,
            column,
            source: PaintError::NotABoundary { segment },
        });
    }
    Ok(model)
}

#[cfg(test)]
mod tests {
    use super::*;

    const GOOD: &str = r#"name = "box"
nominal_range_m = 10.0
corners_m = [[-0.8, 0.5], [0.8, 0.5], [0.8, -0.5], [-0.8, -0.5]]
segments = [
    [0, 1],
    [1, 2],
    [2, 3],
    [3, 0],
]
"#;

    fn err(text: &str) -> String {
        parse(text, Path::new("t.toml")).unwrap_err().to_string()
    }

    #[test]
    fn a_good_file_loads() {
        let m = parse(GOOD, Path::new("t.toml")).unwrap();
        assert_eq!(m.name(), "box");
        assert_eq!(m.segments().len(), 4);
    }

    #[test]
    fn the_shipped_target_loads() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../scenarios/targets/nist-ten-segment.toml");
        let m = load(&path).unwrap();
        assert_eq!(m.segments().len(), 10);
        assert_eq!(m.size_m(), [1.6, 1.0]);
        // The tracker's built-in copy for tests and benchmarks is the same model.
        assert_eq!(m, tracker::synth::nist_ten_segment());
    }

    #[test]
    fn an_open_segment_cannot_be_a_step_edge_but_can_be_a_stripe() {
        // A fifth corner and a bar from the top edge's middle that ends in the open.
        let open = GOOD
            .replace("[-0.8, -0.5]]", "[-0.8, -0.5], [0.0, 0.5], [0.0, 0.1]]")
            .replace("[3, 0],", "[3, 0],\n    [4, 5],");
        let e = err(&open);
        assert!(
            e.starts_with("t.toml:9:5: `segments`: segment 4 does not bound a closed region"),
            "{e}"
        );
        let m = parse(&format!("{open}paint = \"stripes\"\n"), Path::new("t.toml")).unwrap();
        assert_eq!(m.paint(), Paint::Stripes);
        let e = err(&format!("{GOOD}paint = \"dots\"\n"));
        assert!(
            e.starts_with("t.toml:10:9: `paint` = \"dots\": must be"),
            "{e}"
        );
    }

    #[test]
    fn a_diagonal_segment_is_named_with_its_line() {
        let e = err(&GOOD.replace("[2, 3],", "[2, 0],"));
        assert!(e.starts_with("t.toml:7:5: `segments`: segment 2"), "{e}");
        assert!(e.contains("neither horizontal nor vertical"), "{e}");
    }

    #[test]
    fn an_index_out_of_range_is_named() {
        let e = err(&GOOD.replace("[3, 0],", "[3, 9],"));
        assert!(
            e.starts_with("t.toml:8:5: `segments`: segment 3 refers to corner 9"),
            "{e}"
        );
    }

    /// A segment of three corners is refused, not cut to its first two; one whose corners
    /// coincide has no length.
    #[test]
    fn a_segment_must_join_two_distinct_points() {
        let e = err(&GOOD.replace("[1, 2],", "[1, 2, 3],"));
        assert!(
            e.starts_with("t.toml:6:5: `segments` segment 1 = [1, 2, 3]:")
                && e.contains("exactly two corners"),
            "{e}"
        );
        let e = err(&GOOD
            .replace("[-0.8, -0.5]]", "[-0.8, -0.5], [0.8, 0.5]]")
            .replace("[3, 0],", "[3, 0],\n    [1, 4],"));
        assert!(
            e.starts_with(
                "t.toml:9:5: `segments`: segment 4 from corner 1 to corner 4 has no length"
            ),
            "{e}"
        );
    }

    #[test]
    fn a_duplicate_segment_is_named() {
        let e = err(&GOOD.replace("[3, 0],", "[3, 0],\n    [1, 0],"));
        assert!(
            e.contains("t.toml:9:5") && e.contains("segment 4 duplicates segment 0"),
            "{e}"
        );
    }

    #[test]
    fn a_segment_along_another_is_named() {
        // Corner 4 halfway along the top edge, and a segment from it to the top right
        // corner: it runs along segment 0.
        let text = GOOD
            .replace("[-0.8, -0.5]]", "[-0.8, -0.5], [0.0, 0.5]]")
            .replace("[3, 0],", "[3, 0],\n    [4, 1],");
        let e = err(&text);
        assert!(
            e.contains("t.toml:9:5")
                && e.contains("segment 4 overlaps segment 0")
                && e.contains("from 0 m to 0.8 m"),
            "{e}"
        );
        // Meeting end to end at a corner, on one line, is allowed (painted as stripes: a
        // segment that sticks out bounds no region of steps).
        let text = GOOD
            .replace("[-0.8, -0.5]]", "[-0.8, -0.5], [1.2, 0.5]]")
            .replace("[3, 0],", "[3, 0],\n    [1, 4],")
            + "paint = \"stripes\"\n";
        parse(&text, Path::new("t.toml")).unwrap();
    }

    #[test]
    fn an_underdetermined_model_is_refused() {
        let e = err(&GOOD
            .replace("    [1, 2],\n", "")
            .replace("    [3, 0],\n", ""));
        assert!(
            e.contains("at least one horizontal and one vertical"),
            "{e}"
        );
    }

    #[test]
    fn corners_and_range_out_of_bounds_are_named() {
        let e = err(&GOOD.replace("[-0.8, 0.5], [0.8, 0.5]", "[-1e308, 0.5], [0.8, 0.5]"));
        assert!(
            e.starts_with("t.toml:3:14: `corners_m` corner 0 = [-1e308, 0.5]"),
            "{e}"
        );
        let e = err(&GOOD.replace("10.0", "1e300"));
        assert!(
            e.starts_with("t.toml:2:19: `nominal_range_m` = 1e300"),
            "{e}"
        );
    }

    #[test]
    fn a_corner_of_more_or_fewer_than_two_numbers_is_named() {
        for (corner, shown) in [
            ("[-0.8, 0.5, 9.0]", "[-0.8, 0.5, 9.0]"),
            ("[-0.8]", "[-0.8]"),
        ] {
            let e = err(&GOOD.replace("[-0.8, 0.5], [0.8, 0.5]", &format!("{corner}, [0.8, 0.5]")));
            assert!(
                e.starts_with(&format!(
                    "t.toml:3:14: `corners_m` corner 0 = {shown}: a corner is exactly two numbers"
                )),
                "{e}"
            );
        }
    }

    #[test]
    fn unknown_and_mistyped_fields_are_refused_with_position() {
        let e = err(&GOOD.replace("nominal_range_m", "nominal_rang_m"));
        assert!(
            e.starts_with("t.toml:2:1:") && e.contains("nominal_rang_m"),
            "{e}"
        );
        let e = err(&GOOD.replace("10.0", "\"ten\""));
        assert!(e.starts_with("t.toml:2:19:"), "{e}");
    }
}
