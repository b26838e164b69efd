//! `nvector serve` finds its page from any directory and says where from;
//! the API reference page `/api/docs` (Redoc on the service's own OpenAPI
//! document) and its script are served by the service itself. Over a real
//! socket, the real binary.

use nvector_tests::{nvector_bin, parse_response, repo_root, temp_dir};
use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::process::{Child, Command, Stdio};
use std::time::Duration;

struct Service {
    child: Child,
    addr: String,
    log: std::path::PathBuf,
}

impl Drop for Service {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// `nvector serve` started in `cwd` (not the repository), its log in a file.
fn start(cwd: &std::path::Path, extra: &[&str]) -> Service {
    let log = cwd.join("serve.log");
    let db = format!("sqlite://{}", cwd.join("nvector.db").display());
    let mut child = Command::new(nvector_bin())
        .current_dir(cwd)
        .args(["serve", "--addr", "127.0.0.1:0", "--database", &db])
        .args(["--workers", "1"])
        .args(extra)
        .env("RUST_LOG", "info")
        .env("NO_COLOR", "1")
        .stdout(Stdio::piped())
        .stderr(std::fs::File::create(&log).unwrap())
        .spawn()
        .expect("start nvector serve");
    let mut line = String::new();
    BufReader::new(child.stdout.take().unwrap())
        .read_line(&mut line)
        .unwrap();
    let addr = line
        .trim()
        .strip_prefix("nvector serving on http://")
        .unwrap_or_else(|| panic!("unexpected first line: {line}"))
        .to_string();
    Service { child, addr, log }
}

fn get(addr: &str, path: &str) -> (u16, String, Vec<u8>) {
    let mut s = TcpStream::connect(addr).unwrap();
    s.set_read_timeout(Some(Duration::from_secs(30))).unwrap();
    write!(
        s,
        "GET {path} HTTP/1.1\r\nHost: {addr}\r\nConnection: close\r\n\r\n"
    )
    .unwrap();
    let mut buf = Vec::new();
    let _ = s.read_to_end(&mut buf);
    parse_response(&buf)
}

#[test]
fn serve_finds_its_page_from_another_directory_and_logs_it() {
    let cwd = temp_dir("page-cwd");
    assert!(!cwd.join("web/www").exists());
    let s = start(&cwd, &[]);
    let page = std::fs::read(repo_root().join("web/www/index.html")).unwrap();
    let (st, _, body) = get(&s.addr, "/");
    assert_eq!(st, 200);
    assert_eq!(body, page, "/ is not the repository's web/www/index.html");
    let log = std::fs::read_to_string(&s.log).unwrap();
    let www = repo_root().join("web/www").canonicalize().unwrap();
    assert!(
        log.contains(&format!("serving the page from {}", www.display())),
        "{log}"
    );
}

#[test]
fn serve_says_when_the_page_is_missing() {
    let cwd = temp_dir("page-missing");
    let s = start(&cwd, &["--static-dir", "no-such-dir"]);
    let log = std::fs::read_to_string(&s.log).unwrap();
    assert!(log.contains("the page is missing"), "{log}");
    assert!(log.contains("no-such-dir"), "{log}");
    let (st, _, body) = get(&s.addr, "/");
    assert_eq!(st, 200);
    assert!(String::from_utf8_lossy(&body).contains("not built"));
    // The API reference is in the binary: served all the same.
    assert_eq!(get(&s.addr, "/api/docs").0, 200);
}

#[test]
fn api_docs_page_and_its_script_are_served_locally() {
    let cwd = temp_dir("docs-page");
    let s = start(&cwd, &[]);
    let (st, headers, body) = get(&s.addr, "/api/docs");
    assert_eq!(st, 200);
    assert!(
        headers.to_ascii_lowercase().contains("text/html"),
        "{headers}"
    );
    let html = String::from_utf8(body).unwrap();
    assert!(html.contains(r#"<script src="/api/docs/redoc.standalone.js"></script>"#));
    assert!(html.contains(r#"Redoc.init("/api/v1/openapi.json""#));
    // Nothing fetched from elsewhere: every src and href is on the service.
    for attr in ["src=\"", "href=\""] {
        for part in html.split(attr).skip(1) {
            assert!(
                part.starts_with('/'),
                "{attr}{}",
                &part[..part.len().min(40)]
            );
        }
    }
    let (st, headers, js) = get(&s.addr, "/api/docs/redoc.standalone.js");
    assert_eq!(st, 200);
    assert!(
        headers.to_ascii_lowercase().contains("text/javascript"),
        "{headers}"
    );
    assert!(js.len() > 500_000, "{} bytes", js.len());
    assert!(String::from_utf8_lossy(&js[..4000.min(js.len())]).contains("Redoc"));
    // The document the page reads is there.
    let (st, _, doc) = get(&s.addr, "/api/v1/openapi.json");
    assert_eq!(st, 200);
    let doc: serde_json::Value = serde_json::from_slice(&doc).unwrap();
    assert!(doc["openapi"].as_str().unwrap().starts_with("3."));
}

#[test]
fn api_docs_page_is_readable_without_a_key() {
    let cwd = temp_dir("docs-keys");
    let keys = cwd.join("keys.txt");
    std::fs::write(&keys, "k-1\n").unwrap();
    let s = start(&cwd, &["--api-key-file", keys.to_str().unwrap()]);
    assert_eq!(get(&s.addr, "/api/v1/missions").0, 401);
    assert_eq!(get(&s.addr, "/api/docs").0, 200);
    assert_eq!(get(&s.addr, "/api/docs/redoc.standalone.js").0, 200);
    assert_eq!(get(&s.addr, "/api/v1/openapi.json").0, 200);
}
