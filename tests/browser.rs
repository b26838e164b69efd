//! The page in a real headless Chromium driven through chromedriver
//! (WebDriver over HTTP on loopback), against the real `nvector serve` on a
//! fresh SQLite database: the playground's Figure 8 preset, the offline SLAM
//! demo, a mission uploaded through the page and drawn, and the browser's
//! results compared bit for bit with the native binary. Screenshots go to
//! target/screenshots/. Under CI (CI=true) a missing browser is a failure;
//! elsewhere the test is skipped, saying so loudly.

use nvector_tests as common;

use common::{parse_response, Server};
use serde_json::{json, Value};
use std::io::{Read, Write};
use std::net::TcpStream;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

struct Driver {
    child: Child,
    port: u16,
    session: String,
}

fn http(port: u16, method: &str, path: &str, body: Option<&Value>) -> Value {
    let mut s = TcpStream::connect(("127.0.0.1", port)).unwrap();
    s.set_read_timeout(Some(Duration::from_secs(120))).unwrap();
    let body = body.map(|b| b.to_string()).unwrap_or_default();
    let req = format!(
        "{method} {path} HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nConnection: close\r\nContent-Type: application/json\r\nContent-Length: {}\r\n\r\n{body}",
        body.len()
    );
    s.write_all(req.as_bytes()).unwrap();
    // chromedriver may keep the connection open: read by Content-Length.
    let mut buf = Vec::new();
    let mut chunk = [0u8; 65536];
    loop {
        let n = s.read(&mut chunk).unwrap_or(0);
        if n == 0 {
            break;
        }
        buf.extend_from_slice(&chunk[..n]);
        if let Some(h) = buf.windows(4).position(|w| w == b"\r\n\r\n") {
            let head = String::from_utf8_lossy(&buf[..h]).to_ascii_lowercase();
            let len = head.lines().find_map(|l| {
                l.strip_prefix("content-length:")
                    .map(|v| v.trim().parse::<usize>().unwrap_or(0))
            });
            if let Some(len) = len {
                if buf.len() >= h + 4 + len {
                    break;
                }
            }
        }
    }
    let (_, _, b) = parse_response(&buf);
    serde_json::from_slice(&b).unwrap_or(Value::Null)
}

fn free_port() -> u16 {
    std::net::TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port()
}

impl Driver {
    fn start() -> Option<Driver> {
        let chromedriver =
            std::env::var("CHROMEDRIVER").unwrap_or_else(|_| "/usr/bin/chromedriver".into());
        let chromium = ["/usr/bin/chromium", "/usr/bin/chromium-browser"]
            .into_iter()
            .find(|p| Path::new(p).exists());
        let (Some(chromium), true) = (chromium, Path::new(&chromedriver).exists()) else {
            let msg = "Chromium or chromedriver is missing (scripts/setup.sh installs them)";
            assert!(std::env::var("CI").as_deref() != Ok("true"), "{msg}");
            eprintln!("\n*** SKIPPED the browser tests: {msg} ***\n");
            return None;
        };
        let port = free_port();
        let child = Command::new(&chromedriver)
            .arg(format!("--port={port}"))
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        let start = Instant::now();
        while TcpStream::connect(("127.0.0.1", port)).is_err() {
            assert!(
                start.elapsed() < Duration::from_secs(20),
                "chromedriver did not start"
            );
            std::thread::sleep(Duration::from_millis(50));
        }
        let profile =
            std::env::temp_dir().join(format!("nvector-chromium-{}-{port}", std::process::id()));
        let caps = json!({"capabilities": {"alwaysMatch": {"goog:chromeOptions": {
            "binary": chromium,
            "args": ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--disable-dev-shm-usage",
                     "--disable-background-networking", "--disable-component-update", "--disable-sync",
                     "--no-first-run", "--window-size=1200,1000", format!("--user-data-dir={}", profile.display())]
        }}}});
        let r = http(port, "POST", "/session", Some(&caps));
        let session = r["value"]["sessionId"]
            .as_str()
            .unwrap_or_else(|| panic!("no session: {r}"))
            .to_string();
        Some(Driver {
            child,
            port,
            session,
        })
    }

    fn cmd(&self, method: &str, path: &str, body: Option<Value>) -> Value {
        http(
            self.port,
            method,
            &format!("/session/{}{path}", self.session),
            body.as_ref(),
        )["value"]
            .clone()
    }

    fn goto(&self, url: &str) {
        self.cmd("POST", "/url", Some(json!({"url": url})));
    }

    fn js(&self, script: &str) -> Value {
        self.cmd(
            "POST",
            "/execute/sync",
            Some(json!({"script": script, "args": []})),
        )
    }

    /// Polls a script until it returns a truthy value.
    fn wait(&self, script: &str, limit: Duration) -> Value {
        let start = Instant::now();
        loop {
            let v = self.js(script);
            if !(v.is_null() || v == false || v == "") {
                return v;
            }
            assert!(start.elapsed() < limit, "timed out waiting for: {script}");
            std::thread::sleep(Duration::from_millis(100));
        }
    }

    fn element(&self, css: &str) -> String {
        let v = self.cmd(
            "POST",
            "/element",
            Some(json!({"using": "css selector", "value": css})),
        );
        v.as_object()
            .and_then(|o| o.values().next())
            .and_then(Value::as_str)
            .unwrap_or_else(|| panic!("no element {css}: {v}"))
            .to_string()
    }

    fn click(&self, css: &str) {
        let e = self.element(css);
        self.cmd("POST", &format!("/element/{e}/click"), Some(json!({})));
    }

    fn screenshot(&self, name: &str) {
        let b64 = self.cmd("GET", "/screenshot", None);
        let bytes = base64_decode(b64.as_str().unwrap());
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/screenshots");
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join(format!("{name}.png")), bytes).unwrap();
    }
}

impl Drop for Driver {
    fn drop(&mut self) {
        let _ = http(
            self.port,
            "DELETE",
            &format!("/session/{}", self.session),
            None,
        );
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn base64_decode(s: &str) -> Vec<u8> {
    let val = |c: u8| match c {
        b'A'..=b'Z' => c - b'A',
        b'a'..=b'z' => c - b'a' + 26,
        b'0'..=b'9' => c - b'0' + 52,
        b'+' => 62,
        _ => 63,
    };
    let bytes: Vec<u8> = s
        .bytes()
        .filter(|c| !c.is_ascii_whitespace() && *c != b'=')
        .collect();
    let mut out = Vec::with_capacity(bytes.len() * 3 / 4);
    for chunk in bytes.chunks(4) {
        let v: Vec<u32> = chunk.iter().map(|&c| val(c) as u32).collect();
        let n = v
            .iter()
            .enumerate()
            .fold(0u32, |acc, (i, &x)| acc | (x << (18 - 6 * i)));
        out.push((n >> 16) as u8);
        if chunk.len() > 2 {
            out.push((n >> 8) as u8);
        }
        if chunk.len() > 3 {
            out.push(n as u8);
        }
    }
    out
}

/// A server whose static directory is the built page (web/www).
fn page_server() -> Server {
    let www = Path::new(env!("CARGO_MANIFEST_DIR")).join("../web/www");
    assert!(
        www.join("pkg/nvector_web.js").exists(),
        "the page is not built: run `scripts/web.sh build` (make test does)"
    );
    let dir = std::env::temp_dir().join(format!("nvector-browser-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // Server::start_with serves DIR/www: point it at the built page.
    let link = dir.join("www");
    let _ = std::fs::remove_file(&link);
    std::os::unix::fs::symlink(&www, &link).unwrap();
    Server::start_with(
        dir.clone(),
        format!("sqlite://{}", dir.join("db.sqlite").display()),
        &[],
    )
}

fn result_without_time(mut v: Value) -> Value {
    v["metrics"]["elapsed_ms"] = json!(0);
    v
}

#[test]
fn the_page_in_headless_chromium() {
    let Some(d) = Driver::start() else { return };
    let s = page_server();
    let base = format!("http://{}", s.addr);

    // Playground: the Figure 8 preset with the per-axis contractor gives the
    // groups derived by hand in core/tests/nvector_examples.rs.
    d.goto(&format!("{base}/?preset=fig8"));
    d.wait(
        "return document.getElementById('wasm-status').dataset.ready === 'true'",
        Duration::from_secs(30),
    );
    d.js("const m = document.getElementById('pg-mode'); m.value = 'nvalue'; m.dispatchEvent(new Event('change')); return 1;");
    let groups = d.wait(
        "return document.getElementById('pg-summary').dataset.groups",
        Duration::from_secs(10),
    );
    assert_eq!(groups, "[[0,1],[2],[3,4],[5],[6]]");
    d.screenshot("playground-fig8");
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

    // SLAM demo, offline in WASM.
    d.goto(&format!("{base}/?tab=slam&demo=1"));
    let nvd = d.wait(
        "return document.getElementById('sl-summary').dataset.nvectorDiameter",
        Duration::from_secs(120),
    );
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
    assert!(st.success());
    let mission_text = std::fs::read_to_string(&mission_path).unwrap();
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
    assert_eq!(
        d.js("return document.getElementById('rv-summary').dataset.trajectory"),
        "3001"
    );
    assert_eq!(
        d.js("return document.getElementById('rv-summary').dataset.truthInside"),
        "true"
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

    // A reload still lists both jobs (remembered by the browser) and shows
    // the older one again on request.
    d.goto(&format!("{base}/?tab=missions"));
    let states = d.wait(
        "const l = [...document.querySelectorAll('#ms-jobs li')].map(li => li.dataset.state); return l.length === 2 && l.join(',')",
        Duration::from_secs(30),
    );
    assert_eq!(states, "done,done");
    d.click("#ms-jobs li:last-child button.show");
    let shown = d.wait(
        "const s = document.getElementById('rv-summary').dataset; return s.state === 'drawn' && s.contractors",
        Duration::from_secs(30),
    );
    assert_eq!(shown, "best", "the older job of the list is the best run");

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
}
