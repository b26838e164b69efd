//! The page in a real headless Chromium driven through chromedriver
//! (WebDriver over HTTP on loopback), against the real `nvector serve` on a
//! fresh SQLite database: the playground's Figure 8 preset, the offline SLAM
//! demo (range + bearing, and the range-only preset with the `shapes`
//! contractor), the legend's toggles, a mission uploaded through the page and
//! drawn, the CMU Plaza 1 result drawn (the truth path visible in its
//! pixels) and its redraw timed, the legends and axes of every canvas, the
//! favicon and the API reference link, and the browser's results compared
//! bit for bit with the native binary. (The shapes' outlines are computed
//! by core, core/src/outline.rs, whose property tests plant true points in
//! them.)
//! Screenshots go to target/screenshots/. Under CI (CI=true) a missing browser is a failure;
//! elsewhere the test is skipped, saying so loudly.

use nvector_tests as common;

use common::chromium::{canvas_data, fetched, legend_and_axes, page_server, painted, Driver};
use common::Server;
use serde_json::{json, Value};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

fn result_without_time(mut v: Value) -> Value {
    v["metrics"]["elapsed_ms"] = json!(0);
    v
}

/// When the test started, for [`lap`].
static STARTED: std::sync::OnceLock<Instant> = std::sync::OnceLock::new();

/// Prints the time since the test started and the phase just finished
/// (`--nocapture`): where a cold CI run spends its minutes. Reports only.
fn lap(phase: &str) {
    let t = STARTED.get_or_init(Instant::now).elapsed().as_secs_f64();
    eprintln!("browser: {t:7.1} s {phase}");
}

#[test]
fn the_page_in_headless_chromium() {
    lap("start");
    let Some(d) = Driver::start() else { return };
    lap("chromedriver and Chromium started (a session)");
    let s = page_server();
    lap("page server started");
    let base = format!("http://{}", s.addr);

    // Playground: the Figure 8 preset with the per-axis contractor gives the
    // groups derived by hand in core/tests/nvector/examples.rs.
    d.goto(&format!("{base}/?preset=fig8"));
    d.wait(
        "return document.getElementById('wasm-status').dataset.ready === 'true'",
        Duration::from_secs(30),
    );
    // The playground's module alone: the figures module (the outlines) and
    // the SLAM demo's modules (the solver, the simulators) are fetched when
    // a tab needs them (web/www/wasm.js).
    for module in ["pkg-figures", "pkg-slam", "pkg-sim"] {
        assert_eq!(
            d.js(&fetched(module)),
            0,
            "{module} loaded with the playground"
        );
    }
    d.js("const m = document.getElementById('pg-mode'); m.value = 'nvalue'; m.dispatchEvent(new Event('change')); return 1;");
    let groups = d.wait(
        "return document.getElementById('pg-summary').dataset.groups",
        Duration::from_secs(10),
    );
    assert_eq!(groups, "[[0,1],[2],[3,4],[5],[6]]");
    lap("playground loaded and contracted");
    d.screenshot("playground-fig8");
    // The playground's legend and axes (drawn in the canvas; the canvas's
    // dataset says what), and the page's header: the API reference link
    // and a favicon that is served.
    legend_and_axes(
        &d,
        "pg-canvas",
        &[
            "input box",
            "contracted, in a group",
            "alone (singleton)",
            "kernel on an axis",
        ],
        "",
    );
    assert_eq!(
        d.js("return document.querySelector('header a[href=\"/api/docs\"]')?.textContent"),
        "API reference"
    );
    let icons = d.js_async(
        "const done = arguments[arguments.length - 1]; \
         Promise.all(['/favicon.ico', '/favicon.svg'].map((u) => fetch(u).then((r) => r.status + ' ' + r.headers.get('content-type')))).then(done, (e) => done(String(e)));",
    );
    let icons: Vec<&str> = icons
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_str().unwrap())
        .collect();
    assert!(icons[0].starts_with("200 image/"), "{icons:?}");
    assert!(icons[1].starts_with("200 image/svg+xml"), "{icons:?}");
    // Redraw time with 200 boxes (measured in the page): the median of 7
    // batch means of 20 contractions.
    let ms = d.js(
        "const nv = window.nvectorHandle; const boxes = []; \
         for (let i = 0; i < 200; i++) { const c = (i % 20) * 10, w = 1 + (i * 7) % 5; boxes.push([[c - w, c + w], [(i % 7) - w, (i % 7) + w]]); } \
         const req = JSON.stringify({format: 'nvector-contract/1', n: 20, contractor: 'best', boxes}); \
         nv.contract(req); const means = []; \
         for (let b = 0; b < 7; b++) { const t = performance.now(); for (let r = 0; r < 20; r++) nv.contract(req); means.push((performance.now() - t) / 20); } \
         means.sort((x, y) => x - y); return means[3];",
    );
    eprintln!("BENCH browser playground_200_boxes_ms {ms}");
    lap("playground checked");

    // The API reference renders: Redoc, served by the service itself, draws
    // the OpenAPI document's title and its operations. Its policy lets the
    // browser fetch nothing from another origin (Redoc's maker's logo is
    // served as an inline `data:` image: no request).
    d.goto(&format!("{base}/api/docs"));
    let title = d.wait(
        "const h = document.querySelector('h1'); return h && h.textContent.includes('nvector') && h.textContent",
        Duration::from_secs(30),
    );
    assert!(title.as_str().unwrap().starts_with("nvector"), "{title}");
    let api = d.js_async(
        "const done = arguments[arguments.length - 1]; \
         const text = document.body.innerText; \
         const foreign = [...document.querySelectorAll('img, script, link')].map((e) => e.src || e.href || '').filter((u) => u && !u.startsWith(location.origin) && !u.startsWith('data:')); \
         fetch(location.href).then((r) => done([text.includes('/api/v1/jobs'), text.includes('nvector-mission/1'), foreign, r.headers.get('content-security-policy')]), (e) => done(String(e)));",
    );
    assert_eq!(api[0], true, "the jobs endpoint is drawn: {api}");
    assert_eq!(api[1], true, "the mission schema is drawn: {api}");
    assert_eq!(
        api[2],
        json!([]),
        "nothing from another origin in the page: {api}"
    );
    assert!(
        api[3]
            .as_str()
            .unwrap_or("")
            .starts_with("default-src 'self';"),
        "the page's policy keeps it to its origin: {api}"
    );
    d.screenshot("api-docs");

    lap("API reference");
    // SLAM demo, offline in WASM.
    d.goto(&format!("{base}/?tab=slam&demo=1"));
    let nvd = d.wait(
        "return document.getElementById('sl-summary').dataset.nvectorDiameter",
        Duration::from_secs(120),
    );
    // The figures module on the page (the outlines), the solver's and the
    // simulators' in the demo's worker (web/www/slam-worker.js).
    assert!(
        d.js(&fetched("pkg-figures")).as_u64().unwrap() >= 1,
        "pkg-figures was not fetched by the SLAM demo"
    );
    for module in ["pkg-slam", "pkg-sim"] {
        assert!(
            d.js(&format!("return window.nvectorPage.sl.worker.filter((u) => u.includes('/{module}/')).length"))
                .as_u64()
                .unwrap()
                >= 1,
            "{module} was not fetched by the SLAM demo's worker"
        );
    }
    let basic: f64 = d
        .js("return document.getElementById('sl-summary').dataset.basicDiameter")
        .as_str()
        .unwrap()
        .parse()
        .unwrap();
    let nvd: f64 = nvd.as_str().unwrap().parse().unwrap();
    assert!(nvd < basic, "nvector {nvd} should beat basic {basic}");
    assert_eq!(
        d.js("return document.getElementById('sl-summary').dataset.truthInside"),
        "true"
    );
    d.screenshot("slam-demo");
    // The demo with bearings draws sectors, one shape per detection.
    let (shapes, sectors, detections) = (
        canvas_data(&d, "sl-nv", "shapes"),
        canvas_data(&d, "sl-nv", "sectors"),
        d.js("return Number(document.getElementById('sl-summary').dataset.detections)"),
    );
    assert!(
        shapes > 0.0 && sectors == shapes,
        "shapes {shapes}, sectors {sectors}"
    );
    assert_eq!(Some(shapes), detections.as_f64());
    // Each panel has axes in metres and a legend naming what it shows (both
    // at one scale: tests/browser_slam.rs).
    let slam_legend = ["truth path", "trajectory boxes", "detection shapes"];
    legend_and_axes(&d, "sl-basic", &slam_legend, "m");
    legend_and_axes(&d, "sl-nv", &slam_legend, "m");
    let nv_legend = d.js("return document.getElementById('sl-nv').dataset.legend");
    assert!(
        nv_legend.as_str().unwrap().contains("proved groups ("),
        "{nv_legend}"
    );
    assert!(d
        .js("return document.getElementById('sl-summary').textContent")
        .as_str()
        .unwrap()
        .contains("proved groups of at most 4 landmarks"));

    lap("SLAM demo");
    range_only_preset(&d, &base);
    lap("range-only preset");
    woods_preset(&d, &base);
    lap("woods preset");

    // Same bits as native: the paper scenario simulated and run in WASM
    // equals the native binary's output.
    let out_dir = s.dir.clone();
    let mission_path = out_dir.join("paper.json");
    let st = common::nvector()
        .args([
            "simulate",
            "--scenario",
            "paper",
            "--seed",
            "7",
            "--steps",
            "4000",
            "--out",
        ])
        .arg(&mission_path)
        .status()
        .unwrap();
    assert!(st.success());
    lap("native simulate (paper, 4000 steps)");
    let native_result = out_dir.join("native.json");
    let t0 = Instant::now();
    let st = common::nvector()
        .arg("run")
        .arg(&mission_path)
        .args(["--contractor", "projection", "--out"])
        .arg(&native_result)
        .status()
        .unwrap();
    let native_ms = t0.elapsed().as_secs_f64() * 1e3;
    lap("native run (projection)");
    assert!(st.success());
    let mission_text = std::fs::read_to_string(&mission_path).unwrap();
    // The demo solves in its worker; the page loads the same two modules
    // for this comparison (window.loadSlam).
    let loaded = d.js_async(
        "const done = arguments[arguments.length - 1]; window.loadSlam().then(() => done('loaded'), (e) => done(String(e)));",
    );
    assert_eq!(loaded, "loaded");
    let wasm_mission = d.js("return window.nvectorHandle.simulate(JSON.stringify({scenario: 'paper', seed: 7, steps: 4000}))");
    assert_eq!(
        serde_json::from_str::<Value>(wasm_mission.as_str().unwrap()).unwrap(),
        serde_json::from_str::<Value>(&mission_text).unwrap(),
        "simulation differs between wasm and native"
    );
    let script = format!(
        "const t = performance.now(); const r = window.nvectorHandle.run({}, 'projection', () => {{}}); return [r, performance.now() - t];",
        serde_json::to_string(&mission_text).unwrap()
    );
    let got = d.js(&script);
    let wasm_result: Value = serde_json::from_str(got[0].as_str().unwrap()).unwrap();
    let native: Value =
        serde_json::from_str(&std::fs::read_to_string(&native_result).unwrap()).unwrap();
    assert_eq!(
        result_without_time(wasm_result),
        result_without_time(native),
        "wasm and native results differ"
    );
    eprintln!(
        "BENCH browser paper_4000_projection_ms {} native_process_ms {native_ms:.1}",
        got[1]
    );
    lap("same bits in wasm");

    // Missions: upload a simulated mission through the page, follow the job,
    // and see the result drawn.
    let upload: PathBuf = out_dir.join("upload.json");
    let st = common::nvector()
        .args([
            "simulate",
            "--scenario",
            "paper",
            "--seed",
            "2",
            "--steps",
            "3000",
            "--false-detections",
            "2",
            "--out",
        ])
        .arg(&upload)
        .status()
        .unwrap();
    assert!(st.success());
    d.goto(&format!("{base}/?tab=missions"));
    d.wait(
        "return document.getElementById('wasm-status').dataset.ready === 'true'",
        Duration::from_secs(30),
    );
    let file = d.element("#ms-file");
    d.cmd(
        "POST",
        &format!("/element/{file}/value"),
        Some(json!({"text": upload.to_str().unwrap()})),
    );
    d.click("#ms-submit");
    let state = d.wait(
        "const s = document.getElementById('rv-summary').dataset.state; return (s === 'drawn' || s === 'error' || s === 'failed') && s",
        Duration::from_secs(120),
    );
    assert_eq!(
        state,
        "drawn",
        "{}",
        d.js("return document.getElementById('ms-state').textContent")
    );
    // The missions tab draws with the figures module alone (the outlines),
    // without the SLAM module's solver.
    assert!(
        d.js(&fetched("pkg-figures")).as_u64().unwrap() >= 1,
        "the figures module was not fetched"
    );
    for module in ["pkg-slam", "pkg-sim"] {
        assert_eq!(
            d.js(&fetched(module)),
            0,
            "the missions tab fetched the SLAM demo's {module}"
        );
    }
    assert_eq!(
        d.js("return document.getElementById('rv-summary').dataset.trajectory"),
        "3001"
    );
    assert_eq!(
        d.js("return document.getElementById('rv-summary').dataset.truthInside"),
        "true"
    );
    // The mission has 2 planted phantoms (`max_outliers` 2): the summary
    // says both were proved false (metrics.false_detections) and nothing
    // is left open.
    let summary = d.js("return document.getElementById('rv-summary').textContent");
    assert!(
        summary
            .as_str()
            .unwrap()
            .contains("(max_outliers 2: 2 proved false)"),
        "{summary}"
    );
    d.screenshot("missions-result");

    // Basic model against nvector, side by side: run the stored mission
    // again with `none` from the missions list, no second upload.
    d.js("const s = document.getElementById('ms-mode'); s.value = 'none'; return s.value");
    d.wait(
        "return document.querySelector('#ms-missions li[data-id] button.run') !== null",
        Duration::from_secs(30),
    );
    d.click("#ms-missions li[data-id] button.run");
    let shown = d.wait(
        "const s = document.getElementById('rv-summary').dataset; return s.state === 'drawn' && s.shown === '2' && s.contractors",
        Duration::from_secs(120),
    );
    assert_eq!(shown, "none,best", "the newest result is on the left");
    let diameters: Vec<f64> = d
        .js("return document.getElementById('rv-summary').dataset.diameters")
        .as_str()
        .unwrap()
        .split(',')
        .map(|x| x.parse().unwrap())
        .collect();
    assert!(
        diameters[0] > 2.0 * diameters[1],
        "the basic model should be much wider than nvector: {diameters:?}"
    );
    assert!(d
        .js("return document.getElementById('rv-cap-1').textContent")
        .as_str()
        .unwrap()
        .contains("best"));
    d.screenshot("missions-side-by-side");
    lap("missions uploaded, run and drawn");

    cmu_plaza_drawn(&d, &s);
    lap("CMU Plaza imported, run and drawn");

    // A reload still lists both jobs (remembered by the browser) and shows
    // the older one again on request.
    d.goto(&format!("{base}/?tab=missions"));
    let states = d.wait(
        "const l = [...document.querySelectorAll('#ms-jobs li')].map(li => li.dataset.state); return l.length === 3 && l.join(',')",
        Duration::from_secs(30),
    );
    assert_eq!(states, "done,done,done");
    d.click("#ms-jobs li:last-child button.show");
    let shown = d.wait(
        "const s = document.getElementById('rv-summary').dataset; return s.state === 'drawn' && s.contractors",
        Duration::from_secs(30),
    );
    assert_eq!(shown, "best", "the older job of the list is the best run");

    // The radar demo (its own wasm module, loaded with its tab only).
    radar_demo(&d, &base);
    lap("radar demo");

    // A narrow window (a phone held upright): every view fits its width,
    // nothing scrolls sideways.
    d.cmd(
        "POST",
        "/window/rect",
        Some(json!({"width": 380, "height": 800})),
    );
    for tab in ["playground", "slam", "missions"] {
        d.goto(&format!("{base}/?tab={tab}"));
        d.wait(
            "return document.getElementById('wasm-status').dataset.ready === 'true'",
            Duration::from_secs(30),
        );
        let widths = d.js(
            "return [document.documentElement.scrollWidth, window.innerWidth, \
             Math.max(...[...document.querySelectorAll('canvas')].filter(c => c.offsetParent).map(c => c.getBoundingClientRect().right), 0)]",
        );
        let w: Vec<f64> = widths
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect();
        assert!(
            w[0] <= w[1] + 1.0 && w[2] <= w[1] + 1.0,
            "{tab} overflows a narrow window: scrollWidth, innerWidth, canvas right = {w:?}"
        );
        d.screenshot(&format!("narrow-{tab}"));
    }
    lap("narrow window, done");
}

/// The SLAM demo's range-only preset (the paper's P'': ranges and a rough
/// region, no bearing) runs basic against `shapes` in WASM and proves
/// groups; the legend's boxes hide and show the layers.
fn range_only_preset(d: &Driver, base: &str) {
    d.goto(&format!("{base}/?tab=slam&demo=range-only"));
    let summary = d.wait(
        "const s = document.getElementById('sl-summary'); return (s.dataset.recall || s.dataset.error) && s.textContent",
        Duration::from_secs(180),
    );
    let data = d.js("return {...document.getElementById('sl-summary').dataset}");
    assert_eq!(data["error"], "", "{summary}");
    assert_eq!(data["contractor"], "shapes", "{summary}");
    assert_eq!(data["rangeOnly"], "true", "{summary}");
    assert_eq!(data["truthInside"], "true", "{summary}");
    assert_eq!(data["errors"], "0", "{summary}");
    let recall: f64 = data["recall"].as_str().unwrap().parse().unwrap();
    assert!(recall > 0.0, "no proved group: {summary}");
    let basic: f64 = data["basicDiameter"].as_str().unwrap().parse().unwrap();
    let shapes_d: f64 = data["nvectorDiameter"].as_str().unwrap().parse().unwrap();
    assert!(shapes_d < basic, "{summary}");
    eprintln!("BROWSER range-only preset: {summary}");
    // What the page writes matches the figures: the summary shows the recall.
    assert!(
        summary
            .as_str()
            .unwrap()
            .contains(&format!("recall {recall:.2}")),
        "{summary}"
    );
    // Range only: annuli, no sectors, one per detection.
    let n = data["detections"].as_str().unwrap().parse::<f64>().unwrap();
    assert_eq!(canvas_data(d, "sl-nv", "shapes"), n);
    assert_eq!(canvas_data(d, "sl-nv", "sectors"), 0.0);
    let regions = canvas_data(d, "sl-nv", "regions");
    d.screenshot("slam-range-only-shapes");

    // The toggles: each hides its layer (the canvas says what it drew, and
    // fewer pixels are painted), ticking them again restores the picture.
    let layer = |k: &str| format!("#sl-legend input[data-layer='{k}']");
    let all = painted(d, "sl-nv");
    let boxes = canvas_data(d, "sl-nv", "boxes");
    assert!(boxes > 0.0);
    d.click(&layer("shapes"));
    assert_eq!(canvas_data(d, "sl-nv", "shapes"), 0.0);
    let without_shapes = painted(d, "sl-nv");
    assert!(
        without_shapes < all,
        "hiding the shapes painted {without_shapes} pixels, {all} with them"
    );
    d.screenshot("slam-range-only-no-shapes");
    d.click(&layer("boxes"));
    assert_eq!(canvas_data(d, "sl-nv", "boxes"), 0.0);
    assert!(painted(d, "sl-nv") < without_shapes);
    if regions > 0.0 {
        d.click(&layer("regions"));
        assert_eq!(canvas_data(d, "sl-nv", "regions"), 0.0);
        d.click(&layer("regions"));
        assert_eq!(canvas_data(d, "sl-nv", "regions"), regions);
    }
    d.click(&layer("shapes"));
    d.click(&layer("boxes"));
    assert_eq!(canvas_data(d, "sl-nv", "shapes"), n);
    assert_eq!(canvas_data(d, "sl-nv", "boxes"), boxes);
    assert_eq!(painted(d, "sl-nv"), all, "the picture is back");
    // Only the shapes, to see them alone.
    d.click(&layer("boxes"));
    d.screenshot("slam-range-only-shapes-alone");
    d.click(&layer("boxes"));
}

/// The SLAM demo's woods preset (an odometry2d robot among
/// identical landmarks, with scans) simulated by core's woods generator and
/// run in WASM, basic against best (in the demo's worker; the page
/// answering while it solves is tests/browser_slam.rs's); both panels draw the headings as
/// wedges, with "heading (interval)" and "true heading" in the legend, and
/// the headings' box hides and shows them.
fn woods_preset(d: &Driver, base: &str) {
    d.goto(&format!("{base}/?tab=slam&demo=woods"));
    let summary = d.wait(
        "const s = document.getElementById('sl-summary'); return (s.dataset.error || (s.dataset.scenario === 'woods' && s.dataset.recall)) && s.textContent",
        Duration::from_secs(300),
    );
    let data = d.js("return {...document.getElementById('sl-summary').dataset}");
    assert_eq!(data["error"], "", "{summary}");
    assert_eq!(data["model"], "odometry2d", "{summary}");
    assert_eq!(data["contractor"], "best", "{summary}");
    assert_eq!(data["status"], "consistent", "{summary}");
    assert_eq!(data["truthInside"], "true", "{summary}");
    assert_eq!(data["errors"], "0", "{summary}");
    let width: f64 = data["maxHeadingWidth"].as_str().unwrap().parse().unwrap();
    assert!(width > 0.0 && width.is_finite(), "{summary}");
    eprintln!("BROWSER woods preset: {summary}");
    for canvas in ["sl-basic", "sl-nv"] {
        let n = canvas_data(d, canvas, "headings");
        assert!((30.0..=49.0).contains(&n), "{canvas}: {n} heading wedges");
        legend_and_axes(
            d,
            canvas,
            &["heading (interval)", "true heading", "truth path"],
            "m",
        );
    }
    d.screenshot("slam-woods");
    let toggle = "#sl-legend input[data-layer='headings']";
    // Pixels of the wedges' outline colour (#e67e22 = 230, 126, 34, within
    // 12 per channel: not the groups' palette orange #f58231 = 245, 130,
    // 49) in the panel.
    let orange = || {
        d.js("const c = document.getElementById('sl-nv'); const px = c.getContext('2d').getImageData(0, 0, c.width, c.height).data; \
              let n = 0; for (let i = 0; i < px.length; i += 4) if (Math.abs(px[i] - 230) <= 12 && Math.abs(px[i + 1] - 126) <= 12 && Math.abs(px[i + 2] - 34) <= 12) n++; return n;")
            .as_f64()
            .unwrap()
    };
    let (all, n, lit) = (
        painted(d, "sl-nv"),
        canvas_data(d, "sl-nv", "headings"),
        orange(),
    );
    assert!(lit > 50.0, "{lit} orange pixels with the headings drawn");
    d.click(toggle);
    assert_eq!(canvas_data(d, "sl-nv", "headings"), 0.0);
    let legend = d.js("return document.getElementById('sl-nv').dataset.legend");
    assert!(
        !legend.as_str().unwrap().contains("heading (interval)"),
        "{legend}"
    );
    // Hiding them takes their orange away (both panels share one scale,
    // the basic model's: the wedges, 14 pixels each, overlap on a small
    // track, and the proved groups' orange outlines stay).
    let left = orange();
    assert!(
        lit - left >= 50.0,
        "hiding the headings left {left} orange pixels of {lit}"
    );
    d.click(toggle);
    assert_eq!(canvas_data(d, "sl-nv", "headings"), n);
    assert_eq!(painted(d, "sl-nv"), all, "the picture is back");
}

/// CMU Plaza 1 (3529 ranges, ids hidden) uploaded through the page, run
/// with `shapes` by the service and drawn with its shapes; the redraw is
/// timed in the page (median of 3 batch means of 2 redraws, each drawing
/// read back so that the time includes the rasterisation): a full redraw
/// (the view moved: everything drawn again), a frame while panning (the
/// previous picture moved), a step of the time slider, and the full
/// redraw without shapes.
fn cmu_plaza_drawn(d: &Driver, s: &Server) {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("../data/cmu-plaza1");
    assert!(
        data.join("Plaza1_DR.txt").exists(),
        "the CMU Plaza 1 data must be at {} (data/ of the repository)",
        data.display()
    );
    let cmu = s.dir.join("cmu.json");
    let st = common::nvector()
        .args(["import", "--cmu-plaza"])
        .arg(&data)
        .arg("--out")
        .arg(&cmu)
        .status()
        .unwrap();
    assert!(st.success());
    lap("CMU Plaza imported (nvector import)");
    d.js("const s = document.getElementById('ms-mode'); s.value = 'shapes'; return s.value");
    let file = d.element("#ms-file");
    d.cmd(
        "POST",
        &format!("/element/{file}/value"),
        Some(json!({"text": cmu.to_str().unwrap()})),
    );
    d.click("#ms-submit");
    let shown = d.wait(
        "const s = document.getElementById('rv-summary').dataset; return s.state === 'error' || s.state === 'failed' || (s.state === 'drawn' && s.detections === '3529' && s.contractors)",
        Duration::from_secs(180),
    );
    lap("CMU Plaza run by the service (shapes) and drawn");
    assert_eq!(
        shown,
        "shapes,none",
        "{}",
        d.js("return document.getElementById('ms-state').textContent")
    );
    assert_eq!(
        d.js("return document.getElementById('rv-summary').dataset.truthInside"),
        "true"
    );
    // The summary counts proved groups, not landmarks.
    let summary = d.js("return document.getElementById('rv-summary').textContent");
    assert!(
        summary
            .as_str()
            .unwrap()
            .contains("proved groups of at most 4 landmarks"),
        "{summary}"
    );
    // Legend (core's figure's labels, as the CLI's) and axes in metres;
    // the panels each fitted to their own result (Plaza is hundreds of
    // metres, the simulated mission beside it tens).
    legend_and_axes(
        d,
        "rv-0",
        &["true path", "trajectory: ", "landmark regions"],
        "m",
    );
    assert!(d
        .js("return document.getElementById('rv-0').dataset.legend")
        .as_str()
        .unwrap()
        .contains("proved groups of at most 4 landmarks"));
    legend_and_axes(d, "rv-1", &["true path", "trajectory: "], "m");
    let scales = d.js("return window.nvectorPage.shown.map((s) => s.view.scale)");
    assert_ne!(scales[0], scales[1], "both panels share one zoom: {scales}");
    // Thousands of shapes are not drawn by default (they washed the picture
    // purple and grey); the proved groups are outlines, nested ones left
    // out: a handful, not 83.
    assert_eq!(canvas_data(d, "rv-0", "shapes"), 0.0);
    let groups = canvas_data(d, "rv-0", "groups");
    assert!((1.0..=12.0).contains(&groups), "{groups} group outlines");
    eprintln!(
        "BROWSER cmu plaza: {groups} group outlines, landmark regions of {} boxes",
        canvas_data(d, "rv-0", "regions")
    );
    d.screenshot("missions-cmu-plaza-shapes");

    // What a person sees: the truth path (black over a white halo) is
    // visible along its length, no colour floods the picture, and the
    // basic model's panel is not a grey wash.
    let truth = truth_visible(d, 0);
    eprintln!("BROWSER cmu plaza truth path: {truth}");
    assert!(
        truth["seen"].as_f64().unwrap() >= 0.9 * truth["samples"].as_f64().unwrap()
            && truth["samples"].as_f64().unwrap() > 100.0,
        "the truth path is hidden on CMU Plaza 1: {truth}"
    );
    let stats = pixel_stats(d, "rv-0");
    assert!(stats["red"].as_f64().unwrap() < 0.1, "a red flood: {stats}");
    let basic = pixel_stats(d, "rv-1");
    assert!(
        basic["grey"].as_f64().unwrap() < 0.3,
        "the `none` panel is a grey wash: {basic}"
    );
    // The check can fail: with the truth layer hidden, the path's pixels
    // are not dark any more.
    let truth_box = "#rv-legend input[data-layer='truth']";
    d.click(truth_box);
    let hidden = truth_visible(d, 0);
    assert!(
        hidden["seen"].as_f64().unwrap() < 0.2 * hidden["samples"].as_f64().unwrap(),
        "dark pixels along the truth path without it: {hidden}"
    );
    d.click(truth_box);

    // The timings below draw every shape, the unmatched ones too.
    let unmatched_box = "#rv-legend input[data-layer='unmatched']";
    d.click("#rv-legend input[data-layer='shapes']");
    // The unmatched detections' shapes are shown by default.
    assert_eq!(
        d.js(&format!(
            "return document.querySelector(\"{unmatched_box}\").checked"
        )),
        true,
        "the unmatched layer is on"
    );
    assert_eq!(canvas_data(d, "rv-0", "shapes"), 3529.0);
    d.screenshot("missions-cmu-plaza-all-shapes");
    let t = d.js(
        "const p = window.nvectorPage, s = p.shown[0], c = document.getElementById('rv-0'), ctx = c.getContext('2d'); \
         const batch = (f) => { const means = []; for (let b = 0; b < 3; b++) { const t = performance.now(); \
           for (let r = 0; r < 2; r++) { f(); ctx.getImageData(0, 0, 1, 1); } means.push((performance.now() - t) / 2); } \
           means.sort((x, y) => x - y); return means[1]; }; \
         const full = batch(() => { s.view.pan(1, 0); p.redrawResults(false); }); \
         const moving = batch(() => { s.view.pan(1, 0); p.redrawResults(true); }); \
         const time = document.getElementById('rv-time'); let step = Number(time.max); \
         const slider = batch(() => { time.value = String(step -= 7); p.redrawResults(false); }); time.value = time.max; \
         const box = document.querySelector(\"#rv-legend input[data-layer='shapes']\"); box.click(); \
         const bare = batch(() => { s.view.pan(1, 0); p.redrawResults(false); }); box.click(); \
         p.redrawResults(false); \
         return { full, moving, slider, bare, shapes: Number(c.dataset.shapes), regions: Number(c.dataset.regions) };",
    );
    assert_eq!(t["shapes"], 3529, "{t}");
    eprintln!(
        "BENCH browser cmu_plaza_redraw_ms full {} moving {} time_slider {} without_shapes {} (shapes {}, region boxes {})",
        t["full"], t["moving"], t["slider"], t["bare"], t["shapes"], t["regions"]
    );
}

/// Samples the truth path of the result shown in panel `k` (every 10th
/// position in view, away from the axis labels and the legend) and counts
/// those with a dark pixel (the truth colour) within one pixel.
fn truth_visible(d: &Driver, k: usize) -> Value {
    d.js(&format!(
        "const s = window.nvectorPage.shown[{k}], c = document.getElementById('rv-{k}'), w = c.width, h = c.height; \
         const px = c.getContext('2d').getImageData(0, 0, w, h).data; \
         const lb = (c.dataset.legendBox || '0,0,0,0').split(',').map(Number); \
         let samples = 0, seen = 0; const pos = s.mission.truth.positions; \
         for (let i = 0; i < pos.length; i += 10) {{ const p = pos[i]; if (!p) continue; \
           const x = Math.round(s.view.tx(p[0])), y = Math.round(s.view.ty(p[1])); \
           if (x < 45 || y < 4 || x >= w - 4 || y >= h - 30) continue; \
           if (x >= lb[0] - 2 && x <= lb[0] + lb[2] + 2 && y >= lb[1] - 2 && y <= lb[1] + lb[3] + 2) continue; \
           samples++; let dark = false; \
           for (let dy = -1; dy <= 1; dy++) for (let dx = -1; dx <= 1; dx++) {{ const o = ((y + dy) * w + x + dx) * 4; \
             if (px[o + 3] > 200 && px[o] < 90 && px[o + 1] < 90 && px[o + 2] < 90) dark = true; }} \
           if (dark) seen++; }} \
         return {{ samples, seen }};"
    ))
}

/// Fractions of a canvas's pixels, as seen over the page's white, that are
/// strongly red, or grey (a wash: painted, r = g = b within 6, below 250).
fn pixel_stats(d: &Driver, canvas: &str) -> Value {
    d.js(&format!(
        "const c = document.getElementById('{canvas}'), px = c.getContext('2d').getImageData(0, 0, c.width, c.height).data; \
         let red = 0, grey = 0; const n = px.length / 4; \
         for (let i = 0; i < px.length; i += 4) {{ const a = px[i + 3] / 255; if (!a) continue; \
           const [r, g, b] = [0, 1, 2].map((k) => px[i + k] * a + 255 * (1 - a)); \
           if (r > 150 && g < 90 && b < 90) red++; \
           if (Math.abs(r - g) < 6 && Math.abs(g - b) < 6 && r < 250) grey++; }} \
         return {{ red: red / n, grey: grey / n }};"
    ))
}

/// Whether a result box (`[[lo, hi] x3]`) holds the point `p`.
fn box_holds(b: &Value, p: &Value) -> bool {
    let bound = |v: &Value| match v {
        Value::String(s) if s == "-inf" => f64::NEG_INFINITY,
        Value::String(s) if s == "inf" => f64::INFINITY,
        v => v.as_f64().unwrap_or(f64::NAN),
    };
    b.as_array().is_some_and(|axes| {
        axes.len() == 3
            && axes.iter().zip(p.as_array().unwrap()).all(|(a, x)| {
                let x = x.as_f64().unwrap();
                bound(&a[0]) <= x && x <= bound(&a[1])
            })
    })
}

/// The radar demo: its wasm module is not loaded with the page, only when
/// its tab opens; it draws its legend and axes in metres, and its proved
/// groups match the problem's truth (checked here, not by the page): one
/// true emitter per group, whose position the group's box holds, and every
/// pulse's box holds its true position.
fn radar_demo(d: &Driver, base: &str) {
    d.goto(&format!("{base}/"));
    d.wait(
        "return document.getElementById('wasm-status').dataset.ready === 'true'",
        Duration::from_secs(30),
    );
    let loaded = "return performance.getEntriesByType('resource').filter((e) => e.name.includes('pkg-radar')).length";
    assert_eq!(d.js(loaded), 0, "the radar module loaded with the page");
    d.click("nav button[data-tab='radar']");
    let groups = d.wait(
        "const s = document.getElementById('rd-summary').dataset; return (s.groups || s.error) && [s.groups, s.error || '']",
        Duration::from_secs(120),
    );
    assert_eq!(groups[1], "", "the demo failed: {groups}");
    assert!(
        d.js(loaded).as_u64().unwrap() >= 1,
        "the radar module was not fetched"
    );
    legend_and_axes(
        d,
        "rd-canvas",
        &[
            "receivers",
            "pulse boxes",
            "emitter regions",
            "true emitters",
        ],
        "m",
    );
    d.screenshot("radar");
    // The wheel zooms in: the axes' step shrinks.
    let step = canvas_data(d, "rd-canvas", "axes.split(',')[2]");
    d.js("const c = document.getElementById('rd-canvas'); for (let i = 0; i < 8; i++) c.dispatchEvent(new WheelEvent('wheel', {deltaY: -100, clientX: c.getBoundingClientRect().left + 200, clientY: c.getBoundingClientRect().top + 200, cancelable: true})); return 1;");
    d.wait(
        &format!("return Number(document.getElementById('rd-canvas').dataset.axes.split(',')[2]) < {step}"),
        Duration::from_secs(10),
    );
    let run = d.js("return window.nvectorRadar");
    let (problem, result) = (&run["problem"], &run["result"]);
    let truth = &problem["truth"];
    for (k, b) in result["pulses"].as_array().unwrap().iter().enumerate() {
        assert!(box_holds(b, &truth["positions"][k]), "pulse {k}: {b}");
    }
    let matching = result["matching"].as_array().unwrap();
    assert!(matching.len() >= 2, "{}", result["matching"]);
    let mut grouped = 0;
    for (g, members) in matching.iter().enumerate() {
        let members = members.as_array().unwrap();
        let e = &truth["matching"][members[0].as_u64().unwrap() as usize];
        for m in members {
            assert_eq!(
                &truth["matching"][m.as_u64().unwrap() as usize],
                e,
                "group {g}"
            );
        }
        let point = &truth["emitters"][e.as_u64().unwrap() as usize];
        assert!(box_holds(&result["emitters"][g], point), "group {g}");
        grouped += members.len();
    }
    let recall = grouped as f64 / result["pulses"].as_array().unwrap().len() as f64;
    assert!(recall >= 0.8, "recall {recall}");
    assert_eq!(groups[0], json!(matching.len().to_string()));
}
