"""Times the master loop of tests/interop/python/fmpy_master.py (fmpy's FMU2Slave, the
harness's Gauss-Seidel exchange, every output recorded) on a system, with a clock around
the stepping loop only: extracting, loading, instantiating and initializing are outside it,
as they are outside the harness's figure.

The exchange is fmpy_master's own (its Unit class and step count); only the sequence of
`simulate` is repeated here, with the clock added. The Rust side checks the final row
against the harness's flight of the same system, so a drift between the two sequences
shows as a failure, not as a figure.

Needs tests/interop/python on PYTHONPATH. Usage: python fmpy_timed.py SYSTEM.json REPEATS
Prints one JSON object: steps, loop_seconds (one per repeat), final_bits (the last row by
column, each value as the 64 bits of its IEEE double, so the comparison is exact).
"""
import json
import shutil
import struct
import sys
import time

from fmpy_master import Unit, step_count


def bits(value: float) -> int:
    return struct.unpack("<Q", struct.pack("<d", value))[0]


def fly(system: dict) -> tuple[int, float, dict]:
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

    def record(t: float) -> None:
        times.append(t)
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
    started = time.perf_counter()
    for k in range(steps):
        t = start + k * h
        step = stop - t if k + 1 == steps else h
        for unit in units:
            unit.set_inputs()
            unit.get_outputs()
        record(t)
        for unit in units:
            unit.fmu.doStep(currentCommunicationPoint=t, communicationStepSize=step)
        for unit in units:
            unit.get_outputs()
    loop_seconds = time.perf_counter() - started
    for unit in units:
        unit.set_inputs()
        unit.get_outputs()
    record(stop)

    for unit in units:
        unit.fmu.terminate()
        unit.fmu.freeInstance()
        shutil.rmtree(unit.unzip_dir, ignore_errors=True)
    final = {f"{u.name}.{name}": bits(value) for (u, name), value in zip(columns, rows[-1])}
    return steps, loop_seconds, final


def main(system_path: str, repeats: str) -> int:
    with open(system_path) as f:
        system = json.load(f)
    loop_seconds = []
    for _ in range(int(repeats)):
        steps, seconds, final = fly(system)
        loop_seconds.append(seconds)
    print(json.dumps({"steps": steps, "loop_seconds": loop_seconds, "final_bits": final}))
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:]))
