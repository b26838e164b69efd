//! The CSV reader of `nvector import`: numbers with file, line and column
//! in every error. Below `import` and its data-set readers.

use crate::CliError;
use std::path::Path;

/// A parsed CSV: header and numeric rows, with file/line/column in errors.
pub struct Csv {
    /// Column names.
    pub header: Vec<String>,
    /// Rows of numbers.
    pub rows: Vec<Vec<f64>>,
}

/// Reads a CSV with a header row (comma or whitespace separated).
pub fn read_csv(path: &Path, header: bool) -> Result<Csv, CliError> {
    read_csv_with(path, header, 0)
}

/// The rows of a CSV without a header whose rows have at least `columns`
/// cells each (more are allowed): a shorter row, a truncated last line for
/// example, is an error naming its file and line, not an index out of
/// bounds later.
pub fn read_table(path: &Path, columns: usize) -> Result<Vec<Vec<f64>>, CliError> {
    Ok(read_csv_with(path, false, columns)?.rows)
}

fn read_csv_with(path: &Path, header: bool, min_columns: usize) -> Result<Csv, CliError> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| CliError(format!("reading {}: {e}", path.display())))?;
    let mut lines = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty());
    let split = |l: &str| -> Vec<String> {
        if l.contains(',') {
            l.split(',').map(|s| s.trim().to_string()).collect()
        } else {
            l.split_whitespace().map(str::to_string).collect()
        }
    };
    let head = if header {
        let (_, l) = lines
            .next()
            .ok_or_else(|| CliError(format!("{}: empty file", path.display())))?;
        split(l)
    } else {
        Vec::new()
    };
    let mut rows = Vec::new();
    for (i, l) in lines {
        let cells = split(l);
        if !head.is_empty() && cells.len() != head.len() {
            return Err(CliError(format!(
                "{}:{}: expected {} columns like the header, found {}",
                path.display(),
                i + 1,
                head.len(),
                cells.len()
            )));
        }
        if cells.len() < min_columns {
            return Err(CliError(format!(
                "{}:{}: expected at least {min_columns} columns, found {}",
                path.display(),
                i + 1,
                cells.len()
            )));
        }
        let mut row = Vec::with_capacity(cells.len());
        for (c, cell) in cells.iter().enumerate() {
            let x: f64 = cell
                .parse()
                .ok()
                .filter(|x: &f64| x.is_finite())
                .ok_or_else(|| {
                    CliError(format!(
                        "{}:{}: column {} ({}): '{cell}' is not a finite number",
                        path.display(),
                        i + 1,
                        c + 1,
                        head.get(c).map_or("", String::as_str)
                    ))
                })?;
            row.push(x);
        }
        rows.push(row);
    }
    Ok(Csv { header: head, rows })
}
