//! The shape of a result file read back (`nvector plot`): formats.md's
//! `nvector-result/1`, checked before anything is drawn from it, every
//! fault named by its JSON path (a result edited by hand or cut short
//! was drawn as if whole, or not at all, without a word).

use serde_json::Value;

/// The top-level fields a result may have.
const FIELDS: &[&str] = &[
    "detections",
    "format",
    "headings",
    "landmark_regions",
    "landmarks",
    "matching",
    "metrics",
    "mission",
    "options",
    "reason",
    "score",
    "status",
    "trajectory",
];

/// Checks `v` as an `nvector-result/1` document; the error names the path
/// of the first bad value.
pub fn check_result(v: &Value) -> Result<(), String> {
    let o = v
        .as_object()
        .ok_or("the result must be a JSON object".to_string())?;
    if let Some(k) = o.keys().find(|k| !FIELDS.contains(&k.as_str())) {
        return Err(format!("{k}: unknown field of a result"));
    }
    let need = |k: &str| o.get(k).ok_or(format!("{k}: missing"));
    if need("format")? != "nvector-result/1" {
        return Err("format: expected \"nvector-result/1\"".into());
    }
    if !need("mission")?.is_string() {
        return Err("mission: expected the mission's name (a string)".into());
    }
    let status = need("status")?;
    if !matches!(
        status.as_str(),
        Some("consistent" | "infeasible" | "stopped")
    ) {
        return Err(format!(
            "status: expected \"consistent\", \"infeasible\" or \"stopped\", not {status}"
        ));
    }
    let mut dim = None;
    let trajectory = boxes(need("trajectory")?, "trajectory", &mut dim)?;
    if trajectory == 0 {
        return Err("trajectory: expected N+1 boxes, found none".into());
    }
    let detections = boxes(need("detections")?, "detections", &mut dim)?;
    let landmarks = boxes(need("landmarks")?, "landmarks", &mut dim)?;
    check_matching(need("matching")?, detections, landmarks)?;
    if !need("metrics")?.is_object() {
        return Err("metrics: expected an object".into());
    }
    for k in ["options", "score"] {
        if o.get(k).is_some_and(|x| !x.is_object()) {
            return Err(format!("{k}: expected an object"));
        }
    }
    if o.get("reason").is_some_and(|x| !x.is_string()) {
        return Err("reason: expected a string".into());
    }
    check_headings(o.get("headings"), trajectory)?;
    if let Some(r) = o.get("landmark_regions") {
        check_regions(r, landmarks, &mut dim)?;
    }
    Ok(())
}

/// `matching`: one group per landmark box, each of detection indices.
fn check_matching(v: &Value, detections: usize, landmarks: usize) -> Result<(), String> {
    let matching = v
        .as_array()
        .ok_or("matching: expected an array of groups")?;
    if matching.len() != landmarks {
        return Err(format!(
            "landmarks: {landmarks} boxes for {} groups of matching (one box per group)",
            matching.len()
        ));
    }
    for (g, group) in matching.iter().enumerate() {
        let members = group.as_array().ok_or(format!(
            "matching[{g}]: expected an array of detection indices"
        ))?;
        for (x, j) in members.iter().enumerate() {
            match j.as_u64() {
                Some(j) if (j as usize) < detections && j <= usize::MAX as u64 => {}
                _ => {
                    return Err(format!(
                        "matching[{g}][{x}]: expected a detection index below {detections}, not {j}"
                    ))
                }
            }
        }
    }
    Ok(())
}

/// `headings` (optional): one interval per trajectory box.
fn check_headings(v: Option<&Value>, trajectory: usize) -> Result<(), String> {
    if let Some(h) = v {
        let h = h
            .as_array()
            .ok_or("headings: expected an array of intervals")?;
        if h.len() != trajectory {
            return Err(format!(
                "headings: {} intervals for {trajectory} trajectory boxes (one per step)",
                h.len()
            ));
        }
        for (i, x) in h.iter().enumerate() {
            if x != "empty" {
                interval(x, &format!("headings[{i}]"))?;
            }
        }
    }
    Ok(())
}

/// `landmark_regions` (optional): one paving per landmark.
fn check_regions(r: &Value, landmarks: usize, dim: &mut Option<usize>) -> Result<(), String> {
    let r = r
        .as_array()
        .ok_or("landmark_regions: expected one paving per landmark")?;
    if r.len() != landmarks {
        return Err(format!(
            "landmark_regions: {} pavings for {landmarks} landmarks",
            r.len()
        ));
    }
    for (i, p) in r.iter().enumerate() {
        boxes(p, &format!("landmark_regions[{i}]"), dim)?;
    }
    Ok(())
}

/// An array of boxes of one dimension (2 or 3, shared through `dim`);
/// returns its length.
fn boxes(v: &Value, path: &str, dim: &mut Option<usize>) -> Result<usize, String> {
    let a = v
        .as_array()
        .ok_or(format!("{path}: expected an array of boxes"))?;
    for (i, b) in a.iter().enumerate() {
        if b == "empty" {
            continue;
        }
        let axes = b.as_array().ok_or(format!(
            "{path}[{i}]: expected a box (an array of intervals) or \"empty\""
        ))?;
        match *dim {
            None if matches!(axes.len(), 2 | 3) => *dim = Some(axes.len()),
            None => {
                return Err(format!(
                    "{path}[{i}]: a box of dimension {}, expected 2 or 3",
                    axes.len()
                ))
            }
            Some(d) if d != axes.len() => {
                return Err(format!(
                    "{path}[{i}]: a box of dimension {}, expected {d} as the boxes before it",
                    axes.len()
                ))
            }
            Some(_) => {}
        }
        for (a, x) in axes.iter().enumerate() {
            interval(x, &format!("{path}[{i}][{a}]"))?;
        }
    }
    Ok(a.len())
}

/// An interval `[lo, hi]` of bounds (numbers, `"-inf"`, `"inf"`), lo <= hi:
/// core's reader of input intervals, its error named by the path.
fn interval(v: &Value, path: &str) -> Result<(), String> {
    nvector_core::json::interval(v, path)
        .map(|_| ())
        .map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::check_result;
    use serde_json::json;

    fn good() -> serde_json::Value {
        json!({
            "format": "nvector-result/1", "mission": "m", "status": "consistent",
            "options": {"contractor": "best", "max_rounds": 10, "tolerance": 1e-9},
            "trajectory": [[[0, 1], [0, 1]], [[0, "inf"], ["-inf", 1]], "empty"],
            "headings": [[0, 1], [0, 1], "empty"],
            "detections": [[[2, 3], [2, 3]], [[2, 3], [2, 3]]],
            "landmarks": [[[2, 3], [2, 3]]],
            "landmark_regions": [[[[2, 3], [2, 3]]]],
            "matching": [[0, 1]],
            "metrics": {"rounds": 1}
        })
    }

    #[test]
    fn a_whole_result_passes_and_each_fault_is_named() {
        assert_eq!(check_result(&good()), Ok(()));
        type Edit = Box<dyn Fn(&mut serde_json::Value)>;
        let cases: Vec<(Edit, &str)> = vec![
            (Box::new(|v| v["bogus"] = json!(1)), "bogus: unknown field"),
            (Box::new(|v| v["status"] = json!("weird")), "status:"),
            (
                Box::new(|v| v["trajectory"][1][0] = json!([3, 2])),
                "trajectory[1][0]: lower bound 3",
            ),
            (
                Box::new(|v| v["trajectory"][0] = json!([[0, 1], [0, 1], [0, 1]])),
                "trajectory[1]: a box of dimension 2, expected 3",
            ),
            (
                Box::new(|v| v["trajectory"][0] = json!("abc")),
                "trajectory[0]: expected a box",
            ),
            (
                Box::new(|v| {
                    v.as_object_mut().unwrap().remove("trajectory");
                }),
                "trajectory: missing",
            ),
            (
                Box::new(|v| {
                    v.as_object_mut().unwrap().remove("metrics");
                }),
                "metrics: missing",
            ),
            (
                Box::new(|v| v["matching"][0][1] = json!(99999)),
                "matching[0][1]: expected a detection index below 2",
            ),
            (
                Box::new(|v| v["headings"] = json!([[0, 1]])),
                "headings: 1 intervals for 3",
            ),
            (
                Box::new(|v| v["headings"][0] = json!([1, 0])),
                "headings[0]: lower bound 1",
            ),
            (
                Box::new(|v| v["landmarks"] = json!([])),
                "landmarks: 0 boxes for 1 groups",
            ),
            (
                Box::new(|v| v["detections"][0][1] = json!([0, "nan"])),
                "detections[0][1][1]: expected a number",
            ),
            (
                Box::new(|v| v["format"] = json!("nvector-result/2")),
                "format:",
            ),
        ];
        for (edit, want) in cases {
            let mut v = good();
            edit(&mut v);
            let err = check_result(&v).expect_err(want);
            assert!(err.starts_with(want), "{err} (wanted {want})");
        }
    }
}
