//! Reader for the dense Siconos `.dat` LCP format (see `tests/data/lcp/README.md`):
//!
//! ```text
//! n                 problem size
//! 0                 storage flag (0 = dense; sparse-block is not supported)
//! rows cols         matrix shape, then once more as "rows cols"
//! M                 rows × cols numbers, row by row
//! q                 n numbers
//! ...               anything after q is a free-text comment
//! ```
//!
//! Tokens are whitespace-separated. Errors name the file and what was wrong.

use crate::LcpProblem;
use nalgebra::{DMatrix, DVector};
use std::path::Path;

/// A `.dat` file that cannot be read or parsed. `Display` starts with the file name.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DatError {
    #[error("{file}: cannot read: {message}")]
    Io { file: String, message: String },
    #[error("{file}: {problem}")]
    Format { file: String, problem: String },
}

impl DatError {
    /// The file (or origin) the error is about.
    pub fn file(&self) -> &str {
        match self {
            DatError::Io { file, .. } | DatError::Format { file, .. } => file,
        }
    }
}

/// Reads and parses a `.dat` file; errors name it by its path as given.
pub fn read_dat(path: &Path) -> Result<LcpProblem, DatError> {
    let origin = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| DatError::Io {
        file: origin.clone(),
        message: e.to_string(),
    })?;
    parse_dat(&text, &origin)
}

/// Parses the text of a `.dat` file; `origin` names it in errors.
pub fn parse_dat(text: &str, origin: &str) -> Result<LcpProblem, DatError> {
    let fail = |problem: String| DatError::Format {
        file: origin.to_string(),
        problem,
    };
    let mut tokens = Tokens {
        text,
        pos: 0,
        count: 0,
    };

    let mut header = |what: &str| -> Result<usize, DatError> {
        let Some(tok) = tokens.next() else {
            return Err(fail(format!("file ends before the {what}")));
        };
        tok.parse::<usize>().map_err(|_| {
            fail(format!(
                "token {} '{tok}' ({what}) is not a non-negative integer",
                tokens.count
            ))
        })
    };
    let n = header("problem size n")?;
    let storage = header("storage flag")?;
    let shape = [
        header("matrix row count")?,
        header("matrix column count")?,
        header("repeated matrix row count")?,
        header("repeated matrix column count")?,
    ];
    if n == 0 {
        return Err(fail("problem size n is 0".into()));
    }
    if storage != 0 {
        return Err(fail(format!(
            "storage flag {storage} is not supported (only 0 = dense)"
        )));
    }
    if shape.iter().any(|&s| s != n) {
        return Err(fail(format!(
            "matrix shape {}×{} (repeated as {}×{}) does not match problem size {n}",
            shape[0], shape[1], shape[2], shape[3]
        )));
    }

    let mut numbers = |count: usize, what: &str| -> Result<Vec<f64>, DatError> {
        let mut out = Vec::with_capacity(count);
        while out.len() < count {
            let Some(tok) = tokens.next() else {
                return Err(fail(format!(
                    "expected {count} {what}, found {}",
                    out.len()
                )));
            };
            match tok.parse::<f64>() {
                Ok(v) if v.is_finite() => out.push(v),
                Ok(_) => {
                    return Err(fail(format!(
                        "token {} '{tok}' ({what}) is not a finite number",
                        tokens.count
                    )))
                }
                Err(_) => {
                    return Err(fail(format!(
                        "token {} '{tok}' ({what}) is not a number",
                        tokens.count
                    )))
                }
            }
        }
        Ok(out)
    };
    let m = numbers(n * n, "matrix entries")?;
    let q = numbers(n, "entries of q")?;
    let comment = tokens.rest().trim().to_string();
    Ok(LcpProblem {
        m: DMatrix::from_row_slice(n, n, &m),
        q: DVector::from_vec(q),
        comment,
    })
}

/// Whitespace tokenizer that counts tokens (1-based in messages) and keeps the rest.
struct Tokens<'a> {
    text: &'a str,
    pos: usize,
    count: usize,
}

impl<'a> Tokens<'a> {
    fn next(&mut self) -> Option<&'a str> {
        let rest = &self.text[self.pos..];
        let start = rest.find(|c: char| !c.is_whitespace())?;
        let tail = &rest[start..];
        let len = tail.find(char::is_whitespace).unwrap_or(tail.len());
        self.pos += start + len;
        self.count += 1;
        Some(&tail[..len])
    }

    fn rest(&self) -> &'a str {
        &self.text[self.pos..]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_header_matrix_rows_q_and_comment() {
        let p = parse_dat("2\n0\n2\n2\n2 2\n1 2\n3 4\n-5 6\n# hello\n", "x.dat").unwrap();
        assert_eq!(p.m[(0, 1)], 2.0);
        assert_eq!(p.m[(1, 0)], 3.0);
        assert_eq!(p.q.as_slice(), &[-5.0, 6.0]);
        assert_eq!(p.comment, "# hello");
    }

    #[test]
    fn round_trips_through_to_dat_string() {
        let p = parse_dat("2 0 2 2 2 2 0.1 -2e-7 3 4 -5 6 some words", "x.dat").unwrap();
        let again = parse_dat(&p.to_dat_string(), "y.dat").unwrap();
        assert_eq!(p, again);
    }
}
