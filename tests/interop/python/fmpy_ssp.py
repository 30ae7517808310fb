"""fmpy's own SSP runner on LanderDescent.ssp.

- `read_ssd` validates SystemStructure.ssd against the SSP 1.0 schema (validate=True).
- `simulate_ssp` applies parameters only from a parameter set passed to it, named
  `<component>.<variable>`; the SSD's inline ParameterBindings (which read_ssd parses) are
  otherwise ignored, so they are collected here into such a set.
- Its loop is fmpy 0.3's (fmpy/ssp/simulation.py): every connector starts at 0.0, no
  exchange in initialization mode, then while t < stop: each component sets its inputs,
  steps from t by h and reads its outputs; then the connections are applied (Jacobi), the
  row is recorded under the label t with the values at t + h, and t += h (accumulated).

Writes the output connectors as `instance.variable` columns, under fmpy's time labels.

Usage: python fmpy_ssp.py LanderDescent.ssp OUT.csv
"""
import sys
import zipfile

from lxml import etree
from fmpy.ssp.simulation import simulate_ssp
from fmpy.ssp.ssd import ParameterSet, find_components, read_ssd

from results import write_csv


def inline_parameters(ssd) -> ParameterSet:
    """The components' inline parameter values as one set with component-prefixed names."""
    collected = ParameterSet(name="inline bindings")
    for component in find_components(ssd.system):
        for binding in component.parameterBindings:
            for parameter_set in binding.parameterValues:
                for parameter in parameter_set.parameters:
                    parameter.name = f"{component.name}.{parameter.name}"
                    collected.parameters.append(parameter)
    return collected


def experiment(ssp_path: str) -> tuple[float, float, float]:
    """Start, stop and step of the SSD's DefaultExperiment, which fmpy 0.3 does not parse;
    SSP 1.0 has no element for the step, so it is in the harness's annotation."""
    with zipfile.ZipFile(ssp_path) as archive:
        root = etree.parse(archive.open("SystemStructure.ssd")).getroot()
    ns = {"ssd": "http://ssp-standard.org/SSP1/SystemStructureDescription"}
    default = root.find("ssd:DefaultExperiment", ns)
    master = default.find(".//Master")
    return (float(default.get("startTime")), float(default.get("stopTime")),
            float(master.get("stepSize")))


def main(ssp_path: str, out_path: str) -> int:
    ssd = read_ssd(ssp_path, validate=True)
    start, stop, step = experiment(ssp_path)
    parameters = inline_parameters(ssd)
    print(f"fmpy_ssp: {len(find_components(ssd.system))} components, "
          f"{len(parameters.parameters)} inline parameters, t = {start} .. {stop} s by {step} s")
    result = simulate_ssp(ssp_path, start_time=start, stop_time=stop, step_size=step,
                          parameter_set=parameters)
    outputs = [c for c in find_components(ssd.system) for c in c.connectors if c.kind == "output"]
    names = [f"{c.parent.name}.{c.name}" for c in outputs]
    columns = [result[name] for name in names]
    rows = [[float(col[k]) for col in columns] for k in range(len(result))]
    write_csv(out_path, names, [float(t) for t in result["time"]], rows)
    print(f"fmpy_ssp: {len(result)} rows, last label t = {result['time'][-1]!r}")
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:]))
