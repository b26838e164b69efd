//! `nvector tdoa`: one TDOA passive-location problem (`nvector-tdoa/1`),
//! solved locally (core's `tdoa`), with an optional figure; and the radar
//! scenario of `nvector simulate --scenario radar`.

use crate::CliError;
use nvector_core::nvector::Contractor;
use nvector_core::tdoa::problem::TdoaProblem;
use nvector_core::tdoa::result::group_box;
use nvector_core::tdoa::simulate::{simulate_radar, RadarOptions};
use nvector_core::tdoa::{solve_tdoa, tdoa_result_json, TdoaOptions, TdoaSolution};
use nvector_core::IntervalBox;
use plotters::prelude::*;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Arguments of `nvector tdoa`.
#[derive(clap::Args)]
pub struct Args {
    /// The problem (nvector-tdoa/1 JSON).
    mission: PathBuf,
    /// none, nvalue, projection, independent, exact, shapes or best
    /// (default best; none: the operator's matching only).
    #[arg(long, value_parser = parse_contractor)]
    contractor: Option<Mode>,
    /// Bisections of each pulse's paving.
    #[arg(long, default_value_t = nvector_core::tdoa::pulse::DEFAULT_BUDGET)]
    budget: usize,
    /// Most rounds.
    #[arg(long, default_value_t = 8)]
    max_rounds: usize,
    /// Output file for the result (default: standard output).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Also draw the result (.svg): receivers, pulse boxes, emitter boxes,
    /// truth, in the x-y plane (metres).
    #[arg(long)]
    plot: Option<PathBuf>,
}

/// The value of `--contractor`: `None` for `none` (the operator's matching
/// only). A newtype, not `Option<Option<Contractor>>`: clap reads that type
/// as a flag whose value is optional and of type `Contractor`, and panicked
/// on every `--contractor` given (the parser returns an `Option`).
#[derive(Clone, Copy)]
struct Mode(Option<Contractor>);

fn parse_contractor(s: &str) -> Result<Mode, String> {
    if s == "none" {
        return Ok(Mode(None));
    }
    Contractor::parse(s).map(|c| Mode(Some(c))).ok_or_else(|| {
        format!("unknown contractor '{s}' (expected none, nvalue, projection, independent, exact, shapes or best)")
    })
}

/// Most bisections per pulse (the work is budget x pulses x readings).
const MAX_BUDGET: usize = 100_000;

/// Runs the subcommand.
pub fn run(a: Args) -> Result<(), CliError> {
    let text = std::fs::read_to_string(&a.mission)
        .map_err(|e| CliError(format!("reading {}: {e}", a.mission.display())))?;
    let problem = TdoaProblem::from_json_str(&text).map_err(|e| {
        CliError(format!(
            "{}: {}",
            a.mission.display(),
            super::wrong_kind(&text, "nvector-tdoa/1", e.to_string())
        ))
    })?;
    if a.budget > MAX_BUDGET {
        return Err(CliError(format!("--budget must be at most {MAX_BUDGET}")));
    }
    if let Some(p) = &a.plot {
        // The figure is SVG only: a .png name got SVG bytes.
        let svg = p
            .extension()
            .and_then(|e| e.to_str())
            .is_some_and(|e| e.eq_ignore_ascii_case("svg"));
        if !svg {
            return Err(CliError(format!(
                "--plot {}: the figure must end in .svg",
                p.display()
            )));
        }
    }
    let options = TdoaOptions {
        mode: a.contractor.map_or(Some(Contractor::Best), |m| m.0),
        budget: a.budget,
        max_rounds: a.max_rounds.clamp(1, 1000),
    };
    let t0 = Instant::now();
    let s = solve_tdoa(&problem, &options);
    let ms = t0.elapsed().as_secs_f64() * 1e3;
    let result = tdoa_result_json(&problem, &options, &s, ms);
    let text = format!(
        "{}\n",
        serde_json::to_string(&result).expect("a JSON value")
    );
    match &a.out {
        Some(p) => std::fs::write(p, text)
            .map_err(|e| CliError(format!("writing {}: {e}", p.display())))?,
        None => {
            use std::io::Write as _;
            std::io::stdout()
                .write_all(text.as_bytes())
                .map_err(|e| CliError(format!("writing standard output: {e}")))?
        }
    }
    if let Some(p) = &a.plot {
        plot(&problem, &s, p)?;
    }
    say!(
        "{}: {} pulses, {} groups, {} in {:.0} ms",
        problem.name,
        problem.pulses.len(),
        s.groups.len(),
        result["status"].as_str().unwrap_or(""),
        ms
    );
    Ok(())
}

/// Options of the radar scenario, from `nvector simulate`'s arguments.
pub fn simulate(o: &RadarOptions) -> Result<serde_json::Value, CliError> {
    simulate_radar(o)
        .map_err(|e| CliError(format!("--{}: {}", e.path.replace('_', "-"), e.message)))
}

fn finite_box(b: &IntervalBox) -> Option<[f64; 4]> {
    let a = b.axes();
    let r = [a[0].lo(), a[0].hi(), a[1].lo(), a[1].hi()];
    (!b.is_empty() && r.iter().all(|x| x.is_finite())).then_some(r)
}

/// The x-y extent of what is drawn: receivers, truth, bounded boxes.
fn extent(p: &TdoaProblem, s: &TdoaSolution) -> [f64; 4] {
    let mut e = [
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    ];
    let mut add = |x: f64, y: f64| {
        if x.is_finite() && y.is_finite() {
            e = [e[0].min(x), e[1].max(x), e[2].min(y), e[3].max(y)];
        }
    };
    for r in &p.receivers {
        let m = r.position.mid();
        add(m[0], m[1]);
    }
    for t in p.truth.iter().flat_map(|t| &t.emitters) {
        add(t[0], t[1]);
    }
    for v in &s.vars {
        if let Some(b) = finite_box(&IntervalBox::new(&v.x)) {
            add(b[0], b[2]);
            add(b[1], b[3]);
        }
    }
    if !e[0].is_finite() {
        return [-1.0, 1.0, -1.0, 1.0];
    }
    let pad = 0.05 * (e[1] - e[0]).max(e[3] - e[2]).max(1.0);
    [e[0] - pad, e[1] + pad, e[2] - pad, e[3] + pad]
}

/// Draws the x-y plane: receivers, pulse boxes, emitter boxes, truth.
fn plot(p: &TdoaProblem, s: &TdoaSolution, path: &Path) -> Result<(), CliError> {
    crate::render::font_ready()?;
    let err = |e: String| CliError(format!("drawing {}: {e}", path.display()));
    let root = SVGBackend::new(path, (900, 800)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| err(e.to_string()))?;
    let [x0, x1, y0, y1] = extent(p, s);
    let mut chart = ChartBuilder::on(&root)
        .caption(
            format!("{}: TDOA pulses and emitters", p.name),
            ("sans-serif", 20),
        )
        .margin(15)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(|e| err(e.to_string()))?;
    chart
        .configure_mesh()
        .x_desc("x east (m)")
        .y_desc("y north (m)")
        .draw()
        .map_err(|e| err(e.to_string()))?;
    let rect = |b: [f64; 4], style: ShapeStyle| Rectangle::new([(b[0], b[2]), (b[1], b[3])], style);
    let pulse_style = BLUE.mix(0.4).stroke_width(1);
    chart
        .draw_series(
            s.vars
                .iter()
                .filter_map(|v| finite_box(&IntervalBox::new(&v.x)))
                .map(|b| rect(b, pulse_style)),
        )
        .map_err(|e| err(e.to_string()))?
        .label("pulse boxes")
        .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 10, y + 5)], pulse_style));
    let group_style = RED.stroke_width(2);
    chart
        .draw_series(
            s.groups
                .iter()
                .filter_map(|g| finite_box(&group_box(s, g)))
                .map(|b| rect(b, group_style)),
        )
        .map_err(|e| err(e.to_string()))?
        .label("emitter boxes (proved groups)")
        .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 10, y + 5)], group_style));
    let rx: Vec<(f64, f64)> = p
        .receivers
        .iter()
        .map(|r| r.position.mid())
        .map(|m| (m[0], m[1]))
        .collect();
    chart
        .draw_series(
            rx.iter()
                .map(|&c| TriangleMarker::new(c, 8, BLACK.filled())),
        )
        .map_err(|e| err(e.to_string()))?
        .label("receivers")
        .legend(|(x, y)| TriangleMarker::new((x + 5, y), 6, BLACK.filled()));
    if let Some(t) = &p.truth {
        chart
            .draw_series(
                t.emitters
                    .iter()
                    .map(|e| Cross::new((e[0], e[1]), 6, GREEN.stroke_width(2))),
            )
            .map_err(|e| err(e.to_string()))?
            .label("true emitters")
            .legend(|(x, y)| Cross::new((x + 5, y), 5, GREEN.stroke_width(2)));
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.9))
        .border_style(BLACK)
        .draw()
        .map_err(|e| err(e.to_string()))?;
    root.present().map_err(|e| err(e.to_string()))
}
