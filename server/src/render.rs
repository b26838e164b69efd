//! The figure of a result, as SVG or PNG, drawn with plotters from core's
//! one description of the picture (`nvector_core::figure`: layers,
//! thinning, colours, legend labels), the same as Python's `nvector.plot`:
//! for `nvector plot`, `nvector run --plot`, `nvector tdoa` and the
//! service's `?format=svg`. One style for both formats: a two-line
//! title (mission, contractor, status; the diameters in metres), axes in
//! metres at one scale on x and y, the layers bottom to top, and a legend
//! on the right. The font (DejaVu Sans, server/assets) is compiled in, so
//! no system font is needed. Below both `cli` and `service`.
//!
//! The PNG carries a text chunk `nvector-plot-area` = "left top right
//! bottom x0 x1 y0 y1": the plotting area in pixels and the metres it
//! shows, so that a reader (the tests) can find a point of the data in the
//! image.

use crate::CliError;
use nvector_core::figure::{describe, Figure, Kind, Layer};
use nvector_core::format::result::ResultDoc;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::FontStyle;
use serde_json::Value;
use std::sync::OnceLock;

/// Width of the whole figure in pixels.
const WIDTH: u32 = 1200;
/// Width of the legend panel on the right.
const LEGEND_WIDTH: u32 = 330;
/// Height of the title band.
const TITLE_HEIGHT: u32 = 64;
const MARGIN: u32 = 16;
const X_LABEL_AREA: u32 = 50;
const Y_LABEL_AREA: u32 = 80;
/// Height of the plotting area: between these (the view widens to keep
/// one scale on both axes).
const MIN_PLOT_HEIGHT: f64 = 320.0;
const MAX_PLOT_HEIGHT: f64 = 1100.0;
/// Largest magnitude of a drawn bound (past it, clamped: plotters' axes
/// need a finite span).
const LIMIT: f64 = 1e300;

static FONT: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");

pub(crate) fn font_ready() -> Result<(), CliError> {
    static READY: OnceLock<bool> = OnceLock::new();
    let ok = *READY.get_or_init(|| {
        plotters::style::register_font("sans-serif", FontStyle::Normal, FONT).is_ok()
    });
    if ok {
        Ok(())
    } else {
        Err(CliError("the figure's font could not be loaded".into()))
    }
}

/// `#rrggbb` to a colour (black for anything else).
fn colour(hex: &str) -> RGBColor {
    let h = hex.trim_start_matches('#');
    let c = |i: usize| {
        h.get(i..i + 2)
            .and_then(|s| u8::from_str_radix(s, 16).ok())
            .unwrap_or(0)
    };
    RGBColor(c(0), c(2), c(4))
}

/// The layout of a figure: its size and the view widened so that a metre
/// is as long on x as on y.
struct Layout {
    width: u32,
    height: u32,
    view: [f64; 4],
}

fn layout(fig: &Figure) -> Layout {
    let clamp = |v: f64| v.clamp(-LIMIT, LIMIT);
    let mut view = fig.view.map(clamp);
    let pw = f64::from(WIDTH - LEGEND_WIDTH - 2 * MARGIN - Y_LABEL_AREA);
    let (dx, dy) = (view[1] - view[0], view[3] - view[2]);
    let mut ph = MIN_PLOT_HEIGHT;
    if dx.is_finite() && dy.is_finite() && dx > 0.0 && dy > 0.0 {
        ph = pw * dy / dx;
        if ph > MAX_PLOT_HEIGHT {
            // Too tall: widen x.
            ph = MAX_PLOT_HEIGHT;
            let grow = (dy * pw / ph - dx) / 2.0;
            view[0] = clamp(view[0] - grow);
            view[1] = clamp(view[1] + grow);
        } else if ph < MIN_PLOT_HEIGHT {
            // Too flat: widen y.
            ph = MIN_PLOT_HEIGHT;
            let grow = (dx * ph / pw - dy) / 2.0;
            view[2] = clamp(view[2] - grow);
            view[3] = clamp(view[3] + grow);
        }
    }
    Layout {
        width: WIDTH,
        height: TITLE_HEIGHT + 2 * MARGIN + X_LABEL_AREA + ph as u32,
        view,
    }
}

/// Tick labels: as many decimals as the span needs.
fn tick(span: f64) -> impl Fn(&f64) -> String {
    let decimals = if span >= 50.0 {
        0
    } else if span >= 5.0 {
        1
    } else if span >= 0.5 {
        2
    } else {
        4
    };
    move |v: &f64| {
        if span >= 1e7 {
            format!("{v:.2e}")
        } else {
            format!("{v:.decimals$}")
        }
    }
}

/// Breaks a legend label into lines of at most `width` characters.
fn wrap(text: &str, width: usize) -> Vec<String> {
    let mut lines = vec![String::new()];
    for word in text.split_whitespace() {
        let line = lines.last_mut().expect("one line");
        if !line.is_empty() && line.chars().count() + 1 + word.chars().count() > width {
            lines.push(word.to_string());
        } else {
            if !line.is_empty() {
                line.push(' ');
            }
            line.push_str(word);
        }
    }
    lines
}

type PlotArea = ([i32; 4], [f64; 4]);

fn err<E: std::fmt::Display>(e: E) -> CliError {
    CliError(format!("drawing the figure: {e}"))
}

/// Draws `fig` on `root`; returns the plotting area in pixels and the view.
fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    fig: &Figure,
    lay: &Layout,
) -> Result<PlotArea, CliError> {
    root.fill(&WHITE).map_err(err)?;
    let (top, rest) = root.split_vertically(TITLE_HEIGHT);
    top.draw_text(
        &fig.title,
        &("sans-serif", 20).into_font().color(&BLACK),
        (MARGIN as i32, 10),
    )
    .map_err(err)?;
    top.draw_text(
        &fig.subtitle,
        &("sans-serif", 16).into_font().color(&RGBColor(60, 60, 60)),
        (MARGIN as i32, 38),
    )
    .map_err(err)?;
    let (chart_area, legend_area) = rest.split_horizontally(WIDTH - LEGEND_WIDTH);
    let v = lay.view;
    let mut chart = ChartBuilder::on(&chart_area)
        .margin(MARGIN)
        .x_label_area_size(X_LABEL_AREA)
        .y_label_area_size(Y_LABEL_AREA)
        .build_cartesian_2d(v[0]..v[1], v[2]..v[3])
        .map_err(err)?;
    let xf = tick(v[1] - v[0]);
    let yf = tick(v[3] - v[2]);
    chart
        .configure_mesh()
        .x_desc(&fig.x_label)
        .y_desc(&fig.y_label)
        .x_labels(8)
        .y_labels(8)
        .x_label_formatter(&xf)
        .y_label_formatter(&yf)
        .label_style(("sans-serif", 14))
        .axis_desc_style(("sans-serif", 15))
        .light_line_style(WHITE)
        .bold_line_style(RGBColor(235, 235, 235))
        .draw()
        .map_err(err)?;
    for layer in &fig.layers {
        draw_layer(&mut chart, layer, v)?;
    }
    let (xs, ys) = chart.plotting_area().get_pixel_range();
    legend(&legend_area, &fig.layers)?;
    root.present().map_err(err)?;
    Ok(([xs.start, ys.start, xs.end, ys.end], v))
}

fn draw_layer<DB: DrawingBackend>(
    chart: &mut ChartContext<
        DB,
        Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
    >,
    layer: &Layer,
    view: [f64; 4],
) -> Result<(), CliError> {
    // Coordinates far outside the view (up to the float limits) are
    // brought to one view's span beyond it: plotters maps them to i32
    // pixels, which must not overflow; what lies outside is clipped anyway.
    let (sx, sy) = (view[1] - view[0], view[3] - view[2]);
    let cx = |x: f64| x.clamp(view[0] - sx, view[1] + sx);
    let cy = |y: f64| y.clamp(view[2] - sy, view[3] + sy);
    let corners = |r: &[f64; 4]| [(cx(r[0]), cy(r[2])), (cx(r[1]), cy(r[3]))];
    let c = colour(layer.colour);
    match layer.kind {
        Kind::Rects => {
            if layer.fill_alpha > 0.0 {
                let style = c.mix(layer.fill_alpha).filled();
                chart
                    .draw_series(
                        layer
                            .rects
                            .iter()
                            .map(|r| Rectangle::new(corners(r), style)),
                    )
                    .map_err(err)?;
            }
            if layer.line_width > 0.0 {
                // Hairlines (under 1 px) as 1 px at half strength.
                let style = if layer.line_width < 1.0 {
                    c.mix(0.5).stroke_width(1)
                } else {
                    c.stroke_width(layer.line_width.ceil() as u32)
                };
                chart
                    .draw_series(
                        layer
                            .rects
                            .iter()
                            .map(|r| Rectangle::new(corners(r), style)),
                    )
                    .map_err(err)?;
            }
        }
        Kind::Path => {
            chart
                .draw_series(LineSeries::new(
                    layer.points.iter().map(|p| (cx(p[0]), cy(p[1]))),
                    c.stroke_width(layer.line_width.ceil() as u32),
                ))
                .map_err(err)?;
        }
        Kind::Points => {
            chart
                .draw_series(
                    layer
                        .points
                        .iter()
                        .map(|p| Circle::new((cx(p[0]), cy(p[1])), 5, c.filled())),
                )
                .map_err(err)?;
        }
        Kind::Polygons => draw_polygons(chart, layer, c, view)?,
    }
    Ok(())
}

/// A layer of polygons (heading wedges, true-heading ticks): filled when
/// `fill_alpha` > 0, outlined (closed; a two-point polygon is a segment)
/// when `line_width` > 0, coordinates brought within a view's span as in
/// [`draw_layer`].
fn draw_polygons<DB: DrawingBackend>(
    chart: &mut ChartContext<
        DB,
        Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
    >,
    layer: &Layer,
    c: RGBColor,
    view: [f64; 4],
) -> Result<(), CliError> {
    let (sx, sy) = (view[1] - view[0], view[3] - view[2]);
    let pts = |poly: &Vec<[f64; 2]>| -> Vec<(f64, f64)> {
        poly.iter()
            .map(|p| {
                (
                    p[0].clamp(view[0] - sx, view[1] + sx),
                    p[1].clamp(view[2] - sy, view[3] + sy),
                )
            })
            .collect()
    };
    if layer.fill_alpha > 0.0 {
        let style = c.mix(layer.fill_alpha).filled();
        chart
            .draw_series(
                layer
                    .polygons
                    .iter()
                    .filter(|p| p.len() > 2)
                    .map(|p| Polygon::new(pts(p), style)),
            )
            .map_err(err)?;
    }
    if layer.line_width > 0.0 {
        let style = c.stroke_width(layer.line_width.ceil() as u32);
        chart
            .draw_series(layer.polygons.iter().map(|p| {
                let mut v = pts(p);
                if v.len() > 2 {
                    v.push(v[0]);
                }
                PathElement::new(v, style)
            }))
            .map_err(err)?;
    }
    Ok(())
}

fn legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    layers: &[Layer],
) -> Result<(), CliError> {
    let font = ("sans-serif", 14).into_font().color(&BLACK);
    area.draw_text(
        "Legend",
        &("sans-serif", 16).into_font().color(&BLACK),
        (10, MARGIN as i32),
    )
    .map_err(err)?;
    let mut y = MARGIN as i32 + 30;
    for layer in layers {
        let c = colour(layer.colour);
        let (x0, x1, y0, y1) = (10, 40, y + 1, y + 15);
        match layer.kind {
            Kind::Rects => {
                if layer.fill_alpha > 0.0 {
                    area.draw(&Rectangle::new(
                        [(x0, y0), (x1, y1)],
                        c.mix(layer.fill_alpha).filled(),
                    ))
                    .map_err(err)?;
                }
                if layer.line_width > 0.0 {
                    area.draw(&Rectangle::new(
                        [(x0, y0), (x1, y1)],
                        c.stroke_width(layer.line_width.ceil() as u32),
                    ))
                    .map_err(err)?;
                }
            }
            Kind::Points => area
                .draw(&Circle::new((25, y + 8), 5, c.filled()))
                .map_err(err)?,
            Kind::Polygons if layer.fill_alpha > 0.0 => {
                // A wedge: its apex on the left, its arc on the right.
                let wedge = vec![(x0, y + 8), (x1, y0), (x1 + 2, y + 8), (x1, y1)];
                area.draw(&Polygon::new(
                    wedge.clone(),
                    c.mix(layer.fill_alpha).filled(),
                ))
                .map_err(err)?;
                let mut outline = wedge;
                outline.push((x0, y + 8));
                area.draw(&PathElement::new(outline, c.stroke_width(1)))
                    .map_err(err)?;
            }
            // A line: paths, and polygons drawn unfilled.
            Kind::Path | Kind::Polygons => area
                .draw(&PathElement::new(
                    vec![(x0, y + 8), (x1, y + 8)],
                    c.stroke_width(layer.line_width.ceil() as u32),
                ))
                .map_err(err)?,
        }
        for line in wrap(&layer.label, 34) {
            area.draw_text(&line, &font, (50, y)).map_err(err)?;
            y += 18;
        }
        y += 10;
    }
    Ok(())
}

/// The figure as SVG text (the service's `?format=svg`): the result read
/// through its types (`nvector_core::format::result`); a result that does
/// not read, or a drawing that fails (it does not, on a string), gives an
/// SVG stating why.
pub fn render_svg(result: &Value, mission: &Value) -> String {
    nvector_core::format::result::read_value(result)
        .map_err(|e| CliError(format!("result: {e}")))
        .and_then(|result| try_render_svg(&result, mission))
        .unwrap_or_else(|CliError(e)| {
        format!(
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"600\" height=\"40\"><text x=\"8\" y=\"24\">{}</text></svg>\n",
            e.replace('&', "&amp;").replace('<', "&lt;")
        )
    })
}

/// The figure as SVG text.
pub fn try_render_svg(result: &ResultDoc, mission: &Value) -> Result<String, CliError> {
    font_ready()?;
    let fig = describe(result, Some(mission));
    let lay = layout(&fig);
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, (lay.width, lay.height)).into_drawing_area();
        draw(&root, &fig, &lay)?;
    }
    Ok(out)
}

/// The figure as a PNG image.
pub fn render_png(result: &ResultDoc, mission: &Value) -> Result<Vec<u8>, CliError> {
    font_ready()?;
    let fig = describe(result, Some(mission));
    let lay = layout(&fig);
    let mut px = vec![255u8; lay.width as usize * lay.height as usize * 3];
    let (area, view) = {
        let root = BitMapBackend::with_buffer(&mut px, (lay.width, lay.height)).into_drawing_area();
        draw(&root, &fig, &lay)?
    };
    let mut bytes = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut bytes, lay.width, lay.height);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        let text = format!(
            "{} {} {} {} {:e} {:e} {:e} {:e}",
            area[0], area[1], area[2], area[3], view[0], view[1], view[2], view[3]
        );
        enc.add_text_chunk("nvector-plot-area".into(), text)
            .map_err(|e| CliError(format!("PNG: {e}")))?;
        enc.add_itxt_chunk("Title".into(), format!("{} — {}", fig.title, fig.subtitle))
            .map_err(|e| CliError(format!("PNG: {e}")))?;
        let mut writer = enc
            .write_header()
            .map_err(|e| CliError(format!("PNG: {e}")))?;
        writer
            .write_image_data(&px)
            .map_err(|e| CliError(format!("PNG: {e}")))?;
    }
    Ok(bytes)
}
