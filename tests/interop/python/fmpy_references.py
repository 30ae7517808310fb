"""The FMI-LS-REF references an FMU carries, checked in fmpy, independent of the harness that
wrote them: the experiment of `extra/org.fmi-standard.fmi-ls-ref/experiments.xml` simulated
with `simulate_fmu` (its times, its stimuli as `input`, an output at every step; for FMI 3.0,
whose arrays fmpy 0.3's `input` cannot mix with scalars, the same loop over `FMU3Slave`:
step, record the outputs, set the inputs of the new time, as `simulate_fmu` does), each
reference signal compared with fmpy's `validate_signal` (fmpy.cross_check) within the
tolerances the file gives. The files name an array's elements (`r_nue[1]`) as the FMI 2.0
scalars are named; in FMI 3.0 the array `r_nue` is set and read whole. A reference thinned to every k-th step vouches for those steps:
the result is judged at the reference's times, as the harness judges it, and no sample may
lie outside the band (fmpy's cross-check allows 10 %). `num` lays the band's points on every
reference time and halfway between; `dx` spans the time tolerance.

Usage: python fmpy_references.py FMU...   (exit status 1 when a signal fails)
"""
import shutil
import sys
import zipfile
import xml.etree.ElementTree as ET

import numpy as np
from fmpy import extract, read_model_description, simulate_fmu
from fmpy.fmi3 import FMU3Slave
from fmpy.cross_check import validate_signal

LS = "extra/org.fmi-standard.fmi-ls-ref/"


def table(text: str):
    """A CSV as (names, times, columns); names kept as written (`r_nue[1]`)."""
    lines = [line.split(",") for line in text.strip().splitlines()]
    names = lines[0][1:]
    data = np.array([[float(x) for x in row] for row in lines[1:]])
    return names, data[:, 0], data[:, 1:]


def local(tag: str) -> str:
    return tag.rsplit("}", 1)[-1]


def element(name: str) -> tuple[str, int] | None:
    """`r_nue[2]` as (`r_nue`, 1); None for a scalar's name."""
    if not name.endswith("]") or "[" not in name:
        return None
    base, index = name[:-1].split("[", 1)
    return (base, int(index) - 1) if index.isdigit() else None


def input_signals(path: str, names: list[str], times, columns):
    """The stimuli as fmpy's `input`: a field per input, an FMI 3.0 array's elements joined."""
    shapes = {v.name: v.shape for v in read_model_description(path).modelVariables
              if v.causality == "input"}
    fields, values = [("time", float)], {"time": times}
    for j, name in enumerate(names):
        if name in shapes:
            fields.append((name, float))
            values[name] = columns[:, j]
        elif (split := element(name)) and shapes.get(split[0]):
            base, index = split
            if base not in values:
                fields.append((base, float, tuple(shapes[base])))
                values[base] = np.zeros((len(times),) + tuple(shapes[base]))
            values[base][:, index] = columns[:, j]
    signals = np.zeros(len(times), dtype=fields)
    for name, value in values.items():
        signals[name] = value
    return signals


def fmi3_run(path: str, start: float, stop: float, step: float, stimuli):
    """The FMI 3.0 FMU at `path` over the experiment, inputs from `stimuli` ((names, times,
    columns) or None): the times and every output element by its scalar name."""
    description = read_model_description(path)
    variables = {v.name: v for v in description.modelVariables}
    size = {n: int(v.dimensions[0].start) if v.dimensions else 1 for n, v in variables.items()}
    unzipped = extract(path)
    fmu = FMU3Slave(guid=description.guid, unzipDirectory=unzipped,
                    modelIdentifier=description.coSimulation.modelIdentifier,
                    instanceName="reference")
    # Each input array: its current values and the stimuli columns of its elements.
    inputs = {}
    if stimuli is not None:
        names, times, columns = stimuli
        for j, name in enumerate(names):
            base, index = element(name) or (name, 0)
            if base not in inputs:
                inputs[base] = ([0.0] * size[base], [])
            inputs[base][1].append((index, j))

    def set_inputs(t):
        for base, (values, elements) in inputs.items():
            variable = variables[base]
            held = variable.type != "Float64" or variable.variability == "discrete"
            for index, j in elements:
                if held:
                    row = max(np.searchsorted(times, t, side="right") - 1, 0)
                    values[index] = columns[row, j]
                else:
                    values[index] = float(np.interp(t, times, columns[:, j]))
            setter = getattr(fmu, "set" + ("Int64" if variable.type == "Enumeration" else variable.type))
            setter([variable.valueReference],
                   values if variable.type == "Float64" else [type_of(variable)(x) for x in values])

    outputs = [v for v in description.modelVariables if v.causality == "output"]
    # One get per type and step: (getter, value references, number of values, column names).
    by_type = {}
    for v in outputs:
        kind = "Int64" if v.type == "Enumeration" else v.type
        getter, vrs, count, names = by_type.setdefault(kind, (getattr(fmu, "get" + kind), [], [0], []))
        vrs.append(v.valueReference)
        count[0] += size[v.name]
        names += [f"{v.name}[{i + 1}]" if v.dimensions else v.name for i in range(size[v.name])]
    rows = []

    def record(t):
        row = [t]
        for getter, vrs, count, _ in by_type.values():
            row += [float(x) for x in getter(vrs, count[0])]
        rows.append(row)

    # Early return, so that a step the FMU ends early (LanderPlant's touchdown) is recorded
    # where it ended, as fmpy records an FMI 2.0 step ended by fmi2Discard.
    fmu.instantiate(eventModeUsed=False, earlyReturnAllowed=True)
    fmu.enterInitializationMode(startTime=start, stopTime=stop)
    set_inputs(start)
    record(start)
    fmu.exitInitializationMode()
    k, t = 0, start
    while t < stop - 1e-9 * max(1.0, abs(stop)):
        following = start + (k + 1) * step
        _, terminate, early, ended = fmu.doStep(currentCommunicationPoint=t,
                                                communicationStepSize=following - t)
        k, t = k + 1, ended if early else following
        record(t)
        if terminate:
            break
        set_inputs(t)
    fmu.terminate()
    fmu.freeInstance()
    shutil.rmtree(unzipped, ignore_errors=True)
    data = np.array(rows)
    names = [n for _, _, _, group in by_type.values() for n in group]
    return data[:, 0], {n: data[:, j + 1] for j, n in enumerate(names)}


def type_of(variable):
    return bool if variable.type == "Boolean" else int


def column(result, name: str):
    """A reference column's values in fmpy's result, an element of an array included."""
    if name in result.dtype.names:
        return result[name].astype(float)
    split = element(name)
    if split and split[0] in result.dtype.names:
        return result[split[0]][:, split[1]].astype(float)
    return None


def check(path: str) -> tuple[bool, str]:
    with zipfile.ZipFile(path) as archive:
        root = ET.fromstring(archive.read(LS + "experiments.xml"))
        experiment = next(e for e in root.iter() if local(e.tag) == "Experiment")
        stimuli = next((e for e in experiment if local(e.tag) == "Stimuli"), None)
        references = next(e for e in experiment if local(e.tag) == "References")
        stimuli_table = None
        if stimuli is not None:
            stimuli_table = table(archive.read(LS + stimuli.get("source")).decode())
        ref_names, t_ref, ref_columns = table(archive.read(LS + references.get("source")).decode())
    start = float(experiment.get("startTime"))
    stop = float(experiment.get("stopTime"))
    step = float(experiment.get("stepSize"))
    relative = float(references.get("relativeTolerance", "0.1"))
    absolute = float(references.get("absoluteTolerance", "0"))
    time_tolerance = float(references.get("timeTolerance", "0.01"))

    if read_model_description(path).fmiVersion.startswith("3."):
        t_res, outputs = fmi3_run(path, start, stop, step, stimuli_table)

        def values_of(name):
            return outputs.get(name)
    else:
        inputs = None if stimuli_table is None else input_signals(path, *stimuli_table)
        result = simulate_fmu(path, start_time=start, stop_time=stop, step_size=step,
                              output_interval=step, input=inputs, fmi_type="CoSimulation",
                              validate=False)
        t_res = result["time"]

        def values_of(name):
            return column(result, name)
    # The result's rows at the reference's times.
    at = np.searchsorted(t_res, t_ref - 1e-9 * np.maximum(1.0, np.abs(t_ref)))
    at = np.minimum(at, len(t_res) - 1)
    if not np.allclose(t_res[at], t_ref, rtol=1e-9, atol=1e-9):
        return False, f"{path}: the result has no row at some reference times"
    num = 2 * (len(t_ref) - 1) + 1
    dx = 2 * round(time_tolerance * (num - 1)) + 1
    failed, worst = [], (0.0, "", 0.0)
    for j, name in enumerate(ref_names):
        values = values_of(name)
        if values is None:
            failed.append(f"{name}: not in fmpy's result")
            continue
        y = values[at]
        y_ref = ref_columns[:, j]
        _, _, _, outside = validate_signal(t=t_ref, y=y, t_ref=t_ref, y_ref=y_ref,
                                           t_start=start, t_stop=stop, num=num, dx=dx, dy=relative)
        deviation = np.abs(y - y_ref)
        # fmpy's band has no absolute floor: a sample within it of the reference is inside.
        outside &= deviation > absolute
        k = int(np.argmax(deviation))
        if deviation[k] > worst[0]:
            worst = (float(deviation[k]), name, float(t_ref[k]))
        if outside.any():
            first = int(np.argmax(outside))
            failed.append(f"{name}: {int(outside.sum())} of {len(y)} samples outside the band, "
                          f"first at t = {t_ref[first]} s ({y[first]} against {y_ref[first]})")
    where = f" ({worst[1]} at t = {worst[2]} s)" if worst[1] else ""
    summary = (f"{path}: {len(ref_names)} signals, {len(failed)} failed; largest deviation "
               f"{worst[0]:.3e}{where}")
    return not failed, "\n    ".join([summary] + failed)


def main() -> int:
    passed = failed = 0
    for path in sys.argv[1:]:
        ok, report = check(path)
        print(("PASS " if ok else "FAIL ") + report)
        passed, failed = passed + ok, failed + (not ok)
    print(f"fmpy_references: {passed} passed, {failed} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
