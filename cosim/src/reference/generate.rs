//! Writing an FMU's FMI-LS-REF files from runs of the FMU itself, so that the references a
//! package carries are those of the code it was built from: the FMU's inputs taken from a
//! flight of a system that connects it (what its neighbours sent it there) or, when no
//! system does, a unit step on each continuous Real input; the FMU then run alone over its
//! DefaultExperiment with those inputs; both tables thinned to about [`ROWS`] rows.
//!
//! Thinned inputs are held, not interpolated: each sample holds from the middle of the
//! interval before it to the middle of the one after, with a ramp half a step long between
//! two communication points. No communication point falls inside a ramp, so every tool that
//! interpolates linearly (fmpy, fmusim, the harness) sets only values the flight had: a
//! unit quaternion stays one, which an interpolation between two of its samples is not.
//! And the inputs hold still around each row of the reference (rows at the samples' times):
//! a master that records a step's outputs before it sets the next inputs (fmpy) and one that
//! records after (the harness) read the same outputs there, direct feedthrough included.
use super::archive::{EXPERIMENTS, MANIFEST};
use super::tube::Tolerances;
use crate::master::{MasterError, Trajectory};
use crate::supervise::Runner;
use crate::system::{single, InputTable, SystemDescription};
use model_description::{Causality, Variability, VariableKind};
use std::path::Path;

/// The rows a reference or stimuli table keeps at most (plus the last one), every one of
/// them in each FMU of both FMI versions: the tube is drawn on 1000 points, and half as
/// many keep a lander FMU's tables under a megabyte.
pub const ROWS: usize = 500;

/// The files of one FMU's LS-REF folder, by file name.
#[derive(Debug, Clone, PartialEq)]
pub struct Files {
    pub files: Vec<(String, String)>,
}

/// A flight of `system`, every output recorded.
pub fn fly(system: SystemDescription, fmu_dir: &Path) -> Result<Trajectory, MasterError> {
    let mut runner = Runner::new(system, fmu_dir)?;
    let mut trajectory = Trajectory {
        names: runner.column_names().to_vec(),
        times: Vec::new(),
        values: Vec::new(),
    };
    runner.run(&mut trajectory)?;
    Ok(trajectory)
}

/// What `flight` of `system` sent the inputs of its instance `instance`, one column per
/// input element, named as the FMU names them (`r_nue[1]`).
pub fn inputs_of(system: &SystemDescription, instance: &str, flight: &Trajectory) -> InputTable {
    let mut names = Vec::new();
    let mut columns = Vec::new();
    for connection in &system.connections {
        let Some(input) = connection
            .to
            .strip_prefix(instance)
            .and_then(|r| r.strip_prefix('.'))
        else {
            continue;
        };
        for (j, column) in flight.names.iter().enumerate() {
            // The source itself, or one element of it when it is a vector.
            let Some(rest) = column.strip_prefix(&connection.from) else {
                continue;
            };
            if rest.is_empty() || rest.starts_with('[') {
                names.push(format!("{input}{rest}"));
                columns.push(j);
            }
        }
    }
    let width = flight.names.len();
    InputTable {
        names,
        times: flight.times.clone(),
        rows: flight
            .values
            .chunks(width.max(1))
            .map(|row| columns.iter().map(|&j| row[j]).collect())
            .collect(),
    }
}

/// A unit step on every continuous Real input of the FMU at `fmu`, at an odd communication
/// point near the middle of its DefaultExperiment (off the reference's rows, see the
/// module's note), as CSV; `None` when it has none.
pub fn step_csv(fmu: &Path, start: f64, stop: f64, step: f64) -> Result<Option<String>, String> {
    let (_, description) = fmi_import::read_description(fmu).map_err(|e| e.to_string())?;
    let names: Vec<String> = description
        .variables()
        .filter(|v| {
            v.causality == Some(Causality::Input)
                && v.variability.unwrap_or(Variability::Continuous) == Variability::Continuous
                && v.kind() == Some(VariableKind::Real)
        })
        .map(|v| v.name.clone())
        .collect();
    if names.is_empty() {
        return Ok(None);
    }
    let steps = ((stop - start) / step).round() as u64;
    let at = start + ((steps / 2) | 1) as f64 * step;
    let zeros = vec![0.0; names.len()];
    let ones = vec![1.0; names.len()];
    let mut text = header(&names);
    push_row(&mut text, start, &zeros);
    push_row(&mut text, at - step / 2.0, &zeros);
    push_row(&mut text, at, &ones);
    push_row(&mut text, stop, &ones);
    Ok(Some(text))
}

/// Every how many communication points of an experiment of `steps` steps a table keeps a
/// row: about [`ROWS`] of them, and a divisor of `steps` where one up to twice the least
/// stride is, so that the rows are evenly spaced to the last: a checker can then lay its
/// band's points on them (fmpy's `num` of `2 (rows - 1) + 1`).
pub fn stride(steps: usize) -> usize {
    let least = steps.div_ceil(ROWS).max(1);
    (least..=2 * least)
        .find(|&k| steps.is_multiple_of(k))
        .unwrap_or(least)
}

/// The number of communication steps of an experiment.
fn steps_of(start: f64, stop: f64, step: f64) -> usize {
    ((stop - start) / step).round().max(1.0) as usize
}

/// Every `k`-th of `len` rows and the last one.
fn thinned(len: usize, k: usize) -> Vec<usize> {
    let mut keep: Vec<usize> = (0..len).step_by(k.max(1)).collect();
    if len > 0 && keep.last() != Some(&(len - 1)) {
        keep.push(len - 1);
    }
    keep
}

/// A CSV row: numbers in the shortest form that reads back to the same bits.
fn push_row(text: &mut String, time: f64, values: &[f64]) {
    text.push_str(&time.to_string());
    for value in values {
        text.push(',');
        text.push_str(&value.to_string());
    }
    text.push('\n');
}

fn header(names: &[String]) -> String {
    let mut text = String::from("time");
    for name in names {
        text.push(',');
        text.push_str(name);
    }
    text.push('\n');
    text
}

/// The CSV of `stimuli` over the experiment [`start`, `stop`] in steps of `step`: the
/// samples at every [`stride`]-th communication point (the rows the reference will have),
/// each held from the middle of the interval before it to the middle of the one after (see
/// the module's note). What the FMU is then run with.
pub fn stimuli_csv(stimuli: &InputTable, start: f64, stop: f64, step: f64) -> String {
    let mut text = header(&stimuli.names);
    let steps = steps_of(start, stop, step);
    let k = stride(steps);
    // The row of the table nearest each kept communication point.
    let keep: Vec<(f64, usize)> = thinned(steps + 1, k)
        .into_iter()
        .map(|i| start + i as f64 * step)
        .filter_map(|t| {
            let after = stimuli.times.partition_point(|&x| x < t);
            let nearest = [after.saturating_sub(1), after]
                .into_iter()
                .filter(|&j| j < stimuli.times.len())
                .min_by(|&a, &b| {
                    (stimuli.times[a] - t)
                        .abs()
                        .total_cmp(&(stimuli.times[b] - t).abs())
                })?;
            Some((t, nearest))
        })
        .collect();
    let Some(&(first_time, first)) = keep.first() else {
        return text;
    };
    push_row(&mut text, first_time, &stimuli.rows[first]);
    let mut written = first_time;
    for pair in keep.windows(2) {
        let ((before, row_before), (after, row_after)) = (pair[0], pair[1]);
        let steps = ((after - before) / step).round().max(1.0) as u64;
        let change = before + (steps / 2).max(1) as f64 * step;
        if change - step / 2.0 > written {
            push_row(&mut text, change - step / 2.0, &stimuli.rows[row_before]);
        }
        push_row(&mut text, change, &stimuli.rows[row_after]);
        written = change;
    }
    let &(last_time, last) = keep.last().expect("not empty");
    if last_time > written {
        push_row(&mut text, last_time, &stimuli.rows[last]);
    }
    text
}

/// Runs the FMU at `fmu` alone over its DefaultExperiment with the CSV `stimuli_text` (of
/// [`stimuli_csv`] or [`step_csv`]: the reference is of the inputs the FMU carries), and
/// returns its LS-REF files: the manifest, the experiments file, `<model>_out.csv` and
/// `<model>_in.csv`.
pub fn references(
    fmu: &Path,
    model: &str,
    stimuli_text: Option<String>,
    tolerances: &Tolerances,
) -> Result<Files, String> {
    let mut system = single::of_fmu(fmu).map_err(|e| e.to_string())?;
    let instance = system.instances[0].name.clone();
    if let Some(text) = &stimuli_text {
        let mut table = InputTable::parse_csv(text).map_err(|p| p.join("\n"))?;
        table.names = table
            .names
            .iter()
            .map(|n| format!("{instance}.{n}"))
            .collect();
        system.inputs = Some(table);
    }
    let (start, stop, step) = (system.start_time, system.stop_time, system.step_size);
    let run = fly(system, Path::new("")).map_err(|e| format!("{e:#}"))?;
    let prefix = format!("{instance}.");
    let names: Vec<String> = run
        .names
        .iter()
        .map(|n| n.strip_prefix(&prefix).unwrap_or(n).to_owned())
        .collect();
    let width = run.names.len();
    let mut out = header(&names);
    // The experiment's stride, not one of the run's length: a run that ended early keeps
    // its rows where the stimuli hold still.
    for k in thinned(run.times.len(), stride(steps_of(start, stop, step))) {
        push_row(
            &mut out,
            run.times[k],
            &run.values[k * width..(k + 1) * width],
        );
    }
    let out_name = format!("{model}_out.csv");
    let in_name = format!("{model}_in.csv");
    let mut manifest = format!(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n\
         <fmiReferences\n    xmlns:fmi-ls=\"http://fmi-standard.org/fmi-ls-manifest\"\n    \
         fmi-ls:fmi-ls-name=\"org.fmi-standard.fmi-ls-ref\"\n    \
         fmi-ls:fmi-ls-version=\"1.0.0-alpha.1\">\n    \
         <Related type=\"text/csv\" source=\"{out_name}\" role=\"result\" \
         description=\"Output of the default experiment\"/>\n"
    );
    let mut experiment = format!(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<Experiments>\n  \
         <Experiment name=\"DefaultExperiment\" startTime=\"{start}\" stopTime=\"{stop}\" \
         stepSize=\"{step}\">\n"
    );
    if stimuli_text.is_some() {
        manifest.push_str(&format!(
            "    <Related type=\"text/csv\" source=\"{in_name}\" role=\"input\" \
             description=\"Input signals of the default experiment\"/>\n"
        ));
        experiment.push_str(&format!("    <Stimuli source=\"{in_name}\"/>\n"));
    }
    manifest.push_str("</fmiReferences>\n");
    experiment.push_str(&format!(
        "    <References source=\"{out_name}\" relativeTolerance=\"{}\" \
         absoluteTolerance=\"{}\" timeTolerance=\"{}\"/>\n  </Experiment>\n</Experiments>\n",
        tolerances.relative, tolerances.absolute, tolerances.time
    ));
    let mut files = vec![
        (MANIFEST.to_owned(), manifest),
        (EXPERIMENTS.to_owned(), experiment),
        (out_name, out),
    ];
    if let Some(text) = stimuli_text {
        files.push((in_name, text));
    }
    Ok(Files { files })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_thinned_table_keeps_its_first_and_last_rows_and_at_most_rows_more() {
        let times: Vec<f64> = (0..=17200).map(|k| k as f64 * 0.01).collect();
        let keep = thinned(times.len(), stride(17200));
        assert_eq!(keep[0], 0);
        assert_eq!(*keep.last().unwrap(), 17200);
        assert!(keep.len() <= ROWS + 1, "{}", keep.len());
        // 17200 intervals in 430 of 40: evenly spaced to the last row.
        assert_eq!(keep.len(), 431);
        assert!(keep.windows(2).all(|w| w[1] - w[0] == 40));
        assert_eq!(thinned(2, stride(1)), [0, 1]);
        assert_eq!(thinned(5, 3), [0, 3, 4]);
    }

    #[test]
    fn a_connected_vector_input_gets_a_column_per_element() {
        let system = crate::system::toml_format::parse(
            r#"name = "s"
stop_time = 1.0
[[instance]]
name = "gnc"
fmu = "G.fmu"
[[instance]]
name = "plant"
fmu = "P.fmu"
[[connection]]
from = "plant.r"
to = "gnc.r_in"
[[connection]]
from = "gnc.f"
to = "plant.f"
"#,
            Path::new("s.toml"),
        )
        .unwrap();
        let flight = Trajectory {
            names: ["plant.r[1]", "plant.r[2]", "plant.rate", "gnc.f"]
                .map(String::from)
                .to_vec(),
            times: vec![0.0, 0.5],
            values: vec![1.0, 2.0, 9.0, 5.0, 3.0, 4.0, 9.0, 6.0],
        };
        let table = inputs_of(&system, "gnc", &flight);
        assert_eq!(table.names, ["r_in[1]", "r_in[2]"]);
        assert_eq!(table.rows, [vec![1.0, 2.0], vec![3.0, 4.0]]);
        // One step apart: held until half a step before the next sample.
        let csv = stimuli_csv(&table, 0.0, 0.5, 0.5);
        assert_eq!(csv, "time,r_in[1],r_in[2]\n0,1,2\n0.25,1,2\n0.5,3,4\n");
        // 2000 steps keep every 4th: the change in the middle, off both samples.
        let ramp = InputTable {
            names: vec!["u".into()],
            times: (0..=2000).map(f64::from).collect(),
            rows: (0..=2000).map(|k| vec![f64::from(k)]).collect(),
        };
        let csv = stimuli_csv(&ramp, 0.0, 2000.0, 1.0);
        assert!(
            csv.starts_with("time,u\n0,0\n1.5,0\n2,4\n5.5,4\n6,8\n"),
            "{}",
            &csv[..80]
        );
        assert!(csv.ends_with("1998,2000\n2000,2000\n"), "{csv}");
        assert_eq!(inputs_of(&system, "plant", &flight).names, ["f"]);
    }
}
