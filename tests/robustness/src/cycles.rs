//! Instantiate/initialize/step/free cycles, the unit of the leak check: whatever one cycle
//! allocates, the next must find freed.
use crate::ffi::fmi2OK;
use crate::instance::Fmu;
use crate::reference::{Wiring, STEP_S};

/// Steps per cycle.
pub const STEPS: usize = 10;

/// One cycle: instantiate, initialize, step with inputs set and outputs read, save, serialize,
/// restore and free an FMU state, then free the instance (which frees any state left).
pub fn cycle(fmu: &Fmu, wiring: &Wiring, k: usize) -> Result<(), String> {
    let inst = fmu.instantiate(&format!("cycle{k}"), k.is_multiple_of(2));
    let check = |what: &str, status| {
        if status == fmi2OK {
            Ok(())
        } else {
            Err(format!(
                "cycle {k}: {what} returned {status}: {:?}",
                inst.take_log()
            ))
        }
    };
    check("initialization", inst.init_at(0.0))?;
    for step in 0..STEPS {
        let t = step as f64 * STEP_S;
        check("setting the inputs", wiring.set_inputs(&inst, t))?;
        check("reading the outputs", wiring.get_outputs(&inst).0)?;
        check("fmi2DoStep", inst.step(t, STEP_S))?;
    }
    let (status, mut state) = inst.get_fmu_state();
    check("fmi2GetFMUstate", status)?;
    let bytes = inst
        .serialize(state)
        .map_err(|s| format!("serialize: {s}"))?;
    let (status, mut restored) = inst.deserialize(&bytes);
    check("fmi2DeSerializeFMUstate", status)?;
    check("fmi2SetFMUstate", inst.set_fmu_state(restored))?;
    check("fmi2FreeFMUstate", inst.free_fmu_state(&mut restored))?;
    if k.is_multiple_of(3) {
        // Left for fmi2FreeInstance to free.
        return Ok(());
    }
    check("fmi2FreeFMUstate", inst.free_fmu_state(&mut state))?;
    check("fmi2Terminate", inst.terminate())?;
    Ok(())
}
