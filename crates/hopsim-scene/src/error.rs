//! Scene errors a person can act on: where (file:line:column or the `--set` override),
//! which key, what was found and what was expected.

use crate::tree::Origin;
use std::path::{Path, PathBuf};

/// Where an invalid value was written.
#[derive(Clone, Debug, PartialEq)]
pub enum Location {
    /// A position in the scene file (1-based line and column).
    File {
        path: PathBuf,
        line: usize,
        column: usize,
    },
    /// A command-line override, as the user gave it ([`crate::Override::text`]).
    Override(String),
}

impl std::fmt::Display for Location {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Location::File { path, line, column } => {
                write!(f, "{}:{line}:{column}", path.display())
            }
            Location::Override(text) => write!(f, "{text}"),
        }
    }
}

/// Why a scene cannot be loaded.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The file cannot be read.
    #[error("{}: {source}", path.display())]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    /// The file is not valid TOML.
    #[error("{location}: TOML syntax error: {message}")]
    Syntax { location: Location, message: String },
    /// A value is missing, of the wrong type, out of range, or refers to nothing.
    #[error("{location}: {key}: {message}")]
    Invalid {
        location: Location,
        /// Dotted path of the key, e.g. `bodies[1].mass` or `controller.torque`.
        key: String,
        message: String,
    },
    /// A `--set` argument that is not `key=value`.
    #[error("{text}: {message}")]
    Override { text: String, message: String },
    /// A MuJoCo model that cannot be read or has no scene (the message names its place).
    #[error("{0}")]
    Import(String),
}

impl SceneError {
    /// The dotted key an [`SceneError::Invalid`] is about.
    pub fn key(&self) -> Option<&str> {
        match self {
            SceneError::Invalid { key, .. } => Some(key),
            _ => None,
        }
    }

    /// Where the error is, if it has a place.
    pub fn location(&self) -> Option<&Location> {
        match self {
            SceneError::Invalid { location, .. } | SceneError::Syntax { location, .. } => {
                Some(location)
            }
            _ => None,
        }
    }
}

/// The scene file being read: turns origins into locations.
#[derive(Clone, Copy)]
pub struct Source<'a> {
    pub path: &'a Path,
    pub text: &'a str,
}

impl Source<'_> {
    /// The location of `origin`.
    pub fn locate(&self, origin: &Origin) -> Location {
        match origin {
            Origin::File(span) => self.locate_offset(span.start),
            Origin::Override(text) => Location::Override(text.clone()),
        }
    }

    /// The file location of byte `offset` (1-based line and column, columns in chars).
    pub fn locate_offset(&self, offset: usize) -> Location {
        let offset = offset.min(self.text.len());
        let before = &self.text[..offset];
        let line = before.matches('\n').count() + 1;
        let line_start = before.rfind('\n').map_or(0, |i| i + 1);
        let column = self.text[line_start..offset].chars().count() + 1;
        Location::File {
            path: self.path.to_path_buf(),
            line,
            column,
        }
    }

    /// An [`SceneError::Invalid`] at `origin`.
    pub fn invalid(&self, origin: &Origin, key: &str, message: impl Into<String>) -> SceneError {
        SceneError::Invalid {
            location: self.locate(origin),
            key: key.to_string(),
            message: message.into(),
        }
    }
}

pub use hopsim_io::number;

/// At most `max` of `items` joined by ", ", then "… (N more)".
pub fn short_list<'a>(items: impl IntoIterator<Item = &'a str>, max: usize) -> String {
    let items: Vec<&str> = items.into_iter().collect();
    if items.len() <= max {
        return items.join(", ");
    }
    format!(
        "{}, … ({} more)",
        items[..max].join(", "),
        items.len() - max
    )
}

/// The candidate closest to `word` by edit distance, if it is close enough to be a likely
/// typo (distance ≤ max(1, len/3)).
pub fn did_you_mean<'a>(
    word: &str,
    candidates: impl IntoIterator<Item = &'a str>,
) -> Option<&'a str> {
    let limit = (word.chars().count() / 3).max(1);
    candidates
        .into_iter()
        .map(|c| (edit_distance(word, c), c))
        .filter(|&(d, _)| d <= limit)
        .min_by_key(|&(d, _)| d)
        .map(|(_, c)| c)
}

/// Edit distance over chars, case-insensitive: insertions, deletions, substitutions and
/// transpositions of neighbours each cost one (optimal string alignment).
fn edit_distance(a: &str, b: &str) -> usize {
    let a: Vec<char> = a.to_lowercase().chars().collect();
    let b: Vec<char> = b.to_lowercase().chars().collect();
    let mut d = vec![vec![0usize; b.len() + 1]; a.len() + 1];
    for (i, row) in d.iter_mut().enumerate() {
        row[0] = i;
    }
    for (j, cell) in d[0].iter_mut().enumerate() {
        *cell = j;
    }
    for i in 1..=a.len() {
        for j in 1..=b.len() {
            let cost = usize::from(a[i - 1] != b[j - 1]);
            let mut v = (d[i - 1][j] + 1)
                .min(d[i][j - 1] + 1)
                .min(d[i - 1][j - 1] + cost);
            if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                v = v.min(d[i - 2][j - 2] + 1);
            }
            d[i][j] = v;
        }
    }
    d[a.len()][b.len()]
}

/// `"; did you mean 'x'?"` or nothing.
pub fn suggestion<'a>(word: &str, candidates: impl IntoIterator<Item = &'a str>) -> String {
    did_you_mean(word, candidates)
        .map(|c| format!("; did you mean '{c}'?"))
        .unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn typos_get_suggestions_and_unrelated_words_do_not() {
        let keys = ["mass", "inertia", "name", "parent"];
        assert_eq!(did_you_mean("mas", keys), Some("mass"));
        assert_eq!(did_you_mean("intertia", keys), Some("inertia"));
        assert_eq!(did_you_mean("Mass", keys), Some("mass"));
        assert_eq!(did_you_mean("nmae", keys), Some("name"));
        assert_eq!(did_you_mean("colour", keys), None);
    }

    #[test]
    fn numbers_in_messages_are_short_and_exact() {
        assert_eq!(number(1e308), "1e308");
        assert_eq!(number(-1.5e-308), "-1.5e-308");
        assert_eq!(number(0.1), "0.1");
        assert_eq!(number(-0.431), "-0.431");
        assert_eq!(number(30.0), "30");
        assert_eq!(number(0.0002), "0.0002");
        assert_eq!(number(2e-5), "2e-5");
        assert_eq!(number(f64::INFINITY), "inf");
        assert_eq!(number(1.0 / 3.0), "0.3333333333333333");
        for v in [
            1e308,
            1.0 / 3.0,
            2e-5,
            123456789.125,
            f64::MIN_POSITIVE,
            5e-324,
        ] {
            assert!(number(v).len() <= 24, "{v}");
            assert_eq!(number(v).parse::<f64>().unwrap(), v);
        }
    }

    #[test]
    fn long_lists_are_cut() {
        assert_eq!(short_list(["a", "b"], 3), "a, b");
        assert_eq!(short_list(["a", "b", "c", "d"], 2), "a, b, … (2 more)");
    }

    #[test]
    fn offsets_become_one_based_lines_and_columns() {
        let text = "a = 1\nbé = 2\n";
        let src = Source {
            path: Path::new("s.toml"),
            text,
        };
        let at = |o| src.locate_offset(o).to_string();
        assert_eq!(at(0), "s.toml:1:1");
        assert_eq!(at(6), "s.toml:2:1");
        assert_eq!(at(text.find('=').unwrap()), "s.toml:1:3");
        assert_eq!(at(text.rfind('=').unwrap()), "s.toml:2:4");
    }
}
