//! The missions tab as a person reads it, in a real headless Chromium at
//! 1400x900 against the real `nvector serve` (the harness of
//! tests/src/browser.rs): CMU Plaza 1 uploaded through the page, run by the
//! service and drawn from core's description of the figure (the CLI's
//! picture: the landmark regions as the thin arcs they are, not a block
//! over the plaza; the same legend; axes labelled in metres); the progress
//! bar's values over the job; a result file uploaded as a mission refused
//! with a message saying so, in the error colour, the progress bar
//! cleared; the missions list with id, date and size, and one upload per
//! chosen file; and no request from any page to another origin.

use nvector_tests as common;

use common::browser::{page_server, Driver};
use serde_json::{json, Value};
use std::path::Path;
use std::time::Duration;

/// The CMU Plaza 1 mission, imported by the CLI into `dir`.
fn plaza_mission(dir: &Path) -> std::path::PathBuf {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("../data/cmu-plaza1");
    let out = dir.join("plaza.json");
    let st = common::nvector()
        .args(["import", "--cmu-plaza"])
        .arg(&data)
        .arg("--out")
        .arg(&out)
        .status()
        .unwrap();
    assert!(st.success(), "nvector import --cmu-plaza");
    out
}

/// Chooses `file` in the tab's file input (as a person picking it).
fn choose(d: &Driver, file: &Path) {
    let input = d.element("#ms-file");
    d.cmd(
        "POST",
        &format!("/element/{input}/value"),
        Some(json!({"text": file.to_str().unwrap()})),
    );
}

/// Fractions of the plotting area's pixels (inside the axes' labels and
/// the scale bar) of the landmark regions' colour as drawn: core's
/// `GROUPS` #c0392b at opacity 0.3 over white (236, 194, 191), or fainter
/// where a thin arc covers part of a pixel: any red tint (r above g and b),
/// what a flood of regions over the plaza paints too.
fn region_coloured(d: &Driver, canvas: &str) -> Value {
    d.js(&format!(
        "const c = document.getElementById('{canvas}'), w = c.width, h = c.height; \
         const px = c.getContext('2d').getImageData(0, 0, w, h).data; \
         let n = 0, red = 0; \
         for (let y = 10; y < h - 40; y++) for (let x = 40; x < w - 10; x++) {{ const o = (y * w + x) * 4; \
           const a = px[o + 3] / 255, [r, g, b] = [0, 1, 2].map((k) => px[o + k] * a + 255 * (1 - a)); n++; \
           if (r > 150 && r - g > 6 && r - b > 6) red++; }} \
         return {{ share: red / n, pixels: red }};"
    ))
}

/// The mission list's and the progress bar's state, the state line's
/// colour and text.
fn state_line(d: &Driver) -> Value {
    d.js("const s = document.getElementById('ms-state'), p = document.getElementById('ms-progress'); \
          return { text: s.textContent, error: s.classList.contains('error'), colour: getComputedStyle(s).color, progress: p.value };")
}

#[test]
fn the_missions_tab_as_a_person_reads_it() {
    let Some(d) = Driver::start() else { return };
    d.window(1400, 900);
    let s = page_server();
    let base = format!("http://{}", s.addr);
    d.goto(&format!("{base}/?tab=missions"));
    d.wait(
        "return document.getElementById('wasm-status').dataset.ready === 'true'",
        Duration::from_secs(30),
    );

    // CMU Plaza 1 through the page, the default contractor (best: the
    // shapes run, the landmark regions are in the result).
    let plaza = plaza_mission(&s.dir);
    choose(&d, &plaza);
    d.click("#ms-submit");
    // The bar's values while the job runs, sampled by the page itself.
    d.js("window.bar = []; const p = document.getElementById('ms-progress'); \
          window.barTimer = setInterval(() => window.bar.push([performance.now(), p.value]), 50); return 1;");
    // One upload per chosen file: the button is off once clicked.
    assert_eq!(
        d.js("return document.getElementById('ms-submit').disabled"),
        true
    );
    let state = d.wait(
        "const s = document.getElementById('rv-summary').dataset.state; return (s === 'drawn' || s === 'error' || s === 'failed') && s",
        Duration::from_secs(300),
    );
    d.js("clearInterval(window.barTimer); return 1;");
    assert_eq!(state, "drawn", "{}", state_line(&d));
    assert_eq!(
        d.js("return document.getElementById('ms-submit').disabled"),
        true,
        "the file is forgotten once stored: a second click uploads nothing"
    );
    assert_eq!(
        d.js("return document.querySelectorAll('#ms-missions li[data-id]').length"),
        1
    );

    // The figure is core's: its layers, the CLI's legend labels, axes in
    // metres with their labels.
    let data = d.js("return {...document.getElementById('rv-0').dataset}");
    eprintln!("BROWSER plaza figure: {data}");
    let layers = data["layers"].as_str().unwrap();
    for l in ["trajectory", "regions", "groups", "truth_path"] {
        assert!(layers.split(',').any(|x| x == l), "no {l} layer: {layers}");
    }
    let legend: Vec<&str> = data["legend"].as_str().unwrap().split('|').collect();
    for want in [
        "trajectory: envelope of the ",
        "landmark regions of the drawn groups",
        "proved groups of at most 4 landmarks",
        "true path",
    ] {
        assert!(
            legend.iter().any(|l| l.contains(want)),
            "no \"{want}\" in the legend {legend:?}"
        );
    }
    assert_eq!(data["unit"], "m");
    assert_eq!(data["xLabel"], "x (m)");
    assert_eq!(data["yLabel"], "y (m)");
    // The same legend under the canvas, for a reader.
    let html = d.js("return [...document.querySelectorAll('#rv-0 ~ .figlegend li')].map((l) => l.textContent).join('|')");
    assert_eq!(html, data["legend"]);
    // The landmark regions are thin arcs: a small share of the plot is
    // region-coloured (the page drew every group's regions, a pink block
    // over the whole plaza), and some of it is (the arcs are there).
    let red = region_coloured(&d, "rv-0");
    eprintln!("BROWSER plaza region-coloured pixels: {red}");
    assert!(
        red["share"].as_f64().unwrap() < 0.05,
        "the landmark regions flood the plaza: {red}"
    );
    assert!(
        red["pixels"].as_f64().unwrap() > 20.0,
        "no landmark region drawn: {red}"
    );
    // The check can fail: the regions' pixels go with their layer.
    d.click("#rv-legend input[data-layer='regions']");
    let hidden = region_coloured(&d, "rv-0");
    assert!(
        hidden["pixels"].as_f64().unwrap() + 20.0 <= red["pixels"].as_f64().unwrap(),
        "as many red-tinted pixels without the regions: {hidden} (with: {red})"
    );
    d.click("#rv-legend input[data-layer='regions']");
    d.screenshot("missions-plaza-figure");

    // The progress bar over the job: never back, and not stuck near the
    // end for most of it (it reached 97 % at round 9 of 52 and stayed).
    let bar = d.js("return window.bar");
    let bar: Vec<(f64, f64)> = bar
        .as_array()
        .unwrap()
        .iter()
        .map(|p| (p[0].as_f64().unwrap(), p[1].as_f64().unwrap()))
        .collect();
    check_bar(&bar);

    // A result file uploaded as a mission: refused, saying it is a result,
    // in the error colour, the bar cleared.
    let result_file = s.dir.join("result.json");
    let job = d.js("return JSON.parse(localStorage.getItem('nvector.jobs'))[0].id");
    let text = d.js_async(&format!(
        "const done = arguments[arguments.length - 1]; fetch('/api/v1/jobs/{}/result').then((r) => r.text()).then(done, (e) => done(String(e)));",
        job.as_str().unwrap()
    ));
    std::fs::write(&result_file, text.as_str().unwrap()).unwrap();
    choose(&d, &result_file);
    d.click("#ms-submit");
    let line = d.wait(
        "const s = document.getElementById('ms-state'); return s.classList.contains('error') && s.textContent",
        Duration::from_secs(30),
    );
    let st = state_line(&d);
    assert!(
        line.as_str().unwrap().contains("nvector-result/1")
            && line.as_str().unwrap().contains("not a mission"),
        "{st}"
    );
    assert_eq!(
        st["progress"], 0.0,
        "the bar still shows the last job: {st}"
    );
    assert_ne!(
        st["colour"], "rgb(34, 34, 34)",
        "an error in the text's colour: {st}"
    );
    assert_eq!(
        d.js("return document.querySelectorAll('#ms-missions li[data-id]').length"),
        1,
        "the result file was stored as a mission"
    );
    d.screenshot("missions-result-refused");

    // The missions list: id, date and size on each line; two uploads of
    // one file told apart by their ids.
    choose(&d, &plaza);
    d.click("#ms-submit");
    d.wait(
        "return document.querySelectorAll('#ms-missions li[data-id]').length === 2",
        Duration::from_secs(60),
    );
    let lines = d.js("return [...document.querySelectorAll('#ms-missions li[data-id]')].map((l) => [l.dataset.id, l.textContent])");
    let bytes = std::fs::metadata(&plaza).unwrap().len() as f64;
    for l in lines.as_array().unwrap() {
        let (id, text) = (l[0].as_str().unwrap(), l[1].as_str().unwrap());
        assert!(text.contains(&id[..10]), "no id in {text}");
        let year = text.contains("202") && text.contains(':');
        assert!(year, "no date in {text}");
        let mb = format!("{:.1} MB", bytes / 1024.0 / 1024.0);
        let kb = format!("{:.1} kB", bytes / 1024.0);
        assert!(
            text.contains(" MB") || text.contains(" kB"),
            "no size in {text} (the file is {mb} / {kb} as written by import)"
        );
    }
    assert_ne!(lines[0][1], lines[1][1], "two identical lines: {lines}");
    // The second run is not needed: cancelled (the bar cleared, no error).
    d.wait(
        "return !document.getElementById('ms-cancel').disabled",
        Duration::from_secs(60),
    );
    d.click("#ms-cancel");
    let end = d.wait(
        "const s = document.getElementById('rv-summary').dataset.state; return s !== 'queued' && s !== 'running' && s",
        Duration::from_secs(300),
    );
    let st = state_line(&d);
    assert!(end == "cancelled" || end == "drawn", "{end}: {st}");
    assert_eq!(st["error"], false, "{st}");
}

/// The bar's samples (time in ms, value) over a job: never decreasing, and
/// at half the time between its first move and its end, at most 0.75 (the
/// share of the work, estimated: on CMU Plaza 1 with the old estimate it
/// was 0.97 from round 9 of 52 on, so 0.97 or more at half the time).
fn check_bar(bar: &[(f64, f64)]) {
    let moved: Vec<&(f64, f64)> = bar.iter().filter(|p| p.1 > 0.0).collect();
    assert!(moved.len() > 10, "too few samples of the bar: {bar:?}");
    for w in moved.windows(2) {
        assert!(w[1].1 >= w[0].1, "the bar went back: {w:?}");
    }
    let (t0, t1) = (
        moved[0].0,
        moved
            .iter()
            .find(|p| p.1 >= 1.0)
            .map_or(moved[moved.len() - 1].0, |p| p.0),
    );
    let half = moved.iter().rfind(|p| p.0 <= (t0 + t1) / 2.0).unwrap();
    let summary: Vec<String> = (0..=10)
        .map(|k| {
            let t = t0 + (t1 - t0) * k as f64 / 10.0;
            let v = moved.iter().rfind(|p| p.0 <= t).map_or(0.0, |p| p.1);
            format!("{:.2}", v)
        })
        .collect();
    eprintln!(
        "BROWSER plaza progress at tenths of the job's time ({:.1} s): {}",
        (t1 - t0) / 1e3,
        summary.join(" ")
    );
    assert!(
        half.1 <= 0.75,
        "the bar showed {} at half the job's time: {summary:?}",
        half.1
    );
}

/// No page asks another origin for anything: the page's tabs and the API
/// reference, each loaded and used, with the browser's resource timing
/// (every request made) and its console (requests refused by a policy,
/// failed loads) read after each.
#[test]
fn no_page_asks_another_origin() {
    let Some(d) = Driver::start() else { return };
    let s = page_server();
    let base = format!("http://{}", s.addr);
    let _ = d.console();
    let foreign = "return performance.getEntriesByType('resource').map((e) => e.name).concat(performance.getEntriesByType('navigation').map((e) => e.name)).filter((u) => !u.startsWith(location.origin) && !u.startsWith('data:') && !u.startsWith('blob:'))";
    let pages = [
        ("/", "return document.getElementById('wasm-status').dataset.ready === 'true'"),
        ("/?tab=slam&demo=1", "return document.getElementById('sl-summary').dataset.nvectorDiameter"),
        ("/?tab=missions", "return document.getElementById('wasm-status').dataset.ready === 'true' && document.querySelector('#ms-missions li') !== null"),
        ("/?tab=radar", "return document.getElementById('rd-summary').dataset.groups || document.getElementById('rd-summary').dataset.error"),
        ("/api/docs", "const h = document.querySelector('h1'); return h && h.textContent.includes('nvector')"),
    ];
    let mut seen = Vec::new();
    for (path, ready) in pages {
        d.goto(&format!("{base}{path}"));
        d.wait(ready, Duration::from_secs(120));
        // Let late requests (images of a rendered menu) go out.
        std::thread::sleep(Duration::from_millis(1500));
        let other = d.js(foreign);
        assert_eq!(other, json!([]), "{path} asked another origin: {other}");
        let console = d.console();
        let refused: Vec<&(String, String)> = console
            .iter()
            .filter(|(level, m)| {
                level == "SEVERE" || m.contains("Refused to") || m.contains("net::ERR")
            })
            .collect();
        assert!(
            refused.is_empty(),
            "{path}: errors in the console (a request to another origin refused?): {refused:?}"
        );
        seen.push(path);
    }
    assert_eq!(seen.len(), 5);
}
