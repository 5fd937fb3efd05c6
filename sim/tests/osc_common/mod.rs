//! What the OpenSCENARIO command-line tests share: the test files, `carfollow` run as a
//! user runs it, and a run's `frames.csv` read by column name.

#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

pub fn data() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../sim/core/tests/data/openscenario")
}

pub fn carfollow(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_carfollow"))
        .args(args)
        .output()
        .unwrap()
}

pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// The one line a refusal printed: `o` must have exited 2 with one line on stderr
/// (`context` names the case in a failure).
pub fn refusal(o: &Output, context: &str) -> String {
    let e = stderr(o);
    assert_eq!(o.status.code(), Some(2), "{context}: {e}");
    assert_eq!(e.lines().count(), 1, "{context}: {e}");
    e
}

/// `frames.csv` of `carfollow run SCENARIO --quiet --out OUT` with `extra` arguments; the
/// run must complete (passed or not).
pub fn frames_of(scenario: &Path, out: &Path, extra: &[&str]) -> String {
    let args = [
        &[
            "run",
            scenario.to_str().unwrap(),
            "--quiet",
            "--out",
            out.to_str().unwrap(),
        ][..],
        extra,
    ]
    .concat();
    let o = carfollow(&args);
    assert!(matches!(o.status.code(), Some(0 | 1)), "{}", stderr(&o));
    std::fs::read_to_string(out.join("frames.csv")).unwrap()
}

/// `carfollow import FILE -o TOML`, which must succeed, and the scenario text it wrote.
pub fn import_to(file: &Path, toml: &Path) -> String {
    let o = carfollow(&[
        "import",
        file.to_str().unwrap(),
        "-o",
        toml.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    std::fs::read_to_string(toml).unwrap()
}

/// `carfollow export TOML -o OUT`, which must succeed: the `.xosc` it wrote and its text.
pub fn export_to(toml: &Path, out: &Path) -> (PathBuf, String) {
    let o = carfollow(&[
        "export",
        toml.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let xosc = std::fs::read_dir(out)
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.extension().is_some_and(|e| e == "xosc"))
        .unwrap();
    let text = std::fs::read_to_string(&xosc).unwrap();
    (xosc, text)
}

/// A run's `frames.csv`, its rows read by column name.
pub struct Frames {
    pub header: Vec<String>,
    pub rows: Vec<Vec<String>>,
}

impl Frames {
    pub fn parse(csv: &str) -> Frames {
        let split = |l: &str| l.split(',').map(String::from).collect::<Vec<_>>();
        let mut lines = csv.lines();
        Frames {
            header: split(lines.next().unwrap()),
            rows: lines.map(split).collect(),
        }
    }

    /// Column `name` of row `r`, a number.
    pub fn num(&self, r: &[String], name: &str) -> f64 {
        let col = self.header.iter().position(|c| c == name).unwrap();
        r[col].parse().unwrap()
    }

    /// The time of the first frame whose `event` column holds `event`
    /// (`vehicle/name:started`).
    pub fn logged(&self, event: &str) -> Option<f64> {
        let col = self.header.iter().position(|c| c == "event").unwrap();
        self.rows
            .iter()
            .find(|r| r[col].contains(event))
            .map(|r| self.num(r, "t_s"))
    }
}

/// A copy of the test files in a temporary folder, with `cut-in.xosc`'s text changed by
/// `edit` and written as `mutant.xosc`.
pub fn mutant(edit: impl Fn(&str) -> String) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    for name in ["two-lanes.xodr", "catalogs/VehicleCatalog.xosc"] {
        let to = dir.path().join(name);
        std::fs::create_dir_all(to.parent().unwrap()).unwrap();
        std::fs::copy(data().join(name), to).unwrap();
    }
    let text = std::fs::read_to_string(data().join("cut-in.xosc")).unwrap();
    let path = dir.path().join("mutant.xosc");
    std::fs::write(&path, edit(&text)).unwrap();
    (dir, path)
}

/// The line (from 1) of the first line of the file at `path` that holds `needle`.
pub fn line_of(path: &Path, needle: &str) -> usize {
    let text = std::fs::read_to_string(path).unwrap();
    1 + text
        .lines()
        .position(|l| l.contains(needle))
        .unwrap_or_else(|| panic!("`{needle}` is not in {}", path.display()))
}
