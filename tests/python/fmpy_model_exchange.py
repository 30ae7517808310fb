"""LanderPlant as a Model Exchange FMU, integrated by fmpy's CVode, against analytic solutions
and against the same FMU's Co-Simulation interface.

- free fall from 800 m: r_nue[2] = 800 - 0.81 t^2 to 1e-6 m, touchdown found at
  sqrt(800 / 0.81) = 31.42697 s to 1e-6 s (the event ends the run: terminateSimulation);
- hover (thrust m g, no mass flow): ME and CS agree to 1e-6;
- pure-torque tumbling: ME and CS (at a 1 ms RK4 sub-step) agree to 1e-6.

The same checks run on the FMI 2.0 and the FMI 3.0 FMU: an element such as `r_nue[2]` is a
scalar variable in FMI 2.0 and element 2 of the array `r_nue` in FMI 3.0.

Usage: python fmpy_model_exchange.py PLANT_FMU...   (exit status 1 when any check fails)
"""
import math
import sys

import numpy as np
from fmpy import read_model_description, simulate_fmu

G = 1.62
TOUCHDOWN_EXACT_S = math.sqrt(800.0 / (0.5 * G))
TOLERANCE = 1e-6
# CVode's tolerances: relative 1e-10, absolute 1e-10 x the state nominals (1e-7 m on a
# 1e3 m position nominal); far below the 1e-6 checked, far above round-off.
RTOL = 1e-10
STATES = ["r_nue[1]", "r_nue[2]", "r_nue[3]", "v_nue[1]", "v_nue[2]", "v_nue[3]",
          "q_body_to_nue[1]", "q_body_to_nue[2]", "q_body_to_nue[3]", "q_body_to_nue[4]",
          "omega_body[1]", "omega_body[2]", "omega_body[3]", "mass"]


def split(name):
    """'r_nue[2]' -> ('r_nue', 1); 'mass' -> ('mass', None)."""
    if name.endswith("]"):
        base, index = name[:-1].split("[")
        return base, int(index) - 1
    return name, None


class Fmu:
    """Element names over either standard: FMI 2.0 scalars or FMI 3.0 arrays."""

    def __init__(self, path):
        self.path = path
        self.description = read_model_description(path)
        self.fmi3 = self.description.fmiVersion.startswith("3")
        self.variables = {v.name: v for v in self.description.modelVariables}

    def outputs(self, names):
        if not self.fmi3:
            return list(names)
        return list(dict.fromkeys(split(n)[0] for n in names))

    def start_values(self, values):
        if not self.fmi3:
            return dict(values)
        grouped = {}
        for name, value in values.items():
            base, index = split(name)
            if index is None:
                grouped[base] = value
                continue
            if base not in grouped:
                grouped[base] = [float(v) for v in str(self.variables[base].start).split()]
            grouped[base][index] = value
        return {k: (np.array(v) if isinstance(v, list) else v) for k, v in grouped.items()}

    def column(self, result, name):
        if not self.fmi3:
            return result[name]
        base, index = split(name)
        return result[base] if index is None else result[base][:, index]

    def simulate(self, fmi_type, start_values=None, output=(), **kwargs):
        if fmi_type == "ModelExchange":
            kwargs.update(solver="CVode", relative_tolerance=RTOL)
        return simulate_fmu(self.path, fmi_type=fmi_type,
                            start_values=self.start_values(start_values or {}),
                            output=self.outputs(output), **kwargs)


def check_free_fall(fmu):
    result = fmu.simulate("ModelExchange", stop_time=40.0, output_interval=0.1,
                          record_events=True, output=["r_nue[2]", "v_nue[2]", "touchdown"])
    t = result["time"]
    error = float(np.max(np.abs(fmu.column(result, "r_nue[2]") - (800.0 - 0.5 * G * t * t))))
    t_end = float(t[-1])
    print(f"  free fall: {len(t)} rows, max |r_nue[2] - (800 - 0.81 t^2)| = {error:.2e} m, "
          f"run ends at {t_end!r} s (exact {TOUCHDOWN_EXACT_S!r}, error {t_end - TOUCHDOWN_EXACT_S:.2e} s)")
    problems = []
    if not error <= TOLERANCE:
        problems.append(f"free fall: position error {error:.3e} m > {TOLERANCE}")
    if not abs(t_end - TOUCHDOWN_EXACT_S) <= TOLERANCE:
        problems.append(f"free fall: touchdown at {t_end} s, exact {TOUCHDOWN_EXACT_S} s")
    return problems


def compare(name, fmu, stop_time, start_values, cs_start_values):
    outputs = STATES
    a = fmu.simulate("ModelExchange", stop_time=stop_time, output_interval=0.1,
                     start_values=start_values, output=outputs)
    b = fmu.simulate("CoSimulation", stop_time=stop_time, output_interval=0.1,
                     start_values={**start_values, **cs_start_values}, output=outputs)
    if len(a) != len(b) or np.max(np.abs(a["time"] - b["time"])) > 1e-9:
        return [f"{name}: ME and CS sampled different times ({len(a)} vs {len(b)} rows)"]
    worst = max(float(np.max(np.abs(fmu.column(a, v) - fmu.column(b, v)))) for v in outputs)
    print(f"  {name}: {len(a)} rows, max |ME - CS| over {len(outputs)} states = {worst:.2e}")
    return [] if worst <= TOLERANCE else [f"{name}: ME and CS differ by {worst:.3e} > {TOLERANCE}"]


def check_plant(path):
    fmu = Fmu(path)
    if fmu.description.modelExchange is None or fmu.description.coSimulation is None:
        return [f"{path} does not declare both ModelExchange and CoSimulation"]
    print(f"  FMI {fmu.description.fmiVersion}")
    problems = check_free_fall(fmu)
    problems += compare("hover", fmu, 30.0, {"isp": 1e15, "thrust_cmd": 900.0 * G}, {})
    problems += compare(
        "pure-torque tumbling", fmu, 10.0,
        {"r0_nue[2]": 1e6, "omega0_body[1]": 0.8, "omega0_body[2]": 0.02, "omega0_body[3]": 0.03,
         "torque_cmd_body[1]": 5.0, "torque_cmd_body[2]": -10.0, "torque_cmd_body[3]": 3.0},
        {"integration_step": 1e-3})
    return problems


def main(paths):
    problems = []
    for path in paths:
        print(path)
        problems += [f"{path}: {p}" for p in check_plant(path)]
    for p in problems:
        print("FAIL " + p)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
