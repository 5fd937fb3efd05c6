//! `carfollow export`: a scenario written as ASAM OpenSCENARIO (`.xosc`) on its route
//! written as ASAM OpenDRIVE (`.xodr`), which `carfollow import` reads back as the same
//! scenario.

use clap::Args;
use sim_core::openscenario::export::carried::{self, carried as carried_fields, differences};
use sim_core::openscenario::export::{write_files, Carried, CARRIED_PREFIX};
use sim_core::openscenario::ImportOptions;
use sim_core::Scenario;
use std::path::{Path, PathBuf};

/// Arguments of `carfollow export`.
#[derive(Args, Debug)]
#[command(
    after_help = super::exit::HELP,
    about = "Write a scenario as OpenSCENARIO (.xosc) on an OpenDRIVE road (.xodr)",
    long_about = "Write a scenario as ASAM OpenSCENARIO 1.2 (DIR/NAME.xosc) on its route \
                  written as an ASAM OpenDRIVE 1.7 road (DIR/NAME.xodr), NAME the scenario's \
                  name. The vehicles, their start, speed profiles and events, the weather and \
                  the duration are the standard's elements; carfollow's own settings that the \
                  standard has no element for (the camera, the tracker, the chase's \
                  controller, ...) are carried as parameters named carfollow.FIELD, which \
                  other readers ignore and `carfollow import` applies, so that the imported \
                  scenario runs as this one does, bit for bit (the export checks this by \
                  importing what it wrote). A failed export writes nothing. Exit status: 0 \
                  when written, 2 on bad input."
)]
pub struct ExportArgs {
    /// The scenario file (.toml, or .xosc).
    pub scenario: PathBuf,
    /// The folder to write NAME.xosc and NAME.xodr in (made if missing).
    #[arg(short, long, value_name = "DIR")]
    pub out: PathBuf,
    /// Override a field by its dotted path, e.g. --set tracker.lambda=0.7 (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
}

/// Runs the subcommand.
pub fn run_export(args: ExportArgs) -> anyhow::Result<()> {
    let scenario = Scenario::load(&args.scenario, &args.set)?;
    let stem = sim_core::openscenario::safe_name(&scenario.name);
    std::fs::create_dir_all(&args.out)
        .map_err(|e| anyhow::anyhow!("{}: cannot make the folder: {e}", args.out.display()))?;
    // Written into a folder of its own beside the outputs, then renamed into place: a
    // failed export leaves nothing.
    let work = args
        .out
        .join(format!(".{stem}.export-{}", std::process::id()));
    let result = std::fs::create_dir(&work)
        .map_err(|e| anyhow::anyhow!("{}: cannot write: {e}", work.display()))
        .and_then(|()| export_in(&scenario, &args.scenario, &work, &stem))
        .and_then(|warnings| {
            for ext in ["xodr", "xosc"] {
                let name = format!("{stem}.{ext}");
                std::fs::rename(work.join(&name), args.out.join(&name)).map_err(|e| {
                    anyhow::anyhow!("{}: cannot write: {e}", args.out.join(&name).display())
                })?;
            }
            Ok(warnings)
        });
    let _ = std::fs::remove_dir_all(&work);
    let warnings = result?;
    for w in &warnings {
        eprintln!("warning: {}: {w}", args.scenario.display());
    }
    say!(
        "{}: wrote {} and {}",
        args.scenario.display(),
        args.out.join(format!("{stem}.xosc")).display(),
        args.out.join(format!("{stem}.xodr")).display()
    );
    Ok(())
}

/// Writes `stem.xosc` and `stem.xodr` of `s` (read from `path`) in `work`, and says what
/// the file carries as carfollow's parameters.
fn export_in(s: &Scenario, path: &Path, work: &Path, stem: &str) -> anyhow::Result<Vec<String>> {
    let xodr_name = format!("{stem}.xodr");
    let xosc = work.join(format!("{stem}.xosc"));
    let write = |carried: &[Carried]| -> anyhow::Result<bool> {
        let files = write_files(s, &xodr_name, carried);
        std::fs::write(work.join(&xodr_name), files.xodr)?;
        std::fs::write(&xosc, files.xosc)?;
        Ok(files.road_exact)
    };
    let read_back = || -> anyhow::Result<Scenario> {
        Scenario::load_openscenario(&xosc, &[], &ImportOptions::default()).map_err(|e| {
            anyhow::anyhow!(
                "{}: the exported file does not read back: {e}",
                path.display()
            )
        })
    };
    // The elements alone, read back: what they do not say is carried.
    let road_exact = write(&[])?;
    let plain = read_back()?;
    let original = s.resolved_json();
    let mut carry = carried_fields(&original, &plain.resolved_json())
        .map_err(|e| anyhow::anyhow!("{}: cannot export: {e}", path.display()))?;
    if !road_exact {
        carry.push(carried::route(&s.route));
    }
    if plain.target != s.target {
        carry.push(Carried {
            path: "tracker.target".into(),
            value: toml_string(&target_path(s, path, work)),
        });
    }
    write(&carry)?;
    let back = read_back()?;
    let mut warnings = Vec::new();
    if !carry.is_empty() {
        let mut sections: Vec<&str> = carry
            .iter()
            .map(|c| c.path.split('.').next().unwrap_or(""))
            .collect();
        sections.dedup();
        sections.sort_unstable();
        sections.dedup();
        warnings.push(format!(
            "{} setting(s) of {} have no OpenSCENARIO element as carfollow reads them back: \
             carried as {CARRIED_PREFIX}* parameters, which carfollow's import applies and \
             other readers ignore",
            carry.len(),
            sections.join(", ")
        ));
    }
    let mut differ = differences(&original, &back.resolved_json());
    if back.route != s.route {
        differ.push("/route".into());
    }
    if back.target != s.target {
        differ.push("/tracker/target".into());
    }
    if !differ.is_empty() {
        warnings.push(format!(
            "imported back, the file differs from the scenario at {}: it will not run as this one does",
            differ.join(", ")
        ));
    }
    Ok(warnings)
}

/// `tracker.target` as the exported file carries it: relative to the file's folder when
/// it names a file, else as written (a target shipped with carfollow).
fn target_path(s: &Scenario, path: &Path, work: &Path) -> String {
    let target = &s.resolved.tracker.target;
    let file = path.parent().unwrap_or(Path::new(".")).join(target);
    if !file.is_file() {
        return target.clone();
    }
    carried::relative(&file, work)
        .to_string_lossy()
        .replace('\\', "/")
}

fn toml_string(s: &str) -> String {
    toml::Value::String(s.to_string()).to_string()
}
