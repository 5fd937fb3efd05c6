//! The actions of the stories' events, each onto an event's action: speed changes (to a
//! speed or relative to a vehicle's), speed profiles, kept gaps, lane changes and lane
//! offsets.

use super::super::error::OscError;
use super::super::init::RoadLanes;
use super::super::xml::{child, children, elements, only_element};
use super::Context;
use roxmltree::Node;
use vehicle::{ActionSpec, KeepSide, KeepSpec, ProfileEntry, Shape};

impl Context<'_, '_> {
    /// An `Action` of an event on `owner`.
    pub(super) fn action(&self, action: Node, owner: &str) -> Result<ActionSpec, OscError> {
        let xml = self.xml;
        let private = only_element(xml, action)?;
        if private.has_tag_name("GlobalAction")
            && super::super::xml::elements(private).any(|e| e.has_tag_name("EnvironmentAction"))
        {
            return Err(xml.at(
                private,
                "unsupported action <EnvironmentAction> in a story: carfollow's environment is fixed for the run (set it in <Init>)",
            ));
        }
        if private.tag_name().name() != "PrivateAction" {
            return Err(xml.unsupported(
                private,
                "action",
                "carfollow's events move their own vehicle",
            ));
        }
        let kind = only_element(xml, private)?;
        // An action of attributes alone (`VisibilityAction`, `ActivateControllerAction`)
        // is one carfollow does not read, not an empty element.
        if elements(kind).next().is_none() {
            return Err(xml.unsupported(kind, "action", ""));
        }
        let inner = only_element(xml, kind)?;
        match (kind.tag_name().name(), inner.tag_name().name()) {
            ("LongitudinalAction", "SpeedAction") => self.speed(inner),
            ("LongitudinalAction", "SpeedProfileAction") => self.speed_profile(inner),
            ("LongitudinalAction", "LongitudinalDistanceAction") => self.keep(inner),
            ("LateralAction", "LaneChangeAction") => self.lane_change(inner, owner),
            ("LateralAction", "LaneOffsetAction") => {
                // An offset is from the vehicle's lane at the time, which for one that
                // starts on the oncoming side carfollow does not follow.
                if self.init.placed.get(owner).is_some_and(|p| p.oncoming) {
                    return Err(xml.at(inner, format!("<LaneOffsetAction>: `{owner}` starts on the oncoming side: an offset of it is refused")));
                }
                self.lane_offset(inner)
            }
            _ => Err(xml.unsupported(inner, "action", "")),
        }
    }

    /// A `LongitudinalDistanceAction`: a gap (`distance`) or time gap (`timeGap`) kept to a
    /// vehicle, bumper to bumper (`freespace="true"`) or between the reference points,
    /// behind it (`displacement` `trailingReferencedEntity`, and when left out, as the
    /// 1.2 schema and esmini read it), ahead (`leadingReferencedEntity`) or on the side it
    /// is on (`any`), along the road (`coordinateSystem` `road`, `lane` or `entity`,
    /// which on carfollow's one road measure the same), within its `DynamicConstraints`.
    fn keep(&self, action: Node) -> Result<ActionSpec, OscError> {
        let xml = self.xml;
        let (gap_m, time_gap_s) = match (
            xml.opt_num(action, "distance")?,
            xml.opt_num(action, "timeGap")?,
        ) {
            (Some(d), None) => (Some(d), None),
            (None, Some(t)) => (None, Some(t)),
            _ => {
                return Err(xml.at(
                    action,
                    "<LongitudinalDistanceAction> takes exactly one of distance and timeGap",
                ))
            }
        };
        let side = match xml.attr(action, "displacement")?.as_deref() {
            None | Some("trailingReferencedEntity") => KeepSide::Behind,
            Some("leadingReferencedEntity") => KeepSide::Ahead,
            Some("any") => KeepSide::Either,
            Some(d) => return Err(xml.at(action, format!("<LongitudinalDistanceAction displacement=\"{d}\">: not a displacement of the standard (trailingReferencedEntity, leadingReferencedEntity, any)"))),
        };
        match xml.attr(action, "coordinateSystem")?.as_deref() {
            None | Some("road" | "lane" | "entity") => {}
            Some(c) => return Err(xml.at(action, format!("<LongitudinalDistanceAction coordinateSystem=\"{c}\">: carfollow measures gaps along the road"))),
        }
        let mut keep = KeepSpec {
            to: self.name(action, &xml.req(action, "entityRef")?)?,
            gap_m,
            time_gap_s,
            between_axles: !xml.boolean(action, "freespace")?,
            side: Some(side),
            continuous: Some(xml.boolean(action, "continuous")?),
            ..KeepSpec::default()
        };
        if let Some(c) = child(action, "DynamicConstraints") {
            keep.max_accel_mps2 = xml.opt_num(c, "maxAcceleration")?;
            keep.max_decel_mps2 = xml.opt_num(c, "maxDeceleration")?;
            keep.max_speed_mps = xml.opt_num(c, "maxSpeed")?;
            keep.max_jerk_mps3 = match (xml.opt_num(c, "maxAccelerationRate")?, xml.opt_num(c, "maxDecelerationRate")?) {
                (None, None) => None,
                (Some(a), Some(d)) if a == d => Some(a),
                (a, d) => return Err(xml.at(c, format!("<DynamicConstraints maxAccelerationRate={a:?} maxDecelerationRate={d:?}>: carfollow's kept gap takes one jerk limit for both, or none"))),
            };
        }
        Ok(ActionSpec {
            keep: Some(keep),
            ..ActionSpec::default()
        })
    }

    /// A `LaneOffsetAction` to an absolute offset, cubic or sinusoidal at its
    /// `maxLateralAcc`. Continuous or not, the vehicle keeps the offset until another
    /// lateral action; a continuous one never ends, so nothing may wait for its end.
    fn lane_offset(&self, action: Node) -> Result<ActionSpec, OscError> {
        let xml = self.xml;
        let dynamics = child(action, "LaneOffsetActionDynamics").ok_or_else(|| {
            xml.at(
                action,
                "<LaneOffsetAction> has no <LaneOffsetActionDynamics>",
            )
        })?;
        let shape = match xml.req(dynamics, "dynamicsShape")?.as_str() {
            "cubic" => Shape::Cubic,
            "sinusoidal" => Shape::Sinusoidal,
            other => return Err(xml.at(dynamics, format!("<LaneOffsetActionDynamics dynamicsShape=\"{other}\">: carfollow's offsets are cubic or sinusoidal"))),
        };
        let accel = xml.opt_num(dynamics, "maxLateralAcc")?.ok_or_else(|| {
            xml.at(dynamics, "<LaneOffsetActionDynamics> has no maxLateralAcc: carfollow moves an offset at its peak lateral acceleration")
        })?;
        let target = child(action, "LaneOffsetTarget")
            .map(|t| only_element(xml, t))
            .transpose()?
            .ok_or_else(|| xml.at(action, "<LaneOffsetAction> has no <LaneOffsetTarget>"))?;
        if target.tag_name().name() != "AbsoluteTargetLaneOffset" {
            return Err(xml.unsupported(
                target,
                "lane offset target",
                "carfollow's offsets are from the vehicle's own lane's centre",
            ));
        }
        Ok(ActionSpec {
            offset_m: Some(xml.num(target, "value")?),
            lateral_accel_mps2: Some(accel),
            shape: Some(shape),
            ..ActionSpec::default()
        })
    }

    /// A `SpeedProfileAction` (`followingMode="position"`, absolute speeds): its entries
    /// as a profile's changes, each over its `time`, or without one at the
    /// `DynamicConstraints`' `maxAcceleration` or `maxDeceleration` as the change goes.
    fn speed_profile(&self, action: Node) -> Result<ActionSpec, OscError> {
        let xml = self.xml;
        if let Some(of) = xml.attr(action, "entityRef")? {
            return Err(xml.at(action, format!("<SpeedProfileAction entityRef=\"{of}\">: carfollow's profiles are of absolute speeds")));
        }
        match xml.req(action, "followingMode")?.as_str() {
            "position" => {}
            mode => return Err(xml.at(action, format!("<SpeedProfileAction followingMode=\"{mode}\">: carfollow follows a profile's changes as written (\"position\")"))),
        }
        let limits = match child(action, "DynamicConstraints") {
            None => None,
            Some(c) => {
                for jerk in ["maxAccelerationRate", "maxDecelerationRate"] {
                    if xml.attr(c, jerk)?.is_some() {
                        return Err(xml.at(c, format!("<DynamicConstraints {jerk}>: carfollow's profile changes are linear")));
                    }
                }
                let max_speed = xml.opt_num(c, "maxSpeed")?;
                Some((
                    xml.num(c, "maxAcceleration")?,
                    xml.num(c, "maxDeceleration")?,
                    max_speed,
                    c,
                ))
            }
        };
        let entries: Vec<_> = children(action, "SpeedProfileEntry").collect();
        if entries.is_empty() {
            return Err(xml.at(action, "<SpeedProfileAction> has no <SpeedProfileEntry>"));
        }
        let mut profile = Vec::with_capacity(entries.len());
        let mut before: Option<f64> = None;
        for entry in entries {
            let speed_mps = xml.num(entry, "speed")?;
            if let Some((_, _, Some(max), c)) = limits {
                if speed_mps > max {
                    return Err(xml.at(c, format!("<DynamicConstraints maxSpeed=\"{max}\">: below a speed of the profile ({speed_mps} m/s), which carfollow would not clip")));
                }
            }
            let (duration_s, rate_mps2) = match (xml.opt_num(entry, "time")?, limits) {
                (Some(t), _) => (Some(t), None),
                (None, Some((up, down, _, c))) => {
                    let rate = match before {
                        Some(v) if speed_mps >= v => up,
                        Some(_) => down,
                        None if up == down => up,
                        None => return Err(xml.at(c, "<DynamicConstraints>: the first entry's rate depends on the speed it starts from: give it a time, or equal maxAcceleration and maxDeceleration")),
                    };
                    (None, Some(rate))
                }
                (None, None) => {
                    return Err(xml.at(
                        entry,
                        "<SpeedProfileEntry> has no time, and its action no <DynamicConstraints>",
                    ))
                }
            };
            profile.push(ProfileEntry {
                speed_mps,
                duration_s,
                rate_mps2,
            });
            before = Some(speed_mps);
        }
        Ok(ActionSpec {
            profile: Some(profile),
            ..ActionSpec::default()
        })
    }

    fn speed(&self, speed: Node) -> Result<ActionSpec, OscError> {
        let xml = self.xml;
        let dynamics = child(speed, "SpeedActionDynamics")
            .ok_or_else(|| xml.at(speed, "<SpeedAction> has no <SpeedActionDynamics>"))?;
        let target = child(speed, "SpeedActionTarget")
            .map(|t| only_element(xml, t))
            .transpose()?
            .ok_or_else(|| xml.at(speed, "<SpeedAction> has no <SpeedActionTarget>"))?;
        let mut spec = match target.tag_name().name() {
            "AbsoluteTargetSpeed" => ActionSpec {
                speed_mps: Some(xml.num(target, "value")?),
                ..ActionSpec::default()
            },
            "RelativeTargetSpeed" => self.relative_speed_target(target)?,
            _ => {
                return Err(xml.unsupported(
                    target,
                    "speed target",
                    "carfollow's speed actions go to a speed, or relative to a vehicle's",
                ))
            }
        };
        let shape = xml.req(dynamics, "dynamicsShape")?;
        let dimension = xml.req(dynamics, "dynamicsDimension")?;
        let value = xml.num(dynamics, "value")?;
        match (shape.as_str(), dimension.as_str()) {
            ("step", _) => spec.shape = Some(Shape::Step),
            (_, "time") if value == 0.0 => spec.shape = Some(Shape::Step),
            ("linear", "time") => {
                spec.duration_s = Some(value);
                spec.shape = Some(Shape::Linear);
            }
            ("cubic", "time") => {
                spec.duration_s = Some(value);
                spec.shape = Some(Shape::Cubic);
            }
            ("linear", "rate") => spec.rate_mps2 = Some(value.abs()),
            _ => return Err(xml.at(dynamics, format!("<SpeedActionDynamics dynamicsShape=\"{shape}\" dynamicsDimension=\"{dimension}\">: carfollow's speed changes are a step, linear over a time or at a rate, or cubic over a time"))),
        }
        Ok(spec)
    }

    /// A `RelativeTargetSpeed` `target`: the speed of the vehicle it names plus its value
    /// (`delta`) or times it (`factor`), kept so with `continuous="true"`.
    fn relative_speed_target(&self, target: Node) -> Result<ActionSpec, OscError> {
        let xml = self.xml;
        let of = self.name(target, &xml.req(target, "entityRef")?)?;
        let value = xml.num(target, "value")?;
        let continuous = xml.boolean(target, "continuous")?;
        let mut spec = ActionSpec {
            speed_of: Some(of),
            continuous,
            ..ActionSpec::default()
        };
        match xml.req(target, "speedTargetValueType")?.as_str() {
            "delta" => spec.speed_mps = Some(value),
            "factor" => spec.speed_factor = Some(value),
            v => {
                return Err(xml.at(
                    target,
                    format!("<RelativeTargetSpeed speedTargetValueType=\"{v}\">: delta or factor"),
                ))
            }
        }
        Ok(spec)
    }

    fn lane_change(&self, change: Node, owner: &str) -> Result<ActionSpec, OscError> {
        let xml = self.xml;
        if xml
            .opt_num(change, "targetLaneOffset")?
            .is_some_and(|o| o != 0.0)
        {
            return Err(xml.at(change, "<LaneChangeAction targetLaneOffset>: carfollow's lane changes end on the lane's centre"));
        }
        let dynamics = child(change, "LaneChangeActionDynamics").ok_or_else(|| {
            xml.at(
                change,
                "<LaneChangeAction> has no <LaneChangeActionDynamics>",
            )
        })?;
        let target = child(change, "LaneChangeTarget")
            .map(|t| only_element(xml, t))
            .transpose()?
            .ok_or_else(|| xml.at(change, "<LaneChangeAction> has no <LaneChangeTarget>"))?;
        let id = match target.tag_name().name() {
            "AbsoluteTargetLane" => {
                let v = xml.req(target, "value")?;
                v.trim().parse::<i64>().map_err(|_| {
                    xml.at(
                        target,
                        format!("<AbsoluteTargetLane value=\"{v}\">: not a lane id"),
                    )
                })?
            }
            "RelativeTargetLane" => {
                let of = xml.req(target, "entityRef")?;
                let changes = self.lane_changes.get(&of).copied().unwrap_or(0);
                if !(changes == 0 || (of == owner && changes == 1)) {
                    return Err(xml.at(target, format!("<RelativeTargetLane entityRef=\"{of}\">: `{of}` changes lane in the stories, so its lane when this starts is not known before the run")));
                }
                let placed = self.init.placed.get(&of).ok_or_else(|| {
                    xml.at(
                        target,
                        format!("<RelativeTargetLane>: `{of}` is not placed in <Init>"),
                    )
                })?;
                if placed.oncoming {
                    return Err(xml.at(target, format!("<RelativeTargetLane entityRef=\"{of}\">: `{of}` starts on the oncoming side: a lane counted from it is refused")));
                }
                let lane = placed.lane;
                let d = xml.num(target, "value")?;
                if d.fract() != 0.0 || d.abs() > 100.0 {
                    return Err(xml.at(
                        target,
                        format!("<RelativeTargetLane value=\"{d}\">: not a whole number of lanes"),
                    ));
                }
                RoadLanes::relative_id(self.road.id_of(lane), d as i64)
            }
            _ => return Err(xml.unsupported(target, "lane change target", "")),
        };
        let Some(lane) = self.road.lane_of(id) else {
            return Err(xml.at(
                target,
                format!(
                    "<{}>: {}",
                    target.tag_name().name(),
                    self.road.not_driven(id)
                ),
            ));
        };
        let shape = xml.req(dynamics, "dynamicsShape")?;
        let dimension = xml.req(dynamics, "dynamicsDimension")?;
        let value = xml.num(dynamics, "value")?;
        let mut spec = ActionSpec {
            lane: Some(lane),
            ..ActionSpec::default()
        };
        spec.shape = match shape.as_str() {
            "sinusoidal" => Some(Shape::Sinusoidal),
            "cubic" => Some(Shape::Cubic),
            _ => return Err(xml.at(dynamics, format!("<LaneChangeActionDynamics dynamicsShape=\"{shape}\">: carfollow's lane changes are cubic or sinusoidal"))),
        };
        match dimension.as_str() {
            "time" => spec.duration_s = Some(value),
            "rate" => spec.lateral_speed_mps = Some(value.abs()),
            _ => return Err(xml.at(dynamics, format!("<LaneChangeActionDynamics dynamicsDimension=\"{dimension}\">: carfollow's lane changes take a time or a lateral rate"))),
        }
        Ok(spec)
    }
}
