//! `nvector._nvector`: the compiled part of the `nvector` Python package.
//!
//! A thin layer over nvector-core's public functions, the same ones the
//! `nvector` binary calls, so that the answers agree bit for bit:
//! - `contract` -> `nvector::contract::contract_json` (as `nvector contract`);
//! - `simulate` -> `slam::simulate::simulate` (paper, auv, woods: as
//!   `nvector simulate`);
//! - `run` -> `slam::mission::Mission` + `slam::solve::solve` (as
//!   `nvector run`);
//! - `import_dataset`, `import_csv` -> nvector-import (as `nvector
//!   import`).
//!
//! Python values cross as JSON values (`serde_json::Value`), converted here
//! with the JSON path of every value that has no JSON form (NaN, a non-string
//! key, an object of an unknown type), so a bad input raises
//! `nvector.InputError` naming the path and never reaches core. The friendly
//! API (numpy arrays, files, progress bars, the HTTP client, figures) is the
//! pure-Python code beside this crate, in `nvector/`.

use nvector_core::format::leaf::{Finite, Integer};
use nvector_core::json::{bound, field_path, index_path};
use nvector_core::nvector::contract::contract_json;
use nvector_core::slam::mission::{Mission, MAX_STEPS};
use nvector_core::slam::simulate::simulate as simulate_mission;
use nvector_core::slam::simulate::{SimulateLimits, SimulateRequest};
use nvector_core::slam::solve::solve;
use nvector_core::slam::types::{Association, Progress, SolveOptions};
use nvector_core::InputError;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyBytes, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use serde_json::{Map, Number, Value};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

/// Deepest nesting accepted from Python (serde_json's own limit): deeper
/// input is refused with an error instead of overflowing the stack.
const MAX_DEPTH: usize = 128;

/// `nvector.InputError(path, message)` (defined in Python, `nvector/_errors.py`,
/// so that it carries `.path` and `.message`); a plain `ValueError` if that
/// module cannot be imported.
fn input_error(py: Python<'_>, e: &InputError) -> PyErr {
    let made = py
        .import("nvector._errors")
        .and_then(|m| m.getattr("InputError"))
        .and_then(|cls| cls.call1((e.path.as_str(), e.message.as_str())));
    match made {
        Ok(instance) => PyErr::from_value(instance),
        Err(_) => PyValueError::new_err(e.to_string()),
    }
}

/// A Python object as a JSON value. `float('inf')` / `-inf` become the
/// spec's `"inf"` / `"-inf"` bounds; NaN, non-string keys and objects with
/// no JSON form are errors naming `path`. Anything with a `tolist()` method
/// (numpy arrays and scalars) is converted through it.
fn to_value(obj: &Bound<'_, PyAny>, path: &str, depth: usize) -> Result<Value, InputError> {
    if depth > MAX_DEPTH {
        return Err(InputError::new(
            path,
            format!("nested more than {MAX_DEPTH} levels deep"),
        ));
    }
    if let Some(v) = scalar_to_value(obj, path) {
        return v;
    }
    if let Ok(d) = obj.cast::<PyDict>() {
        return dict_to_value(d, path, depth);
    }
    if let Ok(l) = obj.cast::<PyList>() {
        return items_to_value(l.iter(), l.len(), path, depth);
    }
    if let Ok(t) = obj.cast::<PyTuple>() {
        return items_to_value(t.iter(), t.len(), path, depth);
    }
    if obj.hasattr("tolist").unwrap_or(false) {
        if let Ok(plain) = obj.call_method0("tolist") {
            // A tolist() that returns an object of its own type would loop.
            if !plain.get_type().is(obj.get_type()) {
                return to_value(&plain, path, depth + 1);
            }
        }
    }
    Err(InputError::new(
        path,
        format!("{} has no JSON form", type_name(obj)),
    ))
}

/// None, a bool, an int, a float or a str as a JSON value (`None`: none
/// of those).
fn scalar_to_value(obj: &Bound<'_, PyAny>, path: &str) -> Option<Result<Value, InputError>> {
    if obj.is_none() {
        return Some(Ok(Value::Null));
    }
    if let Ok(b) = obj.cast::<PyBool>() {
        return Some(Ok(Value::Bool(b.is_true())));
    }
    if obj.is_instance_of::<PyInt>() {
        if let Ok(i) = obj.extract::<i64>() {
            return Some(Ok(Value::from(i)));
        }
        if let Ok(u) = obj.extract::<u64>() {
            return Some(Ok(Value::from(u)));
        }
        return Some(Err(InputError::new(
            path,
            "integer out of range (a JSON integer fits in 64 bits)",
        )));
    }
    if obj.is_instance_of::<PyFloat>() {
        let Ok(x) = obj.extract::<f64>() else {
            return Some(Err(InputError::new(path, "expected a float")));
        };
        return Some(match Number::from_f64(x) {
            Some(n) => Ok(Value::Number(n)),
            None if x == f64::INFINITY => Ok(Value::from("inf")),
            None if x == f64::NEG_INFINITY => Ok(Value::from("-inf")),
            None => Err(InputError::new(path, "NaN is not a valid number")),
        });
    }
    if let Ok(s) = obj.cast::<PyString>() {
        return Some(
            s.to_str()
                .map(|s| Value::from(s.to_owned()))
                .map_err(|_| InputError::new(path, "string is not valid UTF-8")),
        );
    }
    None
}

/// A dict with str keys as a JSON object.
fn dict_to_value(d: &Bound<'_, PyDict>, path: &str, depth: usize) -> Result<Value, InputError> {
    let mut map = Map::new();
    for (k, v) in d.iter() {
        let key = match k.cast::<PyString>() {
            Ok(s) => s
                .to_str()
                .map_err(|_| InputError::new(path, "key is not valid UTF-8"))?
                .to_owned(),
            Err(_) => {
                return Err(InputError::new(
                    path,
                    format!("keys must be strings, found {}", type_name(&k)),
                ))
            }
        };
        let value = to_value(&v, &field_path(path, &key), depth + 1)?;
        map.insert(key, value);
    }
    Ok(Value::Object(map))
}

/// The items of a list or tuple as a JSON array.
fn items_to_value<'py>(
    items: impl Iterator<Item = Bound<'py, PyAny>>,
    len: usize,
    path: &str,
    depth: usize,
) -> Result<Value, InputError> {
    let mut out = Vec::with_capacity(len);
    for (i, item) in items.enumerate() {
        out.push(to_value(&item, &index_path(path, i), depth + 1)?);
    }
    Ok(Value::Array(out))
}

fn type_name(obj: &Bound<'_, PyAny>) -> String {
    obj.get_type()
        .name()
        .map(|n| format!("an object of type {n}"))
        .unwrap_or_else(|_| "an object".into())
}

/// A JSON value as plain Python objects (dict, list, str, int, float, bool,
/// None): what `json.loads` gives for the same text.
fn to_py<'py>(py: Python<'py>, v: &Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match v {
        Value::Null => py.None().into_bound(py),
        Value::Bool(b) => PyBool::new(py, *b).to_owned().into_any(),
        Value::Number(n) => {
            if let Some(i) = n.as_i64() {
                i.into_pyobject(py)?.into_any()
            } else if let Some(u) = n.as_u64() {
                u.into_pyobject(py)?.into_any()
            } else {
                PyFloat::new(py, n.as_f64().unwrap_or(f64::NAN)).into_any()
            }
        }
        Value::String(s) => PyString::new(py, s).into_any(),
        Value::Array(a) => {
            let list = PyList::empty(py);
            for item in a {
                list.append(to_py(py, item)?)?;
            }
            list.into_any()
        }
        Value::Object(m) => {
            let dict = PyDict::new(py);
            for (k, item) in m {
                dict.set_item(k, to_py(py, item)?)?;
            }
            dict.into_any()
        }
    })
}

/// The boxes of a contraction response as little-endian f64 bytes, k x d x 2
/// (an `"empty"` box as NaN on every bound).
fn boxes_bytes(response: &Value, dim: usize) -> Result<Vec<u8>, InputError> {
    let boxes = response["boxes"]
        .as_array()
        .map(Vec::as_slice)
        .unwrap_or(&[]);
    let mut out = Vec::with_capacity(boxes.len() * dim * 16);
    for (i, b) in boxes.iter().enumerate() {
        let path = index_path("boxes", i);
        match b {
            Value::Array(axes) if axes.len() == dim => {
                for (a, x) in axes.iter().enumerate() {
                    let p = index_path(&path, a);
                    for (e, end) in [0, 1].into_iter().zip(["lo", "hi"]) {
                        let v = bound(&x[e], &format!("{p}.{end}"))?;
                        out.extend_from_slice(&v.to_le_bytes());
                    }
                }
            }
            _ => {
                for _ in 0..2 * dim {
                    out.extend_from_slice(&f64::NAN.to_le_bytes());
                }
            }
        }
    }
    Ok(out)
}

/// One atmost_nvector contraction.
///
/// `request` is an `nvector-contract/1` request as Python objects. Returns
/// `(response, boxes, dim)`: the `nvector-contract-result/1` response (as
/// `nvector contract` prints it, `stats.elapsed_us` measured here), the
/// contracted boxes as little-endian f64 bytes (k x dim x 2, NaN for an
/// empty box) and the dimension.
#[pyfunction]
fn contract<'py>(
    py: Python<'py>,
    request: &Bound<'py, PyAny>,
) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyBytes>, usize)> {
    let request = to_value(request, "", 0).map_err(|e| input_error(py, &e))?;
    let start = Instant::now();
    let mut response = py
        .detach(|| contract_json(&request, None))
        .map_err(|e| input_error(py, &e))?;
    response["stats"]["elapsed_us"] = Value::from(start.elapsed().as_micros() as u64);
    // A valid request has at least one box, each of one dimension.
    let dim = request["boxes"][0].as_array().map_or(0, Vec::len);
    let bytes = boxes_bytes(&response, dim).map_err(|e| input_error(py, &e))?;
    Ok((to_py(py, &response)?, PyBytes::new(py, &bytes), dim))
}

/// A simulated mission with truth, as `nvector simulate` writes it (the
/// same checks of the options as the CLI, errors named by option).
#[pyfunction]
#[pyo3(signature = (scenario, seed, steps, landmarks, operator, noise, layout, range_only, false_detections))]
#[allow(clippy::too_many_arguments)]
fn simulate<'py>(
    py: Python<'py>,
    scenario: &str,
    seed: u64,
    steps: Option<usize>,
    landmarks: Option<usize>,
    operator: bool,
    noise: f64,
    layout: &str,
    range_only: bool,
    false_detections: usize,
) -> PyResult<Bound<'py, PyAny>> {
    // Core's one simulation request type, its checks and limits (as the
    // CLI, the service and the page).
    let request = SimulateRequest {
        scenario: Some(scenario.into()),
        seed: Some(Integer::Value(seed)),
        steps: steps.map(|s| Integer::Value(s as u64)),
        landmarks: landmarks.map(|n| Integer::Value(n as u64)),
        operator: Some(operator),
        noise: Some(Finite(noise)),
        layout: Some(layout.into()),
        range_only: Some(range_only),
        false_detections: Some(Integer::Value(false_detections as u64)),
    };
    let options = request
        .options(SimulateLimits::CORE)
        .map_err(|e| input_error(py, &e))?;
    let mission = py.detach(|| simulate_mission(&options));
    to_py(py, &mission)
}

/// One SLAM job, as `nvector run` runs it.
///
/// `mission` is the mission's JSON text (a file's content) or Python
/// objects; `contractor` None means the CLI's default (best when the
/// mission has `landmark_count`, none otherwise). `progress`, when given, is
/// called with `(round, max_trajectory_diameter, fraction)` at each report
/// of the propagator; an exception raised by it, or a KeyboardInterrupt,
/// stops the propagation and is raised here.
#[pyfunction]
#[pyo3(signature = (mission, contractor, max_rounds, tolerance, progress))]
fn run<'py>(
    py: Python<'py>,
    mission: &Bound<'py, PyAny>,
    contractor: Option<&str>,
    max_rounds: u32,
    tolerance: f64,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyAny>> {
    let parsed = if let Ok(text) = mission.cast::<PyString>() {
        let text = text.to_str()?.to_owned();
        py.detach(|| Mission::from_json(&text))
    } else {
        let value = to_value(mission, "", 0).map_err(|e| input_error(py, &e))?;
        py.detach(|| Mission::from_value(&value))
    };
    let mission = parsed.map_err(|e| input_error(py, &e))?;
    if !(tolerance.is_finite() && tolerance >= 0.0) {
        return Err(input_error(
            py,
            &InputError::new(
                "tolerance",
                format!("must be a finite number >= 0, found {tolerance}"),
            ),
        ));
    }
    let association = match contractor {
        Some(name) => Association::parse(name).ok_or_else(|| {
            input_error(
                py,
                &InputError::new(
                    "contractor",
                    format!("unknown contractor '{name}' (expected none, nvalue, projection, independent or best)"),
                ),
            )
        })?,
        None if mission.landmark_count.is_some() => {
            Association::NVector(nvector_core::nvector::Contractor::Best)
        }
        None => Association::None,
    };
    let options = SolveOptions {
        association,
        max_rounds,
        tolerance,
        threads: std::thread::available_parallelism().map_or(1, |n| n.get()),
    };
    let cancel = AtomicBool::new(false);
    let mut failure: Option<PyErr> = None;
    let start = Instant::now();
    let mut result = py.detach(|| {
        let mut report = |p: &Progress| {
            if failure.is_some() {
                return;
            }
            let outcome = Python::attach(|py| -> PyResult<()> {
                py.check_signals()?;
                if let Some(f) = &progress {
                    f.call1(py, (p.round, p.max_trajectory_diameter, p.fraction))?;
                }
                Ok(())
            });
            if let Err(e) = outcome {
                failure = Some(e);
                cancel.store(true, Ordering::Relaxed);
            }
        };
        solve(&mission, &options, &mut report, &cancel)
    });
    if let Some(e) = failure {
        return Err(e);
    }
    result["metrics"]["elapsed_ms"] = Value::from(start.elapsed().as_secs_f64() * 1e3);
    to_py(py, &result)
}

/// One TDOA problem (`nvector-tdoa/1`, JSON text or objects) solved as
/// `nvector tdoa` does: `nvector-tdoa-result/1`. `contractor`: `none`
/// (the operator's matching only) or an atmost_nvector mode (default best).
#[pyfunction]
#[pyo3(signature = (problem, contractor, budget, max_rounds))]
fn tdoa<'py>(
    py: Python<'py>,
    problem: &Bound<'py, PyAny>,
    contractor: Option<&str>,
    budget: usize,
    max_rounds: usize,
) -> PyResult<Bound<'py, PyAny>> {
    use nvector_core::tdoa::{problem::TdoaProblem, solve_tdoa, tdoa_result_json, TdoaOptions};
    let parsed = if let Ok(text) = problem.cast::<PyString>() {
        let text = text.to_str()?.to_owned();
        py.detach(|| TdoaProblem::from_json_str(&text))
    } else {
        let value = to_value(problem, "", 0).map_err(|e| input_error(py, &e))?;
        py.detach(|| TdoaProblem::from_value(&value))
    };
    let problem = parsed.map_err(|e| input_error(py, &e))?;
    let mode = match contractor {
        None => Some(nvector_core::nvector::Contractor::Best),
        Some("none") => None,
        Some(name) => Some(nvector_core::nvector::Contractor::parse(name).ok_or_else(|| {
            input_error(
                py,
                &InputError::new(
                    "contractor",
                    format!("unknown contractor '{name}' (expected none, nvalue, projection, independent, exact, shapes or best)"),
                ),
            )
        })?),
    };
    if budget > 100_000 {
        return Err(input_error(
            py,
            &InputError::new("budget", "at most 100000"),
        ));
    }
    let options = TdoaOptions {
        mode,
        budget,
        max_rounds: max_rounds.clamp(1, 1000),
    };
    let start = Instant::now();
    let solution = py.detach(|| solve_tdoa(&problem, &options));
    let ms = start.elapsed().as_secs_f64() * 1e3;
    to_py(py, &tdoa_result_json(&problem, &options, &solution, ms))
}

/// Python objects as compact JSON text, the way the `nvector` binary writes
/// JSON (serde_json: shortest round-trip floats); `float('inf')` as `"inf"`.
#[pyfunction]
fn dumps(py: Python<'_>, obj: &Bound<'_, PyAny>) -> PyResult<String> {
    let value = to_value(obj, "", 0).map_err(|e| input_error(py, &e))?;
    Ok(value.to_string())
}

/// A result (`nvector-result/1`, JSON text or Python objects) read
/// through core's types (`nvector_core::format::result`, as `nvector plot`
/// reads it) and given back as Python objects, as written (bounds
/// `"inf"` / `"-inf"`, empty boxes `"empty"`); `InputError` names the
/// JSON path of the first fault.
#[pyfunction]
fn read_result<'py>(py: Python<'py>, result: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
    use nvector_core::format::result::{read, read_value};
    let doc = if let Ok(text) = result.cast::<PyString>() {
        let text = text.to_str()?.to_owned();
        py.detach(|| read(&text))
    } else {
        read_value(&to_value(result, "", 0).map_err(|e| input_error(py, &e))?)
    }
    .map_err(|e| input_error(py, &e))?;
    let v = serde_json::to_value(&doc).map_err(|e| PyValueError::new_err(e.to_string()))?;
    to_py(py, &v)
}

/// The picture of a result (`nvector_core::figure::describe`, what the
/// CLI's figures draw) as JSON text: layers, thinning, colours, legend
/// labels, title and view. `mission` (or None) adds its truth.
#[pyfunction]
#[pyo3(signature = (result, mission=None))]
fn figure(
    py: Python<'_>,
    result: &Bound<'_, PyAny>,
    mission: Option<&Bound<'_, PyAny>>,
) -> PyResult<String> {
    let result = to_value(result, "result", 0).map_err(|e| input_error(py, &e))?;
    let result =
        nvector_core::format::result::read_value(&result).map_err(|e| input_error(py, &e))?;
    let mission = match mission {
        Some(m) if !m.is_none() => {
            Some(to_value(m, "mission", 0).map_err(|e| input_error(py, &e))?)
        }
        _ => None,
    };
    let fig = nvector_core::figure::describe(&result, mission.as_ref());
    serde_json::to_string(&fig).map_err(|e| PyValueError::new_err(e.to_string()))
}

/// Every constraint of a mission (`nvector-mission/1` with truth, JSON
/// text or objects) that its truth breaks, as `nvector check --json`
/// gives it: `{"violations": [...], "unchecked", "broken_detections",
/// "max_outliers"}` (docs/formats.md, "Check"). A mission without truth
/// is an error naming `truth`.
#[pyfunction]
fn check<'py>(py: Python<'py>, mission: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
    use nvector_core::slam::check::{check_json, check_value};
    let report = if let Ok(text) = mission.cast::<PyString>() {
        let text = text.to_str()?.to_owned();
        py.detach(|| check_json(&text))
    } else {
        let value = to_value(mission, "", 0).map_err(|e| input_error(py, &e))?;
        py.detach(|| check_value(&value))
    };
    let report = report.map_err(|e| input_error(py, &e))?;
    to_py(py, &report.to_json())
}

// The importers (nvector-import, as `nvector import` calls them): a data
// set's directory or a CSV pair as a mission, its errors as Python ones.

/// An import error as a Python exception: a setting as
/// `InputError(setting, message)`; a fault in a file as `InputError("",
/// message, file="FILE:LINE")` (its `str` is the CLI's message); a file
/// that cannot be read as the `OSError` of its kind.
fn import_error(py: Python<'_>, e: nvector_import::ImportError) -> PyErr {
    use nvector_import::ImportError as E;
    let located = |file: String, message: String| -> PyErr {
        let made = py
            .import("nvector._errors")
            .and_then(|m| m.getattr("InputError"))
            .and_then(|cls| cls.call1(("", message.as_str(), file.as_str())));
        match made {
            Ok(instance) => PyErr::from_value(instance),
            Err(_) => PyValueError::new_err(format!("{file}: {message}")),
        }
    };
    match e {
        E::Read { ref source, .. } => {
            let text = e.to_string();
            match source.kind() {
                std::io::ErrorKind::NotFound => {
                    pyo3::exceptions::PyFileNotFoundError::new_err(text)
                }
                std::io::ErrorKind::PermissionDenied => {
                    pyo3::exceptions::PyPermissionError::new_err(text)
                }
                _ => pyo3::exceptions::PyOSError::new_err(text),
            }
        }
        E::Cell {
            ref path,
            line,
            column,
            ref name,
            ref text,
        } => located(
            format!("{}:{line}", path.display()),
            format!("column {column} ({name}): '{text}' is not a finite number"),
        ),
        E::Line {
            path,
            line,
            message,
        } => located(format!("{}:{line}", path.display()), message),
        E::File { path, message } => located(path.display().to_string(), message),
        E::Setting { option, message } => input_error(py, &InputError::new(option, message)),
        E::InvalidMission(e) | E::InvalidTdoa(e) => input_error(py, &e),
    }
}

/// A data set's directory as `nvector import --cmu-plaza/--utias-woods/
/// --locards-mlat DIR` converts it: a mission (a TDOA problem for LocaRDS).
#[pyfunction]
#[pyo3(signature = (name, directory, operator, outlier_share, false_detections, seed, set))]
#[allow(clippy::too_many_arguments)]
fn import_dataset<'py>(
    py: Python<'py>,
    name: &str,
    directory: std::path::PathBuf,
    operator: bool,
    outlier_share: f64,
    false_detections: usize,
    seed: u64,
    set: u32,
) -> PyResult<Bound<'py, PyAny>> {
    use nvector_import::{DataSet, DataSetImport};
    let which = DataSet::parse(name).ok_or_else(|| {
        input_error(
            py,
            &InputError::new(
                "name",
                format!(
                    "unknown data set '{name}' (expected cmu-plaza, utias-woods or locards-mlat)"
                ),
            ),
        )
    })?;
    if !(1..=8).contains(&set) {
        return Err(input_error(
            py,
            &InputError::new("set", format!("must be in 1..=8, found {set}")),
        ));
    }
    let o = DataSetImport {
        operator,
        outlier_share,
        false_detections,
        seed,
        set,
    };
    let doc = py
        .detach(|| nvector_import::import_dataset(which, &directory, &o))
        .map_err(|e| import_error(py, e))?;
    to_py(py, &doc)
}

/// A log CSV and a detections CSV as `nvector import --model ...` reads
/// them: `(mission, notes)`, the notes naming the columns left unread.
#[pyfunction]
#[pyo3(signature = (model, log, detections, errors, dt, motion_error, initial, initial_heading, heading_error, sensor_offset, landmark_count, landmark_min_separation, max_outliers, name))]
#[allow(clippy::too_many_arguments)]
fn import_csv<'py>(
    py: Python<'py>,
    model: String,
    log: std::path::PathBuf,
    detections: std::path::PathBuf,
    errors: Vec<(String, f64)>,
    dt: Option<f64>,
    motion_error: f64,
    initial: Option<Vec<[f64; 2]>>,
    initial_heading: Option<[f64; 2]>,
    heading_error: Option<f64>,
    sensor_offset: Option<[f64; 2]>,
    landmark_count: Option<usize>,
    landmark_min_separation: Option<f64>,
    max_outliers: Option<u64>,
    name: Option<String>,
) -> PyResult<(Bound<'py, PyAny>, Vec<String>)> {
    let settings = nvector_import::CsvImport {
        model,
        log,
        detections,
        errors,
        dt,
        motion_error,
        initial,
        initial_heading,
        heading_error,
        sensor_offset,
        landmark_count,
        landmark_min_separation,
        max_outliers,
        name,
    };
    let imported = py
        .detach(|| nvector_import::import_csv(&settings))
        .map_err(|e| import_error(py, e))?;
    Ok((to_py(py, &imported.mission)?, imported.notes))
}

// (end of the importers)

/// The compiled part of the `nvector` package (use `import nvector`).
#[pymodule]
fn _nvector(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(contract, m)?)?;
    m.add_function(wrap_pyfunction!(simulate, m)?)?;
    m.add_function(wrap_pyfunction!(run, m)?)?;
    m.add_function(wrap_pyfunction!(tdoa, m)?)?;
    m.add_function(wrap_pyfunction!(dumps, m)?)?;
    m.add_function(wrap_pyfunction!(figure, m)?)?;
    m.add_function(wrap_pyfunction!(read_result, m)?)?;
    m.add_function(wrap_pyfunction!(check, m)?)?;
    m.add_function(wrap_pyfunction!(import_dataset, m)?)?;
    m.add_function(wrap_pyfunction!(import_csv, m)?)?;
    m.add("MAX_STEPS", MAX_STEPS)?;
    Ok(())
}
