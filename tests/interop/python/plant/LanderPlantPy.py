"""A third-party lunar lander plant: a rigid body over a flat Moon, written from
docs/interface.md alone (no code shared with LanderPlant) and packaged as an FMI 2.0
Co-Simulation FMU with pythonfmu.

Signal contract (docs/interface.md): NUE frame (1 North, 2 Up, 3 East), gravity [0, -g, 0];
body axes 1 = x, 2 = y = thrust axis, 3 = z; quaternion Hamilton, scalar first,
`q_body_to_nue` rotates body vectors into NUE; `omega_body` in body axes.

Model: translation m r'' = R(q) [0, T, 0] + m [0, -g, 0]; rotation I w' = tau - w x I w with
a diagonal inertia; q' = q (x) [0, w] / 2; mass flow m' = -T / (isp g0). The thrust command is
off at or below 1 N, else held in [720, 1600] N; the torque command is limited to +-116 N m
per axis (two 58 N thrusters on a 1 m arm); at the dry mass the engines cut out. One
classical RK4 step per communication step; the quaternion is renormalised after it. No
touchdown model: the scenarios flown with it end hovering.
"""
import math

from pythonfmu import Fmi2Causality, Fmi2Slave, Fmi2Variability, Real

GRAVITY_MPS2 = 1.62
ISP_S = 300.0
G0_MPS2 = 9.81
DRY_MASS_KG = 600.0
INERTIA_BODY_KGM2 = (400.0, 300.0, 450.0)
THRUST_OFF_N = 1.0
THRUST_MIN_N = 720.0
THRUST_MAX_N = 1600.0
TORQUE_MAX_NM = 116.0


def quat_mul(a, b):
    aw, ax, ay, az = a
    bw, bx, by, bz = b
    return (aw * bw - ax * bx - ay * by - az * bz,
            aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw)


def rotate(q, v):
    """q (x) [0, v] (x) q*: a body vector in NUE."""
    w, x, y, z = quat_mul(quat_mul(q, (0.0, *v)), (q[0], -q[1], -q[2], -q[3]))
    return (x, y, z)


def derivative(state, thrust_n, torque_body_nm):
    r, v, q, w, m = state
    thrust = thrust_n if m > DRY_MASS_KG else 0.0
    f_nue = rotate(q, (0.0, thrust, 0.0))
    a = (f_nue[0] / m, f_nue[1] / m - GRAVITY_MPS2, f_nue[2] / m)
    i = INERTIA_BODY_KGM2
    iw = (i[0] * w[0], i[1] * w[1], i[2] * w[2])
    gyro = (w[1] * iw[2] - w[2] * iw[1], w[2] * iw[0] - w[0] * iw[2], w[0] * iw[1] - w[1] * iw[0])
    w_dot = tuple((torque_body_nm[k] - gyro[k]) / i[k] for k in range(3))
    q_dot = tuple(0.5 * c for c in quat_mul(q, (0.0, *w)))
    return (v, a, q_dot, w_dot, -thrust / (ISP_S * G0_MPS2))


def advance(state, d, h):
    return tuple(tuple(s + h * ds for s, ds in zip(part, dpart)) if isinstance(part, tuple)
                 else part + h * dpart for part, dpart in zip(state, d))


def rk4(state, thrust_n, torque_body_nm, h):
    k1 = derivative(state, thrust_n, torque_body_nm)
    k2 = derivative(advance(state, k1, h / 2), thrust_n, torque_body_nm)
    k3 = derivative(advance(state, k2, h / 2), thrust_n, torque_body_nm)
    k4 = derivative(advance(state, k3, h), thrust_n, torque_body_nm)
    combined = tuple(
        tuple((a + 2 * b + 2 * c + e) / 6 for a, b, c, e in zip(p1, p2, p3, p4))
        if isinstance(p1, tuple) else (p1 + 2 * p2 + 2 * p3 + p4) / 6
        for p1, p2, p3, p4 in zip(k1, k2, k3, k4))
    r, v, q, w, m = advance(state, combined, h)
    norm = math.sqrt(sum(c * c for c in q))
    return (r, v, tuple(c / norm for c in q), w, m)


class LanderPlantPy(Fmi2Slave):

    author = "lander-fmi interoperability tests"
    description = "Rigid-body lunar lander over a flat Moon (third-party plant for LanderGnc)"

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.r0_nue = [0.0, 800.0, 0.0]
        self.v0_nue = [0.0, 0.0, 0.0]
        self.q0_body_to_nue = [1.0, 0.0, 0.0, 0.0]
        self.omega0_body = [0.0, 0.0, 0.0]
        self.m0 = 900.0
        self.thrust_cmd = 0.0
        self.torque_cmd_body = [0.0, 0.0, 0.0]
        self.state = None  # set when initialization ends; before, outputs show the initial values
        self._vector("r0_nue", 3, Fmi2Causality.parameter, "m")
        self._vector("v0_nue", 3, Fmi2Causality.parameter, "m/s")
        self._vector("q0_body_to_nue", 4, Fmi2Causality.parameter, "1")
        self._vector("omega0_body", 3, Fmi2Causality.parameter, "rad/s")
        self.register_variable(Real("m0", causality=Fmi2Causality.parameter,
                                    variability=Fmi2Variability.fixed))
        self.register_variable(Real("thrust_cmd", causality=Fmi2Causality.input))
        self._vector("torque_cmd_body", 3, Fmi2Causality.input, "N.m")
        for name, part, size in (("r_nue", 0, 3), ("v_nue", 1, 3), ("q_body_to_nue", 2, 4),
                                 ("omega_body", 3, 3)):
            for k in range(size):
                self.register_variable(Real(f"{name}[{k + 1}]", causality=Fmi2Causality.output,
                                            getter=lambda part=part, k=k: self._current()[part][k]))
        self.register_variable(Real("mass", causality=Fmi2Causality.output,
                                    getter=lambda: self._current()[4]))

    def _vector(self, name, size, causality, unit):
        values = getattr(self, name)
        variability = (Fmi2Variability.fixed if causality == Fmi2Causality.parameter
                       else Fmi2Variability.continuous)
        for k in range(size):
            def set_component(value, k=k):
                values[k] = value
            self.register_variable(Real(f"{name}[{k + 1}]", causality=causality,
                                        variability=variability,
                                        getter=lambda k=k: values[k], setter=set_component))

    def _initial(self):
        return (tuple(self.r0_nue), tuple(self.v0_nue), tuple(self.q0_body_to_nue),
                tuple(self.omega0_body), self.m0)

    def _current(self):
        return self.state if self.state is not None else self._initial()

    def exit_initialization_mode(self):
        q = self.q0_body_to_nue
        norm = math.sqrt(sum(c * c for c in q))
        r, v, _, w, m = self._initial()
        self.state = (r, v, tuple(c / norm for c in q), w, m)

    def do_step(self, current_time, step_size):
        thrust = 0.0 if self.thrust_cmd <= THRUST_OFF_N else min(max(self.thrust_cmd, THRUST_MIN_N),
                                                                 THRUST_MAX_N)
        torque = tuple(min(max(t, -TORQUE_MAX_NM), TORQUE_MAX_NM) for t in self.torque_cmd_body)
        self.state = rk4(self.state, thrust, torque, step_size)
        return True
