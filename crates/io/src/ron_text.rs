//! RON scene text: errors in our words, and where things are in the text.
//!
//! Places are found by one linear pass over the text ([`Outline`]), run
//! only when an error needs a place: it skips comments, strings and raw
//! strings and records where each top-level field and each element of
//! `objects: [...]` starts, so a message can point at the object it is
//! about even when the object has no distinctive text.

use crate::error::Error;
use std::path::Path;

/// A RON error in our words.
pub(crate) fn ron_error(path: &Path, src: &str, e: &ron::error::SpannedError) -> Error {
    use ron::Error as R;
    let list = |names: &[&str]| {
        // Hide the snake_case aliases when the PascalCase name is listed.
        let shown: Vec<String> = names
            .iter()
            .filter(|n| {
                !(n.starts_with(|c: char| c.is_ascii_lowercase())
                    && names
                        .iter()
                        .any(|m| m.to_ascii_lowercase() == n.replace('_', "") && m != *n))
            })
            .map(|n| format!("`{n}`"))
            .collect();
        shown.join(", ")
    };
    let msg = match &e.code {
        R::NoSuchStructField {
            expected,
            found,
            outer,
        } => format!(
            "unknown field `{found}`{}; expected one of {}",
            outer
                .as_ref()
                .map_or_else(String::new, |o| format!(" in `{o}`")),
            list(expected)
        ),
        R::NoSuchEnumVariant {
            expected,
            found,
            outer,
        } => format!(
            "unknown {} `{found}`; expected one of {}",
            outer
                .as_ref()
                .map_or_else(|| "variant".to_string(), |o| format!("`{o}` kind")),
            list(expected)
        ),
        R::MissingStructField { field, outer } => format!(
            "missing field `{field}`{}: add `{field}: ...`",
            outer
                .as_ref()
                .map_or_else(String::new, |o| format!(" in `{o}`"))
        ),
        R::Message(m) => m.clone(),
        R::ExpectedStructLike | R::ExpectedNamedStructLike(_) if src.trim_start().is_empty() => {
            "the file is empty: a scene is `Scene(objects: [...])` (see docs/scene-format.md)"
                .to_string()
        }
        other => format!("{other} (see docs/scene-format.md)"),
    };
    Error::Ron {
        path: path.to_path_buf(),
        line: e.position.line,
        col: e.position.col,
        msg,
    }
}

/// Line and column of byte offset `at`.
pub(crate) fn line_col(bytes: &[u8], at: usize) -> (usize, usize) {
    let before = &bytes[..at.min(bytes.len())];
    let line = before.iter().filter(|&&b| b == b'\n').count() + 1;
    let start = before
        .iter()
        .rposition(|&b| b == b'\n')
        .map_or(0, |p| p + 1);
    (line, at - start + 1)
}

/// Where the parts of a scene start in its text (byte offsets).
#[derive(Debug, Default)]
pub(crate) struct Outline {
    /// Top-level fields (`camera`, `objects`, …) and where their names start.
    pub fields: Vec<(String, usize)>,
    /// `objects[i]`: the byte range of each element of the objects list.
    pub objects: Vec<(usize, usize)>,
    /// Byte ranges of comments.
    comments: Vec<(usize, usize)>,
}

impl Outline {
    /// Scans `src` once.
    pub(crate) fn new(src: &str) -> Self {
        let b = src.as_bytes();
        let mut o = Self::default();
        let mut depth = 0usize;
        let mut i = 0;
        // Inside the `objects` list (at depth 2), expecting an element.
        let mut in_objects = false;
        let mut expect = false;
        let mut last_ident: Option<(usize, usize)> = None;
        while i < b.len() {
            let c = b[i];
            if c == b'/' && b.get(i + 1) == Some(&b'/') {
                let end = b[i..]
                    .iter()
                    .position(|&x| x == b'\n')
                    .map_or(b.len(), |p| i + p);
                o.comments.push((i, end));
                i = end;
                continue;
            }
            if c == b'/' && b.get(i + 1) == Some(&b'*') {
                let end = src[i + 2..].find("*/").map_or(b.len(), |p| i + 2 + p + 2);
                o.comments.push((i, end));
                i = end;
                continue;
            }
            if c.is_ascii_whitespace() {
                i += 1;
                continue;
            }
            if in_objects && depth == 2 && expect && c != b']' && c != b',' {
                o.objects.push((i, b.len()));
                expect = false;
            }
            match c {
                b'"' => i = skip_string(b, i + 1),
                b'\'' => i = skip_char(b, i + 1),
                b'r' if matches!(b.get(i + 1), Some(b'#' | b'"'))
                    && (i == 0 || !is_ident(b[i - 1])) =>
                {
                    i = skip_raw_string(b, i + 1);
                }
                b'(' | b'[' | b'{' => {
                    depth += 1;
                    if c == b'[' && depth == 2 {
                        let key = o.fields.last().map(|(k, _)| k.as_str());
                        in_objects = key == Some("objects");
                        expect = in_objects;
                    }
                    i += 1;
                }
                b')' | b']' | b'}' => {
                    if in_objects && depth == 2 {
                        if let Some(last) = o.objects.last_mut() {
                            last.1 = i;
                        }
                        in_objects = false;
                    }
                    depth = depth.saturating_sub(1);
                    i += 1;
                }
                b',' => {
                    if in_objects && depth == 2 {
                        if let Some(last) = o.objects.last_mut() {
                            last.1 = i;
                        }
                        expect = true;
                    }
                    i += 1;
                }
                b':' => {
                    if depth == 1 {
                        if let Some((s, e)) = last_ident.take() {
                            o.fields.push((src[s..e].to_string(), s));
                        }
                    }
                    i += 1;
                }
                _ if is_ident(c) => {
                    let start = i;
                    while i < b.len() && is_ident(b[i]) {
                        i += 1;
                    }
                    last_ident = Some((start, i));
                    continue;
                }
                _ => i += 1,
            }
            last_ident = None;
        }
        o
    }

    /// The start of the top-level field `name`.
    pub(crate) fn field(&self, name: &str) -> Option<usize> {
        self.fields
            .iter()
            .find(|(k, _)| k == name)
            .map(|&(_, at)| at)
    }

    /// The first `needle` in `range` that is not in a comment, or the start
    /// of the range when there is none.
    pub(crate) fn find_in(&self, src: &str, range: (usize, usize), needle: &str) -> usize {
        let (s, e) = (range.0.min(src.len()), range.1.min(src.len()));
        src.get(s..e)
            .and_then(|part| {
                part.match_indices(needle)
                    .map(|(at, _)| s + at)
                    .find(|&at| {
                        let k = self.comments.partition_point(|&(cs, _)| cs <= at);
                        k == 0 || self.comments[k - 1].1 <= at
                    })
            })
            .unwrap_or(s)
    }
}

fn is_ident(c: u8) -> bool {
    c.is_ascii_alphanumeric() || c == b'_'
}

/// The index after a string whose opening quote is before `i`.
fn skip_string(b: &[u8], mut i: usize) -> usize {
    while i < b.len() {
        match b[i] {
            b'\\' => i += 2,
            b'"' => return i + 1,
            _ => i += 1,
        }
    }
    b.len()
}

/// The index after a character literal whose opening quote is before `i`
/// (or just after the quote when it is not a literal, as in a lifetime).
fn skip_char(b: &[u8], i: usize) -> usize {
    let mut k = i;
    if b.get(k) == Some(&b'\\') {
        k += 2;
    } else {
        k += 1;
    }
    // A multi-byte UTF-8 character.
    while k < b.len() && (b[k] & 0xC0) == 0x80 {
        k += 1;
    }
    if b.get(k) == Some(&b'\'') {
        k + 1
    } else {
        i
    }
}

/// The index after a raw string `r#"…"#` whose `r` is before `i`.
fn skip_raw_string(b: &[u8], mut i: usize) -> usize {
    let mut hashes = 0;
    while b.get(i) == Some(&b'#') {
        hashes += 1;
        i += 1;
    }
    if b.get(i) != Some(&b'"') {
        return i;
    }
    i += 1;
    while i < b.len() {
        if b[i] == b'"'
            && b[i + 1..]
                .iter()
                .take(hashes)
                .filter(|&&x| x == b'#')
                .count()
                == hashes
        {
            return i + 1 + hashes;
        }
        i += 1;
    }
    b.len()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn outline_finds_fields_and_objects() {
        let src = "Scene(\n  // objects: [fake]\n  camera: Camera(eye: (0,0,1)),\n  objects: [\n    Sphere(material: \"a,b\"), /* , */ Box(min: (0,0,0)),\n    Mesh(file: r#\"x]\"#),\n  ],\n)";
        let o = Outline::new(src);
        let at = |k: usize| line_col(src.as_bytes(), k);
        assert_eq!(at(o.field("camera").unwrap()), (3, 3));
        assert_eq!(o.objects.len(), 3, "{o:?}");
        assert_eq!(at(o.objects[0].0), (5, 5));
        assert!(src[o.objects[1].0..].starts_with("Box"));
        assert!(src[o.objects[2].0..].starts_with("Mesh"));
        assert_eq!(at(o.find_in(src, o.objects[0], "\"a,b\"")), (5, 22));
    }

    #[test]
    fn outline_is_linear_on_a_long_line() {
        // One line of 200k objects: a quadratic search would take minutes.
        let mut src = String::from("(objects: [");
        for _ in 0..200_000 {
            src.push_str("Sphere(center: (0,0,0), radius: 1, material: \"m\"),");
        }
        src.push_str("])");
        let o = Outline::new(&src);
        assert_eq!(o.objects.len(), 200_000);
        let last = *o.objects.last().unwrap();
        assert!(src[last.0..].starts_with("Sphere"));
    }
}
