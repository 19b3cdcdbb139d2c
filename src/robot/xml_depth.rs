//! A cheap scan of an XML text's element nesting depth, run before the URDF parser: the parser
//! recurses once per nesting level, so a file nested tens of thousands of elements deep would
//! overflow the stack (an abort, not an error). A URDF nests about 6 deep (`robot > link >
//! collision > geometry > box`); the limit is [`MAX_XML_DEPTH`](crate::limits::MAX_XML_DEPTH).
//!
//! The scan counts start tags (`<name …>`) up and end tags (`</name>`) down, skipping
//! self-closing tags (`<name …/>`), comments (`<!-- … -->`), CDATA sections, declarations
//! (`<!DOCTYPE …>`) and processing instructions (`<? … ?>`), and quoted attribute values. It
//! does not validate the XML (the parser does); it only bounds the depth. Linear in the text.
//!
//! ```
//! use helixreach::robot::xml_depth::max_depth;
//! assert_eq!(max_depth("<robot><link name=\"a>b\"/><!-- <x> --></robot>"), (1, 1));
//! let deep = "<a>".repeat(300);
//! assert_eq!(max_depth(&deep), (300, 1));
//! ```

use crate::error::{Error, Result};

/// The deepest element nesting of `text` and the (1-based) line where it is first reached.
pub fn max_depth(text: &str) -> (usize, usize) {
    let b = text.as_bytes();
    let (mut depth, mut best, mut best_line, mut line) = (0usize, 0usize, 1usize, 1usize);
    let mut i = 0;
    // Skip to just past `end`, counting lines.
    let skip_to = |i: &mut usize, line: &mut usize, end: &[u8]| {
        while *i < b.len() && !b[*i..].starts_with(end) {
            *line += usize::from(b[*i] == b'\n');
            *i += 1;
        }
        *i = (*i + end.len()).min(b.len());
    };
    while i < b.len() {
        match b[i] {
            b'\n' => {
                line += 1;
                i += 1;
            }
            b'<' if b[i..].starts_with(b"<!--") => skip_to(&mut i, &mut line, b"-->"),
            b'<' if b[i..].starts_with(b"<![CDATA[") => skip_to(&mut i, &mut line, b"]]>"),
            b'<' if b[i..].starts_with(b"<?") => skip_to(&mut i, &mut line, b"?>"),
            b'<' if b[i..].starts_with(b"<!") => skip_to(&mut i, &mut line, b">"),
            b'<' => {
                let closing = b.get(i + 1) == Some(&b'/');
                // Find the tag's end outside quoted values.
                let mut j = i + 1;
                let mut quote = None;
                while j < b.len() {
                    let c = b[j];
                    line += usize::from(c == b'\n');
                    match quote {
                        Some(q) if c == q => quote = None,
                        Some(_) => {}
                        None if c == b'"' || c == b'\'' => quote = Some(c),
                        None if c == b'>' => break,
                        None => {}
                    }
                    j += 1;
                }
                let self_closing = j > i + 1 && b.get(j - 1) == Some(&b'/');
                if closing {
                    depth = depth.saturating_sub(1);
                } else if !self_closing {
                    depth += 1;
                    if depth > best {
                        best = depth;
                        best_line = line;
                    }
                }
                i = j + 1;
            }
            _ => i += 1,
        }
    }
    (best, best_line)
}

/// Refuse `text` (named `source` in the error) when its elements nest deeper than
/// [`MAX_XML_DEPTH`](crate::limits::MAX_XML_DEPTH).
pub fn check_depth(text: &str, source: &str) -> Result<()> {
    let max = crate::limits::MAX_XML_DEPTH;
    let (depth, line) = max_depth(text);
    if depth > max {
        return Err(Error::BadLine {
            path: source.into(),
            line,
            field: "element nesting".into(),
            reason: format!(
                "elements nest {depth} deep; a URDF may nest at most {max} deep \
                 (helixreach::limits::MAX_XML_DEPTH)"
            ),
        });
    }
    Ok(())
}
