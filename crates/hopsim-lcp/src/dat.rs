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
//!
//! The reader is bounded ([`DatLimits`]): it reads at most [`MAX_DAT_BYTES`] of a file and
//! stops at the first NUL byte (so `/dev/zero`, `/dev/urandom` or a pipe that never ends is
//! an error, not an exhausted memory), and it
//! accepts problems up to [`MAX_DAT_DIMENSION`]; memory is only reserved for values the
//! file actually holds, so a header declaring a huge `n` over a few numbers is an error
//! naming the count, not an 80 GB allocation. The environment variables
//! [`MAX_BYTES_ENV`] and [`MAX_DIMENSION_ENV`] raise the limits of [`read_dat`].

use crate::LcpProblem;
use nalgebra::{DMatrix, DVector};
use std::io::Read;
use std::path::Path;

/// Largest `.dat` file [`read_dat`] reads by default, bytes (64 MiB).
pub const MAX_DAT_BYTES: u64 = 64 << 20;
/// Largest problem size `n` accepted by default (a dense `M` of 10⁸ entries, 800 MB).
pub const MAX_DAT_DIMENSION: usize = 10_000;
/// Environment variable that raises (or lowers) the file-size limit of [`read_dat`], bytes.
pub const MAX_BYTES_ENV: &str = "HOPSIM_LCP_MAX_BYTES";
/// Environment variable that raises (or lowers) the problem-size limit of [`read_dat`].
pub const MAX_DIMENSION_ENV: &str = "HOPSIM_LCP_MAX_N";

/// How much a `.dat` reader accepts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DatLimits {
    /// Largest file read, bytes.
    pub max_bytes: u64,
    /// Largest problem size `n`.
    pub max_dimension: usize,
}

impl Default for DatLimits {
    /// [`MAX_DAT_BYTES`] and [`MAX_DAT_DIMENSION`].
    fn default() -> Self {
        Self {
            max_bytes: MAX_DAT_BYTES,
            max_dimension: MAX_DAT_DIMENSION,
        }
    }
}

impl DatLimits {
    /// The defaults, overridden by [`MAX_BYTES_ENV`] and [`MAX_DIMENSION_ENV`] when they
    /// hold a non-negative integer (other values are ignored).
    pub fn from_env() -> Self {
        let var = |name: &str| std::env::var(name).ok()?.trim().parse::<u64>().ok();
        let default = Self::default();
        Self {
            max_bytes: var(MAX_BYTES_ENV).unwrap_or(default.max_bytes),
            max_dimension: var(MAX_DIMENSION_ENV)
                .and_then(|n| usize::try_from(n).ok())
                .unwrap_or(default.max_dimension),
        }
    }
}

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

/// Reads and parses a `.dat` file with the limits of [`DatLimits::from_env`]; errors name
/// it by its path as given.
pub fn read_dat(path: &Path) -> Result<LcpProblem, DatError> {
    read_dat_with(path, &DatLimits::from_env())
}

/// Reads and parses a `.dat` file within `limits`. A regular file above
/// `limits.max_bytes` is refused unread; any other input (a pipe, a device) is read in
/// blocks and refused at its first NUL byte (a `.dat` file is text) or at the limit.
pub fn read_dat_with(path: &Path, limits: &DatLimits) -> Result<LcpProblem, DatError> {
    let origin = path.display().to_string();
    let io = |message: String| DatError::Io {
        file: origin.clone(),
        message,
    };
    let too_large = || {
        io(format!(
            "the file is larger than the {} limit of .dat files (set {MAX_BYTES_ENV} to \
             raise it)",
            bytes_text(limits.max_bytes)
        ))
    };
    let mut file = std::fs::File::open(path).map_err(|e| io(e.to_string()))?;
    if file
        .metadata()
        .is_ok_and(|m| m.is_file() && m.len() > limits.max_bytes)
    {
        return Err(too_large());
    }
    let mut bytes = Vec::new();
    let mut block = vec![0u8; 1 << 16];
    loop {
        let n = match file.read(&mut block) {
            Ok(0) => break,
            Ok(n) => n,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
            Err(e) => return Err(io(e.to_string())),
        };
        if let Some(i) = block[..n].iter().position(|&b| b == 0) {
            return Err(io(format!(
                "not a text file (NUL byte at offset {})",
                bytes.len() + i
            )));
        }
        if (bytes.len() + n) as u64 > limits.max_bytes {
            return Err(too_large());
        }
        bytes.extend_from_slice(&block[..n]);
    }
    let text = String::from_utf8(bytes).map_err(|e| {
        io(format!(
            "not a text file (invalid UTF-8 at offset {})",
            e.utf8_error().valid_up_to()
        ))
    })?;
    parse_dat_with(&text, &origin, limits)
}

/// `64 MiB`, `2 GiB`, `80.0 GB`, `100 bytes`.
fn bytes_text(bytes: u64) -> String {
    const MIB: u64 = 1 << 20;
    const GIB: u64 = 1 << 30;
    match bytes {
        b if b >= GIB && b % GIB == 0 => format!("{} GiB", b / GIB),
        b if b >= MIB && b % MIB == 0 => format!("{} MiB", b / MIB),
        b if b >= 1_000_000_000 => format!("{:.1} GB", b as f64 / 1e9),
        b if b >= 1_000_000 => format!("{:.1} MB", b as f64 / 1e6),
        b => format!("{b} bytes"),
    }
}

/// Parses the text of a `.dat` file within the default [`DatLimits`]; `origin` names it
/// in errors.
pub fn parse_dat(text: &str, origin: &str) -> Result<LcpProblem, DatError> {
    parse_dat_with(text, origin, &DatLimits::default())
}

/// Parses the text of a `.dat` file, accepting problem sizes up to
/// `limits.max_dimension` (`limits.max_bytes` is not checked here: the text is already in
/// memory).
pub fn parse_dat_with(
    text: &str,
    origin: &str,
    limits: &DatLimits,
) -> Result<LcpProblem, DatError> {
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
    if n > limits.max_dimension {
        // A file too short for its header is broken whatever the limit: say so first.
        let needed = (n as u128) * (n as u128) + n as u128;
        let present = tokens.rest().split_whitespace().count();
        if (present as u128) < needed {
            return Err(fail(format!(
                "problem size n = {n} needs {needed} numbers (M and q) after the header, \
                 found {present}"
            )));
        }
        return Err(fail(format!(
            "problem size n = {n} is above the limit of {} (a dense {n}×{n} M would take \
             {}); set {MAX_DIMENSION_ENV}={n} to read it anyway",
            limits.max_dimension,
            bytes_text((n as u64).saturating_mul(n as u64).saturating_mul(8)),
        )));
    }

    let mut numbers = |count: usize, what: &str| -> Result<Vec<f64>, DatError> {
        // Reserve only for values the text can hold: a token takes at least two bytes
        // (a digit and a separator), so a huge declared size over a short file costs
        // nothing before the count is found short.
        let mut out = Vec::with_capacity(count.min(tokens.remaining_bound()));
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
    // n ≤ max_dimension, so n² fits (checked anyway for a limit raised to usize::MAX).
    let entries = n
        .checked_mul(n)
        .ok_or_else(|| fail(format!("problem size n = {n} is too large")))?;
    let m = numbers(entries, "matrix entries")?;
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

    /// An upper bound on the number of tokens left.
    fn remaining_bound(&self) -> usize {
        (self.text.len() - self.pos).div_ceil(2)
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
