//! `junit.xml`: the scenarios of one `carfollow run` as a JUnit report for CI systems.
//!
//! One `<testsuite>` per scenario (its `name` the scenario's, its `timestamp` when the
//! report was written, UTC), holding one `<testcase>` per criterion of its `[expect]`
//! (`classname` `carfollow.<scenario>`, `name` the criterion's: `gap_band`, `max_lost`,
//! `max_lateral_deviation`, `no_collision`, `min_distance`, `max_range_error_p95`,
//! `max_loss_events`) after one named `completed`. A failed criterion has a `<failure>`
//! whose `message` gives the measured value and the limit; a run that could not complete
//! has an `<error>` in `completed` and no criteria. The layout follows the common JUnit XML
//! schema that Jenkins, GitLab and GitHub reporters read (`sim/tests/data/junit.xsd`
//! checks it).

use quick_junit::{NonSuccessKind, Property, Report, TestCase, TestCaseStatus, TestSuite};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::{Duration, SystemTime};

use super::{ReportError, Summary};

/// One scenario of a report: how its run went.
#[derive(Clone, Copy, Debug)]
pub enum JunitScenario<'a> {
    /// It ran to the end: its summary, with its criteria.
    Ran(&'a Summary),
    /// It could not complete (renderer, worker, I/O).
    Incomplete {
        /// Scenario name.
        scenario: &'a str,
        /// Its seed.
        seed: u64,
        /// Wall-clock seconds spent before it stopped.
        wall_s: f64,
        /// Why, on one line.
        error: &'a str,
    },
}

impl JunitScenario<'_> {
    fn name(&self) -> &str {
        match self {
            JunitScenario::Ran(s) => &s.scenario,
            JunitScenario::Incomplete { scenario, .. } => scenario,
        }
    }

    fn wall_s(&self) -> f64 {
        match self {
            JunitScenario::Ran(s) => s.wall_s,
            JunitScenario::Incomplete { wall_s, .. } => *wall_s,
        }
        .max(0.0)
    }
}

/// `YYYY-MM-DDThh:mm:ss` in UTC, the form of the schema's `timestamp` (ISO 8601 without a
/// zone).
pub fn iso8601_utc(t: SystemTime) -> String {
    let secs = t
        .duration_since(SystemTime::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs()) as i64;
    let (days, rem) = (secs.div_euclid(86_400), secs.rem_euclid(86_400));
    // Howard Hinnant's civil-from-days.
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!(
        "{year:04}-{month:02}-{day:02}T{:02}:{:02}:{:02}",
        rem / 3600,
        rem / 60 % 60,
        rem % 60
    )
}

/// A measured value or limit for a message: three decimals, or what it is when not finite.
fn figure(v: f64) -> String {
    if v.is_finite() {
        format!("{v:.3}")
    } else {
        "not measured".into()
    }
}

/// Seconds as a JUnit `time`: never negative, never not finite.
fn seconds(s: f64) -> Duration {
    Duration::try_from_secs_f64(s).unwrap_or(Duration::ZERO)
}

/// The JUnit XML text for these scenarios, written at `timestamp`, by `quick-junit` (the
/// serializer cargo-nextest writes its reports with). The suites' timestamps are written
/// as Ant writes them, in UTC without a zone (`iso8601_utc`), which every reader takes.
pub fn junit_xml(scenarios: &[JunitScenario], timestamp: SystemTime) -> String {
    let stamp = iso8601_utc(timestamp);
    let mut report = Report::new("carfollow");
    report.set_time(seconds(scenarios.iter().map(|s| s.wall_s()).sum()));
    for (id, s) in scenarios.iter().enumerate() {
        report.add_test_suite(suite(s, id, &stamp));
    }
    report
        .to_string()
        .expect("a report of valid UTF-8 text serialises")
}

/// One scenario's `<testsuite>`: `completed`, then a case per criterion.
fn suite(s: &JunitScenario, id: usize, stamp: &str) -> TestSuite {
    let mut suite = TestSuite::new(s.name());
    for (key, value) in [
        ("timestamp", stamp.to_string()),
        ("id", id.to_string()),
        ("package", "carfollow".into()),
        ("hostname", "localhost".into()),
    ] {
        suite.extra.insert(key.into(), value.into());
    }
    suite.set_time(seconds(s.wall_s()));
    let seed = match s {
        JunitScenario::Ran(r) => r.seed,
        JunitScenario::Incomplete { seed, .. } => *seed,
    };
    suite.add_property(Property::new("seed", seed.to_string()));
    let classname = format!("carfollow.{}", s.name());
    let case = |name: &str, status: TestCaseStatus, time: f64| {
        let mut case = TestCase::new(name, status);
        case.set_classname(classname.as_str())
            .set_time(seconds(time));
        case
    };
    let mut out = String::new();
    match s {
        JunitScenario::Incomplete { error, .. } => {
            let mut status = TestCaseStatus::non_success(NonSuccessKind::Error);
            status
                .set_type("incomplete")
                .set_message("the run could not complete")
                .set_description(*error);
            suite.add_test_case(case("completed", status, s.wall_s()));
            let _ = writeln!(out, "{}: could not complete: {error}", s.name());
        }
        JunitScenario::Ran(r) => {
            suite.add_test_case(case("completed", TestCaseStatus::success(), s.wall_s()));
            let _ = writeln!(
                out,
                "{}: {} frames, {:.2} s simulated, seed {}",
                r.scenario, r.frames, r.duration_s, r.seed
            );
            if r.criteria.is_empty() {
                out.push_str("no criteria checked\n");
            }
            for c in &r.criteria {
                let _ = writeln!(
                    out,
                    "{} {}: {}",
                    if c.passed { "PASS" } else { "FAIL" },
                    c.name,
                    c.message
                );
                let status = if c.passed {
                    TestCaseStatus::success()
                } else {
                    let mut failed = TestCaseStatus::non_success(NonSuccessKind::Failure);
                    failed
                        .set_type("expect")
                        .set_message(format!(
                            "measured {}, limit {}",
                            figure(c.value),
                            figure(c.limit)
                        ))
                        .set_description(c.message.as_str());
                    failed
                };
                suite.add_test_case(case(&c.name, status, 0.0));
            }
        }
    }
    suite.set_system_out(out);
    suite.set_system_err("");
    suite
}

/// Writes [`junit_xml`] to `path`, stamped now; a directory gets `junit.xml` inside it.
pub fn write_junit(
    path: impl AsRef<Path>,
    scenarios: &[JunitScenario],
) -> Result<PathBuf, ReportError> {
    let mut path = path.as_ref().to_path_buf();
    if path.is_dir() {
        path.push("junit.xml");
    }
    std::fs::write(&path, junit_xml(scenarios, SystemTime::now()))
        .map_err(ReportError::io(&path))?;
    Ok(path)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::frames_csv::tests::record;
    use sim_core::Expect;

    fn summaries() -> Vec<Summary> {
        let rs: Vec<_> = (0..30).map(record).collect();
        let pass = Summary::compute(
            "nist-grounds",
            1,
            &rs,
            &Expect {
                gap_band_m: Some([5.0, 15.0]),
                no_collision: true,
                ..Expect::default()
            },
            1.5,
        );
        let fail = Summary::compute(
            "a <b> & \"c\" 'd'\u{1}",
            2,
            &rs,
            &Expect {
                gap_band_m: Some([11.0, 15.0]),
                min_distance_m: Some(1e3),
                ..Expect::default()
            },
            0.5,
        );
        vec![pass, fail]
    }

    fn xml() -> String {
        let s = summaries();
        let mut all: Vec<JunitScenario> = s.iter().map(JunitScenario::Ran).collect();
        all.push(JunitScenario::Incomplete {
            scenario: "weave",
            seed: 3,
            wall_s: 0.25,
            error: "the renderer <failed>",
        });
        // 2026-11-23T12:34:56Z.
        junit_xml(
            &all,
            SystemTime::UNIX_EPOCH + Duration::from_secs(1_795_437_296),
        )
    }

    #[test]
    fn timestamps_are_utc_iso8601() {
        assert_eq!(iso8601_utc(SystemTime::UNIX_EPOCH), "1970-01-01T00:00:00");
        let t = SystemTime::UNIX_EPOCH + Duration::from_secs(1_795_437_296);
        assert_eq!(iso8601_utc(t), "2026-11-23T12:34:56");
        // A leap day.
        let t = SystemTime::UNIX_EPOCH + Duration::from_secs(951_782_400);
        assert_eq!(iso8601_utc(t), "2000-02-29T00:00:00");
    }

    /// An element: its name, attributes and text.
    type Element = (String, Vec<(String, String)>, String);

    /// Every element of `xml` in document order.
    fn elements(xml: &str) -> Vec<Element> {
        use quick_xml::events::Event;
        let mut reader = quick_xml::Reader::from_str(xml);
        let mut all: Vec<Element> = Vec::new();
        let mut open: Vec<usize> = Vec::new();
        loop {
            let event = reader.read_event().expect("well-formed XML");
            let start = |e: &quick_xml::events::BytesStart| {
                let attributes = e
                    .attributes()
                    .map(|a| {
                        let a = a.expect("an attribute");
                        let key = String::from_utf8(a.key.as_ref().to_vec()).unwrap();
                        (key, a.unescape_value().unwrap().into_owned())
                    })
                    .collect();
                let name = String::from_utf8(e.name().as_ref().to_vec()).unwrap();
                (name, attributes, String::new())
            };
            match event {
                Event::Start(e) => {
                    all.push(start(&e));
                    open.push(all.len() - 1);
                }
                Event::Empty(e) => all.push(start(&e)),
                Event::Text(text) => {
                    if let Some(&k) = open.last() {
                        all[k].2.push_str(&text.unescape().unwrap());
                    }
                }
                Event::End(_) => {
                    open.pop();
                }
                Event::Eof => break,
                _ => {}
            }
        }
        assert!(open.is_empty());
        all
    }

    fn attribute<'a>(e: &'a (String, Vec<(String, String)>, String), key: &str) -> &'a str {
        e.1.iter()
            .find(|(k, _)| k == key)
            .map_or("", |(_, v)| v.as_str())
    }

    #[test]
    fn one_suite_per_scenario_one_case_per_criterion() {
        let x = xml();
        assert!(
            x.starts_with("<?xml version=\"1.0\" encoding=\"UTF-8\"?>"),
            "{x}"
        );
        let all = elements(&x);
        let named = |name: &'static str| all.iter().filter(move |e| e.0 == name);
        let root = named("testsuites").next().expect("testsuites");
        // completed + 2 criteria, three times over, less the incomplete run's criteria.
        for (key, value) in [
            ("name", "carfollow"),
            ("tests", "7"),
            ("failures", "2"),
            ("errors", "1"),
        ] {
            assert_eq!(attribute(root, key), value, "{key}: {x}");
        }
        assert_eq!(named("testsuite").count(), 3);
        for suite in named("testsuite") {
            assert_eq!(attribute(suite, "timestamp"), "2026-11-23T12:34:56", "{x}");
            assert_eq!(attribute(suite, "package"), "carfollow");
        }
        assert_eq!(named("testcase").count(), 7);
        assert!(named("testcase").all(|c| !attribute(c, "time").is_empty()));
        assert!(
            named("testcase").any(|c| attribute(c, "classname") == "carfollow.nist-grounds"
                && attribute(c, "name") == "no_collision")
        );
        let failures: Vec<_> = named("failure").collect();
        assert_eq!(failures.len(), 2);
        assert!(failures.iter().all(|f| attribute(f, "type") == "expect"));
        assert_eq!(
            attribute(failures[0], "message"),
            "measured 2.000, limit 0.000"
        );
        assert!(
            failures[0].2.starts_with("gap left the band [11, 15] m"),
            "{x}"
        );
        assert_eq!(
            attribute(failures[1], "message"),
            "measured 9.667, limit 1000.000"
        );
        assert!(failures[1].2.starts_with("the chase vehicle drove"), "{x}");
        let error = named("error").next().expect("the incomplete run's error");
        assert_eq!(attribute(error, "type"), "incomplete");
        assert_eq!(attribute(error, "message"), "the run could not complete");
        assert_eq!(error.2, "the renderer <failed>");
        assert!(named("system-out").any(|o| o
            .2
            .contains("PASS no_collision: the vehicles collided 0 time(s) (allowed 0)")));
        let seeds: Vec<&str> = named("property").map(|p| attribute(p, "value")).collect();
        assert_eq!(seeds, ["1", "2", "3"]);
    }

    #[test]
    fn parses_back_as_xml() {
        use quick_xml::events::Event;
        let x = xml();
        let mut reader = quick_xml::Reader::from_str(&x);
        let mut suites = Vec::new();
        let mut depth = 0i32;
        loop {
            match reader.read_event().expect("well-formed XML") {
                Event::Start(e) => {
                    depth += 1;
                    if e.name().as_ref() == b"testsuite" {
                        let name = e.try_get_attribute("name").unwrap().unwrap();
                        suites.push(name.unescape_value().unwrap().into_owned());
                    }
                }
                Event::End(_) => depth -= 1,
                Event::Eof => break,
                _ => {}
            }
        }
        assert_eq!(depth, 0);
        // Markup escaped, and the control character XML cannot hold left out.
        assert_eq!(suites, ["nist-grounds", "a <b> & \"c\" 'd'", "weave"]);
    }

    #[test]
    fn writes_into_a_directory_or_a_file() {
        let dir = tempfile::tempdir().unwrap();
        let s = summaries();
        let all: Vec<JunitScenario> = s.iter().map(JunitScenario::Ran).collect();
        let p = write_junit(dir.path(), &all).unwrap();
        assert_eq!(p, dir.path().join("junit.xml"));
        let q = write_junit(dir.path().join("ci.xml"), &all).unwrap();
        assert!(std::fs::read_to_string(q)
            .unwrap()
            .contains("name=\"gap_band\""));
    }
}
