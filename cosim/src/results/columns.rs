//! The type of a recorded column, and how its values sit in a row.
//!
//! A row is one 64-bit slot per column ([`crate::master::Recorder`] takes `&[f64]`), and
//! every value is exact in its slot:
//!
//! - Float64, Float32, the integers up to 32 bits and Boolean (0 or 1) are the f64 of their
//!   value, which holds each of them exactly (so plots, requirements and every existing
//!   reader of a trajectory read them as numbers);
//! - Int64 and UInt64 are not all f64s, so their slot holds the integer's 64 bits
//!   (`f64::from_bits`): [`ColumnType::number`] gives the value as the nearest f64, and the
//!   result files write the integer itself.
//!
//! - String and Binary columns have the slot 0: their values reach a recorder as text
//!   (`Recorder::record_text`, a Binary in lower-case hex, two digits a byte, as fmusim
//!   writes it), which the result streams write; a trajectory in memory keeps no text.
//!
//! A file written with types writes integers as integers (`1000`, not `1000.0`) in CSV and
//! as typed columns in Arrow; Float32 is written as its exact f64 value; a String as text
//! (quoted where CSV needs it), a Binary as hex in CSV and as bytes in Arrow.
use fmi_import::{word, Fmi3Type};

#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub enum ColumnType {
    #[default]
    Float64,
    Float32,
    Int8,
    UInt8,
    Int16,
    UInt16,
    Int32,
    UInt32,
    Int64,
    UInt64,
    Boolean,
    String,
    Binary,
}

impl ColumnType {
    /// The column of a variable of a word type (`fmi_import::word`).
    pub fn of_fmi3(kind: Fmi3Type) -> ColumnType {
        match kind {
            Fmi3Type::Float32 => ColumnType::Float32,
            Fmi3Type::Int8 => ColumnType::Int8,
            Fmi3Type::UInt8 => ColumnType::UInt8,
            Fmi3Type::Int16 => ColumnType::Int16,
            Fmi3Type::UInt16 => ColumnType::UInt16,
            Fmi3Type::Int32 | Fmi3Type::Enumeration => ColumnType::Int32,
            Fmi3Type::UInt32 => ColumnType::UInt32,
            Fmi3Type::Int64 => ColumnType::Int64,
            Fmi3Type::UInt64 => ColumnType::UInt64,
            Fmi3Type::Boolean => ColumnType::Boolean,
            Fmi3Type::String => ColumnType::String,
            Fmi3Type::Binary => ColumnType::Binary,
            _ => ColumnType::Float64,
        }
    }

    /// The name as the FMI 3.0 description writes the type.
    pub fn name(self) -> &'static str {
        match self {
            ColumnType::Float64 => "Float64",
            ColumnType::Float32 => "Float32",
            ColumnType::Int8 => "Int8",
            ColumnType::UInt8 => "UInt8",
            ColumnType::Int16 => "Int16",
            ColumnType::UInt16 => "UInt16",
            ColumnType::Int32 => "Int32",
            ColumnType::UInt32 => "UInt32",
            ColumnType::Int64 => "Int64",
            ColumnType::UInt64 => "UInt64",
            ColumnType::Boolean => "Boolean",
            ColumnType::String => "String",
            ColumnType::Binary => "Binary",
        }
    }

    /// A String or Binary column: its values come as text, not in the row.
    pub fn is_text(self) -> bool {
        matches!(self, ColumnType::String | ColumnType::Binary)
    }

    /// Whether the slot holds the value's bits rather than its f64.
    pub fn in_bits(self) -> bool {
        matches!(self, ColumnType::Int64 | ColumnType::UInt64)
    }

    pub fn is_integer(self) -> bool {
        !matches!(
            self,
            ColumnType::Float64
                | ColumnType::Float32
                | ColumnType::Boolean
                | ColumnType::String
                | ColumnType::Binary
        )
    }

    /// The slot of a word (`fmi_import::word`) of this column's type.
    pub fn slot_of_word(self, w: u64) -> f64 {
        match self {
            ColumnType::Int64 | ColumnType::UInt64 => f64::from_bits(w),
            ColumnType::Float32 => f64::from_bits(w),
            ColumnType::UInt8 | ColumnType::UInt16 | ColumnType::UInt32 => w as f64,
            _ => (w as i64) as f64,
        }
    }

    /// The integer a slot of an integer column holds.
    pub fn integer(self, slot: f64) -> i128 {
        match self {
            ColumnType::Int64 => i128::from(slot.to_bits() as i64),
            ColumnType::UInt64 => i128::from(slot.to_bits()),
            _ => slot as i128,
        }
    }

    /// The value of a slot as a number (the nearest f64 for Int64 and UInt64).
    pub fn number(self, slot: f64) -> f64 {
        match self {
            ColumnType::Int64 => word::to_f64(Fmi3Type::Int64, slot.to_bits()),
            ColumnType::UInt64 => word::to_f64(Fmi3Type::UInt64, slot.to_bits()),
            _ => slot,
        }
    }

    /// The slot of a value read back from a file as text: an integer of an Int64 or UInt64
    /// column into its bits, every other as the f64 it is.
    pub fn parse_slot(self, text: &str) -> Result<f64, String> {
        let text = text.trim();
        match self {
            ColumnType::Int64 => text
                .parse::<i64>()
                .map(|i| f64::from_bits(i as u64))
                .map_err(|e| format!("{text:?} is not an Int64: {e}")),
            ColumnType::UInt64 => text
                .parse::<u64>()
                .map(f64::from_bits)
                .map_err(|e| format!("{text:?} is not a UInt64: {e}")),
            _ => text
                .parse::<f64>()
                .map_err(|e| format!("{text:?} is not a number: {e}")),
        }
    }
}

/// `types[j]`, Float64 where `types` is shorter (a file written without types).
pub fn type_of(types: &[ColumnType], j: usize) -> ColumnType {
    types.get(j).copied().unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_slot_holds_every_value_of_its_type_exactly() {
        let big = u64::MAX - 1;
        let slot = ColumnType::UInt64.slot_of_word(big);
        assert_eq!(ColumnType::UInt64.integer(slot), i128::from(big));
        // The slot of a UInt64 this large is a NaN pattern: compare bits.
        let back = ColumnType::UInt64.parse_slot(&big.to_string()).unwrap();
        assert_eq!(back.to_bits(), slot.to_bits());
        let min = i64::MIN as u64;
        let slot = ColumnType::Int64.slot_of_word(min);
        assert_eq!(ColumnType::Int64.integer(slot), i128::from(i64::MIN));
        assert_eq!(ColumnType::Int8.slot_of_word(-5i64 as u64), -5.0);
        assert_eq!(
            ColumnType::UInt32.slot_of_word(u64::from(u32::MAX)),
            4294967295.0
        );
        let third = word::from_float32(1.0 / 3.0).unwrap();
        assert_eq!(
            ColumnType::Float32.slot_of_word(third),
            f64::from(1.0f32 / 3.0)
        );
    }
}
