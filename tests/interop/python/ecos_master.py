"""The closed loop in Ecos (ecospy), built by Ecos itself from an SSP package.

- Ecos groups the SSD's parameter sets by name across components and applies one named set
  at initialization: the package names every component's set `initialValues`, and this
  script applies that one.
- Ecos's fixed-step algorithm (src/ecos/simulation.cpp, algorithm/fixed_step_algorithm.cpp)
  is Jacobi: each instance sets its inputs, steps from t by h and reads its outputs, then
  every connection is transferred. Initialization exchanges in initialization mode (one
  round per instance), as libcosim does. Time is a running sum, t += h, and `step_until`
  steps while that sum is below the stop time.
- After the transfer, Ecos sets every instance's inputs again and reads its outputs, so a
  direct-feedthrough controller's outputs as recorded are re-evaluated at the new inputs. The
  script records the plant's outputs only; those depend on no input.

Prints `control_law = N` as Ecos reads it after initialization, or that Ecos has no Integer
variable of that name (Ecos does not expose FMI 2.0 Enumeration variables).

Usage: python ecos_master.py PACKAGE.ssp OUT.csv STOP_TIME STEP_SIZE
"""
import sys
import zipfile

from lxml import etree
from ecospy import EcosLib, EcosSimulation

from results import write_csv

PARAMETER_SET = "initialValues"
NS = {"ssd": "http://ssp-standard.org/SSP1/SystemStructureDescription"}


def plant_outputs(ssp_path: str) -> list[str]:
    """The Real output connectors of component `plant`, as the SSD declares them."""
    with zipfile.ZipFile(ssp_path) as archive:
        root = etree.parse(archive.open("SystemStructure.ssd")).getroot()
    component = root.find(".//ssd:Component[@name='plant']", NS)
    return [c.get("name") for c in component.iterfind("ssd:Connectors/ssd:Connector", NS)
            if c.get("kind") == "output"]


def main(ssp_path: str, out_path: str, stop: str, step: str) -> int:
    stop_time, step_size = float(stop), float(step)
    EcosLib.set_log_level("warn")
    names = plant_outputs(ssp_path)
    times, rows = [], []
    with EcosSimulation(step_size=step_size, ssp_path=ssp_path) as sim:
        sim.init(parameter_set=PARAMETER_SET)
        try:
            print(f"ecos: control_law = {sim.get_integer('gnc::control_law')}")
        except Exception as error:  # ecospy raises a bare Exception with Ecos's message
            print(f"ecos: control_law is not an Integer variable to Ecos ({error})")
        while sim.get_time() < stop_time:
            sim.step()
            times.append(sim.get_time())
            rows.append([sim.get_real(f"plant::{name}") for name in names])
        sim.terminate()
    write_csv(out_path, [f"plant.{name}" for name in names], times, rows)
    print(f"ecos: {len(rows)} steps of {step_size} s, {len(names)} plant outputs")
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:]))
