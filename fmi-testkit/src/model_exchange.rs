//! Model Exchange: the 10 ME entry points of an FMU and a solver of the kit's own that
//! drives them as an ME master does: classical RK4 at a fixed step over `fmi2SetTime`,
//! `fmi2SetContinuousStates` and `fmi2GetDerivatives`, state events located by bisection on
//! `fmi2GetEventIndicators` and handled with `fmi2EnterEventMode` / `fmi2NewDiscreteStates`.
use crate::functions::Fmi2Functions;
use crate::instance::Instance;
use fmi_abi::fmi2::*;

/// The Model Exchange functions of an FMU (the importer's table; `fmi2_me_functions!` fills
/// it from a linked FMU crate).
pub use fmi_import::tables::fmi2::Fmi2ModelExchange as Fmi2MeFunctions;

/// A Model Exchange instance with the solver's time and state vector.
#[derive(Debug)]
pub struct MeSolver {
    pub instance: Instance,
    me: Fmi2MeFunctions,
    pub t: f64,
    pub x: Vec<f64>,
    nz: usize,
}

impl MeSolver {
    /// `fmi2Instantiate` as Model Exchange; set up, enter initialization mode and call
    /// `before_exit` (to set parameters and inputs) before the caller calls [`MeSolver::start`].
    pub fn instantiate(
        functions: &Fmi2Functions,
        me: Fmi2MeFunctions,
        guid: &str,
        nx: usize,
        nz: usize,
    ) -> MeSolver {
        let instance =
            Instance::new_as(functions, "model-exchange", guid, false, fmi2ModelExchange)
                .unwrap_or_else(|log| panic!("fmi2Instantiate (ME) returned NULL: {log:?}"));
        instance.enter_init();
        MeSolver {
            instance,
            me,
            t: 0.0,
            x: vec![f64::NAN; nx],
            nz,
        }
    }

    fn ok(&self, status: fmi2Status, what: &str) {
        assert_eq!(status, fmi2OK, "{what}: {:?}", self.instance.messages());
    }

    /// Ends initialization, runs the initial event update and enters continuous-time mode.
    pub fn start(&mut self) {
        let c = self.instance.component();
        self.ok(
            self.instance.exit_initialization_mode(),
            "fmi2ExitInitializationMode",
        );
        let mut info = fmi2EventInfo::default();
        // SAFETY: a live instance and out-parameters of the right types and lengths.
        unsafe {
            self.ok(
                (self.me.new_discrete_states)(c, &mut info),
                "fmi2NewDiscreteStates",
            );
            self.ok(
                (self.me.enter_continuous_time_mode)(c),
                "fmi2EnterContinuousTimeMode",
            );
            let n = self.x.len();
            let status = (self.me.get_continuous_states)(c, self.x.as_mut_ptr(), n);
            self.ok(status, "fmi2GetContinuousStates");
        }
    }

    /// Sets time and states, then reads `n` values with `read`.
    fn evaluate(&self, t: f64, x: &[f64], read: fmi2GetRealVectorTYPE, n: usize) -> Vec<f64> {
        let c = self.instance.component();
        let mut values = vec![f64::NAN; n];
        // SAFETY: as in `start`.
        unsafe {
            self.ok((self.me.set_time)(c, t), "fmi2SetTime");
            self.ok(
                (self.me.set_continuous_states)(c, x.as_ptr(), x.len()),
                "fmi2SetContinuousStates",
            );
            self.ok(
                read(c, values.as_mut_ptr(), n),
                "reading a continuous vector",
            );
        }
        values
    }

    fn derivatives(&self, t: f64, x: &[f64]) -> Vec<f64> {
        self.evaluate(t, x, self.me.get_derivatives, x.len())
    }

    fn indicators(&self, t: f64, x: &[f64]) -> Vec<f64> {
        self.evaluate(t, x, self.me.get_event_indicators, self.nz)
    }

    /// The classical RK4 step of size `h` from the solver's state.
    fn rk4(&self, h: f64) -> Vec<f64> {
        let (t, x) = (self.t, &self.x);
        let at =
            |k: &[f64], s: f64| -> Vec<f64> { x.iter().zip(k).map(|(a, b)| a + s * b).collect() };
        let k1 = self.derivatives(t, x);
        let k2 = self.derivatives(t + h / 2.0, &at(&k1, h / 2.0));
        let k3 = self.derivatives(t + h / 2.0, &at(&k2, h / 2.0));
        let k4 = self.derivatives(t + h, &at(&k3, h));
        (0..x.len())
            .map(|i| x[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]))
            .collect()
    }

    /// One step of `h`, cut at the first indicator crossing (from > 0 to <= 0, located to
    /// 1e-13 s) where the event is handled; returns whether the FMU ended the simulation.
    pub fn step(&mut self, h: f64) -> bool {
        let z0 = self.indicators(self.t, &self.x);
        let crossed = |z1: &[f64]| z0.iter().zip(z1).any(|(a, b)| *a > 0.0 && *b <= 0.0);
        let x1 = self.rk4(h);
        if !crossed(&self.indicators(self.t + h, &x1)) {
            self.t += h;
            self.x = x1;
            self.completed();
            return false;
        }
        let (mut lo, mut hi) = (0.0, h);
        while hi - lo > 1e-13 {
            let mid = 0.5 * (lo + hi);
            let xm = self.rk4(mid);
            if crossed(&self.indicators(self.t + mid, &xm)) {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        self.x = self.rk4(hi);
        self.t += hi;
        self.event()
    }

    fn completed(&self) {
        let c = self.instance.component();
        let (mut enter, mut terminate) = (fmi2False, fmi2False);
        // SAFETY: as in `start`.
        unsafe {
            self.ok((self.me.set_time)(c, self.t), "fmi2SetTime");
            self.ok(
                (self.me.set_continuous_states)(c, self.x.as_ptr(), self.x.len()),
                "fmi2SetContinuousStates",
            );
            self.ok(
                (self.me.completed_integrator_step)(c, fmi2True, &mut enter, &mut terminate),
                "fmi2CompletedIntegratorStep",
            );
        }
    }

    /// The event at the solver's time; true when the FMU ends the simulation.
    fn event(&mut self) -> bool {
        let c = self.instance.component();
        let mut info = fmi2EventInfo::default();
        // SAFETY: as in `start`.
        unsafe {
            self.ok((self.me.set_time)(c, self.t), "fmi2SetTime");
            self.ok(
                (self.me.set_continuous_states)(c, self.x.as_ptr(), self.x.len()),
                "fmi2SetContinuousStates",
            );
            self.ok((self.me.enter_event_mode)(c), "fmi2EnterEventMode");
            let status = (self.me.new_discrete_states)(c, &mut info);
            assert!(status.is_success(), "{:?}", self.instance.messages());
            if info.valuesOfContinuousStatesChanged == fmi2True {
                let n = self.x.len();
                let status = (self.me.get_continuous_states)(c, self.x.as_mut_ptr(), n);
                self.ok(status, "fmi2GetContinuousStates");
            }
            if info.terminateSimulation == fmi2False {
                self.ok(
                    (self.me.enter_continuous_time_mode)(c),
                    "fmi2EnterContinuousTimeMode",
                );
            }
        }
        info.terminateSimulation == fmi2True
    }
}
