//! The unit symbols our variables may use and their SI base-unit exponents, in one table.
//! A symbol missing here is refused by [`check_units`] (which both model-description writers
//! run) rather than written without meaning.
use model_description::BaseUnit;

/// Exponents of (kg, m, s, rad).
type Exponents = [i32; 4];

const UNITS: &[(&str, Exponents)] = &[
    ("1", [0, 0, 0, 0]),
    ("kg", [1, 0, 0, 0]),
    ("kg/s", [1, 0, -1, 0]),
    ("kg.m2", [1, 2, 0, 0]),
    ("m", [0, 1, 0, 0]),
    ("m2", [0, 2, 0, 0]),
    ("m/s", [0, 1, -1, 0]),
    ("m/s2", [0, 1, -2, 0]),
    ("s", [0, 0, 1, 0]),
    ("1/s", [0, 0, -1, 0]),
    ("1/s2", [0, 0, -2, 0]),
    ("Hz", [0, 0, -1, 0]),
    ("N", [1, 1, -2, 0]),
    ("N/m", [1, 0, -2, 0]),
    ("N/s", [1, 1, -3, 0]),
    ("N.m/s", [1, 2, -3, 0]),
    ("N.s", [1, 1, -1, 0]),
    ("N.s/m", [1, 0, -1, 0]),
    ("N.m", [1, 2, -2, 0]),
    ("N.m.s", [1, 2, -1, 0]),
    ("J", [1, 2, -2, 0]),
    ("W", [1, 2, -3, 0]),
    ("rad", [0, 0, 0, 1]),
    ("rad/s", [0, 0, -1, 1]),
    ("rad/s2", [0, 0, -2, 1]),
];

/// Display units offered for the SI units a reviewer reads in other units: angles in
/// degrees (display value = factor x value). Tools show these in plots and dialogs.
const DISPLAY_UNITS: &[(&str, &str, f64)] = &[
    ("rad", "deg", 180.0 / std::f64::consts::PI),
    ("rad/s", "deg/s", 180.0 / std::f64::consts::PI),
    ("rad/s2", "deg/s2", 180.0 / std::f64::consts::PI),
];

/// The display unit (name, factor) of a unit symbol, if it has one.
pub fn display_unit(symbol: &str) -> Option<(&'static str, f64)> {
    DISPLAY_UNITS
        .iter()
        .find(|(unit, _, _)| *unit == symbol)
        .map(|&(_, name, factor)| (name, factor))
}

/// A declared range as a refusal shows it in `unit`: [`fmi_model::range_text`], with an
/// angle's ends that are simple multiples of pi written so (`[-4π, 4π]`), as the
/// declarations state them.
pub fn range_in_unit(
    min: Option<fmi_model::Limit>,
    max: Option<fmi_model::Limit>,
    unit: Option<&str>,
) -> String {
    let angle = unit.is_some_and(|u| u.starts_with("rad"));
    let as_pi = |limit: Option<fmi_model::Limit>| limit.map(|l| l.value()).and_then(pi_multiple);
    match (angle, as_pi(min), as_pi(max)) {
        (true, Some(low), Some(high)) => {
            let text = fmi_model::range_text(min, max);
            let (open, close) = (&text[..1], &text[text.len() - 1..]);
            format!("{open}{low}, {high}{close}")
        }
        _ => fmi_model::range_text(min, max),
    }
}

/// `value` as `kπ/n` for small `k` and `n`, if it is one (to the last bits).
fn pi_multiple(value: f64) -> Option<String> {
    if value == 0.0 {
        return Some("0".into());
    }
    for n in [1_i32, 2, 3, 4, 6] {
        let k = value * f64::from(n) / std::f64::consts::PI;
        let rounded = k.round();
        if rounded != 0.0 && rounded.abs() <= 24.0 && (k - rounded).abs() < 1e-12 {
            let sign = if rounded < 0.0 { "-" } else { "" };
            let k = rounded.abs() as i32;
            let numerator = if k == 1 {
                "π".to_string()
            } else {
                format!("{k}π")
            };
            return Some(if n == 1 {
                format!("{sign}{numerator}")
            } else {
                format!("{sign}{numerator}/{n}")
            });
        }
    }
    None
}

/// A suggested value, short: four significant digits.
pub fn short(value: f64) -> String {
    let text = format!("{value:.4}");
    let trimmed = text.trim_end_matches('0').trim_end_matches('.');
    if value != 0.0 && (value.abs() < 1e-3 || value.abs() >= 1e6) {
        format!("{value:.3e}")
    } else {
        trimmed.to_string()
    }
}

/// The `<BaseUnit>` of a known symbol.
pub fn base_unit(symbol: &str) -> Option<BaseUnit> {
    let &(_, [kg, m, s, rad]) = UNITS.iter().find(|(name, _)| *name == symbol)?;
    let exponent = |e: i32| (e != 0).then_some(e);
    Some(BaseUnit {
        kg: exponent(kg),
        m: exponent(m),
        s: exponent(s),
        rad: exponent(rad),
        ..BaseUnit::default()
    })
}

/// Every unit symbol `M` declares is in the table, else the first one that is not.
pub fn check_units<M: fmi_model::Model>() -> Result<(), String> {
    match M::declarations()
        .iter()
        .find(|d| d.unit.is_some_and(|u| base_unit(u).is_none()))
    {
        Some(d) => Err(format!(
            "variable {}: unit {:?} is not in the unit table (fmi-export/src/units.rs)",
            d.name,
            d.unit.unwrap_or_default()
        )),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn angle_ranges_in_multiples_of_pi_and_others_plain() {
        use fmi_model::Limit;
        let pi = std::f64::consts::PI;
        let range = |a: f64, b: f64, u: &str| {
            range_in_unit(
                Some(Limit::Inclusive(a)),
                Some(Limit::Inclusive(b)),
                Some(u),
            )
        };
        assert_eq!(range(-4.0 * pi, 4.0 * pi, "rad"), "[-4π, 4π]");
        assert_eq!(range(0.0, pi / 2.0, "rad"), "[0, π/2]");
        assert_eq!(
            range(0.0, 1.3962634015954636, "rad"),
            "[0, 1.3962634015954636]"
        );
        assert_eq!(
            range(-4.0 * pi, 4.0 * pi, "m"),
            "[-12.566370614359172, 12.566370614359172]"
        );
        assert_eq!(short(2.6179938779914944), "2.618");
        assert_eq!(short(3.0), "3");
    }

    #[test]
    fn symbols_are_unique() {
        for (i, (a, _)) in UNITS.iter().enumerate() {
            assert!(UNITS[i + 1..].iter().all(|(b, _)| a != b), "{a} twice");
        }
    }

    /// An independent reading of each compound symbol: multiply the exponents of its
    /// factors ("." multiplies, "/" divides, a trailing digit is a power).
    #[test]
    fn compound_symbols_agree_with_their_factors() {
        fn parse(symbol: &str) -> [i32; 4] {
            let basic = |f: &str| -> [i32; 4] {
                let (name, power) = match f.chars().last() {
                    Some(d) if d.is_ascii_digit() && f.len() > 1 => {
                        (&f[..f.len() - 1], d.to_digit(10).unwrap() as i32)
                    }
                    _ => (f, 1),
                };
                let unit = match name {
                    "1" => [0, 0, 0, 0],
                    "kg" => [1, 0, 0, 0],
                    "m" => [0, 1, 0, 0],
                    "s" => [0, 0, 1, 0],
                    "rad" => [0, 0, 0, 1],
                    "N" => [1, 1, -2, 0],
                    "J" => [1, 2, -2, 0],
                    "W" => [1, 2, -3, 0],
                    "Hz" => [0, 0, -1, 0],
                    other => panic!("no factor {other}"),
                };
                unit.map(|e| e * power)
            };
            let mut total = [0; 4];
            for (i, part) in symbol.split('/').enumerate() {
                for factor in part.split('.') {
                    let sign = if i == 0 { 1 } else { -1 };
                    for (t, e) in total.iter_mut().zip(basic(factor)) {
                        *t += sign * e;
                    }
                }
            }
            total
        }
        for (symbol, exponents) in UNITS {
            assert_eq!(parse(symbol), *exponents, "{symbol}");
        }
    }

    #[test]
    fn newton_metre_is_kg_m2_per_s2_and_unknown_symbols_are_refused() {
        let nm = base_unit("N.m").unwrap();
        assert_eq!(
            (nm.kg, nm.m, nm.s, nm.rad),
            (Some(1), Some(2), Some(-2), None)
        );
        assert_eq!(base_unit("1"), Some(BaseUnit::default()));
        assert_eq!(base_unit("furlong"), None);
    }
}
