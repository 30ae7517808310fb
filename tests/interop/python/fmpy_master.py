"""A co-simulation master written with fmpy's FMU2Slave, exchanging exactly as the Rust
harness does with its default conventions (harness/src/master/mod.rs), so that the two give
bit-identical trajectories for the same FMU binaries:

- time t_k = start + k * h from an integer step counter; the last step is shortened to land
  on the stop time;
- initialization: setupExperiment(start, stop), parameters, enterInitializationMode, read
  every output, then instance by instance in declaration order set its inputs from the
  freshest outputs and read its outputs, exitInitializationMode, read every output;
- Gauss-Seidel at each communication point: instance by instance set inputs, read outputs;
  record the row; then every instance steps from t_k to t_k + h_k and every output is read;
- after the last step: set inputs and read outputs once more and record the row at the stop
  time.

The system comes from a JSON file the Rust test writes from the harness's own scenario
(instances in exchange order with their FMU and parameters, scalar connections), so both
masters fly the same system, whatever the number of instances (the paper loop of two, or
plant -> nav -> gnc with LanderNav between them). Every output of every instance is recorded as
`instance.variable`, as the harness does.

Usage: python fmpy_master.py SYSTEM.json OUT.csv
"""
import json
from time import perf_counter
import shutil
import sys

from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

from results import write_csv


class Unit:
    """One instance: the FMU, its variables by name, its connected inputs and its outputs."""

    def __init__(self, name: str, fmu_path: str):
        self.name = name
        self.description = read_model_description(fmu_path)
        self.variables = {v.name: v for v in self.description.modelVariables}
        self.unzip_dir = extract(fmu_path)
        self.fmu = FMU2Slave(guid=self.description.guid,
                             unzipDirectory=self.unzip_dir,
                             modelIdentifier=self.description.coSimulation.modelIdentifier,
                             instanceName=name)
        self.outputs = [v for v in self.description.modelVariables if v.causality == "output"]
        self.output_values = {v.name: 0.0 for v in self.outputs}
        # (input variable, source unit, source output name), in connection order.
        self.links = []

    def set_parameter(self, name: str, value) -> None:
        variable = self.variables[name]
        if variable.type == "Real":
            self.fmu.setReal([variable.valueReference], [float(value)])
        elif variable.type in ("Integer", "Enumeration"):
            self.fmu.setInteger([variable.valueReference], [int(value)])
        elif variable.type == "Boolean":
            self.fmu.setBoolean([variable.valueReference], [bool(value)])
        else:
            self.fmu.setString([variable.valueReference], [str(value)])

    def set_inputs(self) -> None:
        real = [(v.valueReference, source.output_values[output])
                for v, source, output in self.links if v.type == "Real"]
        if real:
            self.fmu.setReal([vr for vr, _ in real], [value for _, value in real])
        integer = [(v.valueReference, int(source.output_values[output]))
                   for v, source, output in self.links if v.type in ("Integer", "Enumeration")]
        if integer:
            self.fmu.setInteger([vr for vr, _ in integer], [value for _, value in integer])
        boolean = [(v.valueReference, bool(source.output_values[output]))
                   for v, source, output in self.links if v.type == "Boolean"]
        if boolean:
            self.fmu.setBoolean([vr for vr, _ in boolean], [value for _, value in boolean])

    def get_outputs(self) -> None:
        real = [v for v in self.outputs if v.type == "Real"]
        if real:
            for v, value in zip(real, self.fmu.getReal([v.valueReference for v in real])):
                self.output_values[v.name] = value
        integer = [v for v in self.outputs if v.type in ("Integer", "Enumeration")]
        if integer:
            for v, value in zip(integer, self.fmu.getInteger([v.valueReference for v in integer])):
                self.output_values[v.name] = float(value)
        boolean = [v for v in self.outputs if v.type == "Boolean"]
        if boolean:
            for v, value in zip(boolean, self.fmu.getBoolean([v.valueReference for v in boolean])):
                self.output_values[v.name] = 1.0 if value else 0.0


def step_count(start: float, stop: float, h: float) -> int:
    """As the harness: a ratio within 1e-9 of an integer is that integer."""
    ratio = (stop - start) / h
    if abs(ratio - round(ratio)) < 1e-9 * max(ratio, 1.0):
        return int(round(ratio))
    return int(-(-ratio // 1))


def simulate(system: dict) -> tuple[list[str], list[float], list[list[float]]]:
    names, times, rows, _ = simulate_timed(system)
    return names, times, rows


def simulate_timed(system: dict) -> tuple[list[str], list[float], list[list[float]], float]:
    """`simulate`, also returning the seconds spent in the stepping loop alone (loading,
    instantiating and initializing excluded), for tests/speed."""
    units = [Unit(i["name"], i["fmu"]) for i in system["instances"]]
    by_name = {u.name: u for u in units}
    for source, destination in system["connections"]:
        from_unit, from_var = source.split(".", 1)
        to_unit, to_var = destination.split(".", 1)
        target = by_name[to_unit]
        target.links.append((target.variables[to_var], by_name[from_unit], from_var))

    start, stop, h = system["start_time"], system["stop_time"], system["step_size"]
    columns = [(u, v.name) for u in units for v in u.outputs]
    times, rows = [], []

    def record(time: float) -> None:
        times.append(time)
        rows.append([u.output_values[name] for u, name in columns])

    for unit, instance in zip(units, system["instances"]):
        unit.fmu.instantiate()
        unit.fmu.setupExperiment(startTime=start, stopTime=stop)
        for name, value in instance["parameters"]:
            unit.set_parameter(name, value)
        unit.fmu.enterInitializationMode()
    for unit in units:
        unit.get_outputs()
    for unit in units:
        unit.set_inputs()
        unit.get_outputs()
    for unit in units:
        unit.fmu.exitInitializationMode()
    for unit in units:
        unit.get_outputs()

    steps = step_count(start, stop, h)
    started = perf_counter()
    for k in range(steps):
        time = start + k * h
        step = stop - time if k + 1 == steps else h
        for unit in units:
            unit.set_inputs()
            unit.get_outputs()
        record(time)
        for unit in units:
            unit.fmu.doStep(currentCommunicationPoint=time, communicationStepSize=step)
        for unit in units:
            unit.get_outputs()
    loop_seconds = perf_counter() - started
    for unit in units:
        unit.set_inputs()
        unit.get_outputs()
    record(stop)

    for unit in units:
        unit.fmu.terminate()
        unit.fmu.freeInstance()
        shutil.rmtree(unit.unzip_dir, ignore_errors=True)
    return [f"{u.name}.{name}" for u, name in columns], times, rows, loop_seconds


def main(system_path: str, out_path: str) -> int:
    with open(system_path) as f:
        system = json.load(f)
    names, times, rows = simulate(system)
    write_csv(out_path, names, times, rows)
    print(f"fmpy_master: {len(times)} rows of {len(names)} outputs, t = {times[0]} .. {times[-1]} s")
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:]))
