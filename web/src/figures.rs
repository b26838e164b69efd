//! The figures module's part of the facade (feature `figures`): the
//! description of a result's picture (core's `figure::describe`, the one
//! the CLI's SVG and PNG draw), which the missions tab draws; the drawing
//! outlines of detection shapes and the boundaries of landmark regions,
//! computed by core (core/src/outline.rs), for the SLAM demo's and the
//! missions tab's pictures.

use crate::{into_error, Nvector};
use nvector_core::figure::describe;
use nvector_core::outline::{shape_outline, union_boundary};
use nvector_core::shapes::shape::{Shape, MAX_DIM};
use nvector_core::{InputError, Interval, IntervalBox};
use std::cmp::Ordering;
use wasm_bindgen::prelude::*;

/// Reads the flat numbers of an outline request, naming the place of a bad
/// one (`shapes[3].range`).
struct Numbers<'a> {
    what: &'static str,
    rest: &'a [f64],
}

impl Numbers<'_> {
    fn take(&mut self, item: usize, field: &str) -> Result<f64, InputError> {
        let (x, rest) = self.rest.split_first().ok_or_else(|| {
            InputError::new(
                format!("{}[{item}].{field}", self.what),
                "the list ends early",
            )
        })?;
        self.rest = rest;
        Ok(*x)
    }

    fn interval(&mut self, item: usize, field: &str) -> Result<Interval, InputError> {
        let (lo, hi) = (self.take(item, field)?, self.take(item, field)?);
        let ordered = matches!(lo.partial_cmp(&hi), Some(Ordering::Less | Ordering::Equal));
        if !ordered || lo == f64::INFINITY || hi == f64::NEG_INFINITY {
            return Err(InputError::new(
                format!("{}[{item}].{field}", self.what),
                "not an interval: the lower bound is above the upper one, infinite \
                 the wrong way or not a number",
            ));
        }
        Ok(Interval::new(lo, hi))
    }

    /// A count of items of `size` numbers each, bounded by what is left.
    fn count(&mut self, item: usize, field: &str, size: usize) -> Result<usize, InputError> {
        let n = self.take(item, field)?;
        if !(n >= 0.0 && n.fract() == 0.0 && n * size as f64 <= self.rest.len() as f64) {
            return Err(InputError::new(
                format!("{}[{item}].{field}", self.what),
                "not a count of the boxes that follow (4 numbers each)",
            ));
        }
        Ok(n as usize)
    }

    fn boxed(&mut self, item: usize, field: &str, dim: usize) -> Result<IntervalBox, InputError> {
        let mut axes = [Interval::ZERO; MAX_DIM];
        for a in axes.iter_mut().take(dim) {
            *a = self.interval(item, field)?;
        }
        Ok(IntervalBox::new(&axes[..dim]))
    }
}

/// The outlines of detection shapes, computed by core
/// (core/src/outline.rs), from flat numbers (a Float64Array in the page: no
/// JSON for thousands of shapes). Per shape: `dim` (1 to 3); the centre
/// box's `2 dim` bounds (lo, hi per axis); the range's lo, hi; 0, or 1 and
/// the heading's lo, hi and the bearing's lo, hi; the cut box's `2 dim`
/// bounds (infinite for no cut). The answer, per shape: `n_outer, n_hole`,
/// then the outer polygon's `2 n_outer` and the hole's `2 n_hole`
/// coordinates (x, y, ...; `n_outer` = 0: nothing to draw). The outer
/// polygon is counter-clockwise, the hole clockwise: filled with the
/// nonzero rule, the outline encloses the shape.
pub fn shape_outlines(input: &[f64]) -> Result<Vec<f64>, InputError> {
    let mut r = Numbers {
        what: "shapes",
        rest: input,
    };
    let mut out = Vec::new();
    let mut i = 0;
    while !r.rest.is_empty() {
        let dim = r.take(i, "dim")?;
        if !(1.0..=MAX_DIM as f64).contains(&dim) || dim.fract() != 0.0 {
            return Err(InputError::new(
                format!("shapes[{i}].dim"),
                "expected 1, 2 or 3 axes",
            ));
        }
        let dim = dim as usize;
        let centre = r.boxed(i, "centre", dim)?;
        let range = r.interval(i, "range")?;
        let bearing = match r.take(i, "bearing")? {
            0.0 => None,
            1.0 => Some((r.interval(i, "heading")?, r.interval(i, "bearing")?)),
            _ => {
                return Err(InputError::new(
                    format!("shapes[{i}].bearing"),
                    "expected 0 (no bearing) or 1 (heading and bearing follow)",
                ))
            }
        };
        let cut = r.boxed(i, "cut", dim)?;
        match shape_outline(&Shape::new(centre, range, bearing, cut)) {
            Some(o) => {
                let hole = o.hole.as_deref().unwrap_or(&[]);
                out.extend([o.outer.len() as f64, hole.len() as f64]);
                out.extend(o.outer.iter().chain(hole).flatten());
            }
            None => out.extend([0.0, 0.0]),
        }
        i += 1;
    }
    Ok(out)
}

/// The boundaries of landmark regions (unions of boxes), computed by core
/// (core/src/outline.rs), from flat numbers. Per region: the number of
/// boxes, then per box x lo, x hi, y lo, y hi. The answer, per region: the
/// number of segments, then per segment x0, y0, x1, y1; -1 (and nothing
/// after it) for a region of too many boxes to trace (core's
/// `MAX_UNION_BOXES`: the page draws its fill alone).
pub fn region_boundaries(input: &[f64]) -> Result<Vec<f64>, InputError> {
    let mut r = Numbers {
        what: "regions",
        rest: input,
    };
    let mut out = Vec::new();
    let mut i = 0;
    while !r.rest.is_empty() {
        let n = r.count(i, "boxes", 4)?;
        let mut boxes = Vec::with_capacity(n);
        for _ in 0..n {
            boxes.push(r.boxed(i, "boxes", 2)?);
        }
        match union_boundary(&boxes) {
            Some(segments) => {
                out.push(segments.len() as f64);
                out.extend(segments.iter().flatten().flatten());
            }
            None => out.push(-1.0),
        }
        i += 1;
    }
    Ok(out)
}

/// The figure of a result (`nvector-result/1` JSON text) with the truth of
/// its mission (`nvector-mission/1` JSON text, or empty for none), as
/// core's `figure::describe` gives it to the CLI's SVG and PNG: title,
/// axis labels, view and layers (name, label, kind, colour, fill_alpha,
/// line_width, rects, points, polygons), as JSON.
pub fn describe_json(result: &str, mission: &str) -> Result<String, InputError> {
    let read = |what: &str, text: &str| {
        serde_json::from_str::<serde_json::Value>(text)
            .map_err(|e| InputError::new(what.to_string(), format!("invalid JSON: {e}")))
    };
    // The result through its types, each fault named `result.PATH`.
    let result =
        nvector_core::format::result::read_value(&read("result", result)?).map_err(|e| match e
            .path
            .as_str()
        {
            "" => InputError::new("result", e.message),
            path => InputError::new(format!("result.{path}"), e.message),
        })?;
    let mission = if mission.trim().is_empty() {
        None
    } else {
        Some(read("mission", mission)?)
    };
    serde_json::to_string(&describe(&result, mission.as_ref()))
        .map_err(|e| InputError::new("figure".to_string(), e.to_string()))
}

#[wasm_bindgen]
impl Nvector {
    /// The figure of a result (see [`describe_json`]).
    pub fn describe(&self, result: &str, mission: &str) -> Result<String, JsError> {
        describe_json(result, mission).map_err(into_error)
    }

    /// The outlines of detection shapes (see [`shape_outlines`]).
    pub fn outlines(&self, shapes: &[f64]) -> Result<Vec<f64>, JsError> {
        shape_outlines(shapes).map_err(into_error)
    }

    /// The boundaries of landmark regions (see [`region_boundaries`]).
    pub fn boundaries(&self, regions: &[f64]) -> Result<Vec<f64>, JsError> {
        region_boundaries(regions).map_err(into_error)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn outlines_of_a_ring_a_cut_away_shape_and_a_sector() {
        let inf = f64::INFINITY;
        let ring = [2.0, 0.0, 1.0, 0.0, 1.0, 5.0, 6.0, 0.0, -inf, inf, -inf, inf];
        let away = [
            2.0, 0.0, 1.0, 0.0, 1.0, 5.0, 6.0, 0.0, 50.0, 60.0, 50.0, 60.0,
        ];
        let sector = [
            2.0, 0.0, 1.0, 0.0, 1.0, 0.0, 2.0, 1.0, 0.0, 0.0, 0.0, 0.5, -inf, inf, -inf, inf,
        ];
        let input: Vec<f64> = [&ring[..], &away, &sector].concat();
        let out = shape_outlines(&input).unwrap();
        let (n0, h0) = (out[0] as usize, out[1] as usize);
        assert!(n0 >= 3 && h0 >= 3, "a ring has a hole: {out:?}");
        let mut k = 2 + 2 * (n0 + h0);
        assert_eq!(&out[k..k + 2], &[0.0, 0.0], "cut away: nothing to draw");
        k += 2;
        let (n2, h2) = (out[k] as usize, out[k + 1] as usize);
        assert!(n2 >= 3 && h2 == 0, "a sector from range 0 has no hole");
        assert_eq!(out.len(), k + 2 + 2 * n2);
        // Every vertex of the sector lies in the quarter plane x, y >= 0
        // widened by the box (bearing [0, 0.5] from the box [0, 1]^2).
        assert!(out[k + 2..]
            .chunks(2)
            .all(|p| p[0] >= -1e-6 && p[1] >= -1e-6));
    }

    #[test]
    fn region_boundaries_of_two_overlapping_boxes() {
        let out = region_boundaries(&[
            2.0, 0.0, 2.0, 0.0, 1.0, 1.0, 3.0, 0.0, 1.0, 1.0, 5.0, 6.0, 5.0, 6.0,
        ])
        .unwrap();
        // Region 0: 6 segments (the rectangle [0, 3] x [0, 1], its bottom
        // and top sides in two pieces each); region 1: a square's 4 sides.
        assert_eq!(out[0], 6.0);
        assert_eq!(out[1 + 24], 4.0);
        assert_eq!(out.len(), 1 + 24 + 1 + 16);
    }

    #[test]
    fn the_figure_is_cores_description() {
        let result = r#"{"format": "nvector-result/1", "mission": "m", "status": "consistent",
            "options": {"contractor": "best", "max_rounds": 10, "tolerance": 0},
            "metrics": {"contractions": 0, "elapsed_ms": 0, "matched_detections": 2,
                "max_detection_diameter": 1, "max_trajectory_diameter": 1,
                "mean_trajectory_diameter": 1, "rounds": 1},
            "trajectory": [[[0, 1], [0, 1]], [[1, 2], [0, 1]]],
            "detections": [[[5, 6], [5, 6]], [[5, 6], [5, 6]]],
            "landmarks": [[[5, 6], [5, 6]]], "matching": [[0, 1]],
            "landmark_regions": [[[[5, 5.1], [5, 6]]]]}"#;
        let mission = r#"{"landmark_count": 4, "truth": {"positions": [[0.5, 0.5], [1.5, 0.5]]}}"#;
        let fig: serde_json::Value =
            serde_json::from_str(&describe_json(result, mission).unwrap()).unwrap();
        let want = serde_json::to_value(describe(
            &nvector_core::format::result::read(result).unwrap(),
            Some(&serde_json::from_str(mission).unwrap()),
        ))
        .unwrap();
        assert_eq!(fig, want);
        assert_eq!(fig["x_label"], "x (m)");
        let names: Vec<&str> = fig["layers"]
            .as_array()
            .unwrap()
            .iter()
            .map(|l| l["name"].as_str().unwrap())
            .collect();
        assert_eq!(
            names,
            [
                "trajectory",
                "detections",
                "regions",
                "groups",
                "truth_path"
            ]
        );
        let e = describe_json("[1,", "").unwrap_err();
        assert!(e.to_string().contains("result"), "{e}");
        let e = describe_json(result, "{").unwrap_err();
        assert!(e.to_string().contains("mission"), "{e}");
        let e = describe_json(&result.replace("[[0, 1]]", "[[0, 7]]"), "").unwrap_err();
        assert_eq!(
            e.to_string(),
            "result.matching[0][1]: expected a detection index below 2, found 7"
        );
    }

    #[test]
    fn outline_errors_name_the_place() {
        let e = shape_outlines(&[2.0, 0.0, 1.0, 0.0, 1.0, 3.0, 1.0]).unwrap_err();
        assert!(e.to_string().contains("shapes[0].range"), "{e}");
        let e = shape_outlines(&[4.0]).unwrap_err();
        assert!(e.to_string().contains("shapes[0].dim"), "{e}");
        let e = shape_outlines(&[1.0, 0.0, 1.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 0.0]).unwrap_err();
        assert!(e.to_string().contains("shapes[1].centre"), "{e}");
        let e = shape_outlines(&[1.0, 0.0, 1.0, 0.0, 1.0, 2.0]).unwrap_err();
        assert!(e.to_string().contains("shapes[0].bearing"), "{e}");
        let e = region_boundaries(&[1e9, 0.0]).unwrap_err();
        assert!(e.to_string().contains("regions[0].boxes"), "{e}");
        let e = region_boundaries(&[1.0, 0.0, f64::NAN, 0.0, 1.0]).unwrap_err();
        assert!(e.to_string().contains("regions[0].boxes"), "{e}");
    }
}
