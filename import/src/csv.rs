//! The CSV reader of the importers and of the calibration: numbers with
//! file, line and column in every error. One reader for every file: the
//! data sets' logs, the generic import's CSVs and the calibration's four
//! files, whose empty cells are the truth's gaps ([`read_cells`]).

use crate::ImportError;
use std::path::{Path, PathBuf};

/// A parsed CSV: header and numeric rows, with file/line/column in errors.
pub struct Csv {
    /// Column names.
    pub header: Vec<String>,
    /// Rows of numbers.
    pub rows: Vec<Vec<f64>>,
}

/// A CSV with a header whose cells may be empty (`None`), each row with
/// its line number (1-based, as an editor counts).
pub struct Table {
    /// The file, named in errors.
    pub path: PathBuf,
    /// Column names.
    pub header: Vec<String>,
    /// Rows, with their line numbers.
    pub rows: Vec<(usize, Vec<Option<f64>>)>,
}

impl Table {
    /// The index of column `name`, or an error naming the file.
    pub fn column(&self, name: &str) -> Result<usize, ImportError> {
        self.optional(name).ok_or_else(|| {
            ImportError::file(&self.path, format!("missing column '{name}' in the header"))
        })
    }

    /// The index of column `name`, when the header has it.
    pub fn optional(&self, name: &str) -> Option<usize> {
        self.header.iter().position(|h| h == name)
    }

    /// The number in a row's column, or an error naming file, line and
    /// column when the cell is empty.
    pub fn number(&self, row: usize, col: usize) -> Result<f64, ImportError> {
        let (line, cells) = &self.rows[row];
        cells[col].ok_or_else(|| {
            ImportError::line(
                &self.path,
                *line,
                format!("column {} ({}) is empty", col + 1, self.header[col]),
            )
        })
    }

    /// The columns `names`, every cell required.
    pub fn numbers(&self, names: &[&str]) -> Result<Vec<Vec<f64>>, ImportError> {
        let idx: Vec<usize> = names
            .iter()
            .map(|n| self.column(n))
            .collect::<Result<_, _>>()?;
        let mut out = vec![Vec::with_capacity(self.rows.len()); names.len()];
        for r in 0..self.rows.len() {
            for (o, &c) in out.iter_mut().zip(&idx) {
                o.push(self.number(r, c)?);
            }
        }
        Ok(out)
    }
}

/// Reads a CSV with a header row (comma or whitespace separated), every
/// cell a finite number.
pub fn read_csv(path: &Path, header: bool) -> Result<Csv, ImportError> {
    let t = read_rows(path, header, 0, false)?;
    Ok(Csv {
        header: t.header,
        rows: t
            .rows
            .into_iter()
            .map(|(_, r)| r.into_iter().flatten().collect())
            .collect(),
    })
}

/// The rows of a CSV without a header whose rows have at least `columns`
/// cells each (more are allowed): a shorter row, a truncated last line for
/// example, is an error naming its file and line, not an index out of
/// bounds later.
pub fn read_table(path: &Path, columns: usize) -> Result<Vec<Vec<f64>>, ImportError> {
    let t = read_rows(path, false, columns, false)?;
    Ok(t.rows
        .into_iter()
        .map(|(_, r)| r.into_iter().flatten().collect())
        .collect())
}

/// Reads a CSV with a header row whose empty cells are `None` (the
/// calibration's files: the truth's gaps); any other cell must be a
/// finite number.
pub fn read_cells(path: &Path) -> Result<Table, ImportError> {
    read_rows(path, true, 0, true)
}

/// [`read_cells`] of a text already in memory (a data set converted to
/// the calibration's files), `path` naming it in errors.
pub fn cells_of_text(text: &str, path: &Path) -> Result<Table, ImportError> {
    rows_of_text(text, path, true, 0, true)
}

fn read_rows(
    path: &Path,
    header: bool,
    min_columns: usize,
    empty_ok: bool,
) -> Result<Table, ImportError> {
    let text = std::fs::read_to_string(path).map_err(|e| ImportError::read(path, e))?;
    rows_of_text(&text, path, header, min_columns, empty_ok)
}

fn rows_of_text(
    text: &str,
    path: &Path,
    header: bool,
    min_columns: usize,
    empty_ok: bool,
) -> Result<Table, ImportError> {
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
            .ok_or_else(|| ImportError::file(path, "empty file"))?;
        split(l)
    } else {
        Vec::new()
    };
    if let Some((i, h)) = head
        .iter()
        .enumerate()
        .find(|(i, h)| head[..*i].contains(h))
    {
        return Err(ImportError::file(
            path,
            format!(
                "column '{h}' appears twice in the header (columns {} and {})",
                head.iter().position(|x| x == h).unwrap_or(0) + 1,
                i + 1
            ),
        ));
    }
    let mut rows = Vec::new();
    for (i, l) in lines {
        let cells = split(l);
        if !head.is_empty() && cells.len() != head.len() {
            return Err(ImportError::line(
                path,
                i + 1,
                format!(
                    "expected {} columns like the header, found {}",
                    head.len(),
                    cells.len()
                ),
            ));
        }
        if cells.len() < min_columns {
            return Err(ImportError::line(
                path,
                i + 1,
                format!(
                    "expected at least {min_columns} columns, found {}",
                    cells.len()
                ),
            ));
        }
        let mut row = Vec::with_capacity(cells.len());
        for (c, cell) in cells.iter().enumerate() {
            if empty_ok && cell.is_empty() {
                row.push(None);
                continue;
            }
            let x: f64 = cell
                .parse()
                .ok()
                .filter(|x: &f64| x.is_finite())
                .ok_or_else(|| ImportError::Cell {
                    path: path.to_path_buf(),
                    line: i + 1,
                    column: c + 1,
                    name: head.get(c).cloned().unwrap_or_default(),
                    text: cell.clone(),
                })?;
            row.push(Some(x));
        }
        rows.push((i + 1, row));
    }
    Ok(Table {
        path: path.to_path_buf(),
        header: head,
        rows,
    })
}

/// The columns of a CSV by name, or an error naming the file and column.
pub fn columns(csv: &Csv, path: &Path, names: &[&str]) -> Result<Vec<usize>, ImportError> {
    names.iter().map(|n| column(csv, path, n)).collect()
}

/// The column `name` of a CSV, or an error naming the file and column.
pub fn column(csv: &Csv, path: &Path, name: &str) -> Result<usize, ImportError> {
    csv.header
        .iter()
        .position(|h| h == name)
        .ok_or_else(|| ImportError::file(path, format!("missing column '{name}' in the header")))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp(name: &str, text: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("nvector-import-csv-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        p
    }

    #[test]
    fn a_bad_cell_is_named_by_file_line_and_column() {
        let p = temp("bad.csv", "t,speed\n0,1\n\n1,fast\n");
        let e = read_csv(&p, true).err().unwrap().to_string();
        assert!(
            e.ends_with("bad.csv:4: column 2 (speed): 'fast' is not a finite number"),
            "{e}"
        );
        let p = temp("inf.csv", "t,speed\n0,inf\n");
        let e = read_csv(&p, true).err().unwrap().to_string();
        assert!(
            e.ends_with("inf.csv:2: column 2 (speed): 'inf' is not a finite number"),
            "{e}"
        );
    }

    #[test]
    fn short_rows_and_empty_files_are_refused() {
        let p = temp("short.csv", "1 2 3\n4 5\n");
        let e = read_table(&p, 3).err().unwrap().to_string();
        assert!(
            e.ends_with("short.csv:2: expected at least 3 columns, found 2"),
            "{e}"
        );
        let p = temp("ragged.csv", "a,b\n1,2,3\n");
        let e = read_csv(&p, true).err().unwrap().to_string();
        assert!(
            e.ends_with("ragged.csv:2: expected 2 columns like the header, found 3"),
            "{e}"
        );
        let p = temp("empty.csv", "\n\n");
        let e = read_csv(&p, true).err().unwrap().to_string();
        assert!(e.ends_with("empty.csv: empty file"), "{e}");
        let missing = p.with_file_name("no-such.csv");
        let e = read_csv(&missing, true).err().unwrap().to_string();
        assert!(
            e.starts_with("reading ") && e.contains("no-such.csv"),
            "{e}"
        );
    }

    #[test]
    fn whitespace_and_comma_separated_rows_read_alike() {
        let a = read_table(&temp("ws.txt", "1 2\t3\n"), 3).unwrap();
        let b = read_table(&temp("c.txt", "1, 2,3\n"), 3).unwrap();
        assert_eq!(a, b);
        assert_eq!(a, vec![vec![1.0, 2.0, 3.0]]);
    }
}
