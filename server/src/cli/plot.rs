//! `nvector plot`: a figure like the paper's Figure 9 — trajectory boxes,
//! detection boxes, landmark boxes and the truth — as SVG or PNG (first two
//! axes, y up).

use crate::CliError;
use serde_json::Value;
use std::fmt::Write as _;
use std::path::PathBuf;

/// Arguments of `nvector plot`.
#[derive(clap::Args)]
pub struct Args {
    /// The result (nvector-result/1 JSON).
    result: PathBuf,
    /// The mission it was computed from (for the truth).
    #[arg(long)]
    mission: PathBuf,
    /// Output figure: .svg or .png.
    #[arg(long)]
    out: PathBuf,
}

/// A rectangle on the first two axes.
#[derive(Debug, Clone, Copy)]
struct Rect {
    x0: f64,
    x1: f64,
    y0: f64,
    y1: f64,
}

fn bound(v: &Value) -> Option<f64> {
    v.as_f64().filter(|x| x.is_finite())
}

/// The first two axes of a box, when bounded and non-empty.
fn rect(b: &Value) -> Option<Rect> {
    let a = b.as_array()?;
    let x = a.first()?.as_array()?;
    let y = a.get(1)?.as_array()?;
    Some(Rect {
        x0: bound(&x[0])?,
        x1: bound(&x[1])?,
        y0: bound(&y[0])?,
        y1: bound(&y[1])?,
    })
}

/// What a figure shows, extracted from the result and mission JSON.
struct Scene {
    trajectory: Vec<Rect>,
    detections: Vec<(Rect, usize)>,
    landmarks: Vec<Rect>,
    truth_path: Vec<(f64, f64)>,
    truth_landmarks: Vec<(f64, f64)>,
    view: Rect,
}

fn scene(result: &Value, mission: &Value) -> Scene {
    let arr = |v: &Value| v.as_array().cloned().unwrap_or_default();
    let traj = arr(&result["trajectory"]);
    // At most 1500 trajectory boxes are drawn (every k-th, plus the last).
    let stride = traj.len().div_ceil(1500).max(1);
    let mut trajectory: Vec<Rect> = traj.iter().step_by(stride).filter_map(rect).collect();
    if let Some(r) = traj.last().and_then(rect) {
        trajectory.push(r);
    }
    let mut group_of = vec![usize::MAX; arr(&result["detections"]).len()];
    for (g, members) in arr(&result["matching"]).iter().enumerate() {
        for m in arr(members) {
            if let Some(i) = m
                .as_u64()
                .map(|i| i as usize)
                .filter(|&i| i < group_of.len())
            {
                group_of[i] = g;
            }
        }
    }
    let detections: Vec<(Rect, usize)> = arr(&result["detections"])
        .iter()
        .zip(&group_of)
        .filter_map(|(b, &g)| rect(b).map(|r| (r, g)))
        .collect();
    let landmarks: Vec<Rect> = arr(&result["landmarks"]).iter().filter_map(rect).collect();
    let point = |p: &Value| Some((bound(p.get(0)?)?, bound(p.get(1)?)?));
    let truth_path: Vec<(f64, f64)> = arr(&mission["truth"]["positions"])
        .iter()
        .filter_map(point)
        .collect();
    let truth_landmarks: Vec<(f64, f64)> = arr(&mission["truth"]["landmarks"])
        .iter()
        .filter_map(point)
        .collect();
    let mut view = Rect {
        x0: f64::INFINITY,
        x1: f64::NEG_INFINITY,
        y0: f64::INFINITY,
        y1: f64::NEG_INFINITY,
    };
    let mut grow = |x: f64, y: f64| {
        view.x0 = view.x0.min(x);
        view.x1 = view.x1.max(x);
        view.y0 = view.y0.min(y);
        view.y1 = view.y1.max(y);
    };
    for r in trajectory
        .iter()
        .chain(landmarks.iter())
        .chain(detections.iter().map(|(r, _)| r))
    {
        grow(r.x0, r.y0);
        grow(r.x1, r.y1);
    }
    for &(x, y) in truth_path.iter().chain(&truth_landmarks) {
        grow(x, y);
    }
    if !view.x0.is_finite() {
        view = Rect {
            x0: -1.0,
            x1: 1.0,
            y0: -1.0,
            y1: 1.0,
        };
    }
    let pad = 0.03 * (view.x1 - view.x0).max(view.y1 - view.y0).max(1e-9);
    view = Rect {
        x0: view.x0 - pad,
        x1: view.x1 + pad,
        y0: view.y0 - pad,
        y1: view.y1 + pad,
    };
    Scene {
        trajectory,
        detections,
        landmarks,
        truth_path,
        truth_landmarks,
        view,
    }
}

/// Colours of matching groups (detections in no group are grey).
const PALETTE: [&str; 8] = [
    "#e6194b", "#3cb44b", "#4363d8", "#f58231", "#911eb4", "#42d4f4", "#f032e6", "#9a6324",
];

fn group_colour(g: usize) -> &'static str {
    if g == usize::MAX {
        "#888888"
    } else {
        PALETTE[g % PALETTE.len()]
    }
}

/// The figure as SVG text (900 px wide; y up; first two axes).
pub fn render_svg(result: &Value, mission: &Value) -> String {
    let s = scene(result, mission);
    let v = s.view;
    let width = 900.0;
    let scale = width / (v.x1 - v.x0);
    let height = ((v.y1 - v.y0) * scale).clamp(100.0, 4000.0);
    let tx = |x: f64| (x - v.x0) * scale;
    let ty = |y: f64| (v.y1 - y) * scale;
    let mut out = String::new();
    let _ = writeln!(
        out,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width:.0}" height="{height:.0}" viewBox="0 0 {width:.0} {height:.0}">"#
    );
    let _ = writeln!(out, r#"<rect width="100%" height="100%" fill="white"/>"#);
    let title = result["mission"].as_str().unwrap_or("");
    let contractor = result["options"]["contractor"].as_str().unwrap_or("");
    let _ = writeln!(
        out,
        r#"<title>{} ({})</title>"#,
        escape(title),
        escape(contractor)
    );
    let mut rect_svg = |r: &Rect, class: &str, stroke: &str, fill: &str| {
        let _ = writeln!(
            out,
            r#"<rect class="{class}" x="{:.2}" y="{:.2}" width="{:.2}" height="{:.2}" fill="{fill}" stroke="{stroke}" stroke-width="0.6"/>"#,
            tx(r.x0),
            ty(r.y1),
            ((r.x1 - r.x0) * scale).max(0.5),
            ((r.y1 - r.y0) * scale).max(0.5)
        );
    };
    for r in &s.trajectory {
        rect_svg(r, "trajectory", "#4a90d9", "none");
    }
    for (r, g) in &s.detections {
        rect_svg(r, "detection", group_colour(*g), "none");
    }
    for r in &s.landmarks {
        rect_svg(r, "landmark", "#b00000", "rgba(200,0,0,0.25)");
    }
    if !s.truth_path.is_empty() {
        let stride = (s.truth_path.len() / 5000).max(1);
        let pts: Vec<String> = s
            .truth_path
            .iter()
            .step_by(stride)
            .map(|&(x, y)| format!("{:.2},{:.2}", tx(x), ty(y)))
            .collect();
        let _ = writeln!(
            out,
            r#"<polyline class="truth" points="{}" fill="none" stroke="black" stroke-width="0.8"/>"#,
            pts.join(" ")
        );
    }
    for &(x, y) in &s.truth_landmarks {
        let _ = writeln!(
            out,
            r#"<circle class="truth-landmark" cx="{:.2}" cy="{:.2}" r="3" fill="black"/>"#,
            tx(x),
            ty(y)
        );
    }
    let _ = writeln!(
        out,
        r#"<text x="8" y="18" font-family="sans-serif" font-size="14">{} — {} — max trajectory diameter {}</text>"#,
        escape(title),
        escape(contractor),
        result["metrics"]["max_trajectory_diameter"]
    );
    out.push_str("</svg>\n");
    out
}

fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// The figure as a PNG image (rectangle outlines and the truth path).
pub fn render_png(result: &Value, mission: &Value) -> Result<Vec<u8>, CliError> {
    let s = scene(result, mission);
    let v = s.view;
    let w: usize = 900;
    let scale = w as f64 / (v.x1 - v.x0);
    let h = (((v.y1 - v.y0) * scale) as usize).clamp(100, 4000);
    let mut px = vec![255u8; w * h * 3];
    let mut put = |x: f64, y: f64, c: [u8; 3]| {
        let (i, j) = (x.round(), y.round());
        if i >= 0.0 && j >= 0.0 && (i as usize) < w && (j as usize) < h {
            let k = (j as usize * w + i as usize) * 3;
            px[k..k + 3].copy_from_slice(&c);
        }
    };
    let tx = |x: f64| (x - v.x0) * scale;
    let ty = |y: f64| (v.y1 - y) * scale;
    let line =
        |x0: f64, y0: f64, x1: f64, y1: f64, c: [u8; 3], put: &mut dyn FnMut(f64, f64, [u8; 3])| {
            let n = ((x1 - x0).abs().max((y1 - y0).abs()).ceil() as usize).clamp(1, 20_000);
            for t in 0..=n {
                let f = t as f64 / n as f64;
                put(x0 + f * (x1 - x0), y0 + f * (y1 - y0), c);
            }
        };
    let outline = |r: &Rect, c: [u8; 3], put: &mut dyn FnMut(f64, f64, [u8; 3])| {
        let (x0, x1, y0, y1) = (tx(r.x0), tx(r.x1), ty(r.y1), ty(r.y0));
        line(x0, y0, x1, y0, c, put);
        line(x1, y0, x1, y1, c, put);
        line(x1, y1, x0, y1, c, put);
        line(x0, y1, x0, y0, c, put);
    };
    for r in &s.trajectory {
        outline(r, [74, 144, 217], &mut put);
    }
    for (r, _) in &s.detections {
        outline(r, [245, 130, 49], &mut put);
    }
    for r in &s.landmarks {
        outline(r, [176, 0, 0], &mut put);
    }
    for w2 in s.truth_path.windows(2) {
        let (a, b) = (w2[0], w2[1]);
        let n = 2;
        for t in 0..=n {
            let f = t as f64 / n as f64;
            put(
                tx(a.0 + f * (b.0 - a.0)),
                ty(a.1 + f * (b.1 - a.1)),
                [0, 0, 0],
            );
        }
    }
    let mut bytes = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut bytes, w as u32, h as u32);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        let mut writer = enc
            .write_header()
            .map_err(|e| CliError(format!("PNG: {e}")))?;
        writer
            .write_image_data(&px)
            .map_err(|e| CliError(format!("PNG: {e}")))?;
    }
    Ok(bytes)
}

/// Writes the figure to `path` (.svg or .png).
pub fn write_plot(path: &PathBuf, result: &Value, mission: &Value) -> Result<(), CliError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    let bytes = match ext.as_str() {
        "svg" => render_svg(result, mission).into_bytes(),
        "png" => render_png(result, mission)?,
        _ => {
            return Err(CliError(format!(
                "{}: the figure must end in .svg or .png",
                path.display()
            )))
        }
    };
    std::fs::write(path, bytes).map_err(|e| CliError(format!("writing {}: {e}", path.display())))
}

fn read_json(path: &PathBuf) -> Result<Value, CliError> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| CliError(format!("reading {}: {e}", path.display())))?;
    serde_json::from_str(&text)
        .map_err(|e| CliError(format!("{}: invalid JSON: {e}", path.display())))
}

/// Runs the subcommand.
pub fn run(a: Args) -> Result<(), CliError> {
    let result = read_json(&a.result)?;
    if result["format"] != "nvector-result/1" {
        return Err(CliError(format!(
            "{}: format: expected \"nvector-result/1\"",
            a.result.display()
        )));
    }
    let mission = read_json(&a.mission)?;
    write_plot(&a.out, &result, &mission)
}
