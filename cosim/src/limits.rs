//! The limits of a supervised run (a scenario's `[limits]`, the command line's timeouts):
//! data the system description carries and the supervisor enforces.

use std::time::Duration;

/// Per-call and per-run limits of a supervised run; each `None` takes its default.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Limits {
    /// Longest one FMU call may take (also the longest stretch with no call started). 60 s.
    pub call_timeout_s: Option<f64>,
    /// Longest one run may take, from its start to its last row. 3600 s.
    pub run_timeout_s: Option<f64>,
    /// The worker's address space in MB (a larger allocation fails). By default 80 % of
    /// the memory available when the worker starts.
    pub memory_mb: Option<f64>,
}

impl Limits {
    pub const DEFAULT_CALL_TIMEOUT_S: f64 = 60.0;
    pub const DEFAULT_RUN_TIMEOUT_S: f64 = 3600.0;

    /// These limits where set, else `fallback`'s.
    pub fn or(self, fallback: Limits) -> Limits {
        Limits {
            call_timeout_s: self.call_timeout_s.or(fallback.call_timeout_s),
            run_timeout_s: self.run_timeout_s.or(fallback.run_timeout_s),
            memory_mb: self.memory_mb.or(fallback.memory_mb),
        }
    }

    /// Every problem with the values, naming each (`where_` says where they came from).
    pub fn problems(&self, where_: &str) -> Vec<String> {
        [
            ("call_timeout_s", self.call_timeout_s),
            ("run_timeout_s", self.run_timeout_s),
            ("memory_mb", self.memory_mb),
        ]
        .into_iter()
        .filter_map(|(name, value)| {
            let value = value?;
            (!(value.is_finite() && value > 0.0))
                .then(|| format!("{where_}: {name} = {value} must be a positive number"))
        })
        .collect()
    }

    pub fn call_timeout_s(&self) -> f64 {
        self.call_timeout_s.unwrap_or(Self::DEFAULT_CALL_TIMEOUT_S)
    }

    pub fn run_timeout_s(&self) -> f64 {
        self.run_timeout_s.unwrap_or(Self::DEFAULT_RUN_TIMEOUT_S)
    }

    pub(crate) fn call_timeout(&self) -> Duration {
        Duration::from_secs_f64(self.call_timeout_s())
    }

    pub(crate) fn run_timeout(&self) -> Duration {
        Duration::from_secs_f64(self.run_timeout_s())
    }

    /// The worker's address-space limit in bytes; 0 for none (memory unknown).
    pub fn memory_bytes(&self) -> u64 {
        match self.memory_mb {
            Some(mb) => (mb * 1e6) as u64,
            None => crate::memory::available_bytes()
                .map_or(0, |bytes| (crate::memory::USABLE_FRACTION * bytes) as u64),
        }
    }
}
