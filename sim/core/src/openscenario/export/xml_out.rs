//! A small XML writer: elements with attributes, nested with two spaces, every attribute
//! value and comment escaped. OpenSCENARIO and OpenDRIVE hold nothing but elements with
//! attributes, so this is all their writers need (no text nodes, no namespaces).

use std::fmt::Write;

/// XML being written, one element a line.
pub struct XmlOut {
    text: String,
    open: Vec<&'static str>,
}

/// `value` as an attribute value may hold it (quoted with `"`): `&`, `<`, `>`, `"` and `'`
/// as entities, and the control characters XML 1.0 allows (tab, line feed, carriage
/// return) as character references, so that a reader's attribute normalisation keeps them.
/// The other control characters XML 1.0 forbids are dropped.
pub fn escape(value: &str) -> String {
    let mut out = String::with_capacity(value.len());
    for c in value.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            '\t' => out.push_str("&#9;"),
            '\n' => out.push_str("&#10;"),
            '\r' => out.push_str("&#13;"),
            c if (c as u32) < 0x20 || c == '\u{FFFE}' || c == '\u{FFFF}' => {}
            c => out.push(c),
        }
    }
    out
}

/// A number as XML Schema's `double` writes it: the shortest decimal that reads back as
/// the same `f64` (Rust's `Display`), so a file read back gives the very value written.
pub fn num(v: f64) -> String {
    if v == 0.0 {
        // No `-0`.
        return "0".into();
    }
    format!("{v}")
}

impl XmlOut {
    /// A document with its XML declaration.
    pub fn new() -> XmlOut {
        XmlOut {
            text: "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n".into(),
            open: Vec::new(),
        }
    }

    fn tag(&mut self, name: &str, attributes: &[(&str, String)], close: bool) {
        let indent = "  ".repeat(self.open.len());
        let _ = write!(self.text, "{indent}<{name}");
        for (key, value) in attributes {
            let _ = write!(self.text, " {key}=\"{}\"", escape(value));
        }
        self.text.push_str(if close { "/>\n" } else { ">\n" });
    }

    /// Opens `name`, to be closed by [`XmlOut::close`].
    pub fn open(&mut self, name: &'static str, attributes: &[(&str, String)]) {
        self.tag(name, attributes, false);
        self.open.push(name);
    }

    /// An element without children.
    pub fn empty(&mut self, name: &str, attributes: &[(&str, String)]) {
        self.tag(name, attributes, true);
    }

    /// Closes the element opened last.
    pub fn close(&mut self) {
        let name = self.open.pop().expect("an element is open");
        let indent = "  ".repeat(self.open.len());
        let _ = writeln!(self.text, "{indent}</{name}>");
    }

    /// A comment (`--` cannot stand in one, so it is written `- -`).
    pub fn comment(&mut self, text: &str) {
        let indent = "  ".repeat(self.open.len());
        let mut body = escape(text).replace("--", "- -");
        if body.ends_with('-') {
            body.push(' ');
        }
        let _ = writeln!(self.text, "{indent}<!-- {body} -->");
    }

    /// The document, every element closed.
    pub fn finish(mut self) -> String {
        while !self.open.is_empty() {
            self.close();
        }
        self.text
    }
}

/// `(key, value)` of an attribute, its value as text.
pub fn a(key: &'static str, value: impl ToString) -> (&'static str, String) {
    (key, value.to_string())
}

/// `(key, value)` of a number attribute ([`num`]).
pub fn n(key: &'static str, value: f64) -> (&'static str, String) {
    (key, num(value))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_are_escaped_and_numbers_read_back_exactly() {
        assert_eq!(
            escape("a<b & \"c\" 'd'>\n"),
            "a&lt;b &amp; &quot;c&quot; &apos;d&apos;&gt;&#10;"
        );
        assert_eq!(escape("bell\u{7}"), "bell");
        for v in [0.1, 1.0 / 3.0, 1e-12, 123456.789, -2.5e-7, 5e20] {
            assert_eq!(num(v).parse::<f64>().unwrap(), v);
        }
        assert_eq!(num(-0.0), "0");
        let mut x = XmlOut::new();
        x.open("A", &[a("k", "v&")]);
        x.empty("B", &[n("x", 0.5)]);
        x.comment("no -- here-");
        let t = x.finish();
        assert!(roxmltree::Document::parse(&t).is_ok(), "{t}");
        assert!(t.contains("<A k=\"v&amp;\">"), "{t}");
    }
}
