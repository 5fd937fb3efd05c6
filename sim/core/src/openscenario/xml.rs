//! One OpenSCENARIO XML file as the importer reads it: its elements with their lines, and
//! their attributes with parameters resolved (`$name`, `${expression}`), from the nearest
//! `ParameterDeclarations` outward, as the standard scopes them.

use super::error::OscError;
use super::expr;
use roxmltree::{Document, Node};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// How many parameters deep a value may refer (`$a` whose value is `$b` ...): a loop of
/// references ends here instead of hanging.
const MAX_REFERENCE_DEPTH: usize = 16;

/// The largest file read, bytes: far beyond any scenario or catalog.
const MAX_FILE_BYTES: u64 = 32 << 20;

/// A file's text, read whole (within [`MAX_FILE_BYTES`]).
pub fn read_text(path: &Path) -> Result<String, OscError> {
    let io = |source| OscError::Io {
        path: path.to_owned(),
        source,
    };
    let len = std::fs::metadata(path).map_err(io)?.len();
    if len > MAX_FILE_BYTES {
        return Err(OscError::File {
            path: path.to_owned(),
            message: format!(
                "{len} bytes: larger than the {MAX_FILE_BYTES} an OpenSCENARIO file may be here"
            ),
        });
    }
    std::fs::read_to_string(path).map_err(io)
}

/// A parsed file, with the values that replace its root's parameters (`--param`) or, for
/// a catalog's entry, the reference's `ParameterAssignments`.
pub struct Xml<'a> {
    /// The file, as errors name it.
    pub path: PathBuf,
    /// Its tree.
    pub doc: Document<'a>,
    /// Parameter values given from outside, by name.
    pub given: BTreeMap<String, String>,
    /// Whether `given` replaces declarations anywhere in the file (a catalog's entry, by its
    /// reference's assignments) or only the root's (a scenario, by `--param`).
    pub given_anywhere: bool,
}

impl<'a> Xml<'a> {
    /// Parses `text`, the file at `path`.
    pub fn parse(text: &'a str, path: &Path) -> Result<Xml<'a>, OscError> {
        let options = roxmltree::ParsingOptions {
            allow_dtd: false,
            nodes_limit: 1 << 20,
            ..roxmltree::ParsingOptions::default()
        };
        let doc = Document::parse_with_options(text, options).map_err(|e| OscError::Xml {
            path: path.to_owned(),
            line: e.pos().row,
            message: e.to_string(),
        })?;
        Ok(Xml {
            path: path.to_owned(),
            doc,
            given: BTreeMap::new(),
            given_anywhere: false,
        })
    }

    /// The 1-based line `node` starts on.
    pub fn line(&self, node: Node) -> u32 {
        self.doc.text_pos_at(node.range().start).row
    }

    /// An error at `node`.
    pub fn at(&self, node: Node, message: impl Into<String>) -> OscError {
        OscError::At {
            path: self.path.clone(),
            line: self.line(node),
            message: message.into(),
        }
    }

    /// `unsupported WHAT <Tag>` at `node`, with why.
    pub fn unsupported(&self, node: Node, what: &str, why: &str) -> OscError {
        let tag = node.tag_name().name();
        let why = if why.is_empty() {
            String::new()
        } else {
            format!(" ({why})")
        };
        self.at(node, format!("unsupported {what} <{tag}>{why}"))
    }

    /// The attribute `name` of `node` with its parameters resolved; `None` when absent.
    pub fn attr(&self, node: Node, name: &str) -> Result<Option<String>, OscError> {
        match node.attribute(name) {
            None => Ok(None),
            Some(raw) => self.resolve(node, raw, 0).map(Some).map_err(|why| {
                self.at(
                    node,
                    format!("<{} {name}=\"{raw}\">: {why}", node.tag_name().name()),
                )
            }),
        }
    }

    /// The attribute `name`, which must be there.
    pub fn req(&self, node: Node, name: &str) -> Result<String, OscError> {
        self.attr(node, name)?.ok_or_else(|| {
            self.at(
                node,
                format!("<{}> has no `{name}`", node.tag_name().name()),
            )
        })
    }

    /// The attribute `name` as a finite number; `None` when absent.
    pub fn opt_num(&self, node: Node, name: &str) -> Result<Option<f64>, OscError> {
        let Some(text) = self.attr(node, name)? else {
            return Ok(None);
        };
        match text.trim().parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(Some(v)),
            _ => Err(self.at(
                node,
                format!(
                    "<{} {name}=\"{text}\">: not a finite number",
                    node.tag_name().name()
                ),
            )),
        }
    }

    /// The attribute `name` as a finite number, which must be there.
    pub fn num(&self, node: Node, name: &str) -> Result<f64, OscError> {
        self.opt_num(node, name)?.ok_or_else(|| {
            self.at(
                node,
                format!("<{}> has no `{name}`", node.tag_name().name()),
            )
        })
    }

    /// The attribute `name` as a boolean (`true`, `1`, `false` or `0`), which must be there.
    pub fn boolean(&self, node: Node, name: &str) -> Result<bool, OscError> {
        match self.req(node, name)?.as_str() {
            "true" | "1" => Ok(true),
            "false" | "0" => Ok(false),
            v => Err(self.at(
                node,
                format!("<{} {name}=\"{v}\">: not a boolean", node.tag_name().name()),
            )),
        }
    }

    /// The value of parameter `name` as seen from `node`.
    pub fn param_value(&self, node: Node, name: &str) -> Result<String, OscError> {
        self.param(node, name, 0)
            .map_err(|why| self.at(node, format!("<{}>: {why}", node.tag_name().name())))
    }

    /// A value as written (`raw`, at `node`) with its parameter reference or expression
    /// resolved.
    fn resolve(&self, node: Node, raw: &str, depth: usize) -> Result<String, String> {
        if depth > MAX_REFERENCE_DEPTH {
            return Err(format!(
                "parameters refer to one another more than {MAX_REFERENCE_DEPTH} deep (a loop?)"
            ));
        }
        let trimmed = raw.trim();
        if let Some(body) = trimmed.strip_prefix("${").and_then(|b| b.strip_suffix('}')) {
            let lookup = |name: &str| -> Result<f64, String> {
                let v = self.param(node, name, depth + 1)?;
                match v.trim() {
                    "true" => Ok(1.0),
                    "false" => Ok(0.0),
                    t => t
                        .parse::<f64>()
                        .map_err(|_| format!("parameter `{name}` = \"{v}\" is not a number")),
                }
            };
            return expr::evaluate(body, &lookup).map(|v| format!("{v}"));
        }
        if let Some(name) = trimmed.strip_prefix('$') {
            return self.param(node, name, depth + 1);
        }
        Ok(raw.to_string())
    }

    /// The value of parameter `name` as seen from `node`: its declaration in the nearest
    /// enclosing `ParameterDeclarations`, or the value given from outside for the root's.
    fn param(&self, node: Node, name: &str, depth: usize) -> Result<String, String> {
        for scope in node.ancestors() {
            let Some(decls) = child(scope, "ParameterDeclarations") else {
                continue;
            };
            let Some(decl) =
                children(decls, "ParameterDeclaration").find(|d| d.attribute("name") == Some(name))
            else {
                continue;
            };
            let is_outermost = scope.parent().is_some_and(|p| p.is_root());
            if is_outermost || self.given_anywhere {
                if let Some(v) = self.given.get(name) {
                    return Ok(v.clone());
                }
            }
            let raw = decl
                .attribute("value")
                .ok_or_else(|| format!("parameter `{name}` has no value"))?;
            return self.resolve(decl, raw, depth);
        }
        Err(format!("no parameter `{name}` is declared"))
    }
}

/// The element children of `node` named `name`.
pub fn children<'a, 'b>(
    node: Node<'a, 'b>,
    name: &'static str,
) -> impl Iterator<Item = Node<'a, 'b>> {
    node.children()
        .filter(move |c| c.is_element() && c.tag_name().name() == name)
}

/// The first element child of `node` named `name`.
pub fn child<'a, 'b>(node: Node<'a, 'b>, name: &'static str) -> Option<Node<'a, 'b>> {
    children(node, name).next()
}

/// Every element child of `node`.
pub fn elements<'a, 'b>(node: Node<'a, 'b>) -> impl Iterator<Item = Node<'a, 'b>> {
    node.children().filter(|c| c.is_element())
}

/// The one element child of `node` (a choice of the schema: `<Position>` holds exactly one
/// kind of position).
pub fn only_element<'a, 'b>(xml: &Xml, node: Node<'a, 'b>) -> Result<Node<'a, 'b>, OscError> {
    let mut all = elements(node);
    match (all.next(), all.next()) {
        (Some(one), None) => Ok(one),
        (None, _) => Err(xml.at(node, format!("<{}> is empty", node.tag_name().name()))),
        (Some(_), Some(second)) => Err(xml.at(
            second,
            format!(
                "<{}> holds more than one element where the standard allows one",
                node.tag_name().name()
            ),
        )),
    }
}
