//! Where a scene's static geometry lives: built a few districts at a time (`bins`), kept
//! while in use, and built again when asked for after it was let go. A scene's memory then
//! does not grow with its route's length: only the chunks' outlines (index ranges and
//! bounding spheres) are kept for the whole route.
//!
//! The districts are grouped in the order the builders first lay in them (along the route:
//! the ground is laid first, from its start), each group holding about [`GROUP_INDICES`]
//! indices; a group is what is built at once and kept, [`CACHED_GROUPS`] of them.

use super::bins::Cell;
use super::mesh::Mesh;
use std::collections::BTreeSet;
use std::ops::Range;
use std::sync::{Arc, Mutex, PoisonError};

/// Indices a group of districts holds at most, as laid before draping (unless one district
/// alone holds more): about 1.7 MB of geometry, a kilometre and a half of road with its
/// clutter. The builders run whole for each group built, about 2.3 ms a kilometre of
/// route.
pub(super) const GROUP_INDICES: usize = 60_000;

/// Groups kept built at once: the renderer draws from at most about a kilometre of road.
pub(super) const CACHED_GROUPS: usize = 3;

/// Groups the districts of a survey (each district with its indices, in the order first
/// laid in): consecutive districts, each group's indices at most `budget` (or one district).
pub(super) fn group(survey: &[(Cell, usize)], budget: usize) -> Vec<BTreeSet<Cell>> {
    let mut groups: Vec<BTreeSet<Cell>> = Vec::new();
    let mut held = 0;
    for &(district, indices) in survey {
        match groups.last_mut() {
            Some(group) if held + indices <= budget => {
                group.insert(district);
                held += indices;
            }
            _ => {
                groups.push(BTreeSet::from([district]));
                held = indices;
            }
        }
    }
    groups
}

/// Where a chunk's geometry lies: its group, and its indices and vertices in the group's
/// mesh.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Home {
    pub group: usize,
    pub indices: Range<u32>,
    pub vertices: Range<u32>,
}

/// The groups of districts, where each chunk lies, and the groups built.
#[derive(Debug)]
pub(super) struct Districts {
    pub groups: Vec<BTreeSet<Cell>>,
    /// Each chunk's home, in the scene's chunks' order.
    pub homes: Vec<Home>,
    /// The groups built, the one used last at the end.
    built: Mutex<Vec<(usize, Arc<Mesh>)>>,
}

impl Districts {
    /// The districts grouped as `groups`, each chunk's home, and the groups already built.
    pub fn new(
        groups: Vec<BTreeSet<Cell>>,
        homes: Vec<Home>,
        built: Vec<(usize, Arc<Mesh>)>,
    ) -> Districts {
        Districts {
            groups,
            homes,
            built: Mutex::new(built),
        }
    }

    /// The meshes of `wanted` (groups, in that order), built by `build` where they are not
    /// kept; then at most [`CACHED_GROUPS`] are kept, those used last.
    pub fn meshes(&self, wanted: &[usize], build: impl Fn(usize) -> Mesh) -> Vec<Arc<Mesh>> {
        let mut built = self.built.lock().unwrap_or_else(PoisonError::into_inner);
        let meshes = wanted
            .iter()
            .map(|&g| {
                let kept = match built.iter().position(|(h, _)| *h == g) {
                    Some(at) => built.remove(at),
                    None => (g, Arc::new(build(g))),
                };
                let mesh = Arc::clone(&kept.1);
                built.push(kept);
                mesh
            })
            .collect();
        let over = built.len().saturating_sub(CACHED_GROUPS);
        built.drain(..over);
        meshes
    }

    /// How many groups are kept built.
    #[cfg(test)]
    pub fn kept(&self) -> usize {
        self.built
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .len()
    }
}

impl Clone for Districts {
    fn clone(&self) -> Districts {
        let built = self.built.lock().unwrap_or_else(PoisonError::into_inner);
        Districts::new(self.groups.clone(), self.homes.clone(), built.clone())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn districts_are_grouped_in_order_within_the_budget() {
        let survey = [
            ((0, 0), 40),
            ((1, 0), 30),
            ((1, 1), 90),
            ((2, 1), 5),
            ((2, 2), 5),
        ];
        let groups = group(&survey, 70);
        let expected: Vec<BTreeSet<Cell>> = vec![
            [(0, 0), (1, 0)].into(),
            [(1, 1)].into(),
            [(2, 1), (2, 2)].into(),
        ];
        assert_eq!(groups, expected);
        assert!(group(&[], 70).is_empty());
    }
}
