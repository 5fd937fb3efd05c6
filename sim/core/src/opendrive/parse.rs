//! Reading a road file into the [`OpenDrive`] model. Every element is either read, one of
//! the few that describe nothing carfollow draws or drives by ([`NOT_DRAWN`]), or refused
//! with its line: an element this reader does not know is refused, never skipped.

use super::model::{
    Geometry, GeometryKind, Lane, LaneSection, OpenDrive, Place, Poly3Record, Road, RoadLink,
};
use super::OpenDriveError;
use roxmltree::Node;
use std::path::Path;

/// Elements read past, anywhere: what they hold is neither geometry nor lanes carfollow
/// drives (its paint, verge and scenery are its own): user data, road marks, a lane's
/// material, visibility, speed, access, height and rule, lane links, a road's type (its
/// speed limit), the header and what it holds.
const NOT_DRAWN: &[&str] = &[
    "userData",
    "roadMark",
    "material",
    "visibility",
    "speed",
    "access",
    "height",
    "rule",
    "link",
    "type",
    "dataQuality",
];

/// The longest attribute value an error quotes, characters.
const QUOTE_CHARS: usize = 24;
/// The most attributes an error quotes.
const QUOTE_ATTRIBUTES: usize = 4;

/// Reads the road file at `path`.
pub fn load(path: &Path) -> Result<OpenDrive, OpenDriveError> {
    let text = std::fs::read_to_string(path).map_err(|source| OpenDriveError::Io {
        path: path.to_owned(),
        source,
    })?;
    parse(&text, path)
}

/// Reads road-file `text`; `path` names it in errors.
pub fn parse(text: &str, path: &Path) -> Result<OpenDrive, OpenDriveError> {
    let doc = roxmltree::Document::parse(text).map_err(|e| OpenDriveError::Xml {
        path: path.to_owned(),
        line: e.pos().row,
        message: e.to_string(),
    })?;
    let r = Reader { doc: &doc, path };
    let root = doc.root_element();
    if root.tag_name().name() != "OpenDRIVE" {
        return Err(r.refuse(root, "the root element must be <OpenDRIVE>"));
    }
    let mut roads = Vec::new();
    for child in r.elements(root) {
        match child.tag_name().name() {
            "header" => {}
            "road" => roads.push(r.road(child)?),
            "junction" => {
                return Err(r.refuse(
                    child,
                    "junctions are refused: carfollow's route follows one road",
                ))
            }
            name if NOT_DRAWN.contains(&name) => {}
            _ => return Err(r.refuse(child, "not part of the subset carfollow reads")),
        }
    }
    Ok(OpenDrive {
        path: path.to_owned(),
        roads,
    })
}

/// The document being read and its file's name.
struct Reader<'a, 'input> {
    doc: &'a roxmltree::Document<'input>,
    path: &'a Path,
}

impl<'a, 'input> Reader<'a, 'input> {
    /// The element children of `node`.
    fn elements(&self, node: Node<'a, 'input>) -> impl Iterator<Item = Node<'a, 'input>> {
        node.children().filter(Node::is_element)
    }

    /// Where `node` stands.
    fn place(&self, node: Node) -> Place {
        let line = self.doc.text_pos_at(node.range().start).row;
        let mut element = format!("<{}", node.tag_name().name());
        for a in node.attributes().take(QUOTE_ATTRIBUTES) {
            let value: String = a.value().chars().take(QUOTE_CHARS).collect();
            let more = if a.value().chars().count() > QUOTE_CHARS {
                "…"
            } else {
                ""
            };
            element.push_str(&format!(" {}=\"{value}{more}\"", a.name()));
        }
        if node.attributes().len() > QUOTE_ATTRIBUTES {
            element.push_str(" …");
        }
        element.push('>');
        Place { line, element }
    }

    /// The error refusing `node`.
    fn refuse(&self, node: Node, reason: impl Into<String>) -> OpenDriveError {
        self.place(node).refuse(self.path, reason)
    }

    /// A required finite number attribute.
    fn number(&self, node: Node, name: &str) -> Result<f64, OpenDriveError> {
        match node.attribute(name) {
            None => Err(self.refuse(node, format!("`{name}` is missing"))),
            Some(text) => match text.trim().parse::<f64>() {
                Ok(v) if v.is_finite() => Ok(v),
                _ => Err(self.refuse(node, format!("`{name}` must be a finite number"))),
            },
        }
    }

    /// An optional finite number attribute, `default` when absent.
    fn number_or(&self, node: Node, name: &str, default: f64) -> Result<f64, OpenDriveError> {
        if node.attribute(name).is_none() {
            return Ok(default);
        }
        self.number(node, name)
    }

    /// Four number attributes.
    fn four(&self, node: Node, names: [&str; 4]) -> Result<[f64; 4], OpenDriveError> {
        Ok([
            self.number(node, names[0])?,
            self.number(node, names[1])?,
            self.number(node, names[2])?,
            self.number(node, names[3])?,
        ])
    }

    /// A `<road>`.
    fn road(&self, node: Node<'a, 'input>) -> Result<Road, OpenDriveError> {
        let mut road = Road {
            id: node.attribute("id").unwrap_or_default().to_string(),
            length: self.number(node, "length")?,
            junction: node
                .attribute("junction")
                .unwrap_or("-1")
                .trim()
                .to_string(),
            rule: node.attribute("rule").unwrap_or("RHT").to_string(),
            links: Vec::new(),
            geometries: Vec::new(),
            lane_offsets: Vec::new(),
            elevations: Vec::new(),
            superelevations: Vec::new(),
            lane_sections: Vec::new(),
            scenery: None,
            at: self.place(node),
        };
        for child in self.elements(node) {
            match child.tag_name().name() {
                "link" => road.links = self.links(child)?,
                "planView" => {
                    for g in self.elements(child) {
                        match g.tag_name().name() {
                            "geometry" => road.geometries.push(self.geometry(g)?),
                            "userData" => {}
                            _ => return Err(self.refuse(g, "a plan view holds geometries")),
                        }
                    }
                }
                "elevationProfile" => road.elevations = self.records(child, "elevation", &[])?,
                "lateralProfile" => {
                    road.superelevations =
                        self.records(child, "superelevation", &["crossfall", "shape"])?
                }
                "lanes" => self.lanes(child, &mut road)?,
                "objects" | "signals" | "surface" => {
                    if let Some(item) = self.elements(child).find(|e| !is_not_drawn(e)) {
                        road.scenery = road.scenery.take().or(Some(self.place(item)));
                    }
                }
                "type" | "userData" | "dataQuality" => {}
                _ => return Err(self.refuse(child, "not part of the subset carfollow reads")),
            }
        }
        Ok(road)
    }

    /// A road's `<link>`: its predecessor and successor.
    fn links(&self, node: Node) -> Result<Vec<RoadLink>, OpenDriveError> {
        let mut links = Vec::new();
        for l in self.elements(node) {
            match l.tag_name().name() {
                "predecessor" | "successor" => links.push(RoadLink {
                    successor: l.tag_name().name() == "successor",
                    element_type: l.attribute("elementType").unwrap_or("road").to_string(),
                    element_id: l.attribute("elementId").unwrap_or_default().to_string(),
                    contact_point: l.attribute("contactPoint").map(str::to_string),
                    at: self.place(l),
                }),
                "userData" => {}
                _ => {
                    return Err(self.refuse(l, "neighbours are refused: carfollow follows one road"))
                }
            }
        }
        Ok(links)
    }

    /// A `<geometry>` and its one shape.
    fn geometry(&self, node: Node) -> Result<Geometry, OpenDriveError> {
        let mut shapes = self.elements(node).filter(|e| !is_not_drawn(e));
        let Some(shape) = shapes.next() else {
            return Err(self.refuse(
                node,
                "a geometry needs one of line, arc, spiral, poly3, paramPoly3",
            ));
        };
        if let Some(extra) = shapes.next() {
            return Err(self.refuse(extra, "a geometry holds one shape"));
        }
        let kind = match shape.tag_name().name() {
            "line" => GeometryKind::Line,
            "arc" => GeometryKind::Arc(self.number(shape, "curvature")?),
            "spiral" => GeometryKind::Spiral(
                self.number(shape, "curvStart")?,
                self.number(shape, "curvEnd")?,
            ),
            "poly3" => GeometryKind::Poly3(self.four(shape, ["a", "b", "c", "d"])?),
            "paramPoly3" => GeometryKind::ParamPoly3 {
                u: self.four(shape, ["aU", "bU", "cU", "dU"])?,
                v: self.four(shape, ["aV", "bV", "cV", "dV"])?,
                normalized: match shape.attribute("pRange").unwrap_or("arcLength") {
                    "arcLength" => false,
                    "normalized" => true,
                    _ => return Err(self.refuse(shape, "`pRange` must be arcLength or normalized")),
                },
            },
            _ => return Err(self.refuse(shape, "not a geometry carfollow reads")),
        };
        Ok(Geometry {
            s: self.number(node, "s")?,
            x: self.number(node, "x")?,
            y: self.number(node, "y")?,
            hdg: self.number(node, "hdg")?,
            length: self.number(node, "length")?,
            kind,
            at: self.place(node),
            shape_at: self.place(shape),
        })
    }

    /// The `name` records (`s a b c d`) under `node`; elements named in `refused` are
    /// refused.
    fn records(
        &self,
        node: Node,
        name: &str,
        refused: &[&str],
    ) -> Result<Vec<Poly3Record>, OpenDriveError> {
        let mut out = Vec::new();
        for e in self.elements(node) {
            let tag = e.tag_name().name();
            if tag == name {
                out.push(self.record(e, "s")?);
            } else if refused.contains(&tag) {
                return Err(self.refuse(e, "refused: carfollow's road is flat across"));
            } else if !is_not_drawn(&e) {
                return Err(self.refuse(e, "not part of the subset carfollow reads"));
            }
        }
        Ok(out)
    }

    /// One `s a b c d` record, its start in attribute `start`.
    fn record(&self, e: Node, start: &str) -> Result<Poly3Record, OpenDriveError> {
        Ok(Poly3Record {
            s: self.number_or(e, start, 0.0)?,
            coefficients: self.four(e, ["a", "b", "c", "d"])?,
            at: self.place(e),
        })
    }

    /// `<lanes>`: lane offsets and lane sections.
    fn lanes(&self, node: Node<'a, 'input>, road: &mut Road) -> Result<(), OpenDriveError> {
        for e in self.elements(node) {
            match e.tag_name().name() {
                "laneOffset" => road.lane_offsets.push(self.record(e, "s")?),
                "laneSection" => road.lane_sections.push(self.lane_section(e)?),
                "userData" => {}
                _ => return Err(self.refuse(e, "not part of the subset carfollow reads")),
            }
        }
        Ok(())
    }

    /// A `<laneSection>`.
    fn lane_section(&self, node: Node<'a, 'input>) -> Result<LaneSection, OpenDriveError> {
        let mut section = LaneSection {
            s: self.number(node, "s")?,
            single_side: node.attribute("singleSide") == Some("true"),
            left: Vec::new(),
            right: Vec::new(),
            at: self.place(node),
        };
        for side in self.elements(node) {
            let name = side.tag_name().name();
            let lanes = match name {
                "left" => &mut section.left,
                "right" => &mut section.right,
                "center" | "userData" => continue,
                _ => return Err(self.refuse(side, "not part of the subset carfollow reads")),
            };
            for lane in self.elements(side) {
                if lane.tag_name().name() != "lane" {
                    if is_not_drawn(&lane) {
                        continue;
                    }
                    return Err(self.refuse(lane, "a side holds lanes"));
                }
                lanes.push(self.lane(lane)?);
            }
        }
        Ok(section)
    }

    /// A `<lane>` of a side.
    fn lane(&self, node: Node) -> Result<Lane, OpenDriveError> {
        let id = node
            .attribute("id")
            .and_then(|t| t.trim().parse::<i32>().ok())
            .ok_or_else(|| self.refuse(node, "`id` must be a whole number"))?;
        let mut lane = Lane {
            id,
            kind: node.attribute("type").unwrap_or("none").to_string(),
            widths: Vec::new(),
            at: self.place(node),
        };
        for e in self.elements(node) {
            match e.tag_name().name() {
                "width" => lane.widths.push(self.record(e, "sOffset")?),
                "border" => {
                    return Err(self.refuse(e, "lane borders are refused: give lane widths"))
                }
                _ if is_not_drawn(&e) => {}
                _ => return Err(self.refuse(e, "not part of the subset carfollow reads")),
            }
        }
        Ok(lane)
    }
}

/// Whether `e` is one of the [`NOT_DRAWN`] elements.
fn is_not_drawn(e: &Node) -> bool {
    NOT_DRAWN.contains(&e.tag_name().name())
}
