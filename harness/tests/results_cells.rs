//! The cells of a campaign block: what each item of its marker's `summary.csv:` list computes
//! from the campaign's `summary.csv` and `manifest.csv`.
//!
//! A cell is one or more items joined by ` / `. An item is
//! `[per law | largest of the laws] [at PHI deg] VALUE`, and a VALUE one of
//!
//! - `COLUMN` (`COLUMN in deg`): the summary.csv column of the cell, to three significant
//!   digits (converted from radians), or its text;
//! - `count COLUMN > X`: how many of the cell's flights (`manifest.csv` rows) exceed X;
//! - `mean COLUMN`: the mean of the cell's flights' values;
//! - `ci90 VALUE`: the two-sided 90 % Clopper-Pearson interval of the share VALUE (a count)
//!   is of the cell's runs, in percent (`34.8-40.4 %`), as `scipy.stats.binomtest(k,
//!   n).proportion_ci(0.90)` gives it.
//!
//! The cell (law and phi_cmd) is the row's (its leading cells name them: `coupled, 150 deg`,
//! or `paper, 0` and `coupled`); `at PHI deg` sets the phi_cmd, `per law` gives the value of
//! each law the campaign flies, in its order, joined by ` / `, `largest of the laws` their
//! largest.
use std::collections::BTreeMap;

/// A CSV row by column name.
pub type Row = BTreeMap<String, String>;

/// What a campaign wrote: its summary.csv and manifest.csv rows.
pub struct Campaign {
    pub summary: Vec<Row>,
    pub manifest: Vec<Row>,
}

impl Campaign {
    /// The laws the campaign flew, in its summary's order.
    pub fn laws(&self) -> Vec<String> {
        let mut laws: Vec<String> = Vec::new();
        for row in &self.summary {
            if !laws.contains(&row["law"]) {
                laws.push(row["law"].clone());
            }
        }
        laws
    }

    fn summary_row(&self, law: &str, phi: f64) -> Result<&Row, String> {
        self.summary
            .iter()
            .find(|r| r["law"] == law && r["phi_cmd_deg"].parse::<f64>() == Ok(phi))
            .ok_or_else(|| format!("no summary row {law}, {phi} deg"))
    }

    fn flights(&self, law: &str, phi: f64) -> impl Iterator<Item = &Row> {
        let law = law.to_owned();
        self.manifest
            .iter()
            .filter(move |r| r["law"] == law && r["phi_cmd_deg"].parse::<f64>() == Ok(phi))
    }
}

#[derive(Debug, Clone, PartialEq)]
pub enum Over {
    /// The row's law.
    Row,
    /// Each law, joined by ` / `.
    EachLaw,
    /// The largest value of the laws.
    LargestOfLaws,
}

#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    Column { name: String, degrees: bool },
    Count { column: String, above: f64 },
    Mean { column: String },
    Ci90(Box<Value>),
}

#[derive(Debug, Clone, PartialEq)]
pub struct Item {
    pub over: Over,
    pub phi_deg: Option<f64>,
    pub value: Value,
}

pub fn parse_item(text: &str) -> Result<Item, String> {
    let mut rest = text.trim();
    let mut over = Over::Row;
    if let Some(r) = rest.strip_prefix("per law ") {
        (over, rest) = (Over::EachLaw, r);
    } else if let Some(r) = rest.strip_prefix("largest of the laws ") {
        (over, rest) = (Over::LargestOfLaws, r);
    }
    let mut phi_deg = None;
    if let Some(r) = rest.strip_prefix("at ") {
        let (phi, r) = r
            .split_once(" deg ")
            .ok_or_else(|| format!("`{text}`: expected `at PHI deg VALUE`"))?;
        let phi = phi
            .trim()
            .parse()
            .map_err(|_| format!("`{text}`: `{phi}` is no phi_cmd in deg"))?;
        (phi_deg, rest) = (Some(phi), r);
    }
    Ok(Item {
        over,
        phi_deg,
        value: parse_value(rest.trim()).map_err(|e| format!("`{text}`: {e}"))?,
    })
}

fn parse_value(text: &str) -> Result<Value, String> {
    if let Some(inner) = text.strip_prefix("ci90 ") {
        return Ok(Value::Ci90(Box::new(parse_value(inner.trim())?)));
    }
    if let Some(rest) = text.strip_prefix("count ") {
        let (column, above) = rest
            .split_once(" > ")
            .ok_or("expected `count COLUMN > X`")?;
        let above = above
            .trim()
            .parse()
            .map_err(|_| format!("`{above}` is no number"))?;
        return Ok(Value::Count {
            column: column.trim().to_owned(),
            above,
        });
    }
    if let Some(column) = text.strip_prefix("mean ") {
        return Ok(Value::Mean {
            column: column.trim().to_owned(),
        });
    }
    if text.is_empty() || text.contains(' ') && !text.ends_with(" in deg") {
        return Err(format!("`{text}` is no column"));
    }
    Ok(match text.strip_suffix(" in deg") {
        Some(name) => Value::Column {
            name: name.to_owned(),
            degrees: true,
        },
        None => Value::Column {
            name: text.to_owned(),
            degrees: false,
        },
    })
}

impl Value {
    /// The file and column the value reads.
    pub fn column(&self) -> (&'static str, &str) {
        match self {
            Value::Column { name, .. } => ("summary.csv", name),
            Value::Count { column, .. } | Value::Mean { column } => ("manifest.csv", column),
            Value::Ci90(inner) => inner.column(),
        }
    }
}

/// The number a value has in one cell; None where summary.csv leaves it empty.
fn number(value: &Value, campaign: &Campaign, law: &str, phi: f64) -> Result<Option<f64>, String> {
    let parse = |row: &Row, column: &str| -> Result<Option<f64>, String> {
        let text = row
            .get(column)
            .ok_or_else(|| format!("no column `{column}`"))?;
        if text.is_empty() {
            return Ok(None);
        }
        text.parse()
            .map(Some)
            .map_err(|_| format!("`{column}` = `{text}` is no number"))
    };
    match value {
        Value::Column { name, degrees } => {
            let x = parse(campaign.summary_row(law, phi)?, name)?;
            Ok(x.map(|x| if *degrees { x.to_degrees() } else { x }))
        }
        Value::Count { column, above } => {
            let mut count = 0;
            for flight in campaign.flights(law, phi) {
                if parse(flight, column)?.is_some_and(|x| x > *above) {
                    count += 1;
                }
            }
            Ok(Some(f64::from(count)))
        }
        Value::Mean { column } => {
            let mut values = Vec::new();
            for flight in campaign.flights(law, phi) {
                values.extend(parse(flight, column)?);
            }
            if values.is_empty() {
                return Err(format!("no flight {law}, {phi} deg"));
            }
            Ok(Some(values.iter().sum::<f64>() / values.len() as f64))
        }
        Value::Ci90(_) => Err("an interval is no number".into()),
    }
}

/// The text of a value in one cell.
fn text(value: &Value, campaign: &Campaign, law: &str, phi: f64) -> Result<String, String> {
    if let Value::Ci90(inner) = value {
        let count = number(inner, campaign, law, phi)?.ok_or("an empty count")?;
        let runs: u64 = campaign.summary_row(law, phi)?["runs"]
            .parse()
            .map_err(|_| "runs is no count")?;
        let (low, high) = clopper_pearson_90(count as u64, runs);
        let percent = |p: f64| match 100.0 * p {
            0.0 => "0".to_owned(),
            x => three_digits(&x.to_string()),
        };
        return Ok(format!("{}-{} %", percent(low), percent(high)));
    }
    if let Value::Column { name, .. } = value {
        // A text column (`_influential_inputs`, `statement`) as it is.
        let raw = campaign
            .summary_row(law, phi)?
            .get(name)
            .ok_or_else(|| format!("no column `{name}`"))?;
        if !raw.is_empty() && raw.parse::<f64>().is_err() {
            return Ok(raw.clone());
        }
    }
    Ok(number(value, campaign, law, phi)?
        .map_or_else(String::new, |x| three_digits(&x.to_string())))
}

/// An item's text in the row of `law` (if the row names one) at `phi` (if it names one).
pub fn evaluate(
    item: &Item,
    campaign: &Campaign,
    law: Option<&str>,
    phi: Option<f64>,
) -> Result<String, String> {
    let phi = item
        .phi_deg
        .or(phi)
        .ok_or("the row names no phi_cmd and the item no `at PHI deg`")?;
    match item.over {
        Over::Row => {
            let law = law.ok_or(
                "the row names no law and the item neither `per law` nor `largest of the laws`",
            )?;
            text(&item.value, campaign, law, phi)
        }
        Over::EachLaw => {
            let values: Result<Vec<String>, String> = campaign
                .laws()
                .iter()
                .map(|law| text(&item.value, campaign, law, phi))
                .collect();
            Ok(values?.join(" / "))
        }
        Over::LargestOfLaws => {
            let mut largest: Option<f64> = None;
            for law in campaign.laws() {
                if let Some(x) = number(&item.value, campaign, &law, phi)? {
                    largest = Some(largest.map_or(x, |l| l.max(x)));
                }
            }
            Ok(largest.map_or_else(String::new, |x| three_digits(&x.to_string())))
        }
    }
}

/// The law and phi_cmd a row's leading cells name: a cell that is a law's name, or
/// `LAW, PHI [deg]`, or `LABEL, PHI [deg]` (phi_cmd only).
pub fn row_cell(lead: &[String], laws: &[String]) -> (Option<String>, Option<f64>) {
    let (mut law, mut phi) = (None, None);
    for cell in lead {
        if cell.starts_with('`') {
            // A command: its words are no cell's name.
            continue;
        }
        if laws.contains(cell) {
            law = Some(cell.clone());
        } else if let Some((left, right)) = cell.split_once(',') {
            if let Ok(p) = right.trim().trim_end_matches("deg").trim().parse::<f64>() {
                phi = Some(p);
                if laws.iter().any(|l| l == left.trim()) {
                    law = Some(left.trim().to_owned());
                }
            }
        }
    }
    (law, phi)
}

/// The two-sided 90 % Clopper-Pearson interval of a share of `count` in `runs`: each end
/// the one-sided 95 % bound, from the campaign's own one-sided bound (the lower end by
/// counting the other outcome).
pub fn clopper_pearson_90(count: u64, runs: u64) -> (f64, f64) {
    use campaign::stats::reliability_lower_bound;
    let low = reliability_lower_bound(runs - count, runs, 0.95);
    let high = 1.0 - reliability_lower_bound(count, runs, 0.95);
    (low, high)
}

/// A value to three significant digits; integers as they are.
pub fn three_digits(value: &str) -> String {
    let Ok(x) = value.parse::<f64>() else {
        return value.to_owned();
    };
    if !x.is_finite() || x == x.trunc() && x.abs() < 1e6 {
        return value.trim_end_matches(".0").to_owned();
    }
    if x.abs() < 1e-3 {
        return format!("{x:.2e}");
    }
    let decimals = (2 - x.abs().log10().floor() as i32).max(0) as usize;
    format!("{x:.decimals$}")
}

#[test]
fn items_parse() {
    assert_eq!(
        parse_item("per law at 150 deg count max_horizontal_deviation_descent_m > 10").unwrap(),
        Item {
            over: Over::EachLaw,
            phi_deg: Some(150.0),
            value: Value::Count {
                column: "max_horizontal_deviation_descent_m".into(),
                above: 10.0
            }
        }
    );
    assert_eq!(
        parse_item("ci90 failed_verdicts").unwrap().value,
        Value::Ci90(Box::new(Value::Column {
            name: "failed_verdicts".into(),
            degrees: false
        }))
    );
    assert!(parse_item("largest of the laws at 0 deg x_max").is_ok());
    assert!(parse_item("count x").is_err());
    assert!(parse_item("at zero deg x").is_err());
    assert!(parse_item("two words").is_err());
}

#[test]
fn the_interval_is_scipys() {
    // scipy.stats.binomtest(k, n).proportion_ci(0.90), exact (Clopper-Pearson):
    // (320, 852) -> (0.348060, 0.403753); (5, 852) -> (0.00231514, 0.0122994);
    // (0, 852) -> (0, 0.00350994); (852, 852) -> (0.996490, 1).
    let close = |(a, b): (f64, f64), (x, y): (f64, f64)| {
        assert!((a - x).abs() < 1e-6 && (b - y).abs() < 1e-6, "{a} {b}");
    };
    close(clopper_pearson_90(320, 852), (0.348060, 0.403753));
    close(clopper_pearson_90(5, 852), (0.00231514, 0.0122994));
    close(clopper_pearson_90(0, 852), (0.0, 0.00350994));
    close(clopper_pearson_90(852, 852), (0.996490, 1.0));
}

#[test]
fn a_row_names_its_cell() {
    let laws = vec!["coupled".to_owned(), "decoupled".to_owned()];
    let s = |v: &[&str]| v.iter().map(|c| c.to_string()).collect::<Vec<_>>();
    assert_eq!(
        row_cell(&s(&["coupled, 150 deg"]), &laws),
        (Some("coupled".into()), Some(150.0))
    );
    assert_eq!(
        row_cell(&s(&["paper, 0", "decoupled"]), &laws),
        (Some("decoupled".into()), Some(0.0))
    );
    assert_eq!(
        row_cell(
            &s(&["torque model", "`harness monte-carlo`", "coupled"]),
            &laws
        ),
        (Some("coupled".into()), None)
    );
}

#[test]
fn items_compute_from_a_campaigns_files() {
    // GIVEN a campaign of two laws at one phi_cmd, three flights each
    let row = |pairs: &[(&str, &str)]| -> Row {
        pairs
            .iter()
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect()
    };
    let summary = ["coupled", "decoupled"]
        .iter()
        .map(|law| {
            row(&[
                ("law", law),
                ("phi_cmd_deg", "150.0"),
                ("runs", "3"),
                ("d_max", "0.5"),
            ])
        })
        .collect();
    let mut manifest = Vec::new();
    for (law, values) in [
        ("coupled", ["12", "3", "40"]),
        ("decoupled", ["1", "2", "11.5"]),
    ] {
        for v in values {
            manifest.push(row(&[("law", law), ("phi_cmd_deg", "150.0"), ("d", v)]));
        }
    }
    let campaign = Campaign { summary, manifest };
    let at = |text: &str, law: Option<&str>| {
        evaluate(&parse_item(text).unwrap(), &campaign, law, Some(150.0)).unwrap()
    };
    // THEN each item reads its file and cell
    assert_eq!(at("count d > 10", Some("coupled")), "2");
    assert_eq!(at("per law count d > 10", None), "2 / 1");
    assert_eq!(at("mean d", Some("decoupled")), "4.83");
    assert_eq!(at("largest of the laws mean d", None), "18.3");
    assert_eq!(at("d_max in deg", Some("coupled")), "28.6");
    // AND the interval of 2 in 3 is scipy's (0.135, 0.983)
    assert_eq!(at("ci90 count d > 10", Some("coupled")), "13.5-98.3 %");
    assert!(evaluate(
        &parse_item("count e > 1").unwrap(),
        &campaign,
        Some("coupled"),
        Some(150.0)
    )
    .is_err());
}
