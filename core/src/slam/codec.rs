//! A validated [`Mission`] as a compact binary stream, and back: how the
//! page hands a mission to the solver's wasm module without the JSON
//! reader in it (the simulators' module reads and validates the JSON with
//! [`Mission::from_value`], then [`encode`]s; the solver's module
//! [`decode`]s). No serde: a little-endian stream of u8/u64/f64 after a
//! version tag, the fields in the order of [`Mission`]'s declaration.
//!
//! Decoding never panics and never allocates more than the input's length
//! bounds (every count is checked against the bytes left before a vector
//! is made); a stream that is truncated, garbled or not a valid mission is
//! an [`InputError`] at path `mission`. What [`decode`] checks is what the
//! solver relies on and what [`Mission::from_value`] guarantees (the
//! model's dimension and channels, N, the counts, the indices, the
//! intervals non-empty), not the JSON reader's every message: a stream
//! comes from [`encode`] of a mission that was validated.
//!
//! Not carried: `meta` (free-form, never read by the solver; decoded as
//! `{}`).
//!
//! A new mission field is one line in [`encode`] and one in [`decode`]
//! (after the last ones), with [`VERSION`] raised.
//!
//! May import: `slam::mission` and below.

use crate::error::InputError;
use crate::ibox::IntervalBox;
use crate::interval::Interval;
use crate::odometry::drift::{DriftWindow, MAX_EXEMPT_LEVELS};
use crate::slam::mission::{Detection, Mission, Model, Points, Truth, MAX_STEPS};
use serde_json::{Map, Value};

/// The stream's first bytes: a tag and the layout's version.
const VERSION: [u8; 8] = *b"nvmbin03";

/// The error of every malformed stream.
fn bad(what: &str) -> InputError {
    InputError::new("mission", format!("invalid binary mission: {what}"))
}

/// The writer: bytes appended in order.
struct Out(Vec<u8>);

impl Out {
    fn u8(&mut self, x: u8) {
        self.0.push(x);
    }
    fn u64(&mut self, x: u64) {
        self.0.extend_from_slice(&x.to_le_bytes());
    }
    fn len(&mut self, n: usize) {
        self.u64(n as u64);
    }
    fn f64(&mut self, x: f64) {
        self.0.extend_from_slice(&x.to_bits().to_le_bytes());
    }
    fn floats(&mut self, v: &[f64]) {
        self.len(v.len());
        v.iter().for_each(|&x| self.f64(x));
    }
    fn interval(&mut self, x: Interval) {
        self.f64(x.lo());
        self.f64(x.hi());
    }
    fn intervals(&mut self, v: &[Interval]) {
        self.len(v.len());
        v.iter().for_each(|&x| self.interval(x));
    }
    fn option<T>(&mut self, v: Option<T>, write: impl FnOnce(&mut Self, T)) {
        self.u8(v.is_some() as u8);
        if let Some(v) = v {
            write(self, v);
        }
    }
    fn ibox(&mut self, b: &IntervalBox) {
        self.intervals(b.axes());
    }
    fn points(&mut self, p: &Points) {
        self.len(p.dim());
        self.floats(&p.iter().flatten().copied().collect::<Vec<_>>());
    }
    fn detection(&mut self, d: &Detection) {
        self.len(d.step);
        self.interval(d.range);
        self.option(d.bearing, Out::interval);
        self.option(d.region.as_ref(), Out::ibox);
        self.option(d.depth, Out::interval);
        self.option(d.landmark, Out::len);
        self.option(d.scan, Out::u64);
    }
    fn truth(&mut self, t: &Truth) {
        self.points(&t.positions);
        self.points(&t.landmarks);
        self.len(t.matching.len());
        t.matching.iter().for_each(|&m| self.option(m, Out::len));
        self.option(t.positions_known.as_ref(), |o, k| {
            o.len(k.len());
            k.iter().for_each(|&b| o.u8(b as u8));
        });
        self.option(t.headings.as_ref(), |o, h| {
            o.len(h.len());
            h.iter().for_each(|&x| o.option(x, Out::f64));
        });
    }
}

/// The mission as a binary stream ([`decode`] reads it back).
pub fn encode(m: &Mission) -> Vec<u8> {
    let mut o = Out(VERSION.to_vec());
    o.len(m.name.len());
    o.0.extend_from_slice(m.name.as_bytes());
    o.u8(match m.model {
        Model::Unicycle2d => 0,
        Model::Auv3d => 1,
        Model::Odometry2d => 2,
    });
    o.f64(m.dt);
    o.len(m.steps);
    o.len(m.detection_count);
    o.ibox(&m.initial_position);
    o.option(m.final_position.as_ref(), Out::ibox);
    o.len(m.inputs.len());
    m.inputs.iter().for_each(|c| o.intervals(c));
    o.floats(&m.motion_error);
    o.len(m.detections.len());
    m.detections.iter().for_each(|d| o.detection(d));
    o.option(m.landmark_count, Out::len);
    o.option(m.landmark_region.as_ref(), Out::ibox);
    o.len(m.max_outliers);
    o.option(m.truth.as_ref(), Out::truth);
    o.option(m.initial_heading, Out::interval);
    o.option(m.final_heading, Out::interval);
    o.floats(&m.heading_error);
    o.option(m.sensor_offset, |o, s| o.floats(&s));
    o.f64(m.landmark_min_separation);
    for windows in [&m.heading_drift, &m.motion_drift] {
        o.len(windows.len());
        windows.iter().for_each(|w| {
            o.u64(w.steps);
            o.f64(w.error);
            o.option(w.exempt_above, Out::f64);
        });
    }
    o.0
}

/// The reader: a position in the stream; every read checks the bytes left.
struct In<'a> {
    bytes: &'a [u8],
}

impl In<'_> {
    fn take(&mut self, n: usize) -> Result<&[u8], InputError> {
        if n > self.bytes.len() {
            return Err(bad("truncated"));
        }
        let (head, rest) = self.bytes.split_at(n);
        self.bytes = rest;
        Ok(head)
    }
    fn u8(&mut self) -> Result<u8, InputError> {
        Ok(self.take(1)?[0])
    }
    fn flag(&mut self) -> Result<bool, InputError> {
        match self.u8()? {
            0 => Ok(false),
            1 => Ok(true),
            _ => Err(bad("a flag is neither 0 nor 1")),
        }
    }
    fn u64(&mut self) -> Result<u64, InputError> {
        let mut b = [0; 8];
        b.copy_from_slice(self.take(8)?);
        Ok(u64::from_le_bytes(b))
    }
    /// A count or an index: at most `max`.
    fn at_most(&mut self, max: usize) -> Result<usize, InputError> {
        match usize::try_from(self.u64()?) {
            Ok(n) if n <= max => Ok(n),
            _ => Err(bad("a count or an index is out of range")),
        }
    }
    /// The length of a vector of items of at least `size` bytes each:
    /// bounded by the bytes left, so that nothing is sized by the stream's
    /// numbers alone.
    fn count(&mut self, size: usize) -> Result<usize, InputError> {
        self.at_most(self.bytes.len() / size)
    }
    fn f64(&mut self) -> Result<f64, InputError> {
        Ok(f64::from_bits(self.u64()?))
    }
    fn finite(&mut self) -> Result<f64, InputError> {
        let x = self.f64()?;
        if x.is_finite() {
            Ok(x)
        } else {
            Err(bad("a number is not finite"))
        }
    }
    fn floats(&mut self) -> Result<Vec<f64>, InputError> {
        let n = self.count(8)?;
        (0..n).map(|_| self.finite()).collect()
    }
    fn interval(&mut self) -> Result<Interval, InputError> {
        let x = Interval::new(self.f64()?, self.f64()?);
        if x.is_empty() {
            return Err(bad("an interval is empty"));
        }
        Ok(x)
    }
    fn intervals(&mut self, len: usize) -> Result<Vec<Interval>, InputError> {
        if self.count(16)? != len {
            return Err(bad("a vector has the wrong length"));
        }
        (0..len).map(|_| self.interval()).collect()
    }
    fn ibox(&mut self, dim: usize) -> Result<IntervalBox, InputError> {
        Ok(IntervalBox::new(&self.intervals(dim)?))
    }
    fn option<T>(
        &mut self,
        read: impl FnOnce(&mut Self) -> Result<T, InputError>,
    ) -> Result<Option<T>, InputError> {
        if self.flag()? {
            read(self).map(Some)
        } else {
            Ok(None)
        }
    }
    fn points(&mut self, dim: usize) -> Result<Points, InputError> {
        if self.at_most(3)? != dim {
            return Err(bad("points of the wrong dimension"));
        }
        let flat = self.floats()?;
        if !flat.len().is_multiple_of(dim) {
            return Err(bad("a point's coordinates are cut"));
        }
        Ok(Points::new(dim, flat))
    }
}

/// Checks that `ok` holds, else the error naming `what`.
fn check(ok: bool, what: &str) -> Result<(), InputError> {
    if ok {
        Ok(())
    } else {
        Err(bad(what))
    }
}

/// One detection of a mission of `model` with `steps` steps.
fn detection(i: &mut In, model: Model, steps: usize) -> Result<Detection, InputError> {
    let dim = model.dim();
    let d = Detection {
        step: i.at_most(steps)?,
        range: i.interval()?,
        bearing: i.option(In::interval)?,
        region: i.option(|i| i.ibox(dim))?,
        depth: i.option(In::interval)?,
        landmark: i.option(|i| i.at_most(u32::MAX as usize))?,
        scan: i.option(In::u64)?,
    };
    check(d.range.lo() >= 0.0, "a negative range")?;
    check(
        d.depth.is_none() || model == Model::Auv3d,
        "a depth off auv3d",
    )?;
    Ok(d)
}

/// The truth of a mission of `model` with `steps` steps and `k` detections.
fn truth(i: &mut In, model: Model, steps: usize, k: usize) -> Result<Truth, InputError> {
    let dim = model.dim();
    let positions = i.points(dim)?;
    check(
        positions.len() == steps + 1,
        "truth positions: not steps + 1",
    )?;
    let landmarks = i.points(dim)?;
    let n = landmarks.len();
    check(i.count(1)? == k, "truth matching: not one per detection")?;
    let matching = (0..k)
        .map(|_| i.option(|i| i.at_most(n.wrapping_sub(1))))
        .collect::<Result<Vec<_>, _>>()?;
    check(matching.iter().flatten().all(|&l| l < n), "truth matching")?;
    let positions_known = i.option(|i| {
        check(i.count(1)? == steps + 1, "truth positions known")?;
        (0..=steps).map(|_| i.flag()).collect::<Result<Vec<_>, _>>()
    })?;
    // As the JSON reader makes them: a mask only when a position is
    // unknown, and zeros there.
    if let Some(known) = &positions_known {
        check(known.contains(&false), "truth positions known: all")?;
        check(
            positions
                .iter()
                .zip(known)
                .all(|(p, &k)| k || p.iter().all(|x| x.to_bits() == 0)),
            "truth positions: an unknown one is not zeros",
        )?;
    }
    let headings = i.option(|i| {
        check(model == Model::Odometry2d, "truth headings off odometry2d")?;
        check(i.count(1)? == steps + 1, "truth headings: not steps + 1")?;
        (0..=steps)
            .map(|_| i.option(In::finite))
            .collect::<Result<Vec<_>, _>>()
    })?;
    Ok(Truth {
        positions,
        landmarks,
        matching,
        positions_known,
        headings,
    })
}

/// The version tag, then `name`, `model`, `dt` (> 0) and `steps` (1 to
/// [`MAX_STEPS`]).
fn header(i: &mut In) -> Result<(String, Model, f64, usize), InputError> {
    check(i.take(VERSION.len())? == VERSION, "not version nvmbin03")?;
    let name_len = i.count(1)?;
    let name = String::from_utf8(i.take(name_len)?.to_vec()).map_err(|_| bad("name"))?;
    let model = match i.u8()? {
        0 => Model::Unicycle2d,
        1 => Model::Auv3d,
        2 => Model::Odometry2d,
        _ => return Err(bad("unknown model")),
    };
    let dt = i.finite()?;
    check(dt > 0.0, "dt")?;
    let steps = i.at_most(MAX_STEPS)?;
    check(steps >= 1, "no step")?;
    Ok((name, model, dt, steps))
}

/// Drift windows (`what`: heading or motion): a count, then (k >= 1,
/// b >= 0 and not NaN, an optional `exempt_above` >= 0 and finite) of 17
/// or 25 bytes each, at most [`MAX_EXEMPT_LEVELS`] distinct `exempt_above`.
fn windows(i: &mut In, what: &'static str) -> Result<Vec<DriftWindow>, InputError> {
    let n = i.count(17)?;
    let mut out = Vec::with_capacity(n);
    let mut levels: Vec<f64> = Vec::new();
    for _ in 0..n {
        let steps = i.u64()?;
        let error = i.f64()?;
        let exempt_above = i.option(In::f64)?;
        check(steps >= 1 && error >= 0.0, what)?;
        if let Some(t) = exempt_above {
            check(t >= 0.0 && t.is_finite(), what)?;
            if !levels.contains(&t) {
                levels.push(t);
            }
        }
        check(levels.len() <= MAX_EXEMPT_LEVELS, what)?;
        out.push(DriftWindow {
            steps,
            error,
            exempt_above,
        });
    }
    Ok(out)
}

/// The heading then the motion drift windows, both empty unless the
/// mission is `odometry`'s.
type Windows = (Vec<DriftWindow>, Vec<DriftWindow>);
fn drift_windows(i: &mut In, odometry: bool) -> Result<Windows, InputError> {
    let heading = windows(i, "a heading drift window")?;
    check(odometry || heading.is_empty(), "heading_drift")?;
    let motion = windows(i, "a motion drift window")?;
    check(odometry || motion.is_empty(), "motion_drift")?;
    Ok((heading, motion))
}

/// A mission from its binary stream ([`encode`]); an error names what is
/// malformed. Never panics; allocates at most in proportion to
/// `bytes.len()`.
pub fn decode(bytes: &[u8]) -> Result<Mission, InputError> {
    let mut i = In { bytes };
    let (name, model, dt, steps) = header(&mut i)?;
    let dim = model.dim();
    let detection_count = i.count(1)?;
    let initial_position = i.ibox(dim)?;
    let final_position = i.option(|i| i.ibox(dim))?;
    check(i.count(1)? == model.channels().len(), "inputs")?;
    let inputs = (0..model.channels().len())
        .map(|_| i.intervals(steps))
        .collect::<Result<Vec<_>, _>>()?;
    let motion_error = i.floats()?;
    check(motion_error.len() == steps, "motion_error: not steps")?;
    check(i.count(1)? == detection_count, "detection count")?;
    // The landmark count comes after the detections: their ids are checked
    // against it below.
    let detections = (0..detection_count)
        .map(|_| detection(&mut i, model, steps))
        .collect::<Result<Vec<_>, _>>()?;
    let landmark_count = i.option(|i| i.at_most(u32::MAX as usize))?;
    check(landmark_count != Some(0), "landmark_count 0")?;
    check(
        detections.iter().all(|d| {
            d.landmark
                .is_none_or(|l| landmark_count.is_none_or(|n| l < n))
        }),
        "a detection's landmark is not below landmark_count",
    )?;
    let landmark_region = i.option(|i| i.ibox(dim))?;
    let max_outliers = i.at_most(u32::MAX as usize)?;
    let truth = i.option(|i| truth(i, model, steps, detection_count))?;
    let initial_heading = i.option(In::interval)?;
    let final_heading = i.option(In::interval)?;
    let heading_error = i.floats()?;
    let odometry = model == Model::Odometry2d;
    check(initial_heading.is_some() == odometry, "initial_heading")?;
    check(odometry || final_heading.is_none(), "final_heading")?;
    check(
        heading_error.len() == if odometry { steps } else { 0 },
        "heading_error",
    )?;
    let sensor_offset = i.option(|i| match i.floats()?[..] {
        [x, y] if dim == 2 => Ok([x, y]),
        _ => Err(bad("sensor_offset")),
    })?;
    let landmark_min_separation = i.finite()?;
    check(
        motion_error.iter().chain(&heading_error).all(|&e| e >= 0.0)
            && landmark_min_separation >= 0.0,
        "a negative bound",
    )?;
    let (heading_drift, motion_drift) = drift_windows(&mut i, odometry)?;
    check(i.bytes.is_empty(), "bytes after the mission")?;
    Ok(Mission {
        name,
        model,
        dt,
        steps,
        detection_count,
        initial_position,
        final_position,
        inputs,
        motion_error,
        detections,
        landmark_count,
        landmark_region,
        max_outliers,
        meta: Value::Object(Map::new()),
        truth,
        initial_heading,
        final_heading,
        heading_error,
        heading_drift,
        motion_drift,
        sensor_offset,
        landmark_min_separation,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::slam::simulate::{simulate, Layout, Scenario, SimulateOptions};
    use crate::test_rng::Lcg;
    use serde_json::json;

    /// Simulated missions of every model and option, and hand-written
    /// ones holding the optional fields the simulators leave out.
    fn missions() -> Vec<Mission> {
        let mut out = Vec::new();
        for (scenario, seed, operator, false_detections, layout, range_only) in [
            (Scenario::Paper, 1, false, 0, Layout::Line, false),
            (Scenario::Paper, 2, true, 0, Layout::Ring, false),
            (Scenario::Paper, 3, false, 3, Layout::Random, false),
            (Scenario::Paper, 4, false, 0, Layout::Line, true),
            (Scenario::Auv, 5, true, 0, Layout::Line, false),
            (Scenario::Auv, 6, false, 2, Layout::Line, false),
            (Scenario::Woods, 7, false, 0, Layout::Line, false),
            (Scenario::Woods, 8, true, 0, Layout::Line, false),
        ] {
            let mut o = SimulateOptions::new(scenario, seed);
            o.steps = Some(if scenario == Scenario::Woods { 60 } else { 300 });
            o.operator = operator;
            o.false_detections = false_detections;
            o.layout = layout;
            o.range_only = range_only;
            out.push(Mission::from_value(&simulate(&o)).unwrap());
        }
        let odometry = json!({
            "format": "nvector-mission/1", "name": "odo ✓", "model": "odometry2d",
            "dt": 0.1, "steps": 2,
            "initial_position": [[0, 0], [0, 0]], "final_position": [[-1, 1], [-2, 2]],
            "initial_heading": [-0.01, 0.01], "final_heading": 0.5,
            "inputs": {
                "speed": {"value": [1.0, -0.5], "error": 0.05},
                "turn_rate": {"lo": [0.2, -0.0], "hi": [0.3, 0.1]}
            },
            "heading_error": [0.001, 0.002], "sensor_offset": [0.3, -0.0],
            "heading_drift": [{"steps": 1, "error": 0.0}, {"steps": 18446744073709551615u64, "error": 0.25, "exempt_above": 0.0015}],
            "motion_drift": [{"steps": 2, "error": 0.0}, {"steps": 18446744073709551615u64, "error": 0.75, "exempt_above": 0.03}],
            "detections": [
                {"step": 1, "range": [2, 3], "bearing": [0.1, 0.2], "scan": 18446744073709551615u64},
                {"step": 2, "range": 4, "region": [[-9, 9], [0, 1]], "landmark": 2}
            ],
            "landmark_count": 3, "landmark_region": [[-50, 50], [-50, 50]],
            "landmark_min_separation": 1.33, "max_outliers": 4294967295u64,
            "meta": {"kept": "no"},
            "truth": {
                "positions": [[0, 0], null, [0.15, 0.01]],
                "landmarks": [[2.5, 0.3], [2, 4]],
                "matching": [null, 1],
                "headings": [0.0, null, 0.03]
            }
        });
        out.push(Mission::from_value(&odometry).unwrap());
        out
    }

    /// What the stream carries: the mission but `meta`.
    fn carried(m: &Mission) -> Mission {
        Mission {
            meta: Value::Object(Map::new()),
            ..m.clone()
        }
    }

    /// The same bits: `==` on floats would take -0 for 0.
    fn same(a: &Mission, b: &Mission) -> bool {
        a == b && encode(a) == encode(b)
    }

    #[test]
    fn round_trip_on_missions_of_every_model() {
        let mut models = Vec::new();
        for m in missions() {
            let back = decode(&encode(&m)).unwrap();
            assert!(same(&back, &carried(&m)), "{} differs", m.name);
            models.push(m.model);
        }
        for model in [Model::Unicycle2d, Model::Auv3d, Model::Odometry2d] {
            assert!(models.contains(&model), "{model:?} not covered");
        }
    }

    /// Every prefix is refused (no panic), and so is a stream with bytes
    /// after the mission.
    #[test]
    fn truncated_and_extended_streams_are_errors() {
        for m in missions().iter().filter(|m| m.steps <= 60) {
            let bytes = encode(m);
            for n in 0..bytes.len() {
                let e = decode(&bytes[..n]).unwrap_err();
                assert_eq!(e.path, "mission");
            }
            let mut more = bytes.clone();
            more.push(0);
            assert!(decode(&more).is_err());
        }
    }

    /// Garbled streams (bytes replaced, counts made huge) never panic and
    /// never allocate beyond the input (a count of 2^64 - 1 would abort),
    /// and whatever decodes is a mission the JSON reader accepts (decode
    /// checks what the solver relies on).
    #[test]
    fn garbled_streams_are_errors_or_valid_missions() {
        let mut rng = Lcg::new(17);
        let (mut refused, mut accepted) = (0, 0);
        for m in missions().iter().filter(|m| m.steps <= 60) {
            let bytes = encode(m);
            for case in 0..3000 {
                let mut b = bytes.clone();
                let at = rng.bits() as usize % b.len();
                match case % 3 {
                    0 => b[at] = rng.bits() as u8,
                    1 => b[at] ^= 1 << (rng.bits() % 8),
                    _ => {
                        let end = (at + 8).min(b.len());
                        b[at..end].iter_mut().for_each(|x| *x = 0xff);
                    }
                }
                match decode(&b) {
                    Err(e) => {
                        assert_eq!(e.path, "mission");
                        refused += 1;
                    }
                    Ok(d) => {
                        let again = Mission::from_value(&d.to_value());
                        assert!(again.is_ok(), "{:?}", again.err());
                        // `==`: the JSON writer may turn [-0, 0] into
                        // the point 0 (the same set), so not the bits.
                        assert!(again.unwrap() == d);
                        accepted += 1;
                    }
                }
            }
        }
        assert!(refused > 1000 && accepted > 1000, "{refused} {accepted}");
    }

    #[test]
    fn huge_counts_and_wrong_tags_are_errors() {
        let m = &missions()[0];
        let bytes = encode(m);
        // The name's length is the first count.
        let mut b = bytes.clone();
        b[8..16].copy_from_slice(&u64::MAX.to_le_bytes());
        assert!(decode(&b).is_err());
        let mut b = bytes.clone();
        b[7] = b'1';
        assert!(decode(&b).unwrap_err().message.contains("version"));
        assert!(decode(b"").is_err());
    }
}
