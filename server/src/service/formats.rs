//! What a JSON document says it is: the `format` it declares, and the name
//! of each of the project's formats, so that a file given where another
//! format is expected (a result uploaded as a mission, a TDOA problem given
//! to `nvector run`) is refused with a message that says what it is. The
//! one recognition of the CLI (`run`, `tdoa`) and the service (missions).
//! Below both: `cli` uses it, the service's handlers too.

/// What a format is, in a reader's words, with the command that reads it.
pub fn what(format: &str) -> Option<&'static str> {
    match format {
        "nvector-mission/1" => Some("a mission (for nvector run)"),
        "nvector-tdoa/1" => Some("a TDOA problem (for nvector tdoa)"),
        "nvector-result/1" => Some("a SLAM result (for nvector plot)"),
        "nvector-tdoa-result/1" => Some("a TDOA result"),
        "nvector-contract/1" => Some("a contraction request (for nvector contract)"),
        _ => None,
    }
}

/// "the file's format is "F": what F is, not EXPECTED" when `declared` is
/// another of the project's formats than `expected`; None otherwise.
pub fn other_format(declared: Option<&str>, expected: &str) -> Option<String> {
    let f = declared.filter(|f| *f != expected)?;
    what(f).map(|w| format!("the file's format is \"{f}\": {w}, not {expected}"))
}

/// The `format` a JSON text declares at its top (the first `"format":
/// "..."` pair; None when there is none).
pub fn declared_format(text: &str) -> Option<&str> {
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
pub fn wrong_kind(text: &str, expected: &str, error: String) -> String {
    match other_format(declared_format(text), expected) {
        Some(note) => format!("{error} ({note})"),
        None => error,
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
        assert_eq!(
            super::other_format(Some("nvector-result/1"), "nvector-mission/1").as_deref(),
            Some("the file's format is \"nvector-result/1\": a SLAM result (for nvector plot), not nvector-mission/1")
        );
        assert_eq!(super::other_format(Some("x/1"), "nvector-mission/1"), None);
    }
}
