//! A [`Mission`] written back in the spec's format through its document
//! types (`format::mission_doc`; `Mission::from_value(&m.to_value()) ==
//! m`).

use super::{Detection, Mission, Model, Points, Truth, FORMAT};
use crate::format::leaf::{BoxIn, Finite, Integer, IntervalIn, List, PerStep, PointsIn};
use crate::format::mission_doc::{
    ChannelDoc, DetectionDoc, DriftWindowDoc, InputsDoc, MissionDoc, TruthDoc,
};
use crate::ibox::IntervalBox;
use crate::odometry::drift::DriftWindow;
use serde_json::Value;

impl Mission {
    /// The mission in the spec's format (`from_value(to_value(m)) == m`).
    pub fn to_value(&self) -> Value {
        crate::format::to_value(&self.to_doc())
    }

    /// The mission as its document: every field the validation reads back
    /// into this mission (`final_position` and `meta` always, `null` when
    /// absent; odometry2d's fields for odometry2d only; the defaults
    /// `landmark_min_separation` 0 and `max_outliers` 0 left out).
    pub fn to_doc(&self) -> MissionDoc {
        let odometry = self.model == Model::Odometry2d;
        let inputs = self
            .model
            .channels()
            .iter()
            .zip(&self.inputs)
            .map(|(&name, ch)| {
                let lo = ch.iter().map(|x| x.lo()).collect();
                let hi = ch.iter().map(|x| x.hi()).collect();
                (name, ChannelDoc::bounds(lo, hi))
            });
        MissionDoc {
            format: Some(FORMAT.into()),
            name: Some(self.name.clone()),
            model: Some(self.model.name().into()),
            dt: Some(Finite(self.dt)),
            steps: Some(Integer::Value(self.steps as u64)),
            initial_position: Some(box_doc(&self.initial_position)),
            final_position: self.final_position.as_ref().map(box_doc),
            initial_heading: self.initial_heading.map(IntervalIn),
            final_heading: self.final_heading.map(IntervalIn),
            inputs: Some(InputsDoc::of(inputs)),
            motion_error: Some(PerStep::Each(self.motion_error.clone())),
            heading_error: odometry.then(|| PerStep::Each(self.heading_error.clone())),
            heading_drift: windows(odometry, &self.heading_drift),
            motion_drift: windows(odometry, &self.motion_drift),
            sensor_offset: self.sensor_offset.map(|s| List(s.map(Finite).to_vec())),
            detections: Some(List(self.detections.iter().map(detection_doc).collect())),
            landmark_count: self.landmark_count.map(|n| Integer::Value(n as u64)),
            landmark_region: self.landmark_region.as_ref().map(box_doc),
            landmark_min_separation: (self.landmark_min_separation > 0.0)
                .then_some(Finite(self.landmark_min_separation)),
            max_outliers: (self.max_outliers > 0)
                .then_some(Integer::Value(self.max_outliers as u64)),
            meta: Some(self.meta.clone()),
            truth: self.truth.as_ref().map(truth_doc),
        }
    }
}

/// A box as its document.
pub(crate) fn box_doc(b: &IntervalBox) -> BoxIn {
    BoxIn(b.axes().to_vec())
}

/// The drift windows, when the model has them and there are any.
fn windows(odometry: bool, w: &[DriftWindow]) -> Option<List<DriftWindowDoc>> {
    (odometry && !w.is_empty()).then(|| {
        List(
            w.iter()
                .map(|w| DriftWindowDoc {
                    steps: Some(Integer::Value(w.steps)),
                    error: Some(Finite(w.error)),
                    exempt_above: w.exempt_above.map(Finite),
                })
                .collect(),
        )
    })
}

/// A detection as its document (the optional fields when present).
fn detection_doc(d: &Detection) -> DetectionDoc {
    DetectionDoc {
        step: Some(Integer::Value(d.step as u64)),
        range: Some(IntervalIn(d.range)),
        bearing: d.bearing.map(IntervalIn),
        region: d.region.as_ref().map(box_doc),
        depth: d.depth.map(IntervalIn),
        landmark: d.landmark.map(|l| Integer::Value(l as u64)),
        scan: d.scan.map(Integer::Value),
    }
}

/// Points as their document, `null` where `known` says so.
fn points_doc(p: &Points, known: Option<&[bool]>) -> PointsIn {
    let mut out = PointsIn {
        count: p.len(),
        width: p.dim(),
        ..PointsIn::default()
    };
    for (i, row) in p.iter().enumerate() {
        if known.is_some_and(|k| !k[i]) {
            out.nulls.push(i);
        } else {
            out.flat.extend_from_slice(row);
        }
    }
    out
}

/// The truth as its document (`null` for an unknown position).
fn truth_doc(t: &Truth) -> TruthDoc {
    TruthDoc {
        positions: Some(points_doc(&t.positions, t.positions_known.as_deref())),
        landmarks: Some(points_doc(&t.landmarks, None)),
        matching: Some(List(
            t.matching
                .iter()
                .map(|m| m.map(|j| Integer::Value(j as u64)))
                .collect(),
        )),
        headings: t
            .headings
            .as_ref()
            .map(|h| List(h.iter().map(|x| x.map(Finite)).collect())),
    }
}
