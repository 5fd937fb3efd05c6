//! `ParameterValueDistribution` files (OpenSCENARIO 1.1–1.3): a scenario file and the
//! values its parameters take, each set of values one run. carfollow runs them as a sweep
//! (`carfollow sweep FILE.xosc`), a point per run.
//!
//! - **Deterministic**: each `DeterministicSingleParameterDistribution` (a
//!   `DistributionSet` of values, or a `DistributionRange`, `lowerLimit` to `upperLimit`
//!   inclusive by `stepWidth`) and each `DeterministicMultiParameterDistribution` (a
//!   `ValueSetDistribution`, each `ParameterValueSet` one choice of several parameters
//!   together) is one dimension; the runs are every combination, the first distribution
//!   outermost and the last fastest, as the standard combines them.
//! - **Stochastic**: `numberOfTestRuns` runs, each parameter drawn independently from its
//!   `StochasticDistribution` (`ProbabilityDistributionSet`, `NormalDistribution`,
//!   `LogNormalDistribution`, `UniformDistribution`, `PoissonDistribution`, `Histogram`;
//!   a `Range` restricts a normal, log-normal or Poisson distribution to it, by drawing
//!   again). Each parameter draws from its own random stream, named after it, of the seed
//!   `randomSeed` (0 when absent): the same file gives the same runs, and a parameter
//!   added to the file changes no other's values.
//!
//! `UserDefinedDistribution` is refused: its meaning is the tool's that wrote it.

use super::draw::{self, MAX_POISSON_MEAN, MAX_REJECTIONS};
use super::error::OscError;
use super::xml::{child, children, elements, only_element, read_text, Xml};
use roxmltree::Node;
use std::path::{Path, PathBuf};

/// The most runs a distribution may make (a typo such as `stepWidth="0.0001"` should not
/// launch a million runs; a sweep file's axes have the same bound).
pub const MAX_RUNS: usize = 10_000;

/// Decimal places kept of a `DistributionRange`'s values, as a sweep file's ranges keep:
/// `1.1 + 2·0.2` is `1.5`, not `1.5000000000000002`.
const RANGE_DECIMALS: i32 = 9;

/// The prefix of every stochastic parameter's random stream; the parameter's name follows.
pub const STREAM_PREFIX: &str = "openscenario-distribution/";

/// Runs, each `(parameter, value)` in the file's order.
pub type Runs = Vec<Vec<(String, String)>>;

/// One parameter the distribution sets, and where.
#[derive(Clone, Debug, PartialEq)]
pub struct DistributedParameter {
    /// Its name, as the scenario declares it.
    pub name: String,
    /// The line of the element that sets it.
    pub line: u32,
}

/// A `ParameterValueDistribution` file, read.
#[derive(Clone, Debug, PartialEq)]
pub struct Distribution {
    /// The distribution file.
    pub path: PathBuf,
    /// The scenario file it names (`ScenarioFile`), resolved against its folder.
    pub scenario: PathBuf,
    /// The line of its `ScenarioFile`.
    pub scenario_line: u32,
    /// Whether the runs were drawn (`Stochastic`), with the seed they were drawn from.
    pub random_seed: Option<u64>,
    /// The parameters it sets, in the order they first appear in the file.
    pub parameters: Vec<DistributedParameter>,
    /// The runs, each `(parameter, value)` in the file's order.
    pub runs: Runs,
}

/// Whether the OpenSCENARIO file at `path` is a `ParameterValueDistribution` (false when
/// it cannot be read or parsed: reading it says why).
pub fn is_distribution(path: &Path) -> bool {
    let Ok(text) = read_text(path) else {
        return false;
    };
    Xml::parse(&text, path)
        .is_ok_and(|xml| child(xml.doc.root_element(), "ParameterValueDistribution").is_some())
}

/// Reads the distribution file at `path`: its scenario file and its runs. Each parameter
/// it sets must be declared at the top of that scenario file.
pub fn read_distribution(path: &Path) -> Result<Distribution, OscError> {
    let text = read_text(path)?;
    let xml = Xml::parse(&text, path)?;
    let root = xml.doc.root_element();
    let Some(pvd) = child(root, "ParameterValueDistribution") else {
        return Err(xml.at(
            root,
            "<OpenSCENARIO>: not a parameter distribution (no <ParameterValueDistribution>); \
             a scenario runs with `carfollow run`",
        ));
    };
    super::version(&xml, 1.0, "parameter distributions are OpenSCENARIO")?;
    let file = child(pvd, "ScenarioFile")
        .ok_or_else(|| xml.at(pvd, "<ParameterValueDistribution> has no <ScenarioFile>"))?;
    let dir = path.parent().unwrap_or(Path::new("."));
    let scenario = dir.join(xml.req(file, "filepath")?);
    let declared = declared_parameters(&scenario).map_err(|why| {
        xml.at(
            file,
            format!("<ScenarioFile filepath=\"{}\">: {why}", scenario.display()),
        )
    })?;
    let definition = elements(pvd)
        .find(|e| e.tag_name().name() != "ScenarioFile")
        .ok_or_else(|| {
            xml.at(
                pvd,
                "<ParameterValueDistribution> has no <Deterministic> or <Stochastic>",
            )
        })?;
    let mut parameters = Vec::new();
    let (random_seed, runs) = match definition.tag_name().name() {
        "Deterministic" => (
            None,
            deterministic(&xml, definition, &declared, &mut parameters)?,
        ),
        "Stochastic" => {
            let (seed, runs) = stochastic(&xml, definition, &declared, &mut parameters)?;
            (Some(seed), runs)
        }
        _ => return Err(xml.unsupported(definition, "distribution", "")),
    };
    Ok(Distribution {
        path: path.to_owned(),
        scenario,
        scenario_line: xml.line(file),
        random_seed,
        parameters,
        runs,
    })
}

/// The parameters declared at the top of the scenario file at `path`.
fn declared_parameters(path: &Path) -> Result<Vec<String>, String> {
    let text = read_text(path).map_err(|e| e.to_string())?;
    let xml = Xml::parse(&text, path).map_err(|e| e.to_string())?;
    let root = xml.doc.root_element();
    if child(root, "ParameterValueDistribution").is_some() {
        return Err("is a parameter distribution itself, not a scenario".into());
    }
    Ok(child(root, "ParameterDeclarations")
        .map(|d| {
            children(d, "ParameterDeclaration")
                .filter_map(|p| p.attribute("name").map(str::to_string))
                .collect()
        })
        .unwrap_or_default())
}

/// Records that `node` sets parameter `name`: it must be declared, and set by no other
/// distribution.
fn claim(
    xml: &Xml,
    node: Node,
    name: &str,
    declared: &[String],
    parameters: &[DistributedParameter],
    within: &mut Vec<String>,
) -> Result<(), OscError> {
    if !declared.iter().any(|d| d == name) {
        let known = if declared.is_empty() {
            "none".to_string()
        } else {
            declared.join(", ")
        };
        return Err(xml.at(
            node,
            format!(
                "<{}>: the scenario declares no parameter `{name}` (it declares: {known})",
                node.tag_name().name()
            ),
        ));
    }
    if within.iter().any(|n| n == name) {
        return Err(xml.at(
            node,
            format!("<{}>: sets `{name}` twice", node.tag_name().name()),
        ));
    }
    within.push(name.to_string());
    if let Some(p) = parameters.iter().find(|p| p.name == name) {
        return Err(xml.at(
            node,
            format!(
                "<{}>: `{name}` is set by another distribution too (line {})",
                node.tag_name().name(),
                p.line
            ),
        ));
    }
    Ok(())
}

/// The runs of a `Deterministic`: the product of its distributions, the last fastest.
fn deterministic(
    xml: &Xml,
    node: Node,
    declared: &[String],
    parameters: &mut Vec<DistributedParameter>,
) -> Result<Runs, OscError> {
    let mut runs: Runs = vec![Vec::new()];
    for dist in elements(node) {
        let choices: Runs = match dist.tag_name().name() {
            "DeterministicSingleParameterDistribution" => {
                let name = xml.req(dist, "parameterName")?;
                let mut within = Vec::new();
                claim(xml, dist, &name, declared, parameters, &mut within)?;
                let values = single_values(xml, only_element(xml, dist)?)?;
                parameters.push(DistributedParameter {
                    name: name.clone(),
                    line: xml.line(dist),
                });
                values
                    .into_iter()
                    .map(|v| vec![(name.clone(), v)])
                    .collect()
            }
            "DeterministicMultiParameterDistribution" => {
                value_sets(xml, only_element(xml, dist)?, declared, parameters)?
            }
            _ => return Err(xml.unsupported(dist, "distribution", "")),
        };
        let count = runs.len().saturating_mul(choices.len());
        if count > MAX_RUNS {
            return Err(xml.at(
                dist,
                format!(
                    "<{}>: the distributions make {count} runs or more; at most {MAX_RUNS} are allowed",
                    dist.tag_name().name()
                ),
            ));
        }
        runs = runs
            .iter()
            .flat_map(|run| {
                choices.iter().map(move |choice| {
                    let mut r = run.clone();
                    r.extend(choice.iter().cloned());
                    r
                })
            })
            .collect();
    }
    Ok(runs)
}

/// The values of a single parameter's `DistributionSet` or `DistributionRange`.
fn single_values(xml: &Xml, node: Node) -> Result<Vec<String>, OscError> {
    match node.tag_name().name() {
        "DistributionSet" => {
            let mut values: Vec<String> = Vec::new();
            for e in children(node, "Element") {
                let v = xml.req(e, "value")?;
                if values.contains(&v) {
                    return Err(xml.at(e, format!("<Element value=\"{v}\">: listed twice")));
                }
                values.push(v);
            }
            if values.is_empty() {
                return Err(xml.at(node, "<DistributionSet> has no <Element>"));
            }
            Ok(values)
        }
        "DistributionRange" => {
            let step = xml.num(node, "stepWidth")?;
            let (lower, upper) = range(xml, node)?;
            if step <= 0.0 {
                return Err(xml.at(
                    node,
                    format!("<DistributionRange stepWidth=\"{step}\">: must be > 0"),
                ));
            }
            // The ε forgives a step that does not divide the span exactly in binary.
            let steps = ((upper - lower) / step + 1e-6).floor();
            if steps + 1.0 > MAX_RUNS as f64 {
                return Err(xml.at(
                    node,
                    format!(
                        "<DistributionRange>: {} values; at most {MAX_RUNS} are allowed",
                        steps + 1.0
                    ),
                ));
            }
            let scale = 10f64.powi(RANGE_DECIMALS);
            Ok((0..=steps as u64)
                .map(|i| number(((lower + i as f64 * step) * scale).round() / scale))
                .collect())
        }
        _ => Err(xml.unsupported(
            node,
            "distribution",
            "its meaning is the tool's that wrote it",
        )),
    }
}

/// The choices of a `ValueSetDistribution`: each `ParameterValueSet` one.
fn value_sets(
    xml: &Xml,
    node: Node,
    declared: &[String],
    parameters: &mut Vec<DistributedParameter>,
) -> Result<Runs, OscError> {
    if node.tag_name().name() != "ValueSetDistribution" {
        return Err(xml.unsupported(node, "distribution", ""));
    }
    let mut sets = Vec::new();
    let mut mine: Vec<DistributedParameter> = Vec::new();
    for set in children(node, "ParameterValueSet") {
        let mut within = Vec::new();
        let mut values = Vec::new();
        for a in children(set, "ParameterAssignment") {
            let name = xml.req(a, "parameterRef")?;
            claim(xml, a, &name, declared, parameters, &mut within)?;
            if !mine.iter().any(|p| p.name == name) {
                mine.push(DistributedParameter {
                    name: name.clone(),
                    line: xml.line(a),
                });
            }
            values.push((name, xml.req(a, "value")?));
        }
        if values.is_empty() {
            return Err(xml.at(set, "<ParameterValueSet> has no <ParameterAssignment>"));
        }
        sets.push(values);
    }
    if sets.is_empty() {
        return Err(xml.at(node, "<ValueSetDistribution> has no <ParameterValueSet>"));
    }
    parameters.extend(mine);
    Ok(sets)
}

/// A `Stochastic`'s seed and runs.
fn stochastic(
    xml: &Xml,
    node: Node,
    declared: &[String],
    parameters: &mut Vec<DistributedParameter>,
) -> Result<(u64, Runs), OscError> {
    let runs = xml.num(node, "numberOfTestRuns")?;
    if runs < 1.0 || runs.fract() != 0.0 || runs > MAX_RUNS as f64 {
        return Err(xml.at(
            node,
            format!("<Stochastic numberOfTestRuns=\"{runs}\">: must be a whole number from 1 to {MAX_RUNS}"),
        ));
    }
    let seed = match xml.opt_num(node, "randomSeed")? {
        None => 0,
        Some(s) if s >= 0.0 && s.fract() == 0.0 && s < 2f64.powi(64) => s as u64,
        // A seed that is not a whole number still names one stream: its bits.
        Some(s) => s.to_bits(),
    };
    let mut columns: Runs = Vec::new();
    let mut within = Vec::new();
    for dist in children(node, "StochasticDistribution") {
        let name = xml.req(dist, "parameterName")?;
        claim(xml, dist, &name, declared, parameters, &mut within)?;
        let shape = only_element(xml, dist)?;
        let mut rng = vehicle::named_stream(seed, &format!("{STREAM_PREFIX}{name}"));
        let values = (0..runs as usize)
            .map(|_| draw_one(xml, shape, &mut rng))
            .collect::<Result<Vec<String>, OscError>>()?;
        parameters.push(DistributedParameter {
            name: name.clone(),
            line: xml.line(dist),
        });
        columns.push(values.into_iter().map(|v| (name.clone(), v)).collect());
    }
    if columns.is_empty() {
        return Err(xml.at(node, "<Stochastic> has no <StochasticDistribution>"));
    }
    Ok((
        seed,
        (0..runs as usize)
            .map(|i| columns.iter().map(|c| c[i].clone()).collect())
            .collect(),
    ))
}

/// One draw from the distribution `shape`, as the parameter's value.
fn draw_one(xml: &Xml, shape: Node, rng: &mut rand_chacha::ChaCha8Rng) -> Result<String, OscError> {
    let tag = shape.tag_name().name();
    match tag {
        "ProbabilityDistributionSet" => {
            let mut values = Vec::new();
            let mut weights = Vec::new();
            for e in children(shape, "Element") {
                values.push(xml.req(e, "value")?);
                weights.push(non_negative(xml, e, "weight")?);
            }
            weights_sum(xml, shape, &weights)?;
            Ok(values.swap_remove(draw::weighted(rng, &weights)))
        }
        "Histogram" => {
            let mut bins = Vec::new();
            let mut weights = Vec::new();
            for b in children(shape, "Bin") {
                weights.push(non_negative(xml, b, "weight")?);
                bins.push(range(xml, b)?);
            }
            weights_sum(xml, shape, &weights)?;
            let (lower, upper) = bins[draw::weighted(rng, &weights)];
            Ok(number(lower + draw::unit(rng) * (upper - lower)))
        }
        "UniformDistribution" => {
            let (lower, upper) = range(xml, shape)?;
            Ok(number(lower + draw::unit(rng) * (upper - lower)))
        }
        "NormalDistribution" | "LogNormalDistribution" => {
            let mean = xml.num(shape, "expectedValue")?;
            let variance = non_negative(xml, shape, "variance")?;
            // A log-normal's expected value m and variance v are its own (the standard's
            // words): ln X is normal with σ² = ln(1 + v/m²) and μ = ln m − σ²/2.
            let (mu, sigma) = if tag == "NormalDistribution" {
                (mean, variance.sqrt())
            } else if mean > 0.0 {
                let s2 = (1.0 + variance / (mean * mean)).ln();
                (mean.ln() - s2 / 2.0, s2.sqrt())
            } else {
                return Err(xml.at(
                    shape,
                    format!("<{tag} expectedValue=\"{mean}\">: must be > 0"),
                ));
            };
            let bounds = optional_range(xml, shape)?;
            truncated(xml, shape, bounds, || {
                let x = mu + sigma * draw::standard_normal(rng);
                if tag == "NormalDistribution" {
                    x
                } else {
                    x.exp()
                }
            })
            .map(number)
        }
        "PoissonDistribution" => {
            let lambda = non_negative(xml, shape, "expectedValue")?;
            if lambda > MAX_POISSON_MEAN {
                return Err(xml.at(
                    shape,
                    format!("<PoissonDistribution expectedValue=\"{lambda}\">: carfollow draws up to {MAX_POISSON_MEAN}"),
                ));
            }
            let bounds = optional_range(xml, shape)?;
            truncated(xml, shape, bounds, || draw::poisson(rng, lambda) as f64)
                .map(|k| format!("{}", k as u64))
        }
        _ => Err(xml.unsupported(
            shape,
            "distribution",
            "its meaning is the tool's that wrote it",
        )),
    }
}

/// A draw of `draw` inside `bounds` (inclusive), drawing again while outside.
fn truncated(
    xml: &Xml,
    node: Node,
    bounds: Option<(f64, f64)>,
    mut draw: impl FnMut() -> f64,
) -> Result<f64, OscError> {
    let Some((lower, upper)) = bounds else {
        return Ok(draw());
    };
    for _ in 0..MAX_REJECTIONS {
        let x = draw();
        if (lower..=upper).contains(&x) {
            return Ok(x);
        }
    }
    Err(xml.at(
        node,
        format!(
            "<{}>: its <Range> holds too little of it ({MAX_REJECTIONS} draws in a row fell outside)",
            node.tag_name().name()
        ),
    ))
}

/// The `Range` child of `node`: `(lowerLimit, upperLimit)`, lower ≤ upper.
fn range(xml: &Xml, node: Node) -> Result<(f64, f64), OscError> {
    optional_range(xml, node)?
        .ok_or_else(|| xml.at(node, format!("<{}> has no <Range>", node.tag_name().name())))
}

fn optional_range(xml: &Xml, node: Node) -> Result<Option<(f64, f64)>, OscError> {
    let Some(r) = child(node, "Range") else {
        return Ok(None);
    };
    let (lower, upper) = (xml.num(r, "lowerLimit")?, xml.num(r, "upperLimit")?);
    if lower > upper {
        return Err(xml.at(
            r,
            format!("<Range lowerLimit=\"{lower}\" upperLimit=\"{upper}\">: needs lowerLimit <= upperLimit"),
        ));
    }
    Ok(Some((lower, upper)))
}

fn non_negative(xml: &Xml, node: Node, name: &str) -> Result<f64, OscError> {
    let v = xml.num(node, name)?;
    if v < 0.0 {
        return Err(xml.at(
            node,
            format!("<{} {name}=\"{v}\">: must be >= 0", node.tag_name().name()),
        ));
    }
    Ok(v)
}

fn weights_sum(xml: &Xml, node: Node, weights: &[f64]) -> Result<(), OscError> {
    if weights.is_empty() || weights.iter().sum::<f64>() <= 0.0 {
        return Err(xml.at(
            node,
            format!(
                "<{}>: needs elements whose weights sum to more than 0",
                node.tag_name().name()
            ),
        ));
    }
    Ok(())
}

/// A number as a parameter's value: the shortest text that reads back as it (`1.5`,
/// `70`), with −0 written 0.
fn number(v: f64) -> String {
    format!("{}", v + 0.0)
}
