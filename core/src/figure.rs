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
//!    boxes do; then, for odometry2d results (`headings`), the heading
//!    interval of every k-th step (at most [`MAX_HEADING_MARKS`], the last
//!    kept) as a wedge from the centre of that step's position box, its
//!    radius [`HEADING_RADIUS`] of the view's longer side, its arc
//!    spanning the interval; a heading 2π wide or more (or unbounded) is a
//!    circle, in a layer of its own, outlined only. The legend reads
//!    "heading (interval) ...". Other models have no `headings` and no
//!    such layer;
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
//!    points, every k-th and the last) and the landmarks, on top; with
//!    `truth.headings`, a short tick along the true heading from the true
//!    position at the steps that have a wedge.
//!
//! The title rounds the diameters to metres ("max trajectory diameter
//! 73.0 m") and the groups' legend reads "k proved groups of at most n
//! landmarks" (n the mission's `landmark_count`, when known).
//!
//! Pure: no I/O; the float operations are + - * /, floor and ceil, which
//! are exact or correctly rounded, and libm's sin and cos for the heading
//! wedges, so native and wasm give the same bits.
//! Nothing decides soundness here: this is a drawing. Complexity:
//! O(N + D + G log G + G·[`MAX_GROUP_OUTLINES`] + R + ENVELOPE_CELLS²) for
//! N trajectory boxes, D detections, G groups and R region boxes (the
//! heading wedges add O(N + [`MAX_HEADING_MARKS`]·[`ARC_POINTS`])); no
//! allocation is sized by a number read from the input (only by the input's
//! own length or the constants here).

use crate::format::result::{BoxOut, IntervalOut, ResultDoc};
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
/// Most heading wedges drawn (every k-th step and the last).
pub const MAX_HEADING_MARKS: usize = 48;
/// Radius of a heading wedge, as a fraction of the view's longer side.
pub const HEADING_RADIUS: f64 = 0.035;
/// Points on the arc of a full turn (a wedge has its share, at least 2).
pub const ARC_POINTS: usize = 36;

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
    /// Closed polygons `polygons` (filled when `fill_alpha` > 0, outlined
    /// when `line_width` > 0); a polygon of two points is a segment.
    Polygons,
}

/// One layer of the picture, in drawing order.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Layer {
    /// Stable name: `trajectory`, `headings`, `detections`, `regions`,
    /// `groups`, `truth_path`, `truth_headings`, `truth_landmarks`.
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
    /// Polygons, each a list of points `[x, y]` (kind `polygons`).
    pub polygons: Vec<Vec<[f64; 2]>>,
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
/// Colour of the heading wedges.
pub const HEADINGS: &str = "#e67e22";

/// A box's first two axes `[x0, x1, y0, y1]`, when bounded and non-empty.
fn rect(b: &BoxOut) -> Option<[f64; 4]> {
    let a = b.axes()?;
    let axis = |x: &crate::interval::Interval| {
        (x.lo().is_finite() && x.hi().is_finite()).then_some((x.lo(), x.hi()))
    };
    let (x0, x1) = axis(a.first()?)?;
    let (y0, y1) = axis(a.get(1)?)?;
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
        // Not 300 digits for 1e300.
        Some(x) if x.abs() >= 1e7 => format!("{x:.2e} m"),
        Some(x) if x.abs() >= 100.0 => format!("{x:.0} m"),
        Some(x) if x.abs() >= 1.0 => format!("{x:.1} m"),
        Some(x) if x.abs() >= 0.01 => format!("{x:.3} m"),
        Some(x) if x.abs() > 0.0 => format!("{x:.2e} m"),
        Some(_) => "0 m".to_string(),
    }
}

/// A step's position box and heading interval, when drawable.
type StepMark = (Option<[f64; 4]>, Option<[f64; 2]>);

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
    /// odometry2d: per step, the position box and the heading interval
    /// (`None`: not drawable); empty for the other models.
    steps: Vec<StepMark>,
    /// Per step, the true position and heading (`None`: unknown).
    truth_poses: Vec<(Option<[f64; 2]>, Option<f64>)>,
}

impl Drawable {
    fn read(result: &ResultDoc, mission: &Value) -> Drawable {
        let boxes = &result.trajectory.0;
        let trajectory: Vec<[f64; 4]> = boxes.iter().filter_map(rect).collect();
        let undrawn = match boxes.len() - trajectory.len() {
            0 => String::new(),
            1 => " (1 more unbounded or empty, not drawn)".to_string(),
            u => format!(" ({u} more unbounded or empty, not drawn)"),
        };
        Drawable {
            trajectory,
            undrawn,
            detections: result.detections.0.iter().filter_map(rect).collect(),
            group_boxes: result.landmarks.0.iter().map(rect).collect(),
            truth_path: list(&mission["truth"]["positions"])
                .iter()
                .filter_map(point)
                .collect(),
            truth_landmarks: list(&mission["truth"]["landmarks"])
                .iter()
                .filter_map(point)
                .collect(),
            steps: result
                .headings
                .iter()
                .flat_map(|h| &h.0)
                .enumerate()
                .map(|(i, h)| (boxes.get(i).and_then(rect), heading(h)))
                .collect(),
            truth_poses: list(&mission["truth"]["headings"])
                .iter()
                .enumerate()
                .map(|(i, h)| {
                    let p = mission["truth"]["positions"].get(i).and_then(point);
                    (p, h.as_f64().filter(|t| t.is_finite()))
                })
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

/// A heading interval `[lo, hi]` (a bound may be infinite), when not
/// empty.
fn heading(h: &IntervalOut) -> Option<[f64; 2]> {
    (!h.0.is_empty()).then_some([h.0.lo(), h.0.hi()])
}

/// The outline of a heading wedge: the centre `c`, then the arc of radius
/// `r` over the interval `h`; a disc (the circle alone) when `h` is 2π
/// wide or more, or unbounded. A zero-width interval gives a segment.
fn wedge(c: [f64; 2], r: f64, h: [f64; 2]) -> Vec<[f64; 2]> {
    let turn = 2.0 * core::f64::consts::PI;
    let width = h[1] - h[0];
    let at = |a: f64| [c[0] + r * libm::cos(a), c[1] + r * libm::sin(a)];
    // A NaN width (both bounds infinite) is a disc too.
    if width >= turn || width.is_nan() {
        return (0..ARC_POINTS)
            .map(|k| at(k as f64 * turn / ARC_POINTS as f64))
            .collect();
    }
    let n = ((width / turn * ARC_POINTS as f64).ceil() as usize).clamp(1, ARC_POINTS);
    let mut points = Vec::with_capacity(n + 2);
    points.push(c);
    points.extend((0..=n).map(|k| at(h[0] + width * k as f64 / n as f64)));
    points
}

/// "1st", "2nd", "3rd", "4th", "11th", "12th", "22nd".
fn ordinal(n: usize) -> String {
    let suffix = match (n % 10, n % 100) {
        (_, 11..=13) => "th",
        (1, _) => "st",
        (2, _) => "nd",
        (3, _) => "rd",
        _ => "th",
    };
    format!("{n}{suffix}")
}

/// Layer 1b (odometry2d): the heading wedges of every k-th step that has a
/// bounded position box and a heading, at most [`MAX_HEADING_MARKS`] (the
/// last kept), and the circles of those 2π wide or more (a layer of their
/// own, outlined only: stacked discs would hide everything under them);
/// with the steps drawn, for the true-heading ticks. Empty when there is
/// none, or the view is too wide for a finite radius.
fn heading_layers(d: &Drawable, view: [f64; 4]) -> (Vec<Layer>, Vec<usize>) {
    let r = HEADING_RADIUS * (view[1] - view[0]).max(view[3] - view[2]);
    let candidates: Vec<usize> = (0..d.steps.len())
        .filter(|&i| matches!(d.steps[i], (Some(_), Some(_))))
        .collect();
    let m = candidates.len();
    if m == 0 || !(r.is_finite() && r > 0.0) {
        return (Vec::new(), Vec::new());
    }
    let stride = m.div_ceil(MAX_HEADING_MARKS).max(1);
    let mut drawn: Vec<usize> = candidates.iter().step_by(stride).copied().collect();
    if drawn.last() != Some(&candidates[m - 1]) {
        drawn.push(candidates[m - 1]);
    }
    let turn = 2.0 * core::f64::consts::PI;
    let (mut wedges, mut discs) = (Vec::new(), Vec::new());
    for &i in &drawn {
        if let (Some(b), Some(h)) = d.steps[i] {
            let c = [b[0] / 2.0 + b[1] / 2.0, b[2] / 2.0 + b[3] / 2.0];
            if h[1] - h[0] < turn {
                wedges.push(wedge(c, r, h));
            } else {
                discs.push(wedge(c, r, h));
            }
        }
    }
    let at = if stride == 1 {
        format!("at each of the {m} steps")
    } else {
        format!("at every {} of {m} steps", ordinal(stride))
    };
    let layer = |name, label, fill_alpha, line_width, polygons| Layer {
        name,
        label,
        kind: Kind::Polygons,
        colour: HEADINGS,
        fill_alpha,
        line_width,
        rects: Vec::new(),
        points: Vec::new(),
        polygons,
    };
    let mut layers = Vec::new();
    if !wedges.is_empty() {
        layers.push(layer(
            "headings",
            format!("heading (interval) {at}"),
            0.2,
            1.0,
            wedges,
        ));
    }
    if !discs.is_empty() {
        let n = discs.len();
        layers.push(layer(
            "headings_unknown",
            format!("heading (interval) 2\u{3c0} wide or more: a circle ({n} of the steps drawn)"),
            0.0,
            0.6,
            discs,
        ));
    }
    (layers, drawn)
}

/// The true-heading ticks: from the true position along the true heading,
/// one wedge radius long, at the steps that have a wedge and a known truth.
fn truth_heading_layer(d: &Drawable, view: [f64; 4], drawn: &[usize]) -> Option<Layer> {
    let r = HEADING_RADIUS * (view[1] - view[0]).max(view[3] - view[2]);
    let polygons: Vec<Vec<[f64; 2]>> = drawn
        .iter()
        .filter_map(|&i| match d.truth_poses.get(i) {
            Some(&(Some(p), Some(t))) => {
                Some(vec![p, [p[0] + r * libm::cos(t), p[1] + r * libm::sin(t)]])
            }
            _ => None,
        })
        .collect();
    (!polygons.is_empty()).then(|| Layer {
        name: "truth_headings",
        label: "true heading".to_string(),
        kind: Kind::Polygons,
        colour: TRUTH,
        fill_alpha: 0.0,
        line_width: 1.0,
        rects: Vec::new(),
        points: Vec::new(),
        polygons,
    })
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
        polygons: Vec::new(),
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
fn group_layers(d: &Drawable, result: &ResultDoc, mission: &Value, layers: &mut Vec<Layer>) {
    let groups = d.group_boxes.len();
    if groups == 0 {
        return;
    }
    let drawn = tightest(&d.group_boxes);
    let regions = result.landmark_regions.as_ref().map_or(&[][..], |r| &r.0);
    let region_rects: Vec<[f64; 4]> = drawn
        .iter()
        .filter_map(|&g| regions.get(g))
        .flat_map(|paving| paving.0.iter().filter_map(rect))
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
            polygons: Vec::new(),
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
            polygons: Vec::new(),
        });
    }
}

/// The title (mission, contractor, status) and the subtitle (diameters,
/// whether the truth is inside).
fn titles(result: &ResultDoc) -> (String, String) {
    let (name, contractor) = (&result.mission, &result.options.contractor);
    let status = result.status.name();
    let metrics = &result.metrics;
    let mut subtitle = format!(
        "max trajectory diameter {}, mean {}",
        metres(Some(metrics.max_trajectory_diameter.0)),
        metres(Some(metrics.mean_trajectory_diameter.0))
    );
    if let Some(inside) = result.score.as_ref().map(|s| s.truth_inside) {
        subtitle.push_str(if inside {
            ", truth inside"
        } else {
            ", TRUTH OUTSIDE"
        });
    }
    (format!("{name}: {contractor}, {status}"), subtitle)
}

/// Describes the figure of `result` (`nvector-result/1`, read through its
/// types: [`crate::format::result::read`]), with the truth of `mission`
/// (`nvector-mission/1`) when given. Values it cannot draw (unbounded or
/// empty boxes; in the mission, non-numbers) are left out, never an
/// error.
pub fn describe(result: &ResultDoc, mission: Option<&Value>) -> Figure {
    let null = Value::Null;
    let mission = mission.unwrap_or(&null);
    let d = Drawable::read(result, mission);
    let view = d.view();
    let mut layers = Vec::new();
    layers.extend(trajectory_layer(&d, view));
    let (headings, drawn) = heading_layers(&d, view);
    layers.extend(headings);
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
    if let Some(ticks) = truth_heading_layer(&d, view, &drawn) {
        // Over the true path, under the true landmarks' markers.
        let at = layers
            .iter()
            .position(|l| l.name == "truth_landmarks")
            .unwrap_or(layers.len());
        layers.insert(at, ticks);
    }
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
    crate::sort::stable_by(&mut order, |a, b| {
        area(&a.1).total_cmp(&area(&b.1)).then(a.0.cmp(&b.0))
    });
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

    /// A result: `fields` over a whole one with no boxes (status
    /// consistent); `metrics` entries are set one by one.
    fn doc(fields: Value) -> ResultDoc {
        let mut v = json!({
            "detections": [], "format": "nvector-result/1", "landmarks": [],
            "matching": [], "mission": "m", "status": "consistent",
            "metrics": {"contractions": 0, "elapsed_ms": 0.0, "matched_detections": 0,
                "max_detection_diameter": 0.0, "max_trajectory_diameter": 0.0,
                "mean_trajectory_diameter": 0.0, "rounds": 0},
            "options": {"contractor": "best", "max_rounds": 10, "tolerance": 0.0},
        });
        for (k, x) in fields.as_object().expect("an object") {
            match x.as_object() {
                Some(o) if k == "metrics" => {
                    for (m, y) in o {
                        v[k][m] = y.clone();
                    }
                }
                _ => v[k] = x.clone(),
            }
        }
        crate::format::result::read_value(&v).unwrap_or_else(|e| panic!("{e}"))
    }

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
        let f = describe(&doc(json!({"trajectory": traj})), None);
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
        let result = doc(json!({
            "metrics": {"max_trajectory_diameter": 73.02259, "mean_trajectory_diameter": 0.004},
            "trajectory": [[[0, 1], [0, 1]]],
            "detections": ["empty", "empty", "empty", "empty", "empty", "empty", "empty", "empty"],
            "landmarks": [[[0, 10], [0, 10]], [[1, 2], [1, 2]], [[5, 30], [5, 30]], [["-inf", 1], [0, 1]]],
            "matching": [[0, 1], [2, 3], [4, 5], [6, 7]],
        }));
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
            &doc(json!({"trajectory": traj, "metrics": {"max_trajectory_diameter": "inf"}})),
            None,
        );
        let layer = &f.layers[0];
        assert!(layer.rects.len() <= MAX_TRAJECTORY_BOXES + 1);
        assert!(f.subtitle.contains("unbounded"));
        let nothing = doc(json!({"trajectory": ["empty"]}));
        assert!(describe(&nothing, Some(&json!(7))).layers.is_empty());
    }

    /// An odometry2d-like result: `n` + 1 steps along x, heading interval
    /// [0.1 i - w, 0.1 i + w] at step i (w = 4 past step 300: a disc).
    fn odometry_result(n: usize) -> (Value, Value) {
        let traj: Vec<Value> = (0..=n)
            .map(|i| json!([[i as f64 - 0.5, i as f64 + 0.5], [-0.5, 0.5]]))
            .collect();
        let heads: Vec<Value> = (0..=n)
            .map(|i| {
                let w = if i > 300 { 4.0 } else { 0.2 };
                json!([0.1 * i as f64 - w, 0.1 * i as f64 + w])
            })
            .collect();
        let truth_pos: Vec<Value> = (0..=n).map(|i| json!([i as f64, 0.0])).collect();
        let truth_heads: Vec<Value> = (0..=n)
            .map(|i| {
                if i == 0 {
                    Value::Null
                } else {
                    json!(0.1 * i as f64)
                }
            })
            .collect();
        (
            json!({"trajectory": traj, "headings": heads}),
            json!({"truth": {"positions": truth_pos, "headings": truth_heads}}),
        )
    }

    #[test]
    fn headings_are_wedges_from_the_box_centres_over_their_intervals() {
        let (result, mission) = odometry_result(400);
        let f = describe(&doc(result), Some(&mission));
        let names: Vec<&str> = f.layers.iter().map(|l| l.name).collect();
        assert_eq!(
            names,
            [
                "trajectory",
                "headings",
                "headings_unknown",
                "truth_path",
                "truth_headings"
            ]
        );
        let (h, u) = (&f.layers[1], &f.layers[2]);
        assert_eq!(h.kind, Kind::Polygons);
        assert_eq!(h.label, "heading (interval) at every 9th of 401 steps");
        assert_eq!(
            u.label,
            "heading (interval) 2\u{3c0} wide or more: a circle (12 of the steps drawn)"
        );
        assert_eq!((u.fill_alpha, h.fill_alpha > 0.0), (0.0, true));
        assert!(h.polygons.len() + u.polygons.len() <= MAX_HEADING_MARKS + 1);
        let r = HEADING_RADIUS * (f.view[1] - f.view[0]).max(f.view[3] - f.view[2]);
        let steps: Vec<usize> = (0..=400).step_by(9).chain([400]).collect();
        assert_eq!(h.polygons.len() + u.polygons.len(), steps.len());
        let near = |a: f64, b: f64| (a - b).abs() <= 1e-9 * (1.0 + a.abs());
        for (poly, &i) in h.polygons.iter().chain(&u.polygons).zip(&steps) {
            let c = [i as f64, 0.0];
            let (lo, hi) = if i > 300 {
                (0.1 * i as f64 - 4.0, 0.1 * i as f64 + 4.0)
            } else {
                (0.1 * i as f64 - 0.2, 0.1 * i as f64 + 0.2)
            };
            let arc = if i > 300 {
                // A disc: the circle alone, every point at the radius.
                assert_eq!(poly.len(), ARC_POINTS);
                &poly[..]
            } else {
                assert_eq!(poly[0], c, "step {i}: the wedge starts at the box centre");
                &poly[1..]
            };
            for p in arc {
                let (dx, dy) = (p[0] - c[0], p[1] - c[1]);
                assert!(near(libm::hypot(dx, dy), r), "step {i}: {p:?} off the arc");
                if i <= 300 {
                    // The point's angle, brought next to the interval,
                    // lies in it.
                    let mut a = libm::atan2(dy, dx);
                    let turn = 2.0 * core::f64::consts::PI;
                    while a < lo - 1e-9 {
                        a += turn;
                    }
                    while a > hi + 1e-9 {
                        a -= turn;
                    }
                    assert!(
                        lo - 1e-9 <= a && a <= hi + 1e-9,
                        "step {i}: angle {a} not in [{lo}, {hi}]"
                    );
                }
            }
            if i <= 300 {
                // Both ends of the interval are on the arc.
                let (first, last) = (arc[0], arc[arc.len() - 1]);
                assert!(
                    near(first[0], c[0] + r * libm::cos(lo)) && near(first[1], r * libm::sin(lo))
                );
                assert!(
                    near(last[0], c[0] + r * libm::cos(hi)) && near(last[1], r * libm::sin(hi))
                );
            }
        }
        // The true-heading ticks: at the drawn steps with a known truth
        // (not step 0), along the true heading.
        let t = &f.layers[4];
        assert_eq!(t.label, "true heading");
        assert_eq!(t.polygons.len(), steps.len() - 1);
        let p = &t.polygons[0];
        assert_eq!(p[0], [9.0, 0.0]);
        assert!(near(p[1][0], 9.0 + r * libm::cos(0.9)));
    }

    #[test]
    fn no_headings_no_heading_layer_and_unbounded_headings_are_discs() {
        // A unicycle2d result has no `headings`.
        let (mut result, mission) = odometry_result(20);
        result.as_object_mut().unwrap().remove("headings");
        let f = describe(&doc(result), Some(&mission));
        assert!(f
            .layers
            .iter()
            .all(|l| l.name != "headings" && l.name != "truth_headings"));
        assert!(f.layers.iter().all(|l| !l.label.contains("heading")));
        // Unbounded, huge and empty headings; an unbounded box.
        let result = doc(json!({
            "trajectory": [[[0, 1], [0, 1]], [[0, 1], [0, 1]], [[0, 1], [0, 1]], [["-inf", "inf"], [0, 1]], [[1, 2], [1, 2]], [[1, 2], [1, 2]]],
            "headings": [["-inf", "inf"], [-1e308, 1e308], [1e300, 1e300], [0, 1], "empty", "empty"],
        }));
        let f = describe(&result, None);
        let h = f.layers.iter().find(|l| l.name == "headings").unwrap();
        let u = f
            .layers
            .iter()
            .find(|l| l.name == "headings_unknown")
            .unwrap();
        assert_eq!((h.polygons.len(), u.polygons.len()), (1, 2));
        assert_eq!(u.polygons[0].len(), ARC_POINTS);
        assert_eq!(u.polygons[1].len(), ARC_POINTS);
        assert!(h
            .polygons
            .iter()
            .chain(&u.polygons)
            .flatten()
            .all(|p| p[0].is_finite() && p[1].is_finite()));
        // A view too wide for a finite radius: no wedges, no panic.
        let wide =
            doc(json!({"trajectory": [[[-1.7e308, 1.7e308], [0, 1]]], "headings": [[0, 1]]}));
        assert!(describe(&wide, None)
            .layers
            .iter()
            .all(|l| l.name != "headings"));
        assert_eq!(ordinal(2), "2nd");
        assert_eq!(ordinal(13), "13th");
        assert_eq!(ordinal(21), "21st");
    }

    #[test]
    fn metres_rounds() {
        assert_eq!(metres(Some(73.02259360692675)), "73.0 m");
        assert_eq!(metres(Some(612.4)), "612 m");
        assert_eq!(metres(Some(0.4123)), "0.412 m");
        assert_eq!(metres(None), "?");
        assert_eq!(metres(Some(0.0)), "0 m");
        assert_eq!(metres(Some(0.004)), "4.00e-3 m");
        assert_eq!(metres(Some(9_999_999.0)), "9999999 m");
        assert_eq!(metres(Some(1e308)), "1.00e308 m");
        assert_eq!(metres(Some(-1.7e308)), "-1.70e308 m");
    }
}
