//! A chain of OpenDRIVE roads, each linked to the next end to start, is one route: esmini's
//! `curves.xodr` (MPL-2.0, `tests/data/opendrive/`) cut into two and three roads lies where
//! the one road lies, its elevation and lane offset moved on by where each road starts;
//! what a chain cannot be (a road driven backwards, a road off the chain, unlike lanes, a
//! gap at a join, a link to a junction, a predecessor that is not the road before) is
//! refused in one line naming the file, the line and the element.

use sim_core::opendrive::{self, OpenDrive};
use sim_core::Scenario;
use sim_render::{Route, RouteSpec};
use std::path::{Path, PathBuf};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/opendrive")
        .join(name)
}

/// The value of attribute `name` on `line`.
fn attr(line: &str, name: &str) -> f64 {
    let key = format!(" {name}=\"");
    let from = line.find(&key).unwrap() + key.len();
    let to = from + line[from..].find('"').unwrap();
    line[from..to].parse().unwrap()
}

/// `line` with attribute `name` set to `value`.
fn set_attr(line: &str, name: &str, value: &str) -> String {
    let key = format!(" {name}=\"");
    let from = line.find(&key).unwrap() + key.len();
    let to = from + line[from..].find('"').unwrap();
    format!("{}{value}{}", &line[..from], &line[to..])
}

/// `curves.xodr`'s one road cut before each geometry of `cuts` into roads 1, 2, ...: each
/// with its part of the plan view (stations from its own start), the lanes and the other
/// records as the file's, linked to the next end to start. `links(k, n)` writes road k's
/// (1-based) `<link>` body among n roads. Also the stations where the roads start.
fn cut_curves(cuts: &[usize], links: impl Fn(usize, usize) -> String) -> (String, Vec<f64>) {
    let text = std::fs::read_to_string(data("curves.xodr")).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    let find = |needle: &str| lines.iter().position(|l| l.contains(needle)).unwrap();
    let (road_at, plan_at, plan_end, road_end) = (
        find("<road "),
        find("<planView>"),
        find("</planView>"),
        find("</road>"),
    );
    let geometries: Vec<usize> = (plan_at..plan_end)
        .filter(|&i| lines[i].trim_start().starts_with("<geometry"))
        .collect();
    let total = attr(lines[road_at], "length");
    let mut bounds: Vec<usize> = cuts.iter().map(|&k| geometries[k]).collect();
    bounds.insert(0, geometries[0]);
    bounds.push(plan_end);
    let starts: Vec<f64> = bounds[..bounds.len() - 1]
        .iter()
        .map(|&i| attr(lines[i], "s"))
        .collect();
    let n = starts.len();
    let mut out: Vec<String> = lines[..road_at].iter().map(|l| l.to_string()).collect();
    for k in 0..n {
        let length = if k + 1 < n {
            starts[k + 1] - starts[k]
        } else {
            total - starts[k]
        };
        let head = set_attr(
            &set_attr(lines[road_at], "length", &length.to_string()),
            "id",
            &(k + 1).to_string(),
        );
        out.push(head);
        out.push(format!("        <link>{}</link>", links(k + 1, n)));
        out.push("        <planView>".into());
        for line in &lines[bounds[k]..bounds[k + 1]] {
            if line.trim_start().starts_with("<geometry") {
                let s = attr(line, "s") - starts[k];
                out.push(set_attr(line, "s", &s.to_string()));
            } else {
                out.push(line.to_string());
            }
        }
        out.extend(lines[plan_end..=road_end].iter().map(|l| l.to_string()));
    }
    out.extend(lines[road_end + 1..].iter().map(|l| l.to_string()));
    let mut text = out.join("\n");
    text.push('\n');
    // The original road's own empty link went with its header: drop the copies.
    text = text.replace("</link>\n        <link>\n        </link>", "</link>");
    (text, starts)
}

/// Each road's links on a chain of `n`: its predecessor the road before's end, its
/// successor the next road's start.
fn chained(k: usize, n: usize) -> String {
    let mut s = String::new();
    if k > 1 {
        s += &format!(
            "<predecessor elementType=\"road\" elementId=\"{}\" contactPoint=\"end\"/>",
            k - 1
        );
    }
    if k < n {
        s += &format!(
            "<successor elementType=\"road\" elementId=\"{}\" contactPoint=\"start\"/>",
            k + 1
        );
    }
    s
}

fn route_of(file: &OpenDrive) -> (opendrive::ImportedRoad, Route) {
    let road = opendrive::import(file, None, |_| None).unwrap_or_else(|e| panic!("{e}"));
    let route = Route::new(RouteSpec {
        segments: road.segments.clone(),
        intersections_m: vec![],
        lane_width_m: road.lane_width_m,
        lanes: road.lanes,
        elevation: road.elevation.clone(),
        median_m: road.median_m,
        lane_widths_m: road.lane_widths_m.clone(),
        lane_offset: road.lane_offset.clone(),
    });
    (road, route)
}

#[test]
fn a_chain_of_roads_lies_where_the_one_road_lies() {
    let whole = opendrive::load(&data("curves.xodr")).unwrap();
    let (one, one_route) = route_of(&whole);
    for cuts in [vec![3], vec![2, 7], vec![1, 5, 11]] {
        let (text, starts) = cut_curves(&cuts, chained);
        let file =
            opendrive::parse(&text, Path::new("/tmp/chain.xodr")).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(file.roads.len(), cuts.len() + 1);
        let (road, route) = route_of(&file);
        assert_eq!(road.segments.len(), one.segments.len(), "{cuts:?}");
        let ids: Vec<&str> = road.roads.iter().map(|r| r.id.as_str()).collect();
        let want: Vec<String> = (1..=starts.len()).map(|k| k.to_string()).collect();
        assert_eq!(ids, want, "{cuts:?}");
        for (r, s) in road.roads.iter().zip(&starts) {
            assert!((r.start_m - s).abs() < 1e-9, "{cuts:?}: {r:?} against {s}");
        }
        // Every metre of the route where the one road's is.
        let length = whole.roads[0].length;
        let mut worst = 0.0f64;
        let mut s = 0.0;
        while s <= length {
            let [x, z, h] = route.at(s);
            let [x1, z1, h1] = one_route.at(s);
            worst = worst.max((x - x1).hypot(z - z1));
            assert!((h - h1).sin().abs() < 1e-9, "{cuts:?}: heading at {s}");
            s += 1.0;
        }
        assert!(worst < 1e-6, "{cuts:?}: {worst} m off the one road");
    }
}

#[test]
fn a_chains_elevation_and_lane_offset_follow_each_road() {
    // Road 2 climbs 2 % from where road 1 ends level; its lane offset eases 1 m left.
    let (text, starts) = cut_curves(&[3], chained);
    let mut parts: Vec<&str> = text.split("<lateralProfile>").collect();
    assert_eq!(parts.len(), 3);
    let climb = "<elevationProfile><elevation s=\"0\" a=\"0\" b=\"0.02\" c=\"0\" d=\"0\"/></elevationProfile>\n<lateralProfile>";
    let last = format!("{climb}{}", parts.pop().unwrap());
    let text = format!("{}<lateralProfile>{}{last}", parts[0], parts[1]);
    let ease = "<laneOffset s=\"0\" a=\"0\" b=\"0\" c=\"0.0012\" d=\"-0.000016\"/>\n<laneOffset s=\"50\" a=\"1\" b=\"0\" c=\"0\" d=\"0\"/>\n<laneSection s=";
    let at = text.rfind("<laneSection s=").unwrap();
    let text = format!(
        "{}{ease}{}",
        &text[..at],
        &text[at + "<laneSection s=".len()..]
    );
    let file =
        opendrive::parse(&text, Path::new("/tmp/chain.xodr")).unwrap_or_else(|e| panic!("{e}"));
    let (road, _) = route_of(&file);
    let s2 = starts[1];
    assert_eq!(
        road.elevation,
        vec![[0.0, 0.0, 0.0, 0.0, 0.0], [s2, 0.0, 0.02, 0.0, 0.0]]
    );
    assert_eq!(
        road.lane_offset,
        vec![
            [0.0, 0.0, 0.0, 0.0, 0.0],
            [s2, 0.0, 0.0, 0.0012, -0.000016],
            [s2 + 50.0, 1.0, 0.0, 0.0, 0.0]
        ]
    );
}

/// A scenario on the road file at `path`.
fn scenario_on(path: &Path) -> Result<Scenario, sim_core::ScenarioError> {
    let target =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/targets/nist-ten-segment.toml");
    let text = format!(
        "name = \"chain\"\nduration_s = 1.0\n[route]\nopendrive = {{ file = {:?} }}\n\
         [lead]\nstart_m = 30.0\ninitial_speed_mps = 5.0\nspeed_profile = [[0.0, 5.0]]\n\
         [tracker]\ntarget = {:?}\n",
        path.display().to_string(),
        target.display().to_string()
    );
    Scenario::from_file_text(&text, Path::new("/tmp/chain.toml"), &[])
}

#[test]
fn what_a_chain_cannot_be_is_refused_at_its_line() {
    let dir = tempfile::tempdir().unwrap();
    let two = |links: fn(usize, usize) -> String| cut_curves(&[3], links).0;
    let backwards = two(|k, _| {
        if k == 1 {
            "<successor elementType=\"road\" elementId=\"2\" contactPoint=\"end\"/>".into()
        } else {
            String::new()
        }
    });
    let junction = two(|k, n| {
        if k == 2 {
            format!(
                "{}<successor elementType=\"junction\" elementId=\"7\"/>",
                chained(k, n)
            )
        } else {
            chained(k, n)
        }
    });
    let wrong_back = two(|k, _| {
        if k == 1 {
            "<successor elementType=\"road\" elementId=\"2\" contactPoint=\"start\"/>".into()
        } else {
            "<predecessor elementType=\"road\" elementId=\"1\" contactPoint=\"start\"/>".into()
        }
    });
    let unlinked = two(|_, _| String::new());
    let (chain, _) = cut_curves(&[3], chained);
    let widths = {
        let road2 = chain.find(" id=\"2\" junction").unwrap();
        let w = "a=\"3.0699999999999998e+00\"";
        assert!(chain[road2..].contains(w));
        format!(
            "{}{}",
            &chain[..road2],
            chain[road2..].replace(w, "a=\"3.5\"")
        )
    };
    let gap = chain.replacen(
        "x=\"2.1564971938253680e+02\"",
        "x=\"2.1574971938253680e+02\"",
        1,
    );
    let cases: Vec<(&str, String, &str, &str)> = vec![
        (
            "backwards",
            backwards,
            "contactPoint=\"end\"",
            "a road driven against its reference line",
        ),
        (
            "junction",
            junction,
            "elementType=\"junction\"",
            "a link to a junction is refused",
        ),
        (
            "predecessor",
            wrong_back,
            "<predecessor elementType=\"road\" elementId=\"1\" contactPoint=\"start\"",
            "its predecessor must be",
        ),
        (
            "off the chain",
            unlinked,
            " id=\"2\" junction",
            "a road the route does not drive",
        ),
        (
            "lanes",
            widths,
            " id=\"2\" junction",
            "differ from road 1's",
        ),
        (
            "gap",
            gap,
            "x=\"2.1574971938253680e+02\"",
            "from where the road before ends",
        ),
    ];
    for (what, text, needle, reason) in cases {
        let path = dir.path().join(format!("{}.xodr", what.replace(' ', "_")));
        std::fs::write(&path, &text).unwrap();
        let err = scenario_on(&path)
            .err()
            .unwrap_or_else(|| panic!("{what}: accepted"))
            .to_string();
        assert!(!err.contains('\n'), "{what}: more than one line: {err}");
        let line = 1 + text
            .lines()
            .position(|l| l.contains(needle))
            .unwrap_or_else(|| panic!("{what}: {needle} not in the file"));
        let place = format!("{}:{line}: ", path.display());
        assert!(err.contains(&place), "{what}: not at {place}: {err}");
        assert!(err.contains(reason), "{what}: {err}");
    }
    // The chain itself is accepted, and a scenario on it plans.
    let path = dir.path().join("chain.xodr");
    std::fs::write(&path, &chain).unwrap();
    let s = scenario_on(&path).unwrap_or_else(|e| panic!("{e}"));
    sim_core::Plan::new(&s).unwrap_or_else(|e| panic!("{e}"));
}
