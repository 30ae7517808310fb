//! LanderPlant through its FMI 3.0 C functions on the test kit's FMI 3.0 driver
//! ([`Fmi3Instance`]); variables by name (FMI 3.0 keeps one value reference per array).
#![allow(dead_code)]

use fmi_model::Model;
use fmi_testkit::fmi3_ffi::*;
use fmi_testkit::{fmi3_functions, CoSimulationOptions, Fmi3Functions, Fmi3Instance};
use std::ops::Deref;

pub static FUNCTIONS: Fmi3Functions = fmi3_functions!(fmu_plant);

/// The value reference of a declaration (an array's one reference).
pub fn vr(name: &str) -> u32 {
    fmu_plant::LanderPlant::declarations()
        .iter()
        .find(|d| d.name == name)
        .unwrap_or_else(|| panic!("no declaration {name}"))
        .value_reference
}

pub fn token() -> String {
    fmi3_export::instantiation_token::<fmu_plant::LanderPlant>()
}

/// One instance, freed on drop; every call of the kit's [`Fmi3Instance`] is available.
pub struct Plant(pub Fmi3Instance);

impl Deref for Plant {
    type Target = Fmi3Instance;
    fn deref(&self) -> &Fmi3Instance {
        &self.0
    }
}

impl Plant {
    /// A Co-Simulation instance "plant", no Event Mode; `early_return_allowed` as the
    /// master chooses it.
    pub fn co_simulation(early_return_allowed: bool) -> Plant {
        let options = CoSimulationOptions {
            early_return_allowed,
            ..CoSimulationOptions::default()
        };
        Plant(
            Fmi3Instance::co_simulation(&FUNCTIONS, "plant", &token(), options)
                .unwrap_or_else(|log| panic!("fmi3InstantiateCoSimulation: {log:?}")),
        )
    }

    /// A Model Exchange instance "plant".
    pub fn model_exchange() -> Plant {
        Plant(
            Fmi3Instance::model_exchange(&FUNCTIONS, "plant", &token(), false)
                .unwrap_or_else(|log| panic!("fmi3InstantiateModelExchange: {log:?}")),
        )
    }

    /// Every message, one a line.
    pub fn log(&self) -> String {
        self.messages().join("\n")
    }

    /// The `n` elements of a Float64 variable; panics unless the get succeeds.
    pub fn get(&self, name: &str, n: usize) -> Vec<f64> {
        let (status, values) = self.get_float64(&[vr(name)], n);
        assert_eq!(status, fmi3OK, "{}", self.log());
        values
    }

    /// All elements of a Float64 variable.
    pub fn set(&self, name: &str, values: &[f64]) -> fmi3Status {
        self.set_float64(&[vr(name)], values)
    }

    /// Enter and exit initialization at t = 0, no stop time; panics unless both are OK.
    pub fn init(&self) {
        assert_eq!(
            self.enter_initialization_mode(0.0, None),
            fmi3OK,
            "{}",
            self.log()
        );
        assert_eq!(self.exit_initialization_mode(), fmi3OK, "{}", self.log());
    }

    /// The instance's current state, serialized.
    pub fn genuine(&self) -> Vec<u8> {
        let (status, state) = self.get_state();
        assert_eq!(status, fmi3OK, "{}", self.log());
        let (status, bytes) = self.serialize(state);
        assert_eq!(status, fmi3OK, "{}", self.log());
        assert_eq!(self.free_state(state), fmi3OK);
        bytes
    }

    /// fmi3DeserializeFMUState then, if accepted, fmi3SetFMUState and fmi3FreeFMUState.
    pub fn restore(&self, bytes: &[u8]) -> fmi3Status {
        let (status, state) = self.deserialize(bytes);
        if status != fmi3OK {
            assert!(state.is_null());
            return status;
        }
        assert_eq!(self.set_state(state), fmi3OK, "{}", self.log());
        assert_eq!(self.free_state(state), fmi3OK);
        status
    }
}
