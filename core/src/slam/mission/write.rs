//! A [`Mission`] written back in the spec's format
//! (`Mission::from_value(&m.to_value()) == m`).

use super::{Detection, Mission, Model, Truth, FORMAT};
use crate::json;
use serde_json::{Map, Value};

impl Mission {
    /// odometry2d's fields of [`Mission::to_value`]: `heading_error` and
    /// the drift windows when there are any.
    fn odometry_fields(&self, o: &mut Map<String, Value>) {
        o.insert(
            "heading_error".into(),
            serde_json::json!(self.heading_error),
        );
        for (name, windows) in [
            ("heading_drift", &self.heading_drift),
            ("motion_drift", &self.motion_drift),
        ] {
            if windows.is_empty() {
                continue;
            }
            let w: Vec<Value> = windows
                .iter()
                .map(|w| {
                    let mut o = serde_json::json!({"steps": w.steps, "error": w.error});
                    if let Some(t) = w.exempt_above {
                        o["exempt_above"] = t.into();
                    }
                    o
                })
                .collect();
            o.insert(name.into(), Value::Array(w));
        }
    }

    /// The mission in the spec's format (`from_value(to_value(m)) == m`).
    pub fn to_value(&self) -> Value {
        let mut o = Map::new();
        o.insert("format".into(), FORMAT.into());
        o.insert("name".into(), self.name.clone().into());
        o.insert("model".into(), self.model.name().into());
        o.insert("dt".into(), self.dt.into());
        o.insert("steps".into(), self.steps.into());
        o.insert(
            "initial_position".into(),
            json::box_to_json(&self.initial_position),
        );
        o.insert(
            "final_position".into(),
            self.final_position
                .as_ref()
                .map_or(Value::Null, json::box_to_json),
        );
        let mut inputs = Map::new();
        for (name, ch) in self.model.channels().iter().zip(&self.inputs) {
            // Bounds, not bare floats: an unbounded input is "-inf" /
            // "inf" (serde_json would write a non-finite float as null).
            let lo: Vec<Value> = ch.iter().map(|x| json::bound_to_json(x.lo())).collect();
            let hi: Vec<Value> = ch.iter().map(|x| json::bound_to_json(x.hi())).collect();
            inputs.insert((*name).into(), serde_json::json!({"lo": lo, "hi": hi}));
        }
        o.insert("inputs".into(), Value::Object(inputs));
        o.insert("motion_error".into(), serde_json::json!(self.motion_error));
        if let Some(h) = self.initial_heading {
            o.insert("initial_heading".into(), json::interval_to_json(h));
        }
        if let Some(h) = self.final_heading {
            o.insert("final_heading".into(), json::interval_to_json(h));
        }
        if self.model == Model::Odometry2d {
            self.odometry_fields(&mut o);
        }
        if let Some(s) = self.sensor_offset {
            o.insert("sensor_offset".into(), serde_json::json!(s));
        }
        if self.landmark_min_separation > 0.0 {
            o.insert(
                "landmark_min_separation".into(),
                self.landmark_min_separation.into(),
            );
        }
        let dets: Vec<Value> = self.detections.iter().map(detection_json).collect();
        o.insert("detections".into(), Value::Array(dets));
        if let Some(n) = self.landmark_count {
            o.insert("landmark_count".into(), n.into());
        }
        if let Some(r) = &self.landmark_region {
            o.insert("landmark_region".into(), json::box_to_json(r));
        }
        if self.max_outliers > 0 {
            o.insert("max_outliers".into(), self.max_outliers.into());
        }
        o.insert("meta".into(), self.meta.clone());
        if let Some(t) = &self.truth {
            o.insert("truth".into(), truth_json(t));
        }
        Value::Object(o)
    }
}

/// A detection in the spec's format (the optional fields when present).
fn detection_json(d: &Detection) -> Value {
    let mut m = Map::new();
    m.insert("step".into(), d.step.into());
    m.insert("range".into(), json::interval_to_json(d.range));
    if let Some(b) = d.bearing {
        m.insert("bearing".into(), json::interval_to_json(b));
    }
    if let Some(r) = &d.region {
        m.insert("region".into(), json::box_to_json(r));
    }
    if let Some(z) = d.depth {
        m.insert("depth".into(), json::interval_to_json(z));
    }
    if let Some(l) = d.landmark {
        m.insert("landmark".into(), l.into());
    }
    if let Some(scan) = d.scan {
        m.insert("scan".into(), scan.into());
    }
    Value::Object(m)
}

/// The truth in the spec's format (`null` for an unknown position).
fn truth_json(t: &Truth) -> Value {
    let positions = match &t.positions_known {
        None => serde_json::json!(t.positions),
        Some(known) => Value::Array(
            t.positions
                .iter()
                .zip(known)
                .map(|(p, &k)| if k { serde_json::json!(p) } else { Value::Null })
                .collect(),
        ),
    };
    let mut truth = serde_json::json!({"positions": positions, "landmarks": t.landmarks, "matching": t.matching});
    if let Some(h) = &t.headings {
        truth["headings"] = serde_json::json!(h);
    }
    truth
}
