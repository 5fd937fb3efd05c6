//! `Entities`: each `ScenarioObject` as a vehicle of one of carfollow's kinds, read from its
//! `Vehicle` element or from a vehicle catalog by `CatalogReference`.

use super::error::OscError;
use super::xml::{child, children, elements, read_text, Xml};
use roxmltree::Node;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// A vehicle of the scenario.
#[derive(Clone, Debug)]
pub struct Entity {
    /// Its name in the file.
    pub name: String,
    /// carfollow's kind for it: `sedan`, `hatchback`, `van` or `truck`.
    pub kind: &'static str,
    /// The line of its `ScenarioObject`.
    pub line: u32,
    /// Whether a controller is assigned to it in `Entities` (`ObjectController`).
    pub controlled: bool,
    /// Whether its `Vehicle` says it follows no lead, as carfollow's export writes a chase
    /// without one: the property [`LEAD_PROPERTY`] = `none`.
    pub follows_no_lead: bool,
}

/// The `Property` of a `Vehicle` by which carfollow's export says what the ego follows:
/// `none`, for a scenario without a lead (a vehicle ahead of the ego is then no lead).
pub const LEAD_PROPERTY: &str = "carfollow:lead";

/// Whether the `<Vehicle>` `vehicle` has the property [`LEAD_PROPERTY`] = `none`.
fn follows_no_lead(vehicle: Node) -> bool {
    child(vehicle, "Properties").is_some_and(|p| {
        children(p, "Property").any(|q| {
            q.attribute("name") == Some(LEAD_PROPERTY)
                && q.attribute("value") == Some(super::write::NO_LEAD)
        })
    })
}

/// The kind whose shape is nearest a vehicle of `category` with a bounding box of
/// `length × height` metres: trucks, buses and trailers are `truck`; vans, and cars at
/// least 1.8 m tall (an MPV's roof), are `van`; cars shorter than 4.3 m (a C-segment
/// hatchback's length) are `hatchback`; other cars `sedan`.
pub fn kind_of(category: &str, length_m: f64, height_m: f64) -> Option<&'static str> {
    match category {
        "truck" | "bus" | "trailer" | "semitrailer" => Some("truck"),
        "van" => Some("van"),
        "car" if height_m >= 1.8 => Some("van"),
        "car" if length_m < 4.3 => Some("hatchback"),
        "car" => Some("sedan"),
        _ => None,
    }
}

/// Where catalogs of each kind are (`CatalogLocations`), relative to the scenario file's
/// folder as the standard says.
pub struct Catalogs {
    dirs: BTreeMap<String, PathBuf>,
}

impl Catalogs {
    /// The `CatalogLocations` of `xml` (the scenario), if any.
    pub fn read(xml: &Xml, dir: &Path) -> Result<Catalogs, OscError> {
        let mut dirs = BTreeMap::new();
        if let Some(locations) = child(xml.doc.root_element(), "CatalogLocations") {
            for catalog in elements(locations) {
                let Some(directory) = child(catalog, "Directory") else {
                    return Err(xml.at(
                        catalog,
                        format!("<{}> has no <Directory>", catalog.tag_name().name()),
                    ));
                };
                let path = xml.req(directory, "path")?;
                dirs.insert(catalog.tag_name().name().to_string(), dir.join(path));
            }
        }
        Ok(Catalogs { dirs })
    }

    /// The folder of catalogs of `kind` (`VehicleCatalog`, ...).
    fn dir(&self, kind: &str) -> Option<&Path> {
        self.dirs.get(kind).map(PathBuf::as_path)
    }
}

/// Every `ScenarioObject` of the scenario.
pub fn read_entities(xml: &Xml, catalogs: &Catalogs) -> Result<Vec<Entity>, OscError> {
    let root = xml.doc.root_element();
    let Some(entities) = child(root, "Entities") else {
        return Err(xml.at(root, "<OpenSCENARIO> has no <Entities>"));
    };
    let mut out: Vec<Entity> = Vec::new();
    for object in elements(entities) {
        if object.tag_name().name() != "ScenarioObject" {
            return Err(xml.unsupported(object, "entity", "carfollow's entities are vehicles"));
        }
        let name = xml.req(object, "name")?;
        if out.iter().any(|e| e.name == name) {
            return Err(xml.at(
                object,
                format!("<ScenarioObject name=\"{name}\">: a second entity of that name"),
            ));
        }
        let mut kind = None;
        let mut controlled = false;
        let mut no_lead = false;
        for element in elements(object) {
            match element.tag_name().name() {
                "Vehicle" => {
                    kind = Some(vehicle_kind(xml, element)?);
                    no_lead = follows_no_lead(element);
                }
                "CatalogReference" => kind = Some(catalog_vehicle(xml, element, catalogs)?),
                "ObjectController" => controlled = true,
                "Pedestrian" | "MiscObject" | "ExternalObjectReference" => {
                    return Err(xml.unsupported(
                        element,
                        "entity",
                        "carfollow's entities are vehicles",
                    ))
                }
                _ => return Err(xml.unsupported(element, "element", "")),
            }
        }
        let kind = kind.ok_or_else(|| {
            xml.at(
                object,
                format!("<ScenarioObject name=\"{name}\"> has no vehicle"),
            )
        })?;
        out.push(Entity {
            name,
            kind,
            line: xml.line(object),
            controlled,
            follows_no_lead: no_lead,
        });
    }
    Ok(out)
}

/// carfollow's kind of the `<Vehicle>` element `vehicle`.
fn vehicle_kind(xml: &Xml, vehicle: Node) -> Result<&'static str, OscError> {
    let category = xml.req(vehicle, "vehicleCategory")?;
    let dimensions = child(vehicle, "BoundingBox")
        .and_then(|b| child(b, "Dimensions"))
        .ok_or_else(|| xml.at(vehicle, "<Vehicle> has no <BoundingBox><Dimensions>"))?;
    let length = xml.num(dimensions, "length")?;
    let height = xml.num(dimensions, "height")?;
    if !(length > 0.0 && height > 0.0) {
        return Err(xml.at(
            dimensions,
            "<Dimensions>: length and height must be positive",
        ));
    }
    kind_of(&category, length, height).ok_or_else(|| {
        xml.at(
            vehicle,
            format!("unsupported vehicleCategory=\"{category}\" (carfollow draws cars, vans, trucks and buses)"),
        )
    })
}

/// The kind of the vehicle a `CatalogReference` names (see [`catalog_entry`]).
fn catalog_vehicle(
    xml: &Xml,
    reference: Node,
    catalogs: &Catalogs,
) -> Result<&'static str, OscError> {
    let vehicle = catalog_entry(
        xml,
        reference,
        catalogs,
        "VehicleCatalog",
        "Vehicle",
        vehicle_kind,
    );
    let Err(not_a_vehicle) = vehicle else {
        return vehicle;
    };
    // An entry of a pedestrian or object catalog is refused as what it is, not as a
    // vehicle the vehicle catalog lacks.
    for (kind, element) in [
        ("PedestrianCatalog", "Pedestrian"),
        ("MiscObjectCatalog", "MiscObject"),
    ] {
        if catalog_entry(xml, reference, catalogs, kind, element, |_, _| Ok(())).is_ok() {
            return Err(xml.at(
                reference,
                format!(
                    "<CatalogReference catalogName=\"{}\" entryName=\"{}\">: a <{element}> of the {kind}, and carfollow's entities are vehicles",
                    reference.attribute("catalogName").unwrap_or_default(),
                    reference.attribute("entryName").unwrap_or_default(),
                ),
            ));
        }
    }
    Err(not_a_vehicle)
}

/// `read` of the entry a `CatalogReference` names: the element `element` named `entryName`
/// in the file of the `kind` folder (`VehicleCatalog`, `EnvironmentCatalog`) whose
/// `<Catalog name>` is `catalogName`, read with the reference's `ParameterAssignments`
/// over the entry's own declarations.
pub fn catalog_entry<T>(
    xml: &Xml,
    reference: Node,
    catalogs: &Catalogs,
    kind: &str,
    element: &'static str,
    read: impl FnOnce(&Xml, Node) -> Result<T, OscError>,
) -> Result<T, OscError> {
    let catalog_name = xml.req(reference, "catalogName")?;
    let entry = xml.req(reference, "entryName")?;
    let dir = catalogs.dir(kind).ok_or_else(|| {
        xml.at(
            reference,
            format!("<CatalogReference catalogName=\"{catalog_name}\">: no <{kind}> in <CatalogLocations>"),
        )
    })?;
    let mut given = BTreeMap::new();
    if let Some(assignments) = child(reference, "ParameterAssignments") {
        for a in children(assignments, "ParameterAssignment") {
            // A name, not a value: written `Name` (or, in older files, `$Name`).
            let name = a
                .attribute("parameterRef")
                .ok_or_else(|| xml.at(a, "<ParameterAssignment> has no `parameterRef`"))?;
            given.insert(
                name.trim_start_matches('$').to_string(),
                xml.req(a, "value")?,
            );
        }
    }
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .map_err(|e| {
            xml.at(
                reference,
                format!(
                    "<CatalogReference catalogName=\"{catalog_name}\">: cannot read the {kind} folder {}: {e}",
                    dir.display()
                ),
            )
        })?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "xosc"))
        .collect();
    files.sort();
    for file in files {
        let text = read_text(&file)?;
        let mut catalog = Xml::parse(&text, &file)?;
        let Some(c) = child(catalog.doc.root_element(), "Catalog") else {
            continue;
        };
        if c.attribute("name") != Some(catalog_name.as_str()) {
            continue;
        }
        let found = children(c, element).find(|v| v.attribute("name") == Some(entry.as_str()));
        if let Some(node) = found {
            catalog.given = given;
            catalog.given_anywhere = true;
            return read(&catalog, node);
        }
    }
    Err(xml.at(
        reference,
        format!(
            "<CatalogReference catalogName=\"{catalog_name}\" entryName=\"{entry}\">: no such {} in {}",
            element.to_lowercase(),
            dir.display()
        ),
    ))
}

#[cfg(test)]
mod tests {
    use super::kind_of;

    #[test]
    fn kinds_follow_the_category_and_the_box() {
        assert_eq!(kind_of("car", 5.04, 1.5), Some("sedan"));
        assert_eq!(kind_of("car", 4.0, 1.45), Some("hatchback"));
        assert_eq!(kind_of("car", 4.8, 1.9), Some("van"));
        assert_eq!(kind_of("van", 5.0, 2.0), Some("van"));
        assert_eq!(kind_of("truck", 8.0, 3.2), Some("truck"));
        assert_eq!(kind_of("bus", 12.0, 3.2), Some("truck"));
        assert_eq!(kind_of("bicycle", 1.8, 1.7), None);
        assert_eq!(kind_of("motorbike", 2.0, 1.2), None);
    }
}
