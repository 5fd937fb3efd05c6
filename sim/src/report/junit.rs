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

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::SystemTime;

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

    /// (tests, failures, errors).
    fn counts(&self) -> (usize, usize, usize) {
        match self {
            JunitScenario::Ran(s) => (
                1 + s.criteria.len(),
                s.criteria.iter().filter(|c| !c.passed).count(),
                0,
            ),
            JunitScenario::Incomplete { .. } => (1, 0, 1),
        }
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

/// The JUnit XML text for these scenarios, written at `timestamp`.
pub fn junit_xml(scenarios: &[JunitScenario], timestamp: SystemTime) -> String {
    let stamp = iso8601_utc(timestamp);
    let (mut tests, mut failures, mut errors) = (0, 0, 0);
    for s in scenarios {
        let (t, f, e) = s.counts();
        tests += t;
        failures += f;
        errors += e;
    }
    let time: f64 = scenarios.iter().map(|s| s.wall_s()).sum();
    let mut x = String::new();
    x.push_str("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    let _ = writeln!(
        x,
        "<testsuites name=\"carfollow\" tests=\"{tests}\" failures=\"{failures}\" errors=\"{errors}\" time=\"{time:.3}\">"
    );
    for (id, s) in scenarios.iter().enumerate() {
        let (tests, failures, errors) = s.counts();
        let name = escape(s.name());
        let _ = writeln!(
            x,
            "  <testsuite name=\"{name}\" id=\"{id}\" package=\"carfollow\" hostname=\"localhost\" \
             timestamp=\"{stamp}\" tests=\"{tests}\" failures=\"{failures}\" errors=\"{errors}\" \
             skipped=\"0\" time=\"{:.3}\">",
            s.wall_s()
        );
        let seed = match s {
            JunitScenario::Ran(r) => r.seed,
            JunitScenario::Incomplete { seed, .. } => *seed,
        };
        x.push_str("    <properties>\n");
        let _ = writeln!(x, "      <property name=\"seed\" value=\"{seed}\"/>");
        x.push_str("    </properties>\n");
        let classname = format!("carfollow.{name}");
        let mut out = String::new();
        match s {
            JunitScenario::Incomplete { error, .. } => {
                let _ = writeln!(
                    x,
                    "    <testcase classname=\"{classname}\" name=\"completed\" time=\"{:.3}\">",
                    s.wall_s()
                );
                let _ = writeln!(
                    x,
                    "      <error type=\"incomplete\" message=\"the run could not complete\">{}</error>",
                    escape(error)
                );
                x.push_str("    </testcase>\n");
                let _ = writeln!(out, "{}: could not complete: {error}", s.name());
            }
            JunitScenario::Ran(r) => {
                let _ = writeln!(
                    x,
                    "    <testcase classname=\"{classname}\" name=\"completed\" time=\"{:.3}\"/>",
                    s.wall_s()
                );
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
                    let open = format!(
                        "    <testcase classname=\"{classname}\" name=\"{}\" time=\"0.000\"",
                        escape(&c.name)
                    );
                    if c.passed {
                        let _ = writeln!(x, "{open}/>");
                    } else {
                        let _ = writeln!(x, "{open}>");
                        let _ = writeln!(
                            x,
                            "      <failure type=\"expect\" message=\"measured {}, limit {}\">{}</failure>",
                            figure(c.value),
                            figure(c.limit),
                            escape(&c.message)
                        );
                        x.push_str("    </testcase>\n");
                    }
                }
            }
        }
        let _ = writeln!(x, "    <system-out>{}</system-out>", escape(&out));
        x.push_str("    <system-err/>\n");
        x.push_str("  </testsuite>\n");
    }
    x.push_str("</testsuites>\n");
    x
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

/// Escapes text for XML 1.0 content and attributes. Control characters XML 1.0 cannot hold
/// at all become U+FFFD.
fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            '\t' | '\n' | '\r' => out.push(c),
            c if (c as u32) < 0x20 || c == '\u{FFFE}' || c == '\u{FFFF}' => out.push('\u{FFFD}'),
            c => out.push(c),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::record::Expect;
    use crate::report::frames_csv::tests::record;
    use std::time::Duration;

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

    #[test]
    fn escapes_markup_quotes_and_control_characters() {
        assert_eq!(
            escape("a <b> & \"c\" 'd'\u{1}\n"),
            "a &lt;b&gt; &amp; &quot;c&quot; &apos;d&apos;\u{FFFD}\n"
        );
    }

    #[test]
    fn one_suite_per_scenario_one_case_per_criterion() {
        let x = xml();
        assert!(x.starts_with("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"));
        assert_eq!(x.matches("<testsuite ").count(), 3);
        // completed + 2 criteria, three times over, less the incomplete run's criteria.
        assert!(
            x.contains("<testsuites name=\"carfollow\" tests=\"7\" failures=\"2\" errors=\"1\""),
            "{x}"
        );
        assert_eq!(x.matches("<testcase ").count(), 7);
        assert!(x.contains("timestamp=\"2026-11-23T12:34:56\""), "{x}");
        assert!(x.contains(
            "<testcase classname=\"carfollow.nist-grounds\" name=\"no_collision\" time=\"0.000\"/>"
        ));
        assert_eq!(x.matches("<failure ").count(), 2);
        assert!(
            x.contains("<failure type=\"expect\" message=\"measured 2.000, limit 0.000\">gap left the band [11, 15] m"),
            "{x}"
        );
        assert!(
            x.contains("message=\"measured 9.667, limit 1000.000\">the chase vehicle drove"),
            "{x}"
        );
        assert!(x.contains(
            "<error type=\"incomplete\" message=\"the run could not complete\">the renderer &lt;failed&gt;</error>"
        ));
        assert!(x.contains("PASS no_collision: the vehicles collided 0 time(s) (allowed 0)"));
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
        assert_eq!(
            suites,
            ["nist-grounds", "a <b> & \"c\" 'd'\u{FFFD}", "weave"]
        );
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
