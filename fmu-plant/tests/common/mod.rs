//! LanderPlant driven through its exported C functions, as a master would call them, on the
//! workspace's test kit; variables by name.
#![allow(dead_code)]

use fmi_testkit::fmi2::*;
use fmi_testkit::{fmi2_functions, Fmi2Functions, Instance};
use std::ops::Deref;

pub static FUNCTIONS: Fmi2Functions = fmi2_functions!(fmu_plant);

/// Looks a value reference up by name among the FMI 2.0 variables of the declarations.
pub fn vr(name: &str) -> u32 {
    fmi2_export::variables::<fmu_plant::LanderPlant>()
        .iter()
        .find(|v| v.name() == name)
        .unwrap_or_else(|| panic!("no variable {name}"))
        .value_reference
}

/// One instance, freed on drop; every call of the test kit's [`Instance`] is available.
pub struct Plant(Instance);

impl Deref for Plant {
    type Target = Instance;
    fn deref(&self) -> &Instance {
        &self.0
    }
}

impl Plant {
    pub fn new() -> Plant {
        let guid = fmi2_export::guid::<fmu_plant::LanderPlant>();
        Plant(Instance::instantiate(&FUNCTIONS, "plant", &guid))
    }

    pub fn exit_init(&self) -> fmi2Status {
        self.exit_initialization_mode()
    }

    pub fn init(&self) {
        assert_eq!(self.initialize(), fmi2OK, "{:?}", self.messages());
    }

    pub fn step(&self, t: f64, h: f64) -> fmi2Status {
        self.do_step(t, h)
    }

    pub fn set(&self, name: &str, value: f64) {
        let status = self.set_real(vr(name), value);
        assert_eq!(status, fmi2OK, "set {name}: {:?}", self.messages());
    }

    pub fn set_integer(&self, name: &str, value: i32) {
        let status = self.0.set_integer(vr(name), value);
        assert_eq!(status, fmi2OK, "set {name}: {:?}", self.messages());
    }

    pub fn get(&self, name: &str) -> f64 {
        self.get_real(vr(name))
    }

    pub fn get_many(&self, vrs: &[u32]) -> Vec<f64> {
        let (status, values) = self.get_reals(vrs);
        assert!(status.is_success(), "{status:?} {:?}", self.messages());
        values
    }

    pub fn get_boolean(&self, name: &str) -> bool {
        self.0.get_boolean(vr(name))
    }

    pub fn set_state(&self, state: fmi2FMUstate) {
        assert_eq!(self.0.set_state(state), fmi2OK, "{:?}", self.messages());
    }

    pub fn free_state(&self, state: fmi2FMUstate) {
        assert_eq!(self.0.free_state(state), fmi2OK, "{:?}", self.messages());
    }

    pub fn deserialize(&self, bytes: &[u8]) -> fmi2FMUstate {
        let (status, state) = self.0.deserialize(bytes);
        assert_eq!(status, fmi2OK, "{:?}", self.messages());
        state
    }
}

impl Default for Plant {
    fn default() -> Self {
        Self::new()
    }
}

/// The LanderPlant outputs of the INTERFACE contract, in order.
pub const NAVIGATION_OUTPUTS: [&str; 14] = [
    "r_nue[1]",
    "r_nue[2]",
    "r_nue[3]",
    "v_nue[1]",
    "v_nue[2]",
    "v_nue[3]",
    "q_body_to_nue[1]",
    "q_body_to_nue[2]",
    "q_body_to_nue[3]",
    "q_body_to_nue[4]",
    "omega_body[1]",
    "omega_body[2]",
    "omega_body[3]",
    "mass",
];

pub fn navigation_vrs() -> Vec<u32> {
    NAVIGATION_OUTPUTS.iter().map(|n| vr(n)).collect()
}
