//! Errors and notices, each located at `file:line:column` and naming the element and, where
//! there is one, the attribute.

use std::fmt;
use std::sync::Arc;

/// Where something was written: the file (as given, or `<string>`), line and column (from 1).
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Location {
    pub file: Arc<str>,
    pub line: u32,
    pub column: u32,
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}:{}", self.file, self.line, self.column)
    }
}

/// What a message is about: the element and, where there is one, its attribute.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Subject {
    pub element: String,
    pub attribute: Option<String>,
}

impl fmt::Display for Subject {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.attribute {
            Some(a) => write!(f, "<{}> attribute `{}`", self.element, a),
            None => write!(f, "<{}>", self.element),
        }
    }
}

/// A model that cannot be read: outside the supported subset, malformed, or not planar.
#[derive(Debug, Clone, PartialEq)]
pub struct MjcfError {
    pub location: Location,
    /// Absent for errors of the whole document (an XML syntax error, an unreadable file).
    pub subject: Option<Subject>,
    pub message: String,
}

impl fmt::Display for MjcfError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.subject {
            Some(s) => write!(f, "{}: {}: {}", self.location, s, self.message),
            None => write!(f, "{}: {}", self.location, self.message),
        }
    }
}

impl std::error::Error for MjcfError {}

/// Why a part of the file was read and left without effect.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum NoticeKind {
    /// It has no meaning for a planar rigid-body simulation (visuals, solver settings, sensors).
    Ignored,
    /// A parameter of MuJoCo's soft contact or soft constraints; hopsim's contacts and stops
    /// are hard (complementarity with Newton restitution, docs/physics.md §4).
    NotApplicable,
    /// Physics that the planar model leaves out (only when [`ReadOptions::unmodelled`] allows
    /// it; by default this is an error).
    ///
    /// [`ReadOptions::unmodelled`]: crate::ReadOptions::unmodelled
    Unmodelled,
}

/// An attribute or element read and left without effect, with the reason.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Notice {
    pub kind: NoticeKind,
    pub location: Location,
    pub subject: Subject,
    pub reason: String,
}

impl fmt::Display for Notice {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let what = match self.kind {
            NoticeKind::Ignored => "ignored",
            NoticeKind::NotApplicable => "not applicable to hard contact",
            NoticeKind::Unmodelled => "NOT MODELLED",
        };
        write!(
            f,
            "{}: {}: {what}: {}",
            self.location, self.subject, self.reason
        )
    }
}

pub(crate) type Result<T> = std::result::Result<T, MjcfError>;

/// An error at `location` about `element` (and `attribute`).
pub(crate) fn located(
    location: &Location,
    element: &str,
    attribute: Option<&str>,
    message: impl Into<String>,
) -> MjcfError {
    MjcfError {
        location: location.clone(),
        subject: Some(Subject {
            element: element.to_string(),
            attribute: attribute.map(str::to_string),
        }),
        message: message.into(),
    }
}
