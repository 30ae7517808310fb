"""The Gauss-Seidel master of fmpy_master.py over fmpy's FMU3Slave and the FMI 3.0 FMUs
(target/fmu/fmi3/), so that the paper scenario flown through FMI 3.0 can be compared bit for
bit with the FMI 2.0 pair in the Rust harness.

Same exchange, same order, same communication points as fmpy_master.py. What differs is
FMI 3.0 itself: a vector is one array variable, so an input array is written whole (its
connected elements from the freshest outputs, the others kept), outputs are read as arrays
and recorded element by element under the FMI 2.0 names (`plant.r_nue[2]`); integers are
Int32 and enumerations Int64. The system JSON is the one fmpy_master.py reads; each FMU
path is mapped to its FMI 3.0 twin in the `fmi3` folder beside it.

Usage: python fmpy3_master.py SYSTEM.json OUT.csv
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
    def __init__(self, name: str, fmu_path: str):
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

    def set_inputs(self) -> None:
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


def simulate(system: dict):
    units = [Unit(i["name"], fmi3_twin(i["fmu"])) for i in system["instances"]]
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
        unit.fmu.instantiate()
        for name, value in instance["parameters"]:
            unit.set_parameter(name, value)
        unit.fmu.enterInitializationMode(startTime=start, stopTime=stop)
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
    for unit in units:
        unit.set_inputs()
        unit.get_outputs()
    record(stop)

    for unit in units:
        unit.fmu.terminate()
        unit.fmu.freeInstance()
        shutil.rmtree(unit.unzip_dir, ignore_errors=True)
    return [f"{u.name}.{c}" for u, c in columns], times, rows


def main(system_path: str, out_path: str) -> int:
    with open(system_path) as f:
        system = json.load(f)
    names, times, rows = simulate(system)
    write_csv(out_path, names, times, rows)
    print(f"fmpy3_master: {len(times)} rows of {len(names)} outputs, t = {times[0]} .. {times[-1]} s")
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:]))
