"""LanderGnc flying a vehicle of your own in fmpy: a rigid body written here in plain Python,
whose thrust is along its own body +z, wired to the GNC through a constant rotation.

    pip install fmpy
    python own_vehicle.py path/to/LanderGnc.fmu [--mistake NAME] [--seconds S] [--products P]

The FMU may be the FMI 2.0 or the FMI 3.0 LanderGnc (read from its model description).
The vehicle: 1,000 kg, principal inertia 900/700/1,000 kg m2, thrust 800-2,400 N along body
+z, torque +-200 N m per axis, lunar gravity (--products P gives its inertia tensor the
products of inertia Ixy = Iyz = Izx = -P kg m2; the GNC is given the tensor's diagonal). It hovers at 800 m, turns the GNC's sensor axis
by 150 deg about the thrust axis and starts the descent. Every message the GNC logs is
printed as it comes.

--mistake makes one of the wiring mistakes a first flight with a new plant usually makes, to
see the message that names it (docs/interface.md, "Bringing your own vehicle"):
  scalar-last        the quaternion sent as [x, y, z, w]
  conjugate          the quaternion from NUE to body instead of body to NUE
  deg-per-s          body rates in deg/s
  enu                position and velocity in East, North, Up
  earth-gravity      gravity = 9.81
  inertia-1000x      the vehicle's inertia 1,000 times the one declared to the GNC
  thrust-max-default thrust_max left at the GNC's default (1,600 N, below the weight)

The constant rotation: the GNC's thrust axis is its body +y. q_c, from GNC body axes to this
vehicle's body axes, is +90 deg about x (it takes +y to +z), and
  q_body_to_nue = q_vehicle_to_nue * q_c,
  omega_body    = R(q_c)^T omega_vehicle,
  torque on the vehicle = R(q_c) torque_cmd_body,
  inertia_body  = [Ixx, Izz, Iyy] of the vehicle.
"""
import argparse
import math
import shutil
import sys

from fmpy import extract, read_model_description

STEP_S = 0.01
MOON_GRAVITY = 1.62
INERTIA_VEHICLE = (900.0, 700.0, 1000.0)
MISTAKES = ["none", "scalar-last", "conjugate", "deg-per-s", "enu", "earth-gravity",
            "inertia-1000x", "thrust-max-default"]


# Quaternions [w, x, y, z], Hamilton product; vectors as 3-lists.
def q_mul(a, b):
    aw, ax, ay, az = a
    bw, bx, by, bz = b
    return [aw * bw - ax * bx - ay * by - az * bz,
            aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw]


def q_conj(q):
    return [q[0], -q[1], -q[2], -q[3]]


def rotate(q, v):
    """R(q) v: a vector in the rotated frame expressed in the reference frame."""
    return q_mul(q_mul(q, [0.0] + list(v)), q_conj(q))[1:]


def normalized(q):
    n = math.sqrt(sum(x * x for x in q))
    return [x / n for x in q]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def mat_vec(m, v):
    return [sum(m[i][k] * v[k] for k in range(3)) for i in range(3)]


def inverse(m):
    """The inverse of a 3x3 matrix (cofactors over the determinant)."""
    c = [cross(m[(i + 1) % 3], m[(i + 2) % 3]) for i in range(3)]  # rows of adj(m)^T
    det = sum(m[0][k] * c[0][k] for k in range(3))
    return [[c[k][i] / det for k in range(3)] for i in range(3)]


Q_C = [math.cos(math.pi / 4), math.sin(math.pi / 4), 0.0, 0.0]  # GNC body -> vehicle body


class Vehicle:
    """A rigid body with thrust along its body +z, integrated in 10 sub-steps per step."""

    def __init__(self, inertia_scale=1.0, products=0.0):
        tilt = math.radians(15.0)  # tilted toward North at the start, as in the paper
        q_gnc_to_nue = [math.cos(tilt / 2), 0.0, 0.0, -math.sin(tilt / 2)]
        self.r_nue = [0.0, 800.0, 0.0]
        self.v_nue = [0.0, 0.0, 0.0]
        self.q_vehicle_to_nue = q_mul(q_gnc_to_nue, q_conj(Q_C))
        self.omega_vehicle = [0.01, -0.02, 0.01]
        self.mass_kg = 1000.0
        i = INERTIA_VEHICLE
        self.inertia = [[(i[r] if r == c else -products) * inertia_scale for c in range(3)]
                        for r in range(3)]
        self.inertia_inverse = inverse(self.inertia)

    def step(self, thrust_n, torque_vehicle, dt):
        thrust_n = 0.0 if thrust_n <= 1.0 else min(max(thrust_n, 800.0), 2400.0)
        torque = [min(max(t, -200.0), 200.0) for t in torque_vehicle]
        n = 10
        h = dt / n
        for _ in range(n):
            along = rotate(self.q_vehicle_to_nue, [0.0, 0.0, thrust_n / self.mass_kg])
            a = [along[0], along[1] - MOON_GRAVITY, along[2]]
            self.r_nue = [r + v * h + 0.5 * x * h * h for r, v, x in zip(self.r_nue, self.v_nue, a)]
            self.v_nue = [v + x * h for v, x in zip(self.v_nue, a)]
            w = self.omega_vehicle
            gyro = cross(w, mat_vec(self.inertia, w))
            w_dot = mat_vec(self.inertia_inverse, [torque[k] - gyro[k] for k in range(3)])
            w_mid = [w[k] + 0.5 * h * w_dot[k] for k in range(3)]
            self.omega_vehicle = [w[k] + h * w_dot[k] for k in range(3)]
            dq = q_mul(self.q_vehicle_to_nue, [0.0] + w_mid)
            self.q_vehicle_to_nue = normalized(
                [q + 0.5 * h * d for q, d in zip(self.q_vehicle_to_nue, dq)])

    def navigation(self, mistake):
        """What the GNC reads: r_nue, v_nue, q_body_to_nue, omega_body, mass (14 values)."""
        r, v = list(self.r_nue), list(self.v_nue)
        q = q_mul(self.q_vehicle_to_nue, Q_C)
        omega = rotate(q_conj(Q_C), self.omega_vehicle)
        if mistake == "scalar-last":
            q = q[1:] + q[:1]
        elif mistake == "conjugate":
            q = q_conj(q)
        elif mistake == "deg-per-s":
            omega = [math.degrees(w) for w in omega]
        elif mistake == "enu":
            r, v = [r[2], r[0], r[1]], [v[2], v[0], v[1]]
        return r + v + q + omega + [self.mass_kg]


def gnc_parameters(mistake):
    """LanderGnc's parameters for this vehicle, in GNC body axes."""
    i = INERTIA_VEHICLE
    parameters = {"phi_cmd": [math.radians(150.0)], "inertia_body": [i[0], i[2], i[1]],
                  "thrust_min": [800.0], "thrust_max": [2400.0],
                  "torque_limit_body": [200.0] * 3, "gravity": [MOON_GRAVITY]}
    if mistake == "earth-gravity":
        parameters["gravity"] = [9.81]
    if mistake == "thrust-max-default":
        del parameters["thrust_max"]
    return parameters


INPUTS = [("r_nue", 3), ("v_nue", 3), ("q_body_to_nue", 4), ("omega_body", 3), ("mass", 1)]
OUTPUTS = [("thrust_cmd", 1), ("torque_cmd_body", 3)]


class Gnc:
    """LanderGnc through fmpy, FMI 2.0 (set, get, step: the command of t_k acts over
    [t_k, t_k + h]) or FMI 3.0 with Event Mode (the same loop, FMI 3.0's way)."""

    def __init__(self, path, log):
        self.description = read_model_description(path)
        self.fmi3 = self.description.fmiVersion.startswith("3.")
        self.directory = extract(path)
        common = dict(guid=self.description.guid, unzipDirectory=self.directory,
                      modelIdentifier=self.description.coSimulation.modelIdentifier,
                      instanceName="gnc")
        self.vr = {v.name: v.valueReference for v in self.description.modelVariables}
        if self.fmi3:
            from fmpy.fmi3 import FMU3Slave
            self.fmu = FMU3Slave(**common)
            self.fmu.instantiate(eventModeUsed=True, earlyReturnAllowed=False,
                                 logMessage=lambda env, status, category, message:
                                 log(status, message.decode()))
        else:
            from ctypes import byref
            from fmpy.fmi2 import (FMU2Slave, fmi2CallbackFunctions, fmi2CallbackLoggerTYPE,
                                   fmi2CallbackAllocateMemoryTYPE, fmi2CallbackFreeMemoryTYPE,
                                   calloc, free)
            from fmpy.logging import addLoggerProxy
            self.fmu = FMU2Slave(**common)
            callbacks = fmi2CallbackFunctions()
            callbacks.logger = fmi2CallbackLoggerTYPE(
                lambda env, name, status, category, message: log(status, message.decode()))
            callbacks.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
            callbacks.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
            addLoggerProxy(byref(callbacks))  # formats the message's variadic arguments
            self.callbacks = callbacks  # kept alive as long as the instance
            self.fmu.instantiate(callbacks=callbacks)

    def names(self, signals):
        """FMI 3.0: one array variable per signal; FMI 2.0: one scalar per element."""
        if self.fmi3:
            return [name for name, _ in signals]
        return [name if size == 1 else f"{name}[{k + 1}]" for name, size in signals
                for k in range(size)]

    def set_parameters(self, parameters):
        for name, values in parameters.items():
            if self.fmi3:
                self.fmu.setFloat64([self.vr[name]], values)
            else:
                self.fmu.setReal([self.vr[n] for n in self.names([(name, len(values))])],
                                 values)

    def set_inputs(self, values):
        refs = [self.vr[n] for n in self.names(INPUTS)]
        if self.fmi3:
            self.fmu.setFloat64(refs, values)
        else:
            self.fmu.setReal(refs, values)

    def commands(self):
        refs = [self.vr[n] for n in self.names(OUTPUTS)]
        if self.fmi3:
            return list(self.fmu.getFloat64(refs, nValues=4))
        return list(self.fmu.getReal(refs))

    def start(self, parameters, stop_s, inputs):
        if self.fmi3:
            self.set_parameters(parameters)
            self.fmu.enterInitializationMode(startTime=0.0, stopTime=stop_s)
        else:
            self.fmu.setupExperiment(startTime=0.0, stopTime=stop_s)
            self.set_parameters(parameters)
            self.fmu.enterInitializationMode()
        self.set_inputs(inputs)
        self.commands()
        self.fmu.exitInitializationMode()  # FMI 3.0: into Event Mode (eventModeUsed)
        self.in_event_mode = self.fmi3

    def exchange(self, inputs):
        """The command for these inputs, at this communication point."""
        if self.fmi3 and not self.in_event_mode:
            self.fmu.enterEventMode()
            self.in_event_mode = True
        self.set_inputs(inputs)
        return self.commands()

    def step(self, t, h):
        if self.fmi3:
            while True:
                update_needed, terminate, *_ = self.fmu.updateDiscreteStates()
                if terminate or not update_needed:
                    break
            self.fmu.enterStepMode()
            self.in_event_mode = False
        self.fmu.doStep(currentCommunicationPoint=t, communicationStepSize=h)

    def close(self):
        self.fmu.terminate()
        self.fmu.freeInstance()
        shutil.rmtree(self.directory, ignore_errors=True)


LABELS = ["OK", "WARNING", "DISCARD", "ERROR", "FATAL", "PENDING"]


def fly(gnc_path, mistake="none", seconds=40.0, products=0.0):
    """Flies `seconds`; returns the messages logged, as (label, text), and the lowest height."""
    messages = []

    def log(status, text):
        messages.append((LABELS[status], text))
        print(f"gnc [{LABELS[status]}] {text}", flush=True)

    gnc = Gnc(gnc_path, log)
    vehicle = Vehicle(inertia_scale=1000.0 if mistake == "inertia-1000x" else 1.0,
                      products=products)
    gnc.start(gnc_parameters(mistake), seconds, vehicle.navigation(mistake))
    lowest_m = vehicle.r_nue[1]
    steps = round(seconds / STEP_S)
    for k in range(steps):
        t = k * STEP_S
        thrust_n, *torque_gnc = gnc.exchange(vehicle.navigation(mistake))
        gnc.step(t, STEP_S)
        vehicle.step(thrust_n, rotate(Q_C, torque_gnc), STEP_S)
        lowest_m = min(lowest_m, vehicle.r_nue[1])
        if vehicle.r_nue[1] <= 0.0:
            print(f"t = {t + STEP_S:.2f} s: the vehicle hit the ground")
            break
    gnc.close()
    return messages, lowest_m


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("gnc", help="LanderGnc.fmu (FMI 2.0 or 3.0)")
    parser.add_argument("--mistake", choices=MISTAKES, default="none")
    parser.add_argument("--seconds", type=float, default=40.0)
    parser.add_argument("--products", type=float, default=0.0,
                        help="products of inertia of the vehicle, kg m2")
    args = parser.parse_args(argv)
    messages, lowest_m = fly(args.gnc, args.mistake, args.seconds, args.products)
    print(f"lowest height {lowest_m:.1f} m; LanderGnc logged {len(messages)} message(s)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
