//! LanderPlant falling to touchdown in fmpy's `simulate_fmu`
//! (tests/interop/python/fmpy3_touchdown.py): the FMI 2.0 FMU in Co-Simulation, the FMI 3.0
//! FMU in Co-Simulation (without early return, with it, with Event Mode too) and in Model
//! Exchange under CVode. Every run must end without an exception at the touchdown, with the
//! same touchdown as the FMI 2.0 run and as the closed form of the free fall.
//!
//! Expectations, independent of the FMI 3.0 layer: the closed form (from 800 m at
//! g = 1.62 m/s^2, no thrust: touchdown at t = sqrt(800 / 0.81) s, v = -g t), and the FMI 2.0
//! FMU's own touchdown through fmpy's FMI 2.0 path (fmi2Discard + fmi2Terminated).
//! Tolerances: the Co-Simulation runs share the plant's integrator, its event location and
//! the communication grid, so their touchdown values must equal the FMI 2.0 run's exactly;
//! CVode (relative tolerance 1e-10) and the closed form are held to 1e-6 s and 1e-5 m/s.
use interop_tests::{fmu_path, python, scratch};
use serde_json::Value;
use system_tests::fmi3_fmu_path;

const G: f64 = 1.62;

struct Run<'a> {
    name: &'a str,
    json: &'a Value,
}

impl Run<'_> {
    fn f(&self, key: &str) -> f64 {
        self.json[key]
            .as_f64()
            .unwrap_or_else(|| panic!("{}: no number {key}", self.name))
    }
    fn touchdown_v(&self) -> [f64; 3] {
        let v = self.json["touchdown_v_nue"]
            .as_array()
            .unwrap_or_else(|| panic!("{}: no touchdown_v_nue", self.name));
        [0, 1, 2].map(|i| v[i].as_f64().unwrap())
    }
}

#[test]
fn fmpy_simulate_fmu_runs_the_fmi3_plant_through_touchdown_like_the_fmi2_plant() {
    // GIVEN the plant with its defaults: a free fall from 800 m, touching down before 35 s
    let t_exact = (800.0 / (0.5 * G)).sqrt();
    let v_exact = -G * t_exact;
    assert!(t_exact < 35.0);

    // WHEN fmpy's simulate_fmu runs it to 35 s, FMI 2.0 and FMI 3.0, CS and ME
    let dir = scratch("interop-fmpy3-touchdown-");
    let out = dir.path().join("touchdown.json");
    python::run(
        "fmpy3_touchdown.py",
        [
            fmu_path("LanderPlant").as_os_str(),
            fmi3_fmu_path("LanderPlant").as_os_str(),
            out.as_os_str(),
        ],
    );
    let text = std::fs::read_to_string(&out).unwrap();
    let runs: Value = serde_json::from_str(&text).unwrap();
    let run = |name| Run {
        name,
        json: &runs[name],
    };

    // THEN the FMI 2.0 run (the reference) ends at its touchdown, as the closed form says
    let reference = run("fmi2_cs");
    let t_td = reference.f("touchdown_time");
    let v_td = reference.touchdown_v();
    println!(
        "FMI 2.0 CS touchdown: t = {t_td} s (closed form {t_exact}, {:+.2e}), v = {:?} m/s \
         (closed form {v_exact}, {:+.2e})",
        t_td - t_exact,
        v_td,
        v_td[1] - v_exact
    );
    assert!((t_td - t_exact).abs() < 1e-6, "touchdown time {t_td}");
    assert!(
        (v_td[1] - v_exact).abs() < 1e-5,
        "touchdown velocity {v_td:?}"
    );
    assert_eq!(
        reference.f("time"),
        t_td,
        "FMI 2.0: the last row is the touchdown"
    );

    for name in [
        "fmi2_cs",
        "fmi3_cs",
        "fmi3_cs_early_return",
        "fmi3_cs_event_mode",
        "fmi3_me",
    ] {
        let r = run(name);
        // what the instance says once fmpy has terminated it
        let after = Run {
            name,
            json: &r.json["after"],
        };
        let (time, td_time, td_v) = (r.f("time"), r.f("touchdown_time"), r.touchdown_v());
        let (after_time, after_v) = (after.f("touchdown_time"), after.touchdown_v());
        println!(
            "{name}: {} rows, last row t = {time} s, altitude {:.3e} m, touchdown flag {}; \
             touchdown_time {after_time} s ({:+.2e} vs FMI 2.0), touchdown v_nue[2] {} m/s \
             ({:+.2e} vs FMI 2.0)",
            r.f("rows"),
            r.f("altitude"),
            r.json["touchdown"],
            after_time - t_td,
            after_v[1],
            after_v[1] - v_td[1]
        );
        // the run ended at the touchdown, before the stop time, on the touchdown state
        assert!(time < 35.0, "{name}: ran to {time} s");
        assert!(
            r.f("altitude").abs() < 1e-6,
            "{name}: altitude {}",
            r.f("altitude")
        );
        assert!(
            r.f("r_nue_2").abs() < 1e-6,
            "{name}: r_nue[2] {}",
            r.f("r_nue_2")
        );
        // touched down, and the last row's state is the touchdown state
        assert_eq!(
            after.json["touchdown"],
            Value::Bool(true),
            "{name}: touchdown flag"
        );
        assert_eq!(
            r.f("v_nue_2"),
            after_v[1],
            "{name}: v_nue[2] at the last row"
        );
        if name == "fmi3_me" {
            // CVode's own event location. fmpy records the event row before the event
            // update that sets the touchdown outputs, so they are read after the run.
            assert!(
                (after_time - t_td).abs() < 1e-6,
                "{name}: touchdown at {after_time} s"
            );
            assert!(
                (after_v[1] - v_td[1]).abs() < 1e-5,
                "{name}: touchdown v {after_v:?}"
            );
            assert_eq!(time, after_time, "{name}: the last row is the event");
            continue;
        }
        assert_eq!(
            (td_time, td_v),
            (after_time, after_v),
            "{name}: frozen outputs"
        );
        // Co-Simulation: the same integrator on the same grid as the FMI 2.0 run, and the
        // last row already carries the touchdown outputs
        assert_eq!(
            r.json["touchdown"],
            Value::Bool(true),
            "{name}: touchdown flag"
        );
        assert_eq!(td_time, t_td, "{name}: touchdown time");
        assert_eq!(td_v, v_td, "{name}: touchdown velocity");
        match name {
            // without early return fmpy stamps the last row at the step's end (it reads
            // lastSuccessfulTime only after an early return), with the touchdown values
            "fmi3_cs" => assert!(
                time > td_time && time - td_time <= 0.1 + 1e-9,
                "{name}: last row at {time} s, touchdown at {td_time} s"
            ),
            "fmi3_cs_early_return" | "fmi3_cs_event_mode" => {
                assert_eq!(time, td_time, "{name}: early return at the touchdown");
                // an FMU that returns early says so in its model description
                assert_eq!(
                    r.json["might_return_early"],
                    Value::Bool(true),
                    "{name}: mightReturnEarlyFromDoStep"
                );
            }
            _ => {}
        }
    }

    // AND one step over the touchdown without early return, through fmpy's FMI 3.0 binding,
    // reports the FMU's internal time as lastSuccessfulTime (FMI 3.0, fmi3DoStep: "the
    // internal time of the FMU when fmi3DoStep returns, for any value of earlyReturn"): the
    // touchdown (the closed form's, the one step integrating on its own grid), not 35 s
    let step = &runs["fmi3_step_over_touchdown"];
    assert_eq!(step["terminate_simulation"], Value::Bool(true), "{step}");
    assert_eq!(step["early_return"], Value::Bool(false), "{step}");
    let last = step["last_successful_time"].as_f64().unwrap();
    assert!((last - t_exact).abs() < 1e-6, "{step}");
}
