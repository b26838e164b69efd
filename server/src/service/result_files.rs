//! A job's result in the other formats of `GET /jobs/{id}/result`: the
//! trajectory (SLAM) or the pulse boxes (TDOA) as CSV, and the TDOA figure
//! as SVG (the SLAM figure is crate::render's). Pure functions of the
//! stored result JSON, below the handlers of `jobs` and `tdoa`.

use nvector_core::format::leaf::List;
use nvector_core::format::result::{BoxOut, ResultDoc};
use nvector_core::Interval;
use serde_json::Value;

/// The trajectory as CSV: `step,t,x_lo,x_hi,y_lo,y_hi[,z_lo,z_hi]`, `t`
/// the time of the step in seconds (step times the mission's `dt`: the
/// model's steps are `dt` apart from t = 0; empty when the mission has no
/// positive finite `dt`), bounds as the JSON writes them. The result is
/// read through its types ([`ResultDoc`]).
pub fn trajectory_csv(result: &ResultDoc, mission: &Value) -> String {
    let dt = mission["dt"]
        .as_f64()
        .filter(|dt| dt.is_finite() && *dt > 0.0);
    boxes_csv(&result.trajectory.0, "step", Some(dt))
}

/// A bound as the JSON writes it (`BoundOut`): a number, `inf`, `-inf`.
fn bound_text(x: f64) -> String {
    match serde_json::Number::from_f64(x + 0.0) {
        Some(n) => n.to_string(),
        None if x > 0.0 => "inf".into(),
        None => "-inf".into(),
    }
}

/// Boxes as CSV rows: the index (column `index`), the time when `time` is
/// given (`Some(dt)`: the index times dt, or empty), then the bounds (an
/// empty box, or an axis it lacks, `empty`); as many axes as the first
/// non-empty box has (at most 3; 2 when every box is empty).
fn boxes_csv(boxes: &[BoxOut], index: &str, time: Option<Option<f64>>) -> String {
    let dim = boxes
        .iter()
        .find_map(|b| b.axes().map(<[Interval]>::len))
        .unwrap_or(2)
        .min(3);
    let names = ["x", "y", "z"];
    let mut out = String::from(index);
    if time.is_some() {
        out.push_str(",t");
    }
    for n in names.iter().take(dim) {
        out.push_str(&format!(",{n}_lo,{n}_hi"));
    }
    out.push('\n');
    for (i, b) in boxes.iter().enumerate() {
        out.push_str(&i.to_string());
        match time {
            Some(Some(dt)) => out.push_str(&format!(",{}", i as f64 * dt)),
            Some(None) => out.push(','),
            None => {}
        }
        for a in 0..dim {
            match b.axes().and_then(|x| x.get(a)) {
                Some(x) => out.push_str(&format!(",{},{}", bound_text(x.lo()), bound_text(x.hi()))),
                None => out.push_str(",empty,empty"),
            }
        }
        out.push('\n');
    }
    out
}

/// A TDOA result's pulse boxes as CSV (`GET /jobs/{id}/result?format=csv`):
/// `pulse,x_lo,x_hi,y_lo,y_hi,z_lo,z_hi`, bounds as the JSON writes them;
/// the boxes read as a result's ([`BoxOut`]).
pub fn pulses_csv(result: &Value) -> Result<String, nvector_core::InputError> {
    let List(pulses) = nvector_core::format::from_value::<List<BoxOut>>(&result["pulses"])
        .map_err(|e| {
            let sep = if e.path.starts_with('[') { "" } else { "." };
            nvector_core::InputError::new(format!("pulses{sep}{}", e.path), e.message)
        })?;
    Ok(boxes_csv(&pulses, "pulse", None))
}

/// A TDOA result's figure (`?format=svg`), drawn from the result and the
/// stored problem in the x-y plane (metres, y up): receivers (squares),
/// pulse boxes outlined in their proved group's colour (grey: in none),
/// emitter regions ringed, true emitters (dots). Unbounded boxes are left
/// out.
pub fn tdoa_svg(result: &Value, problem: &Value) -> String {
    const PALETTE: [&str; 8] = [
        "#e6194b", "#3cb44b", "#4363d8", "#f58231", "#911eb4", "#42d4f4", "#f032e6", "#9a6324",
    ];
    let receivers: Vec<[f64; 4]> = list(&problem["receivers"])
        .iter()
        .filter_map(|r| xy(&r["position"]))
        .collect();
    let truth: Vec<(f64, f64)> = list(&problem["truth"]["emitters"])
        .iter()
        .filter_map(|p| Some((p[0].as_f64()?, p[1].as_f64()?)))
        .collect();
    let emitters: Vec<Option<[f64; 4]>> = list(&result["emitters"]).iter().map(xy).collect();
    let pulses = pulses_by_group(result);
    let e = extent(&receivers, &emitters, &truth);
    let span = (e[1] - e[0]).max(e[3] - e[2]).max(1e-9);
    let (size, pad) = (800.0, 0.06 * span);
    let k = size / (span + 2.0 * pad);
    let px = |x: f64| (x - e[0] + pad) * k;
    let py = |y: f64| size - (y - e[2] + pad) * k;
    let mut out = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{size}\" height=\"{size}\" viewBox=\"0 0 {size} {size}\">\n\
         <title>{} (x-y plane, metres)</title>\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n",
        result["name"].as_str().unwrap_or("tdoa").replace('&', "&amp;").replace('<', "&lt;")
    );
    for (g, r) in &pulses {
        let colour = if *g == usize::MAX {
            "#999999"
        } else {
            PALETTE[g % PALETTE.len()]
        };
        out += &format!(
            "<rect class=\"pulse\" x=\"{:.2}\" y=\"{:.2}\" width=\"{:.2}\" height=\"{:.2}\" fill=\"none\" stroke=\"{colour}\"/>\n",
            px(r[0]), py(r[3]), ((r[1] - r[0]) * k).max(1.0), ((r[3] - r[2]) * k).max(1.0)
        );
    }
    for (g, r) in emitters.iter().enumerate() {
        if let Some(r) = r {
            out += &format!(
                "<circle class=\"emitter\" cx=\"{:.2}\" cy=\"{:.2}\" r=\"10\" fill=\"none\" stroke=\"{}\" stroke-width=\"2\"/>\n",
                px((r[0] + r[1]) / 2.0), py((r[2] + r[3]) / 2.0), PALETTE[g % PALETTE.len()]
            );
        }
    }
    for (x, y) in &truth {
        out += &format!(
            "<circle class=\"truth\" cx=\"{:.2}\" cy=\"{:.2}\" r=\"3\"/>\n",
            px(*x),
            py(*y)
        );
    }
    for r in &receivers {
        out += &format!(
            "<rect class=\"receiver\" x=\"{:.2}\" y=\"{:.2}\" width=\"8\" height=\"8\" fill=\"#333\"/>\n",
            px((r[0] + r[1]) / 2.0) - 4.0, py((r[2] + r[3]) / 2.0) - 4.0
        );
    }
    out += &format!(
        "<text x=\"8\" y=\"{}\" font-size=\"12\">receivers (squares), pulse boxes by proved group, \
         emitter regions (rings), true emitters (dots); {} across</text>\n</svg>\n",
        size - 8.0,
        nvector_core::figure::metres(Some(span + 2.0 * pad))
    );
    out
}

/// The x-y extent of a TDOA figure: receivers, emitter regions, truth
/// (finite values only; a unit square when there is none).
fn extent(receivers: &[[f64; 4]], emitters: &[Option<[f64; 4]>], truth: &[(f64, f64)]) -> [f64; 4] {
    let mut e = [
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    ];
    let boxes = || receivers.iter().chain(emitters.iter().flatten());
    let points = boxes()
        .map(|r| (r[0], r[2]))
        .chain(boxes().map(|r| (r[1], r[3])))
        .chain(truth.iter().copied());
    for (x, y) in points.filter(|(x, y)| x.is_finite() && y.is_finite()) {
        e = [e[0].min(x), e[1].max(x), e[2].min(y), e[3].max(y)];
    }
    if e[0].is_finite() {
        e
    } else {
        [-1.0, 1.0, -1.0, 1.0]
    }
}

/// The x-y rectangle `[x_lo, x_hi, y_lo, y_hi]` of a result box, when its
/// bounds are finite numbers.
fn xy(b: &Value) -> Option<[f64; 4]> {
    let a = b.as_array()?;
    let (x, y) = (a.first()?, a.get(1)?);
    Some([
        x[0].as_f64()?,
        x[1].as_f64()?,
        y[0].as_f64()?,
        y[1].as_f64()?,
    ])
}

/// The elements of a JSON array (none for anything else).
fn list(v: &Value) -> Vec<Value> {
    v.as_array().cloned().unwrap_or_default()
}

/// Each bounded pulse box with its proved group (`usize::MAX`: none).
fn pulses_by_group(result: &Value) -> Vec<(usize, [f64; 4])> {
    let pulses = list(&result["pulses"]);
    let mut group = vec![usize::MAX; pulses.len()];
    for (g, members) in list(&result["matching"]).iter().enumerate() {
        for m in list(members) {
            if let Some(slot) = m.as_u64().and_then(|k| group.get_mut(k as usize)) {
                *slot = g;
            }
        }
    }
    pulses
        .iter()
        .enumerate()
        .filter_map(|(k, b)| Some((group[k], xy(b)?)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Bounds as the result's JSON writes them: unbounded as `inf` /
    /// `-inf`, a zero as `0.0`; an empty box `empty` on every axis.
    #[test]
    fn unbounded_and_empty_boxes_are_written_as_the_json_writes_them() {
        let boxes = [
            BoxOut::Axes(vec![
                Interval::new(f64::NEG_INFINITY, 1.0),
                Interval::new(-0.0, f64::INFINITY),
            ]),
            BoxOut::Empty,
        ];
        assert_eq!(
            boxes_csv(&boxes, "step", Some(Some(0.5))),
            "step,t,x_lo,x_hi,y_lo,y_hi\n0,0,-inf,1.0,0.0,inf\n1,0.5,empty,empty,empty,empty\n"
        );
        assert_eq!(
            boxes_csv(&[BoxOut::Empty], "pulse", None),
            "pulse,x_lo,x_hi,y_lo,y_hi\n0,empty,empty,empty,empty\n"
        );
    }
}
