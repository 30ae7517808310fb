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
