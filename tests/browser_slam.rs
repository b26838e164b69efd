//! The SLAM demo as a person uses it, in headless Chromium (the harness:
//! tests/src/chromium.rs): it solves in a Web Worker (the page answers
//! while it solves, says it is busy, and a Cancel stops the solve and
//! leaves the page usable); each preset sets every control to what it runs
//! (the controls read back against the mission and the result, and a run
//! from the controls gives the same mission again); both panels share one
//! world-to-screen transform that holds every true landmark and every
//! bounded box either panel draws; and the scale bars read round numbers
//! with units ("50 km", not "50000 m"), the radar tab's too. Screenshots
//! at 1400x900 go to target/screenshots/slam-*.png and radar-scale.png.

use nvector_tests::chromium::{canvas_data, page_server, painted, Driver};
use serde_json::{json, Value};
use std::time::Duration;

/// The page at 1400x900 (the screenshots' size), the SLAM tab open.
fn open_slam(d: &Driver, base: &str) {
    // The viewport itself at 1400x900 (a window of that size has a smaller
    // viewport): Chromium's device metrics, through chromedriver.
    d.cmd(
        "POST",
        "/goog/cdp/execute",
        Some(json!({"cmd": "Emulation.setDeviceMetricsOverride",
                    "params": {"width": 1400, "height": 900, "deviceScaleFactor": 1, "mobile": false}})),
    );
    d.goto(&format!("{base}/?tab=slam"));
    d.wait(
        "return document.getElementById('wasm-status').dataset.ready === 'true'",
        Duration::from_secs(30),
    );
}

/// A browser on the SLAM tab of the page served on loopback (None: no
/// browser here, outside CI); the server lives as long as the pair.
fn slam_page() -> Option<(Driver, nvector_tests::Server)> {
    let d = Driver::start()?;
    let s = page_server();
    open_slam(&d, &format!("http://{}", s.addr));
    Some((d, s))
}

/// Waits until the demo's run ends (`done`, `error`) and returns the
/// summary's dataset, asserting it is done.
fn finished(d: &Driver, limit: Duration) -> Value {
    d.wait(
        "const s = document.getElementById('sl-summary').dataset.state; return (s === 'done' || s === 'error') && s",
        limit,
    );
    let data = d.js("return {...document.getElementById('sl-summary').dataset, text: document.getElementById('sl-summary').textContent}");
    assert_eq!(data["state"], "done", "{data}");
    data
}

/// The demo's busy state as the page shows it: [tab's data-busy,
/// aria-busy, cancel disabled, run disabled, summary state].
const BUSY: &str = "const t = document.getElementById('slam'); \
    return [t.dataset.busy || '', t.getAttribute('aria-busy') || '', document.getElementById('sl-cancel')?.disabled ?? 'none', \
    document.getElementById('sl-run').disabled, document.getElementById('sl-summary').dataset.state || ''];";

#[test]
fn the_slam_demo_solves_in_a_worker_and_cancels() {
    let Some((d, _s)) = slam_page() else { return };
    // A long job: the paper scenario at its most steps and landmarks with
    // `best` (tens of seconds; it is cancelled long before it ends).
    d.js(
        "const set = (id, v) => { const e = document.getElementById(id); e.value = v; e.dispatchEvent(new Event('input')); e.dispatchEvent(new Event('change')); }; \
         set('sl-scenario', 'paper'); set('sl-steps', '20000'); set('sl-landmarks', '20'); set('sl-layout', 'ring'); set('sl-mode', 'best'); return 1;",
    );
    d.click("#sl-run");
    // The page answers at once (a script runs while the worker solves)
    // and says it is busy: Cancel offered, the runs disabled.
    let busy = d.js(BUSY);
    assert_eq!(
        busy,
        json!(["true", "true", false, true, "solving"]),
        "busy state while solving"
    );
    // Timers fire during the solve: five timeouts in turn, each handled
    // while the page is still solving.
    let ticks = d.js_async(
        "const done = arguments[arguments.length - 1]; let n = 0; const seen = []; \
         const tick = () => { seen.push(document.getElementById('slam').dataset.busy); if (++n < 5) setTimeout(tick, 20); else done(seen); }; \
         setTimeout(tick, 20);",
    );
    assert_eq!(
        ticks,
        json!(["true", "true", "true", "true", "true"]),
        "timers during the solve"
    );
    // A click is handled during the solve: a layer's box of the legend.
    d.click("#sl-legend input[data-layer='boxes']");
    assert_eq!(
        d.js("return [document.querySelector(\"#sl-legend input[data-layer='boxes']\").checked, document.getElementById('slam').dataset.busy]"),
        json!([false, "true"]),
        "a click during the solve"
    );
    d.click("#sl-legend input[data-layer='boxes']");
    d.screenshot("slam-busy");

    // Cancel: the page is idle at once, nothing is drawn, and no message
    // of the cancelled solve arrives afterwards.
    d.click("#sl-cancel");
    let after = d.js(BUSY);
    assert_eq!(
        after,
        json!(["false", "false", true, false, "cancelled"]),
        "after cancel"
    );
    let text = d.js("return document.getElementById('sl-summary').textContent");
    assert!(text.as_str().unwrap().starts_with("cancelled"), "{text}");
    let quiet = d.js_async(
        "const done = arguments[arguments.length - 1]; const before = document.getElementById('sl-summary').textContent; \
         setTimeout(() => done([document.getElementById('sl-summary').textContent === before, window.nvectorPage.sl.shown.length]), 500);",
    );
    assert_eq!(quiet, json!([true, 0]), "a message of the cancelled solve");
    d.screenshot("slam-cancelled");

    // Usable again: a preset runs to its end in a new worker.
    d.click("#sl-preset-woods");
    let data = finished(&d, Duration::from_secs(120));
    assert_eq!(data["scenario"], "woods", "{data}");
    assert_eq!(d.js(BUSY), json!(["false", "false", true, false, "done"]));
}

/// Watches the woods preset from the page's own scripts: a MutationObserver
/// keeps every text and state of the summary (the progress lines
/// included) and when it went done; the preset is clicked; then timers tick
/// every 10 ms while the tab is busy, the first two clicking the legend's
/// boxes (off, then on again) and noting whether the click was handled
/// while the solve went on; the longest gap between ticks is kept.
const WATCH_WOODS: &str = "const s = document.getElementById('sl-summary'), tab = document.getElementById('slam'); \
    const box = document.querySelector(\"#sl-legend input[data-layer='boxes']\"); \
    const r = window.woodsWatch = {texts: [], clicks: [], ticks: 0, maxGap: 0, ms: null}; \
    const t0 = performance.now(); \
    new MutationObserver(() => { r.texts.push([s.dataset.state || '', s.textContent]); \
      if (r.ms === null && (s.dataset.state === 'done' || s.dataset.state === 'error')) r.ms = performance.now() - t0; }) \
      .observe(s, {childList: true, characterData: true, subtree: true, attributes: true}); \
    document.getElementById('sl-preset-woods').click(); \
    r.afterClick = [tab.dataset.busy, s.dataset.state]; \
    let last = performance.now(); \
    const tick = () => { const now = performance.now(); r.maxGap = Math.max(r.maxGap, now - last); last = now; \
      if (tab.dataset.busy !== 'true') return; r.ticks++; \
      if (r.clicks.length < 2) { const before = box.checked; box.click(); r.clicks.push([before, box.checked, tab.dataset.busy]); } \
      setTimeout(tick, 10); }; \
    setTimeout(tick, 10); return 1;";

/// The woods preset runs `best` in the worker, as a person sees it: the
/// page answers while it solves (its timers fire, a click on the legend is
/// handled, a real click too, and the progress line names `best`), then
/// the result is drawn and the summary reads consistent, truth inside, no
/// matching error, with the proved groups drawn; the result is the native
/// binary's on the same mission, bit for bit. The time from the click to
/// the drawn result is printed (`BROWSER woods best`), not asserted.
#[test]
fn the_woods_preset_solves_best_in_the_worker() {
    let Some((d, _s)) = slam_page() else { return };
    d.js(WATCH_WOODS);
    // A real click (through the browser's input), handled while it solves.
    d.click("#sl-legend input[data-layer='regions']");
    let during = d.js("return [document.querySelector(\"#sl-legend input[data-layer='regions']\").checked, document.getElementById('slam').dataset.busy]");
    d.click("#sl-legend input[data-layer='regions']");
    assert_eq!(during, json!([false, "true"]), "a click during the solve");
    let data = finished(&d, Duration::from_secs(300));
    let watch = d.js("return window.woodsWatch");
    assert_eq!(watch["afterClick"], json!(["true", "solving"]), "{watch}");
    assert_eq!(
        watch["clicks"],
        json!([[true, false, "true"], [false, true, "true"]]),
        "clicks handled while solving: {watch}"
    );
    assert!(
        watch["ticks"].as_u64().unwrap() >= 2,
        "timers while solving: {watch}"
    );
    let texts = watch["texts"].as_array().unwrap();
    assert!(
        texts
            .iter()
            .any(|t| t[0] == "solving" && t[1].as_str().unwrap().contains("(best, run 2 of 2)")),
        "no progress of best shown: {watch}"
    );
    for (key, want) in [
        ("scenario", "woods"),
        ("contractor", "best"),
        ("status", "consistent"),
        ("truthInside", "true"),
        ("errors", "0"),
        ("error", ""),
    ] {
        assert_eq!(data[key], want, "{key}: {data}");
    }
    let groups: f64 = data["groups"].as_str().unwrap().parse().unwrap();
    assert!((1.0..=17.0).contains(&groups), "{data}");
    let text = data["text"].as_str().unwrap();
    assert!(
        text.contains(": consistent;")
            && text.contains(&format!("{groups} proved groups of at most 17 landmarks")),
        "{text}"
    );
    assert_eq!(canvas_data(&d, "sl-nv", "groups"), groups, "groups drawn");
    assert!(painted(&d, "sl-nv") > 0.0);
    d.screenshot("slam-woods-best");
    let ms =
        d.js("return [window.woodsWatch.ms, document.getElementById('sl-summary').dataset.ms]");
    eprintln!(
        "BROWSER woods best: {:.0} ms from the click to the drawn result ({} ms the worker's best run), longest gap between the page's timers {:.0} ms, {} ticks",
        ms[0].as_f64().unwrap(),
        ms[1].as_str().unwrap(),
        watch["maxGap"].as_f64().unwrap(),
        watch["ticks"]
    );
    // The native binary on the page's mission: the same result.
    let dir = nvector_tests::temp_dir("woods-best");
    let mission = d.js("return JSON.stringify(window.nvectorPage.sl.mission)");
    std::fs::write(dir.join("m.json"), mission.as_str().unwrap()).unwrap();
    let st = nvector_tests::nvector()
        .arg("run")
        .arg(dir.join("m.json"))
        .args(["--contractor", "best", "--threads", "1", "--out"])
        .arg(dir.join("r.json"))
        .status()
        .unwrap();
    assert!(st.success());
    // Compared in the page (both read by JavaScript's JSON.parse: the
    // same doubles, the same keys in the same order), the time aside.
    let native = std::fs::read_to_string(dir.join("r.json")).unwrap();
    let same = d.js(&format!(
        "const n = JSON.parse({}), p = structuredClone(window.nvectorPage.sl.shown[1].result); \
         n.metrics.elapsed_ms = 0; p.metrics.elapsed_ms = 0; return JSON.stringify(n) === JSON.stringify(p);",
        serde_json::to_string(&native).unwrap()
    ));
    assert_eq!(
        same, true,
        "the page's best result differs from the native binary's"
    );
}

/// What the page's controls say, read from the elements.
const CONTROLS: &str = "const v = (id) => document.getElementById(id); \
    return {scenario: v('sl-scenario')?.value ?? 'paper', steps: Number(v('sl-steps').value), noise: Number(v('sl-noise').value), \
    landmarks: Number(v('sl-landmarks').value), layout: v('sl-layout').value, range_only: v('sl-range-only').checked, \
    seed: Number(v('sl-seed').value), contractor: v('sl-mode').value};";

/// What was run, from the mission and the result themselves: the
/// scenario, steps, landmarks and seed the mission holds, its layout and
/// range only (meta, paper), the contractor of the atmost_nvector run.
const RUN: &str = "const p = window.nvectorPage.sl, m = p.mission, r = p.shown[1].result; \
    return {scenario: m.meta.scenario, steps: m.steps, landmarks: m.landmark_count, seed: m.meta.seed, \
    layout: m.meta.layout || 'line', range_only: !!m.meta.range_only, contractor: r.options.contractor, \
    bearings: m.detections.filter((x) => x.bearing !== undefined).length, mission: JSON.stringify(m)};";

/// Checks that both panels have one transform that holds every true
/// landmark and every bounded box of both results; returns what it
/// counted.
fn one_scale(d: &Driver) -> Value {
    let v = d.js(
        "const p = window.nvectorPage.sl, [a, b] = p.shown; \
         const num = (x) => x === 'inf' ? Infinity : x === '-inf' ? -Infinity : x; \
         const boxes = []; \
         for (const s of p.shown) for (const key of ['trajectory', 'detections', 'landmarks']) for (const x of s.result[key] || []) { \
           if (!Array.isArray(x) || x.length < 2) continue; const r = [num(x[0][0]), num(x[0][1]), num(x[1][0]), num(x[1][1])]; \
           if (r.every(Number.isFinite)) boxes.push(r); } \
         const points = (p.mission.truth.landmarks || []).map((l) => [l[0], l[0], l[1], l[1]]); \
         const outside = (s, list) => list.filter(([x0, x1, y0, y1]) => { const c = s.view.canvas; \
           return !(s.view.tx(x0) >= -0.5 && s.view.tx(x1) <= c.width + 0.5 && s.view.ty(y1) >= -0.5 && s.view.ty(y0) <= c.height + 0.5); }).length; \
         return {same: [a.view.scale === b.view.scale, a.view.cx === b.view.cx, a.view.cy === b.view.cy, \
                        a.view.canvas.width === b.view.canvas.width, a.view.canvas.height === b.view.canvas.height], \
                 landmarks: points.length, boxes: boxes.length, \
                 outside: p.shown.map((s) => [outside(s, points), outside(s, boxes)])};",
    );
    assert_eq!(
        v["same"],
        json!([true, true, true, true, true]),
        "one transform: {v}"
    );
    assert_eq!(
        v["outside"],
        json!([[0, 0], [0, 0]]),
        "all drawn in both panels: {v}"
    );
    v
}

#[test]
fn presets_set_every_control_and_both_panels_share_one_scale() {
    let Some((d, _s)) = slam_page() else { return };
    for (preset, name) in [
        ("#sl-preset-bearing", "bearing"),
        ("#sl-preset-range", "range-only"),
        ("#sl-preset-woods", "woods"),
    ] {
        // Controls away from every preset first, so that a preset that
        // leaves one alone is seen.
        d.js(
            "const set = (id, v) => { const e = document.getElementById(id); if (!e) return; if (e.type === 'checkbox') e.checked = v; else e.value = v; e.dispatchEvent(new Event('input')); e.dispatchEvent(new Event('change')); }; \
             set('sl-steps', '1500'); set('sl-noise', '2.5'); set('sl-landmarks', '3'); set('sl-layout', 'random'); set('sl-seed', '9'); set('sl-mode', 'nvalue'); set('sl-range-only', true); return 1;",
        );
        d.click(preset);
        let data = finished(&d, Duration::from_secs(180));
        let controls = d.js(CONTROLS);
        let run = d.js(RUN);
        eprintln!("BROWSER preset {name}: controls {controls}, ran {}", {
            let mut r = run.clone();
            r["mission"] = json!("…");
            r
        });
        for key in ["scenario", "steps", "landmarks", "seed", "contractor"] {
            assert_eq!(controls[key], run[key], "{name}: control {key}");
        }
        if run["scenario"] == "paper" {
            assert_eq!(controls["layout"], run["layout"], "{name}: layout");
            assert_eq!(
                controls["range_only"], run["range_only"],
                "{name}: range only"
            );
            // Range only: no detection has a bearing; with bearings, all do.
            let bearings = run["bearings"].as_u64().unwrap();
            let n = data["detections"].as_str().unwrap().parse::<u64>().unwrap();
            assert_eq!(
                bearings,
                if run["range_only"] == true { 0 } else { n },
                "{name}"
            );
        }
        // The woods preset: what the page's title promises.
        if name == "woods" {
            assert_eq!(
                (controls["steps"].clone(), controls["landmarks"].clone()),
                (json!(400), json!(17))
            );
        }
        let scale = one_scale(&d);
        eprintln!(
            "BROWSER preset {name}: one scale over {} true landmarks and {} boxes",
            scale["landmarks"], scale["boxes"]
        );
        d.screenshot(&format!("slam-preset-{name}"));
        // Simulate and run from the controls as the preset left them: the
        // same mission (noise included) and the same contractor.
        d.click("#sl-run");
        finished(&d, Duration::from_secs(180));
        let again = d.js(RUN);
        assert!(
            again["mission"] == run["mission"],
            "{name}: the controls do not give the preset's mission"
        );
        assert_eq!(again["contractor"], run["contractor"], "{name}");
    }
}

#[test]
fn scale_bars_read_round_numbers_with_units() {
    let Some((d, _s)) = slam_page() else { return };
    // The rounding and the text, from the page's own module: the bar's
    // length is 1, 2 or 5 times a power of ten, at least the span over
    // the target and at most 2.5 times it; the text in km from 1000 m.
    let unit = d.js_async(
        "const done = arguments[arguments.length - 1]; import('./draw.js').then((m) => { \
           const texts = [[50000, 'm'], [1000, 'm'], [2e6, 'm'], [500, 'm'], [1, 'm'], [0.5, 'm'], [0.2, 'm'], [0.01, 'm'], [0.005, 'm'], [2e-5, 'm'], [5, ''], [0.2, '']] \
             .map(([v, u]) => m.scaleLabel(v, u)); \
           const bad = []; \
           for (let e = -7; e <= 9; e += 0.037) { const span = 10 ** e, step = m.niceStep(span, 5), raw = span / 5; \
             const k = Math.floor(Math.log10(step) + 1e-9), mant = step / 10 ** k; \
             const label = m.scaleLabel(step, 'm'); const [num, u] = label.split(' '); \
             const mm = Number(num) / 10 ** Math.floor(Math.log10(Number(num)) + 1e-9); \
             const ok = [1, 2, 5].some((x) => Math.abs(mant - x) < 1e-9) && step >= raw * 0.999 && step <= raw * 2.5 \
               && [1, 2, 5].some((x) => Math.abs(mm - x) < 1e-9) && (u === 'km') === (step >= 1000) && !/e|\\.\\d*0$|\\.\\d{7}/.test(num) \
               && (u !== 'm' || Number(num) < 1000); \
             if (!ok) bad.push([span, step, label]); } \
           done({ texts, bad }); }).catch((e) => done(String(e)));",
    );
    assert_eq!(
        unit["texts"],
        json!([
            "50 km", "1 km", "2000 km", "500 m", "1 m", "50 cm", "20 cm", "1 cm", "5 mm",
            "0.02 mm", "5", "0.2"
        ]),
        "{unit}"
    );
    assert_eq!(
        unit["bad"],
        json!([]),
        "steps or texts that are not round: {unit}"
    );

    // The radar tab: kilometres, a round number.
    d.click("nav button[data-tab='radar']");
    let bar = d.wait(
        "const s = document.getElementById('rd-summary').dataset; return (s.groups || s.error) && document.getElementById('rd-canvas').dataset.scaleBar",
        Duration::from_secs(120),
    );
    assert!(
        round_bar(bar.as_str().unwrap(), "km"),
        "radar scale bar: {bar}"
    );
    d.screenshot("radar-scale");
    // The SLAM demo's panels (metres) and the playground's (no unit).
    d.click("nav button[data-tab='slam']");
    d.click("#sl-preset-bearing");
    finished(&d, Duration::from_secs(180));
    for canvas in ["sl-basic", "sl-nv"] {
        let bar = d.js(&format!(
            "return document.getElementById('{canvas}').dataset.scaleBar"
        ));
        assert!(
            round_bar(bar.as_str().unwrap_or(""), "m"),
            "{canvas}: {bar}"
        );
    }
    let bar = d.js("return document.getElementById('pg-canvas').dataset.scaleBar");
    let n: f64 = bar.as_str().unwrap_or("x").parse().unwrap_or(f64::NAN);
    assert!(n > 0.0 && round_mantissa(n), "playground: {bar}");
}

/// A scale bar's text: a number below 1000 whose leading digit is 1, 2 or 5
/// followed by zeros, then the unit.
fn round_bar(text: &str, unit: &str) -> bool {
    let Some((n, u)) = text.split_once(' ') else {
        return false;
    };
    let n: f64 = n.parse().unwrap_or(f64::NAN);
    u == unit && n > 0.0 && n < 1000.0 && round_mantissa(n)
}

fn round_mantissa(n: f64) -> bool {
    let m = n / 10f64.powf((n.log10() + 1e-9).floor());
    [1.0, 2.0, 5.0].iter().any(|x| (m - x).abs() < 1e-9)
}
