//! The true state the sensors measure (the plant's outputs) and the checks a master's values
//! must pass before anything is measured of them.
use serde::{Deserialize, Serialize};

/// How far `|q_body_to_nue|` may be from 1: the plant normalises its quaternion, so a larger
/// error is a wiring or master mistake, not rounding.
pub const QUATERNION_NORM_TOLERANCE: f64 = 1e-6;

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Truth {
    pub r_nue_m: [f64; 3],
    pub v_nue_mps: [f64; 3],
    pub q_body_to_nue: [f64; 4],
    pub omega_body_radps: [f64; 3],
    pub specific_force_body_mps2: [f64; 3],
}

impl Default for Truth {
    fn default() -> Self {
        Truth {
            r_nue_m: [0.0; 3],
            v_nue_mps: [0.0; 3],
            q_body_to_nue: [1.0, 0.0, 0.0, 0.0],
            omega_body_radps: [0.0; 3],
            specific_force_body_mps2: [0.0; 3],
        }
    }
}

/// An input the sensors refuse to measure: its field (as declared), element and why.
#[derive(Debug, Clone, PartialEq)]
pub struct InputError {
    pub field: &'static str,
    pub index: Option<usize>,
    pub value: f64,
    pub reason: String,
}

impl Truth {
    pub fn validate(&self) -> Result<(), InputError> {
        let vectors: [(&'static str, &[f64]); 5] = [
            ("truth.r_nue_m", &self.r_nue_m),
            ("truth.v_nue_mps", &self.v_nue_mps),
            ("truth.q_body_to_nue", &self.q_body_to_nue),
            ("truth.omega_body_radps", &self.omega_body_radps),
            (
                "truth.specific_force_body_mps2",
                &self.specific_force_body_mps2,
            ),
        ];
        for (field, values) in vectors {
            if let Some(i) = values.iter().position(|v| !v.is_finite()) {
                return Err(InputError {
                    field,
                    index: Some(i),
                    value: values[i],
                    reason: "not finite".into(),
                });
            }
        }
        let q = &self.q_body_to_nue;
        let norm = libm::sqrt(q.iter().map(|x| x * x).sum::<f64>());
        if (norm - 1.0).abs() > QUATERNION_NORM_TOLERANCE {
            return Err(InputError {
                field: "truth.q_body_to_nue",
                index: None,
                value: norm,
                reason: format!(
                    "its norm {norm} is not 1 (tolerance {QUATERNION_NORM_TOLERANCE}): \
                     not an attitude"
                ),
            });
        }
        Ok(())
    }
}
