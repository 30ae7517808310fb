"""The Gauss-Seidel master of fmpy_master.py over fmpy's FMU3Slave and the FMI 3.0 FMUs
(target/fmu/fmi3/), so that the paper scenario flown through FMI 3.0 can be compared bit for
bit with the FMI 2.0 pair in the Rust harness, using only call orders FMI 3.0 allows.

The FMI 2.0 master sets a unit's inputs and reads its outputs at the same communication point
(`fmi2SetReal` then `fmi2GetReal`), so LanderGnc's command at t_k is computed from the plant's
state at t_k. FMI 3.0 forbids that order in Step Mode: "Calling fmi3Get{VariableType} is not
allowed after fmi3Set{VariableType} without calling fmi3DoStep in between" (FMI 3.0, 4.2.1,
State: Step Mode). Which orders are left, and the delay each gives:

- Event Mode (`eventModeUsed = true` at instantiation; what this master does for every unit
  whose ModelStructure makes an output depend on an input, LanderGnc and LanderPlant): at
  each communication point fmi3EnterEventMode, set the inputs, get the outputs (in Event Mode
  a get after a set is allowed and returns the outputs of the inputs at that instant),
  fmi3UpdateDiscreteStates, fmi3EnterStepMode, then fmi3DoStep. No delay: the command applied
  over [t_k, t_k+1] is computed from the plant's state at t_k, as in the FMI 2.0 Gauss-Seidel
  loop, and the recorded rows are bit-identical to it.
- Step Mode alone: set the inputs at t_k, fmi3DoStep, get the outputs after the step. The
  GNC's outputs read at t_k+1 were computed from the inputs set at t_k, so the plant applies
  over [t_k+1, t_k+2] a command computed from its state at t_k: one communication step of
  delay (the Jacobi loop of docs/interface.md, whatever the exchange order). `--step-mode`
  flies that loop; it matches the harness's Jacobi run bit for bit.
- A unit whose outputs depend on no input (none in this system; LanderNav in FMI 2.0) could
  stay in Step Mode: its inputs are set before the step and nothing is read after them; the
  values read right after the previous step are its outputs at t_k. Such a unit is
  instantiated with `eventModeUsed = false` here and only ever set, stepped and read.

Same exchange, same order and same communication points as fmpy_master.py otherwise. What
differs is FMI 3.0 itself: a vector is one array variable, so an input array is written
whole (its connected elements from the freshest outputs, the others kept), outputs are read
as arrays and recorded element by element under the FMI 2.0 names (`plant.r_nue[2]`);
integers are Int32 and enumerations Int64. The system JSON is the one fmpy_master.py reads;
each FMU path is mapped to its FMI 3.0 twin in the `fmi3` folder beside it. Early return is
not allowed (`earlyReturnAllowed = false`): a step that meets touchdown still ends at t + h
with `terminateSimulation`, and the loop stops after recording that row.

Usage: python fmpy3_master.py SYSTEM.json OUT.csv [--step-mode]

--step-mode: Step Mode alone for every unit (eventModeUsed = false), to measure the delay.
"""
import json
import os
import shutil
import sys

from fmpy import extract, read_model_description
from fmpy.fmi3 import FMU3Slave

from results import write_csv


def split(name: str):
    """'r_nue[2]' -> ('r_nue', 1); 'mass' -> ('mass', None)."""
    if name.endswith("]"):
        base, index = name[:-1].split("[")
        return base, int(index) - 1
    return name, None


def size(variable) -> int:
    return int(variable.dimensions[0].start) if variable.dimensions else 1


def start_values(variable) -> list:
    if variable.start is None:
        return [0.0] * size(variable)
    return [float(x) for x in str(variable.start).split()]


class Unit:
    def __init__(self, name: str, fmu_path: str, step_mode: bool = False):
        self.name = name
        self.description = read_model_description(fmu_path)
        self.variables = {v.name: v for v in self.description.modelVariables}
        self.unzip_dir = extract(fmu_path)
        self.fmu = FMU3Slave(guid=self.description.guid,
                             unzipDirectory=self.unzip_dir,
                             modelIdentifier=self.description.coSimulation.modelIdentifier,
                             instanceName=name)
        self.outputs = [v for v in self.description.modelVariables if v.causality == "output"]
        # Recorded under FMI 2.0 scalar names, in declaration and element order.
        self.columns = [f"{v.name}[{i + 1}]" if v.dimensions else v.name
                        for v in self.outputs for i in range(size(v))]
        self.output_values = {c: 0.0 for c in self.columns}
        # The current value of every input and parameter array, to write arrays whole.
        self.arrays = {}
        # (input scalar name, source unit, source output scalar name), in connection order.
        self.links = []
        # Same-instant feedthrough: some output depends on some input (an Output element
        # without `dependencies` depends on everything). Such a unit is exchanged in Event Mode.
        inputs = {v.name for v in self.description.modelVariables if v.causality == "input"}
        self.event_mode = any(
            u.dependencies is None or any(d.name in inputs for d in u.dependencies)
            for u in self.description.outputs) and not step_mode
        self.in_event_mode = False
        self.in_step_mode = False
        # Step Mode only: an input was set since the last fmi3DoStep, so no get may follow.
        self.set_since_step = False

    def instantiate(self) -> None:
        self.fmu.instantiate(eventModeUsed=self.event_mode, earlyReturnAllowed=False)

    def enter_event_mode(self) -> None:
        """From Step Mode to Event Mode (a no-op where already there, or without Event Mode)."""
        if self.event_mode and not self.in_event_mode:
            self.fmu.enterEventMode()
            self.in_event_mode, self.in_step_mode = True, False

    def enter_step_mode(self) -> bool:
        """Ends the event instant: fmi3UpdateDiscreteStates until nothing more needs an
        update, then fmi3EnterStepMode. True when the FMU asks to terminate."""
        if not self.in_event_mode:
            return False
        while True:
            (update_needed, terminate, _, _, _, _) = self.fmu.updateDiscreteStates()
            if terminate:
                return True
            if not update_needed:
                break
        self.fmu.enterStepMode()
        self.in_event_mode, self.in_step_mode = False, True
        return False

    def exchange(self) -> None:
        """Inputs from the freshest outputs, then this unit's outputs at the same instant:
        in Event Mode a get may follow a set. Without Event Mode the outputs depend on no
        input, so only the inputs are set and the outputs read after the last step stand."""
        self.set_inputs()
        if self.in_event_mode:
            self.get_outputs()

    def array(self, base: str) -> list:
        if base not in self.arrays:
            self.arrays[base] = start_values(self.variables[base])
        return self.arrays[base]

    def set_parameter(self, name: str, value) -> None:
        base, index = split(name)
        variable = self.variables[base]
        if variable.type == "Float64":
            values = self.array(base)
            values[0 if index is None else index] = float(value)
            self.fmu.setFloat64([variable.valueReference], values)
        elif variable.type == "Int32":
            self.fmu.setInt32([variable.valueReference], [int(value)])
        elif variable.type == "Enumeration":
            self.fmu.setInt64([variable.valueReference], [int(value)])
        elif variable.type == "Boolean":
            self.fmu.setBoolean([variable.valueReference], [bool(value)])
        else:
            self.fmu.setString([variable.valueReference], [str(value)])

    def step(self, currentCommunicationPoint: float, communicationStepSize: float):
        self.set_since_step = False
        return self.fmu.doStep(currentCommunicationPoint=currentCommunicationPoint,
                               communicationStepSize=communicationStepSize)

    def set_inputs(self) -> None:
        if self.in_step_mode:
            self.set_since_step = True
        touched = []
        for name, source, output in self.links:
            base, index = split(name)
            values = self.array(base)
            values[0 if index is None else index] = source.output_values[output]
            if base not in touched:
                touched.append(base)
        floats = [b for b in touched if self.variables[b].type == "Float64"]
        if floats:
            self.fmu.setFloat64([self.variables[b].valueReference for b in floats],
                                [x for b in floats for x in self.arrays[b]])
        for base in touched:
            variable = self.variables[base]
            if variable.type == "Int32":
                self.fmu.setInt32([variable.valueReference], [int(self.arrays[base][0])])
            elif variable.type == "Enumeration":
                self.fmu.setInt64([variable.valueReference], [int(self.arrays[base][0])])

    def get_outputs(self) -> None:
        # The order FMI 3.0 forbids in Step Mode (4.2.1): a get after a set without a step.
        assert not self.set_since_step, f"{self.name}: get after set in Step Mode"

        def store(variables, values):
            k = 0
            for v in variables:
                for i in range(size(v)):
                    key = f"{v.name}[{i + 1}]" if v.dimensions else v.name
                    self.output_values[key] = float(values[k])
                    k += 1

        floats = [v for v in self.outputs if v.type == "Float64"]
        if floats:
            store(floats, self.fmu.getFloat64([v.valueReference for v in floats],
                                              nValues=sum(size(v) for v in floats)))
        for kind, get in (("Int32", self.fmu.getInt32), ("Enumeration", self.fmu.getInt64),
                          ("Boolean", self.fmu.getBoolean)):
            chosen = [v for v in self.outputs if v.type == kind]
            if chosen:
                values = get([v.valueReference for v in chosen])
                store(chosen, [1.0 if x is True else 0.0 if x is False else x for x in values])


def step_count(start: float, stop: float, h: float) -> int:
    ratio = (stop - start) / h
    if abs(ratio - round(ratio)) < 1e-9 * max(ratio, 1.0):
        return int(round(ratio))
    return int(-(-ratio // 1))


def fmi3_twin(path: str) -> str:
    folder, file = os.path.split(path)
    return os.path.join(folder, "fmi3", file)


def simulate(system: dict, step_mode: bool = False):
    """`step_mode`: no unit uses Event Mode, whatever its feedthrough (the one-step delay)."""
    units = [Unit(i["name"], fmi3_twin(i["fmu"]), step_mode) for i in system["instances"]]
    by_name = {u.name: u for u in units}
    for source, destination in system["connections"]:
        from_unit, from_var = source.split(".", 1)
        to_unit, to_var = destination.split(".", 1)
        by_name[to_unit].links.append((to_var, by_name[from_unit], from_var))

    start, stop, h = system["start_time"], system["stop_time"], system["step_size"]
    columns = [(u, c) for u in units for c in u.columns]
    times, rows = [], []

    def record(time: float) -> None:
        times.append(time)
        rows.append([u.output_values[c] for u, c in columns])

    for unit, instance in zip(units, system["instances"]):
        unit.instantiate()
        for name, value in instance["parameters"]:
            unit.set_parameter(name, value)
        unit.fmu.enterInitializationMode(startTime=start, stopTime=stop)
    # Initialization Mode: sets and gets in any order.
    for unit in units:
        unit.get_outputs()
    for unit in units:
        unit.set_inputs()
        unit.get_outputs()
    for unit in units:
        unit.fmu.exitInitializationMode()
        # eventModeUsed: the instance is now in Event Mode; otherwise in Step Mode.
        unit.in_event_mode, unit.in_step_mode = unit.event_mode, not unit.event_mode
    for unit in units:
        unit.get_outputs()

    steps = step_count(start, stop, h)
    time = start
    terminated = False
    for k in range(steps):
        time = start + k * h
        step = stop - time if k + 1 == steps else h
        # Gauss-Seidel at t_k: each unit in Event Mode sets its inputs and reads its outputs.
        for unit in units:
            unit.enter_event_mode()
            unit.exchange()
        record(time)
        for unit in units:
            terminated |= unit.enter_step_mode()
        if terminated:
            break
        for unit in units:
            (_, terminate, early, _) = unit.step(currentCommunicationPoint=time,
                                                 communicationStepSize=step)
            assert not early, f"{unit.name} returned early without earlyReturnAllowed"
            terminated |= terminate
        # Step Mode, after fmi3DoStep and before any set: outputs may be read.
        for unit in units:
            unit.get_outputs()
        time = stop if k + 1 == steps else start + (k + 1) * h
        if terminated:
            break
    if not terminated:
        for unit in units:
            unit.enter_event_mode()
            unit.exchange()
        for unit in units:
            unit.enter_step_mode()
    record(time)

    for unit in units:
        unit.fmu.terminate()
        unit.fmu.freeInstance()
        shutil.rmtree(unit.unzip_dir, ignore_errors=True)
    return [f"{u.name}.{c}" for u, c in columns], times, rows


def main(system_path: str, out_path: str, *flags: str) -> int:
    with open(system_path) as f:
        system = json.load(f)
    assert set(flags) <= {"--step-mode"}, f"unknown options {flags}"
    names, times, rows = simulate(system, step_mode="--step-mode" in flags)
    write_csv(out_path, names, times, rows)
    print(f"fmpy3_master: {len(times)} rows of {len(names)} outputs, t = {times[0]} .. {times[-1]} s")
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:]))
