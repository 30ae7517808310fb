//! LanderGnc driven through its exported C functions (the same calls a master makes), on
//! the workspace's test kit.
#![allow(dead_code)]

use fmi_testkit::fmi2::*;
use fmi_testkit::{fmi2_functions, Fmi2Functions, Instance};
use std::ops::Deref;

pub static FUNCTIONS: Fmi2Functions = fmi2_functions!(fmu_gnc);

pub mod vr {
    pub const R_NUE: [u32; 3] = [1, 2, 3];
    pub const V_NUE: [u32; 3] = [4, 5, 6];
    pub const Q_BODY_TO_NUE: [u32; 4] = [7, 8, 9, 10];
    pub const OMEGA_BODY: [u32; 3] = [11, 12, 13];
    pub const MASS: u32 = 14;
    pub const THRUST_CMD: u32 = 100;
    pub const TORQUE_CMD_BODY: [u32; 3] = [101, 102, 103];
    pub const GUIDANCE_PHASE: u32 = 122;
    pub const TIME_TO_GO: u32 = 123;
    pub const CONTROL_LAW: u32 = 200;
    pub const PHI_CMD: u32 = 201;
    pub const CONTROL_BANDWIDTH: u32 = 203;
    pub const INPUT_MONITOR: u32 = 242;
    pub const SATURATION_TIME: u32 = 243;
    /// thrust_cmd, torque_cmd_body[1..3], a_cmd_nue[1..3], q_ref[1..4], phi_b, err_*, tilt, tgo
    pub const ALL_REAL_OUTPUTS: [u32; 17] = [
        100, 101, 102, 103, 110, 111, 112, 113, 114, 115, 116, 117, 118, 119, 120, 121, 123,
    ];
}

/// One instance, freed on drop; every call of the test kit's [`Instance`] is available.
pub struct Gnc(Instance);

impl Deref for Gnc {
    type Target = Instance;
    fn deref(&self) -> &Instance {
        &self.0
    }
}

impl Gnc {
    pub fn new() -> Gnc {
        let guid = fmi2_export::guid::<fmu_gnc::LanderGnc>();
        Gnc(Instance::instantiate(&FUNCTIONS, "gnc", &guid))
    }

    /// Set the navigation inputs: r, v, q (scalar first), omega, mass.
    pub fn set_navigation(
        &self,
        r: [f64; 3],
        v: [f64; 3],
        q: [f64; 4],
        w: [f64; 3],
        m: f64,
    ) -> fmi2Status {
        let vrs: Vec<u32> = vr::R_NUE
            .iter()
            .chain(&vr::V_NUE)
            .chain(&vr::Q_BODY_TO_NUE)
            .chain(&vr::OMEGA_BODY)
            .chain(&[vr::MASS])
            .copied()
            .collect();
        let values: Vec<f64> = r
            .iter()
            .chain(&v)
            .chain(&q)
            .chain(&w)
            .chain(&[m])
            .copied()
            .collect();
        self.set_reals(&vrs, &values)
    }
}
