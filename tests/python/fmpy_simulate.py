"""fmpy's `simulate_fmu` runs each FMU given on the command line.

- Oscillator (m x'' = -k x - c x' with m = 1 kg, x(0) = x0, x'(0) = 0) is compared with
  the closed-form solution of the damped oscillator, for its default parameters and for
  parameters set through fmpy's start values.
- Any other FMU (the landers) must run a few communication steps with every recorded
  output finite; their physics is tested by their own crates.

Usage: python fmpy_simulate.py FMU...   (exit status 1 when any check fails)
"""
import math
import sys

import numpy as np
from fmpy import read_model_description, simulate_fmu

# The Oscillator integrates with RK4 at 1/8 of the 0.01 s communication step: its global
# error over 10 s is ~1e-11, so 1e-8 separates a right answer from a wrong one by far.
OSCILLATOR_TOLERANCE = 1e-8
# Steps a lander runs: enough to exercise initialization and stepping, far from touchdown.
LANDER_STEPS = 20


def damped_oscillator(t: np.ndarray, x0: float, k: float, c: float) -> tuple[np.ndarray, np.ndarray]:
    """Position and velocity of m x'' + c x' + k x = 0, m = 1, x(0) = x0, x'(0) = 0 (underdamped)."""
    omega_n = math.sqrt(k)
    zeta = c / (2.0 * omega_n)
    assert zeta < 1.0, "the closed form below is the underdamped one"
    omega_d = omega_n * math.sqrt(1.0 - zeta * zeta)
    decay = np.exp(-zeta * omega_n * t)
    x = x0 * decay * (np.cos(omega_d * t) + zeta * omega_n / omega_d * np.sin(omega_d * t))
    v = -x0 * omega_n**2 / omega_d * decay * np.sin(omega_d * t)
    return x, v


def check_oscillator(path: str) -> list[str]:
    problems = []
    cases = [
        ("default parameters", {}, {"x0": 1.0, "k": 1.0, "c": 0.1}),
        ("set through start values", {"x0": 0.5, "k": 4.0, "c": 0.5}, None),
    ]
    for name, start_values, expected_defaults in cases:
        result = simulate_fmu(path, stop_time=10.0, start_values=start_values, output=["x", "v"])
        parameters = expected_defaults or start_values
        x_ref, v_ref = damped_oscillator(result["time"], **parameters)
        error_x = float(np.max(np.abs(result["x"] - x_ref)))
        error_v = float(np.max(np.abs(result["v"] - v_ref)))
        print(f"  Oscillator, {name}: {len(result)} rows, max |x - x_exact| = {error_x:.2e} m, "
              f"max |v - v_exact| = {error_v:.2e} m/s")
        if len(result) != 1001:
            problems.append(f"{name}: {len(result)} rows, expected 1001 (0 to 10 s by 0.01 s)")
        if not (error_x < OSCILLATOR_TOLERANCE and error_v < OSCILLATOR_TOLERANCE):
            problems.append(f"{name}: differs from the closed-form solution")
    return problems


def check_runs(path: str) -> list[str]:
    description = read_model_description(path)
    step = description.defaultExperiment.stepSize
    outputs = [v.name for v in description.modelVariables
               if v.causality == "output" and v.type == "Real"]
    result = simulate_fmu(path, stop_time=LANDER_STEPS * float(step), output=outputs)
    print(f"  {description.coSimulation.modelIdentifier}: {len(result)} rows of {len(outputs)} Real outputs")
    problems = []
    if len(result) != LANDER_STEPS + 1:
        problems.append(f"{len(result)} rows, expected {LANDER_STEPS + 1}")
    for name in outputs:
        if not np.all(np.isfinite(result[name])):
            problems.append(f"output {name} is not finite")
    return problems


def main(fmu_paths: list[str]) -> int:
    if not fmu_paths:
        print("no FMU given")
        return 2
    failed = 0
    for path in fmu_paths:
        identifier = read_model_description(path).coSimulation.modelIdentifier
        problems = check_oscillator(path) if identifier == "Oscillator" else check_runs(path)
        if problems:
            failed += 1
            print(f"FAILED {path}:")
            for problem in problems:
                print(f"  - {problem}")
        else:
            print(f"ok     {path}")
    print(f"fmpy_simulate: {len(fmu_paths) - failed} passed, {failed} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
