//! `carfollow import`: an OpenSCENARIO file written as carfollow's own scenario file, and
//! the options every command that reads one takes (`check`, `run`).

use clap::Args;
use sim_core::openscenario::{import, is_openscenario, ImportOptions};
use sim_core::{Plan, Scenario, ScenarioError};
use std::path::{Path, PathBuf};

/// How an OpenSCENARIO file (`.xosc`) is read: by `check`, `run` and `import`.
#[derive(Args, Debug, Clone, Default)]
pub struct OpenScenarioArgs {
    /// For .xosc files: set a parameter the file declares, NAME=VALUE (repeatable).
    #[arg(long = "param", value_name = "NAME=VALUE")]
    pub params: Vec<String>,
    /// For .xosc files: the entity carfollow drives as the chase (default: one named Ego,
    /// ego, hero or ego_vehicle).
    #[arg(long, value_name = "NAME")]
    pub ego: Option<String>,
    /// For .xosc files: the entity the chase follows (default: the nearest vehicle ahead
    /// of the ego in its lane at t = 0, or none if none is or it starts beyond the 250 m
    /// the renderer draws); `none`: no lead, the chase cruising until it finds a vehicle in
    /// its path.
    #[arg(long, value_name = "NAME")]
    pub lead: Option<String>,
}

impl OpenScenarioArgs {
    fn given(&self) -> bool {
        !self.params.is_empty() || self.ego.is_some() || self.lead.is_some()
    }

    /// The import options these give, for the written scenario's paths relative to
    /// `relative_to` (default: the file's folder).
    pub fn options(&self, relative_to: Option<PathBuf>) -> ImportOptions {
        ImportOptions {
            ego: self.ego.clone(),
            lead: self.lead.clone(),
            params: self.params.clone(),
            duration_s: None,
            relative_to,
        }
    }

    /// Plans the scenario file `path` with `set`: an OpenSCENARIO file read with these
    /// options; these options on another file are refused.
    pub fn plan(&self, path: &Path, set: &[String]) -> anyhow::Result<Plan, anyhow::Error> {
        if is_openscenario(path) {
            let s = Scenario::load_openscenario(path, set, &self.options(None))?;
            return Ok(Plan::new(&s)?);
        }
        if self.given() {
            anyhow::bail!(
                "{}: --param, --ego and --lead are for OpenSCENARIO files (.xosc)",
                path.display()
            );
        }
        Ok(Plan::load(path, set)?)
    }
}

/// Arguments of `carfollow import`.
#[derive(Args, Debug)]
#[command(
    after_help = super::exit::HELP,
    about = "Write an OpenSCENARIO file (.xosc) as a carfollow scenario file",
    long_about = "Read an ASAM OpenSCENARIO 1.0-1.3 file (.xosc) with its catalogs and the \
                  OpenDRIVE road of its RoadNetwork, and write it as a carfollow scenario file \
                  (TOML), which runs as `carfollow run FILE.xosc` does, bit for bit. What \
                  carfollow cannot run as the standard defines it is refused in one line naming \
                  the file, the line and the element; a refused file writes nothing. Exit \
                  status: 0 when written, 2 when the file is refused."
)]
pub struct ImportArgs {
    /// The OpenSCENARIO file.
    pub file: PathBuf,
    /// The scenario file to write.
    #[arg(short, long, value_name = "FILE.toml")]
    pub out: PathBuf,
    /// The run's length, seconds, instead of the file's StopTrigger.
    #[arg(long, value_name = "SECONDS")]
    pub duration: Option<f64>,
    #[command(flatten)]
    pub openscenario: OpenScenarioArgs,
}

/// Runs the subcommand: the file is read and the scenario it gives is checked as `check`
/// checks it before anything is written.
pub fn run_import(args: ImportArgs) -> anyhow::Result<()> {
    // The output's folder is made if missing (the scenario's paths are written relative to
    // it, and checked through it), and taken away again if the file is refused.
    let out_dir = match args.out.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let made = out_dir
        .ancestors()
        .take_while(|d| !d.as_os_str().is_empty() && !d.exists())
        .last()
        .map(Path::to_path_buf);
    if made.is_some() {
        std::fs::create_dir_all(&out_dir)
            .map_err(|e| anyhow::anyhow!("{}: cannot make the folder: {e}", out_dir.display()))?;
    }
    let result = import_into(&args, &out_dir);
    if let (Err(_), Some(made)) = (&result, made) {
        let _ = std::fs::remove_dir_all(made);
    }
    result
}

/// [`run_import`] once the output's folder `out_dir` exists.
fn import_into(args: &ImportArgs, out_dir: &Path) -> anyhow::Result<()> {
    if !is_openscenario(&args.file) {
        anyhow::bail!("{}: not an OpenSCENARIO file (.xosc)", args.file.display());
    }
    if let Some(d) = args.duration.filter(|d| !(d.is_finite() && *d > 0.0)) {
        anyhow::bail!("--duration {d}: must be a positive number of seconds");
    }
    let mut options = args.openscenario.options(Some(out_dir.to_path_buf()));
    options.duration_s = args.duration;
    let imported = import(&args.file, &options)?;
    // What `check` would say of the written file, before it is written.
    let scenario =
        Scenario::from_text(&imported.text, &args.out, out_dir, &[]).map_err(|e| match e {
            ScenarioError::Invalid { field, message, .. } => ScenarioError::Imported {
                path: args.file.clone(),
                message: format!("`{field}` {message}"),
            },
            other => other,
        })?;
    Plan::new(&scenario)?;
    for warning in &imported.warnings {
        eprintln!("warning: {}: {warning}", args.file.display());
    }
    // Written whole or not at all: to a file beside it, then renamed over it.
    let partial = args.out.with_extension("toml.partial");
    std::fs::write(&partial, imported.text.as_bytes())
        .and_then(|()| std::fs::rename(&partial, &args.out))
        .map_err(|e| {
            let _ = std::fs::remove_file(&partial);
            anyhow::anyhow!("{}: cannot write: {e}", args.out.display())
        })?;
    say!("{}: wrote {}", args.file.display(), args.out.display());
    Ok(())
}
