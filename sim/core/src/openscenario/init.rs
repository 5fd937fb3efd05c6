//! `Storyboard/Init`: where each vehicle starts (a `TeleportAction`) and at what speed (a
//! `SpeedAction` with a step), on the scenario's one road.

use super::error::OscError;
use super::world::ReferenceLine;
use super::xml::{child, elements, only_element, Xml};
use roxmltree::Node;
use std::collections::BTreeMap;

/// The fastest a carfollow vehicle drives, m/s (a speed profile's bound).
pub const MAX_SPEED_MPS: f64 = 40.0;

/// How far a lateral position may lie from a lane's centre and still be that lane's centre,
/// m (a start offset within it is none).
const LANE_CENTRE_TOLERANCE_M: f64 = 0.05;
/// How far a `WorldPosition`'s heading may turn from the road's and still be along it
/// unsaid, radians (1°): carfollow's vehicles start along their lane.
const HEADING_TOLERANCE_RAD: f64 = 0.0175;

/// The road the scenario's vehicles are placed on, as far as placing them needs: its id,
/// and its lanes on the right of its reference line (OpenDRIVE's −1, −2, ...).
#[derive(Clone, Debug)]
pub struct RoadLanes {
    /// Its first heading in the file's frame, radians counter-clockwise from +x (carfollow's
    /// +x): for the sun's compass.
    pub heading_rad: f64,
    /// The (first) road's id.
    pub id: String,
    /// The roads the route drives, in order, each with where it starts along the route.
    pub roads: Vec<crate::opendrive::ChainedRoad>,
    /// Driving lanes on the right of the reference line.
    pub lanes: u32,
    /// Each lane's width, m (lane 1's when `lane_widths_m` is given).
    pub lane_width_m: f64,
    /// Each driving lane's width, m, lane 1 first, when they differ; else empty.
    pub lane_widths_m: Vec<f64>,
    /// The lanes between the reference line and lane 1 together (the median), m.
    pub median_m: f64,
    /// How many lanes lie between the reference line and lane 1 on the right: carfollow's
    /// lane k is OpenDRIVE's lane −(k + this).
    pub inner_lanes: u32,
    /// The reference line in the file's frame, for `WorldPosition`s.
    pub reference: ReferenceLine,
    /// The road's lane offset (`route.lane_offset`): how far its centre lane lies to the
    /// left of the reference line, as `[s, a, b, c, d]` records; empty for none.
    pub lane_offset: Vec<[f64; 5]>,
}

impl RoadLanes {
    /// The centre of lane `lane` (1-based), m to the right of the reference line: the
    /// route's own rule (`RouteSpec::lane_centre_m`).
    pub fn centre_m(&self, lane: u32) -> f64 {
        sim_render::RouteSpec {
            segments: Vec::new(),
            intersections_m: Vec::new(),
            lane_width_m: self.lane_width_m,
            lanes: self.lanes,
            elevation: Vec::new(),
            median_m: self.median_m,
            lane_widths_m: self.lane_widths_m.clone(),
            lane_offset: Vec::new(),
        }
        .lane_centre_m(lane)
    }

    /// The OpenDRIVE id of lane `lane` (1-based): −(lane + inner lanes).
    pub fn id_of(&self, lane: u32) -> i64 {
        -i64::from(lane) - i64::from(self.inner_lanes)
    }

    /// The OpenDRIVE id `d` lanes to the left of lane id `base` (to the right for `d`
    /// negative), the centre lane, id 0, not counted, as esmini counts relative lanes
    /// (`roadmanager::GetRelativeLaneId`): `−1` and `1` lanes to the left is `1`.
    pub fn relative_id(base: i64, d: i64) -> i64 {
        let id = base + d;
        if id == 0 || (base != 0 && id.signum() != base.signum()) {
            (id - base).signum() * (id.abs() + 1)
        } else {
            id
        }
    }

    /// Why lane id `id` is not one carfollow drives on: the oncoming side (positive ids,
    /// left of the reference line), or none of the lanes on the right of it.
    pub fn not_driven(&self, id: i64) -> String {
        if id > 0 {
            format!(
                "lane {id} is on the oncoming side of road {}, left of its reference line: carfollow's vehicles drive the lanes on its right ({})",
                self.id,
                self.named()
            )
        } else {
            format!(
                "lane {id} is not a lane carfollow drives on road {} ({}: the lanes on the right of its reference line)",
                self.id,
                self.named()
            )
        }
    }

    /// The lane of our side that OpenDRIVE id `id`, a lane of the oncoming side, mirrors,
    /// if it is one carfollow draws (`id` = lane + inner lanes).
    pub fn oncoming_lane_of(&self, id: i64) -> Option<u32> {
        let k = id - i64::from(self.inner_lanes);
        (1..=i64::from(self.lanes)).contains(&k).then_some(k as u32)
    }

    /// The lane of OpenDRIVE id `id`, if carfollow drives on it.
    pub fn lane_of(&self, id: i64) -> Option<u32> {
        let k = -id - i64::from(self.inner_lanes);
        (1..=i64::from(self.lanes)).contains(&k).then_some(k as u32)
    }

    /// How far the centre lane lies to the left of the reference line at station `s_m`,
    /// m (the lane offset; 0 without one).
    pub fn offset_at(&self, s_m: f64) -> f64 {
        sim_render::elevation_at(&self.lane_offset, s_m.max(0.0))
    }

    /// The offset to the left of lane `lane`'s centre, m, of the point at station `s_m`
    /// that lies `t_m` to the left of the reference line.
    pub fn left_of_centre_m(&self, s_m: f64, lane: u32, t_m: f64) -> f64 {
        t_m - self.offset_at(s_m) + self.centre_m(lane)
    }

    /// The width of lane `lane` (1-based), m.
    fn width_of(&self, lane: u32) -> f64 {
        self.lane_widths_m
            .get(lane as usize - 1)
            .copied()
            .unwrap_or(self.lane_width_m)
    }

    /// The driving lane whose strip (its centre ± half its width) holds the point at
    /// station `s_m` that lies `t_m` from the reference line (negative to the right).
    pub fn lane_holding(&self, s_m: f64, t_m: f64) -> Option<u32> {
        (1..=self.lanes)
            .find(|&k| self.left_of_centre_m(s_m, k, t_m).abs() <= 0.5 * self.width_of(k))
    }

    /// The driving lane on the right whose strip holds the reference point of a vehicle
    /// placed at `p`: none on the oncoming side.
    pub fn lane_of_placed(&self, p: &Placed) -> Option<u32> {
        let t_m = self.offset_at(p.s_m) - self.centre_m(p.lane) + p.offset_m;
        self.lane_holding(p.s_m, t_m)
    }

    /// The lane of the oncoming side whose strip (its centre ± half its width, mirroring
    /// ours about the centre line) holds the point at station `s_m` that lies `t_m` from the
    /// reference line: the lane of ours it mirrors.
    pub fn oncoming_lane_holding(&self, s_m: f64, t_m: f64) -> Option<u32> {
        let left_m = t_m - self.offset_at(s_m);
        (1..=self.lanes).find(|&k| (left_m - self.centre_m(k)).abs() <= 0.5 * self.width_of(k))
    }

    /// The driving lanes' ids, for errors.
    pub fn named(&self) -> String {
        match self.lanes {
            1 => format!("{}", self.id_of(1)).replace('-', "−"),
            n => format!("{} to {}", self.id_of(1), self.id_of(n)).replace('-', "−"),
        }
    }
}

/// Where a vehicle starts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placed {
    /// Its reference point's (the rear axle's) station along the road, m.
    pub s_m: f64,
    /// Its lane: 1 next to the reference line (OpenDRIVE's −1).
    pub lane: u32,
    /// Its offset to the left of its lane's centre, m (0 within
    /// [`LANE_CENTRE_TOLERANCE_M`] of it).
    pub offset_m: f64,
    /// Whether it starts on a lane of the oncoming side, turned to drive with the road:
    /// `lane` is then 1, and `offset_m` reaches across to that lane.
    pub oncoming: bool,
}

impl Placed {
    /// At `s_m` in `lane`, `offset_m` to the left of its centre; an offset within
    /// [`LANE_CENTRE_TOLERANCE_M`] is the centre.
    fn new(s_m: f64, lane: u32, offset_m: f64) -> Placed {
        let offset_m = if offset_m.abs() <= LANE_CENTRE_TOLERANCE_M {
            0.0
        } else {
            offset_m
        };
        Placed {
            s_m,
            lane,
            offset_m,
            oncoming: false,
        }
    }
}

/// What `Init` says of each vehicle.
#[derive(Debug, Default)]
pub struct Init {
    /// Where each starts, by entity name.
    pub placed: BTreeMap<String, Placed>,
    /// Each one's speed at t = 0, m/s (0 when `Init` sets none).
    pub speed_mps: BTreeMap<String, f64>,
    /// The line of each one's `Private`, for errors about its start.
    pub line: BTreeMap<String, u32>,
    /// Lines the importer warns about: what it reads and does not apply.
    pub warnings: Vec<String>,
    /// The lines of the ego's controller actions in `Init`, read and not applied.
    pub ego_controller_lines: Vec<u32>,
    /// The environment `Init` sets, if any.
    pub environment: Option<super::environment::EnvironmentOut>,
}

/// A position still to be placed, relative to another vehicle's.
struct Relative<'a, 'b> {
    entity: String,
    node: Node<'a, 'b>,
    to: String,
}

/// Reads `Init` (environments from `catalogs`); `ego` is the entity carfollow drives (its controller assignments are read
/// and not applied).
pub fn read_init(
    xml: &Xml,
    road: &RoadLanes,
    ego: &str,
    catalogs: &super::entities::Catalogs,
) -> Result<Init, OscError> {
    let root = xml.doc.root_element();
    let storyboard = child(root, "Storyboard")
        .ok_or_else(|| xml.at(root, "<OpenSCENARIO> has no <Storyboard>"))?;
    let mut init = Init::default();
    let Some(actions) = child(storyboard, "Init").and_then(|i| child(i, "Actions")) else {
        return Ok(init);
    };
    let mut relative = Vec::new();
    for element in elements(actions) {
        match element.tag_name().name() {
            "Private" => {
                let entity = xml.req(element, "entityRef")?;
                init.line.insert(entity.clone(), xml.line(element));
                for action in elements(element) {
                    private_action(xml, road, ego, &entity, action, &mut init, &mut relative)?;
                }
            }
            "GlobalAction" => {
                let action = only_element(xml, element)?;
                if action.tag_name().name() != "EnvironmentAction" || init.environment.is_some() {
                    return Err(xml.unsupported(action, "global action", ""));
                }
                init.environment = Some(super::environment::environment(
                    xml,
                    action,
                    catalogs,
                    road.heading_rad,
                    &mut init.warnings,
                )?);
            }
            _ => return Err(xml.unsupported(element, "init action", "")),
        }
    }
    // Relative positions, each once the vehicle it is relative to is placed.
    while !relative.is_empty() {
        let ready = relative
            .iter()
            .position(|r: &Relative| init.placed.contains_key(&r.to));
        let Some(i) = ready else {
            let r = &relative[0];
            return Err(xml.at(r.node, format!("<{}>: `{}` is placed by no <TeleportAction> (or the positions refer to each other in a loop)", r.node.tag_name().name(), r.to)));
        };
        let r = relative.remove(i);
        let base = init.placed[&r.to];
        if base.oncoming {
            return Err(xml.at(
                r.node,
                format!(
                    "<{}>: `{}` starts on the oncoming side: a position relative to it is refused",
                    r.node.tag_name().name(),
                    r.to
                ),
            ));
        }
        let placed = relative_position(xml, road, r.node, base)?;
        // Its reference vehicle drives along the road, so an orientation relative to
        // either is relative to the road.
        facing(xml, road, r.node, placed, &mut init.warnings)?;
        init.placed.insert(r.entity, placed);
    }
    Ok(init)
}

/// One `PrivateAction` of `entity` in `Init`.
fn private_action<'a, 'b>(
    xml: &Xml,
    road: &RoadLanes,
    ego: &str,
    entity: &str,
    action: Node<'a, 'b>,
    init: &mut Init,
    relative: &mut Vec<Relative<'a, 'b>>,
) -> Result<(), OscError> {
    if action.tag_name().name() != "PrivateAction" {
        return Err(xml.unsupported(action, "element", ""));
    }
    let inner = only_element(xml, action)?;
    match inner.tag_name().name() {
        "TeleportAction" => {
            let position = child(inner, "Position")
                .ok_or_else(|| xml.at(inner, "<TeleportAction> has no <Position>"))?;
            let p = only_element(xml, position)?;
            match p.tag_name().name() {
                "LanePosition" | "RoadPosition" => {
                    let placed = absolute_position(xml, road, p)?;
                    facing(xml, road, p, placed, &mut init.warnings)?;
                    init.placed.insert(entity.to_string(), placed);
                }
                "WorldPosition" => {
                    let placed = world_position(xml, road, p, &mut init.warnings)?;
                    init.placed.insert(entity.to_string(), placed);
                }
                "RelativeLanePosition" | "RelativeRoadPosition" => relative.push(Relative {
                    entity: entity.to_string(),
                    node: p,
                    to: xml.req(p, "entityRef")?,
                }),
                _ => {
                    return Err(xml.unsupported(
                        p,
                        "position",
                        "carfollow places vehicles on lanes of its road",
                    ))
                }
            }
        }
        "LongitudinalAction" => {
            let speed = only_element(xml, inner)?;
            let v = initial_speed(xml, speed, entity == ego, &mut init.warnings)?;
            init.speed_mps.insert(entity.to_string(), v);
        }
        // Activating the default controller of a vehicle none is assigned to: its
        // storyboard drives it, as carfollow's events do.
        "ActivateControllerAction" if entity != ego => {}
        // Said in the one warning of what of the ego is not applied.
        "ControllerAction" | "ActivateControllerAction" if entity == ego => {
            init.ego_controller_lines.push(xml.line(inner));
        }
        _ => return Err(xml.unsupported(inner, "init action", "")),
    }
    Ok(())
}

/// A `SpeedAction` of `Init`: a step to an absolute speed. The ego's may be a change over
/// a time or at a rate, from standing: carfollow's loop drives the chase, which starts at
/// the speed the change reaches (its set speed), and a warning in `warnings` says so.
fn initial_speed(
    xml: &Xml,
    speed: Node,
    ego: bool,
    warnings: &mut Vec<String>,
) -> Result<f64, OscError> {
    if speed.tag_name().name() != "SpeedAction" {
        return Err(xml.unsupported(speed, "init action", "Init sets a speed by <SpeedAction>"));
    }
    let mut change = None;
    if let Some(dynamics) = child(speed, "SpeedActionDynamics") {
        let shape = xml.req(dynamics, "dynamicsShape")?;
        let value = xml.opt_num(dynamics, "value")?.unwrap_or(0.0);
        if shape != "step" && value != 0.0 {
            if !ego {
                return Err(xml.at(dynamics, format!("<SpeedActionDynamics dynamicsShape=\"{shape}\">: Init sets each speed at once (a step), but the ego's")));
            }
            change = Some((xml.line(dynamics), shape));
        }
    }
    let target = child(speed, "SpeedActionTarget")
        .ok_or_else(|| xml.at(speed, "<SpeedAction> has no <SpeedActionTarget>"))?;
    let absolute = only_element(xml, target)?;
    if absolute.tag_name().name() != "AbsoluteTargetSpeed" {
        return Err(xml.unsupported(absolute, "init speed", "Init sets absolute speeds"));
    }
    let v = xml.num(absolute, "value")?;
    if !(0.0..=MAX_SPEED_MPS).contains(&v) {
        return Err(xml.at(absolute, format!("<AbsoluteTargetSpeed value=\"{v}\">: carfollow's vehicles drive forward at 0–{} m/s", MAX_SPEED_MPS)));
    }
    if let Some((line, shape)) = change {
        warnings.push(format!(
            "line {line}: the ego's {shape} speed change in <Init> is not applied: carfollow's loop drives the chase, which starts at the speed it reaches, {v} m/s"
        ));
    }
    Ok(v)
}

/// The lane of a lane id (`−(k + inner lanes)` is lane `k`).
fn lane_of_id(xml: &Xml, road: &RoadLanes, node: Node, id: i64) -> Result<u32, OscError> {
    road.lane_of(id).ok_or_else(|| {
        xml.at(
            node,
            format!("<{}>: {}", node.tag_name().name(), road.not_driven(id)),
        )
    })
}

/// The lane whose strip holds the point at station `s_m`, `t_m` from the reference line
/// (negative to the right), and the point's offset to the left of that lane's centre.
fn lane_at(
    xml: &Xml,
    road: &RoadLanes,
    node: Node,
    s_m: f64,
    t_m: f64,
) -> Result<Placed, OscError> {
    if let Some(k) = road.lane_holding(s_m, t_m) {
        return Ok(Placed::new(s_m, k, road.left_of_centre_m(s_m, k, t_m)));
    }
    // On a lane of the oncoming side: lane 1, that far to the left of its centre.
    if road.oncoming_lane_holding(s_m, t_m).is_some() {
        return Ok(Placed {
            oncoming: true,
            ..Placed::new(s_m, 1, road.left_of_centre_m(s_m, 1, t_m))
        });
    }
    Err(xml.at(
        node,
        format!(
            "<{}>: t = {t_m} m is on no lane carfollow drives on road {} ({})",
            node.tag_name().name(),
            road.id,
            road.named()
        ),
    ))
}

/// The station along the route of `s_m` on the road `node`'s `roadId` names: one of the
/// route's roads, `s_m` within its length.
fn route_station(xml: &Xml, road: &RoadLanes, node: Node, s_m: f64) -> Result<f64, OscError> {
    let id = xml.req(node, "roadId")?;
    let tag = node.tag_name().name();
    let Some(on) = road.roads.iter().find(|r| r.id == id) else {
        let ids: Vec<&str> = road.roads.iter().map(|r| r.id.as_str()).collect();
        let alone = if ids.len() == 1 { " alone" } else { "" };
        return Err(xml.at(
            node,
            format!(
                "<{tag} roadId=\"{id}\">: carfollow's route is road {}{alone}",
                ids.join(", ")
            ),
        ));
    };
    if road.roads.len() > 1 && s_m > on.length_m + 1e-6 {
        return Err(xml.at(
            node,
            format!(
                "<{tag}>: s = {s_m} m is past the end of road {id} ({} m long)",
                on.length_m
            ),
        ));
    }
    Ok(on.start_m + s_m)
}

fn check_s(xml: &Xml, node: Node, s: f64) -> Result<f64, OscError> {
    if s < 0.0 {
        return Err(xml.at(
            node,
            format!(
                "<{}>: s = {s} m is before the road's start",
                node.tag_name().name()
            ),
        ));
    }
    Ok(s)
}

/// A `LanePosition` or `RoadPosition`.
fn absolute_position(xml: &Xml, road: &RoadLanes, p: Node) -> Result<Placed, OscError> {
    let s_m = check_s(xml, p, xml.num(p, "s")?)?;
    let s_m = route_station(xml, road, p, s_m)?;
    let (lane, offset_m) = if p.tag_name().name() == "LanePosition" {
        let id = xml.req(p, "laneId")?;
        let id = id
            .trim()
            .parse::<i64>()
            .map_err(|_| xml.at(p, format!("<LanePosition laneId=\"{id}\">: not a lane id")))?;
        let offset = xml.opt_num(p, "offset")?.unwrap_or(0.0);
        if let Some(k) = road.oncoming_lane_of(id) {
            // Lane k of the oncoming side mirrors lane k of ours about the centre line; the
            // offset, like t, is to the left of the reference line.
            return Ok(Placed {
                oncoming: true,
                ..Placed::new(s_m, 1, road.centre_m(1) + road.centre_m(k) + offset)
            });
        }
        (lane_of_id(xml, road, p, id)?, offset)
    } else {
        return lane_at(xml, road, p, s_m, xml.num(p, "t")?);
    };
    Ok(Placed::new(s_m, lane, offset_m))
}

/// A `WorldPosition` `p` on the road: its station, the lane whose strip holds it, its
/// offset to the left of that lane's centre (m) and its heading's turn from the road's
/// (radians; its `h`, 0 when left out, as the standard reads it). Refused off the road's
/// ends, off its driving lanes on the right, and facing against the road.
fn world_point(xml: &Xml, road: &RoadLanes, p: Node) -> Result<(f64, u32, f64, f64), OscError> {
    let (x, y) = (xml.num(p, "x")?, xml.num(p, "y")?);
    let h = xml.opt_num(p, "h")?.unwrap_or(0.0);
    let on = road.reference.project(x, y).ok_or_else(|| {
        xml.at(
            p,
            format!(
                "<WorldPosition x=\"{x}\" y=\"{y}\">: before the start or past the end of road {}",
                road.id
            ),
        )
    })?;
    let Some(lane) = road.lane_holding(on.s_m, on.t_m) else {
        return Err(xml.at(
            p,
            format!(
                "<WorldPosition x=\"{x}\" y=\"{y}\">: t = {:.3} m at s = {:.3} m is on no lane carfollow drives on road {} ({})",
                on.t_m, on.s_m, road.id, road.named()
            ),
        ));
    };
    let turned = (h - on.heading_rad + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU)
        - std::f64::consts::PI;
    if turned.abs() > std::f64::consts::FRAC_PI_2 {
        return Err(xml.at(
            p,
            format!(
                "<WorldPosition h=\"{h}\">: faces against road {} ({:.1}° from its heading there): carfollow's vehicles drive with the road's direction on its right",
                road.id,
                turned.to_degrees()
            ),
        ));
    }
    Ok((
        on.s_m,
        lane,
        road.left_of_centre_m(on.s_m, lane, on.t_m),
        turned,
    ))
}

/// Checks the `<Orientation>` of a vehicle placed at `p` (a lane or road position, relative
/// or not, at station `s_m`): its heading, relative to the road's there (`type="relative"`,
/// as when the type is left out) or in the file's frame (`"absolute"`), must not face
/// against the road; turned farther than [`HEADING_TOLERANCE_RAD`] from it, the vehicle
/// starts along the road, said in a warning, as for a `WorldPosition`. Its pitch and roll
/// are the road's, whatever they say.
pub(super) fn facing(
    xml: &Xml,
    road: &RoadLanes,
    p: Node,
    at: Placed,
    warnings: &mut Vec<String>,
) -> Result<(), OscError> {
    let s_m = at.s_m;
    // A lane of the oncoming side runs against the road: a vehicle there faces that way
    // unless its orientation turns it.
    let lane_turn = if at.oncoming {
        std::f64::consts::PI
    } else {
        0.0
    };
    let Some(o) = child(p, "Orientation") else {
        if at.oncoming {
            return Err(xml.at(p, format!("<{}>: oncoming traffic on road {}: carfollow's vehicles drive with the road (a vehicle on the oncoming side turned to drive with it, relative h = π, is read)", p.tag_name().name(), road.id)));
        }
        return Ok(());
    };
    let h = xml.opt_num(o, "h")?.unwrap_or(0.0);
    let turned = match xml.attr(o, "type")?.as_deref() {
        Some("relative") | None => h + lane_turn,
        Some("absolute") => h - road.reference.heading_at(s_m),
        Some(other) => {
            return Err(xml.at(
                o,
                format!("<Orientation type=\"{other}\">: \"relative\" or \"absolute\""),
            ))
        }
    };
    let turned =
        (turned + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI;
    if turned.abs() > std::f64::consts::FRAC_PI_2 {
        return Err(xml.at(
            o,
            format!(
                "<Orientation h=\"{h}\">: faces against road {} ({:.1}° from its heading there): carfollow's vehicles drive with the road's direction",
                road.id,
                turned.to_degrees()
            ),
        ));
    }
    if turned.abs() > HEADING_TOLERANCE_RAD {
        warnings.push(format!(
            "line {}: <Orientation> is turned {:.1}° from the road: carfollow starts the vehicle along the road",
            xml.line(o),
            turned.to_degrees(),
        ));
    }
    Ok(())
}

/// A `WorldPosition` of a vehicle in `Init`: in its lane, along the road; a heading turned
/// farther from the road's is said in a warning.
fn world_position(
    xml: &Xml,
    road: &RoadLanes,
    p: Node,
    warnings: &mut Vec<String>,
) -> Result<Placed, OscError> {
    let (s_m, lane, offset, turned) = world_point(xml, road, p)?;
    if turned.abs() > HEADING_TOLERANCE_RAD {
        warnings.push(format!(
            "line {}: <WorldPosition> is turned {:.1}° from the road: carfollow starts the vehicle along the road (lane {}, s = {s_m:.2} m)",
            xml.line(p),
            turned.to_degrees(),
            road.id_of(lane),
        ));
    }
    Ok(Placed::new(s_m, lane, offset))
}

/// A `LanePosition`, `RoadPosition` or `WorldPosition` `p` as a point on the road: its
/// station, the lane it is on and its offset to the left of that lane's centre, m.
pub fn point_on_road(xml: &Xml, road: &RoadLanes, p: Node) -> Result<(f64, u32, f64), OscError> {
    let name = p.tag_name().name();
    if name == "WorldPosition" {
        let (s_m, lane, offset, _) = world_point(xml, road, p)?;
        return Ok((s_m, lane, offset));
    }
    if !matches!(name, "LanePosition" | "RoadPosition") {
        return Err(xml.unsupported(
            p,
            "position",
            "carfollow's points are on the road (LanePosition, RoadPosition, WorldPosition)",
        ));
    }
    let s_m = check_s(xml, p, xml.num(p, "s")?)?;
    let s_m = route_station(xml, road, p, s_m)?;
    if name == "LanePosition" {
        let id = xml.req(p, "laneId")?;
        let id = id
            .trim()
            .parse::<i64>()
            .map_err(|_| xml.at(p, format!("<LanePosition laneId=\"{id}\">: not a lane id")))?;
        let lane = lane_of_id(xml, road, p, id)?;
        let offset = xml.opt_num(p, "offset")?.unwrap_or(0.0);
        return Ok((s_m, lane, offset));
    }
    let t_m = xml.num(p, "t")?;
    let Some(k) = road.lane_holding(s_m, t_m) else {
        return Err(xml.at(
            p,
            format!(
                "<RoadPosition>: t = {t_m} m is on no lane carfollow drives on road {} ({})",
                road.id,
                road.named()
            ),
        ));
    };
    Ok((s_m, k, road.left_of_centre_m(s_m, k, t_m)))
}

/// A `RelativeLanePosition` (`dLane`, `ds` or from 1.1 `dsLane`) or `RelativeRoadPosition`
/// (`ds`, `dt`) from `base`.
fn relative_position(
    xml: &Xml,
    road: &RoadLanes,
    p: Node,
    base: Placed,
) -> Result<Placed, OscError> {
    let ds = match (xml.opt_num(p, "ds")?, xml.opt_num(p, "dsLane")?) {
        (Some(ds), None) | (None, Some(ds)) => ds,
        (None, None) => return Err(xml.at(p, format!("<{}> has no `ds`", p.tag_name().name()))),
        (Some(_), Some(_)) => {
            return Err(xml.at(
                p,
                format!("<{}> has both `ds` and `dsLane`", p.tag_name().name()),
            ))
        }
    };
    let s_m = check_s(xml, p, base.s_m + ds)?;
    let (lane, offset_m) = if p.tag_name().name() == "RelativeLanePosition" {
        let d = xml.num(p, "dLane")?;
        if d.fract() != 0.0 || d.abs() > 100.0 {
            return Err(xml.at(
                p,
                format!("<RelativeLanePosition dLane=\"{d}\">: not a whole number of lanes"),
            ));
        }
        // Lane ids grow to the left; the offset is from the target lane's centre.
        let id = RoadLanes::relative_id(road.id_of(base.lane), d as i64);
        let lane = lane_of_id(xml, road, p, id)?;
        (lane, xml.opt_num(p, "offset")?.unwrap_or(0.0))
    } else {
        let t_base = base.offset_m - road.centre_m(base.lane) + road.offset_at(base.s_m);
        return lane_at(xml, road, p, s_m, t_base + xml.num(p, "dt")?);
    };
    Ok(Placed::new(s_m, lane, offset_m))
}

#[cfg(test)]
mod tests {
    use super::RoadLanes;

    #[test]
    fn a_relative_lane_does_not_count_the_centre_lane() {
        // Within one side, ids add.
        assert_eq!(RoadLanes::relative_id(-3, 1), -2);
        assert_eq!(RoadLanes::relative_id(-1, -2), -3);
        assert_eq!(RoadLanes::relative_id(2, 1), 3);
        // Across the centre lane, id 0 is skipped, as esmini's lane change counts.
        assert_eq!(RoadLanes::relative_id(-1, 1), 1);
        assert_eq!(RoadLanes::relative_id(-1, 2), 2);
        assert_eq!(RoadLanes::relative_id(-2, 3), 2);
        assert_eq!(RoadLanes::relative_id(1, -1), -1);
        assert_eq!(RoadLanes::relative_id(2, -3), -2);
        assert_eq!(RoadLanes::relative_id(-2, 0), -2);
    }
}
