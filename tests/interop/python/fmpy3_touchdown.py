"""LanderPlant falling to touchdown in fmpy's own simulate_fmu, FMI 2.0 and FMI 3.0.

With its default parameters and inputs (no thrust, 800 m up, lunar gravity 1.62 m/s^2) the
plant falls freely and touches down at sqrt(800 / 0.81) = 31.43 s, before the 35 s stop
time. Each run below must end without an exception, at the touchdown; the Rust test
(tests/interop/tests/fmpy3_touchdown.rs) compares what each run's last row says.

- `fmi2_cs`: the FMI 2.0 FMU, Co-Simulation: the touchdown step returns fmi2Discard with
  fmi2Terminated; fmpy records the row at fmi2LastSuccessfulTime (the touchdown) and stops.
- `fmi3_cs`: the FMI 3.0 FMU, Co-Simulation, fmpy's defaults (earlyReturnAllowed = false, no
  Event Mode): the touchdown step returns fmi3OK with terminateSimulation and
  lastSuccessfulTime at the touchdown (earlyReturn false). fmpy 0.3.32 reads
  lastSuccessfulTime only after an early return, so it stamps this last row at the step's
  end, t + h, with the touchdown values; `step_over_touchdown` below reads what the FMU
  reports through fmpy's own FMI 3.0 binding.
- `fmi3_cs_early_return`: earlyReturnAllowed = true: the step returns early at the touchdown
  (earlyReturn, lastSuccessfulTime = touchdown), the last row is at the touchdown time.
- `fmi3_cs_event_mode`: the same with eventModeUsed = true (fmpy's use_event_mode).
- `fmi3_me`: the FMI 3.0 FMU, Model Exchange integrated by CVode (relative tolerance
  1e-10): the touchdown is a state event; fmpy records the row at the event and stops on
  the event update's terminateSimulation.

Each run's last row is written as JSON: time, r_nue[2], altitude, v_nue[2], touchdown,
touchdown_time, touchdown_v_nue[1..3], with the number of rows.

Usage: python fmpy3_touchdown.py FMI2_PLANT.fmu FMI3_PLANT.fmu OUT.json
"""
import json
import shutil
import sys

from fmpy import extract, instantiate_fmu, read_model_description, simulate_fmu

STOP_TIME = 35.0
OUTPUT_INTERVAL = 0.1
SCALARS = ["altitude", "touchdown", "touchdown_time"]
VECTORS = {"r_nue": 3, "v_nue": 3, "touchdown_v_nue": 3}


def last_row(path, **kwargs):
    """Runs simulate_fmu on an instance of our own, so that after fmpy's run (which ends with
    fmi*Terminate) the touchdown outputs can still be read from it (getters are allowed in
    Terminated)."""
    description = read_model_description(path)
    fmi3 = description.fmiVersion.startswith("3")
    if fmi3:
        output = SCALARS + list(VECTORS)
    else:
        output = SCALARS + [f"{v}[{i + 1}]" for v, n in VECTORS.items() for i in range(n)]
    unzipdir = extract(path)
    fmu = instantiate_fmu(unzipdir, description, fmi_type=kwargs["fmi_type"],
                          early_return_allowed=kwargs.get("early_return_allowed", False),
                          event_mode_used=kwargs.get("use_event_mode", False))
    result = simulate_fmu(unzipdir, stop_time=STOP_TIME, output_interval=OUTPUT_INTERVAL,
                          output=output, fmu_instance=fmu, model_description=description,
                          **kwargs)
    row = result[-1]

    def element(name, i):
        return float(row[name][i] if fmi3 else row[f"{name}[{i + 1}]"])

    variables = {v.name: v for v in description.modelVariables}

    def read(name, n=None):
        if fmi3:
            return fmu.getFloat64([variables[name].valueReference], nValues=n or 1)
        names = [name] if n is None else [f"{name}[{i + 1}]" for i in range(n)]
        return fmu.getReal([variables[x].valueReference for x in names])

    after = {
        "touchdown": bool(fmu.getBoolean([variables["touchdown"].valueReference])[0]),
        "touchdown_time": float(read("touchdown_time")[0]),
        "touchdown_v_nue": [float(x) for x in read("touchdown_v_nue", 3)],
    }
    fmu.freeInstance()
    shutil.rmtree(unzipdir, ignore_errors=True)
    summary = {
        "rows": len(result),
        "time": float(row["time"]),
        "altitude": float(row["altitude"]),
        "touchdown": bool(row["touchdown"]),
        "touchdown_time": float(row["touchdown_time"]),
        "r_nue_2": element("r_nue", 1),
        "v_nue_2": element("v_nue", 1),
        "touchdown_v_nue": [element("touchdown_v_nue", i) for i in range(3)],
        "after": after,
        # The FMI 3.0 capability flag an FMU that returns early must declare.
        "might_return_early": bool(fmi3 and description.coSimulation.mightReturnEarlyFromDoStep),
    }
    print(f"  {json.dumps(summary)}")
    return summary


def step_over_touchdown(path):
    """One fmi3DoStep(0, 35) through fmpy's FMU3Slave, without early return: what the FMU
    says in doStep's out-arguments when its run ends inside the step."""
    description = read_model_description(path)
    unzipdir = extract(path)
    fmu = instantiate_fmu(unzipdir, description, fmi_type="CoSimulation")
    fmu.enterInitializationMode(startTime=0.0, stopTime=STOP_TIME)
    fmu.exitInitializationMode()
    _, terminate, early_return, last_successful_time = fmu.doStep(
        currentCommunicationPoint=0.0, communicationStepSize=STOP_TIME)
    fmu.terminate()
    fmu.freeInstance()
    shutil.rmtree(unzipdir, ignore_errors=True)
    step = {"terminate_simulation": bool(terminate), "early_return": bool(early_return),
            "last_successful_time": float(last_successful_time)}
    print(f"  {json.dumps(step)}")
    return step


def main(fmi2_plant, fmi3_plant, out_path):
    runs = {}
    for name, path, kwargs in [
        ("fmi2_cs", fmi2_plant, dict(fmi_type="CoSimulation")),
        ("fmi3_cs", fmi3_plant, dict(fmi_type="CoSimulation")),
        ("fmi3_cs_early_return", fmi3_plant,
         dict(fmi_type="CoSimulation", early_return_allowed=True)),
        ("fmi3_cs_event_mode", fmi3_plant,
         dict(fmi_type="CoSimulation", early_return_allowed=True, use_event_mode=True)),
        ("fmi3_me", fmi3_plant,
         dict(fmi_type="ModelExchange", solver="CVode", relative_tolerance=1e-10)),
    ]:
        print(name)
        runs[name] = last_row(path, **kwargs)
    print("fmi3_step_over_touchdown")
    runs["fmi3_step_over_touchdown"] = step_over_touchdown(fmi3_plant)
    with open(out_path, "w") as f:
        json.dump(runs, f, indent=2)
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:]))
