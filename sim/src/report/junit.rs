//! `junit.xml`: the scenarios of one `carfollow run` as a JUnit report for CI systems.
//!
//! One `<testsuite name="carfollow">` holds one `<testcase>` per scenario (its `classname` is
//! `carfollow.scenario`, its `time` the run's wall-clock seconds). A failed scenario has a
//! `<failure>` whose text lists each failed criterion with its value and limit; every scenario
//! lists all its criteria, passed or failed, in `<system-out>` and as `<properties>`.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::{ReportError, Summary};

/// The JUnit XML text for these scenario summaries.
pub fn junit_xml(summaries: &[Summary]) -> String {
    let tests = summaries.len();
    let failures = summaries.iter().filter(|s| !s.passed).count();
    let time: f64 = summaries.iter().map(|s| s.wall_s.max(0.0)).sum();
    let mut x = String::new();
    x.push_str("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    let _ = writeln!(
        x,
        "<testsuites name=\"carfollow\" tests=\"{tests}\" failures=\"{failures}\" errors=\"0\" time=\"{time:.3}\">"
    );
    let _ = writeln!(
        x,
        "  <testsuite name=\"carfollow\" tests=\"{tests}\" failures=\"{failures}\" errors=\"0\" skipped=\"0\" time=\"{time:.3}\">"
    );
    for s in summaries {
        let _ = writeln!(
            x,
            "    <testcase classname=\"carfollow.scenario\" name=\"{}\" time=\"{:.3}\">",
            escape(&s.scenario),
            s.wall_s.max(0.0)
        );
        x.push_str("      <properties>\n");
        let _ = writeln!(x, "        <property name=\"seed\" value=\"{}\"/>", s.seed);
        for c in &s.criteria {
            let _ = writeln!(
                x,
                "        <property name=\"{}\" value=\"{}: {}\"/>",
                escape(&c.name),
                if c.passed { "passed" } else { "FAILED" },
                escape(&c.message)
            );
        }
        x.push_str("      </properties>\n");
        if !s.passed {
            let _ = writeln!(
                x,
                "      <failure type=\"expect\" message=\"{} of {} criteria failed\">{}</failure>",
                s.failures.len(),
                s.criteria.len(),
                escape(&s.failures.join("\n"))
            );
        }
        let mut out = format!(
            "{}: {} frames, {:.2} s simulated, seed {}\n",
            s.scenario, s.frames, s.duration_s, s.seed
        );
        if s.criteria.is_empty() {
            out.push_str("no criteria checked\n");
        }
        for c in &s.criteria {
            let _ = writeln!(
                out,
                "{} {}: {}",
                if c.passed { "PASS" } else { "FAIL" },
                c.name,
                c.message
            );
        }
        let _ = writeln!(x, "      <system-out>{}</system-out>", escape(&out));
        x.push_str("    </testcase>\n");
    }
    x.push_str("  </testsuite>\n</testsuites>\n");
    x
}

/// Writes [`junit_xml`] to `path`; a directory gets `junit.xml` inside it.
pub fn write_junit(path: impl AsRef<Path>, summaries: &[Summary]) -> Result<PathBuf, ReportError> {
    let mut path = path.as_ref().to_path_buf();
    if path.is_dir() {
        path.push("junit.xml");
    }
    std::fs::write(&path, junit_xml(summaries)).map_err(ReportError::io(&path))?;
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

    #[test]
    fn escapes_markup_quotes_and_control_characters() {
        assert_eq!(
            escape("a <b> & \"c\" 'd'\u{1}\n"),
            "a &lt;b&gt; &amp; &quot;c&quot; &apos;d&apos;\u{FFFD}\n"
        );
    }

    #[test]
    fn one_testcase_per_scenario_with_failures_listed() {
        let x = junit_xml(&summaries());
        assert!(x.starts_with("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"));
        assert_eq!(x.matches("<testsuite ").count(), 1);
        assert!(x.contains("tests=\"2\" failures=\"1\""), "{x}");
        assert_eq!(x.matches("<testcase ").count(), 2);
        assert_eq!(x.matches("</testcase>").count(), 2);
        assert!(x.contains("name=\"nist-grounds\" time=\"1.500\""), "{x}");
        assert!(x.contains(
            "name=\"a &lt;b&gt; &amp; &quot;c&quot; &apos;d&apos;\u{FFFD}\" time=\"0.500\""
        ));
        assert_eq!(x.matches("<failure ").count(), 1);
        assert!(x.contains("message=\"2 of 2 criteria failed\">gap left the band [11, 15] m"));
        assert!(x.contains("PASS no_collision: the vehicles collided 0 time(s) (allowed 0)"));
        assert!(x.contains("FAIL min_distance: the chase vehicle drove"));
        // Nothing unescaped inside the text: every '<' opens a known element.
        for part in x.split('<').skip(1) {
            let name: String = part
                .trim_start_matches('/')
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '?')
                .collect();
            assert!(
                [
                    "?xml",
                    "testsuites",
                    "testsuite",
                    "testcase",
                    "properties",
                    "property",
                    "failure",
                    "system"
                ]
                .contains(&name.as_str()),
                "unexpected element {name:?} in\n{x}"
            );
        }
    }

    #[test]
    fn parses_back_as_xml() {
        use quick_xml::events::Event;
        let x = junit_xml(&summaries());
        let mut reader = quick_xml::Reader::from_str(&x);
        let mut testcases = Vec::new();
        let mut failure_text = String::new();
        let mut in_failure = false;
        let mut depth = 0i32;
        loop {
            match reader.read_event().expect("well-formed XML") {
                Event::Start(e) => {
                    depth += 1;
                    if e.name().as_ref() == b"testcase" {
                        let name = e.try_get_attribute("name").unwrap().unwrap();
                        testcases.push(name.unescape_value().unwrap().into_owned());
                    }
                    in_failure = e.name().as_ref() == b"failure";
                }
                Event::End(_) => {
                    depth -= 1;
                    in_failure = false;
                }
                Event::Text(t) if in_failure => {
                    failure_text.push_str(&t.unescape().unwrap());
                }
                Event::Eof => break,
                _ => {}
            }
        }
        assert_eq!(depth, 0);
        assert_eq!(testcases, ["nist-grounds", "a <b> & \"c\" 'd'\u{FFFD}"]);
        assert!(failure_text.starts_with("gap left the band [11, 15] m for 2.00 s"));
        assert!(
            failure_text.contains("\nthe chase vehicle drove 9.7 m (required at least 1000.0 m)")
        );
    }

    #[test]
    fn writes_into_a_directory_or_a_file() {
        let dir = tempfile::tempdir().unwrap();
        let p = write_junit(dir.path(), &summaries()).unwrap();
        assert_eq!(p, dir.path().join("junit.xml"));
        let q = write_junit(dir.path().join("ci.xml"), &summaries()).unwrap();
        assert_eq!(std::fs::read(p).unwrap(), std::fs::read(q).unwrap());
    }
}
