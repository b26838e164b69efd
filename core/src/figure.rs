//! The picture of a SLAM result, described once for every renderer: the
//! CLI's SVG and PNG (`nvector plot`, `nvector run --plot`) and Python's
//! `nvector.plot` draw what [`describe`] returns, so that they show the
//! same layers, the same boxes after thinning, the same colours and the
//! same legend.
//!
//! What is drawn, bottom to top, on the first two axes (metres, y up):
//! 1. the trajectory: every box, translucent, when there are at most
//!    [`MAX_TRAJECTORY_BOXES`]; past that, their *envelope*: the cells of a
//!    grid ([`ENVELOPE_CELLS`] along the longer side of the view) that some
//!    box touches, merged into runs along x, drawn with one translucent
//!    fill. Thousands of overlapping boxes would otherwise pile up into one
//!    opaque block that hides the truth. The envelope covers every box
//!    (a box marks every cell it touches), so it never shows less than the
//!    boxes do;
//! 2. the detection boxes, outlined in grey, only when there are at most
//!    [`MAX_DETECTION_BOXES`] (past that they are not drawn, and the
//!    legend says so);
//! 3. the landmark regions of the drawn groups (`landmark_regions`, when
//!    the shapes contractor ran), translucent;
//! 4. the proved groups (`landmarks`, one box per group of `matching`) as
//!    outlines: the tightest ones, i.e. those that hold no other group's
//!    box, smallest area first, at most [`MAX_GROUP_OUTLINES`]. A group
//!    whose box holds a drawn one adds no place the eye can use;
//! 5. the truth (from the mission): the path (at most [`MAX_PATH_POINTS`]
//!    points, every k-th and the last) and the landmarks, on top.
//!
//! The title rounds the diameters to metres ("max trajectory diameter
//! 73.0 m") and the groups' legend reads "k proved groups of at most n
//! landmarks" (n the mission's `landmark_count`, when known).
//!
//! Pure: no I/O; the only float operations are + - * / and floor, which
//! are exact or correctly rounded, so native and wasm give the same bits.
//! Nothing decides soundness here: this is a drawing. Complexity:
//! O(N + D + G log G + G·[`MAX_GROUP_OUTLINES`] + R + ENVELOPE_CELLS²) for
//! N trajectory boxes, D detections, G groups and R region boxes; no
//! allocation is sized by a number read from the input (only by the input's
//! own length or the constants here).

use serde::Serialize;
use serde_json::Value;

/// Most trajectory boxes drawn one by one; past this, the envelope.
pub const MAX_TRAJECTORY_BOXES: usize = 400;
/// Cells of the envelope's grid along the longer side of the view.
pub const ENVELOPE_CELLS: usize = 240;
/// Most detection boxes drawn (past this, none).
pub const MAX_DETECTION_BOXES: usize = 300;
/// Most proved groups outlined.
pub const MAX_GROUP_OUTLINES: usize = 64;
/// Most points of the truth path.
pub const MAX_PATH_POINTS: usize = 5000;

/// How a layer is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Kind {
    /// Axis-aligned rectangles `[x0, x1, y0, y1]` (`rects`).
    Rects,
    /// A polyline through `points`.
    Path,
    /// Markers at `points`.
    Points,
}

/// One layer of the picture, in drawing order.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Layer {
    /// Stable name: `trajectory`, `detections`, `regions`, `groups`,
    /// `truth_path`, `truth_landmarks`.
    pub name: &'static str,
    /// The legend's text.
    pub label: String,
    /// How it is drawn.
    pub kind: Kind,
    /// Colour of lines, outlines and markers, `#rrggbb`.
    pub colour: &'static str,
    /// Opacity of the fill (0: outlines only).
    pub fill_alpha: f64,
    /// Line or outline width in pixels (0: no outline).
    pub line_width: f64,
    /// Rectangles `[x0, x1, y0, y1]` (kind `rects`).
    pub rects: Vec<[f64; 4]>,
    /// Points `[x, y]` (kinds `path` and `points`).
    pub points: Vec<[f64; 2]>,
}

/// The whole picture.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Figure {
    /// First line of the title: mission, contractor, status.
    pub title: String,
    /// Second line: the diameters in metres, rounded.
    pub subtitle: String,
    /// Axis labels.
    pub x_label: String,
    /// Axis labels.
    pub y_label: String,
    /// The data's extent with a margin: `[x0, x1, y0, y1]`.
    pub view: [f64; 4],
    /// Layers, bottom first.
    pub layers: Vec<Layer>,
}

/// Colour of the trajectory (boxes or envelope).
pub const TRAJECTORY: &str = "#4a90d9";
/// Colour of detection boxes.
pub const DETECTIONS: &str = "#888888";
/// Colour of the proved groups' outlines and regions.
pub const GROUPS: &str = "#c0392b";
/// Colour of the truth.
pub const TRUTH: &str = "#000000";

/// A box's first two axes `[x0, x1, y0, y1]`, when bounded and non-empty.
fn rect(b: &Value) -> Option<[f64; 4]> {
    let a = b.as_array()?;
    let axis = |v: Option<&Value>| -> Option<(f64, f64)> {
        let iv = v?.as_array()?;
        let lo = iv.first()?.as_f64()?;
        let hi = iv.get(1)?.as_f64()?;
        (lo.is_finite() && hi.is_finite() && lo <= hi).then_some((lo, hi))
    };
    let (x0, x1) = axis(a.first())?;
    let (y0, y1) = axis(a.get(1))?;
    Some([x0, x1, y0, y1])
}

fn point(p: &Value) -> Option<[f64; 2]> {
    let x = p.get(0)?.as_f64()?;
    let y = p.get(1)?.as_f64()?;
    (x.is_finite() && y.is_finite()).then_some([x, y])
}

fn list(v: &Value) -> &[Value] {
    v.as_array().map_or(&[], Vec::as_slice)
}

/// A length in metres, rounded for a title: "73.0 m", "0.412 m", "1250 m",
/// "unbounded" for infinity; `None` reads as "?".
pub fn metres(x: Option<f64>) -> String {
    match x {
        None => "?".to_string(),
        Some(x) if x.is_nan() => "?".to_string(),
        Some(x) if x.is_infinite() => "unbounded".to_string(),
        Some(x) if x.abs() >= 100.0 => format!("{x:.0} m"),
        Some(x) if x.abs() >= 1.0 => format!("{x:.1} m"),
        Some(x) if x.abs() >= 0.01 => format!("{x:.3} m"),
        Some(x) if x.abs() > 0.0 => format!("{x:.2e} m"),
        Some(_) => "0 m".to_string(),
    }
}

/// What a figure draws, read from a result and its mission: the
/// drawable rectangles `[x_lo, x_hi, y_lo, y_hi]` and points `[x, y]`.
struct Drawable {
    /// The position boxes that are bounded and not empty.
    trajectory: Vec<[f64; 4]>,
    /// The label's note on the position boxes left out (empty if none).
    undrawn: String,
    detections: Vec<[f64; 4]>,
    /// One per proved group (`None`: not drawable).
    group_boxes: Vec<Option<[f64; 4]>>,
    truth_path: Vec<[f64; 2]>,
    truth_landmarks: Vec<[f64; 2]>,
}

impl Drawable {
    fn read(result: &Value, mission: &Value) -> Drawable {
        let trajectory: Vec<[f64; 4]> = list(&result["trajectory"])
            .iter()
            .filter_map(rect)
            .collect();
        let undrawn = match list(&result["trajectory"]).len() - trajectory.len() {
            0 => String::new(),
            1 => " (1 more unbounded or empty, not drawn)".to_string(),
            u => format!(" ({u} more unbounded or empty, not drawn)"),
        };
        Drawable {
            trajectory,
            undrawn,
            detections: list(&result["detections"])
                .iter()
                .filter_map(rect)
                .collect(),
            group_boxes: list(&result["landmarks"]).iter().map(rect).collect(),
            truth_path: list(&mission["truth"]["positions"])
                .iter()
                .filter_map(point)
                .collect(),
            truth_landmarks: list(&mission["truth"]["landmarks"])
                .iter()
                .filter_map(point)
                .collect(),
        }
    }

    /// Whether the detection boxes are drawn (not too many).
    fn shows_detections(&self) -> bool {
        self.detections.len() <= MAX_DETECTION_BOXES
    }

    /// The view: everything drawn, with a 4 % margin.
    fn view(&self) -> [f64; 4] {
        let mut view = [
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ];
        let mut grow = |x: f64, y: f64| {
            view[0] = view[0].min(x);
            view[1] = view[1].max(x);
            view[2] = view[2].min(y);
            view[3] = view[3].max(y);
        };
        let shown_detections = self.shows_detections();
        for r in self
            .trajectory
            .iter()
            .chain(self.group_boxes.iter().flatten())
            .chain(self.detections.iter().filter(|_| shown_detections))
        {
            grow(r[0], r[2]);
            grow(r[1], r[3]);
        }
        for p in self.truth_path.iter().chain(&self.truth_landmarks) {
            grow(p[0], p[1]);
        }
        if view[0] > view[1] {
            view = [-1.0, 1.0, -1.0, 1.0];
        }
        let span = (view[1] - view[0]).max(view[3] - view[2]);
        let pad = if span.is_finite() && span > 0.0 {
            0.04 * span
        } else if span.is_finite() {
            1.0
        } else {
            0.0
        };
        [view[0] - pad, view[1] + pad, view[2] - pad, view[3] + pad]
    }
}

/// A layer of rectangles.
fn rects_layer(
    name: &'static str,
    label: String,
    colour: &'static str,
    fill_alpha: f64,
    line_width: f64,
    rects: Vec<[f64; 4]>,
) -> Layer {
    Layer {
        name,
        label,
        kind: Kind::Rects,
        colour,
        fill_alpha,
        line_width,
        rects,
        points: Vec::new(),
    }
}

/// Layer 1: the position boxes, or their envelope when there are too many.
fn trajectory_layer(d: &Drawable, view: [f64; 4]) -> Option<Layer> {
    let trajectory = &d.trajectory;
    let (n, undrawn) = (trajectory.len(), &d.undrawn);
    if n == 0 {
        return None;
    }
    let envelope = if n > MAX_TRAJECTORY_BOXES {
        envelope(trajectory, view)
    } else {
        None
    };
    Some(match envelope {
        Some(rects) => rects_layer(
            "trajectory",
            format!("trajectory: envelope of the {n} position boxes{undrawn}"),
            TRAJECTORY,
            0.35,
            0.0,
            rects,
        ),
        None => {
            // Too wide a view for a grid (values near the float
            // limits): every k-th box and the last.
            let stride = n.div_ceil(MAX_TRAJECTORY_BOXES).max(1);
            let mut rects: Vec<[f64; 4]> = trajectory.iter().step_by(stride).copied().collect();
            if rects.last() != Some(&trajectory[n - 1]) {
                rects.push(trajectory[n - 1]);
            }
            let label = if stride == 1 {
                format!("trajectory: {n} position boxes{undrawn}")
            } else {
                format!("trajectory: every {stride}th of {n} position boxes{undrawn}")
            };
            rects_layer("trajectory", label, TRAJECTORY, 0.12, 0.6, rects)
        }
    })
}

/// Layers 3 and 4: the proved groups (the tightest outlined) and the
/// landmark regions of those drawn.
fn group_layers(d: &Drawable, result: &Value, mission: &Value, layers: &mut Vec<Layer>) {
    let groups = d.group_boxes.len();
    if groups == 0 {
        return;
    }
    let drawn = tightest(&d.group_boxes);
    let regions = list(&result["landmark_regions"]);
    let region_rects: Vec<[f64; 4]> = drawn
        .iter()
        .filter_map(|&g| regions.get(g))
        .flat_map(|paving| list(paving).iter().filter_map(rect))
        .collect();
    if !region_rects.is_empty() {
        layers.push(rects_layer(
            "regions",
            "landmark regions of the drawn groups".to_string(),
            GROUPS,
            0.3,
            0.0,
            region_rects,
        ));
    }
    let of_at_most = match mission["landmark_count"].as_u64() {
        Some(k) => format!(" of at most {k} landmark{}", if k == 1 { "" } else { "s" }),
        None => String::new(),
    };
    let plural = if groups == 1 { "group" } else { "groups" };
    let label = if drawn.len() == groups {
        format!("{groups} proved {plural}{of_at_most}")
    } else {
        format!(
            "{groups} proved {plural}{of_at_most} ({} tightest outlined)",
            drawn.len()
        )
    };
    let rects = drawn.iter().filter_map(|&g| d.group_boxes[g]).collect();
    layers.push(rects_layer("groups", label, GROUPS, 0.0, 1.6, rects));
}

/// Layer 5: the true path (at most [`MAX_PATH_POINTS`] points, the last
/// kept) and the true landmarks.
fn truth_layers(d: &Drawable, layers: &mut Vec<Layer>) {
    let path = &d.truth_path;
    if !path.is_empty() {
        let m = path.len();
        let stride = m.div_ceil(MAX_PATH_POINTS).max(1);
        let mut points: Vec<[f64; 2]> = path.iter().step_by(stride).copied().collect();
        if points.last() != Some(&path[m - 1]) {
            points.push(path[m - 1]);
        }
        layers.push(Layer {
            name: "truth_path",
            label: "true path".to_string(),
            kind: Kind::Path,
            colour: TRUTH,
            fill_alpha: 0.0,
            line_width: 1.5,
            rects: Vec::new(),
            points,
        });
    }
    if !d.truth_landmarks.is_empty() {
        layers.push(Layer {
            name: "truth_landmarks",
            label: "true landmarks".to_string(),
            kind: Kind::Points,
            colour: TRUTH,
            fill_alpha: 1.0,
            line_width: 1.0,
            rects: Vec::new(),
            points: d.truth_landmarks.clone(),
        });
    }
}

/// The title (mission, contractor, status) and the subtitle (diameters,
/// whether the truth is inside).
fn titles(result: &Value) -> (String, String) {
    let name = result["mission"].as_str().unwrap_or("result");
    let contractor = result["options"]["contractor"].as_str().unwrap_or("?");
    let status = result["status"].as_str().unwrap_or("?");
    let metrics = &result["metrics"];
    let diameter = |key: &str| match &metrics[key] {
        Value::String(s) if s == "inf" => Some(f64::INFINITY),
        v => v.as_f64(),
    };
    let mut subtitle = format!(
        "max trajectory diameter {}, mean {}",
        metres(diameter("max_trajectory_diameter")),
        metres(diameter("mean_trajectory_diameter"))
    );
    if let Some(inside) = result["score"]["truth_inside"].as_bool() {
        subtitle.push_str(if inside {
            ", truth inside"
        } else {
            ", TRUTH OUTSIDE"
        });
    }
    (format!("{name}: {contractor}, {status}"), subtitle)
}

/// Describes the figure of `result` (`nvector-result/1`), with the truth of
/// `mission` (`nvector-mission/1`) when given. Values it cannot draw
/// (unbounded or empty boxes, non-numbers) are left out, never an error.
pub fn describe(result: &Value, mission: Option<&Value>) -> Figure {
    let null = Value::Null;
    let mission = mission.unwrap_or(&null);
    let d = Drawable::read(result, mission);
    let view = d.view();
    let mut layers = Vec::new();
    layers.extend(trajectory_layer(&d, view));
    // 2. Detections.
    if !d.detections.is_empty() && d.shows_detections() {
        let label = match d.detections.len() {
            1 => "1 detection box".to_string(),
            n => format!("{n} detection boxes"),
        };
        let rects = d.detections.clone();
        layers.push(rects_layer(
            "detections",
            label,
            DETECTIONS,
            0.0,
            0.6,
            rects,
        ));
    }
    group_layers(&d, result, mission, &mut layers);
    truth_layers(&d, &mut layers);
    let (title, subtitle) = titles(result);
    Figure {
        title,
        subtitle,
        x_label: "x (m)".to_string(),
        y_label: "y (m)".to_string(),
        view,
        layers,
    }
}

/// The groups to outline: those whose box holds no other group's box,
/// smallest area first, at most [`MAX_GROUP_OUTLINES`]; indices into
/// `boxes`, in increasing area.
fn tightest(boxes: &[Option<[f64; 4]>]) -> Vec<usize> {
    let area = |r: &[f64; 4]| (r[1] - r[0]) * (r[3] - r[2]);
    let mut order: Vec<(usize, [f64; 4])> = boxes
        .iter()
        .enumerate()
        .filter_map(|(i, r)| r.map(|r| (i, r)))
        .collect();
    order.sort_by(|a, b| area(&a.1).total_cmp(&area(&b.1)).then(a.0.cmp(&b.0)));
    let mut kept: Vec<(usize, [f64; 4])> = Vec::new();
    for (i, r) in order {
        if kept.len() == MAX_GROUP_OUTLINES {
            break;
        }
        // A box holding a kept one (its area is no smaller, so kept ones
        // came first) is left out; so is an equal box.
        let holds = kept
            .iter()
            .any(|(_, k)| r[0] <= k[0] && k[1] <= r[1] && r[2] <= k[2] && k[3] <= r[3]);
        if !holds {
            kept.push((i, r));
        }
    }
    kept.into_iter().map(|(i, _)| i).collect()
}

/// The envelope of `boxes` on a grid over `view`: every cell a box touches,
/// merged into runs along x, as rectangles. `None` when the view is too
/// wide for a grid of finite cells.
fn envelope(boxes: &[[f64; 4]], view: [f64; 4]) -> Option<Vec<[f64; 4]>> {
    let (w, h) = (view[1] - view[0], view[3] - view[2]);
    if !(w.is_finite() && h.is_finite() && w > 0.0 && h > 0.0) {
        return None;
    }
    let cell = w.max(h) / ENVELOPE_CELLS as f64;
    if !(cell.is_finite() && cell > 0.0) {
        return None;
    }
    let nx = ((w / cell) as usize).clamp(1, ENVELOPE_CELLS);
    let ny = ((h / cell) as usize).clamp(1, ENVELOPE_CELLS);
    let ix = |x: f64| (((x - view[0]) / cell).floor().max(0.0) as usize).min(nx - 1);
    let iy = |y: f64| (((y - view[2]) / cell).floor().max(0.0) as usize).min(ny - 1);
    // 2-D difference array: +1 at a box's low corner, -1 past its high
    // corner; the prefix sums count the boxes over each cell.
    let mut diff = vec![0i64; (nx + 1) * (ny + 1)];
    for r in boxes {
        let (i0, i1, j0, j1) = (ix(r[0]), ix(r[1]) + 1, iy(r[2]), iy(r[3]) + 1);
        diff[j0 * (nx + 1) + i0] += 1;
        diff[j0 * (nx + 1) + i1] -= 1;
        diff[j1 * (nx + 1) + i0] -= 1;
        diff[j1 * (nx + 1) + i1] += 1;
    }
    for j in 0..=ny {
        for i in 1..=nx {
            diff[j * (nx + 1) + i] += diff[j * (nx + 1) + i - 1];
        }
    }
    for j in 1..=ny {
        for i in 0..=nx {
            diff[j * (nx + 1) + i] += diff[(j - 1) * (nx + 1) + i];
        }
    }
    let mut rects = Vec::new();
    for j in 0..ny {
        let mut i = 0;
        while i < nx {
            if diff[j * (nx + 1) + i] > 0 {
                let start = i;
                while i < nx && diff[j * (nx + 1) + i] > 0 {
                    i += 1;
                }
                rects.push([
                    view[0] + start as f64 * cell,
                    view[0] + i as f64 * cell,
                    view[2] + j as f64 * cell,
                    view[2] + (j + 1) as f64 * cell,
                ]);
            } else {
                i += 1;
            }
        }
    }
    Some(rects)
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn covered(rects: &[[f64; 4]], x: f64, y: f64) -> bool {
        rects
            .iter()
            .any(|r| r[0] <= x && x <= r[1] && r[2] <= y && y <= r[3])
    }

    #[test]
    fn envelope_covers_every_box() {
        // 1000 boxes along a diagonal, each a 2 m square: the envelope
        // holds each box's corners and centre, and not the far corner.
        let traj: Vec<Value> = (0..1000)
            .map(|i| {
                let c = i as f64 * 0.1;
                json!([[c - 1.0, c + 1.0], [c - 1.0, c + 1.0]])
            })
            .collect();
        let f = describe(&json!({"trajectory": traj}), None);
        let layer = &f.layers[0];
        assert_eq!(layer.name, "trajectory");
        assert!(layer.label.contains("envelope of the 1000"));
        for i in 0..1000 {
            let c = i as f64 * 0.1;
            for (x, y) in [
                (c - 1.0, c - 1.0),
                (c + 1.0, c + 1.0),
                (c, c),
                (c - 1.0, c + 1.0),
            ] {
                assert!(covered(&layer.rects, x, y), "({x}, {y}) not covered");
            }
        }
        assert!(!covered(&layer.rects, 90.0, 0.0));
        assert!(layer.rects.len() <= ENVELOPE_CELLS * ENVELOPE_CELLS);
    }

    #[test]
    fn tightest_groups_and_label() {
        let result = json!({
            "mission": "m", "status": "consistent", "options": {"contractor": "best"},
            "metrics": {"max_trajectory_diameter": 73.02259, "mean_trajectory_diameter": 0.004},
            "trajectory": [[[0, 1], [0, 1]]],
            "landmarks": [[[0, 10], [0, 10]], [[1, 2], [1, 2]], [[5, 30], [5, 30]], ["-inf", 1]],
            "matching": [[0, 1], [2, 3], [4, 5], [6, 7]],
        });
        let f = describe(&result, Some(&json!({"landmark_count": 4})));
        let groups = f.layers.iter().find(|l| l.name == "groups").unwrap();
        assert_eq!(
            groups.rects,
            vec![[1.0, 2.0, 1.0, 2.0], [5.0, 30.0, 5.0, 30.0]]
        );
        assert_eq!(
            groups.label,
            "4 proved groups of at most 4 landmarks (2 tightest outlined)"
        );
        assert_eq!(f.title, "m: best, consistent");
        assert_eq!(f.subtitle, "max trajectory diameter 73.0 m, mean 4.00e-3 m");
    }

    #[test]
    fn unbounded_and_huge_values_do_not_break_the_picture() {
        let traj: Vec<Value> = (0..2000)
            .map(|i| {
                if i % 2 == 0 {
                    json!([[-1e308, 1e308], [0, 1]])
                } else {
                    json!([["-inf", 1], [0, "inf"]])
                }
            })
            .collect();
        let f = describe(
            &json!({"trajectory": traj, "metrics": {"max_trajectory_diameter": "inf"}}),
            None,
        );
        let layer = &f.layers[0];
        assert!(layer.rects.len() <= MAX_TRAJECTORY_BOXES + 1);
        assert!(f.subtitle.contains("unbounded"));
        assert!(describe(&json!(null), Some(&json!(7))).layers.is_empty());
    }

    #[test]
    fn metres_rounds() {
        assert_eq!(metres(Some(73.02259360692675)), "73.0 m");
        assert_eq!(metres(Some(612.4)), "612 m");
        assert_eq!(metres(Some(0.4123)), "0.412 m");
        assert_eq!(metres(None), "?");
        assert_eq!(metres(Some(0.0)), "0 m");
        assert_eq!(metres(Some(0.004)), "4.00e-3 m");
    }
}
