//! The FMI 3.0 numeric types beyond Float64 and Int32 (Float32, Int8, UInt8, Int16, UInt16,
//! UInt32, Int64, UInt64) travel through the importer and the master as one 64-bit *word*
//! per value, so that one buffer and one copy serve them all and no value is rounded:
//!
//! - a signed integer is its value sign-extended to 64 bits (`i64 as u64`);
//! - an unsigned integer is its value zero-extended (a UInt64 above `i64::MAX` keeps every
//!   bit);
//! - a Float32 is the bits of its value as an f64 (f32 -> f64 is exact, and so is the way
//!   back, since the f64 was an f32).
//!
//! Float64, Int32, Enumeration, Boolean, String and Binary keep the paths they have.
pub use model_description::fmi3::Fmi3Type;

/// Whether values of `kind` travel as words.
pub fn is_word(kind: Fmi3Type) -> bool {
    matches!(
        kind,
        Fmi3Type::Float32
            | Fmi3Type::Int8
            | Fmi3Type::UInt8
            | Fmi3Type::Int16
            | Fmi3Type::UInt16
            | Fmi3Type::UInt32
            | Fmi3Type::Int64
            | Fmi3Type::UInt64
    )
}

/// Whether every value of `kind` is an f64 exactly (all word types but Int64 and UInt64).
pub fn fits_f64(kind: Fmi3Type) -> bool {
    !matches!(kind, Fmi3Type::Int64 | Fmi3Type::UInt64)
}

/// The range of an integer type, `None` for the others.
pub fn integer_range(kind: Fmi3Type) -> Option<(i128, i128)> {
    Some(match kind {
        Fmi3Type::Int8 => (i8::MIN.into(), i8::MAX.into()),
        Fmi3Type::UInt8 => (0, u8::MAX.into()),
        Fmi3Type::Int16 => (i16::MIN.into(), i16::MAX.into()),
        Fmi3Type::UInt16 => (0, u16::MAX.into()),
        Fmi3Type::Int32 => (i32::MIN.into(), i32::MAX.into()),
        Fmi3Type::UInt32 => (0, u32::MAX.into()),
        Fmi3Type::Int64 => (i64::MIN.into(), i64::MAX.into()),
        Fmi3Type::UInt64 => (0, u64::MAX.into()),
        _ => return None,
    })
}

/// The word of the integer `value` as `kind`, if `kind` is an integer word type that holds it.
pub fn from_integer(kind: Fmi3Type, value: i128) -> Option<u64> {
    let (min, max) = integer_range(kind)?;
    if !is_word(kind) || value < min || value > max {
        return None;
    }
    // In range: the low 64 bits are the sign- or zero-extended value.
    Some(value as u64)
}

/// The word of `value` as a Float32: the nearest f32 (as a master rounds a decimal start
/// value); `None` beyond the f32 range or for a value that is not a number.
pub fn from_float32(value: f64) -> Option<u64> {
    let single = value as f32;
    (single.is_finite() || !value.is_finite()).then(|| f64::from(single).to_bits())
}

/// The integer a word of an integer `kind` holds.
pub fn to_integer(kind: Fmi3Type, word: u64) -> i128 {
    match kind {
        Fmi3Type::UInt64 => i128::from(word),
        _ => i128::from(word as i64),
    }
}

/// The value of a word as an f64: exact for every word type but Int64 and UInt64, whose
/// values beyond 2^53 round (for a plot or a formula, never for a result file).
pub fn to_f64(kind: Fmi3Type, word: u64) -> f64 {
    match kind {
        Fmi3Type::Float32 => f64::from_bits(word),
        Fmi3Type::UInt64 => word as f64,
        _ => (word as i64) as f64,
    }
}

/// A word as text: an integer in decimal, a Float32 in the shortest form that reads back to
/// the same f32.
pub fn format(kind: Fmi3Type, word: u64) -> String {
    match kind {
        Fmi3Type::Float32 => format!("{:?}", f64::from_bits(word) as f32),
        _ => to_integer(kind, word).to_string(),
    }
}

/// Parses a start value or a value given as text (`"255"`, `"-3"`, `"1.5"`), refusing what
/// `kind` cannot hold.
pub fn parse(kind: Fmi3Type, text: &str) -> Result<u64, String> {
    let text = text.trim();
    if kind == Fmi3Type::Float32 {
        let value: f64 = text
            .parse()
            .map_err(|_| format!("{text:?} is not a number"))?;
        return from_float32(value).ok_or_else(|| format!("{text} is beyond the Float32 range"));
    }
    let value: i128 = text.parse().map_err(|_| {
        format!(
            "{text:?} is not an integer (a {} holds integers)",
            kind.name()
        )
    })?;
    from_integer(kind, value).ok_or_else(|| out_of_range(kind, &value.to_string()))
}

/// "300 is outside the range of UInt8 [0, 255]".
pub fn out_of_range(kind: Fmi3Type, value: &str) -> String {
    match integer_range(kind) {
        Some((min, max)) => format!(
            "{value} is outside the range of {} [{min}, {max}]",
            kind.name()
        ),
        None => format!("{value} is not a {}", kind.name()),
    }
}

/// Binary values as text: lower-case hex, two digits per byte, no separator (as fmusim
/// writes them; an empty value is the empty text).
pub fn hex(bytes: &[u8]) -> String {
    use std::fmt::Write;
    bytes
        .iter()
        .fold(String::with_capacity(2 * bytes.len()), |mut text, byte| {
            let _ = write!(text, "{byte:02x}");
            text
        })
}

/// Reads [`hex`] text (either case; an optional `0x`).
pub fn from_hex(text: &str) -> Result<Vec<u8>, String> {
    let digits = text.trim();
    let digits = digits
        .strip_prefix("0x")
        .or_else(|| digits.strip_prefix("0X"))
        .unwrap_or(digits);
    if !digits.len().is_multiple_of(2) || !digits.bytes().all(|b| b.is_ascii_hexdigit()) {
        return Err(format!(
            "{text:?} is not a Binary value in hex (two hex digits per byte)"
        ));
    }
    (0..digits.len())
        .step_by(2)
        .map(|i| u8::from_str_radix(&digits[i..i + 2], 16).map_err(|e| e.to_string()))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_word_type_round_trips_its_extremes_exactly() {
        for kind in [
            Fmi3Type::Int8,
            Fmi3Type::UInt8,
            Fmi3Type::Int16,
            Fmi3Type::UInt16,
            Fmi3Type::UInt32,
            Fmi3Type::Int64,
            Fmi3Type::UInt64,
        ] {
            let (min, max) = integer_range(kind).unwrap();
            for value in [min, max] {
                let word = from_integer(kind, value).unwrap();
                assert_eq!(to_integer(kind, word), value, "{kind:?}");
                assert_eq!(parse(kind, &format(kind, word)), Ok(word));
            }
            assert_eq!(from_integer(kind, max + 1), None);
            assert_eq!(from_integer(kind, min - 1), None);
        }
        let big = u64::MAX - 1;
        assert_eq!(parse(Fmi3Type::UInt64, &big.to_string()), Ok(big));
        let third = from_float32(1.0 / 3.0).unwrap();
        assert_eq!(f64::from_bits(third), f64::from(1.0f32 / 3.0));
        assert_eq!(
            parse(Fmi3Type::Float32, &format(Fmi3Type::Float32, third)),
            Ok(third)
        );
        assert_eq!(from_float32(1e39), None);
    }

    #[test]
    fn out_of_range_and_fractional_values_are_refused_with_the_range() {
        let text = parse(Fmi3Type::UInt8, "300").unwrap_err();
        assert!(
            text.contains("300") && text.contains("UInt8 [0, 255]"),
            "{text}"
        );
        let text = parse(Fmi3Type::Int16, "1.5").unwrap_err();
        assert!(text.contains("1.5") && text.contains("Int16"), "{text}");
    }

    #[test]
    fn binary_values_read_back_from_hex() {
        let bytes = [0x00, 0x0a, 0xff, 0x10];
        assert_eq!(hex(&bytes), "000aff10");
        assert_eq!(from_hex("000AFF10").unwrap(), bytes);
        assert_eq!(from_hex("0x").unwrap(), Vec::<u8>::new());
        assert!(from_hex("abc").is_err() && from_hex("zz").is_err());
    }
}
