//! Input signals from a table, in the CSV convention fmpy and fmusim read: a first column
//! `time`, then one column per input (`instance.variable`, or the variable of a one-FMU
//! system), array elements one column each. A Real input is interpolated linearly between
//! rows; an Integer or Boolean one holds the value of the last row at or before the time.
//! Where a time repeats (an event), the later row holds from that time on. Before the first
//! row an input takes the first row's value, after the last row the last one's.
use super::SystemError;
use std::path::Path;

#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct InputTable {
    /// The column of each input, as the table names it.
    pub names: Vec<String>,
    /// Non-decreasing.
    pub times: Vec<f64>,
    /// `rows[k][j]`: input `j` at `times[k]`.
    pub rows: Vec<Vec<f64>>,
}

impl InputTable {
    /// Reads a CSV table, naming every problem (row, column, text) at once.
    pub fn read_csv(path: &Path) -> Result<InputTable, SystemError> {
        let text = std::fs::read_to_string(path).map_err(|source| SystemError::Io {
            path: path.to_owned(),
            source,
        })?;
        Self::parse_csv(&text).map_err(|problems| SystemError::Syntax {
            path: path.to_owned(),
            message: problems.join("\n"),
        })
    }

    pub fn parse_csv(text: &str) -> Result<InputTable, Vec<String>> {
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
        if names.is_empty() {
            problems.push("no input column after 'time'".into());
        }
        for (j, name) in names.iter().enumerate() {
            if names[..j].contains(name) {
                problems.push(format!("column '{name}' appears twice"));
            }
        }
        let mut times = Vec::new();
        let mut rows = Vec::new();
        for (k, record) in reader.records().enumerate() {
            let line = k + 2;
            let record = match record {
                Ok(r) => r,
                Err(e) => {
                    problems.push(format!("row {line}: {e}"));
                    continue;
                }
            };
            let mut values = Vec::with_capacity(header.len());
            for (j, field) in record.iter().enumerate() {
                match field.parse::<f64>() {
                    Ok(x) if x.is_finite() => values.push(x),
                    _ => problems.push(format!(
                        "row {line}, column '{}': '{field}' is not a finite number",
                        header.get(j).map(String::as_str).unwrap_or("?")
                    )),
                }
            }
            if values.len() != header.len() {
                continue;
            }
            let time = values.remove(0);
            if let Some(&previous) = times.last() {
                if time < previous {
                    problems.push(format!(
                        "row {line}: time {time} is before the previous row's {previous}"
                    ));
                }
            }
            times.push(time);
            rows.push(values);
        }
        if times.is_empty() && problems.is_empty() {
            problems.push("no rows".into());
        }
        if problems.is_empty() {
            Ok(InputTable { names, times, rows })
        } else {
            Err(problems)
        }
    }

    /// Input `column` at `time`: interpolated linearly when `interpolate`, else held.
    pub fn value(&self, column: usize, time: f64, interpolate: bool) -> f64 {
        // The first row after `time`: rows at `time` itself lie before it, so that of rows
        // at one repeated time the last one holds.
        let after = self.times.partition_point(|&t| t <= time);
        if after == 0 {
            return self.rows[0][column];
        }
        let before = after - 1;
        if after == self.times.len() || !interpolate {
            return self.rows[before][column];
        }
        let (t0, t1) = (self.times[before], self.times[after]);
        let (y0, y1) = (self.rows[before][column], self.rows[after][column]);
        y0 + (y1 - y0) * ((time - t0) / (t1 - t0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table() -> InputTable {
        InputTable::parse_csv("time,u,n\n0,0,1\n1,10,2\n2,10,3\n2,-4,4\n3,0,5\n").unwrap()
    }

    #[test]
    fn a_real_input_is_interpolated_and_a_discrete_one_held() {
        let t = table();
        assert_eq!(t.value(0, 0.25, true), 2.5);
        assert_eq!(t.value(1, 0.25, false), 1.0);
        assert_eq!(t.value(1, 1.0, false), 2.0);
        assert_eq!(t.value(0, 1.5, true), 10.0);
    }

    #[test]
    fn at_a_repeated_time_the_later_row_holds_and_the_ends_extend() {
        let t = table();
        assert_eq!(t.value(0, 2.0, true), -4.0);
        assert_eq!(t.value(0, 2.5, true), -2.0);
        assert_eq!(t.value(0, -1.0, true), 0.0);
        assert_eq!(t.value(1, 9.0, false), 5.0);
    }

    #[test]
    fn every_problem_of_a_table_is_named_at_once() {
        let problems =
            InputTable::parse_csv("t,u,u\n0,x,1\n1,2,3\n0.5,1,1\n2,1,inf\n").unwrap_err();
        let text = problems.join("\n");
        assert!(
            text.contains("the first column is 't', not 'time'"),
            "{text}"
        );
        assert!(text.contains("column 'u' appears twice"), "{text}");
        assert!(
            text.contains("row 2, column 'u': 'x' is not a finite number"),
            "{text}"
        );
        assert!(text.contains("row 5, column 'u': 'inf'"), "{text}");
        assert!(
            text.contains("row 4: time 0.5 is before the previous row's 1"),
            "{text}"
        );
    }
}
