//! What the page's canvases say they drew, read in a real headless
//! Chromium (the session and the page's server are the harness of
//! [`crate::browser`], re-exported here). Used by the browser tests
//! (tests/browser.rs, tests/browser_slam.rs).

pub use crate::browser::{page_server, Driver};

/// A script counting the page's fetches of a module's files (`pkg-slam`...).
pub fn fetched(module: &str) -> String {
    format!("return performance.getEntriesByType('resource').filter((e) => e.name.includes('/{module}/')).length")
}

/// A number from a canvas's dataset (what `drawResult` drew).
pub fn canvas_data(d: &Driver, canvas: &str, key: &str) -> f64 {
    d.js(&format!(
        "return Number(document.getElementById('{canvas}').dataset.{key})"
    ))
    .as_f64()
    .unwrap_or_else(|| panic!("no number in {canvas}.dataset.{key}"))
}

/// Painted pixels (alpha > 0) of a canvas.
pub fn painted(d: &Driver, canvas: &str) -> f64 {
    d.js(&format!(
        "const c = document.getElementById('{canvas}'); const px = c.getContext('2d').getImageData(0, 0, c.width, c.height).data; \
         let n = 0; for (let i = 3; i < px.length; i += 4) if (px[i] > 0) n++; return n;"
    ))
    .as_f64()
    .unwrap()
}

/// A canvas's legend (drawn in it) names at least `labels`, and its axes
/// have ticks on both edges and the unit (`m`, or none in the playground).
pub fn legend_and_axes(d: &Driver, canvas: &str, labels: &[&str], unit: &str) {
    let data = d.js(&format!(
        "const c = document.getElementById('{canvas}').dataset; return [c.legend || '', c.axes || '', c.unit ?? 'none'];"
    ));
    let legend: Vec<&str> = data[0].as_str().unwrap().split('|').collect();
    for l in labels {
        assert!(
            legend.iter().any(|x| x.starts_with(l)),
            "{canvas}: no \"{l}\" in the legend {legend:?}"
        );
    }
    let axes: Vec<f64> = data[1]
        .as_str()
        .unwrap()
        .split(',')
        .map(|x| x.parse().unwrap_or(0.0))
        .collect();
    assert!(
        axes.len() == 3 && axes[0] >= 2.0 && axes[1] >= 2.0 && axes[2] > 0.0,
        "{canvas}: axes (ticks x, ticks y, step) = {axes:?}"
    );
    assert_eq!(data[2], unit, "{canvas}: unit");
}
