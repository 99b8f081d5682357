//! Sampled trajectories read from CSV: the `t` and `q…` columns of the trajectory format
//! `t,q0,…,q{NQ−1},v0,…,v{NV−1}` (what `articulated simulate` writes; a motion-capture file in
//! the same columns reads the same way), and writing such tables.
//!
//! The reader is strict and never panics: the first row is a header of comma-separated column
//! names, which must contain `t` and `q0 … q{nq−1}` for the `nq` the caller asks for (other
//! columns, `v…` included, are ignored; no name may appear twice); every following row has as
//! many fields as the header, each a finite decimal number (Rust's `f64` syntax: `1`, `-0.5`,
//! `2.5e-3`); times strictly increase. Fields are trimmed of spaces; blank lines (anywhere,
//! and a trailing newline) are skipped; `\r\n` line ends are accepted. Errors name the line
//! (1 based) and the column.

use std::fmt;
use std::io::{self, Write};
use std::string::{String, ToString};
use std::vec::Vec;

/// Positions sampled at increasing times: `len()` rows of `t` and `nq` positions.
#[derive(Clone, Debug, PartialEq)]
pub struct Samples {
    t: Vec<f64>,
    q: Vec<f64>,
    nq: usize,
}

impl Samples {
    /// Samples from times and row-major positions (`t.len()·nq` values).
    ///
    /// # Errors
    /// The positions are not `t.len()·nq` long ([`CsvError::FieldCount`] at line 0), a time or
    /// a position is not finite ([`CsvError::NotFinite`]) or times do not strictly increase
    /// ([`CsvError::TimesNotIncreasing`]); lines are then `row + 2`, as if the rows followed a
    /// header on line 1.
    pub fn new(t: Vec<f64>, q: Vec<f64>, nq: usize) -> Result<Self, CsvError> {
        if t.len().checked_mul(nq) != Some(q.len()) {
            return Err(CsvError::FieldCount {
                line: 0,
                expected: t.len().saturating_mul(nq),
                found: q.len(),
            });
        }
        let mut previous: Option<f64> = None;
        // `nq = 0` has no positions per row: each row's slice of `q` is then empty.
        let mut rows = q.chunks(nq.max(1));
        for (row, &time) in t.iter().enumerate() {
            let line = row + 2;
            if !time.is_finite() {
                return Err(CsvError::NotFinite {
                    line,
                    column: "t".to_string(),
                });
            }
            let positions = if nq == 0 {
                &[][..]
            } else {
                rows.next().unwrap_or(&[])
            };
            for (c, x) in positions.iter().enumerate() {
                if !x.is_finite() {
                    return Err(CsvError::NotFinite {
                        line,
                        column: std::format!("q{c}"),
                    });
                }
            }
            if previous.is_some_and(|before| time <= before) {
                return Err(CsvError::TimesNotIncreasing { line });
            }
            previous = Some(time);
        }
        Ok(Samples { t, q, nq })
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.t.len()
    }

    /// `true` without samples.
    pub fn is_empty(&self) -> bool {
        self.t.is_empty()
    }

    /// Positions per sample.
    pub fn nq(&self) -> usize {
        self.nq
    }

    /// The times, strictly increasing.
    pub fn times(&self) -> &[f64] {
        &self.t
    }

    /// All positions, row-major (`len()·nq()` values).
    pub fn positions(&self) -> &[f64] {
        &self.q
    }

    /// The positions of sample `i`, or `None` past the end.
    pub fn q(&self, i: usize) -> Option<&[f64]> {
        let start = i.checked_mul(self.nq)?;
        self.q.get(start..start.checked_add(self.nq)?)
    }

    /// Reads the `t` and `q0 … q{nq−1}` columns of a trajectory CSV (format in the
    /// [module docs](self)).
    ///
    /// ```
    /// use articulated::samples::Samples;
    ///
    /// let csv = "t,q0,q1,v0,v1\n0.0,0.1,0.2,0,0\n0.01,0.11,0.19,1,-1\n";
    /// let s = Samples::parse_csv(csv, 2)?;
    /// assert_eq!(s.times(), &[0.0, 0.01]);
    /// assert_eq!(s.q(1), Some(&[0.11, 0.19][..]));
    /// # Ok::<(), articulated::samples::CsvError>(())
    /// ```
    ///
    /// # Errors
    /// [`CsvError`], naming the line (1 based) and, where there is one, the column.
    pub fn parse_csv(text: &str, nq: usize) -> Result<Self, CsvError> {
        let mut lines = text
            .split('\n')
            .enumerate()
            .map(|(i, l)| (i + 1, l.strip_suffix('\r').unwrap_or(l)))
            .filter(|(_, l)| !l.trim().is_empty());
        let (header_line, header) = lines.next().ok_or(CsvError::MissingHeader)?;
        let names: Vec<&str> = header.split(',').map(str::trim).collect();
        for (i, name) in names.iter().enumerate() {
            if names.iter().take(i).any(|n| n == name) {
                return Err(CsvError::DuplicateColumn {
                    line: header_line,
                    column: name.to_string(),
                });
            }
        }
        let find = |name: &str| {
            names
                .iter()
                .position(|n| *n == name)
                .ok_or_else(|| CsvError::MissingColumn {
                    line: header_line,
                    column: name.to_string(),
                })
        };
        let t_at = find("t")?;
        let q_at = (0..nq)
            .map(|i| find(&std::format!("q{i}")))
            .collect::<Result<Vec<_>, _>>()?;
        let mut t = Vec::new();
        let mut q = Vec::new();
        let mut fields = Vec::with_capacity(names.len());
        for (line, row) in lines {
            fields.clear();
            fields.extend(row.split(',').map(str::trim));
            if fields.len() != names.len() {
                return Err(CsvError::FieldCount {
                    line,
                    expected: names.len(),
                    found: fields.len(),
                });
            }
            // `at` is a column of the header, and this row has as many fields as it.
            let number = |at: usize| -> Result<f64, CsvError> {
                let (field, name) = (
                    fields.get(at).copied().unwrap_or_default(),
                    names.get(at).copied().unwrap_or_default(),
                );
                let x: f64 = field.parse().map_err(|_| CsvError::NotANumber {
                    line,
                    column: name.to_string(),
                    field: field.to_string(),
                })?;
                if x.is_finite() {
                    Ok(x)
                } else {
                    Err(CsvError::NotFinite {
                        line,
                        column: name.to_string(),
                    })
                }
            };
            let time = number(t_at)?;
            for &at in &q_at {
                q.push(number(at)?);
            }
            if let Some(&last) = t.last() {
                if time <= last {
                    return Err(CsvError::TimesNotIncreasing { line });
                }
            }
            t.push(time);
        }
        Ok(Samples { t, q, nq })
    }
}

/// What is wrong with a trajectory CSV. `line` is 1 based and counts blank lines.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum CsvError {
    /// The text has no header row (it is empty or blank).
    MissingHeader,
    /// The header lacks a column the caller needs (`t` or a `q` column).
    MissingColumn {
        /// The header's line.
        line: usize,
        /// The missing column's name.
        column: String,
    },
    /// A column name appears twice in the header.
    DuplicateColumn {
        /// The header's line.
        line: usize,
        /// The name.
        column: String,
    },
    /// A row has a different number of fields than the header.
    FieldCount {
        /// The row's line.
        line: usize,
        /// Fields in the header.
        expected: usize,
        /// Fields in the row.
        found: usize,
    },
    /// A field is not a number.
    NotANumber {
        /// The row's line.
        line: usize,
        /// The field's column.
        column: String,
        /// The field as written (trimmed).
        field: String,
    },
    /// A field is NaN or infinite.
    NotFinite {
        /// The row's line.
        line: usize,
        /// The field's column.
        column: String,
    },
    /// A row's time is not after the previous row's.
    TimesNotIncreasing {
        /// The row's line.
        line: usize,
    },
}

impl fmt::Display for CsvError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CsvError::MissingHeader => write!(f, "no header row (the file is empty)"),
            CsvError::MissingColumn { line, column } => {
                write!(f, "line {line}: the header has no column `{column}`")
            }
            CsvError::DuplicateColumn { line, column } => {
                write!(f, "line {line}: the header names column `{column}` twice")
            }
            CsvError::FieldCount {
                line,
                expected,
                found,
            } => write!(
                f,
                "line {line}: {found} fields, the header has {expected} columns"
            ),
            CsvError::NotANumber {
                line,
                column,
                field,
            } => write!(
                f,
                "line {line}, column `{column}`: `{field}` is not a number"
            ),
            CsvError::NotFinite { line, column } => {
                write!(
                    f,
                    "line {line}, column `{column}`: the number is not finite"
                )
            }
            CsvError::TimesNotIncreasing { line } => write!(
                f,
                "line {line}, column `t`: the time is not after the previous row's"
            ),
        }
    }
}

impl std::error::Error for CsvError {}

/// Writes a table with the header `t,{prefix}0,…,{prefix}{columns−1}` and one row per time,
/// `values` row-major (`t.len()·columns`). Numbers are written in Rust's shortest form that
/// reads back to the same `f64` (`{:?}`: `3.2e-7`, not `0.00000032`), so
/// [`Samples::parse_csv`] round-trips them exactly.
/// `prefix = "tau"` gives the couples file of `articulated invert`.
///
/// # Errors
/// The writer's, and [`io::ErrorKind::InvalidInput`] when `values` is not `t.len()·columns`
/// long.
pub fn write_csv<W: Write>(
    mut out: W,
    prefix: &str,
    t: &[f64],
    columns: usize,
    values: &[f64],
) -> io::Result<()> {
    if t.len().checked_mul(columns) != Some(values.len()) {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            std::format!(
                "{} values for {} rows of {columns} columns",
                values.len(),
                t.len()
            ),
        ));
    }
    write!(out, "t")?;
    for c in 0..columns {
        write!(out, ",{prefix}{c}")?;
    }
    writeln!(out)?;
    // `columns = 0`: every row is the time alone.
    let mut rows = values.chunks(columns.max(1));
    for time in t {
        write!(out, "{time:?}")?;
        let row = if columns == 0 {
            &[][..]
        } else {
            rows.next().unwrap_or(&[])
        };
        for x in row {
            write!(out, ",{x:?}")?;
        }
        writeln!(out)?;
    }
    Ok(())
}
