"""A third-party FMI 3.0 Co-Simulation FMU, packaged with pythonfmu3: a mass on a spring and
a damper, driven by a force (a landing-leg strut, say), written for the interoperability
tests with no code shared with this project's FMUs.

Model: m x'' + c x' + k x = force; underdamped (c < 2 sqrt(k m)) by contract. Each
communication step holds the force over the step and advances the state by the exact
solution of that linear ODE (zero-order hold), so a constant force gives the closed-form step
response at every communication point, to rounding.

Interface, one variable of each kind the tests exchange:
- parameters: `mass`, `stiffness`, `damping` (Float64), `state0` (Float64 array [x0, v0]);
- input: `force` (Float64, N);
- outputs: `x`, `v` (Float64), `state` (Float64 array [x, v]), `spring_force` (Float64: the
  force the spring and damper pass on to the base, k x + c v), `steps` (Int32: communication
  steps taken), `moving_up` (Boolean: v > 0).

Every output is a function of the state alone (none depends on `force` at the same instant).
"""
import math

from pythonfmu3 import (Boolean, Dimension, Fmi3Causality, Fmi3Slave, Fmi3Variability,
                        Float64, Int32)


class SpringDamperPy3(Fmi3Slave):

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.author = "lander-fmi interoperability tests"
        self.description = "Mass, spring and damper driven by a force (third-party FMI 3.0 FMU)"

        self.time = 0.0
        self.mass = 2.0
        self.stiffness = 50.0
        self.damping = 2.0
        self.state0 = [0.0, 0.0]
        self.force = 0.0
        self.steps = 0
        self.current = None  # [x, v] from the end of initialization on

        self.register_variable(Float64("time", causality=Fmi3Causality.independent,
                                       variability=Fmi3Variability.continuous))
        for name in ("mass", "stiffness", "damping"):
            self.register_variable(Float64(name, causality=Fmi3Causality.parameter,
                                           variability=Fmi3Variability.fixed))
        self.register_variable(Float64("state0", causality=Fmi3Causality.parameter,
                                       variability=Fmi3Variability.fixed,
                                       dimensions=[Dimension(start="2")],
                                       getter=lambda: list(self.state0),
                                       setter=self._set_state0))
        self.register_variable(Float64("force", causality=Fmi3Causality.input,
                                       variability=Fmi3Variability.continuous))
        self.register_variable(Float64("x", causality=Fmi3Causality.output,
                                       variability=Fmi3Variability.continuous,
                                       getter=lambda: self._state()[0]))
        self.register_variable(Float64("v", causality=Fmi3Causality.output,
                                       variability=Fmi3Variability.continuous,
                                       getter=lambda: self._state()[1]))
        self.register_variable(Float64("state", causality=Fmi3Causality.output,
                                       variability=Fmi3Variability.continuous,
                                       dimensions=[Dimension(start="2")],
                                       getter=lambda: list(self._state())))
        self.register_variable(Float64("spring_force", causality=Fmi3Causality.output,
                                       variability=Fmi3Variability.continuous,
                                       getter=self._spring_force))
        self.register_variable(Int32("steps", causality=Fmi3Causality.output,
                                     variability=Fmi3Variability.discrete))
        self.register_variable(Boolean("moving_up", causality=Fmi3Causality.output,
                                       variability=Fmi3Variability.discrete,
                                       getter=lambda: self._state()[1] > 0.0))

    def _set_state0(self, values):
        self.state0 = [float(values[0]), float(values[1])]

    def _state(self):
        return self.current if self.current is not None else self.state0

    def _spring_force(self):
        x, v = self._state()
        return self.stiffness * x + self.damping * v

    def exit_initialization_mode(self):
        self.current = list(self.state0)

    def do_step(self, current_time, step_size):
        m, k, c = self.mass, self.stiffness, self.damping
        omega = math.sqrt(k / m)
        sigma = c / (2.0 * m)
        omega_d = math.sqrt(omega * omega - sigma * sigma)
        x, v = self.current
        equilibrium = self.force / k
        e = x - equilibrium
        b = (v + sigma * e) / omega_d
        decay = math.exp(-sigma * step_size)
        cos, sin = math.cos(omega_d * step_size), math.sin(omega_d * step_size)
        self.current = [equilibrium + decay * (e * cos + b * sin),
                        decay * (v * cos - (sigma * b + omega_d * e) * sin)]
        self.steps += 1
        self.time = current_time + step_size
        return True
