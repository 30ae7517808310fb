"""A container FMU made by fmpy's own tool (fmpy.container_fmu: fmpy's C binary runs the
nested FMUs) of the FMI 3.0 LanderGnc and LanderPlant, wired as the paper scenario wires
them; then flown alone by fmpy's simulate_fmu. The Rust test
(tests/interop/tests/container_fmu.rs) flies the same container in the harness and
compares the two result files.

Usage: python container_fmu.py GNC.fmu PLANT.fmu CONTAINER.fmu FMPY_OUT.csv STOP STEP
"""
import sys
import tempfile
import uuid
from pathlib import Path

import numpy as np
import fmpy.container_fmu
from fmpy import read_model_description, simulate_fmu
from fmpy.container_fmu import Configuration
from fmpy.container_fmu.cli import create_container_fmu
from fmpy.container_fmu.config import Component, Connection
from fmpy.model_description import (CoSimulation, DefaultExperiment, ModelDescription,
                                    ModelVariable)

NAVIGATION = ["r_nue", "v_nue", "q_body_to_nue", "omega_body", "mass"]
COMMANDS = ["thrust_cmd", "torque_cmd_body"]
# What the container shows of its components: (name, component, variable).
OUTPUTS = [("altitude", "plant", "altitude"), ("mass", "plant", "mass"),
           ("thrust_cmd", "gnc", "thrust_cmd"), ("phi_b", "gnc", "phi_b"),
           ("tilt_error", "gnc", "tilt_error")]
# The paper's roll demand, 150 deg about the thrust axis, as a parameter of the container.
PHI_CMD_RAD = 2.6179938779914944


# fmpy 0.3.32 writes an array connection's size as numpy's int64, which its json.dump
# refuses; the same number as a Python int.
fmpy.container_fmu.np = type("NumpyIntProd", (), {"prod": staticmethod(lambda s: int(np.prod(s)))})


def main(gnc_path, plant_path, container_path, out_path, stop, step):
    stop, step = float(stop), float(step)
    components = {}
    for name, path in [("gnc", gnc_path), ("plant", plant_path)]:
        md = read_model_description(path)
        components[name] = (Component(name=name, filename=Path(path), modelDescription=md),
                            {v.name: v for v in md.modelVariables})
    connections = []
    for source, destination, names in [("plant", "gnc", NAVIGATION), ("gnc", "plant", COMMANDS)]:
        for name in names:
            start, end = components[source][1][name], components[destination][1][name]
            connections.append(Connection(startElement=components[source][0],
                                          startConnectors=[start],
                                          endElement=components[destination][0],
                                          endConnectors=[end]))
    md = ModelDescription(fmiVersion="3.0", modelName="LanderContainer",
                          instantiationToken="{" + str(uuid.uuid5(uuid.NAMESPACE_URL, "lander-container")) + "}",
                          coSimulation=CoSimulation(modelIdentifier="container_fmu",
                                                    fixedInternalStepSize=step),
                          defaultExperiment=DefaultExperiment(startTime=0.0, stopTime=stop,
                                                              stepSize=step))
    # FMI 3.0 wants the independent variable declared; the container maps it to nothing.
    md.modelVariables.append(ModelVariable(name="time", type="Float64", causality="independent",
                                           variability="continuous"))
    mappings = {}
    phi_cmd = ModelVariable(name="phi_cmd", type="Float64", causality="parameter",
                            variability="fixed", initial="exact")
    phi_cmd.start = repr(PHI_CMD_RAD)
    md.modelVariables.append(phi_cmd)
    mappings[phi_cmd] = [(components["gnc"][0], components["gnc"][1]["phi_cmd"])]
    for name, component, variable in OUTPUTS:
        v = ModelVariable(name=name, type="Float64", causality="output", variability="continuous")
        md.modelVariables.append(v)
        mappings[v] = [(components[component][0], components[component][1][variable])]
    config = Configuration(parallelDoStep=False, modelDescription=md,
                           components=[c for c, _ in components.values()],
                           connections=connections, variableMappings=mappings)
    with tempfile.TemporaryDirectory() as scratch:
        create_container_fmu(config, Path(scratch), Path(container_path))
    result = simulate_fmu(container_path, stop_time=stop, output_interval=step,
                          output=[name for name, _, _ in OUTPUTS])
    names = result.dtype.names
    with open(out_path, "w") as f:
        f.write(",".join(names) + "\n")
        for row in result:
            f.write(",".join(repr(float(row[n])) for n in names) + "\n")
    print(f"container: {len(result)} rows -> {out_path}")
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:]))
