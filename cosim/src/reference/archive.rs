//! What an FMU's FMI-LS-REF folder says about how to check it: the manifest
//! (`fmi-ls-manifest.xml`, its `<Related role="result">` files: the reference results of
//! the DefaultExperiment, as Reference-FMUs ship them) and, when present, the draft's
//! experiments file (`experiments.xml`: `<Experiment>` with its times, `<Stimuli>` and
//! `<References>`), which then says which experiments there are. Every file named is read
//! from the archive; every problem is named with its file and element, all at once.
use super::elements::{self, Element};
use super::table::ReferenceTable;
use super::tube::Tolerances;
use crate::system::InputTable;
use std::io::Read;
use std::path::{Path, PathBuf};

/// The layered standard's folder inside an FMU.
pub const DIR: &str = "extra/org.fmi-standard.fmi-ls-ref";
pub const MANIFEST: &str = "fmi-ls-manifest.xml";
pub const EXPERIMENTS: &str = "experiments.xml";

/// Tolerances a `<References>` element may carry (`relativeTolerance`,
/// `absoluteTolerance`, `timeTolerance`: ours, the draft names none); each unset one
/// keeps the checker's.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ToleranceOverrides {
    pub relative: Option<f64>,
    pub absolute: Option<f64>,
    pub time: Option<f64>,
}

impl ToleranceOverrides {
    /// Each tolerance given that cannot be one, named as `names` (relative, absolute, time)
    /// say it was given.
    pub fn problems(&self, names: [&str; 3]) -> Vec<String> {
        [
            ("relative", self.relative, names[0]),
            ("absolute", self.absolute, names[1]),
            ("time", self.time, names[2]),
        ]
        .into_iter()
        .filter_map(|(which, value, name)| {
            let why = super::tube::problem(which, value?)?;
            Some(format!("{name}: {why}"))
        })
        .collect()
    }

    pub fn over(&self, base: Tolerances) -> Tolerances {
        Tolerances {
            relative: self.relative.unwrap_or(base.relative),
            absolute: self.absolute.unwrap_or(base.absolute),
            time: self.time.unwrap_or(base.time),
        }
    }
}

/// A reference result: where it is in the archive, its table, its tolerances.
#[derive(Debug, Clone, PartialEq)]
pub struct Reference {
    pub source: String,
    pub table: ReferenceTable,
    pub tolerances: ToleranceOverrides,
    /// The columns its `<Signal name>` children select; empty: every column.
    pub signals: Vec<String>,
}

/// The input signals of an experiment: where they are, their text (what `--input` reads)
/// and their table.
#[derive(Debug, Clone, PartialEq)]
pub struct Stimuli {
    pub source: String,
    pub text: String,
    pub table: InputTable,
}

/// One experiment: times unset are the DefaultExperiment's.
#[derive(Debug, Clone, PartialEq)]
pub struct Experiment {
    pub name: String,
    pub start_time: Option<f64>,
    pub stop_time: Option<f64>,
    pub step_size: Option<f64>,
    pub stimuli: Option<Stimuli>,
    pub references: Vec<Reference>,
    /// What the experiment names that the check does not apply (a `<Parameters>` set).
    pub notes: Vec<String>,
}

/// The experiments of one FMU.
#[derive(Debug, Clone, PartialEq)]
pub struct References {
    pub fmu: PathBuf,
    pub experiments: Vec<Experiment>,
}

/// The files of the archive at `fmu`, read on demand.
struct Archive {
    fmu: PathBuf,
    zip: zip::ZipArchive<std::fs::File>,
}

impl Archive {
    fn open(fmu: &Path) -> Result<Archive, String> {
        let file =
            std::fs::File::open(fmu).map_err(|e| format!("{}: cannot open: {e}", fmu.display()))?;
        let zip = zip::ZipArchive::new(file)
            .map_err(|e| format!("{}: not a zip archive: {e}", fmu.display()))?;
        Ok(Archive {
            fmu: fmu.to_owned(),
            zip,
        })
    }

    fn has(&self, path: &str) -> bool {
        self.zip.index_for_name(path).is_some()
    }

    fn read(&mut self, path: &str) -> Result<Vec<u8>, String> {
        let limit = fmi_abi::unpack::max_unpacked_bytes().map_err(|e| e.to_string())?;
        let mut entry = self
            .zip
            .by_name(path)
            .map_err(|e| format!("{}: {path}: {e}", self.fmu.display()))?;
        let mut bytes = Vec::new();
        (&mut entry)
            .take(limit)
            .read_to_end(&mut bytes)
            .map_err(|e| format!("{}: {path}: {e}", self.fmu.display()))?;
        if bytes.len() as u64 >= limit {
            return Err(format!(
                "{}: {path}: larger than the {limit} bytes an archive may unpack to",
                self.fmu.display()
            ));
        }
        Ok(bytes)
    }

    /// The archive path of a file an LS-REF file names: beside it, as Reference-FMUs
    /// place their CSVs, else from the archive's root, as SSP tools write the draft's paths.
    fn locate(&self, source: &str) -> Result<String, String> {
        let beside = format!("{DIR}/{source}");
        let from_root = source.trim_start_matches('/').to_owned();
        if self.has(&beside) {
            Ok(beside)
        } else if self.has(&from_root) {
            Ok(from_root)
        } else {
            Err(format!(
                "no such file in the FMU (looked for {beside} and {from_root})"
            ))
        }
    }

    fn text(&mut self, path: &str) -> Result<String, String> {
        String::from_utf8(self.read(path)?)
            .map_err(|_| format!("{}: {path}: not UTF-8 text", self.fmu.display()))
    }
}

/// The FMU's LS-REF experiments; `None` when it carries neither file.
pub fn read(fmu: &Path) -> Result<Option<References>, Vec<String>> {
    let mut archive = Archive::open(fmu).map_err(|e| vec![e])?;
    let manifest_path = format!("{DIR}/{MANIFEST}");
    let experiments_path = format!("{DIR}/{EXPERIMENTS}");
    let (has_manifest, has_experiments) =
        (archive.has(&manifest_path), archive.has(&experiments_path));
    if !has_manifest && !has_experiments {
        return Ok(None);
    }
    let mut problems = Vec::new();
    // The manifest is read even beside an experiments file: a file it names must exist.
    let from_manifest = if has_manifest {
        manifest(&mut archive, &manifest_path, &mut problems)
    } else {
        None
    };
    let experiments = if has_experiments {
        experiments(&mut archive, &experiments_path, &mut problems)
    } else {
        from_manifest.into_iter().collect()
    };
    if experiments.is_empty() && problems.is_empty() {
        problems.push(format!(
            "{}: {}: no reference result (no <Related role=\"result\"> and no <Experiment>)",
            fmu.display(),
            if has_experiments {
                &experiments_path
            } else {
                &manifest_path
            }
        ));
    }
    if problems.is_empty() {
        Ok(Some(References {
            fmu: fmu.to_owned(),
            experiments,
        }))
    } else {
        Err(problems)
    }
}

/// The elements of the XML file at `path`, or its problem pushed.
fn elements_of(archive: &mut Archive, path: &str, problems: &mut Vec<String>) -> Vec<Element> {
    let fmu = archive.fmu.display().to_string();
    match archive
        .read(path)
        .and_then(|bytes| elements::parse(&bytes).map_err(|e| format!("{fmu}: {path}: {e}")))
    {
        Ok(elements) => elements,
        Err(e) => {
            problems.push(e);
            Vec::new()
        }
    }
}

/// The DefaultExperiment with the manifest's results and inputs.
fn manifest(archive: &mut Archive, path: &str, problems: &mut Vec<String>) -> Option<Experiment> {
    let elements = elements_of(archive, path, problems);
    let root = elements.first()?;
    let fmu = archive.fmu.display().to_string();
    let at = |e: &Element| format!("{fmu}: {path}: {}", e.at(Some("source")));
    if root.name != "fmiReferences" {
        problems.push(format!(
            "{}: {path}: the root element is <{}>, not <fmiReferences>",
            archive.fmu.display(),
            root.name
        ));
        return None;
    }
    let mut experiment = Experiment {
        name: "DefaultExperiment".into(),
        start_time: None,
        stop_time: None,
        step_size: None,
        stimuli: None,
        references: Vec::new(),
        notes: Vec::new(),
    };
    for element in elements.iter().filter(|e| e.name == "Related") {
        let Some(source) = element.attribute("source") else {
            problems.push(format!("{}: no source attribute", at(element)));
            continue;
        };
        let role = element.attribute("role").unwrap_or("");
        let csv = element
            .attribute("type")
            .is_none_or(|t| t == "text/csv" || source.ends_with(".csv"));
        match role {
            "result" if csv => {
                if let Some(table) = reference(archive, source, &at(element), problems) {
                    experiment.references.push(Reference {
                        source: source.to_owned(),
                        table,
                        tolerances: ToleranceOverrides::default(),
                        signals: Vec::new(),
                    });
                }
            }
            "input" | "stimuli" if csv => {
                experiment.stimuli = stimuli(archive, source, &at(element), problems);
            }
            // Sources, documentation, parameter sets: nothing to check them with, but a
            // manifest that names a file the FMU lacks is wrong whatever the file is for.
            _ => {
                if let Err(e) = archive.locate(source) {
                    problems.push(format!("{}: {e}", at(element)));
                }
            }
        }
    }
    (!experiment.references.is_empty()).then_some(experiment)
}

/// The `<Experiment>`s of the experiments file.
fn experiments(archive: &mut Archive, path: &str, problems: &mut Vec<String>) -> Vec<Experiment> {
    let elements = elements_of(archive, path, problems);
    let fmu = archive.fmu.display().to_string();
    let at = |e: &Element, attribute: Option<&str>| format!("{fmu}: {path}: {}", e.at(attribute));
    let mut experiments: Vec<Experiment> = Vec::new();
    let mut experiment_depth = 0;
    // The depth of the `<References>` being read, and whether its table was.
    let mut selecting: Option<(usize, bool)> = None;
    for element in &elements {
        if selecting.is_some_and(|(depth, _)| element.depth <= depth) {
            selecting = None;
        }
        if element.name == "Experiment" {
            experiment_depth = element.depth;
            let mut time = |name: &str| -> Option<f64> {
                let text = element.attribute(name)?;
                match text.trim().parse::<f64>() {
                    Ok(x) if x.is_finite() => Some(x),
                    _ => {
                        problems.push(format!(
                            "{}: {name}=\"{text}\" is not a finite number",
                            at(element, Some("name"))
                        ));
                        None
                    }
                }
            };
            let experiment = Experiment {
                name: element.attribute("name").map_or_else(
                    || format!("experiment {}", experiments.len() + 1),
                    str::to_owned,
                ),
                start_time: time("startTime"),
                stop_time: time("stopTime"),
                step_size: time("stepSize"),
                stimuli: None,
                references: Vec::new(),
                notes: Vec::new(),
            };
            experiments.push(experiment);
            continue;
        }
        let Some(experiment) = experiments.last_mut() else {
            continue;
        };
        if element.depth <= experiment_depth {
            continue;
        }
        if let (Some((_, read)), "Signal") = (selecting, element.name.as_str()) {
            match (element.attribute("name"), experiment.references.last_mut()) {
                (None, _) => problems.push(format!("{}: no name attribute", at(element, None))),
                (Some(name), Some(reference)) if read => reference.signals.push(name.to_owned()),
                _ => {}
            }
            continue;
        }
        let Some(source) = element.attribute("source") else {
            if matches!(
                element.name.as_str(),
                "Stimuli" | "References" | "Parameters"
            ) {
                problems.push(format!("{}: no source attribute", at(element, None)));
            }
            continue;
        };
        let where_ = at(element, Some("source"));
        match element.name.as_str() {
            "Stimuli" => experiment.stimuli = stimuli(archive, source, &where_, problems),
            "References" => {
                let mut tolerances = ToleranceOverrides::default();
                for (attribute, slot) in [
                    ("relativeTolerance", &mut tolerances.relative),
                    ("absoluteTolerance", &mut tolerances.absolute),
                    ("timeTolerance", &mut tolerances.time),
                ] {
                    if let Some(text) = element.attribute(attribute) {
                        match text.trim().parse::<f64>() {
                            Ok(x) => *slot = Some(x),
                            Err(_) => problems
                                .push(format!("{where_}: {attribute}=\"{text}\" is not a number")),
                        }
                    }
                }
                problems.extend(
                    tolerances
                        .problems(["relativeTolerance", "absoluteTolerance", "timeTolerance"])
                        .into_iter()
                        .map(|p| format!("{where_}: {p}")),
                );
                let table = reference(archive, source, &where_, problems);
                selecting = Some((element.depth, table.is_some()));
                if let Some(table) = table {
                    experiment.references.push(Reference {
                        source: source.to_owned(),
                        table,
                        tolerances,
                        signals: Vec::new(),
                    });
                }
            }
            "Parameters" => {
                if let Err(e) = archive.locate(source) {
                    problems.push(format!("{where_}: {e}"));
                } else {
                    experiment.notes.push(format!(
                        "its parameter set {source} is not applied: the FMU runs with its \
                         start values"
                    ));
                }
            }
            _ => {}
        }
    }
    for experiment in &experiments {
        if experiment.references.is_empty() {
            problems.push(format!(
                "{fmu}: {path}: <Experiment name=\"{}\">: no <References>",
                experiment.name
            ));
        }
    }
    experiments
}

fn reference(
    archive: &mut Archive,
    source: &str,
    at: &str,
    problems: &mut Vec<String>,
) -> Option<ReferenceTable> {
    let text = located_text(archive, source, at, problems)?;
    ReferenceTable::parse_csv(&text)
        .map_err(|errors| {
            problems.extend(errors.into_iter().map(|e| format!("{at}: {source}: {e}")));
        })
        .ok()
}

fn stimuli(
    archive: &mut Archive,
    source: &str,
    at: &str,
    problems: &mut Vec<String>,
) -> Option<Stimuli> {
    let text = located_text(archive, source, at, problems)?;
    match InputTable::parse_csv(&text) {
        Ok(table) => Some(Stimuli {
            source: source.to_owned(),
            text,
            table,
        }),
        Err(errors) => {
            problems.extend(errors.into_iter().map(|e| format!("{at}: {source}: {e}")));
            None
        }
    }
}

fn located_text(
    archive: &mut Archive,
    source: &str,
    at: &str,
    problems: &mut Vec<String>,
) -> Option<String> {
    let found = archive
        .locate(source)
        .and_then(|path| archive.text(&path))
        .map_err(|e| problems.push(format!("{at}: {e}")));
    found.ok()
}
