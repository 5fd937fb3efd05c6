//! The roads a route drives: one road, or a chain of roads each linked to the next end to
//! start (its `<successor>` the next road's start, the next road's `<predecessor>`, if
//! given, this road's end), driven one after another along their reference lines. Every
//! road of the file must be on the chain: carfollow draws no other road.

use super::model::{OpenDrive, Road, RoadLink};
use super::OpenDriveError;
use std::path::Path;

/// One road of the chain and where it starts along the route.
#[derive(Clone, Debug, PartialEq)]
pub struct ChainedRoad {
    /// The road's `id`.
    pub id: String,
    /// Its station 0 along the route, metres.
    pub start_m: f64,
    /// Its `length`, metres.
    pub length_m: f64,
}

/// The road's link to a road (`successor` or predecessor), if any; a link to a junction is
/// refused.
fn road_link<'a>(
    road: &'a Road,
    successor: bool,
    path: &Path,
) -> Result<Option<&'a RoadLink>, OpenDriveError> {
    let Some(link) = road.links.iter().find(|l| l.successor == successor) else {
        return Ok(None);
    };
    if link.element_type != "road" {
        return Err(link.at.refuse(
            path,
            "a link to a junction is refused: carfollow's route follows one road, or a chain \
             of roads each linked to the next end to start",
        ));
    }
    Ok(Some(link))
}

/// Whether `road`'s successor names a road other than itself, meeting its start: the link
/// that leads on along a chain.
fn leads_into(road: &Road, id: &str) -> bool {
    road.links.iter().any(|l| {
        l.successor
            && l.element_type == "road"
            && l.element_id == id
            && road.id != id
            && l.contact_point.as_deref() != Some("end")
    })
}

/// The roads of `file` the route drives, in order: from the road `road_id` (without one,
/// the first road in the file that no other road leads into, or the file's first road when
/// every one is led into, a loop), along each road's successor, until a road has none or
/// leads back into the chain's first (a loop, driven once).
pub(super) fn chain<'a>(
    file: &'a OpenDrive,
    road_id: Option<&str>,
) -> Result<Vec<&'a Road>, OpenDriveError> {
    let path = &file.path;
    let first = match road_id {
        Some(id) => file
            .roads
            .iter()
            .find(|r| r.id == id)
            .ok_or_else(|| refused(path, format!("no road with id {id:?}")))?,
        None => {
            let led_into = |r: &Road| file.roads.iter().any(|o| leads_into(o, &r.id));
            file.roads
                .iter()
                .find(|r| !led_into(r))
                .or(file.roads.first())
                .ok_or_else(|| refused(path, "the file holds no road".into()))?
        }
    };
    let mut chain = vec![first];
    let mut road = first;
    while let Some(link) = road_link(road, true, path)? {
        let id = &link.element_id;
        if *id == road.id || *id == first.id {
            break;
        }
        if chain.iter().any(|r| r.id == *id) {
            return Err(link.at.refuse(
                path,
                format!("road {id} is on the route already: a chain of roads leads on or back to its first"),
            ));
        }
        let Some(next) = file.roads.iter().find(|r| r.id == *id) else {
            return Err(link.at.refuse(path, format!("the file holds no road {id}")));
        };
        if link.contact_point.as_deref() == Some("end") {
            return Err(link.at.refuse(
                path,
                format!(
                    "meets road {id} at its end: a road driven against its reference line is \
                     refused (carfollow drives on the right of each road's reference line)"
                ),
            ));
        }
        if let Some(back) = road_link(next, false, path)? {
            if back.element_id != road.id || back.contact_point.as_deref() == Some("start") {
                return Err(back.at.refuse(
                    path,
                    format!(
                        "road {} is led into from road {}'s end, so its predecessor must be \
                         that road's end",
                        next.id, road.id
                    ),
                ));
            }
        }
        chain.push(next);
        road = next;
    }
    if let Some(back) = road_link(first, false, path)? {
        let last = chain
            .last()
            .filter(|l| chain.len() > 1 && leads_into(l, &first.id));
        let id = &back.element_id;
        if *id != first.id && last.is_none_or(|l| l.id != *id) {
            let why = if file.roads.iter().any(|r| r.id == *id) {
                format!(
                    "the route starts at road {}, which road {id} leads into: name the chain's \
                     first road (`route.opendrive`'s `road`), or leave it out",
                    first.id
                )
            } else {
                format!("the file holds no road {id}")
            };
            return Err(back.at.refuse(path, why));
        }
    }
    if let Some(other) = file
        .roads
        .iter()
        .find(|r| !chain.iter().any(|c| c.id == r.id))
    {
        return Err(other.at.refuse(
            path,
            "a road the route does not drive is refused: carfollow's route follows one road, \
             or a chain of roads each linked to the next end to start, and draws no other",
        ));
    }
    Ok(chain)
}

/// Where each road of `chain` starts along the route.
pub(super) fn starts(chain: &[&Road]) -> Vec<ChainedRoad> {
    let mut start_m = 0.0;
    chain
        .iter()
        .map(|r| {
            let c = ChainedRoad {
                id: r.id.clone(),
                start_m,
                length_m: r.length,
            };
            start_m += r.length;
            c
        })
        .collect()
}

fn refused(path: &Path, reason: String) -> OpenDriveError {
    OpenDriveError::Refused {
        path: path.to_owned(),
        line: 1,
        element: "<OpenDRIVE>".into(),
        reason,
    }
}
