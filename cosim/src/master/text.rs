//! String and Binary values of one side (inputs or outputs) of one instance: exchanged
//! through their own buffers, apart from the numeric ones, so that the numeric exchange
//! does no more work than before for a system that has none.
//!
//! Every text output is read whenever the unit's outputs are read after its inputs may have
//! changed (they count as depending on every input); a recorded text column reaches a
//! [`super::Recorder`] through `record_text` when its value changes, Binary as hex
//! (`fmi_import::word::hex`).
use fmi_import::{CallError, Instance};

#[derive(Debug, Default)]
pub(super) struct Texts {
    strings: Slots<String>,
    binaries: Slots<Vec<u8>>,
}

#[derive(Debug, Default)]
struct Slots<T> {
    vrs: Vec<u32>,
    values: Vec<T>,
}

impl<T: Default> Slots<T> {
    fn slot(&mut self, vr: u32) -> usize {
        match self.vrs.iter().position(|&v| v == vr) {
            Some(i) => i,
            None => {
                self.vrs.push(vr);
                self.values.push(T::default());
                self.vrs.len() - 1
            }
        }
    }
}

impl Texts {
    /// Slot of `vr` among the strings (or the binaries), added if new.
    pub(super) fn slot(&mut self, binary: bool, vr: u32) -> usize {
        if binary {
            self.binaries.slot(vr)
        } else {
            self.strings.slot(vr)
        }
    }

    pub(super) fn is_empty(&self) -> bool {
        self.strings.vrs.is_empty() && self.binaries.vrs.is_empty()
    }

    /// Every value empty (the initial inputs of [`super::InitialInputs::Zero`]).
    pub(super) fn clear(&mut self) {
        self.strings.values.iter_mut().for_each(String::clear);
        self.binaries.values.iter_mut().for_each(Vec::clear);
    }

    pub(super) fn set(&self, instance: &mut Instance) -> Result<(), CallError> {
        if !self.strings.vrs.is_empty() {
            let values: Vec<&str> = self.strings.values.iter().map(String::as_str).collect();
            instance.set_string(&self.strings.vrs, &values)?;
        }
        if !self.binaries.vrs.is_empty() {
            let values: Vec<&[u8]> = self.binaries.values.iter().map(Vec::as_slice).collect();
            instance.set_binary(&self.binaries.vrs, &values)?;
        }
        Ok(())
    }

    pub(super) fn get(&mut self, instance: &mut Instance) -> Result<(), CallError> {
        if !self.strings.vrs.is_empty() {
            instance.get_string_into(&self.strings.vrs, &mut self.strings.values)?;
        }
        if !self.binaries.vrs.is_empty() {
            instance.get_binary_into(&self.binaries.vrs, &mut self.binaries.values)?;
        }
        Ok(())
    }

    /// Output slot `from` of `source` into input slot `to` of `self`.
    pub(super) fn copy(&mut self, source: &Texts, binary: bool, from: usize, to: usize) {
        if binary {
            let value = &source.binaries.values[from];
            let slot = &mut self.binaries.values[to];
            slot.clear();
            slot.extend_from_slice(value);
        } else {
            source.strings.values[from].clone_into(&mut self.strings.values[to]);
        }
    }

    /// Whether slot `slot` differs from `text`, the text last recorded for it.
    pub(super) fn differs(&self, binary: bool, slot: usize, text: &str) -> bool {
        if binary {
            fmi_import::word::hex(&self.binaries.values[slot]) != text
        } else {
            self.strings.values[slot] != text
        }
    }

    /// The value of a slot as a result file writes it (a Binary in hex).
    pub(super) fn text(&self, binary: bool, slot: usize) -> String {
        if binary {
            fmi_import::word::hex(&self.binaries.values[slot])
        } else {
            self.strings.values[slot].clone()
        }
    }
}
