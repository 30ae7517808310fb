"""An fmpy (FMI 3.0) master for FMUs of every type pythonfmu3 exports and with structural
parameters (tests/interop/tests/pythonfmu3_types.rs), flying the loop the harness flies for
FMI 3.0 units without Event Mode whose outputs depend on no input, and writing the CSV the
harness writes with column types, so that the two files compare as text.

- Structural parameters: after instantiation, fmi3EnterConfigurationMode, the values set
  (fmi3SetUInt64, ...), fmi3ExitConfigurationMode (FMI 3.0, 4.2); an array whose
  <Dimension valueReference> names one has the extent set (else its start value).
- Other parameters are set before fmi3EnterInitializationMode; in Initialization Mode every
  unit's outputs are read, then each unit's inputs set from the freshest outputs and its
  outputs read; fmi3ExitInitializationMode.
- Gauss-Seidel in Step Mode: at t_k = k h, for each unit in order its outputs are read and
  its inputs set from the freshest outputs; the row is recorded; every unit steps. At the
  end the outputs are read and the last row recorded.
- The CSV: `time` and the recorded columns (arrays element by element, `y[1]`), floats in
  Python's shortest repr (as the harness's ryu), integers as integers, booleans as 0 and 1,
  strings as they are (quoted where CSV needs it).

Usage: python fmpy3_types_master.py SYSTEM.json OUT.csv
SYSTEM.json: {"start_time", "stop_time", "step_size", "instances": [{"name", "fmu",
"parameters": [[name, value], ...]}], "connections": [[from, to], ...], "record": [...]}
"""
import json
import sys

from fmpy import extract, read_model_description
from fmpy.fmi3 import FMU3Slave

INTEGERS = ("Int8", "UInt8", "Int16", "UInt16", "Int32", "UInt32", "Int64", "UInt64",
            "Enumeration")


def split(name: str):
    """'y[2]' -> ('y', 1); 'n' -> ('n', None)."""
    if name.endswith("]"):
        base, index = name[:-1].split("[")
        return base, int(index) - 1
    return name, None


def text(kind: str, value) -> str:
    if kind in INTEGERS:
        return str(int(value))
    if kind == "Boolean":
        return "1" if value else "0"
    if kind == "String":
        if any(c in value for c in ',"\n\r'):
            return '"' + value.replace('"', '""') + '"'
        return value
    return repr(float(value))


class Unit:
    def __init__(self, spec: dict):
        self.name = spec["name"]
        description = read_model_description(spec["fmu"])
        self.variables = {v.name: v for v in description.modelVariables}
        self.by_reference = {v.valueReference: v for v in description.modelVariables}
        self.parameters = spec["parameters"]
        self.structural = {name: value for name, value in self.parameters
                           if self.variables[name].causality == "structuralParameter"}
        self.fmu = FMU3Slave(guid=description.guid, unzipDirectory=extract(spec["fmu"]),
                             modelIdentifier=description.coSimulation.modelIdentifier,
                             instanceName=self.name)
        self.values = {}  # scalar name -> value, of the outputs read
        self.links = []  # (input name, source unit, source scalar name)

    def size(self, variable) -> int:
        extent = 1
        for dimension in variable.dimensions:
            if dimension.start is not None:
                extent *= int(dimension.start)
            else:
                source = self.by_reference[dimension.valueReference]
                extent *= int(self.structural.get(source.name, source.start))
        return extent

    def set(self, name: str, values: list) -> None:
        variable = self.variables[name]
        vr = [variable.valueReference]
        setter = {"Float64": self.fmu.setFloat64, "Int32": self.fmu.setInt32,
                  "Int64": self.fmu.setInt64, "UInt64": self.fmu.setUInt64,
                  "Boolean": self.fmu.setBoolean, "String": self.fmu.setString}[variable.type]
        setter(vr, values)

    def instantiate(self) -> None:
        self.fmu.instantiate(eventModeUsed=False, earlyReturnAllowed=False)
        if self.structural:
            self.fmu.enterConfigurationMode()
            for name, value in self.structural.items():
                self.set(name, [int(value)])
            self.fmu.exitConfigurationMode()

    def set_parameters(self) -> None:
        for name, value in self.parameters:
            if name not in self.structural:
                self.set(name, [value])

    def read(self) -> None:
        for variable in self.variables.values():
            if variable.causality != "output":
                continue
            n = self.size(variable)
            vr = [variable.valueReference]
            getter = {"Float64": self.fmu.getFloat64, "Int32": self.fmu.getInt32,
                      "Int64": self.fmu.getInt64, "UInt64": self.fmu.getUInt64,
                      "Boolean": self.fmu.getBoolean, "String": self.fmu.getString}
            values = getter[variable.type](vr, nValues=n) if variable.type != "String" \
                else getter["String"](vr)
            for i, value in enumerate(values):
                key = f"{variable.name}[{i + 1}]" if variable.dimensions else variable.name
                self.values[key] = value

    def set_inputs(self) -> None:
        for name, source, output in self.links:
            self.set(name, [source.values[output]])

    def kind(self, scalar: str) -> str:
        return self.variables[split(scalar)[0]].type


def main(spec_path: str, out_path: str) -> None:
    with open(spec_path) as f:
        system = json.load(f)
    units = [Unit(spec) for spec in system["instances"]]
    by_name = {u.name: u for u in units}
    for source, destination in system["connections"]:
        (from_unit, output), (to_unit, name) = source.split(".", 1), destination.split(".", 1)
        by_name[to_unit].links.append((name, by_name[from_unit], output))
    # The recorded scalars: an array by its base name stands for all its elements.
    columns = []
    for path in system["record"]:
        unit_name, name = path.split(".", 1)
        unit = by_name[unit_name]
        variable = unit.variables.get(name)
        if variable is not None and variable.dimensions:
            columns += [(unit, f"{name}[{i + 1}]") for i in range(unit.size(variable))]
        else:
            columns.append((unit, name))

    start, stop, h = system["start_time"], system["stop_time"], system["step_size"]
    steps = round((stop - start) / h)
    for unit in units:
        unit.instantiate()
        unit.set_parameters()
        unit.fmu.enterInitializationMode(startTime=start)
    for unit in units:
        unit.read()
    for unit in units:
        unit.set_inputs()
        unit.read()
    for unit in units:
        unit.fmu.exitInitializationMode()
        unit.read()

    rows = []

    def record(time: float) -> None:
        rows.append([repr(float(time))] + [text(u.kind(name), u.values[name])
                                           for u, name in columns])

    for k in range(steps):
        time = start + k * h
        for unit in units:
            unit.read()
            unit.set_inputs()
        record(time)
        for unit in units:
            unit.fmu.doStep(currentCommunicationPoint=time, communicationStepSize=h)
    for unit in units:
        unit.read()
    record(start + steps * h)
    for unit in units:
        unit.fmu.terminate()
        unit.fmu.freeInstance()

    with open(out_path, "w") as f:
        f.write(",".join(["time"] + [f"{u.name}.{name}" for u, name in columns]) + "\n")
        for row in rows:
            f.write(",".join(row) + "\n")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
