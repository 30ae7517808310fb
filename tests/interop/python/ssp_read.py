"""fmpy's SSP reader on LanderDescent.ssp, with schema validation on: `read_ssd` checks
SystemStructure.ssd against the SSP 1.0 XSDs it ships and raises on any violation. Prints
what it read, one fact a line, for the Rust test to check against the harness's system.

Usage: python ssp_read.py LanderDescent.ssp
"""
import sys
import zipfile

from fmpy import read_model_description
from fmpy.ssp.ssd import find_components, get_connections, read_ssd


def main(ssp_path: str) -> int:
    ssd = read_ssd(ssp_path, validate=True)
    print(f"system {ssd.system.name}")
    with zipfile.ZipFile(ssp_path) as archive:
        names = set(archive.namelist())
    for component in find_components(ssd.system):
        assert component.source in names, f"{component.source} is not in the package"
        parameters = [p for b in component.parameterBindings for s in b.parameterValues
                      for p in s.parameters]
        print(f"component {component.name} {component.source} connectors={len(component.connectors)} "
              f"parameters={len(parameters)}")
        for p in parameters:
            print(f"parameter {component.name}.{p.name} {p.value}")
    for start, end in get_connections(ssd.system):
        print(f"connection {start.parent.name}.{start.name} -> {end.parent.name}.{end.name}")
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:]))
