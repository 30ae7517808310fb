//! Resolving a system against its FMUs before anything runs: vector shorthands expanded,
//! every name looked up, every connection type-checked. All problems are reported together,
//! with the names, so a user fixes a scenario in one pass.
use super::loops::{self, Edge, Feedthrough};
use crate::suggest;
use crate::system::{split_path, ParamValue, SystemDescription};
use fmi_import::{word, Fmi3Type, Fmu, VariableInfo, VariableKind};
use model_description::{Causality, Initial, ScalarVariable, Variability};

/// A scalar variable of an instance, by value reference and exchange type.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Port {
    pub instance: usize,
    pub name: String,
    pub value_reference: u32,
    /// Real, Integer (enumerations included), Boolean or String (a Binary too).
    pub kind: VariableKind,
    /// The FMI 3.0 type of a variable that travels as a word (`fmi_import::word`: Float32,
    /// the 8-, 16- and 64-bit and unsigned integers) or is a Binary, each exchanged through
    /// its own buffer and connected only to its own type; `None` for every other.
    pub word: Option<Fmi3Type>,
}

impl Port {
    /// The type's name as the model description writes it.
    pub fn type_name(&self) -> String {
        match self.word {
            Some(kind) => kind.name().to_owned(),
            None => format!("{:?}", self.kind),
        }
    }
}

/// Expands `var` to the scalar names it stands for in `fmu`: itself if it exists, else
/// `var[1]`, `var[2]`, ... while they exist.
pub fn expand(fmu: &Fmu, variable: &str) -> Vec<String> {
    if fmu.variable(variable).is_ok() {
        return vec![variable.to_owned()];
    }
    (1..)
        .map(|i| format!("{variable}[{i}]"))
        .take_while(|name| fmu.variable(name).is_ok())
        .collect()
}

/// The word type of `info` if it travels as a word, or Binary.
fn word_of(info: &VariableInfo) -> Option<Fmi3Type> {
    info.fmi3_type
        .filter(|&kind| word::is_word(kind) || kind == Fmi3Type::Binary)
}

/// The port of a variable.
fn port_of(fmu: &Fmu, instance: usize, name: &str) -> Option<Port> {
    let info = fmu.variable(name).ok()?;
    Some(Port {
        instance,
        name: name.to_owned(),
        value_reference: info.value_reference,
        kind: info.kind.accessed_as(),
        word: word_of(info),
    })
}

impl Port {
    /// A String or a Binary.
    pub fn is_text(&self) -> bool {
        self.kind == VariableKind::String
    }
}

/// Resolves `instance.variable` (vectors allowed) to ports, checking causality with `want`.
pub fn ports(
    system: &SystemDescription,
    fmus: &[Fmu],
    path: &str,
    want: &[Causality],
    problems: &mut Vec<String>,
) -> Vec<Port> {
    let Some((instance_name, variable)) = split_path(path) else {
        problems.push(format!("'{path}' is not of the form instance.variable"));
        return vec![];
    };
    let Some(instance) = system
        .instances
        .iter()
        .position(|i| i.name == instance_name)
    else {
        problems.push(format!(
            "'{path}': no instance named '{instance_name}'{}",
            suggest::hint(
                instance_name,
                system.instances.iter().map(|i| i.name.as_str())
            )
        ));
        return vec![];
    };
    let fmu = &fmus[instance];
    let names = expand(fmu, variable);
    if names.is_empty() {
        problems.push(format!(
            "'{path}': model '{}' has no variable '{variable}' (nor '{variable}[1]'){}",
            fmu.model_name(),
            suggest::hint(variable, suggest::variable_names(fmu.model_description()))
        ));
        return vec![];
    }
    let mut out = Vec::with_capacity(names.len());
    for name in names {
        let info = *fmu.variable(&name).expect("expanded names exist");
        if !want.is_empty() && !want.contains(&info.causality) {
            problems.push(format!(
                "'{instance_name}.{name}' has causality {:?}, expected one of {want:?}",
                info.causality
            ));
            continue;
        }
        out.extend(port_of(fmu, instance, &name));
    }
    out
}

/// Resolves every connection to scalar (source, destination) pairs.
pub fn connections(
    system: &SystemDescription,
    fmus: &[Fmu],
    problems: &mut Vec<String>,
) -> Vec<(Port, Port)> {
    let mut pairs = Vec::new();
    for connection in &super::terminals::expand(system, fmus, problems) {
        let from = ports(
            system,
            fmus,
            &connection.from,
            &[Causality::Output],
            problems,
        );
        let to = ports(system, fmus, &connection.to, &[Causality::Input], problems);
        if from.is_empty() || to.is_empty() {
            continue;
        }
        if from.len() != to.len() {
            problems.push(format!(
                "connection {} -> {}: {} source components but {} destination components",
                connection.from,
                connection.to,
                from.len(),
                to.len()
            ));
            continue;
        }
        for (source, destination) in from.into_iter().zip(to) {
            if source.kind != destination.kind || source.word != destination.word {
                problems.push(format!(
                    "connection {}.{} -> {}.{}: type mismatch ({} -> {})",
                    system.instances[source.instance].name,
                    source.name,
                    system.instances[destination.instance].name,
                    destination.name,
                    source.type_name(),
                    destination.type_name()
                ));
                continue;
            }
            if pairs.iter().any(|(_, d): &(Port, Port)| *d == destination) {
                problems.push(format!(
                    "input {}.{} is connected twice",
                    system.instances[destination.instance].name, destination.name
                ));
                continue;
            }
            pairs.push((source, destination));
        }
    }
    pairs
}

/// The recorded columns: the system's selection, or every output of every instance.
pub fn columns(system: &SystemDescription, fmus: &[Fmu], problems: &mut Vec<String>) -> Vec<Port> {
    match &system.record {
        Some(selection) => {
            let mut out: Vec<Port> = Vec::new();
            for path in selection {
                let found = if is_pattern(path) {
                    pattern_ports(system, fmus, path, problems)
                } else {
                    ports(system, fmus, path, &[], problems)
                };
                // A column named twice (by a name and a pattern) is recorded once.
                for port in found {
                    if !out
                        .iter()
                        .any(|p| p.instance == port.instance && p.name == port.name)
                    {
                        out.push(port);
                    }
                }
            }
            out
        }
        None => {
            let mut out = Vec::new();
            for (instance, fmu) in fmus.iter().enumerate() {
                let first = out.len();
                for variable in fmu.model_description().outputs() {
                    let Some(port) = port_of(fmu, instance, &variable.name) else {
                        continue;
                    };
                    // An alias (the same value reference and type) is one output, recorded
                    // under its first name.
                    if out[first..].iter().any(|p: &Port| {
                        p.value_reference == port.value_reference
                            && p.kind == port.kind
                            && p.word == port.word
                    }) {
                        continue;
                    }
                    out.push(port);
                }
            }
            out
        }
    }
}

fn is_pattern(path: &str) -> bool {
    path.contains(['*', '?'])
}

/// The recordable variables (every type but String) that `instance.variable` matches, where
/// either part may hold `*` (any run of characters, none included) and `?` (one character),
/// in the FMUs' order.
fn pattern_ports(
    system: &SystemDescription,
    fmus: &[Fmu],
    path: &str,
    problems: &mut Vec<String>,
) -> Vec<Port> {
    let Some((instance_pattern, variable_pattern)) = path.split_once('.') else {
        problems.push(format!("'{path}' is not of the form instance.variable"));
        return vec![];
    };
    let mut out = Vec::new();
    for (instance, fmu) in fmus.iter().enumerate() {
        if !glob_matches(instance_pattern, &system.instances[instance].name) {
            continue;
        }
        for variable in fmu.model_description().variables() {
            if !glob_matches(variable_pattern, &variable.name) {
                continue;
            }
            // A pattern records numbers: a String or Binary is recorded by its name.
            if let Some(port) = port_of(fmu, instance, &variable.name).filter(|p| !p.is_text()) {
                out.push(port);
            }
        }
    }
    if out.is_empty() {
        problems.push(format!(
            "'{path}' matches no variable of any instance (in a record pattern `*` stands for \
             any characters and `?` for one; a String or Binary is recorded by its name)"
        ));
    }
    out
}

/// Whether `text` matches `pattern` as a whole: `*` any run of characters, `?` one.
fn glob_matches(pattern: &str, text: &str) -> bool {
    let (p, t): (Vec<char>, Vec<char>) = (pattern.chars().collect(), text.chars().collect());
    let (mut pi, mut ti) = (0, 0);
    // Where the last `*` was and the text position it has absorbed up to: on a mismatch it
    // absorbs one more character, which keeps the search linear in practice and finite.
    let mut star: Option<(usize, usize)> = None;
    while ti < t.len() {
        if pi < p.len() && (p[pi] == '?' || p[pi] == t[ti]) {
            pi += 1;
            ti += 1;
        } else if pi < p.len() && p[pi] == '*' {
            star = Some((pi, ti));
            pi += 1;
        } else if let Some((sp, st)) = star {
            pi = sp + 1;
            ti = st + 1;
            star = Some((sp, st + 1));
        } else {
            return false;
        }
    }
    p[pi..].iter().all(|&c| c == '*')
}

/// A parameter or start value the master would set on `instance`: the variable exists, the
/// value has its type, and it is not an input a connection overwrites at every step.
/// `connections` are the resolved scalar (`from`, `to`) paths.
pub fn parameter_problem(
    system: &SystemDescription,
    fmus: &[Fmu],
    connections: &[(String, String)],
    instance: usize,
    variable: &str,
    value: &ParamValue,
) -> Option<String> {
    let name = &system.instances[instance].name;
    let fmu = &fmus[instance];
    let info = match fmu.variable(variable) {
        Ok(info) => info,
        Err(error) => {
            let description = fmu.model_description();
            let elements = description
                .variables()
                .filter(|v| {
                    v.name
                        .strip_prefix(variable)
                        .is_some_and(|rest| rest.starts_with('['))
                })
                .count();
            if elements > 0 {
                return Some(format!(
                    "instance '{name}': '{variable}' is a vector of {elements}: set its \
                     elements, e.g. {name}.{variable}[1]"
                ));
            }
            // Only what may be set is a useful suggestion (not the output of a similar name).
            let settable = description
                .variables()
                .filter(|v| settable_problem(v).is_none())
                .map(|v| v.name.as_str());
            return Some(format!(
                "instance '{name}': cannot set '{variable}': {error}{}",
                suggest::hint(variable, settable)
            ));
        }
    };
    if let Some(problem) = fmi3_value_problem(name, variable, info, value) {
        return Some(problem);
    }
    let structural = fmu.structural_parameters().contains(&variable);
    let fits = info.is_word()
        || info.fmi3_type == Some(Fmi3Type::Binary)
        || match (info.kind.accessed_as(), value) {
            (VariableKind::Real, ParamValue::Real(_) | ParamValue::Integer(_)) => true,
            (VariableKind::Integer, ParamValue::Integer(i)) => i32::try_from(*i).is_ok(),
            (VariableKind::Boolean, ParamValue::Boolean(_)) => true,
            (VariableKind::String, ParamValue::String(_)) => true,
            _ => false,
        };
    if !fits {
        let given = match value {
            ParamValue::Real(x) => format!("the Real {x}"),
            ParamValue::Integer(i) => format!("the Integer {i}"),
            ParamValue::Boolean(b) => format!("the Boolean {b}"),
            ParamValue::String(s) => format!("the String \"{s}\""),
        };
        let range = if info.kind.accessed_as() == VariableKind::Integer {
            " (a 32-bit integer)"
        } else {
            ""
        };
        return Some(format!(
            "instance '{name}': parameter '{variable}' is {:?}{range}, but the value given is {given}",
            info.kind
        ));
    }
    if let Some(declared) = fmu.model_description().variable(variable) {
        let settable = if structural {
            None
        } else {
            settable_problem(declared)
        };
        if let Some(problem) = settable.or_else(|| range_problem(declared, value)) {
            return Some(format!("instance '{name}': {problem}"));
        }
    }
    let path = format!("{name}.{variable}");
    if let Some((from, _)) = connections.iter().find(|(_, to)| *to == path) {
        return Some(format!(
            "instance '{name}': '{variable}' is an input connected from '{from}'; a value set \
             on it would be overwritten by the connection at every step"
        ));
    }
    None
}

/// A value given for an FMI 3.0 variable of a word type or Binary that its type cannot hold
/// (300 for a UInt8, 1.5 for an Int16, text that is not hex for a Binary), naming the
/// instance, the variable, its type and the value. A UInt64 above the largest TOML integer
/// is given as a string ("18446744073709551615"), a Binary as hex text.
fn fmi3_value_problem(
    instance: &str,
    variable: &str,
    info: &VariableInfo,
    value: &ParamValue,
) -> Option<String> {
    let kind = info.fmi3_type?;
    let problem = if word::is_word(kind) {
        parameter_word(kind, value).err()?
    } else if kind == Fmi3Type::Binary {
        match value {
            ParamValue::String(text) => word::from_hex(text).err()?,
            other => format!("{} is not hex text", given(other)),
        }
    } else {
        return None;
    };
    Some(format!(
        "instance '{instance}': parameter '{variable}' is {}, and the value given cannot be \
         one: {problem}",
        kind.name()
    ))
}

/// The word of a scenario value for a variable of the word type `kind`.
pub(crate) fn parameter_word(kind: Fmi3Type, value: &ParamValue) -> Result<u64, String> {
    match (kind, value) {
        (Fmi3Type::Float32, ParamValue::Real(x)) => {
            word::from_float32(*x).ok_or_else(|| format!("{x} is beyond the Float32 range"))
        }
        (Fmi3Type::Float32, ParamValue::Integer(i)) => {
            word::from_float32(*i as f64).ok_or_else(|| format!("{i} is beyond the Float32 range"))
        }
        (_, ParamValue::Integer(i)) => word::from_integer(kind, i128::from(*i))
            .ok_or_else(|| word::out_of_range(kind, &i.to_string())),
        (_, ParamValue::String(text)) => word::parse(kind, text),
        (_, other) => Err(format!("{} is not a {}", given(other), kind.name())),
    }
}

fn given(value: &ParamValue) -> String {
    match value {
        ParamValue::Real(x) => format!("the Real {x}"),
        ParamValue::Integer(i) => format!("the Integer {i}"),
        ParamValue::Boolean(b) => format!("the Boolean {b}"),
        ParamValue::String(s) => format!("the String \"{s}\""),
    }
}

/// Why the master may not set `variable` before initialization, if it may not: FMI 2.0
/// (3.2.3 and 4.2.4) allows a set there only for a variable that is not a constant and has
/// `initial` exact or approx, and for inputs; the FMU would refuse the rest, late.
fn settable_problem(variable: &ScalarVariable) -> Option<String> {
    let name = &variable.name;
    let causality = variable.causality_or_default();
    if causality == Causality::Independent {
        return Some(format!(
            "'{name}' is the independent variable (time): the master advances it, it cannot \
             be set"
        ));
    }
    if variable.variability_or_default() == Variability::Constant {
        return Some(format!("'{name}' is a constant: it cannot be set"));
    }
    if causality == Causality::Input {
        return None;
    }
    match variable.initial_or_default() {
        Some(Initial::Calculated) | None => Some(format!(
            "'{name}' is {} with initial=\"calculated\": the FMU computes it, so it cannot be \
             set; set a parameter or an input instead",
            match causality {
                Causality::Output => "an output",
                Causality::CalculatedParameter => "a calculated parameter",
                _ => "a local variable",
            }
        )),
        Some(Initial::Exact | Initial::Approx) => None,
    }
}

/// A value outside the variable's declared `min`/`max`, naming both.
fn range_problem(variable: &ScalarVariable, value: &ParamValue) -> Option<String> {
    let (min, max, given) = match value {
        ParamValue::Real(x) => real_range(variable).map(|(lo, hi)| (lo, hi, *x))?,
        ParamValue::Integer(i) => {
            if let Some((lo, hi)) = integer_range(variable) {
                (lo.map(f64::from), hi.map(f64::from), *i as f64)
            } else {
                real_range(variable).map(|(lo, hi)| (lo, hi, *i as f64))?
            }
        }
        _ => return None,
    };
    let name = &variable.name;
    let value = match value {
        ParamValue::Integer(i) => i.to_string(),
        _ => number(given),
    };
    let range = match (min, max) {
        (Some(lo), Some(hi)) => format!(" (range [{}, {}])", number(lo), number(hi)),
        _ => String::new(),
    };
    match (min, max) {
        (Some(lo), _) if given < lo => Some(format!(
            "'{name}' = {value} is below its declared min {}{range}",
            number(lo)
        )),
        (_, Some(hi)) if given > hi => Some(format!(
            "'{name}' = {value} is above its declared max {}{range}",
            number(hi)
        )),
        _ => None,
    }
}

/// A bound as the model description writes it: integers without a fraction, others in the
/// shortest form that reads back exactly (`5e-324`, not 324 digits).
fn number(x: f64) -> String {
    if x.fract() == 0.0 && x.abs() < 1e15 {
        format!("{}", x as i64)
    } else {
        format!("{x:?}")
    }
}

fn real_range(variable: &ScalarVariable) -> Option<(Option<f64>, Option<f64>)> {
    variable.real.as_ref().map(|r| (r.min, r.max))
}

fn integer_range(variable: &ScalarVariable) -> Option<(Option<i32>, Option<i32>)> {
    if let Some(integer) = &variable.integer {
        return Some((integer.min, integer.max));
    }
    variable.enumeration.as_ref().map(|e| (e.min, e.max))
}

/// The SSD's declared connectors against the FMUs, and the connections against the declared
/// connectors: both must agree, or some other tool reading the same SSD would wire a
/// different system.
pub fn declared_connectors(system: &SystemDescription, fmus: &[Fmu], problems: &mut Vec<String>) {
    for (i, instance) in system.instances.iter().enumerate() {
        let Some(declared) = &instance.connectors else {
            continue;
        };
        let fmu = &fmus[i];
        for connector in declared {
            if let Some(found) =
                crate::system::ssp2::connector_problems(fmu, &instance.name, connector)
            {
                problems.extend(found);
                continue;
            }
            let info = match fmu.variable(&connector.name) {
                Ok(info) => info,
                Err(_) => {
                    problems.push(format!(
                        "component '{}': declared connector '{}' is not a variable of model \
                         '{}'{}",
                        instance.name,
                        connector.name,
                        fmu.model_name(),
                        suggest::hint(
                            &connector.name,
                            suggest::variable_names(fmu.model_description())
                        )
                    ));
                    continue;
                }
            };
            if connector.causality().is_some_and(|c| c != info.causality) {
                problems.push(format!(
                    "component '{}': connector '{}' is declared {} but the FMU's variable has \
                     causality {:?}",
                    instance.name, connector.name, connector.kind, info.causality
                ));
            }
            if let Some(type_name) = &connector.type_name {
                // An FMI 3.0 variable may be declared by its own type or its FMI 2.0
                // counterpart (an SSP 1.0 connector knows Real, Integer, ... only).
                if *type_name != format!("{:?}", info.kind) && *type_name != info.type_name() {
                    problems.push(format!(
                        "component '{}': connector '{}' is declared {type_name} but the FMU's \
                         variable is {}",
                        instance.name,
                        connector.name,
                        info.type_name()
                    ));
                }
            }
        }
    }
    for connection in &system.connections {
        for (end, want) in [(&connection.from, "output"), (&connection.to, "input")] {
            let Some((instance_name, variable)) = split_path(end) else {
                continue;
            };
            let Some(declared) = system
                .instance(instance_name)
                .and_then(|i| i.connectors.as_ref())
            else {
                continue;
            };
            match declared.iter().find(|c| c.name == variable) {
                None => problems.push(format!(
                    "connection {} -> {}: '{variable}' is not a declared connector of \
                     component '{instance_name}'{}",
                    connection.from,
                    connection.to,
                    suggest::hint(variable, declared.iter().map(|c| c.name.as_str()))
                )),
                Some(c) if c.kind != want && c.kind != "inout" => problems.push(format!(
                    "connection {} -> {}: connector '{instance_name}.{variable}' is declared \
                     {}, but the {} of a connection must be an {want}",
                    connection.from,
                    connection.to,
                    c.kind,
                    if want == "output" { "start" } else { "end" }
                )),
                Some(_) => {}
            }
        }
    }
}

/// Refuses an algebraic loop through the resolved connections whose every hop is declared,
/// naming it; a loop that exists only through outputs that declare no dependencies (FMI 2.0's
/// worst case, "depends on every input") is a warning on stderr, and the exchange order
/// breaks it. Under Jacobi ordering there is no loop to solve: every input takes the
/// outputs of the communication point before, so every connection is one step of delay.
pub fn algebraic_loop(
    system: &SystemDescription,
    fmus: &[Fmu],
    pairs: &[(Port, Port)],
    problems: &mut Vec<String>,
) {
    if system.ordering == crate::system::Ordering::Jacobi {
        return;
    }
    let feedthrough: Vec<Feedthrough> = fmus
        .iter()
        .map(|fmu| Feedthrough::from_description(fmu.model_description()))
        .collect();
    let edges: Vec<Edge> = pairs
        .iter()
        .map(|(source, destination)| Edge {
            from_instance: &system.instances[source.instance].name,
            from_variable: &source.name,
            to_instance: &system.instances[destination.instance].name,
            to_variable: &destination.name,
        })
        .collect();
    let lookup = |name: &str| {
        system
            .instances
            .iter()
            .position(|i| i.name == name)
            .map(|i| &feedthrough[i])
    };
    if let Some(cycle) = loops::find_loop(&edges, &lookup, true) {
        problems.push(format!(
            "algebraic loop: {} ('->' a connection, '~>' an output that depends on the input \
             before it, as the FMU's ModelStructure declares; a fixed-step master cannot solve \
             it: break it with an FMU whose output does not depend on that input)",
            loops::describe(&edges, &cycle)
        ));
    } else if let Some(cycle) = loops::find_loop(&edges, &lookup, false) {
        eprintln!(
            "harness: warning: possible algebraic loop {}: an output on it declares no \
             dependencies in ModelStructure, which FMI reads as 'depends on every input'; \
             running with the exchange order breaking it",
            loops::describe(&edges, &cycle)
        );
    }
}

#[cfg(test)]
mod tests {
    use super::glob_matches;

    #[test]
    fn a_record_pattern_matches_whole_names_with_star_and_question_mark() {
        let names = [
            "touchdown",
            "touchdown_time",
            "touchdown_v_nue[1]",
            "r_nue[2]",
            "tipped_over",
        ];
        let matched = |pattern: &str| -> Vec<&str> {
            names
                .iter()
                .copied()
                .filter(|n| glob_matches(pattern, n))
                .collect()
        };
        assert_eq!(
            matched("touchdown*"),
            ["touchdown", "touchdown_time", "touchdown_v_nue[1]"]
        );
        assert_eq!(matched("*_nue[?]"), ["touchdown_v_nue[1]", "r_nue[2]"]);
        assert_eq!(matched("*"), names);
        assert_eq!(matched("t*d*e"), ["touchdown_time"]);
        // Whole names only: no pattern character means equality.
        assert_eq!(matched("touchdown"), ["touchdown"]);
        assert!(matched("touch").is_empty());
        assert!(matched("?").is_empty());
        assert!(glob_matches("a**b", "ab") && glob_matches("**", ""));
        assert!(!glob_matches("a*b", "abc"));
    }
}
