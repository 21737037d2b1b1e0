//! Typed, checked reading of one TOML table. Every getter records the key it asked for,
//! so [`Table::finish`] can reject the keys nobody asked for, with a "did you mean".

use crate::error::{did_you_mean, number, suggestion, Location, SceneError, Source};
use crate::tree::{Entry, Kind, Node, Origin};
use std::cell::RefCell;

pub use hopsim_sim::{MAX_COORDINATE, MAX_MAGNITUDE};

/// What a number must be, for checks and for messages.
#[derive(Clone, Copy, Debug)]
pub struct Num {
    /// Unit for messages, e.g. `"kg"` (empty: dimensionless).
    pub unit: &'static str,
    rule: Rule,
    /// Largest accepted magnitude.
    max: f64,
    /// Smallest accepted magnitude of a non-zero value (0: no bound).
    min: f64,
}

#[derive(Clone, Copy, Debug)]
enum Rule {
    Finite,
    Positive,
    NonNegative,
    Range(f64, f64),
}

impl Num {
    const fn new(unit: &'static str, rule: Rule) -> Self {
        Self {
            unit,
            rule,
            max: MAX_MAGNITUDE,
            min: 0.0,
        }
    }
    /// Any finite number (of magnitude at most [`MAX_MAGNITUDE`]).
    pub const fn any(unit: &'static str) -> Self {
        Self::new(unit, Rule::Finite)
    }
    /// A finite number `> 0`.
    pub const fn positive(unit: &'static str) -> Self {
        Self::new(unit, Rule::Positive)
    }
    /// A finite number `≥ 0`.
    pub const fn non_negative(unit: &'static str) -> Self {
        Self::new(unit, Rule::NonNegative)
    }
    /// A number in `lo ..= hi`.
    pub const fn range(lo: f64, hi: f64, unit: &'static str) -> Self {
        Self::new(unit, Rule::Range(lo, hi))
    }
    /// A position, length or angle: magnitude at most [`MAX_COORDINATE`].
    pub const fn coordinate(self) -> Self {
        self.at_most(MAX_COORDINATE)
    }
    /// Magnitude at most `max`.
    pub const fn at_most(mut self, max: f64) -> Self {
        self.max = max;
        self
    }
    /// A non-zero value of magnitude at least `min`.
    pub const fn at_least(mut self, min: f64) -> Self {
        self.min = min;
        self
    }

    /// `None` when `v` is accepted, else what was expected.
    pub(crate) fn check(&self, v: f64) -> Option<String> {
        let ok = v.is_finite()
            && match self.rule {
                Rule::Finite => true,
                Rule::Positive => v > 0.0,
                Rule::NonNegative => v >= 0.0,
                Rule::Range(lo, hi) => (lo..=hi).contains(&v),
            };
        if !ok {
            return Some(self.expected());
        }
        if matches!(self.rule, Rule::Range(..)) {
            return None;
        }
        if v.abs() > self.max {
            return Some(format!(
                "{} of magnitude at most {}",
                self.expected(),
                number(self.max)
            ));
        }
        if v != 0.0 && v.abs() < self.min {
            return Some(format!(
                "{} of magnitude at least {}",
                self.expected(),
                number(self.min)
            ));
        }
        None
    }

    /// "a positive number in kg", "a number in [0, 1]", …
    pub fn expected(&self) -> String {
        let what = match self.rule {
            Rule::Finite => "a finite number".to_string(),
            Rule::Positive => "a positive number".to_string(),
            Rule::NonNegative => "a non-negative number".to_string(),
            Rule::Range(lo, hi) => format!("a number in [{}, {}]", number(lo), number(hi)),
        };
        match self.unit {
            "" => what,
            unit => format!("{what} in {unit}"),
        }
    }
}

/// A table being read.
pub struct Table<'a> {
    src: Source<'a>,
    entries: &'a [Entry],
    origin: Origin,
    path: String,
    asked: RefCell<Vec<&'static str>>,
}

impl<'a> Table<'a> {
    /// The document's root table.
    pub fn root(src: Source<'a>, root: &'a Node) -> Self {
        Self::new(src, root.entries(), root.origin.clone(), String::new())
    }

    fn new(src: Source<'a>, entries: &'a [Entry], origin: Origin, path: String) -> Self {
        Self {
            src,
            entries,
            origin,
            path,
            asked: RefCell::new(Vec::new()),
        }
    }

    /// Dotted path of `key` in this table, e.g. `bodies[1].mass`.
    pub fn key_path(&self, key: &str) -> String {
        if self.path.is_empty() {
            key.to_string()
        } else {
            format!("{}.{key}", self.path)
        }
    }

    /// The raw node of `key`, marking the key as known.
    pub fn get(&self, key: &'static str) -> Option<&'a Node> {
        self.asked.borrow_mut().push(key);
        self.entries.iter().find(|e| e.key == key).map(|e| &e.node)
    }

    /// An error about `key` at `origin`.
    pub fn error(&self, origin: &Origin, key: &str, message: impl Into<String>) -> SceneError {
        self.src.invalid(origin, &self.key_path(key), message)
    }

    /// An error about `key` placed at its value (or at the table if it is absent).
    pub fn error_at_key(&self, key: &str, message: impl Into<String>) -> SceneError {
        let origin = self
            .entries
            .iter()
            .find(|e| e.key == key)
            .map_or(&self.origin, |e| &e.node.origin);
        self.error(origin, key, message)
    }

    /// An error about the table itself, placed at its header.
    pub fn error_here(&self, message: impl Into<String>) -> SceneError {
        self.src.invalid(&self.origin, &self.path, message)
    }

    /// Where the value of `key` was written (the table if it is absent).
    pub fn origin_of(&self, key: &str) -> Origin {
        self.entries
            .iter()
            .find(|e| e.key == key)
            .map_or(&self.origin, |e| &e.node.origin)
            .clone()
    }

    /// The location of `origin` in the scene file or the overrides.
    pub fn locate(&self, origin: &Origin) -> Location {
        self.src.locate(origin)
    }

    fn missing(&self, key: &str, expected: &str) -> SceneError {
        // A misspelling of the missing key is the likelier mistake: report that instead.
        if let Some(typo) = self
            .entries
            .iter()
            .find(|e| e.key != key && did_you_mean(&e.key, [key]).is_some())
        {
            return self.error(
                &typo.key_origin,
                &typo.key,
                format!("unknown key; did you mean '{key}'?"),
            );
        }
        let table = match self.path.as_str() {
            "" => "the scene".to_string(),
            p => format!("[{p}]"),
        };
        self.error(
            &self.origin,
            key,
            format!("missing in {table}; expected {expected}"),
        )
    }

    fn wrong(&self, key: &str, node: &Node, expected: &str) -> SceneError {
        let found = node.kind.describe();
        self.error(
            &node.origin,
            key,
            format!("expected {expected}, found {found}"),
        )
    }

    fn number(&self, key: &str, node: &Node, num: Num) -> Result<f64, SceneError> {
        let v = match node.kind {
            Kind::Float(v) => v,
            Kind::Int(i) => i as f64,
            _ => return Err(self.wrong(key, node, &num.expected())),
        };
        match num.check(v) {
            None => Ok(v),
            Some(expected) => Err(self.wrong(key, node, &expected)),
        }
    }

    /// A required number.
    pub fn f64(&self, key: &'static str, num: Num) -> Result<f64, SceneError> {
        match self.get(key) {
            Some(node) => self.number(key, node, num),
            None => Err(self.missing(key, &num.expected())),
        }
    }

    /// An optional number.
    pub fn opt_f64(&self, key: &'static str, num: Num) -> Result<Option<f64>, SceneError> {
        self.get(key).map(|n| self.number(key, n, num)).transpose()
    }

    /// A number with a default.
    pub fn f64_or(&self, key: &'static str, default: f64, num: Num) -> Result<f64, SceneError> {
        Ok(self.opt_f64(key, num)?.unwrap_or(default))
    }

    /// A boolean with a default.
    pub fn bool_or(&self, key: &'static str, default: bool) -> Result<bool, SceneError> {
        match self.get(key) {
            None => Ok(default),
            Some(Node {
                kind: Kind::Bool(b),
                ..
            }) => Ok(*b),
            Some(node) => Err(self.wrong(key, node, "true or false")),
        }
    }

    /// An optional string.
    pub fn opt_str(&self, key: &'static str) -> Result<Option<&'a str>, SceneError> {
        match self.get(key) {
            None => Ok(None),
            Some(Node {
                kind: Kind::Str(s), ..
            }) => Ok(Some(s)),
            Some(node) => Err(self.wrong(key, node, "a string")),
        }
    }

    /// A required string.
    pub fn str(&self, key: &'static str) -> Result<&'a str, SceneError> {
        self.opt_str(key)?
            .ok_or_else(|| self.missing(key, "a string"))
    }

    /// One of `options` (a string), or `default` when absent (`None`: required).
    pub fn choice(
        &self,
        key: &'static str,
        options: &[&'static str],
        default: Option<&'static str>,
    ) -> Result<&'a str, SceneError> {
        let expected = format!("one of {}", quoted(options));
        let Some(node) = self.get(key) else {
            return default.ok_or_else(|| self.missing(key, &expected));
        };
        let Kind::Str(s) = &node.kind else {
            return Err(self.wrong(key, node, &expected));
        };
        if options.contains(&s.as_str()) {
            return Ok(s);
        }
        let hint = suggestion(s, options.iter().copied());
        Err(self.error(
            &node.origin,
            key,
            format!("expected {expected}, found \"{s}\"{hint}"),
        ))
    }

    /// A list of values (`None` when absent), each read by `item` from its path
    /// (`key[i]`) and node; `len` fixes its length if given, `what` names the values in
    /// messages ("numbers (m)", "strings").
    fn opt_list<T>(
        &self,
        key: &'static str,
        len: Option<usize>,
        what: &str,
        item: impl Fn(&str, &'a Node) -> Result<T, SceneError>,
    ) -> Result<Option<Vec<T>>, SceneError> {
        let Some(node) = self.get(key) else {
            return Ok(None);
        };
        let expected = match len {
            Some(n) => format!("an array of {n} {what}"),
            None => format!("an array of {what}"),
        };
        let Kind::Array(items) = &node.kind else {
            return Err(self.wrong(key, node, &expected));
        };
        if len.is_some_and(|n| n != items.len()) {
            return Err(self.wrong(key, node, &expected));
        }
        items
            .iter()
            .enumerate()
            .map(|(i, node)| item(&format!("{key}[{i}]"), node))
            .collect::<Result<Vec<_>, _>>()
            .map(Some)
    }

    /// A list of numbers (`None` when absent); `len` fixes its length if given.
    pub fn opt_f64_list(
        &self,
        key: &'static str,
        len: Option<usize>,
        num: Num,
    ) -> Result<Option<Vec<f64>>, SceneError> {
        let what = format!("numbers ({})", num.expected());
        self.opt_list(key, len, &what, |path, node| self.number(path, node, num))
    }

    /// A list of strings (`None` when absent); `len` fixes its length if given.
    pub fn opt_str_list(
        &self,
        key: &'static str,
        len: Option<usize>,
    ) -> Result<Option<Vec<&'a str>>, SceneError> {
        self.opt_list(key, len, "strings", |path, node| match &node.kind {
            Kind::Str(s) => Ok(s.as_str()),
            _ => Err(self.wrong(path, node, "a string")),
        })
    }

    /// A 2-vector `[x, y]` with a default (`None`: required).
    pub fn vec2(
        &self,
        key: &'static str,
        default: Option<[f64; 2]>,
        unit: &'static str,
    ) -> Result<[f64; 2], SceneError> {
        match self.opt_f64_list(key, Some(2), Num::any(unit).coordinate())? {
            Some(v) => Ok([v[0], v[1]]),
            None => default.ok_or_else(|| self.missing(key, &format!("[x, y] in {unit}"))),
        }
    }

    /// A required list of 2-vectors `[[x, y], …]`.
    pub fn vec2_list(
        &self,
        key: &'static str,
        unit: &'static str,
    ) -> Result<Vec<[f64; 2]>, SceneError> {
        let expected = format!("an array of [x, y] points in {unit}");
        let Some(node) = self.get(key) else {
            return Err(self.missing(key, &expected));
        };
        let Kind::Array(items) = &node.kind else {
            return Err(self.wrong(key, node, &expected));
        };
        items
            .iter()
            .enumerate()
            .map(|(i, item)| match &item.kind {
                Kind::Array(xy) if xy.len() == 2 => {
                    let path = format!("{key}[{i}]");
                    let num = Num::any(unit).coordinate();
                    Ok([
                        self.number(&path, &xy[0], num)?,
                        self.number(&path, &xy[1], num)?,
                    ])
                }
                _ => Err(self.wrong(&format!("{key}[{i}]"), item, &format!("[x, y] in {unit}"))),
            })
            .collect()
    }

    /// An optional sub-table.
    pub fn opt_table(&self, key: &'static str) -> Result<Option<Table<'a>>, SceneError> {
        match self.get(key) {
            None => Ok(None),
            Some(
                node @ Node {
                    kind: Kind::Table(entries),
                    ..
                },
            ) => Ok(Some(Table::new(
                self.src,
                entries,
                node.origin.clone(),
                self.key_path(key),
            ))),
            Some(node) => Err(self.wrong(key, node, "a table")),
        }
    }

    /// A sub-table that may be absent (then read as empty, placed at this table).
    pub fn table_or_empty(&self, key: &'static str) -> Result<Table<'a>, SceneError> {
        Ok(self
            .opt_table(key)?
            .unwrap_or_else(|| Table::new(self.src, &[], self.origin.clone(), self.key_path(key))))
    }

    /// An array of tables (`[[key]]`); empty when absent.
    pub fn tables(&self, key: &'static str) -> Result<Vec<Table<'a>>, SceneError> {
        let Some(node) = self.get(key) else {
            return Ok(Vec::new());
        };
        let Kind::Array(items) = &node.kind else {
            return Err(self.wrong(key, node, &format!("an array of tables ([[{key}]])")));
        };
        items
            .iter()
            .enumerate()
            .map(|(i, item)| match &item.kind {
                Kind::Table(entries) => Ok(Table::new(
                    self.src,
                    entries,
                    item.origin.clone(),
                    format!("{}[{i}]", self.key_path(key)),
                )),
                _ => Err(self.wrong(&format!("{key}[{i}]"), item, "a table")),
            })
            .collect()
    }

    /// Declares the keys this table may hold and rejects any other at once (so a misspelt
    /// section is reported before the sections it was meant to fill are found missing).
    pub fn allow_only(&self, keys: &[&'static str]) -> Result<(), SceneError> {
        self.asked.borrow_mut().extend_from_slice(keys);
        self.finish()
    }

    /// Rejects every key that no getter asked for, suggesting the closest known key.
    pub fn finish(&self) -> Result<(), SceneError> {
        let asked = self.asked.borrow();
        for e in self.entries {
            if asked.contains(&e.key.as_str()) {
                continue;
            }
            let hint = suggestion(&e.key, asked.iter().copied());
            let known = if hint.is_empty() && !asked.is_empty() {
                let mut keys: Vec<&str> = asked.clone();
                keys.sort_unstable();
                keys.dedup();
                format!("; known keys here: {}", keys.join(", "))
            } else {
                hint
            };
            return Err(self.error(&e.key_origin, &e.key, format!("unknown key{known}")));
        }
        Ok(())
    }
}

/// `"a", "b" or "c"`.
fn quoted(options: &[&str]) -> String {
    let q: Vec<String> = options.iter().map(|o| format!("\"{o}\"")).collect();
    match q.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} or {last}", rest.join(", ")),
        _ => q.join(""),
    }
}
