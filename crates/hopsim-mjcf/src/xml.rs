//! The XML layer: files read within bounds, parsed by `roxmltree`, turned into a small owned
//! tree of elements whose every element and attribute keeps its `file:line:column`, with
//! `<include file="…"/>` replaced by the children of the included file's root.

use std::collections::HashSet;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::error::{located, Location, MjcfError, Result};

/// The largest model file read (each file, includes alike).
pub const MAX_FILE_BYTES: u64 = 8 << 20;
/// The deepest chain of includes.
pub const MAX_INCLUDE_DEPTH: usize = 8;
/// The most XML nodes in one file.
const MAX_NODES: u32 = 1_000_000;

/// One attribute as written.
#[derive(Debug, Clone)]
pub(crate) struct Attr {
    pub name: String,
    pub value: String,
    pub loc: Location,
}

/// One element as written, includes spliced in.
#[derive(Debug, Clone)]
pub(crate) struct Element {
    pub name: String,
    pub loc: Location,
    pub attrs: Vec<Attr>,
    pub children: Vec<Element>,
}

impl Element {
    pub fn attr(&self, name: &str) -> Option<&Attr> {
        self.attrs.iter().find(|a| a.name == name)
    }

    /// An error about this element, or about its attribute `attr` (located there).
    pub fn error(&self, attr: Option<&str>, message: impl Into<String>) -> MjcfError {
        let loc = attr
            .and_then(|a| self.attr(a))
            .map_or(&self.loc, |a| &a.loc);
        located(loc, &self.name, attr, message)
    }
}

/// Reads files and resolves includes relative to the main file's folder, as MuJoCo does.
struct Loader {
    base_dir: Option<PathBuf>,
    included: HashSet<PathBuf>,
}

/// The root element of the model file at `path`, includes spliced in.
pub(crate) fn load_file(path: &Path) -> Result<Element> {
    let name: Arc<str> = path.display().to_string().into();
    let text = read_bounded(path, &name)?;
    let mut loader = Loader {
        base_dir: Some(path.parent().unwrap_or(Path::new("")).to_path_buf()),
        included: HashSet::from([path.canonicalize().unwrap_or_else(|_| path.to_path_buf())]),
    };
    loader.parse(&text, name, 0)
}

/// The root element of the model text `text`, named `name` in messages; includes are
/// resolved in `base_dir` (an include without one is an error).
pub(crate) fn load_str(text: &str, name: &str, base_dir: Option<&Path>) -> Result<Element> {
    if text.len() as u64 > MAX_FILE_BYTES {
        return Err(whole(
            name.into(),
            format!(
                "the model is larger than the {} MiB limit",
                MAX_FILE_BYTES >> 20
            ),
        ));
    }
    let mut loader = Loader {
        base_dir: base_dir.map(Path::to_path_buf),
        included: HashSet::new(),
    };
    loader.parse(text, name.into(), 0)
}

fn whole(file: Arc<str>, message: String) -> MjcfError {
    MjcfError {
        location: Location {
            file,
            line: 1,
            column: 1,
        },
        subject: None,
        message,
    }
}

/// The file's text, refused above [`MAX_FILE_BYTES`] or when it is not UTF-8.
fn read_bounded(path: &Path, name: &Arc<str>) -> Result<String> {
    let fail = |m: String| whole(name.clone(), m);
    let file = std::fs::File::open(path).map_err(|e| fail(format!("cannot read: {e}")))?;
    let mut bytes = Vec::new();
    file.take(MAX_FILE_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| fail(format!("cannot read: {e}")))?;
    if bytes.len() as u64 > MAX_FILE_BYTES {
        return Err(fail(format!(
            "the file is larger than the {} MiB limit of model files",
            MAX_FILE_BYTES >> 20
        )));
    }
    String::from_utf8(bytes).map_err(|e| {
        let ok = &e.as_bytes()[..e.utf8_error().valid_up_to()];
        let line = ok.iter().filter(|&&b| b == b'\n').count() as u32 + 1;
        let column =
            (ok.len() - ok.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1)) as u32 + 1;
        MjcfError {
            location: Location {
                file: name.clone(),
                line,
                column,
            },
            subject: None,
            message: "not UTF-8 text (not an MJCF file?)".into(),
        }
    })
}

impl Loader {
    fn parse(&mut self, text: &str, file: Arc<str>, depth: usize) -> Result<Element> {
        let options = roxmltree::ParsingOptions {
            allow_dtd: false,
            nodes_limit: MAX_NODES,
            ..Default::default()
        };
        let doc = roxmltree::Document::parse_with_options(text, options).map_err(|e| {
            let pos = e.pos();
            MjcfError {
                location: Location {
                    file: file.clone(),
                    line: pos.row,
                    column: pos.col,
                },
                subject: None,
                message: format!("not well-formed XML: {e}"),
            }
        })?;
        let at = |offset: usize| {
            let p = doc.text_pos_at(offset);
            Location {
                file: file.clone(),
                line: p.row,
                column: p.col,
            }
        };
        self.convert(doc.root_element(), &at, depth)
    }

    fn convert(
        &mut self,
        node: roxmltree::Node,
        at: &dyn Fn(usize) -> Location,
        depth: usize,
    ) -> Result<Element> {
        let mut element = Element {
            name: node.tag_name().name().to_string(),
            loc: at(node.range().start),
            attrs: node
                .attributes()
                .map(|a| Attr {
                    name: a.name().to_string(),
                    value: a.value().to_string(),
                    loc: at(a.range().start),
                })
                .collect(),
            children: Vec::new(),
        };
        for child in node.children().filter(roxmltree::Node::is_element) {
            if child.tag_name().name() == "include" {
                let include = self.convert(child, at, depth)?;
                element.children.extend(self.include(&include, depth + 1)?);
            } else {
                element.children.push(self.convert(child, at, depth)?);
            }
        }
        Ok(element)
    }

    /// The children of the root of the file that `include` names.
    fn include(&mut self, include: &Element, depth: usize) -> Result<Vec<Element>> {
        if let Some(a) = include.attrs.iter().find(|a| a.name != "file") {
            return Err(include.error(Some(&a.name), "unknown attribute; expected only `file`"));
        }
        let Some(file) = include.attr("file") else {
            return Err(include.error(None, "missing attribute `file`"));
        };
        if !include.children.is_empty() {
            return Err(include.error(None, "an include must be empty"));
        }
        if depth > MAX_INCLUDE_DEPTH {
            return Err(include.error(
                Some("file"),
                format!("includes are nested deeper than {MAX_INCLUDE_DEPTH} levels"),
            ));
        }
        let Some(base) = &self.base_dir else {
            return Err(include.error(
                Some("file"),
                "a model read from text has no folder to resolve includes in",
            ));
        };
        let path = base.join(&file.value);
        let key = path.canonicalize().unwrap_or_else(|_| path.clone());
        if !self.included.insert(key) {
            return Err(include.error(
                Some("file"),
                format!("`{}` is included more than once", file.value),
            ));
        }
        let name: Arc<str> = path.display().to_string().into();
        let text = read_bounded(&path, &name).map_err(|e| {
            include.error(
                Some("file"),
                format!("cannot include `{}`: {}", file.value, e),
            )
        })?;
        Ok(self.parse(&text, name, depth)?.children)
    }
}
