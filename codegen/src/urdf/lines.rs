//! Finding lines in the URDF text, which urdf-rs does not give, with roxmltree (an XML parser
//! that keeps every node's position): the line of each `<link>` and `<joint>` element, for the
//! importer's errors ([`ElementLines`]), and the line a parse error comes from
//! ([`parse_error_line`]): the first bad tag of malformed XML, else the first `<link>` or
//! `<joint>` element that urdf-rs refuses on its own. Also the one attribute the importer reads
//! that urdf-rs does not: a joint's `<dynamics armature="…">` ([`ElementLines::armature`]).

use roxmltree::{Document, Error, Node, ParsingOptions, TextPos};

use super::read_robot;

/// The text as roxmltree reads it; a DTD is allowed, as urdf-rs allows it.
fn parse(text: &str) -> Result<Document<'_>, Error> {
    let options = ParsingOptions {
        allow_dtd: true,
        ..ParsingOptions::default()
    };
    Document::parse_with_options(text, options)
}

/// The 1-based line of `node`.
fn line_of(node: Node) -> usize {
    node.document().text_pos_at(node.range().start).row as usize
}

/// The robot's `<element>` children (`link` or `joint`), in document order.
fn robot_elements<'a, 'input>(
    doc: &'a Document<'input>,
    element: &'a str,
) -> impl Iterator<Item = Node<'a, 'input>> + 'a {
    doc.root_element()
        .children()
        .filter(move |n| n.is_element() && n.tag_name().name() == element)
}

/// The lines of the robot's `<link>` and `<joint>` elements, by name.
pub(super) struct ElementLines {
    /// Element (`link` or `joint`), `name` attribute and line, in document order.
    elements: Vec<(&'static str, String, usize)>,
    /// Per `<joint>` element, in document order: its name and the text of its
    /// `<dynamics armature="…">`, if any.
    armatures: Vec<(String, Option<String>)>,
}

impl ElementLines {
    /// The elements of `text`; none if roxmltree finds the XML malformed where urdf-rs read it
    /// (the importer's errors then name no line).
    pub(super) fn new(text: &str) -> Self {
        let mut elements = Vec::new();
        let mut armatures = Vec::new();
        if let Ok(doc) = parse(text) {
            for element in ["link", "joint"] {
                for node in robot_elements(&doc, element) {
                    let name = node.attribute("name").unwrap_or_default().to_string();
                    elements.push((element, name.clone(), line_of(node)));
                    if element == "joint" {
                        let armature = node
                            .children()
                            .filter(|n| n.is_element() && n.tag_name().name() == "dynamics")
                            .find_map(|n| n.attribute("armature"))
                            .map(str::to_string);
                        armatures.push((name, armature));
                    }
                }
            }
        }
        ElementLines {
            elements,
            armatures,
        }
    }

    /// The `armature` attribute of the `n`-th (0-based) `<joint>` named `name`'s `<dynamics>`:
    /// not in URDF 1.0, but what MuJoCo and Pinocchio call the rotor inertia, and what some
    /// exporters write there.
    pub(super) fn armature(&self, name: &str, n: usize) -> Option<&str> {
        self.armatures
            .iter()
            .filter(|(na, _)| na == name)
            .nth(n)
            .and_then(|(_, a)| a.as_deref())
    }

    /// The line of the `n`-th (0-based) `<element>` (`link` or `joint`) named `name`.
    pub(super) fn line(&self, element: &str, name: &str, n: usize) -> Option<usize> {
        self.elements
            .iter()
            .filter(|(e, na, _)| *e == element && na == name)
            .nth(n)
            .map(|(_, _, line)| *line)
    }
}

/// The line urdf-rs's parse error most likely comes from: for malformed XML, the first bad tag;
/// for well-formed XML, the first `<link>` or `<joint>` element that fails to read on its own.
pub(super) fn parse_error_line(text: &str) -> Option<usize> {
    match parse(text) {
        Err(e) => malformed_line(text, &e),
        Ok(doc) => ["link", "joint"].into_iter().find_map(|element| {
            robot_elements(&doc, element)
                .find(|node| {
                    // An element from an entity's expansion may have no text of its own.
                    let Some(element) = text.get(node.range()) else {
                        return false;
                    };
                    read_robot(&format!("<robot name=\"x\">{element}</robot>")).is_err()
                })
                .map(line_of)
        }),
    }
}

/// The line of the first bad tag of malformed XML.
fn malformed_line(text: &str, e: &Error) -> Option<usize> {
    match e {
        // `<a><b></a>`: `<b>` is the one left open; a closing tag that closes no open element is
        // the bad one itself.
        Error::UnexpectedCloseTag(_, closing, pos) => {
            let open = offset(text, *pos).and_then(|at| open_elements(text, at));
            match open.as_deref().and_then(<[_]>::split_last) {
                Some((innermost, outer)) if outer.iter().any(|(name, _)| name == closing) => {
                    Some(innermost.1)
                }
                _ => Some(pos.row as usize),
            }
        }
        // The text ends with elements open: the outermost is the first never closed; or it ends
        // inside a tag.
        Error::UnclosedRootNode => match open_elements(text, text.len()) {
            Some(open) => open.first().map(|(_, line)| *line),
            None => Some(last_line(text)),
        },
        // The text ends inside a tag, a comment or a declaration.
        Error::UnexpectedEndOfStream => Some(last_line(text)),
        // No element, or the text ends inside the first: where it ends.
        Error::NoRootNode => (!text.trim().is_empty()).then(|| last_line(text)),
        // A limit: no line to name.
        Error::DtdDetected
        | Error::NodesLimitReached
        | Error::AttributesLimitReached
        | Error::NamespacesLimitReached => None,
        other => Some(other.pos().row as usize),
    }
}

/// The line where `text` ends.
fn last_line(text: &str) -> usize {
    text.matches('\n').count() + 1
}

/// The byte offset of `pos` (row and column in characters, 1-based) in `text`.
fn offset(text: &str, pos: TextPos) -> Option<usize> {
    let row_start = match pos.row {
        0 | 1 => 0,
        row => text.match_indices('\n').nth(row as usize - 2)?.0 + 1,
    };
    let col = (pos.col as usize).checked_sub(1)?;
    let row = &text[row_start..];
    let in_row = row
        .char_indices()
        .map(|(k, _)| k)
        .chain([row.len()])
        .nth(col)?;
    Some(row_start + in_row)
}

/// The elements still open at byte `at` of `text` (outermost first), with their lines, where
/// `text[..at]` is well-formed but for the elements it leaves open. roxmltree names them from the
/// innermost out: after the prefix and the closing tags found so far, a closing tag that matches
/// no element is reported as the wrong one to close the innermost still open. Once all are
/// closed the prefix parses, and the open elements are those that end past `at`.
fn open_elements(text: &str, at: usize) -> Option<Vec<(String, usize)>> {
    const NOTHING: &str = "</articulated:closes-nothing>";
    let prefix = text.get(..at)?;
    let mut closers = String::new();
    let mut names = Vec::new();
    for _ in 0..=prefix.matches('<').count() {
        let closed = format!("{prefix}{closers}");
        if let Ok(doc) = parse(&closed) {
            let lines: Vec<usize> = doc
                .descendants()
                .filter(|n| n.is_element() && n.range().end > at)
                .map(line_of)
                .collect();
            return (lines.len() == names.len())
                .then(|| names.into_iter().rev().zip(lines).collect());
        }
        match parse(&format!("{closed}{NOTHING}")) {
            Err(Error::UnexpectedCloseTag(open, _, _)) => {
                closers.push_str(&format!("</{open}>"));
                names.push(open);
            }
            _ => return None,
        }
    }
    None
}
