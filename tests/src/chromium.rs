//! The page in a real headless Chromium: a WebDriver session driven over
//! HTTP on loopback (chromedriver), the page served by the real `nvector
//! serve` ([`page_server`]), and what the page's canvases say they drew.
//! Used by the browser tests (tests/browser.rs, tests/browser_slam.rs).
//! Screenshots go to target/screenshots/.

use crate::{parse_response, temp_dir, Server};
use serde_json::{json, Value};
use std::io::{Read, Write};
use std::net::TcpStream;
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// A WebDriver session of headless Chromium (chromedriver on a free
/// loopback port), ended when dropped.
pub struct Driver {
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
    assert!(
        buf.windows(4).any(|w| w == b"\r\n\r\n"),
        "chromedriver: no complete answer to {method} {path} {body} within 120 s ({} bytes)",
        buf.len()
    );
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
    /// Starts chromedriver and a session; None (the tests skip, saying so)
    /// when Chromium or chromedriver is missing, except under CI.
    pub fn start() -> Option<Driver> {
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

    /// A WebDriver command of this session; its `value`.
    pub fn cmd(&self, method: &str, path: &str, body: Option<Value>) -> Value {
        http(
            self.port,
            method,
            &format!("/session/{}{path}", self.session),
            body.as_ref(),
        )["value"]
            .clone()
    }

    /// Opens a URL.
    pub fn goto(&self, url: &str) {
        self.cmd("POST", "/url", Some(json!({"url": url})));
    }

    /// Runs a script; its return value.
    pub fn js(&self, script: &str) -> Value {
        self.cmd(
            "POST",
            "/execute/sync",
            Some(json!({"script": script, "args": []})),
        )
    }

    /// Runs an asynchronous script: it calls its last argument with the
    /// result.
    pub fn js_async(&self, script: &str) -> Value {
        self.cmd(
            "POST",
            "/execute/async",
            Some(json!({"script": script, "args": []})),
        )
    }

    /// Polls a script until it returns a truthy value.
    pub fn wait(&self, script: &str, limit: Duration) -> Value {
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

    /// The WebDriver id of the element a CSS selector finds.
    pub fn element(&self, css: &str) -> String {
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

    /// Clicks the element a CSS selector finds.
    pub fn click(&self, css: &str) {
        let e = self.element(css);
        self.cmd("POST", &format!("/element/{e}/click"), Some(json!({})));
    }

    /// A screenshot of the window as target/screenshots/NAME.png.
    pub fn screenshot(&self, name: &str) {
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
pub fn page_server() -> Server {
    let www = Path::new(env!("CARGO_MANIFEST_DIR")).join("../web/www");
    assert!(
        www.join("pkg/nvector_web.js").exists(),
        "the page is not built: run `scripts/web.sh build` (make test does)"
    );
    // A directory of its own (the browser tests run in parallel, each with
    // its server and database).
    let dir = temp_dir("browser");
    // Server::start_with serves DIR/www: point it at the built page.
    std::os::unix::fs::symlink(&www, dir.join("www")).unwrap();
    Server::start_with(
        dir.clone(),
        format!("sqlite://{}", dir.join("db.sqlite").display()),
        &[],
    )
}

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
