"""LanderGnc and LanderPlant in a closed loop with fmpy: the paper's descent from 800 m with
the decoupled attitude law and the camera turned 150 deg about the thrust axis.

    pip install fmpy
    python closed_loop.py path/to/LanderGnc.fmu path/to/LanderPlant.fmu [out.csv]

The loop is the one the harness runs (Gauss-Seidel: the controller acts on the state of the
same communication point), so its rows equal `harness run paper` bit for bit:
- time t_k = k * h from an integer step counter, h = 0.01 s, 17,200 steps to 172 s;
- initialization: parameters, enterInitializationMode, exchange once (gnc from the plant's
  initial state, then the plant from gnc's first command), exitInitializationMode;
- at each point: gnc's inputs from the plant, gnc's outputs; the plant's inputs from gnc,
  the plant's outputs; record; then both step from t_k to t_k + h.
"""
import csv
import math
import shutil
import sys

from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

STOP_S, STEP_S = 172.0, 0.01

# What the controller reads from the plant, and the plant from the controller (names from
# docs/interface.md; a vector is its elements [1]..[n]).
PLANT_TO_GNC = ["r_nue[1]", "r_nue[2]", "r_nue[3]", "v_nue[1]", "v_nue[2]", "v_nue[3]",
                "q_body_to_nue[1]", "q_body_to_nue[2]", "q_body_to_nue[3]", "q_body_to_nue[4]",
                "omega_body[1]", "omega_body[2]", "omega_body[3]", "mass"]
GNC_TO_PLANT = ["thrust_cmd", "torque_cmd_body[1]", "torque_cmd_body[2]", "torque_cmd_body[3]"]

GNC_PARAMETERS = {"control_law": 2, "phi_cmd": math.radians(150.0), "phi_cmd_time": 0.0}
PLANT_PARAMETERS = {"r0_nue[1]": 0.0, "r0_nue[2]": 800.0, "r0_nue[3]": 0.0,
                    # 15 deg of tilt at the start (about the body z axis)
                    "q0_body_to_nue[1]": math.cos(math.radians(-15.0) / 2),
                    "q0_body_to_nue[2]": 0.0, "q0_body_to_nue[3]": 0.0,
                    "q0_body_to_nue[4]": math.sin(math.radians(-15.0) / 2),
                    "m0": 900.0}


class Instance:
    def __init__(self, name, path):
        self.description = read_model_description(path)
        self.vr = {v.name: v.valueReference for v in self.description.modelVariables}
        self.types = {v.name: v.type for v in self.description.modelVariables}
        self.directory = extract(path)
        self.fmu = FMU2Slave(guid=self.description.guid, unzipDirectory=self.directory,
                             modelIdentifier=self.description.coSimulation.modelIdentifier,
                             instanceName=name)

    def set(self, values):
        for name, value in values.items():
            if self.types[name] == "Real":
                self.fmu.setReal([self.vr[name]], [float(value)])
            else:
                self.fmu.setInteger([self.vr[name]], [int(value)])

    def get(self, names):
        return dict(zip(names, self.fmu.getReal([self.vr[n] for n in names])))

    def close(self):
        self.fmu.terminate()
        self.fmu.freeInstance()
        shutil.rmtree(self.directory, ignore_errors=True)


def fly(gnc_path, plant_path):
    gnc, plant = Instance("gnc", gnc_path), Instance("plant", plant_path)
    for unit, parameters in ((gnc, GNC_PARAMETERS), (plant, PLANT_PARAMETERS)):
        unit.fmu.instantiate()
        unit.fmu.setupExperiment(startTime=0.0, stopTime=STOP_S)
        unit.set(parameters)
        unit.fmu.enterInitializationMode()

    def exchange():
        state = plant.get(PLANT_TO_GNC)
        gnc.set(state)
        command = gnc.get(GNC_TO_PLANT)
        plant.set(command)
        return state, command

    exchange()
    for unit in (gnc, plant):
        unit.fmu.exitInitializationMode()

    steps = round(STOP_S / STEP_S)
    rows = []
    for k in range(steps + 1):
        t = k * STEP_S
        state, command = exchange()
        rows.append([t] + [state[n] for n in PLANT_TO_GNC] + [command[n] for n in GNC_TO_PLANT])
        if k < steps:
            for unit in (gnc, plant):
                unit.fmu.doStep(currentCommunicationPoint=t, communicationStepSize=STEP_S)
    gnc.close()
    plant.close()
    return rows


def main(gnc_path, plant_path, out_path=None):
    rows = fly(gnc_path, plant_path)
    t, north, up, east = rows[-1][0], rows[-1][1], rows[-1][2], rows[-1][3]
    print(f"t = {t:.2f} s: altitude {up:.3f} m, {math.hypot(north, east):.3f} m from the "
          f"vertical through the target")
    if out_path:
        with open(out_path, "w", newline="") as f:
            writer = csv.writer(f)
            writer.writerow(["time"] + [f"plant.{n}" for n in PLANT_TO_GNC]
                            + [f"gnc.{n}" for n in GNC_TO_PLANT])
            writer.writerows([repr(v) for v in row] for row in rows)
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:]))
