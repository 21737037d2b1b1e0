//! Typed attributes of an element with its default class, the table of what each element's
//! attributes mean here, and the notices for those read without effect.

use std::collections::HashSet;

use crate::error::{located, Location, MjcfError, Notice, NoticeKind, Result, Subject};
use crate::xml::{Attr, Element};

/// What an attribute is to the planar reader.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Treat {
    /// Read by the reader.
    Read,
    /// Without meaning here (visuals, solver settings): a notice with the reason.
    Ignore(&'static str),
    /// A parameter of MuJoCo's soft contact or constraints: a notice.
    Soft,
    /// Physics outside the subset: an error unless the value is the neutral one (or
    /// [`crate::ReadOptions::unmodelled`] turns it into a notice).
    Unless(Neutral, &'static str),
}

/// The value of an unsupported attribute that means "off".
#[derive(Debug, Clone, Copy)]
pub(crate) enum Neutral {
    /// Every number is 0.
    Zero,
    /// This word.
    Word(&'static str),
    /// None: any value is an error.
    Never,
}

pub(crate) type Table = &'static [(&'static str, Treat)];

pub(crate) const SOFT: &str = "a parameter of MuJoCo's soft contact and constraints: hopsim's contacts and joint stops are hard (complementarity with Newton's restitution)";
pub(crate) const VISUAL: &str = "visual only";

/// Reading state shared by every element: options, notices, the angle unit.
pub(crate) struct Context {
    pub unmodelled_allowed: bool,
    pub notices: Vec<Notice>,
    seen: HashSet<(Location, String)>,
}

impl Context {
    pub fn new(unmodelled_allowed: bool) -> Self {
        Self {
            unmodelled_allowed,
            notices: Vec::new(),
            seen: HashSet::new(),
        }
    }

    /// Records a notice once per place.
    pub fn notice(
        &mut self,
        kind: NoticeKind,
        loc: &Location,
        element: &str,
        attribute: Option<&str>,
        reason: &str,
    ) {
        if self
            .seen
            .insert((loc.clone(), attribute.unwrap_or("").to_string()))
        {
            self.notices.push(Notice {
                kind,
                location: loc.clone(),
                subject: Subject {
                    element: element.to_string(),
                    attribute: attribute.map(str::to_string),
                },
                reason: reason.to_string(),
            });
        }
    }

    /// Physics outside the subset: an error, or a notice when the caller allows it.
    pub fn unmodelled(
        &mut self,
        loc: &Location,
        element: &str,
        attribute: Option<&str>,
        reason: &str,
    ) -> Result<()> {
        if self.unmodelled_allowed {
            self.notice(NoticeKind::Unmodelled, loc, element, attribute, reason);
            Ok(())
        } else {
            Err(located(
                loc,
                element,
                attribute,
                format!("not supported: {reason}"),
            ))
        }
    }

    /// A whole element without meaning here.
    pub fn ignore_element(&mut self, e: &Element, reason: &str) {
        self.notice(NoticeKind::Ignored, &e.loc, &e.name, None, reason);
    }
}

/// Checks that `defaults` (an element in a `<default>` class) names only attributes in `table`.
pub(crate) fn check_names(e: &Element, table: Table) -> Result<()> {
    for a in &e.attrs {
        if a.name != "class" && !table.iter().any(|(n, _)| *n == a.name) {
            return Err(unknown(e, a, table));
        }
    }
    Ok(())
}

fn unknown(e: &Element, a: &Attr, table: Table) -> MjcfError {
    let known: Vec<&str> = table.iter().map(|(n, _)| *n).collect();
    let hint = known
        .iter()
        .filter(|k| close(k, &a.name))
        .map(|k| format!(" (did you mean `{k}`?)"))
        .next()
        .unwrap_or_default();
    located(
        &a.loc,
        &e.name,
        Some(&a.name),
        format!(
            "unknown attribute{hint}; <{}> takes {}",
            e.name,
            known.join(", ")
        ),
    )
}

/// Whether two names differ by at most one edit or one swap.
fn close(a: &str, b: &str) -> bool {
    let (a, b): (Vec<char>, Vec<char>) = (a.chars().collect(), b.chars().collect());
    if a.len().abs_diff(b.len()) > 1 {
        return false;
    }
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    for i in 1..=a.len() {
        let mut cur = vec![i; b.len() + 1];
        for j in 1..=b.len() {
            let cost = usize::from(a[i - 1] != b[j - 1]);
            cur[j] = (prev[j] + 1).min(cur[j - 1] + 1).min(prev[j - 1] + cost);
        }
        prev = cur;
    }
    prev[b.len()] <= 1
}

/// An element seen through its default class: its own attributes first, then the class's.
#[derive(Clone, Copy)]
pub(crate) struct View<'a> {
    pub elem: &'a Element,
    pub defaults: &'a [Attr],
}

impl<'a> View<'a> {
    pub fn new(elem: &'a Element, defaults: &'a [Attr]) -> Self {
        Self { elem, defaults }
    }

    pub fn get(&self, name: &str) -> Option<&'a Attr> {
        self.elem
            .attr(name)
            .or_else(|| self.defaults.iter().find(|a| a.name == name))
    }

    pub fn error_at(&self, a: &Attr, message: impl Into<String>) -> MjcfError {
        located(&a.loc, &self.elem.name, Some(&a.name), message)
    }

    /// An error about the attribute `name`, located where it is written (in the element or
    /// its class), or at the element when it is missing.
    pub fn error_for(&self, name: &str, message: impl Into<String>) -> MjcfError {
        let loc = self.get(name).map_or(&self.elem.loc, |a| &a.loc);
        located(loc, &self.elem.name, Some(name), message)
    }

    pub fn error(&self, message: impl Into<String>) -> MjcfError {
        located(&self.elem.loc, &self.elem.name, None, message)
    }

    /// Checks every attribute against `table`: unknown names are errors, ignored and soft
    /// ones notices, unsupported physics an error unless neutral.
    pub fn check(&self, table: Table, ctx: &mut Context) -> Result<()> {
        for a in &self.elem.attrs {
            if a.name != "class"
                && a.name != "childclass"
                && !table.iter().any(|(n, _)| *n == a.name)
            {
                return Err(unknown(self.elem, a, table));
            }
        }
        for (name, treat) in table {
            let Some(a) = self.get(name) else { continue };
            match treat {
                Treat::Read => {}
                Treat::Ignore(why) => ctx.notice(
                    NoticeKind::Ignored,
                    &a.loc,
                    &self.elem.name,
                    Some(name),
                    why,
                ),
                Treat::Soft => ctx.notice(
                    NoticeKind::NotApplicable,
                    &a.loc,
                    &self.elem.name,
                    Some(name),
                    SOFT,
                ),
                Treat::Unless(neutral, why) => {
                    let is_neutral = match neutral {
                        Neutral::Zero => {
                            numbers(&a.value).is_some_and(|v| v.iter().all(|x| *x == 0.0))
                        }
                        Neutral::Word(w) => a.value.trim() == *w,
                        Neutral::Never => false,
                    };
                    if !is_neutral {
                        ctx.unmodelled(&a.loc, &self.elem.name, Some(name), why)?;
                    }
                }
            }
        }
        Ok(())
    }

    pub fn string(&self, name: &str) -> Option<&'a str> {
        self.get(name).map(|a| a.value.as_str())
    }

    /// Exactly `N` numbers.
    pub fn vector<const N: usize>(&self, name: &str) -> Result<Option<[f64; N]>> {
        self.get(name).map(|a| self.values(a)).transpose()
    }

    /// The `N` numbers of the attribute `a`.
    pub fn values<const N: usize>(&self, a: &Attr) -> Result<[f64; N]> {
        let v = self.parse_numbers(a)?;
        <[f64; N]>::try_from(v.as_slice())
            .map_err(|_| self.error_at(a, format!("expected {N} numbers, found {}", v.len())))
    }

    /// One to `N` numbers, the rest taken from `fill`.
    pub fn up_to<const N: usize>(&self, name: &str, mut fill: [f64; N]) -> Result<[f64; N]> {
        let Some(a) = self.get(name) else {
            return Ok(fill);
        };
        let v = self.parse_numbers(a)?;
        if v.is_empty() || v.len() > N {
            return Err(self.error_at(a, format!("expected 1 to {N} numbers, found {}", v.len())));
        }
        fill[..v.len()].copy_from_slice(&v);
        Ok(fill)
    }

    pub fn number(&self, name: &str) -> Result<Option<f64>> {
        Ok(self.vector::<1>(name)?.map(|[x]| x))
    }

    pub fn number_or(&self, name: &str, default: f64) -> Result<f64> {
        Ok(self.number(name)?.unwrap_or(default))
    }

    /// A number that must not be negative.
    pub fn nonnegative(&self, name: &str, default: f64) -> Result<f64> {
        let Some(a) = self.get(name) else {
            return Ok(default);
        };
        let x = self.number_or(name, default)?;
        if x < 0.0 {
            return Err(self.error_at(a, "must not be negative"));
        }
        Ok(x)
    }

    pub fn integer(&self, name: &str, default: i64) -> Result<i64> {
        let Some(a) = self.get(name) else {
            return Ok(default);
        };
        a.value
            .trim()
            .parse()
            .map_err(|_| self.error_at(a, format!("expected an integer, found `{}`", a.value)))
    }

    /// One of `words`.
    pub fn word(&self, name: &str, words: &[&'static str]) -> Result<Option<&'static str>> {
        let Some(a) = self.get(name) else {
            return Ok(None);
        };
        let v = a.value.trim();
        words
            .iter()
            .find(|w| **w == v)
            .copied()
            .map(Some)
            .ok_or_else(|| {
                self.error_at(
                    a,
                    format!("expected one of {}, found `{v}`", words.join(", ")),
                )
            })
    }

    pub fn boolean(&self, name: &str, default: bool) -> Result<bool> {
        Ok(match self.word(name, &["true", "false"])? {
            Some(w) => w == "true",
            None => default,
        })
    }

    /// `limited`-style tri-state: `Some(true)`, `Some(false)`, or `None` for "auto".
    pub fn tristate(&self, name: &str) -> Result<Option<bool>> {
        Ok(match self.word(name, &["true", "false", "auto"])? {
            Some("true") => Some(true),
            Some("false") => Some(false),
            _ => None,
        })
    }

    fn parse_numbers(&self, a: &Attr) -> Result<Vec<f64>> {
        numbers(&a.value).ok_or_else(|| {
            self.error_at(
                a,
                format!(
                    "expected finite numbers separated by spaces, found `{}`",
                    a.value
                ),
            )
        })
    }
}

/// The finite numbers of a whitespace-separated list, or `None`.
pub(crate) fn numbers(text: &str) -> Option<Vec<f64>> {
    text.split_ascii_whitespace()
        .map(|t| t.parse::<f64>().ok().filter(|x| x.is_finite()))
        .collect()
}
