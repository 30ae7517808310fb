//! A reference result as the CSV files of FMI-LS-REF hold it: a first column `time`, then
//! one column per variable. Reference-FMUs' files carry every type FMI 3.0 has: Booleans
//! are written `true`/`false` and read as 1 and 0, and a column of text (String, Binary) is
//! set aside by name, since no tube can be drawn around it.

#[derive(Debug, Clone, PartialEq)]
pub struct ReferenceTable {
    pub names: Vec<String>,
    /// Non-decreasing; a time repeats at an event (the values before, then after it).
    pub times: Vec<f64>,
    /// `columns[j][k]`: variable `j` at `times[k]`.
    pub columns: Vec<Vec<f64>>,
    /// The columns holding text, which are not compared.
    pub text_columns: Vec<String>,
}

/// A field as a number: Booleans as 0 and 1.
fn number(field: &str) -> Option<f64> {
    match field {
        "true" => Some(1.0),
        "false" => Some(0.0),
        _ => field.parse::<f64>().ok(),
    }
}

impl ReferenceTable {
    /// Every problem of the text at once, each with its row and column.
    pub fn parse_csv(text: &str) -> Result<ReferenceTable, Vec<String>> {
        let mut reader = csv::ReaderBuilder::new()
            .trim(csv::Trim::All)
            .from_reader(text.as_bytes());
        let header: Vec<String> = match reader.headers() {
            Ok(h) => h.iter().map(|s| s.trim_matches('"').to_owned()).collect(),
            Err(e) => return Err(vec![format!("no header row: {e}")]),
        };
        let mut problems = Vec::new();
        if header.first().map(String::as_str) != Some("time") {
            problems.push(format!(
                "the first column is '{}', not 'time'",
                header.first().map(String::as_str).unwrap_or("")
            ));
        }
        let names: Vec<String> = header.iter().skip(1).cloned().collect();
        for (j, name) in names.iter().enumerate() {
            if names[..j].contains(name) {
                problems.push(format!("column '{name}' appears twice"));
            }
        }
        let mut times = Vec::new();
        let mut fields: Vec<Vec<String>> = vec![Vec::new(); names.len()];
        for (k, record) in reader.records().enumerate() {
            let line = k + 2;
            let record = match record {
                Ok(r) => r,
                Err(e) => {
                    problems.push(format!("row {line}: {e}"));
                    continue;
                }
            };
            let mut values = record.iter();
            let time = values.next().unwrap_or("");
            match time.parse::<f64>() {
                Ok(t) if t.is_finite() => {
                    if let Some(&previous) = times.last() {
                        if t < previous {
                            problems.push(format!(
                                "row {line}: time {t} is before the previous row's {previous}"
                            ));
                        }
                    }
                    times.push(t);
                }
                _ => {
                    problems.push(format!("row {line}: time '{time}' is not a finite number"));
                    continue;
                }
            }
            for (column, value) in fields.iter_mut().zip(values) {
                column.push(value.to_owned());
            }
        }
        if times.is_empty() && problems.is_empty() {
            problems.push("no rows".into());
        }
        if !problems.is_empty() {
            return Err(problems);
        }
        let mut table = ReferenceTable {
            names: Vec::new(),
            times,
            columns: Vec::new(),
            text_columns: Vec::new(),
        };
        for (name, column) in names.into_iter().zip(fields) {
            let numbers: Option<Vec<f64>> = column.iter().map(|f| number(f)).collect();
            match numbers {
                Some(values) if values.iter().all(|v| v.is_finite()) => {
                    table.names.push(name);
                    table.columns.push(values);
                }
                _ => table.text_columns.push(name),
            }
        }
        Ok(table)
    }

    pub fn column(&self, name: &str) -> Option<&[f64]> {
        let j = self.names.iter().position(|n| n == name)?;
        Some(&self.columns[j])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn booleans_are_numbers_and_text_columns_are_set_aside() {
        let table = ReferenceTable::parse_csv(
            "time,x,Boolean_output,String_output,Binary_output\n\
             0,1.5,false,Set me!,666f6f\n0.1,2,true,Set me!,666f6f\n",
        )
        .unwrap();
        assert_eq!(table.names, ["x", "Boolean_output"]);
        assert_eq!(table.columns[1], [0.0, 1.0]);
        assert_eq!(table.text_columns, ["String_output", "Binary_output"]);
        assert_eq!(table.times, [0.0, 0.1]);
    }

    #[test]
    fn every_problem_of_a_table_is_named_at_once() {
        let problems = ReferenceTable::parse_csv("t,a,a\nx,1,2\n1,1,2\n0.5,1,2\n").unwrap_err();
        let text = problems.join("\n");
        assert!(text.contains("the first column is 't'"), "{text}");
        assert!(text.contains("column 'a' appears twice"), "{text}");
        assert!(text.contains("row 2: time 'x'"), "{text}");
        assert!(
            text.contains("row 4: time 0.5 is before the previous row's 1"),
            "{text}"
        );
    }
}
