//! The attitude laws a GNC FMU offers, read from the FMU: the items of the enumeration type
//! of its `control_law` parameter. The harness keeps no list of its own, so a law added to
//! LanderGnc (or offered by a user's GNC FMU with the same parameter) is flown, compared,
//! campaigned and plotted without a change here. Only the paper's two laws are named, because
//! the paper compares them.
//!
//! `control_law` may be an Enumeration variable, or an Integer beside an enumeration type
//! named [`Laws::TYPE`] (LanderGnc exchanges it as an Integer: some masters ignore FMI 2.0
//! Enumeration variables).
use cosim::supervise::Runner;
use cosim::system::{ParamValue, SystemDescription};
use model_description::{ModelDescription, VariableKind};
use std::fmt;
use std::path::Path;
use std::sync::Mutex;

/// The parameter that selects the law.
pub const PARAMETER: &str = "control_law";

/// A control law, by the name of its item in the GNC FMU's enumeration.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Law(&'static str);

impl Law {
    /// The classical quaternion PD law the paper improves on.
    pub const COUPLED: Law = Law("coupled");
    /// The paper's decoupled thrust-axis law.
    pub const DECOUPLED: Law = Law("decoupled");

    pub const fn new(name: &'static str) -> Law {
        Law(name)
    }

    /// A law named at run time (on a command line, in a manifest); each distinct name is
    /// kept once for the life of the process.
    pub fn named(name: &str) -> Law {
        static NAMES: Mutex<Vec<&'static str>> = Mutex::new(Vec::new());
        let mut names = NAMES
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner());
        if let Some(kept) = names.iter().find(|kept| **kept == name) {
            return Law(kept);
        }
        let kept: &'static str = Box::leak(name.to_owned().into_boxed_str());
        names.push(kept);
        Law(kept)
    }

    pub fn name(self) -> &'static str {
        self.0
    }
}

impl fmt::Display for Law {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.0)
    }
}

impl serde::Serialize for Law {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_str(self.0)
    }
}

/// The laws one GNC FMU declares, in the order of its items.
#[derive(Debug, Clone, PartialEq)]
pub struct Laws {
    model: String,
    items: Vec<(Law, i32)>,
}

impl Laws {
    /// The enumeration type beside an Integer `control_law`.
    pub const TYPE: &'static str = "ControlLaw";

    /// The laws of a GNC model description.
    pub fn of(description: &ModelDescription) -> Result<Laws, String> {
        let model = &description.model_name;
        let variable = description
            .variable(PARAMETER)
            .ok_or_else(|| format!("model '{model}' has no parameter '{PARAMETER}'"))?;
        let type_name = match variable.kind() {
            Some(VariableKind::Enumeration) => variable.declared_type().unwrap_or(Self::TYPE),
            Some(VariableKind::Integer) => Self::TYPE,
            _ => {
                return Err(format!(
                    "model '{model}': '{PARAMETER}' is neither an Enumeration nor an Integer"
                ))
            }
        };
        let items = description
            .simple_type(type_name)
            .and_then(|t| t.enumeration.as_ref())
            .map(|e| &e.items)
            .filter(|items| !items.is_empty())
            .ok_or_else(|| {
                format!(
                    "model '{model}' declares no enumeration type '{type_name}' naming the \
                     values of '{PARAMETER}'"
                )
            })?;
        Ok(Laws {
            model: model.clone(),
            items: items
                .iter()
                .map(|item| (Law::named(&item.name), item.value))
                .collect(),
        })
    }

    /// The laws of the FMU that instance `instance` of `system` loads from `fmu_dir`: its
    /// model description alone is read, no FMU code runs.
    pub fn of_instance(
        system: &SystemDescription,
        instance: &str,
        fmu_dir: &Path,
    ) -> anyhow::Result<Laws> {
        let found = system.instance(instance).ok_or_else(|| {
            anyhow::anyhow!("scenario '{}' has no instance '{instance}'", system.name)
        })?;
        let path = match &system.package {
            Some(package) => package.0.path().join("resources").join(&found.fmu),
            None => cosim::master::fmu_path(fmu_dir, &found.fmu),
        };
        let (_, description) = fmi_import::read_description(&path)
            .map_err(|e| anyhow::anyhow!("reading {}: {e}", path.display()))?;
        Laws::of(&description).map_err(anyhow::Error::msg)
    }

    /// The laws of instance `instance` of a loaded simulation.
    pub fn of_runner(simulation: &Runner, instance: &str) -> anyhow::Result<Laws> {
        let index = simulation
            .system()
            .instances
            .iter()
            .position(|i| i.name == instance)
            .ok_or_else(|| {
                anyhow::anyhow!(
                    "scenario '{}' has no instance '{instance}'",
                    simulation.system().name
                )
            })?;
        Laws::of(simulation.description(index).1).map_err(anyhow::Error::msg)
    }

    /// Every law, in the order of the items.
    pub fn all(&self) -> Vec<Law> {
        self.items.iter().map(|(law, _)| *law).collect()
    }

    /// The value of `control_law` that selects `law`.
    pub fn value(&self, law: Law) -> Result<i32, String> {
        self.items
            .iter()
            .find(|(item, _)| *item == law)
            .map(|(_, value)| *value)
            .ok_or_else(|| self.unknown(law.name()))
    }

    /// [`Laws::value`] as the parameter a system sets.
    pub fn parameter(&self, law: Law) -> Result<ParamValue, String> {
        self.value(law).map(|v| ParamValue::Integer(i64::from(v)))
    }

    /// The law `control_law = value` selects, `None` if no item has that value.
    pub fn of_value(&self, value: i64) -> Option<Law> {
        self.items
            .iter()
            .find(|(_, v)| i64::from(*v) == value)
            .map(|(law, _)| *law)
    }

    /// The laws `names` name, every unknown name reported at once.
    pub fn parse<S: AsRef<str>>(&self, names: &[S]) -> Result<Vec<Law>, String> {
        let mut laws = Vec::new();
        let mut problems = Vec::new();
        for name in names {
            let law = Law::named(name.as_ref());
            match self.value(law) {
                Ok(_) => laws.push(law),
                Err(problem) => problems.push(problem),
            }
        }
        if problems.is_empty() {
            Ok(laws)
        } else {
            Err(problems.join("\n"))
        }
    }

    /// Every law of `laws` is one of these, each unknown one reported at once.
    pub fn check(&self, laws: &[Law]) -> Result<(), String> {
        let names: Vec<&str> = laws.iter().map(|l| l.name()).collect();
        self.parse(&names).map(|_| ())
    }

    fn unknown(&self, name: &str) -> String {
        let names: Vec<String> = self
            .items
            .iter()
            .map(|(law, value)| format!("{law} ({value})"))
            .collect();
        format!(
            "control law '{name}' is not one of model '{}''s: {}",
            self.model,
            names.join(", ")
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn gnc() -> ModelDescription {
        let xml = std::fs::read_to_string(
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../fmu-gnc/modelDescription.xml"),
        )
        .unwrap();
        ModelDescription::from_xml(&xml).unwrap()
    }

    #[test]
    fn the_laws_are_the_items_landergnc_declares() {
        let laws = Laws::of(&gnc()).unwrap();
        let names: Vec<&str> = laws.all().iter().map(|l| l.name()).collect();
        assert_eq!(names[..3], ["coupled", "decoupled", "reduced"]);
        assert_eq!(laws.value(Law::COUPLED), Ok(1));
        assert_eq!(laws.value(Law::DECOUPLED), Ok(2));
        assert_eq!(laws.of_value(3), Some(Law::new("reduced")));
        // One past the last item is none, however many laws the FMU declares.
        let last = laws
            .all()
            .iter()
            .map(|&l| laws.value(l).unwrap())
            .max()
            .unwrap();
        assert_eq!(laws.of_value(i64::from(last) + 1), None);
    }

    #[test]
    fn a_law_the_fmu_does_not_declare_is_refused_with_every_other_unknown_name() {
        let laws = Laws::of(&gnc()).unwrap();
        let problem = laws.parse(&["decoupled", "lqr", "pid"]).unwrap_err();
        assert_eq!(problem.lines().count(), 2, "{problem}");
        assert!(
            problem.contains("'lqr'") && problem.contains("'pid'"),
            "{problem}"
        );
        assert!(
            problem.contains("coupled (1), decoupled (2), reduced (3)"),
            "{problem}"
        );
        assert_eq!(laws.parse(&["reduced", "decoupled"]).unwrap().len(), 2);
    }

    #[test]
    fn a_fourth_law_in_the_fmu_is_a_law_here() {
        let xml = std::fs::read_to_string(
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../fmu-gnc/modelDescription.xml"),
        )
        .unwrap();
        let shipped = Laws::of(&ModelDescription::from_xml(&xml).unwrap()).unwrap();
        let next = shipped
            .all()
            .iter()
            .map(|&l| shipped.value(l).unwrap())
            .max()
            .unwrap()
            + 1;
        let (head, tail) = xml.split_once(r#"<Item name="reduced""#).unwrap();
        let xml = format!(
            r#"{head}<Item name="lqr" value="{next}" description="one more law"/><Item name="reduced"{tail}"#
        );
        let laws = Laws::of(&ModelDescription::from_xml(&xml).unwrap()).unwrap();
        assert_eq!(laws.value(Law::named("lqr")), Ok(next));
        assert_eq!(laws.all().len(), shipped.all().len() + 1);
    }

    #[test]
    fn a_model_without_the_enumeration_type_is_refused_by_name() {
        let xml = gnc_without_type();
        let problem = Laws::of(&ModelDescription::from_xml(&xml).unwrap()).unwrap_err();
        assert!(
            problem.contains("no enumeration type 'ControlLaw'"),
            "{problem}"
        );
    }

    fn gnc_without_type() -> String {
        let xml = std::fs::read_to_string(
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../fmu-gnc/modelDescription.xml"),
        )
        .unwrap();
        let start = xml.find("<TypeDefinitions>").unwrap();
        let end = xml.find("</TypeDefinitions>").unwrap() + "</TypeDefinitions>".len();
        format!("{}{}", &xml[..start], &xml[end..])
    }
}
