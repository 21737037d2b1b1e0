//! An owned TOML tree in which every value remembers where it came from: a byte range of
//! the scene file, or a `--set` override. Validation errors point there.

use crate::error::number;
use toml::de::{DeTable, DeValue};
use toml::Spanned;

/// Deepest nesting of arrays and tables a scene may use (a scene needs 3: `[[shapes]]`,
/// `vertices`, a vertex); deeper input is rejected before it can exhaust the stack.
pub const MAX_DEPTH: usize = 32;

/// Why a parsed value cannot become a [`Node`]: a message and the byte range it is about.
pub type TreeError = (String, Option<std::ops::Range<usize>>);

/// Where a value was written.
#[derive(Clone, Debug, PartialEq)]
pub enum Origin {
    /// Byte range in the scene file.
    File(std::ops::Range<usize>),
    /// A command-line override, e.g. `--set controller.torque=0.2`.
    Override(String),
}

/// A TOML value with its origin.
#[derive(Clone, Debug)]
pub struct Node {
    pub kind: Kind,
    pub origin: Origin,
}

/// The TOML value kinds hopsim scenes use.
#[derive(Clone, Debug)]
pub enum Kind {
    Str(String),
    Int(i64),
    Float(f64),
    Bool(bool),
    Array(Vec<Node>),
    Table(Vec<Entry>),
    /// A TOML date-time: never valid in a scene, kept to report it.
    Datetime(String),
}

/// One `key = value` of a table.
#[derive(Clone, Debug)]
pub struct Entry {
    pub key: String,
    /// Where the key itself was written.
    pub key_origin: Origin,
    pub node: Node,
}

impl Kind {
    /// What the value is, for messages ("a number", "a string 'abc'", "a table", …).
    pub fn describe(&self) -> String {
        match self {
            Kind::Str(s) => format!("the string \"{s}\""),
            Kind::Int(i) => format!("the integer {i}"),
            Kind::Float(f) => format!("the number {}", number(*f)),
            Kind::Bool(b) => format!("the boolean {b}"),
            Kind::Array(a) => format!("an array of {} values", a.len()),
            Kind::Table(_) => "a table".into(),
            Kind::Datetime(d) => format!("the date-time {d}"),
        }
    }
}

impl Node {
    /// Converts a parsed TOML value (borrowing the source text) into an owned node.
    pub fn from_toml(value: &Spanned<DeValue<'_>>) -> Result<Self, TreeError> {
        Self::from_toml_at(value, 0)
    }

    fn from_toml_at(value: &Spanned<DeValue<'_>>, depth: usize) -> Result<Self, TreeError> {
        let span = value.span();
        if depth > MAX_DEPTH {
            return Err((
                format!("arrays and tables nested more than {MAX_DEPTH} deep"),
                Some(span),
            ));
        }
        let origin = Origin::File(span.clone());
        let kind = match value.get_ref() {
            DeValue::String(s) => Kind::Str(s.to_string()),
            DeValue::Integer(i) => Kind::Int(
                i64::from_str_radix(i.as_str(), i.radix())
                    .map_err(|_| (format!("integer {i} does not fit in 64 bits"), Some(span)))?,
            ),
            DeValue::Float(f) => Kind::Float(parse_float(f.as_str())),
            DeValue::Boolean(b) => Kind::Bool(*b),
            DeValue::Datetime(d) => Kind::Datetime(d.to_string()),
            DeValue::Array(a) => Kind::Array(
                a.iter()
                    .map(|v| Node::from_toml_at(v, depth + 1))
                    .collect::<Result<Vec<_>, _>>()?,
            ),
            DeValue::Table(t) => Kind::Table(entries(t, depth + 1)?),
        };
        Ok(Node { kind, origin })
    }

    /// Parses a whole document into a table node; a syntax error comes with its message
    /// and byte range.
    pub fn parse_document(text: &str) -> Result<Self, TreeError> {
        let table = DeTable::parse(text).map_err(|e| (e.message().to_string(), e.span()))?;
        let kind = Kind::Table(entries(table.get_ref(), 0)?);
        Ok(Node {
            kind,
            origin: Origin::File(table.span()),
        })
    }

    /// The value as a [`toml::Value`] (a date-time that TOML cannot read back becomes its
    /// text).
    pub fn to_toml(&self) -> toml::Value {
        match &self.kind {
            Kind::Str(s) => toml::Value::String(s.clone()),
            Kind::Int(i) => toml::Value::Integer(*i),
            Kind::Float(f) => toml::Value::Float(*f),
            Kind::Bool(b) => toml::Value::Boolean(*b),
            Kind::Datetime(d) => d
                .parse()
                .map_or_else(|_| toml::Value::String(d.clone()), toml::Value::Datetime),
            Kind::Array(items) => toml::Value::Array(items.iter().map(Node::to_toml).collect()),
            Kind::Table(_) => toml::Value::Table(self.to_toml_table()),
        }
    }

    /// The entries of a table node as a [`toml::Table`] (empty for any other kind).
    pub fn to_toml_table(&self) -> toml::Table {
        self.entries()
            .iter()
            .map(|e| (e.key.clone(), e.node.to_toml()))
            .collect()
    }

    /// The entries of a table node (empty for any other kind).
    pub fn entries(&self) -> &[Entry] {
        match &self.kind {
            Kind::Table(e) => e,
            _ => &[],
        }
    }
}

fn entries(table: &DeTable<'_>, depth: usize) -> Result<Vec<Entry>, TreeError> {
    table
        .iter()
        .map(|(k, v)| {
            Ok(Entry {
                key: k.get_ref().to_string(),
                key_origin: Origin::File(k.span()),
                node: Node::from_toml_at(v, depth)?,
            })
        })
        .collect()
}

/// TOML float text to `f64` (`inf`, `nan` and `_` separators included).
fn parse_float(text: &str) -> f64 {
    let clean: String = text.chars().filter(|&c| c != '_').collect();
    match clean.trim_start_matches(['+', '-']) {
        "inf" => {
            if clean.starts_with('-') {
                f64::NEG_INFINITY
            } else {
                f64::INFINITY
            }
        }
        "nan" => f64::NAN,
        _ => clean.parse().unwrap_or(f64::NAN),
    }
}

/// Parses a `--set` value: any TOML value (`0.2`, `true`, `[1, 2]`, `"text"`), else the
/// raw text as a string (so `--set controller.cane_mode=timed` needs no quotes).
pub fn parse_override_value(text: &str, origin: &str) -> Node {
    let origin = Origin::Override(origin.to_string());
    let mut node = DeValue::parse(text.trim())
        .ok()
        .and_then(|v| Node::from_toml(&v).ok())
        .filter(|n| !matches!(n.kind, Kind::Table(_) | Kind::Datetime(_)))
        .unwrap_or(Node {
            kind: Kind::Str(text.to_string()),
            origin: origin.clone(),
        });
    set_origin(&mut node, &origin);
    node
}

fn set_origin(node: &mut Node, origin: &Origin) {
    node.origin = origin.clone();
    if let Kind::Array(items) = &mut node.kind {
        for item in items {
            set_origin(item, origin);
        }
    }
}
