//! `nvector-result/1`: the boxes, matching, metrics and score of a solved
//! mission (docs/formats.md, "Result").

use super::mission::Mission;
use super::robust::relaxed_intersection;
use super::types::SolveOptions;
pub use super::types::{Solution, SolveStatus};
use crate::error::InputError;
use crate::format::result::{BoxView, Diameter, IntervalOut, Metrics, Options, ResultDoc, Score};
use crate::ibox::IntervalBox;
use serde::ser::{SerializeMap, Serializer};
use serde::Serialize;
use serde_json::Value;

// `Solution` lives in `super::types` (the bottom of the pipeline); its
// landmarks need the q-relaxed intersection of the robust propagation, a
// layer above, so this method is defined here, with the output.
impl Solution {
    /// One box per matching group, in the order of `matching`: the common
    /// intersection of its members' boxes; with false detections allowed
    /// (q = `max_outliers` > 0), the q-relaxed intersection of the boxes of
    /// the members not proved false (a sub-mission may drop up to q of
    /// them; see [`super::robust`]).
    pub fn landmarks(&self) -> Vec<IntervalBox> {
        let q = self.model.max_outliers;
        self.matching
            .iter()
            .map(|g| {
                if q > 0 {
                    let members: Vec<&IntervalBox> = g
                        .iter()
                        .map(|&j| &self.model.det[j])
                        .filter(|b| !b.is_empty())
                        .collect();
                    return relaxed_intersection(&members, q, self.model.dim);
                }
                let mut b = self.model.det[g[0]].clone();
                for &j in &g[1..] {
                    b.intersect_with(&self.model.det[j]);
                }
                b
            })
            .collect()
    }
}

/// Score against the mission's truth: (truth_inside, matching_errors,
/// matching_recall). A false detection (`None` in `truth.matching`) has no
/// landmark: its box is not checked, it is never counted as matched, and
/// every pair of a group that holds it is a matching error. The recall is
/// the fraction of the true detections that ended in a group of size >= 2
/// (1 when there is none).
pub fn score(mission: &Mission, s: &Solution) -> Option<(bool, usize, f64)> {
    let truth = mission.truth.as_ref()?;
    let m = &s.model;
    // A null truth entry (unknown position) is not scored.
    let known = |i: usize| truth.positions_known.as_ref().is_none_or(|k| k[i]);
    let mut inside = truth
        .positions
        .iter()
        .enumerate()
        .all(|(i, p)| !known(i) || m.position(i).contains(p));
    // odometry2d: the true headings as real numbers (never modulo 2π),
    // nulls not scored.
    if let Some(headings) = &truth.headings {
        if !m.heading.is_empty() {
            inside &= headings
                .iter()
                .zip(&m.heading)
                .all(|(t, h)| t.is_none_or(|t| h.contains(t)));
        }
    }
    for (j, b) in m.det.iter().enumerate() {
        if let Some(l) = truth.matching[j] {
            inside &= b.contains(&truth.landmarks[l]);
        }
    }
    for (g, b) in s.matching.iter().zip(s.landmarks()) {
        if let Some(l) = g.iter().find_map(|&j| truth.matching[j]) {
            inside &= b.contains(&truth.landmarks[l]);
        }
    }
    let mut errors = 0;
    for g in &s.matching {
        for (x, &a) in g.iter().enumerate() {
            for &b in &g[x + 1..] {
                match (truth.matching[a], truth.matching[b]) {
                    (Some(la), Some(lb)) if la == lb => {}
                    _ => errors += 1,
                }
            }
        }
    }
    let grouped = s
        .matching
        .iter()
        .flatten()
        .filter(|&&j| truth.matching[j].is_some())
        .count();
    let real = truth.matching.iter().filter(|l| l.is_some()).count();
    let recall = if real == 0 {
        1.0
    } else {
        grouped as f64 / real as f64
    };
    Some((inside, errors, recall))
}

/// The result JSON (`metrics.elapsed_ms` = 0; the caller measures time).
pub fn result_json(mission: &Mission, options: &SolveOptions, s: &Solution) -> Value {
    // Serializing a view only fails for non-string keys, which it has none
    // of.
    serde_json::to_value(ResultView::new(mission, options, s, 0.0)).unwrap_or(Value::Null)
}

/// The result as its format's type (what a reader of the written result
/// gets), `metrics.elapsed_ms` = `elapsed_ms`; an error would be a fault
/// of the writer (the test holds the two to the same bytes).
pub fn result_doc(
    mission: &Mission,
    options: &SolveOptions,
    s: &Solution,
    elapsed_ms: f64,
) -> Result<ResultDoc, InputError> {
    let view = ResultView::new(mission, options, s, elapsed_ms);
    crate::format::result::read_value(&serde_json::to_value(view).unwrap_or(Value::Null))
}

/// Writes the result JSON to `w` without building it in memory (a 10^6-step
/// trajectory as a `Value` takes hundreds of megabytes): the same bytes as
/// `serde_json::to_writer(w, &result_json(..))` with `metrics.elapsed_ms`
/// set to `elapsed_ms`. Native only (serde_json's `std`, which the wasm
/// modules leave out).
#[cfg(not(target_arch = "wasm32"))]
pub fn write_result<W: std::io::Write>(
    w: W,
    mission: &Mission,
    options: &SolveOptions,
    s: &Solution,
    elapsed_ms: f64,
) -> std::io::Result<()> {
    serde_json::to_writer(w, &ResultView::new(mission, options, s, elapsed_ms))
        .map_err(std::io::Error::from)
}

/// `nvector-result/1` of a solution, serialized field by field (keys in
/// sorted order, as a serde_json map iterates, so both ways give the same
/// bytes). Its OpenAPI schema (`openapi` feature) is [`SlamResult`]'s.
pub struct ResultView<'a> {
    mission: &'a Mission,
    options: &'a SolveOptions,
    s: &'a Solution,
    elapsed_ms: f64,
}

impl<'a> ResultView<'a> {
    fn new(
        mission: &'a Mission,
        options: &'a SolveOptions,
        s: &'a Solution,
        elapsed_ms: f64,
    ) -> ResultView<'a> {
        ResultView {
            mission,
            options,
            s,
            elapsed_ms,
        }
    }
}

impl ResultView<'_> {
    /// One paving per entry of `landmarks`: the group's landmark region
    /// when the shapes contractor built one (each box cut to the
    /// landmark's box), else that box.
    fn landmark_pavings(&self, landmarks: &[IntervalBox]) -> Vec<Vec<IntervalBox>> {
        let m = &self.s.model;
        self.s
            .matching
            .iter()
            .zip(landmarks)
            .map(
                |(g, b)| match g.iter().find_map(|&j| m.landmark_regions.get(j)?.as_ref()) {
                    Some(boxes) => boxes
                        .iter()
                        .map(|x| x.intersect(b))
                        .filter(|x| !x.is_empty())
                        .collect(),
                    None => vec![b.clone()],
                },
            )
            .collect()
    }

    /// The `metrics` object: work done and the sizes of the boxes.
    fn metrics(&self) -> Metrics {
        let (s, m) = (self.s, &self.s.model);
        let (max_d, mean_d) = m.trajectory_diameters();
        let max_det = m.det.iter().map(|b| b.diameter()).fold(0.0, f64::max);
        let matched: usize = s.matching.iter().map(|g| g.len()).sum();
        Metrics {
            contractions: s.contractions,
            elapsed_ms: self.elapsed_ms,
            false_detections: s.outliers.map(|t| t.proved_false),
            matched_detections: matched,
            max_detection_diameter: Diameter(max_det),
            max_heading_width: (!m.heading.is_empty()).then(|| Diameter(m.max_heading_width())),
            max_trajectory_diameter: Diameter(max_d),
            mean_trajectory_diameter: Diameter(mean_d),
            open_outliers: s.outliers.map(|t| t.open),
            rounds: s.rounds,
        }
    }
}

impl Serialize for ResultView<'_> {
    fn serialize<S: Serializer>(&self, ser: S) -> Result<S::Ok, S::Error> {
        let (s, m) = (self.s, &self.s.model);
        let dim = m.dim;
        let mut o = ser.serialize_map(None)?;
        o.serialize_entry("detections", &Seq(m.det.iter().map(|b| BoxView(b.axes()))))?;
        o.serialize_entry("format", "nvector-result/1")?;
        if !m.heading.is_empty() {
            o.serialize_entry("headings", &Seq(m.heading.iter().map(|&h| IntervalOut(h))))?;
        }
        let landmarks = s.landmarks();
        if !m.landmark_regions.is_empty() {
            let pavings = self.landmark_pavings(&landmarks);
            let views: Vec<Vec<BoxView>> = pavings
                .iter()
                .map(|p| p.iter().map(|x| BoxView(x.axes())).collect())
                .collect();
            o.serialize_entry("landmark_regions", &views)?;
        }
        o.serialize_entry(
            "landmarks",
            &Seq(landmarks.iter().map(|b| BoxView(b.axes()))),
        )?;
        o.serialize_entry("matching", &s.matching)?;
        o.serialize_entry("metrics", &self.metrics())?;
        o.serialize_entry("mission", &self.mission.name)?;
        o.serialize_entry(
            "options",
            &Options {
                contractor: self.options.association.name().to_string(),
                max_rounds: self.options.max_rounds,
                tolerance: self.options.tolerance,
            },
        )?;
        if let SolveStatus::Infeasible(r) = &s.status {
            o.serialize_entry("reason", r)?;
        }
        if let Some((inside, errors, recall)) = score(self.mission, s) {
            o.serialize_entry(
                "score",
                &Score {
                    matching_errors: errors,
                    matching_recall: recall,
                    truth_inside: inside,
                },
            )?;
        }
        let status = match &s.status {
            SolveStatus::Consistent => "consistent",
            SolveStatus::Infeasible(_) => "infeasible",
            SolveStatus::Stopped => "stopped",
        };
        o.serialize_entry("status", status)?;
        o.serialize_entry(
            "trajectory",
            &Seq(m.pos.chunks_exact(dim.max(1)).map(BoxView)),
        )?;
        o.end()
    }
}

/// An iterator serialized as an array (once).
struct Seq<I>(I);

impl<I: Iterator<Item = T> + Clone, T: Serialize> Serialize for Seq<I> {
    fn serialize<S: Serializer>(&self, ser: S) -> Result<S::Ok, S::Error> {
        ser.collect_seq(self.0.clone())
    }
}

/// The result of a SLAM job (`nvector-result/1`) as the OpenAPI document
/// names it: the schema of [`ResultView`]'s output.
pub type SlamResult = ResultView<'static>;

/// The schema of what [`ResultView::serialize`] writes (a map written
/// entry by entry, which no derive sees).
#[cfg(feature = "openapi")]
impl utoipa::PartialSchema for ResultView<'_> {
    fn schema() -> utoipa::openapi::RefOr<utoipa::openapi::schema::Schema> {
        use crate::format::openapi::{described, output};
        use utoipa::openapi::schema::{ArrayBuilder, ObjectBuilder, Type};
        use utoipa::ToSchema;
        let string = |d: &str| {
            ObjectBuilder::new()
                .schema_type(Type::String)
                .description(Some(d))
        };
        let indices = ArrayBuilder::new().items(
            ArrayBuilder::new().items(
                ObjectBuilder::new()
                    .schema_type(Type::Integer)
                    .format(Some(utoipa::openapi::SchemaFormat::Custom("uint64".into())))
                    .minimum(Some(0)),
            ),
        );
        let o = ObjectBuilder::new()
            .description(Some("The result of a SLAM job (`nvector-result/1`)."))
            .property(
                "format",
                string("Always `\"nvector-result/1\"`.").pattern(Some("^nvector-result/1$")),
            )
            .required("format")
            .property("mission", string("The mission's name."))
            .required("mission")
            .property(
                "status",
                string(
                    "What happened: consistent (a fixpoint with no empty domain), infeasible \
                     (a domain became empty: the data are contradictory, `reason`) or stopped \
                     (before the fixpoint: round cap or time limit; boxes sound).",
                )
                .enum_values(Some(["consistent", "infeasible", "stopped"])),
            )
            .required("status")
            .property(
                "reason",
                string("Why it is infeasible (with `infeasible`)."),
            )
            .property("options", described(Options::name(), "The options."))
            .required("options")
            .property("trajectory", output::boxes("N+1 boxes of p(0..=N)."))
            .required("trajectory");
        result_boxes(o)
            .property(
                "matching",
                indices.description(Some(
                    "Groups of detection indices proved to be one landmark.",
                )),
            )
            .required("matching")
            .property("metrics", described(Metrics::name(), "Figures."))
            .required("metrics")
            .property(
                "score",
                described(
                    Score::name(),
                    "Against the truth, when the mission has one.",
                ),
            )
            .into()
    }
}

/// The result's boxes other than the trajectory, each with its
/// description (a part of [`ResultView`]'s schema).
#[cfg(feature = "openapi")]
fn result_boxes(
    o: utoipa::openapi::schema::ObjectBuilder,
) -> utoipa::openapi::schema::ObjectBuilder {
    use crate::format::openapi::output;
    use utoipa::openapi::schema::{ArrayBuilder, Ref};
    o.property(
        "headings",
        ArrayBuilder::new()
            .description(Some("odometry2d only: N+1 intervals of th(0..=N)."))
            .items(Ref::from_schema_name("OutputInterval")),
    )
    .property(
        "detections",
        output::boxes("One box per input detection: the detected landmark's position."),
    )
    .required("detections")
    .property(
        "landmarks",
        output::boxes("One box per group of `matching`."),
    )
    .required("landmarks")
    .property(
        "landmark_regions",
        ArrayBuilder::new()
            .description(Some(
                "With the shapes contractor: per group of `matching`, the boxes of its \
                         landmark region (cut to the group's landmark box).",
            ))
            .items(output::boxes("A paving.")),
    )
}

#[cfg(feature = "openapi")]
impl utoipa::ToSchema for ResultView<'_> {
    fn name() -> std::borrow::Cow<'static, str> {
        std::borrow::Cow::Borrowed("SlamResult")
    }
    fn schemas(
        schemas: &mut Vec<(
            String,
            utoipa::openapi::RefOr<utoipa::openapi::schema::Schema>,
        )>,
    ) {
        use utoipa::{PartialSchema, ToSchema};
        schemas.push((Options::name().into(), Options::schema()));
        schemas.push((Metrics::name().into(), Metrics::schema()));
        <Metrics as ToSchema>::schemas(schemas);
        schemas.push((Score::name().into(), Score::schema()));
        crate::format::openapi::output::schemas(schemas);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::interval::Interval;
    use crate::json::box_to_json;
    use crate::slam::mission::Mission;
    use crate::slam::model::Model;
    use serde_json::{json, Map};

    /// The Value-building code the view replaced, kept to check the bytes.
    fn reference_result_json(mission: &Mission, options: &SolveOptions, s: &Solution) -> Value {
        let m = &s.model;
        let mut o = Map::new();
        o.insert("format".into(), "nvector-result/1".into());
        o.insert("mission".into(), mission.name.clone().into());
        let status = match &s.status {
            SolveStatus::Consistent => "consistent",
            SolveStatus::Infeasible(_) => "infeasible",
            SolveStatus::Stopped => "stopped",
        };
        o.insert("status".into(), status.into());
        if let SolveStatus::Infeasible(r) = &s.status {
            o.insert("reason".into(), r.clone().into());
        }
        o.insert(
            "options".into(),
            json!({
                "contractor": options.association.name(),
                "max_rounds": options.max_rounds,
                "tolerance": options.tolerance,
            }),
        );
        let trajectory: Vec<Value> = (0..=m.steps).map(|i| box_to_json(&m.position(i))).collect();
        o.insert("trajectory".into(), Value::Array(trajectory));
        o.insert(
            "detections".into(),
            Value::Array(m.det.iter().map(box_to_json).collect()),
        );
        o.insert(
            "landmarks".into(),
            Value::Array(s.landmarks().iter().map(box_to_json).collect()),
        );
        o.insert("matching".into(), json!(s.matching));
        if !m.landmark_regions.is_empty() {
            // Added with the detection shapes: per group, the landmark region the
            // shapes contractor built (found at any member), each box cut
            // to the group's landmark box and the empty ones dropped; the
            // landmark box alone when there is none.
            let landmarks = s.landmarks();
            let mut regions = Vec::new();
            for (g, b) in s.matching.iter().zip(&landmarks) {
                let mut region = None;
                for &j in g {
                    if let Some(Some(boxes)) = m.landmark_regions.get(j) {
                        region = Some(boxes);
                        break;
                    }
                }
                let boxes: Vec<Value> = match region {
                    Some(boxes) => boxes
                        .iter()
                        .map(|x| x.intersect(b))
                        .filter(|x| !x.is_empty())
                        .map(|x| box_to_json(&x))
                        .collect(),
                    None => vec![box_to_json(b)],
                };
                regions.push(Value::Array(boxes));
            }
            o.insert("landmark_regions".into(), Value::Array(regions));
        }
        let (max_d, mean_d) = m.trajectory_diameters();
        let max_det = m.det.iter().map(|b| b.diameter()).fold(0.0, f64::max);
        let matched: usize = s.matching.iter().map(|g| g.len()).sum();
        o.insert(
            "metrics".into(),
            json!({
                "max_trajectory_diameter": finite_or_inf(max_d),
                "mean_trajectory_diameter": finite_or_inf(mean_d),
                "max_detection_diameter": finite_or_inf(max_det),
                "matched_detections": matched,
                "rounds": s.rounds,
                "contractions": s.contractions,
                "elapsed_ms": 0.0,
            }),
        );
        if let Some(t) = s.outliers {
            o["metrics"]["false_detections"] = json!(t.proved_false);
            o["metrics"]["open_outliers"] = json!(t.open);
        }
        if let Some((inside, errors, recall)) = score(mission, s) {
            o.insert(
                "score".into(),
                json!({"truth_inside": inside, "matching_errors": errors, "matching_recall": recall}),
            );
        }
        Value::Object(o)
    }

    /// Checks the result's landmark regions on their own: one per group,
    /// each box inside the group's landmark box, the true landmark (when
    /// the mission has its truth and the status is consistent) in one of
    /// the boxes. Returns the number of regions checked.
    fn check_regions(m: &Mission, s: &Solution, regions: &Value) -> usize {
        let regions = regions.as_array().expect("an array");
        assert_eq!(regions.len(), s.matching.len());
        let landmarks = s.landmarks();
        for ((g, b), region) in s.matching.iter().zip(&landmarks).zip(regions) {
            let boxes: Vec<IntervalBox> = region
                .as_array()
                .expect("boxes")
                .iter()
                .map(|x| match x.as_str() {
                    Some("empty") => IntervalBox::empty(b.dim()),
                    _ => crate::json::ibox(x, "region", Some(b.dim())).expect("a box"),
                })
                .collect();
            if s.status == SolveStatus::Consistent {
                assert!(!boxes.is_empty(), "group {g:?} has an empty region");
            }
            for x in &boxes {
                assert!(x.is_subset(b), "{x:?} sticks out of {b:?}");
            }
            if let (Some(t), SolveStatus::Consistent) = (&m.truth, &s.status) {
                if let Some(l) = g.iter().find_map(|&j| t.matching[j]) {
                    let l: Vec<f64> = t.landmarks.iter().nth(l).expect("landmark").to_vec();
                    assert!(
                        boxes.iter().any(|x| x.contains(&l)),
                        "the region of {g:?} lost its landmark"
                    );
                }
            }
        }
        regions.len()
    }

    fn finite_or_inf(x: f64) -> Value {
        if x.is_finite() {
            json!(x)
        } else {
            json!("inf")
        }
    }

    /// The streamed writer gives the bytes of the former code that built
    /// the result as a `Value` (keys, numbers, "inf", "empty" alike), for
    /// consistent, infeasible and stopped solutions, with and without truth;
    /// the landmark regions (built by the reference on its own) are one per
    /// group, inside the group's landmark box, and hold the true landmark.
    #[test]
    fn streamed_result_is_the_former_bytes() {
        let mut regions_seen = 0;
        use crate::slam::simulate::{simulate, Scenario, SimulateOptions};
        use crate::slam::solve::solve_model;
        use crate::slam::types::{Association, SolveOptions};
        use std::sync::atomic::AtomicBool;
        for (scenario, seed, operator, max_rounds) in [
            (Scenario::Paper, 1, false, 10_000),
            (Scenario::Paper, 2, true, 1),
            (Scenario::Auv, 3, true, 10_000),
        ] {
            let mut o = SimulateOptions::new(scenario, seed);
            o.steps = Some(700);
            o.operator = operator;
            let mut v = simulate(&o);
            if seed == 2 {
                v.as_object_mut().unwrap().remove("truth");
            }
            for infeasible in [false, true] {
                if infeasible {
                    v["detections"][0]["range"] = json!([1e5, 1e5 + 1.0]);
                }
                let m = Mission::from_value(&v).unwrap();
                for association in [
                    Association::None,
                    Association::NVector(crate::nvector::Contractor::Best),
                ] {
                    let options = SolveOptions {
                        association,
                        max_rounds,
                        ..SolveOptions::default()
                    };
                    let s = solve_model(&m, &options, &mut |_| {}, &AtomicBool::new(false));
                    let mut want = reference_result_json(&m, &options, &s);
                    if let Some(regions) = want.get("landmark_regions") {
                        regions_seen += check_regions(&m, &s, regions);
                    }
                    want["metrics"]["elapsed_ms"] = json!(12.5);
                    let mut got = Vec::new();
                    write_result(&mut got, &m, &options, &s, 12.5).unwrap();
                    let got = String::from_utf8(got).unwrap();
                    assert_eq!(got, want.to_string());
                    read_back(&got);
                    let doc = result_doc(&m, &options, &s, 12.5).unwrap();
                    assert_eq!(serde_json::to_string(&doc).unwrap(), got);
                    want["metrics"]["elapsed_ms"] = json!(0.0);
                    assert_eq!(result_json(&m, &options, &s), want);
                }
            }
        }
        assert!(regions_seen > 0, "no landmark region was checked");
        // Unbounded and empty boxes.
        let m = mission();
        let mut s = solution(&m, vec![vec![0, 1]]);
        s.model.pos[1] = crate::Interval::new(f64::NEG_INFINITY, 2.0);
        s.model.det[2] = IntervalBox::empty(2);
        s.model.pos[3] = crate::Interval::EMPTY;
        let options = SolveOptions::default();
        let mut got = Vec::new();
        write_result(&mut got, &m, &options, &s, 0.0).unwrap();
        let got = String::from_utf8(got).unwrap();
        assert_eq!(got, reference_result_json(&m, &options, &s).to_string());
        read_back(&got);
    }

    /// A result written is read by the format's types
    /// ([`crate::format::result`]) and written by them again to the same
    /// bytes, from the text and from its parsed value.
    fn read_back(text: &str) {
        let doc = crate::format::result::read(text).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(serde_json::to_string(&doc).unwrap(), text);
        let v: Value = serde_json::from_str(text).unwrap();
        assert_eq!(crate::format::result::read_value(&v).unwrap(), doc);
    }

    /// Three detections of one landmark at (2, 2) by truth, the third a
    /// false detection (`null`), scored against hand-made solutions.
    fn mission() -> Mission {
        Mission::from_value(&json!({
            "format": "nvector-mission/1",
            "model": "unicycle2d",
            "dt": 1.0,
            "steps": 1,
            "initial_position": [[0, 0], [0, 0]],
            "inputs": {"speed": {"value": [0.0], "error": 0}, "heading": {"value": [0.0], "error": 0}},
            "detections": [
                {"step": 0, "range": [2.8, 2.9]},
                {"step": 1, "range": [2.8, 2.9]},
                {"step": 1, "range": [5, 6]}
            ],
            "landmark_count": 1,
            "truth": {"positions": [[0, 0], [0, 0]], "landmarks": [[2, 2]], "matching": [0, 0, null]}
        }))
        .unwrap()
    }

    fn solution(m: &Mission, matching: Vec<Vec<usize>>) -> Solution {
        let mut model = Model::new(m);
        model.pos.fill(crate::Interval::ZERO);
        model.det = vec![
            IntervalBox::new(&[crate::Interval::new(1.0, 3.0); 2]),
            IntervalBox::new(&[crate::Interval::new(1.5, 2.5); 2]),
            // Far from the landmark: not checked, the detection is false.
            IntervalBox::new(&[crate::Interval::new(4.0, 5.0); 2]),
        ];
        Solution {
            status: SolveStatus::Consistent,
            matching,
            rounds: 1,
            contractions: 0,
            model,
            outliers: None,
        }
    }

    #[test]
    fn a_false_detection_is_never_matched_and_its_group_is_an_error() {
        let m = mission();
        assert_eq!(
            score(&m, &solution(&m, vec![vec![0, 1]])),
            Some((true, 0, 1.0))
        );
        // Grouped with both true detections: two wrong pairs; the recall
        // counts the true detections only.
        assert_eq!(
            score(&m, &solution(&m, vec![vec![0, 1, 2]])),
            Some((false, 2, 1.0)),
            "the group's box (empty intersection) cannot hold the landmark"
        );
        assert_eq!(
            score(&m, &solution(&m, vec![vec![1, 2]])),
            Some((false, 1, 0.5))
        );
        assert_eq!(score(&m, &solution(&m, vec![])), Some((true, 0, 0.0)));
    }

    /// A `null` truth position (unknown at that step) is not scored; the
    /// same position given, outside its box, is.
    #[test]
    fn null_truth_positions_are_not_scored() {
        let far = |p: serde_json::Value| {
            let mut v = mission().to_value();
            v["truth"]["positions"][1] = p;
            Mission::from_value(&v).unwrap()
        };
        // Position 1's box away from the origin (a null entry is stored as
        // zeros: only skipping it keeps the score true).
        let away = |m: &Mission| {
            let mut s = solution(m, vec![vec![0, 1]]);
            s.model.pos[2] = Interval::new(10.0, 11.0);
            s.model.pos[3] = Interval::new(10.0, 11.0);
            s
        };
        let m = far(json!([50, 50]));
        assert_eq!(score(&m, &away(&m)), Some((false, 0, 1.0)));
        let m = far(json!([10.5, 10.5]));
        assert_eq!(score(&m, &away(&m)), Some((true, 0, 1.0)));
        let m = far(serde_json::Value::Null);
        assert_eq!(score(&m, &away(&m)), Some((true, 0, 1.0)));
    }

    /// A negative zero in a domain was written `-0.0` in the streamed
    /// result (platform-dependent sign from `f64::min`/`max`).
    #[test]
    fn signed_zero_bounds_stream_as_one_zero() {
        let m = mission();
        let mut s = solution(&m, vec![]);
        s.model.pos[0] = Interval::new(-0.0, -0.0);
        let mut out = Vec::new();
        write_result(&mut out, &m, &SolveOptions::default(), &s, 0.0).unwrap();
        let text = String::from_utf8(out).unwrap();
        assert!(
            text.contains("\"trajectory\":[[[0.0,0.0]"),
            "{}",
            &text[..200.min(text.len())]
        );
        assert!(!text.contains("-0.0"), "{text}");
    }
}
