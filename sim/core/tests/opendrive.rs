//! OpenDRIVE road files (`route.opendrive`), with esmini's files as the test (MPL-2.0,
//! `tests/data/opendrive/`): the roads carfollow accepts are laid where the file puts them
//! (every geometry's start, moved to carfollow's frame, on the route); what it refuses is
//! refused in one line naming the file, the line and the element; 300 mutated files give
//! no panic and no hang, and whatever `check` accepts, the loop runs.

use sim_core::opendrive::{self, GeometryKind, OpenDrive};
use sim_core::{ClosedLoop, Plan, Scenario};
use sim_render::{Backend, Route, RouteSpec};
use std::path::{Path, PathBuf};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/opendrive")
        .join(name)
}

fn read(name: &str) -> OpenDrive {
    opendrive::load(&data(name)).unwrap_or_else(|e| panic!("{e}"))
}

/// A scenario on road file `file` (absolute), with the library's nist-grounds otherwise.
fn scenario_text(file: &Path) -> String {
    let target =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/targets/nist-ten-segment.toml");
    format!(
        r#"name = "od"
duration_s = 1.0
[route]
opendrive = {{ file = {file:?} }}
[lead]
start_m = 30.0
initial_speed_mps = 5.0
speed_profile = [[0.0, 5.0]]
[tracker]
target = {target:?}
"#,
        file = file.display().to_string(),
        target = target.display().to_string(),
    )
}

fn parse_scenario(text: &str) -> Result<Scenario, sim_core::ScenarioError> {
    Scenario::from_file_text(text, Path::new("/tmp/od.toml"), &[])
}

fn road_length(file: &OpenDrive) -> f64 {
    file.roads[0].length
}

#[test]
fn esmini_roads_lie_where_the_file_puts_them() {
    for (name, lanes, width) in [
        ("straight_500m.xodr", 1, 3.07),
        ("circle_300m.xodr", 1, 3.07),
        ("curves.xodr", 1, 3.07),
        ("striaghtAndCurves.xodr", 1, 3.07),
    ] {
        let file = read(name);
        let road = opendrive::import(&file, None, |_| None).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!((road.lanes, road.lane_width_m), (lanes, width), "{name}");
        let route = Route::new(RouteSpec {
            segments: road.segments.clone(),
            intersections_m: vec![],
            lane_width_m: width,
            lanes,
            elevation: Vec::new(),
            median_m: 0.0,
            lane_widths_m: Vec::new(),
            lane_offset: Vec::new(),
        });
        // The file's frame moved so its road starts at the origin heading +x, its y to
        // carfollow's −z: each geometry's start, by hand from its x, y and hdg.
        let g0 = &file.roads[0].geometries[0];
        let mut worst = 0.0f64;
        // The route lays each piece from the one before's end; the file writes each start
        // with its digits: they differ by the file's own gaps at the joins (4e-6 m in
        // curves.xodr, and a heading turned by them over what follows), summed.
        let mut budget = 1e-9;
        for (k, g) in file.roads[0].geometries.iter().enumerate() {
            if k > 0 {
                let before = &file.roads[0].geometries[k - 1];
                let [x, y, hdg] = opendrive::geometry_end(before);
                budget +=
                    (x - g.x).hypot(y - g.y) + (hdg - g.hdg).abs() * (road_length(&file) - g.s);
            }
            let (dx, dy) = (g.x - g0.x, g.y - g0.y);
            let (sin, cos) = g0.hdg.sin_cos();
            let want = [dx * cos + dy * sin, -(-dx * sin + dy * cos)];
            let [x, z, h] = route.at(g.s);
            let d = (x - want[0]).hypot(z - want[1]);
            assert!(
                d < budget,
                "{name}: geometry at s = {} is {d:e} m off (the file's joins: {budget:e})",
                g.s
            );
            let turn = (h - (g.hdg - g0.hdg)).sin().abs();
            assert!(
                turn < 1e-9,
                "{name}: heading at s = {} off by {turn:e}",
                g.s
            );
            worst = worst.max(d);
        }
        eprintln!("{name}: the route within {worst:.1e} m of the file's geometry starts");
        // And the scenario loads and plans on it.
        let s = parse_scenario(&scenario_text(&data(name))).unwrap_or_else(|e| panic!("{e}"));
        Plan::new(&s).unwrap_or_else(|e| panic!("{name}: {e}"));
    }
}

#[test]
fn a_file_of_param_poly3s_joins_end_to_start() {
    // e6mini's reference line is 16 paramPoly3s:
    // each one's end, from its own polynomials, is where the file starts the next.
    let file = read("e6mini.xodr");
    let geometries = &file.roads[0].geometries;
    let cubics = geometries
        .iter()
        .filter(|g| matches!(g.kind, GeometryKind::ParamPoly3 { .. }))
        .count();
    assert!(cubics >= 10, "{cubics}");
    for pair in geometries.windows(2) {
        let [x, y, hdg] = opendrive::geometry_end(&pair[0]);
        let gap = (x - pair[1].x).hypot(y - pair[1].y);
        assert!(
            gap < opendrive::JOIN_POSITION_M,
            "{gap} m at s = {}",
            pair[1].s
        );
        let turn = (hdg - pair[1].hdg).sin().abs();
        assert!(
            turn < opendrive::JOIN_HEADING_RAD,
            "{turn} rad at s = {}",
            pair[1].s
        );
    }
}

/// The lane offset of a taper: 0 to 1.75 m to the left over `[from, from + 50]` m of the
/// reference line, a cubic of zero slope at both ends, and back over the 50 m after
/// `back_at`, as `<laneOffset>` records.
fn taper(from: f64, back_at: f64) -> Vec<[f64; 5]> {
    let (c, d) = (3.0 * 1.75 / 2500.0, -2.0 * 1.75 / 125_000.0);
    vec![
        [0.0, 0.0, 0.0, 0.0, 0.0],
        [from, 0.0, 0.0, c, d],
        [from + 50.0, 1.75, 0.0, 0.0, 0.0],
        [back_at, 1.75, 0.0, -c, -d],
        [back_at + 50.0, 0.0, 0.0, 0.0, 0.0],
    ]
}

#[test]
fn a_lane_offset_moves_the_centre_line_and_lanes_where_the_file_puts_them() {
    // curves.xodr with a taper on its first straight and spiral, and back on its arc.
    let records = taper(20.0, 150.0);
    let xml: String = records
        .iter()
        .map(|[s, a, b, c, d]| {
            format!("<laneOffset s=\"{s}\" a=\"{a}\" b=\"{b}\" c=\"{c}\" d=\"{d}\"/>\n")
        })
        .collect();
    let text = std::fs::read_to_string(data("curves.xodr"))
        .unwrap()
        .replacen("<laneSection s=", &format!("{xml}<laneSection s="), 1);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("offset.xodr");
    std::fs::write(&path, &text).unwrap();
    let file = opendrive::load(&path).unwrap_or_else(|e| panic!("{e}"));
    let road = opendrive::import(&file, None, |_| None).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(road.lane_offset, records);
    let route = Route::new(RouteSpec {
        segments: road.segments.clone(),
        intersections_m: vec![],
        lane_width_m: road.lane_width_m,
        lanes: road.lanes,
        elevation: Vec::new(),
        median_m: 0.0,
        lane_widths_m: Vec::new(),
        lane_offset: road.lane_offset.clone(),
    });
    // The offset by hand: the record holding s, its cubic in ds.
    let offset = |s: f64| {
        let r = records.iter().rev().find(|r| r[0] <= s).unwrap();
        let ds = s - r[0];
        r[1] + r[2] * ds + r[3] * ds * ds + r[4] * ds * ds * ds
    };
    // OpenDRIVE's point at (s, t): the reference line's point, t along its left normal
    // (carfollow's left is −z turned by the heading).
    let at_st = |s: f64, t: f64| {
        let [x, z, h] = route.reference_at(s);
        [x - t * h.sin(), z - t * h.cos()]
    };
    let half = 0.5 * road.lane_width_m;
    let mut worst = [0.0f64; 2];
    let mut s = 0.0;
    while s <= 260.0 {
        // The centre line, exactly.
        let want = at_st(s, offset(s));
        let got = route.point(s, 0.0);
        let d = (got[0] - want[0]).hypot(got[1] - want[1]);
        assert!(d < 1e-9, "centre line at s = {s}: {d:e} m off");
        worst[0] = worst[0].max(d);
        // Lane 1's centre (OpenDRIVE's t = offset − half a width), on carfollow's lane 1:
        // the nearest of its points about s, every 5 mm.
        let want = at_st(s, offset(s) - half);
        let nearest = (-400..=400)
            .map(|k| {
                let p = route.point(s + 0.005 * f64::from(k), half);
                (p[0] - want[0]).hypot(p[1] - want[1])
            })
            .fold(f64::INFINITY, f64::min);
        assert!(nearest < 0.01, "lane 1 at s = {s}: {nearest} m off");
        worst[1] = worst[1].max(nearest);
        s += 2.5;
    }
    eprintln!(
        "the centre line within {:.1e} m, lane 1's centre within {:.1e} m",
        worst[0], worst[1]
    );
    // And the scenario loads and plans on it; `check` refuses the offset given twice.
    let s = parse_scenario(&scenario_text(&path)).unwrap_or_else(|e| panic!("{e}"));
    Plan::new(&s).unwrap_or_else(|e| panic!("{e}"));
    let twice = scenario_text(&path).replace(
        "[lead]",
        "lane_offset = [[0.0, 1.0, 0.0, 0.0, 0.0]]\n[lead]",
    );
    let Err(err) = parse_scenario(&twice) else {
        panic!("the offset given twice is accepted");
    };
    let err = err.to_string();
    assert!(
        err.contains("route.lane_offset") && err.contains("<laneOffset>"),
        "{err}"
    );
}

/// The line of the first line holding `needle` in `text`, 1-based.
fn line_of(text: &str, needle: &str) -> usize {
    text.lines().position(|l| l.contains(needle)).expect(needle) + 1
}

#[test]
fn every_refusal_names_the_file_line_and_element() {
    let dir = tempfile::tempdir().unwrap();
    let base = std::fs::read_to_string(data("curves.xodr")).unwrap();
    let arc = r#"<arc curvature="7.0000000000000001e-03"/>"#;
    let lane_m1 = r#"<lane id="-1" type="driving" level= "false">"#;
    let cases: Vec<(&str, String, &str, &str)> = vec![
        ("junction", base.replace("</OpenDRIVE>", "<junction id=\"9\" name=\"j\"></junction>\n</OpenDRIVE>"), "<junction", "junctions are refused"),
        ("link", base.replace("<link>\n        </link>", "<link><successor elementType=\"road\" elementId=\"2\" contactPoint=\"start\"/></link>"), "<successor", "the file holds no road 2"),
        ("lht", base.replace("junction=\"-1\">", "junction=\"-1\" rule=\"LHT\">"), "<road ", "left-hand traffic"),
        ("offset", base.replace("<laneSection s=", "<laneOffset s=\"0\" a=\"0\" b=\"0.5\" c=\"0\" d=\"0\"/>\n<laneSection s="), "<laneOffset", "changes by 0.500 m a metre"),
        ("steep", base.replace("<lateralProfile>", "<elevationProfile><elevation s=\"0\" a=\"0\" b=\"0.3\" c=\"0\" d=\"0\"/></elevationProfile>\n<lateralProfile>"), "<elevation ", "grade at station 0.00 m is 30.0 %"),
        ("step", base.replace("<lateralProfile>", "<elevationProfile><elevation s=\"0\" a=\"0\" b=\"0.02\" c=\"0\" d=\"0\"/><elevation s=\"50\" a=\"3\" b=\"0\" c=\"0\" d=\"0\"/></elevationProfile>\n<lateralProfile>"), "<elevation s=\"50\"", "a step"),
        ("superelevation", base.replace("<lateralProfile>", "<lateralProfile><superelevation s=\"0\" a=\"0.05\" b=\"0\" c=\"0\" d=\"0\"/>"), "<superelevation", "superelevation is refused"),
        ("tight", base.replacen(arc, r#"<arc curvature="0.5"/>"#, 1), "<arc curvature=\"0.5\"", "curvature"),
        ("nan", base.replacen(arc, r#"<arc curvature="NaN"/>"#, 1), "<arc curvature=\"NaN\"", "finite number"),
        ("width", base.replacen(lane_m1, &format!("{lane_m1}\n<width sOffset=\"100\" a=\"3.07\" b=\"0.01\" c=\"0\" d=\"0\"/>"), 1), "sOffset=\"100\"", "widths that vary"),
        ("border", base.replacen(lane_m1, &format!("{lane_m1}\n<border sOffset=\"0\" a=\"3\" b=\"0\" c=\"0\" d=\"0\"/>"), 1), "<border", "borders are refused"),
        ("second road", base.replace("</OpenDRIVE>", "<road name=\"x\" length=\"10\" id=\"2\" junction=\"-1\"></road>\n</OpenDRIVE>"), "id=\"2\" junction", "a road the route does not drive"),
        ("kink", base.replacen("hdg=\"1.7500000000124150e-01\"", "hdg=\"1.8e-01\"", 1), "hdg=\"1.8e-01\"", "from where the one before ends"),
        ("unknown", base.replace("<planView>", "<planView><fancy/>"), "<fancy", "plan view holds geometries"),
        ("xml", base.replace("</planView>", "</planVew>"), "</planVew>", "not well-formed XML"),
    ];
    for (what, text, needle, reason) in cases {
        let path = dir.path().join(format!("{}.xodr", what.replace(' ', "_")));
        std::fs::write(&path, &text).unwrap();
        let err = parse_scenario(&scenario_text(&path))
            .err()
            .unwrap_or_else(|| panic!("{what}: accepted"))
            .to_string();
        assert!(!err.contains('\n'), "{what}: more than one line: {err}");
        let line = line_of(&text, needle);
        let place = format!("{}:{line}: ", path.display());
        assert!(err.contains(&place), "{what}: not at {place}: {err}");
        assert!(err.contains(reason), "{what}: {err}");
    }
    // esmini's own that carfollow cannot drive.
    for (name, reason) in [
        ("fabriksgatan.xodr", "junction"),
        ("e6mini-lht.xodr", "left-hand traffic"),
    ] {
        let err = parse_scenario(&scenario_text(&data(name)))
            .err()
            .unwrap()
            .to_string();
        assert!(
            err.contains(&format!("{name}:")) && err.contains(reason),
            "{err}"
        );
    }
}

/// A small deterministic generator (SplitMix64): the mutations are the same every run.
struct Mix(u64);
impl Mix {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
}

/// One mutation of `text`: an attribute's value changed to garbage, a line deleted,
/// repeated or swapped, or the file cut short.
fn mutate(text: &str, rng: &mut Mix) -> String {
    let lines: Vec<&str> = text.lines().collect();
    match rng.below(5) {
        0 | 1 => {
            let values: Vec<usize> = text.match_indices("=\"").map(|(i, _)| i + 2).collect();
            let start = values[rng.below(values.len())];
            let end = start + text[start..].find('"').unwrap_or(0);
            let garbage = [
                "NaN",
                "inf",
                "-inf",
                "-1",
                "0",
                "-0",
                "1e308",
                "-1e308",
                "1e-300",
                "abc",
                "",
                "0.2",
                "-0.2",
                "5e4",
                "2",
                "3.07",
                "1",
                "-1",
                "junction",
                "LHT",
                "normalized",
            ];
            let value = if rng.below(3) == 0 {
                format!(
                    "{}",
                    (rng.next() as f64 / u64::MAX as f64 - 0.5)
                        * 10f64.powi(rng.below(8) as i32 - 3)
                )
            } else {
                garbage[rng.below(garbage.len())].to_string()
            };
            format!("{}{value}{}", &text[..start], &text[end..])
        }
        2 => {
            let k = rng.below(lines.len());
            lines
                .iter()
                .enumerate()
                .filter(|&(i, _)| i != k)
                .map(|(_, l)| *l)
                .collect::<Vec<_>>()
                .join("\n")
        }
        3 => {
            let k = rng.below(lines.len());
            let mut out = lines.clone();
            out.insert(k, lines[k]);
            out.join("\n")
        }
        _ => {
            let mut cut = rng.below(text.len());
            while !text.is_char_boundary(cut) {
                cut -= 1;
            }
            text[..cut].to_string()
        }
    }
}

#[test]
fn mutated_files_never_panic_or_hang_and_what_checks_runs() {
    let dir = tempfile::tempdir().unwrap();
    let bases: Vec<String> = [
        "curves.xodr",
        "straight_500m.xodr",
        "circle_300m.xodr",
        "e6mini.xodr",
    ]
    .iter()
    .map(|n| std::fs::read_to_string(data(n)).unwrap())
    .collect();
    let runs_wanted: usize = std::env::var("CARFOLLOW_XODR_RUNS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(6);
    let backend = Backend::choose(None).unwrap();
    let mut rng = Mix(2024);
    let (mut accepted, mut ran) = (0, 0);
    for case in 0..300 {
        let base = &bases[case % bases.len()];
        let mut text = mutate(base, &mut rng);
        if rng.below(3) == 0 {
            text = mutate(&text, &mut rng);
        }
        let path = dir.path().join(format!("m{case}.xodr"));
        std::fs::write(&path, &text).unwrap();
        let started = std::time::Instant::now();
        let checked = parse_scenario(&scenario_text(&path)).and_then(|s| Plan::new(&s));
        assert!(
            started.elapsed().as_secs_f64() < 20.0,
            "case {case}: check took {:?}",
            started.elapsed()
        );
        match checked {
            Err(e) => assert!(!e.to_string().contains('\n'), "case {case}: {e}"),
            Ok(plan) => {
                accepted += 1;
                if ran < runs_wanted {
                    let mut looped = ClosedLoop::new(plan, backend, false).unwrap_or_else(|e| {
                        panic!("case {case} checked, but the loop refused it: {e}")
                    });
                    let mut frames = 0;
                    while let Some(out) =
                        looped.step().unwrap_or_else(|e| panic!("case {case}: {e}"))
                    {
                        assert!(out.record.t_s.is_finite());
                        frames += 1;
                    }
                    assert_eq!(frames, 15, "case {case}");
                    ran += 1;
                }
            }
        }
    }
    eprintln!("{accepted} of 300 mutated files checked; {ran} of them ran");
    assert!(
        accepted > 0 && ran > 0,
        "no mutated file was accepted: the property was never tested"
    );
}

/// A road's objects and signals (poles, rails, signs: scenery, which carfollow places its
/// own of) are read past and said in one warning line naming where they stand, not
/// refused: esmini's `curve_r100` is driven, with its guide posts named.
#[test]
fn a_roads_objects_are_said_and_not_drawn() {
    let s =
        parse_scenario(&scenario_text(&data("curve_r100.xodr"))).unwrap_or_else(|e| panic!("{e}"));
    let warnings = s.warnings();
    let said: Vec<_> = warnings
        .iter()
        .filter(|w| w.contains("objects, signals"))
        .collect();
    assert_eq!(said.len(), 1, "{warnings:?}");
    assert!(
        said[0].contains("curve_r100.xodr:96: <object"),
        "{}",
        said[0]
    );
    Plan::new(&s).unwrap_or_else(|e| panic!("{e}"));
}

/// `[s, a, b, c, d]` of every `<elevation>` in `text`, read by hand from its attributes.
fn elevation_records(text: &str) -> Vec<[f64; 5]> {
    text.lines()
        .filter(|l| l.contains("<elevation "))
        .map(|l| {
            ["s", "a", "b", "c", "d"].map(|k| {
                let at = l.find(&format!(" {k}=\"")).expect(k) + k.len() + 3;
                l[at..at + l[at..].find('"').unwrap()].parse().unwrap()
            })
        })
        .collect()
}

#[test]
fn a_crest_is_imported_and_the_ground_follows_it() {
    // esmini's crest-curve.xodr: level, a 6 m crest between stations 200 and 340, level.
    let text = std::fs::read_to_string(data("crest-curve.xodr")).unwrap();
    let records = elevation_records(&text);
    assert_eq!(records.len(), 4);
    let road = opendrive::import(&read("crest-curve.xodr"), None, |_| None).unwrap();
    assert_eq!(road.elevation, records);
    // The height at station s, evaluated here: the last record starting at or before s.
    let by_hand = |s: f64| {
        let r = records.iter().rev().find(|r| r[0] <= s).unwrap();
        let ds = s - r[0];
        r[1] + r[2] * ds + r[3] * ds * ds + r[4] * ds * ds * ds
    };
    let s = parse_scenario(&scenario_text(&data("crest-curve.xodr"))).unwrap();
    let plan = Plan::new(&s).unwrap_or_else(|e| panic!("{e}"));
    let terrain = plan
        .scene()
        .terrain()
        .expect("a ground that follows the road");
    let route = Route::new(s.route.clone());
    let (mut worst, mut worst_aside) = (0.0f64, 0.0f64);
    let mut top = 0.0f64;
    for k in 0..=1600 {
        let st = 0.25 * k as f64;
        let [x, z] = route.point(st, 0.0);
        // The centreline, and 20 m to either side: the ground beside the road is the road
        // abreast (the road is straight here and gently curved beyond).
        for lateral in [0.0, -20.0, 20.0] {
            let [x, z] = if lateral == 0.0 {
                [x, z]
            } else {
                route.point(st, lateral)
            };
            let off = (terrain.height_m(x, z) - by_hand(st)).abs();
            if lateral == 0.0 {
                worst = worst.max(off);
            } else {
                worst_aside = worst_aside.max(off);
            }
        }
        top = top.max(terrain.height_m(x, z));
    }
    eprintln!(
        "crest-curve.xodr: the ground within {worst:.1e} m of the profile on the centreline, \
         {worst_aside:.1e} m 20 m aside; top {top:.3} m"
    );
    assert!((top - 6.0).abs() < 0.01, "{top}");
    assert!(worst < 0.005, "{worst}");
    // Inside the spiral's tightest part (radius 50 m), 20 m aside, stations pass 1.7 times
    // faster than metres: the 1 m cells' chords depart from the crest's curve by about
    // 1 cm.
    assert!(worst_aside < 0.02, "{worst_aside}");
    // The vehicles stand on it: the lead starts on level ground at 30 m.
    let lead = plan.start_poses().1.expect("a lead");
    assert!(f64::from(lead.translation.y).abs() < 0.05);
}
