//! Lexical forms of XML Schema `xs:double`, shared by the writer, the reader and the
//! diagnosis pass so all three agree on what a number looks like.
//!
//! `f64`'s own `Display` is not usable as is: it writes `inf`/`NaN`, which `xs:double`
//! spells `INF`/`NaN`, and it never uses an exponent, so `1e-300` would become a
//! 300-digit string. Both `Display` and `LowerExp` print the shortest digits that parse
//! back to the same bits, so either form round-trips exactly.

/// Below this magnitude (and at or above [`LARGE`]) the exponent form is shorter.
const SMALL: f64 = 1e-5;
const LARGE: f64 = 1e16;

/// Writes `value` as the shortest `xs:double` literal that parses back to the same bits.
pub(crate) fn format_double(value: f64) -> String {
    if value.is_nan() {
        "NaN".to_owned()
    } else if value.is_infinite() {
        if value > 0.0 { "INF" } else { "-INF" }.to_owned()
    } else if value == 0.0 || (SMALL..LARGE).contains(&value.abs()) {
        format!("{value}")
    } else {
        format!("{value:e}")
    }
}

/// Reads an `xs:double` literal. Also accepts the spellings Rust accepts (`inf`, `1e3`,
/// `.5`), because being lenient with other tools' files costs nothing here.
pub(crate) fn parse_double(text: &str) -> Result<f64, String> {
    let trimmed = trim_xml_whitespace(text);
    match trimmed {
        "INF" | "+INF" => Ok(f64::INFINITY),
        "-INF" => Ok(f64::NEG_INFINITY),
        _ => trimmed
            .parse::<f64>()
            .map_err(|_| format!("\"{text}\" is not a number (xs:double)")),
    }
}

/// `xs:double` collapses whitespace, so `" 1.5 "` is a valid value.
fn trim_xml_whitespace(text: &str) -> &str {
    text.trim_matches(|c| matches!(c, ' ' | '\t' | '\n' | '\r'))
}

/// `#[serde(with = "crate::xsd::opt_f64")]` for optional `xs:double` attributes.
pub(crate) mod opt_f64 {
    use serde::{de::Error as _, Deserialize, Deserializer, Serializer};

    pub(crate) fn serialize<S: Serializer>(value: &Option<f64>, ser: S) -> Result<S::Ok, S::Error> {
        match value {
            Some(v) => ser.serialize_str(&super::format_double(*v)),
            None => ser.serialize_none(),
        }
    }

    pub(crate) fn deserialize<'de, D: Deserializer<'de>>(de: D) -> Result<Option<f64>, D::Error> {
        let text = String::deserialize(de)?;
        super::parse_double(&text)
            .map(Some)
            .map_err(D::Error::custom)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn round_trip(value: f64) -> f64 {
        parse_double(&format_double(value)).expect("own output parses")
    }

    #[test]
    fn awkward_values_round_trip_bit_exactly() {
        let values = [
            0.1,
            -0.0,
            1.0 / 3.0,
            1.62,
            f64::MIN_POSITIVE,
            5e-324,
            f64::MAX,
            -f64::MAX,
            f64::EPSILON,
            1e-5,
            9.999_999_999_999_999e-6,
            1e16,
            9_999_999_999_999_998.0,
            123_456.789_012_345_67,
        ];
        for v in values {
            assert_eq!(
                round_trip(v).to_bits(),
                v.to_bits(),
                "{v:e} -> {}",
                format_double(v)
            );
        }
    }

    #[test]
    fn non_finite_values_use_xsd_spelling() {
        assert_eq!(format_double(f64::INFINITY), "INF");
        assert_eq!(format_double(f64::NEG_INFINITY), "-INF");
        assert_eq!(format_double(f64::NAN), "NaN");
        assert_eq!(round_trip(f64::INFINITY), f64::INFINITY);
        assert_eq!(round_trip(f64::NEG_INFINITY), f64::NEG_INFINITY);
        assert!(round_trip(f64::NAN).is_nan());
    }

    #[test]
    fn extreme_magnitudes_use_an_exponent_and_ordinary_ones_do_not() {
        assert_eq!(format_double(1e-300), "1e-300");
        assert_eq!(format_double(2.5e20), "2.5e20");
        assert_eq!(format_double(0.001), "0.001");
        assert_eq!(format_double(-1737400.0), "-1737400");
    }

    #[test]
    fn reads_other_tools_spellings() {
        assert_eq!(parse_double("1E-3"), Ok(0.001));
        assert_eq!(parse_double(" 2.5 "), Ok(2.5));
        assert_eq!(parse_double(".5"), Ok(0.5));
        assert_eq!(parse_double("+INF"), Ok(f64::INFINITY));
        assert_eq!(parse_double("-1e+2"), Ok(-100.0));
    }

    #[test]
    fn refuses_non_numbers_and_quotes_them() {
        let err = parse_double("1,5").unwrap_err();
        assert!(err.contains("\"1,5\""), "{err}");
        assert!(parse_double("").is_err());
        assert!(parse_double("one").is_err());
    }
}
