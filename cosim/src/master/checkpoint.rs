//! How a simulation saves itself at a communication point and continues a saved run
//! (`saved.rs`): the FMUs' states through the importer, the exchange buffers, the clock.
use super::conventions::Clock;
use super::saved::{
    check, events_before, exchange_of, ordering_text, save_point, version_text, Checkpoints,
    SavedInstance, SavedIo, SavedRun,
};
use super::{Io, MasterError, Simulation};
use std::path::Path;

impl Io {
    pub(super) fn saved(&self) -> SavedIo {
        SavedIo {
            real_vrs: self.real.vrs.clone(),
            real: self.real.values.clone(),
            integer_vrs: self.integer.vrs.clone(),
            integer: self.integer.values.clone(),
            boolean_vrs: self.boolean.vrs.clone(),
            boolean: self.boolean.values.clone(),
        }
    }

    /// Takes the saved values if the layout is this buffer's; else says so.
    pub(super) fn restore(&mut self, saved: &SavedIo) -> Result<(), ()> {
        let fits = saved.real_vrs == self.real.vrs
            && saved.integer_vrs == self.integer.vrs
            && saved.boolean_vrs == self.boolean.vrs
            && saved.real.len() == self.real.values.len()
            && saved.integer.len() == self.integer.values.len()
            && saved.boolean.len() == self.boolean.values.len();
        if !fits {
            return Err(());
        }
        self.real.values.copy_from_slice(&saved.real);
        self.integer.values.copy_from_slice(&saved.integer);
        self.boolean.values.copy_from_slice(&saved.boolean);
        Ok(())
    }
}

/// The error of a failed save, naming the file.
pub(super) fn save_failed(path: &Path, instance: &str, reason: String) -> MasterError {
    MasterError::Checkpoint {
        message: format!(
            "saving the run to {} failed at instance '{instance}': {reason}",
            path.display()
        ),
    }
}

impl Simulation {
    /// What the next runs do about saved runs, checked now: every instance can be saved
    /// (and continued), a saved run fits this system, and the save point is one of its
    /// communication points.
    pub fn set_checkpoints(&mut self, checkpoints: Checkpoints) -> Result<(), MasterError> {
        let asked = checkpoints.resume.is_some() || checkpoints.save.is_some();
        // A saved run carries the Float64, Int32 and Boolean buffers only: a run that
        // exchanges or records FMI 3.0 words, String or Binary would continue without them.
        let others =
            (0..self.units.len()).find(|&u| self.inputs[u].others || self.outputs[u].others);
        if let (true, Some(u)) = (asked, others) {
            return Err(MasterError::Checkpoint {
                message: format!(
                    "instance '{}' exchanges or records values of FMI 3.0 types other than \
                     Float64, Int32, Enumeration and Boolean (or String, Binary), which a saved \
                     run does not carry yet; leave them out of the connections and --record to \
                     save or continue this run",
                    self.units[u].name
                ),
            });
        }
        let fmus = &self.fmus;
        let describe = |i: usize| {
            let fmu: &fmi_import::Fmu = &fmus[i];
            (fmu.fmi_version(), fmu.model_description().clone())
        };
        check(
            &self.system,
            &self.conventions,
            &self.column_names,
            &checkpoints,
            &describe,
        )
        .map_err(|message| MasterError::Checkpoint { message })?;
        if let Some(saved) = &checkpoints.resume {
            self.check_layout(saved)
                .map_err(|message| MasterError::Checkpoint { message })?;
        }
        self.checkpoints = checkpoints;
        Ok(())
    }

    /// The communication point the last run saved at, if it did.
    pub fn saved_at(&self) -> Option<f64> {
        self.saved_at
    }

    /// Whether every buffer of the saved run has this run's layout (the same variables
    /// exchanged and recorded).
    fn check_layout(&self, saved: &SavedRun) -> Result<(), String> {
        for (u, instance) in saved.instances.iter().enumerate() {
            let same = |io: &Io, saved: &SavedIo| {
                io.real.vrs == saved.real_vrs
                    && io.integer.vrs == saved.integer_vrs
                    && io.boolean.vrs == saved.boolean_vrs
            };
            if !same(&self.inputs[u], &instance.inputs)
                || !same(&self.outputs[u], &instance.outputs)
            {
                return Err(format!(
                    "instance '{}' exchanged or recorded other variables when it was saved \
                     (continue with the same connections, --input and --record)",
                    instance.name
                ));
            }
        }
        Ok(())
    }

    /// At the start of a run, after initialization: continues the saved run, if any (the
    /// FMUs' states, the buffers, the clock); the step counter to save at, if any.
    pub(super) fn begin_checkpoints(
        &mut self,
        clock: &mut Clock,
    ) -> Result<Option<u64>, MasterError> {
        self.saved_at = None;
        if let Some(saved) = self.checkpoints.resume.take() {
            let resumed = self.resume(&saved, clock);
            self.checkpoints.resume = Some(saved);
            resumed?;
        }
        match &self.checkpoints.save {
            None => Ok(None),
            Some(request) => save_point(clock, request.at)
                .map(Some)
                .map_err(|message| MasterError::Checkpoint { message }),
        }
    }

    fn resume(&mut self, saved: &SavedRun, clock: &mut Clock) -> Result<(), MasterError> {
        self.check_layout(saved)
            .map_err(|message| MasterError::Checkpoint { message })?;
        for (u, instance) in saved.instances.iter().enumerate() {
            let unit = &mut self.units[u];
            let restored = (|| -> Result<(), fmi_import::CallError> {
                let state = unit.instance.deserialize_fmu_state(&instance.fmu_state)?;
                unit.instance.set_fmu_state(&state)?;
                unit.instance.free_fmu_state(state)?;
                Ok(())
            })();
            restored.map_err(|e| super::call(&unit.name, "restoring its saved FMU state", e))?;
            let layout = self.inputs[u]
                .restore(&instance.inputs)
                .and_then(|()| self.outputs[u].restore(&instance.outputs));
            layout.map_err(|()| MasterError::Checkpoint {
                message: format!(
                    "instance '{}': saved buffers of another size",
                    instance.name
                ),
            })?;
            self.outputs_read[u] = instance.outputs_read;
            // The uninterrupted run noted these when it read them; the row they reach judges.
            let real = &self.outputs[u].real;
            if !real.values.iter().all(|v| v.is_finite()) {
                self.finite.note(u, &real.vrs, &real.values);
            }
        }
        clock.resume((saved.step, saved.accumulated));
        self.now = saved.time;
        Ok(())
    }

    /// Saves the run at the clock's next communication point, before its exchange.
    pub(super) fn save_run(&mut self, clock: &Clock) -> Result<(), MasterError> {
        let Some(request) = self.checkpoints.save.clone() else {
            return Ok(());
        };
        let (step, accumulated) = clock.position();
        let time = clock
            .clone()
            .next_step()
            .map_or_else(|| clock.end_time(), |(time, _)| time);
        let mut instances = Vec::with_capacity(self.units.len());
        for (u, unit) in self.units.iter_mut().enumerate() {
            let serialized = (|| -> Result<Vec<u8>, fmi_import::CallError> {
                let state = unit.instance.get_fmu_state()?;
                let bytes = unit.instance.serialize_fmu_state(&state);
                unit.instance.free_fmu_state(state)?;
                bytes
            })();
            let fmu_state =
                serialized.map_err(|e| save_failed(&request.path, &unit.name, e.to_string()))?;
            let fmu = &self.fmus[u];
            instances.push(SavedInstance {
                name: unit.name.clone(),
                model_name: fmu.model_name().to_owned(),
                token: fmu.model_description().guid.clone(),
                fmi_version: version_text(fmu.fmi_version()).to_owned(),
                fmu_state,
                inputs: self.inputs[u].saved(),
                outputs: self.outputs[u].saved(),
                outputs_read: self.outputs_read[u],
            });
        }
        let saved = SavedRun {
            system: self.system.name.clone(),
            start_time: self.system.start_time,
            step_size: self.system.step_size,
            stop_time: self.system.stop_time,
            ordering: ordering_text(self.system.ordering).to_owned(),
            conventions: format!("{:?}", self.conventions),
            time,
            step,
            accumulated,
            exchange: exchange_of(&self.system),
            columns: self.column_names.clone(),
            events_before: events_before(&self.system, time),
            instances,
            rows_before: None,
        };
        saved
            .write(&request.path)
            .map_err(|e| MasterError::Checkpoint {
                message: format!("writing the saved run {}: {e}", request.path.display()),
            })?;
        self.saved_at = Some(time);
        Ok(())
    }
}
