//! The MJCF text as the importer reads it: one tree of [`Element`]s with every `<include>`
//! expanded in place (each element keeps the file and line it was written at), the `<default>`
//! classes resolved into [`Defaults`], and attributes read as numbers with errors at their
//! element.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use crate::import::ImportError;

/// How deep `<include>`s may nest (a file that includes itself is refused before this).
const MAX_INCLUDE_DEPTH: usize = 16;

/// An element of the model, `<include>`s expanded.
#[derive(Debug)]
pub(super) struct Element {
    pub(super) tag: String,
    attrs: Vec<(String, String)>,
    pub(super) children: Vec<Element>,
    /// The included file it was written in (`None`: the model's own file).
    pub(super) file: Option<PathBuf>,
    /// Its 1-based line in that file.
    pub(super) line: usize,
}

impl Element {
    /// The attribute written on the element itself.
    pub(super) fn own(&self, name: &str) -> Option<&str> {
        self.attrs
            .iter()
            .find(|(k, _)| k == name)
            .map(|(_, v)| v.as_str())
    }
    /// The child elements with that tag.
    pub(super) fn each<'a>(&'a self, tag: &'a str) -> impl Iterator<Item = &'a Element> + 'a {
        self.children.iter().filter(move |c| c.tag == tag)
    }
    /// The error `message` at this element's line.
    pub(super) fn error(&self, message: impl Into<String>) -> ImportError {
        ImportError::new(message)
            .called("<mjcf>")
            .at_file(self.file.clone(), Some(self.line))
    }
}

/// Parses `text` (the file `path`, `None` for a string) into elements, expanding each
/// `<include file="…"/>` with the children of the included file's `<mujoco>` root; include paths
/// are relative to `dir`, the main model file's directory, as MuJoCo resolves them.
pub(super) fn parse(
    text: &str,
    file: Option<PathBuf>,
    dir: Option<&Path>,
) -> Result<Element, ImportError> {
    parse_at(text, file, dir, &mut Vec::new())
}

fn parse_at(
    text: &str,
    file: Option<PathBuf>,
    dir: Option<&Path>,
    open: &mut Vec<PathBuf>,
) -> Result<Element, ImportError> {
    let doc = roxmltree::Document::parse(text).map_err(|e| {
        let pos = e.pos();
        ImportError::new(format!("malformed XML: {e}"))
            .called("<mjcf>")
            .at_file(file.clone(), Some(pos.row as usize))
    })?;
    let root = doc.root_element();
    let mut out = convert(&doc, root, &file);
    expand(&mut out, dir, open)?;
    Ok(out)
}

fn convert(doc: &roxmltree::Document, node: roxmltree::Node, file: &Option<PathBuf>) -> Element {
    Element {
        tag: node.tag_name().name().to_string(),
        attrs: node
            .attributes()
            .map(|a| (a.name().to_string(), a.value().to_string()))
            .collect(),
        children: node
            .children()
            .filter(|c| c.is_element())
            .map(|c| convert(doc, c, file))
            .collect(),
        file: file.clone(),
        line: doc.text_pos_at(node.range().start).row as usize,
    }
}

/// Replaces every `<include>` below `el` by the children of the file it names.
fn expand(
    el: &mut Element,
    dir: Option<&Path>,
    open: &mut Vec<PathBuf>,
) -> Result<(), ImportError> {
    let mut children = Vec::with_capacity(el.children.len());
    for mut child in std::mem::take(&mut el.children) {
        if child.tag != "include" {
            expand(&mut child, dir, open)?;
            children.push(child);
            continue;
        }
        let Some(name) = child.own("file") else {
            return Err(child.error("`<include>` needs a `file` attribute"));
        };
        let Some(dir) = dir else {
            return Err(child.error(format!(
                "`<include file=\"{name}\">` in a description given as text: load the file \
                 from disk so that the included file can be found"
            )));
        };
        let path = dir.join(name);
        if open.contains(&path) || open.len() >= MAX_INCLUDE_DEPTH {
            return Err(child.error(format!("`{name}` includes itself")));
        }
        let text = std::fs::read_to_string(&path)
            .map_err(|e| child.error(format!("cannot read the included file `{name}`: {e}")))?;
        open.push(path.clone());
        let included = parse_at(&text, Some(path), Some(dir), open)?;
        open.pop();
        if included.tag != "mujoco" {
            return Err(included.error(format!(
                "an included file has a `<mujoco>` root, found `<{}>`",
                included.tag
            )));
        }
        children.extend(included.children);
    }
    el.children = children;
    Ok(())
}

/// The `<default>` classes: per class, per element tag, the attributes it sets, each class
/// holding what it inherits from the classes around it.
#[derive(Default)]
pub(super) struct Defaults {
    classes: HashMap<String, HashMap<String, Vec<(String, String)>>>,
}

/// The class every element falls back to.
pub(super) const MAIN: &str = "main";

impl Defaults {
    /// The classes of every `<default>` section of `root` (a `<mujoco>`).
    pub(super) fn read(root: &Element) -> Result<Defaults, ImportError> {
        let mut out = Defaults::default();
        out.classes.insert(MAIN.to_string(), HashMap::new());
        for section in root.each("default") {
            let class = section.own("class").unwrap_or(MAIN).to_string();
            out.class(section, &class, MAIN)?;
        }
        Ok(out)
    }

    fn class(&mut self, el: &Element, class: &str, parent: &str) -> Result<(), ImportError> {
        let mut own = if class == parent {
            self.classes.get(class).cloned().unwrap_or_default()
        } else {
            if self.classes.contains_key(class) {
                return Err(el.error(format!("default class `{class}` is defined twice")));
            }
            self.classes.get(parent).cloned().unwrap_or_default()
        };
        for child in &el.children {
            if child.tag == "default" {
                continue;
            }
            let attrs = own.entry(child.tag.clone()).or_default();
            for (k, v) in &child.attrs {
                match attrs.iter_mut().find(|(name, _)| name == k) {
                    Some(slot) => slot.1 = v.clone(),
                    None => attrs.push((k.clone(), v.clone())),
                }
            }
        }
        self.classes.insert(class.to_string(), own);
        for nested in el.each("default") {
            let Some(name) = nested.own("class") else {
                return Err(nested.error("a nested `<default>` needs a `class`"));
            };
            self.class(nested, name, class)?;
        }
        Ok(())
    }

    /// Whether the class is defined.
    pub(super) fn has(&self, class: &str) -> bool {
        self.classes.contains_key(class)
    }

    /// The attribute `name` of `el`: its own, else the one its class sets for its tag.
    pub(super) fn get<'a>(&'a self, el: &'a Element, class: &str, name: &str) -> Option<&'a str> {
        el.own(name).or_else(|| {
            self.classes
                .get(class)?
                .get(&el.tag)?
                .iter()
                .find(|(k, _)| k == name)
                .map(|(_, v)| v.as_str())
        })
    }
}

/// An element with the class its attributes default from.
#[derive(Clone, Copy)]
pub(super) struct Classed<'a> {
    pub(super) el: &'a Element,
    pub(super) class: &'a str,
    pub(super) defaults: &'a Defaults,
}

impl<'a> Classed<'a> {
    /// The attribute, own or from the class.
    pub(super) fn get(&self, name: &str) -> Option<&'a str> {
        self.defaults.get(self.el, self.class, name)
    }
    /// The attribute's numbers (whitespace-separated, each finite), or `None` where absent.
    pub(super) fn numbers(&self, name: &str) -> Result<Option<Vec<f64>>, ImportError> {
        let Some(text) = self.get(name) else {
            return Ok(None);
        };
        text.split_whitespace()
            .map(|t| match t.parse::<f64>() {
                Ok(x) if x.is_finite() => Ok(x),
                _ => Err(self.el.error(format!(
                    "`<{} {name}=\"{text}\">`: `{t}` is not a finite number",
                    self.el.tag
                ))),
            })
            .collect::<Result<Vec<_>, _>>()
            .map(Some)
    }
    /// Exactly `N` numbers, or `None` where the attribute is absent.
    pub(super) fn array<const N: usize>(
        &self,
        name: &str,
    ) -> Result<Option<[f64; N]>, ImportError> {
        let Some(v) = self.numbers(name)? else {
            return Ok(None);
        };
        <[f64; N]>::try_from(v.as_slice()).map(Some).map_err(|_| {
            self.el.error(format!(
                "`<{} {name}>` expects {N} numbers, found {}",
                self.el.tag,
                v.len()
            ))
        })
    }
    /// Between `min` and `max` numbers (MuJoCo fills the rest), or `None` where absent.
    pub(super) fn some(
        &self,
        name: &str,
        min: usize,
        max: usize,
    ) -> Result<Option<Vec<f64>>, ImportError> {
        let Some(v) = self.numbers(name)? else {
            return Ok(None);
        };
        if v.len() < min || v.len() > max {
            return Err(self.el.error(format!(
                "`<{} {name}>` expects {min} to {max} numbers, found {}",
                self.el.tag,
                v.len()
            )));
        }
        Ok(Some(v))
    }
    /// One number, `default` where absent.
    pub(super) fn number(&self, name: &str, default: f64) -> Result<f64, ImportError> {
        Ok(self.array::<1>(name)?.map_or(default, |[x]| x))
    }
    /// A keyword among `allowed` (the first where absent).
    pub(super) fn keyword(&self, name: &str, allowed: &[&'a str]) -> Result<&'a str, ImportError> {
        let first = allowed.first().copied().unwrap_or("");
        let Some(text) = self.get(name) else {
            return Ok(first);
        };
        allowed.iter().copied().find(|a| *a == text).ok_or_else(|| {
            self.el.error(format!(
                "`<{} {name}=\"{text}\">`: expected one of {}",
                self.el.tag,
                allowed
                    .iter()
                    .map(|a| format!("`{a}`"))
                    .collect::<Vec<_>>()
                    .join(", ")
            ))
        })
    }
}
