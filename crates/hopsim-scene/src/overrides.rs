//! `--set path.to.key=value`: overrides applied to the parsed tree before validation, so an
//! overridden value is type-checked exactly like one written in the file (and an error
//! names the `--set` argument).
//!
//! Path segments are table keys; in an array, a segment is an index (`initial.q.1`) or the
//! `name` of a table in an array of tables (`bodies.disc.mass`).
//!
//! `controller.type` set to another type switches the controller: the keys the file gave
//! the old type are dropped (keys set by other overrides stay), so that
//! `--set controller.type=passive` works on any scene and a new type takes its keys from
//! further `--set` arguments.

use crate::error::{suggestion, SceneError};
use crate::tree::{parse_override_value, Entry, Kind, Node, Origin};

/// One `--set key=value` argument, or a value another option (`--duration`, `--grid`)
/// sets in the scene.
#[derive(Clone, Debug, PartialEq)]
pub struct Override {
    /// Dotted key path, e.g. `controller.torque`.
    pub key: String,
    /// The value as typed (TOML syntax; bare words are strings).
    pub value: String,
    /// The command-line option it came from, named in errors: `--set` unless another.
    pub flag: &'static str,
}

impl Override {
    /// `--set key=value`.
    pub fn new(key: impl Into<String>, value: impl Into<String>) -> Self {
        Self::from_flag("--set", key, value)
    }

    /// `key = value` set by the option `flag` (e.g. `--duration` sets
    /// `simulation.duration`).
    pub fn from_flag(flag: &'static str, key: impl Into<String>, value: impl Into<String>) -> Self {
        Self {
            key: key.into(),
            value: value.into(),
            flag,
        }
    }

    /// The argument as the user gave it: `--set key=value`, or `--duration (key=value)`.
    pub fn text(&self) -> String {
        match self.flag {
            "--set" => format!("--set {}={}", self.key, self.value),
            flag => format!("{flag} ({}={})", self.key, self.value),
        }
    }
}

impl std::str::FromStr for Override {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let (key, value) = s
            .split_once('=')
            .ok_or_else(|| format!("'{s}': expected KEY=VALUE, e.g. controller.torque=0.2"))?;
        let key = key.trim();
        if key.is_empty() || key.split('.').any(|seg| seg.trim().is_empty()) {
            return Err(format!(
                "'{s}': the key must be a dotted path such as controller.torque"
            ));
        }
        Ok(Self::new(key, value.trim()))
    }
}

/// Applies `ov` to the document `root`.
pub fn apply(root: &mut Node, ov: &Override) -> Result<(), SceneError> {
    let text = ov.text();
    let fail = |message: String| SceneError::Override {
        text: text.clone(),
        message,
    };
    let segments: Vec<&str> = ov.key.split('.').map(str::trim).collect();
    let value = parse_override_value(&ov.value, &text);
    if segments == ["controller", "type"] {
        drop_keys_of_another_controller(root, &value);
    }
    let origin = Origin::Override(text.clone());
    let mut node = root;
    let mut walked = String::new();
    for (i, seg) in segments.iter().enumerate() {
        let last = i + 1 == segments.len();
        let here = if walked.is_empty() {
            "the scene".to_string()
        } else {
            format!("'{walked}'")
        };
        node = match &mut node.kind {
            Kind::Table(entries) => {
                let pos = match entries.iter().position(|e| e.key == *seg) {
                    Some(pos) => pos,
                    None => {
                        let kind = if last {
                            value.kind.clone()
                        } else {
                            Kind::Table(Vec::new())
                        };
                        entries.push(Entry {
                            key: seg.to_string(),
                            key_origin: origin.clone(),
                            node: Node {
                                kind,
                                origin: origin.clone(),
                            },
                        });
                        entries.len() - 1
                    }
                };
                let entry = &mut entries[pos];
                if last {
                    check_replaceable(&entry.node, &value, &ov.key).map_err(&fail)?;
                    entry.key_origin = origin.clone();
                    entry.node = value.clone();
                }
                &mut entry.node
            }
            Kind::Array(items) => {
                let pos = (seg.parse::<usize>().ok())
                    .or_else(|| items.iter().position(|item| table_name(item) == Some(*seg)));
                let len = items.len();
                let names: Vec<&str> = items.iter().filter_map(table_name).collect();
                let hint = suggestion(seg, names.iter().copied());
                let Some(item) = pos.and_then(|p| items.get_mut(p)) else {
                    return Err(fail(format!(
                        "{here} is an array of {len}; '{seg}' is neither an index below {len} \
                         nor the name of one of its tables{hint}"
                    )));
                };
                if last {
                    check_replaceable(item, &value, &ov.key).map_err(&fail)?;
                    *item = value.clone();
                }
                item
            }
            other => {
                // Name the override that put the value there, if one did.
                let set_by = match &node.origin {
                    Origin::Override(by) if *by != text => format!(" (set by {by})"),
                    _ => String::new(),
                };
                return Err(fail(format!(
                    "{here} is {}{set_by}, not a table: cannot set '{seg}' inside it",
                    other.describe()
                )));
            }
        };
        if !walked.is_empty() {
            walked.push('.');
        }
        walked.push_str(seg);
    }
    Ok(())
}

/// Removes the keys the file gave `[controller]` when `new_type` is another controller
/// type than the file's (`passive` when it names none).
fn drop_keys_of_another_controller(root: &mut Node, new_type: &Node) {
    let Kind::Table(sections) = &mut root.kind else {
        return;
    };
    let Some(Kind::Table(keys)) = sections
        .iter_mut()
        .find(|e| e.key == "controller")
        .map(|e| &mut e.node.kind)
    else {
        return;
    };
    let old_type = keys.iter().find(|e| e.key == "type").map(|e| &e.node.kind);
    let switched = match (old_type, &new_type.kind) {
        (Some(Kind::Str(old)), Kind::Str(new)) => old != new,
        (None, Kind::Str(new)) => new != "passive",
        _ => false,
    };
    if switched {
        keys.retain(|e| e.key == "type" || matches!(e.key_origin, Origin::Override(_)));
    }
}

/// The `name` of a table in an array of tables.
fn table_name(item: &Node) -> Option<&str> {
    item.entries().iter().find_map(|e| match &e.node.kind {
        Kind::Str(n) if e.key == "name" => Some(n.as_str()),
        _ => None,
    })
}

/// A value may replace a value, not a table or an array of tables: a scene's sections
/// and `[[bodies]]` are set key by key.
fn check_replaceable(old: &Node, new: &Node, key: &str) -> Result<(), String> {
    let holds_tables = |n: &Node| match &n.kind {
        Kind::Table(_) => true,
        Kind::Array(items) => items.iter().any(|i| matches!(i.kind, Kind::Table(_))),
        _ => false,
    };
    if !holds_tables(old) || holds_tables(new) {
        return Ok(());
    }
    let what = match &old.kind {
        Kind::Table(_) => "a table",
        _ => "an array of tables",
    };
    let example = match &old.kind {
        Kind::Table(entries) => entries
            .first()
            .map(|e| format!(", e.g. --set {key}.{}=…", e.key))
            .unwrap_or_default(),
        _ => format!(", e.g. --set {key}.0.<key>=…"),
    };
    Err(format!(
        "'{key}' is {what} in the scene and cannot be replaced by {}; set its keys \
         instead{example}",
        new.kind.describe()
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn doc(text: &str) -> Node {
        Node::parse_document(text).unwrap()
    }

    fn get<'a>(node: &'a Node, key: &str) -> &'a Node {
        &node.entries().iter().find(|e| e.key == key).unwrap().node
    }

    #[test]
    fn overrides_replace_insert_and_index() {
        let mut root =
            doc("[c]\nt = 0.1\n[[bodies]]\nname = \"disc\"\nmass = 1.0\n[i]\nq = [0.0, 0.1]\n");
        for text in [
            "c.t=0.2",
            "c.mode=timed",
            "bodies.disc.mass=2",
            "i.q.1=0.5",
            "new.x=true",
        ] {
            apply(&mut root, &text.parse().unwrap()).unwrap();
        }
        assert!(matches!(get(get(&root, "c"), "t").kind, Kind::Float(v) if v == 0.2));
        assert!(matches!(&get(get(&root, "c"), "mode").kind, Kind::Str(s) if s == "timed"));
        let Kind::Array(bodies) = &get(&root, "bodies").kind else {
            panic!()
        };
        assert!(matches!(get(&bodies[0], "mass").kind, Kind::Int(2)));
        let Kind::Array(q) = &get(get(&root, "i"), "q").kind else {
            panic!()
        };
        assert!(matches!(q[1].kind, Kind::Float(v) if v == 0.5));
        assert_eq!(q[1].origin, Origin::Override("--set i.q.1=0.5".into()));
        assert!(matches!(get(get(&root, "new"), "x").kind, Kind::Bool(true)));
    }

    #[test]
    fn another_controller_type_drops_the_keys_of_the_old_one() {
        let file = "[controller]\ntype = \"pulse\"\njoint = \"leg\"\nforce = 2.0\n";
        let keys = |root: &Node| -> Vec<String> {
            let keys = get(root, "controller").entries().iter();
            let mut keys: Vec<String> = keys.map(|e| e.key.clone()).collect();
            keys.sort();
            keys
        };
        // The same type keeps every key.
        let mut root = doc(file);
        apply(&mut root, &"controller.type=pulse".parse().unwrap()).unwrap();
        assert_eq!(keys(&root), ["force", "joint", "type"]);
        // Another type drops the file's keys, not those set on the command line.
        let mut root = doc(file);
        apply(&mut root, &"controller.torque=0.3".parse().unwrap()).unwrap();
        apply(
            &mut root,
            &"controller.type=momentum_impulse".parse().unwrap(),
        )
        .unwrap();
        assert_eq!(keys(&root), ["torque", "type"]);
        let mut root = doc(file);
        apply(&mut root, &"controller.type=passive".parse().unwrap()).unwrap();
        assert_eq!(keys(&root), ["type"]);
        // A file without a type has the passive controller.
        let mut root = doc("[controller]\n");
        apply(&mut root, &"controller.type=passive".parse().unwrap()).unwrap();
        assert_eq!(keys(&root), ["type"]);
    }

    #[test]
    fn bad_paths_are_errors_naming_the_argument() {
        let mut root = doc("[c]\nt = 0.1\nq = [1.0]\n");
        let e = apply(&mut root, &"c.t.x=1".parse().unwrap())
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("--set c.t.x=1:") && e.contains("'c.t' is the number 0.1"),
            "{e}"
        );
        let e = apply(&mut root, &"c.q.4=1".parse().unwrap())
            .unwrap_err()
            .to_string();
        assert!(e.contains("array of 1"), "{e}");
        assert!(!e.contains("did you mean"), "{e}");
        assert!("novalue".parse::<Override>().is_err());
        assert!("a..b=1".parse::<Override>().is_err());
    }

    #[test]
    fn a_misspelt_table_name_gets_a_suggestion() {
        let mut root = doc(
            "[[bodies]]\nname = \"disc\"\nmass = 1.0\n[[bodies]]\nname = \"flywheel\"\nmass = 0.4\n",
        );
        let e = apply(&mut root, &"bodies.flywhel.mass=0.5".parse().unwrap())
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("--set bodies.flywhel.mass=0.5:")
                && e.ends_with("did you mean 'flywheel'?"),
            "{e}"
        );
        // A name far from every table's gets no guess.
        let e = apply(&mut root, &"bodies.cane.mass=0.5".parse().unwrap())
            .unwrap_err()
            .to_string();
        assert!(!e.contains("did you mean"), "{e}");
    }
}
