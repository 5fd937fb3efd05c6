//! `EnvironmentAction` in `Init` (an `Environment`, or one from an environment catalog) as
//! the scenario's `[environment]`: the fog's visual range, the rain's rate and the sun.
//! carfollow's environment is fixed for the run, so a story's `EnvironmentAction` is
//! refused; what the environment holds that carfollow does not render is said in one
//! warning line.

use super::entities::{catalog_entry, Catalogs};
use super::error::OscError;
use super::xml::{child, elements, Xml};
use roxmltree::Node;

/// Illuminance of full sun on a surface facing it, lux: carfollow's sun strength 1.
const FULL_SUN_LUX: f64 = 100_000.0;
/// The largest sun strength carfollow draws (`environment.sun.strength`'s bound).
const MAX_STRENGTH: f64 = 2.0;

/// What an environment sets, in carfollow's fields.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct EnvironmentOut {
    /// `[environment.sun]`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sun: Option<SunOut>,
    /// `[environment.fog]`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fog: Option<FogOut>,
    /// `[environment.rain]`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rain: Option<RainOut>,
}

/// `[environment.sun]`'s fields an environment sets.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct SunOut {
    /// Degrees from carfollow's +x towards +z.
    pub azimuth_deg: f64,
    /// Degrees above the horizon.
    pub elevation_deg: f64,
    /// Relative to full sun.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub strength: Option<f64>,
}

/// `[environment.fog]`.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct FogOut {
    /// Metres.
    pub visual_range_m: f64,
}

/// `[environment.rain]`.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct RainOut {
    /// mm/h.
    pub rate_mm_h: f64,
}

/// carfollow's sun azimuth of OpenSCENARIO's `azimuth` (radians clockwise from north, the
/// file's +y) on a road whose first heading is `road_heading_rad` (counter-clockwise from
/// the file's +x): the road's start heads along carfollow's +x, its left is carfollow's −z.
pub fn azimuth_deg(osc_azimuth_rad: f64, road_heading_rad: f64) -> f64 {
    let deg = (osc_azimuth_rad + road_heading_rad).to_degrees() - 90.0;
    // Within −360–360, as the field takes it.
    deg % 360.0
}

/// The `EnvironmentAction` `action` of `Init`; `road_heading_rad` is the road's first
/// heading in the file's frame. Warnings go to `warnings`.
pub fn environment(
    xml: &Xml,
    action: Node,
    catalogs: &Catalogs,
    road_heading_rad: f64,
    warnings: &mut Vec<String>,
) -> Result<EnvironmentOut, OscError> {
    let inner = super::xml::only_element(xml, action)?;
    match inner.tag_name().name() {
        "Environment" => read(xml, inner, road_heading_rad, warnings),
        "CatalogReference" => catalog_entry(
            xml,
            inner,
            catalogs,
            "EnvironmentCatalog",
            "Environment",
            |c, env| read(c, env, road_heading_rad, warnings),
        ),
        _ => Err(xml.unsupported(inner, "environment", "")),
    }
}

/// One `<Environment>`.
fn read(
    xml: &Xml,
    env: Node,
    road_heading_rad: f64,
    warnings: &mut Vec<String>,
) -> Result<EnvironmentOut, OscError> {
    let mut out = EnvironmentOut::default();
    let mut unapplied: Vec<String> = Vec::new();
    for element in elements(env) {
        match element.tag_name().name() {
            "ParameterDeclarations" => {}
            "Weather" => weather(xml, element, road_heading_rad, &mut out, &mut unapplied)?,
            "TimeOfDay" => unapplied.push("<TimeOfDay> (the sun is set by <Sun>)".into()),
            "RoadCondition" => unapplied.push("<RoadCondition>".into()),
            _ => return Err(xml.unsupported(element, "environment element", "")),
        }
    }
    if !unapplied.is_empty() {
        let verb = if unapplied.len() == 1 { "is" } else { "are" };
        warnings.push(format!(
            "line {}: the environment's {} {verb} not applied: carfollow does not render them",
            xml.line(env),
            unapplied.join(", ")
        ));
    }
    Ok(out)
}

fn weather(
    xml: &Xml,
    weather: Node,
    road_heading_rad: f64,
    out: &mut EnvironmentOut,
    unapplied: &mut Vec<String>,
) -> Result<(), OscError> {
    for attribute in [
        "fractionalCloudCover",
        "cloudState",
        "temperature",
        "atmosphericPressure",
    ] {
        if weather.attribute(attribute).is_some() {
            unapplied.push(format!("`{attribute}`"));
        }
    }
    for element in elements(weather) {
        match element.tag_name().name() {
            "Sun" => {
                let elevation = xml.num(element, "elevation")?.to_degrees();
                if !(-18.0..=90.0).contains(&elevation) {
                    return Err(xml.at(
                        element,
                        format!(
                            "<Sun elevation>: {elevation:.1}° (carfollow's sun is −18° to 90°)"
                        ),
                    ));
                }
                // 1.0–1.1 write `intensity`, 1.2 on `illuminance`: lux either way.
                let lux = match (
                    xml.opt_num(element, "illuminance")?,
                    xml.opt_num(element, "intensity")?,
                ) {
                    (Some(l), _) | (None, Some(l)) => Some(l),
                    (None, None) => None,
                };
                if lux.is_some_and(|l| l < 0.0) {
                    return Err(xml.at(element, "<Sun>: a negative illuminance"));
                }
                out.sun = Some(SunOut {
                    azimuth_deg: azimuth_deg(xml.num(element, "azimuth")?, road_heading_rad),
                    elevation_deg: elevation,
                    strength: lux.map(|l| (l / FULL_SUN_LUX).min(MAX_STRENGTH)),
                });
            }
            "Fog" => {
                let v = xml.num(element, "visualRange")?;
                if !(1.0..=100_000.0).contains(&v) {
                    return Err(xml.at(
                        element,
                        format!("<Fog visualRange=\"{v}\">: carfollow's fog is 1–100000 m"),
                    ));
                }
                if let Some(b) = child(element, "BoundingBox") {
                    unapplied.push(format!("the fog's <BoundingBox> (line {})", xml.line(b)));
                }
                // Clear air beyond carfollow's longest range: no fog.
                out.fog = Some(FogOut { visual_range_m: v });
            }
            "Precipitation" => {
                let kind = xml.attr(element, "precipitationType")?.unwrap_or_default();
                // 1.0 writes `intensity`, 1.1 on `precipitationIntensity`: mm/h.
                let rate = match (
                    xml.opt_num(element, "precipitationIntensity")?,
                    xml.opt_num(element, "intensity")?,
                ) {
                    (Some(r), _) | (None, Some(r)) => r,
                    (None, None) => 0.0,
                };
                match kind.as_str() {
                    "dry" => {}
                    "rain" if (0.0..=200.0).contains(&rate) => {
                        if rate > 0.0 {
                            out.rain = Some(RainOut { rate_mm_h: rate });
                        }
                    }
                    "rain" => return Err(xml.at(element, format!("<Precipitation precipitationIntensity=\"{rate}\">: carfollow's rain is 0–200 mm/h"))),
                    _ => return Err(xml.at(element, format!("<Precipitation precipitationType=\"{kind}\">: carfollow renders rain, or none (\"dry\")"))),
                }
            }
            "Wind" | "DomeImage" => unapplied.push(format!("<{}>", element.tag_name().name())),
            _ => return Err(xml.unsupported(element, "weather element", "")),
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::azimuth_deg;

    /// The sun's direction in carfollow's frame, from the azimuth (cos az, sin az) on the
    /// ground plane (x ahead at the road's start, z to its right).
    fn towards(az_deg: f64) -> [f64; 2] {
        let a = az_deg.to_radians();
        [a.cos(), a.sin()]
    }

    #[test]
    fn the_suns_compass_turns_with_the_road() {
        let close =
            |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).abs() < 1e-12 && (a[1] - b[1]).abs() < 1e-12;
        // A road heading east (hdg 0): a sun in the north is to the road's left (−z), one
        // in the east ahead (+x), one in the south to its right (+z).
        assert!(close(towards(azimuth_deg(0.0, 0.0)), [0.0, -1.0]));
        assert!(close(
            towards(azimuth_deg(std::f64::consts::FRAC_PI_2, 0.0)),
            [1.0, 0.0]
        ));
        assert!(close(
            towards(azimuth_deg(std::f64::consts::PI, 0.0)),
            [0.0, 1.0]
        ));
        // A road heading north (hdg π/2): the northern sun is ahead.
        assert!(close(
            towards(azimuth_deg(0.0, std::f64::consts::FRAC_PI_2)),
            [1.0, 0.0]
        ));
        assert!(azimuth_deg(6.2, 6.2).abs() <= 360.0);
    }
}
