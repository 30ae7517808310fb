//! `fmi3GetDirectionalDerivative` and `fmi3GetAdjointDerivative` on element references: the
//! standard takes whole variables (an array's every element in its seed and sensitivity), so
//! the elements asked for are gathered into their arrays, the others seeded with 0, and the
//! elements asked for picked from the answer.
#![allow(unsafe_code)]

use super::Fmi3Instance;
use crate::error::CallError;
use crate::status::Success;
use model_description::fmi3::Fmi3Type;

/// The whole variables behind some element references, and where each element sits in the
/// concatenation of their elements.
struct Arrays {
    vrs: Vec<u32>,
    total: usize,
    /// Per element asked for: its position in the concatenation.
    positions: Vec<usize>,
}

impl Fmi3Instance {
    fn arrays(&self, function: &'static str, elements: &[u32]) -> Result<Arrays, CallError> {
        let mut arrays = Arrays {
            vrs: Vec::new(),
            total: 0,
            positions: Vec::with_capacity(elements.len()),
        };
        let mut offsets: Vec<usize> = Vec::new();
        for &vr in elements {
            let element = self
                .api
                .elements
                .get(vr as usize)
                .filter(|e| e.kind == Fmi3Type::Float64)
                .ok_or_else(|| {
                    self.invalid(
                        function,
                        format!("value reference {vr} is not a Float64 element"),
                    )
                })?;
            let offset = match arrays
                .vrs
                .iter()
                .position(|&v| v == element.value_reference)
            {
                Some(i) => offsets[i],
                None => {
                    arrays.vrs.push(element.value_reference);
                    offsets.push(arrays.total);
                    arrays.total += element.len;
                    arrays.total - element.len
                }
            };
            arrays.positions.push(offset + element.index);
        }
        Ok(arrays)
    }

    /// `sensitivity = J seed` (directional) or `sensitivity = seed^T J` (adjoint), `J` the
    /// partials of `unknowns` with respect to `knowns`; for the adjoint `seed` runs over the
    /// unknowns and `sensitivity` over the knowns.
    pub(crate) fn derivative(
        &mut self,
        adjoint: bool,
        unknowns: &[u32],
        knowns: &[u32],
        seed: &[f64],
        sensitivity: &mut [f64],
    ) -> Result<Success, CallError> {
        let function = if adjoint {
            "fmi3GetAdjointDerivative"
        } else {
            "fmi3GetDirectionalDerivative"
        };
        let (seeded, sensed) = if adjoint {
            (unknowns.len(), knowns.len())
        } else {
            (knowns.len(), unknowns.len())
        };
        self.check_lengths(function, seeded, seed.len())?;
        self.check_lengths(function, sensed, sensitivity.len())?;
        let unknown_arrays = self.arrays(function, unknowns)?;
        let known_arrays = self.arrays(function, knowns)?;
        let (seed_arrays, sense_arrays) = if adjoint {
            (&unknown_arrays, &known_arrays)
        } else {
            (&known_arrays, &unknown_arrays)
        };
        let mut whole_seed = vec![0.0; seed_arrays.total];
        for (&position, &value) in seed_arrays.positions.iter().zip(seed) {
            whole_seed[position] += value;
        }
        let mut whole_sensitivity = vec![0.0; sense_arrays.total];
        let functions = &self.api.functions;
        let call = if adjoint {
            functions.get_adjoint_derivative
        } else {
            functions.get_directional_derivative
        };
        let mark = self.log.mark();
        let noted = crate::blackbox::enter(
            self.black_box,
            if adjoint {
                const { crate::blackbox::function("fmi3GetAdjointDerivative") }
            } else {
                const { crate::blackbox::function("fmi3GetDirectionalDerivative") }
            },
        );
        // SAFETY: every array holds as many elements as passed with it; the sensitivity is
        // writable.
        let raw = unsafe {
            call(
                self.c(),
                unknown_arrays.vrs.as_ptr(),
                unknown_arrays.vrs.len(),
                known_arrays.vrs.as_ptr(),
                known_arrays.vrs.len(),
                whole_seed.as_ptr(),
                whole_seed.len(),
                whole_sensitivity.as_mut_ptr(),
                whole_sensitivity.len(),
            )
        };
        drop(noted);
        let success = self.check(function, mark, raw)?;
        for (value, &position) in sensitivity.iter_mut().zip(&sense_arrays.positions) {
            *value = whole_sensitivity[position];
        }
        Ok(success)
    }
}
