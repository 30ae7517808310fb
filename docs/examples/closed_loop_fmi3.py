"""LanderGnc and LanderPlant in FMI 3.0 in a closed loop with fmpy: the paper's descent from
800 m with the decoupled attitude law and the camera turned 150 deg about the thrust axis.

    pip install fmpy
    python closed_loop_fmi3.py path/to/fmi3/LanderGnc.fmu path/to/fmi3/LanderPlant.fmu [out.csv]

The loop is closed_loop.py's (Gauss-Seidel: the controller acts on the state of the same
communication point), so its rows equal `harness run paper` bit for bit. FMI 3.0 forbids
reading an output after setting an input in Step Mode without a step in between (FMI 3.0,
4.2.1), so each communication point is an event instant:
- instantiate with eventModeUsed = true: exitInitializationMode then leaves both units in
  Event Mode;
- at each point t_k = k * h: enterEventMode (from the second point on); gnc's inputs from the
  plant, gnc's outputs; the plant's inputs from gnc, the plant's outputs (in Event Mode a
  get after a set returns the outputs of those inputs); record; updateDiscreteStates until
  no further update is needed; enterStepMode; both doStep from t_k to t_k + h.
A vector is one array variable in FMI 3.0: it is set and read whole. The columns are named
as in FMI 2.0 (`plant.r_nue[1]`) so that the two versions' results compare directly.
"""
import csv
import math
import shutil
import sys

from fmpy import extract, read_model_description
from fmpy.fmi3 import FMU3Slave

STOP_S, STEP_S = 172.0, 0.01

# What the controller reads from the plant, and the plant from the controller, with their
# sizes (names from docs/interface.md).
PLANT_TO_GNC = [("r_nue", 3), ("v_nue", 3), ("q_body_to_nue", 4), ("omega_body", 3), ("mass", 1)]
GNC_TO_PLANT = [("thrust_cmd", 1), ("torque_cmd_body", 3)]

# control_law is an Int32 (1 coupled, 2 decoupled, 3 reduced); the others are Float64.
GNC_PARAMETERS = {"control_law": 2, "phi_cmd": [math.radians(150.0)], "phi_cmd_time": [0.0]}
PLANT_PARAMETERS = {"r0_nue": [0.0, 800.0, 0.0],
                    # 15 deg of tilt at the start (about the body z axis)
                    "q0_body_to_nue": [math.cos(math.radians(-15.0) / 2), 0.0, 0.0,
                                       math.sin(math.radians(-15.0) / 2)],
                    "m0": [900.0]}


def columns(signals):
    """FMI 2.0 scalar names of the arrays: r_nue -> r_nue[1], r_nue[2], r_nue[3]."""
    return [name if size == 1 else f"{name}[{i + 1}]" for name, size in signals
            for i in range(size)]


class Instance:
    def __init__(self, name, path):
        self.description = read_model_description(path)
        assert self.description.fmiVersion.startswith("3."), f"{path} is not an FMI 3.0 FMU"
        self.variables = {v.name: v for v in self.description.modelVariables}
        self.directory = extract(path)
        self.fmu = FMU3Slave(guid=self.description.guid, unzipDirectory=self.directory,
                             modelIdentifier=self.description.coSimulation.modelIdentifier,
                             instanceName=name)

    def set(self, values):
        """Parameters or inputs: {name: int} for an Int32, {name: [floats]} for a Float64."""
        for name, value in values.items():
            variable = self.variables[name]
            if variable.type == "Int32":
                self.fmu.setInt32([variable.valueReference], [int(value)])
            else:
                self.fmu.setFloat64([variable.valueReference], [float(x) for x in value])

    def get(self, signals):
        """{name: [floats]} of Float64 outputs, each read whole."""
        refs = [self.variables[name].valueReference for name, _ in signals]
        flat = self.fmu.getFloat64(refs, nValues=sum(size for _, size in signals))
        values, k = {}, 0
        for name, size in signals:
            values[name] = list(flat[k:k + size])
            k += size
        return values

    def end_event_instant(self):
        """updateDiscreteStates until no further update is needed, then Step Mode. True when
        the unit asks to end the simulation."""
        while True:
            update_needed, terminate, *_ = self.fmu.updateDiscreteStates()
            if terminate:
                return True
            if not update_needed:
                break
        self.fmu.enterStepMode()
        return False

    def close(self):
        self.fmu.terminate()
        self.fmu.freeInstance()
        shutil.rmtree(self.directory, ignore_errors=True)


def fly(gnc_path, plant_path):
    gnc, plant = Instance("gnc", gnc_path), Instance("plant", plant_path)
    for unit, parameters in ((gnc, GNC_PARAMETERS), (plant, PLANT_PARAMETERS)):
        unit.fmu.instantiate(eventModeUsed=True, earlyReturnAllowed=False)
        unit.set(parameters)
        unit.fmu.enterInitializationMode(startTime=0.0, stopTime=STOP_S)

    def exchange():
        state = plant.get(PLANT_TO_GNC)
        gnc.set(state)
        command = gnc.get(GNC_TO_PLANT)
        plant.set(command)
        return [x for name, _ in PLANT_TO_GNC for x in state[name]] + \
               [x for name, _ in GNC_TO_PLANT for x in command[name]]

    exchange()
    for unit in (gnc, plant):
        unit.fmu.exitInitializationMode()  # into Event Mode (eventModeUsed)

    steps = round(STOP_S / STEP_S)
    rows = []
    for k in range(steps + 1):
        t = k * STEP_S
        if k > 0:
            for unit in (gnc, plant):
                unit.fmu.enterEventMode()
        rows.append([t] + exchange())
        if k == steps:
            break
        if any([unit.end_event_instant() for unit in (gnc, plant)]):
            break
        terminate = False
        for unit in (gnc, plant):
            _, terminate_now, _, _ = unit.fmu.doStep(currentCommunicationPoint=t,
                                                     communicationStepSize=STEP_S)
            terminate |= terminate_now
        if terminate:
            break
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
            writer.writerow(["time"] + [f"plant.{n}" for n in columns(PLANT_TO_GNC)]
                            + [f"gnc.{n}" for n in columns(GNC_TO_PLANT)])
            writer.writerows([repr(v) for v in row] for row in rows)
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:]))
