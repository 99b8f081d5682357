//! Finding lines in the URDF text, which urdf-rs does not give: the line of a parse error (the
//! first badly nested tag, else the first `<link>` or `<joint>` element that fails to read on its
//! own) and the line of the `n`-th element of a given name.

use super::read_robot;

/// The line urdf-rs's error most likely comes from: the first badly nested tag, else the first
/// `<link>` or `<joint>` element that fails to read on its own.
pub(super) fn locate_parse_error(text: &str) -> Option<usize> {
    if let Err(pos) = check_nesting(text) {
        return Some(line_at(text, pos));
    }
    for element in ["link", "joint"] {
        for (start, end) in element_blocks(text, element) {
            let alone = format!("<robot name=\"x\">{}</robot>", &text[start..end]);
            if read_robot(&alone).is_err() {
                return Some(line_at(text, start));
            }
        }
    }
    None
}

fn line_at(text: &str, pos: usize) -> usize {
    text[..pos.min(text.len())].matches('\n').count() + 1
}

/// Checks that tags nest; on failure the byte offset of the offending tag (a closing tag that
/// does not match, or an opening tag never closed).
fn check_nesting(text: &str) -> Result<(), usize> {
    let mut open: Vec<(&str, usize)> = Vec::new();
    let mut i = 0;
    while let Some(k) = text[i..].find('<') {
        let start = i + k;
        let rest = &text[start..];
        let (skip_to, tag) = if rest.starts_with("<!--") {
            (rest.find("-->").map(|e| e + 3), None)
        } else if rest.starts_with("<![CDATA[") {
            (rest.find("]]>").map(|e| e + 3), None)
        } else if rest.starts_with("<?") || rest.starts_with("<!") {
            (rest.find('>').map(|e| e + 1), None)
        } else {
            (
                rest.find('>').map(|e| e + 1),
                rest.find('>').map(|e| &rest[1..e]),
            )
        };
        let Some(len) = skip_to else {
            return Err(start);
        };
        i = start + len;
        let Some(tag) = tag else { continue };
        let name_of = |t: &str| -> String {
            t.chars()
                .take_while(|c| !c.is_whitespace() && *c != '/')
                .collect()
        };
        if let Some(closing) = tag.strip_prefix('/') {
            let name = name_of(closing.trim_start());
            match open.pop() {
                Some((o, _)) if name_of(o) == name => {}
                // `<a><b></a>`: `<b>` is the one left open.
                Some((_, o_start)) if open.iter().any(|(t, _)| name_of(t) == name) => {
                    return Err(o_start)
                }
                _ => return Err(start),
            }
        } else if !tag.ends_with('/') {
            open.push((tag, start));
        }
    }
    match open.first() {
        Some((_, start)) => Err(*start),
        None => Ok(()),
    }
}

/// Byte ranges of the `<element …/>` and `<element …>…</element>` elements in `text`.
fn element_blocks(text: &str, element: &str) -> Vec<(usize, usize)> {
    let open = format!("<{element}");
    let close = format!("</{element}>");
    let mut out = Vec::new();
    let mut from = 0;
    while let Some(k) = text[from..].find(&open) {
        let start = from + k;
        from = start + open.len();
        if !text[from..].starts_with(|c: char| c.is_whitespace() || c == '>' || c == '/') {
            continue;
        }
        let Some(gt) = text[from..].find('>') else {
            break;
        };
        let tag_end = from + gt + 1;
        let end = if text[..tag_end].ends_with("/>") {
            tag_end
        } else {
            match text[tag_end..].find(&close) {
                Some(c) => tag_end + c + close.len(),
                None => break,
            }
        };
        out.push((start, end));
        from = end;
    }
    out
}

/// The 1-based line of the `n`-th (0-based) `<element … name="name" …>` tag in `text`.
pub(super) fn find_line(text: &str, element: &str, name: &str, n: usize) -> Option<usize> {
    let open = format!("<{element}");
    let mut seen = 0;
    let mut from = 0;
    while let Some(k) = text[from..].find(&open) {
        let start = from + k;
        from = start + open.len();
        let rest = &text[from..];
        if !rest.starts_with(|c: char| c.is_whitespace() || c == '>' || c == '/') {
            continue;
        }
        let end = rest.find('>').unwrap_or(rest.len());
        if tag_attribute(&rest[..end], "name") == Some(name) {
            if seen == n {
                return Some(line_at(text, start));
            }
            seen += 1;
        }
    }
    None
}

/// The value of attribute `attr` in the inside of a tag (`a="x" b='y'`).
fn tag_attribute<'t>(mut tag: &'t str, attr: &str) -> Option<&'t str> {
    loop {
        tag = tag.trim_start();
        let eq = tag.find('=')?;
        let key = tag[..eq].trim();
        let rest = tag[eq + 1..].trim_start();
        let quote = rest.chars().next().filter(|c| *c == '"' || *c == '\'')?;
        let body = &rest[1..];
        let close = body.find(quote)?;
        if key == attr {
            return Some(&body[..close]);
        }
        tag = &body[close + 1..];
    }
}
