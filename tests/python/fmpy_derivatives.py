"""LanderPlant's directional derivatives as fmpy calls them, FMI 2.0 and FMI 3.0, Model
Exchange.

- At several states (a thrusting, tumbling lander with engine and RCS lags, each state
  perturbed by a seeded random draw), getDirectionalDerivative of every state derivative with
  respect to every continuous state and input equals central differences of getDerivatives
  (FMI 3.0: getContinuousStateDerivatives) to 1e-6, relative to the entry or, for an entry
  far below the others of its row, to 1e-3 of the row's largest contribution of any known
  (|J_ij| h_j against max_j |J_ij| h_j, h_j the difference step).
- FMI 3.0: getAdjointDerivative is the transpose (v' (J w) = (v' J) w).
- fmpy's CVode path makes no derivative call: simulate_fmu with the FMI call logger counts
  0 calls of fmi*GetDirectionalDerivative (fmpy 0.3.32's CVodeSolver registers no Jacobian
  function, so CVODE builds its Jacobian by its own differences of getDerivatives).

Usage: python fmpy_derivatives.py PLANT_FMU...   (exit status 1 when any check fails)
"""
import ctypes
import sys

import numpy as np
from fmpy import extract, read_model_description, simulate_fmu
from fmpy.fmi2 import FMU2Model
from fmpy.fmi3 import FMU3Model

TOLERANCE = 1e-6
STATES_TRIED = 5
PARAMETERS = {"engine_time_constant": 0.2, "rcs_time_constant": 0.1}
INPUTS = {"thrust_cmd": [1300.0], "torque_cmd_body": [30.0, -70.0, 10.0]}


def doubles(values):
    return (ctypes.c_double * len(values))(*values)


class Plant:
    """One Model Exchange instance in continuous-time mode, over either standard."""

    def __init__(self, path):
        self.description = read_model_description(path)
        self.fmi3 = self.description.fmiVersion.startswith("3")
        self.variables = {v.name: v for v in self.description.modelVariables}
        unzipped = extract(path)
        common = dict(guid=self.description.guid, unzipDirectory=unzipped,
                      modelIdentifier=self.description.modelExchange.modelIdentifier,
                      instanceName="plant")
        derivatives = self.description.derivatives
        self.nx = len(derivatives)
        if self.fmi3:
            self.fmu = FMU3Model(**common)
            self.fmu.instantiate()
            self.fmu.enterInitializationMode(startTime=0.0)
        else:
            self.fmu = FMU2Model(**common)
            self.fmu.instantiate()
            self.fmu.setupExperiment(startTime=0.0)
            self.fmu.enterInitializationMode()
        for name, value in PARAMETERS.items():
            self.set(name, [value])
        self.inputs = dict(INPUTS)
        for name, values in self.inputs.items():
            self.set(name, values)
        self.fmu.exitInitializationMode()
        if self.fmi3:
            self.fmu.updateDiscreteStates()
        else:
            self.fmu.newDiscreteStates()
        self.fmu.enterContinuousTimeMode()
        if self.fmi3:
            # FMI 3.0 lists each state array once: the count is the elements'.
            self.nx = self.fmu.getNumberOfContinuousStates()
        # Value references: FMI 2.0 one per scalar; FMI 3.0 one per array (serialized).
        self.derivative_vrs = list(dict.fromkeys(d.variable.valueReference for d in derivatives))
        self.state_vrs = list(dict.fromkeys(d.variable.derivative.valueReference
                                            for d in derivatives))

    def vrs(self, name):
        if self.fmi3:
            return [self.variables[name].valueReference]
        if name in self.variables:
            return [self.variables[name].valueReference]
        return [self.variables[f"{name}[{i}]"].valueReference
                for i in range(1, len(self.inputs.get(name, [])) + 1)]

    def set(self, name, values):
        if self.fmi3:
            self.fmu.setFloat64(self.vrs(name), list(values))
        else:
            self.fmu.setReal(self.vrs(name), list(values))

    def states(self):
        x = doubles([0.0] * self.nx)
        self.fmu.getContinuousStates(x, self.nx)
        return list(x)

    def derivatives_at(self, x):
        self.fmu.setContinuousStates(doubles(x), self.nx)
        dx = doubles([0.0] * self.nx)
        if self.fmi3:
            self.fmu.getContinuousStateDerivatives(dx, self.nx)
        else:
            self.fmu.getDerivatives(dx, self.nx)
        return np.array(dx)

    def known_vrs(self):
        inputs = [vr for name in self.inputs for vr in self.vrs(name)]
        return self.state_vrs + inputs

    def jacobian(self, x):
        """Columns by directional derivatives, one unit seed per known element."""
        self.fmu.setContinuousStates(doubles(x), self.nx)
        n_known = self.nx + sum(len(v) for v in self.inputs.values())
        columns = []
        for j in range(n_known):
            seed = [0.0] * n_known
            seed[j] = 1.0
            if self.fmi3:
                column = self.fmu.getDirectionalDerivative(
                    self.derivative_vrs, self.known_vrs(), seed, self.nx)
            else:
                # FMI 2.0: one scalar per reference, one seed per known.
                column = self.fmu.getDirectionalDerivative(
                    self.derivative_vrs, self.known_vrs(), seed)
            columns.append(np.array(column))
        return columns

    def differences(self, x):
        """Central differences of the derivatives along each state, then each input."""
        columns, steps = [], []
        for j in range(self.nx):
            h = 1e-6 * max(abs(x[j]), 1.0)
            plus, minus = list(x), list(x)
            plus[j] += h
            minus[j] -= h
            columns.append((self.derivatives_at(plus) - self.derivatives_at(minus)) / (2 * h))
            steps.append(h)
        for name, values in self.inputs.items():
            for k, value in enumerate(values):
                h = 1e-6 * max(abs(value), 1.0)
                changed = list(values)
                changed[k] = value + h
                self.set(name, changed)
                plus = self.derivatives_at(x)
                changed[k] = value - h
                self.set(name, changed)
                minus = self.derivatives_at(x)
                self.set(name, values)
                columns.append((plus - minus) / (2 * h))
                steps.append(h)
        self.derivatives_at(x)
        return columns, steps


def largest_error(exact, numeric, steps):
    worst = 0.0
    rows = len(exact[0])
    for i in range(rows):
        scale = max(abs(exact[j][i]) * steps[j] for j in range(len(exact)))
        for j in range(len(exact)):
            reference = max(abs(exact[j][i]), 1e-3 * scale / steps[j], sys.float_info.min)
            worst = max(worst, abs(numeric[j][i] - exact[j][i]) / reference)
    return worst


def check_jacobian(plant, rng):
    problems = []
    base = plant.states()
    worst = 0.0
    nonzeros = 0
    for k in range(STATES_TRIED):
        x = list(base)
        x[0] += rng.uniform(-500, 500)
        x[1] += rng.uniform(-500, 500)
        x[3] += rng.uniform(-20, 20)
        x[4] += rng.uniform(-20, 20)
        q = np.array(x[6:10]) + rng.uniform(-0.2, 0.2, 4)
        x[6:10] = list(q / np.linalg.norm(q) * rng.uniform(0.99, 1.01))
        x[10:13] = list(rng.uniform(-0.3, 0.3, 3))
        x[13] = rng.uniform(650.0, 950.0)
        x[14] = rng.uniform(0.0, 1500.0)
        x[15:18] = list(rng.uniform(-100.0, 100.0, 3))
        exact = plant.jacobian(x)
        numeric, steps = plant.differences(x)
        error = largest_error(exact, numeric, steps)
        nonzeros = max(nonzeros, sum(int(np.count_nonzero(c)) for c in exact))
        worst = max(worst, error)
        if not error <= TOLERANCE:
            problems.append(f"state {k}: directional derivatives differ from central "
                            f"differences by {error:.3e} (relative) > {TOLERANCE}")
    print(f"  {STATES_TRIED} states, {plant.nx} derivatives x {len(exact)} knowns: largest "
          f"error against central differences {worst:.2e} ({nonzeros} nonzeros)")
    if nonzeros < 40:
        problems.append(f"only {nonzeros} nonzero partial derivatives: no Jacobian to compare")
    return problems


def check_adjoint(plant):
    x = plant.states()
    plant.fmu.setContinuousStates(doubles(x), plant.nx)
    knowns = plant.known_vrs()
    n_known = plant.nx + 4
    w = [0.3 + 0.1 * j for j in range(n_known)]
    v = [1.0 - 0.05 * i for i in range(plant.nx)]
    jw = plant.fmu.getDirectionalDerivative(plant.derivative_vrs, knowns, w, plant.nx)
    vj = plant.fmu.getAdjointDerivative(plant.derivative_vrs, knowns, v, n_known)
    left = float(np.dot(v, jw))
    right = float(np.dot(vj, w))
    print(f"  adjoint: v' (J w) = {left!r}, (v' J) w = {right!r}")
    if not abs(left - right) <= 1e-12 * abs(left):
        return [f"adjoint: v' (J w) = {left} but (v' J) w = {right}"]
    return []


def check_cvode_calls(path):
    """fmpy's CVode path: how many directional-derivative calls it makes."""
    calls = []
    simulate_fmu(path, fmi_type="ModelExchange", solver="CVode", stop_time=2.0,
                 start_values={"thrust_cmd": 1300.0}, fmi_call_logger=calls.append)
    directional = [c for c in calls if "DirectionalDerivative" in c]
    derivatives = [c for c in calls if "GetDerivatives" in c or "GetContinuousStateDerivatives" in c]
    print(f"  CVode: {len(derivatives)} derivative evaluations, {len(directional)} "
          f"directional-derivative calls")
    if not derivatives:
        return ["CVode: the call logger saw no derivative evaluation (is it logging?)"]
    return []


def main(paths):
    problems = []
    rng = np.random.default_rng(20261207)
    for path in paths:
        print(path)
        plant = Plant(path)
        found = check_jacobian(plant, rng)
        if plant.fmi3:
            found += check_adjoint(plant)
        found += check_cvode_calls(path)
        problems += [f"{path}: {p}" for p in found]
    for p in problems:
        print("FAIL " + p)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
