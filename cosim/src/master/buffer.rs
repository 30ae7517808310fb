//! Which exchange buffer of an instance's inputs or outputs holds a variable, and the paths
//! of the FMI 3.0 words and of texts, kept out of line so that the Float64, Integer and
//! Boolean exchange does no more work than without them.
use super::resolve::Port;
use fmi_import::{Fmi3Type, VariableKind};

/// The exchange buffer of a port, with the word type of a word's.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Buffer {
    Real,
    /// Integers and enumerations.
    Integer,
    Boolean,
    Word(Fmi3Type),
    String,
    Binary,
}

impl Buffer {
    pub(super) fn of(port: &Port) -> Buffer {
        match (port.word, port.kind) {
            (Some(Fmi3Type::Binary), _) => Buffer::Binary,
            (Some(kind), _) => Buffer::Word(kind),
            (None, VariableKind::Real) => Buffer::Real,
            (None, VariableKind::Boolean) => Buffer::Boolean,
            (None, VariableKind::String) => Buffer::String,
            (None, _) => Buffer::Integer,
        }
    }

    pub(super) fn is_text(self) -> bool {
        matches!(self, Buffer::String | Buffer::Binary)
    }

    /// The type of a recorded column of this buffer.
    pub(super) fn column_type(self) -> crate::results::ColumnType {
        use crate::results::ColumnType;
        match self {
            Buffer::Real => ColumnType::Float64,
            Buffer::Integer => ColumnType::Int32,
            Buffer::Boolean => ColumnType::Boolean,
            Buffer::Word(kind) => ColumnType::of_fmi3(kind),
            Buffer::String => ColumnType::String,
            Buffer::Binary => ColumnType::Binary,
        }
    }
}

/// The row slots of words of type `kind` (see `results::ColumnType`); out of line, so that
/// the loop over the other columns stays as it is without them.
#[inline(never)]
pub(super) fn word_slots(kind: Fmi3Type, row: &mut [f64], words: &[u64]) {
    let column = crate::results::ColumnType::of_fmi3(kind);
    for (value, &w) in row.iter_mut().zip(words) {
        *value = column.slot_of_word(w);
    }
}

/// Which exchange buffer of an [`Io`] holds a variable (enumerations in the integer one);
/// also the tag `record` dispatches on, a plain number being cheaper to match than a
/// [`Buffer`] with its word type.
pub(super) const REAL: u8 = 0;
pub(super) const INTEGER: u8 = 1;
pub(super) const BOOLEAN: u8 = 2;
pub(super) const WORD: u8 = 3;
pub(super) const STRING: u8 = 4;
pub(super) const BINARY: u8 = 5;

pub(super) fn block_index(buffer: Buffer) -> usize {
    usize::from(match buffer {
        Buffer::Real => REAL,
        Buffer::Integer => INTEGER,
        Buffer::Boolean => BOOLEAN,
        Buffer::Word(_) => WORD,
        Buffer::String => STRING,
        Buffer::Binary => BINARY,
    })
}
