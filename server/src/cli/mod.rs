//! Subcommands, one file each.

pub mod bench;
pub mod bench_real;
pub mod bench_service;
pub mod bench_slam;
pub mod calibrate;
pub mod check;
pub mod contract;
pub mod import;
pub mod measure;
pub mod plot;
mod result_check;
pub mod run;
pub mod serve;
pub mod simulate;
pub mod tdoa;
pub mod worker;

/// The `format` a JSON text declares at its top (the first `"format":
/// "..."` pair; None when there is none).
fn declared_format(text: &str) -> Option<&str> {
    let mut rest = text;
    while let Some(i) = rest.find("\"format\"") {
        rest = &rest[i + 8..];
        let after = rest.trim_start();
        if let Some(v) = after.strip_prefix(':') {
            let v = v.trim_start();
            if let Some(v) = v.strip_prefix('"') {
                return v.find('"').map(|end| &v[..end]);
            }
        }
    }
    None
}

/// A reading error of a file meant as `expected`, with a word on what the
/// file is when it declares another of the formats (a TDOA problem given
/// to `run` was reported by its first unknown field only).
pub(crate) fn wrong_kind(text: &str, expected: &str, error: String) -> String {
    let what = |f: &str| match f {
        "nvector-mission/1" => Some("a mission (for nvector run)"),
        "nvector-tdoa/1" => Some("a TDOA problem (for nvector tdoa)"),
        "nvector-result/1" => Some("a SLAM result (for nvector plot)"),
        "nvector-tdoa-result/1" => Some("a TDOA result"),
        "nvector-contract/1" => Some("a contraction request (for nvector contract)"),
        _ => None,
    };
    match declared_format(text) {
        Some(f) if f != expected => match what(f) {
            Some(w) => format!("{error} (the file's format is \"{f}\": {w}, not {expected})"),
            None => error,
        },
        _ => error,
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn a_file_of_another_format_is_named() {
        let e = super::wrong_kind(
            "{\"emitter_count\": 3, \"format\" : \"nvector-tdoa/1\"}",
            "nvector-mission/1",
            "emitter_count: unknown field".into(),
        );
        assert!(e.contains("a TDOA problem (for nvector tdoa)"), "{e}");
        let same = super::wrong_kind(
            "{\"format\": \"nvector-mission/1\"}",
            "nvector-mission/1",
            "x".into(),
        );
        assert_eq!(same, "x");
        assert_eq!(
            super::wrong_kind("{}", "nvector-mission/1", "x".into()),
            "x"
        );
    }
}
