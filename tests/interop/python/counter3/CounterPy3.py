"""A third-party FMI 3.0 Co-Simulation FMU, packaged with pythonfmu3, with a structural
parameter and the non-Float64 types pythonfmu3 (0.3.4) exports: written for the
interoperability tests with no code shared with this project's FMUs.

Interface:
- structural parameter `n` (UInt64, start 2), set in Configuration Mode; it sizes the
  Float64 arrays `gains` (parameter, gains[i] = i + 1 unless set) and `y` (output);
- parameter `offset` (Int64, start -2^62: beyond what an f64 holds exactly);
- inputs `u` (Float64), `big_in` (UInt64), `label_in` (String);
- outputs, each a function of the state the last step left (none depends on an input at
  the same instant):
  `y[i] = gains[i] * u + steps` as of the last step (Float64 array of n),
  `count = offset + steps` (Int64), `big = 2^64 - 1 - steps` (UInt64, above 2^63),
  `odd` (Boolean: steps is odd), `label` (String, "n=<n> step <steps>"),
  `echo_big` (UInt64: big_in as of the last step), `echo_label` (String: label_in as of
  the last step, with "!" added).
"""
from pythonfmu3 import (Boolean, Dimension, Fmi3Causality, Fmi3Slave, Fmi3Variability,
                        Float64, Int64, String, UInt64)

U64_MAX = 2**64 - 1


class CounterPy3(Fmi3Slave):

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.author = "lander-fmi interoperability tests"
        self.description = "Counter with a structural parameter (third-party FMI 3.0 FMU)"

        self.time = 0.0
        self.n = 2
        self.gains = [1.0, 2.0]
        self.offset = -2**62
        self.u = 0.0
        self.big_in = 0
        self.label_in = ""
        self.steps = 0
        self.y = [0.0, 0.0]
        self.echo_big = 0
        self.echo_label = "!"

        self.register_variable(Float64("time", causality=Fmi3Causality.independent,
                                       variability=Fmi3Variability.continuous))
        n = UInt64("n", causality=Fmi3Causality.structuralParameter,
                   variability=Fmi3Variability.fixed, setter=self._set_n)
        self.register_variable(n)
        by_n = [Dimension(valueReference=str(n.value_reference))]
        self.register_variable(Float64("gains", causality=Fmi3Causality.parameter,
                                       variability=Fmi3Variability.fixed, dimensions=by_n,
                                       getter=lambda: list(self.gains),
                                       setter=self._set_gains))
        self.register_variable(Int64("offset", causality=Fmi3Causality.parameter,
                                     variability=Fmi3Variability.fixed))
        self.register_variable(Float64("u", causality=Fmi3Causality.input,
                                       variability=Fmi3Variability.continuous))
        self.register_variable(UInt64("big_in", causality=Fmi3Causality.input,
                                      variability=Fmi3Variability.discrete))
        self.register_variable(String("label_in", causality=Fmi3Causality.input,
                                      variability=Fmi3Variability.discrete))
        self.register_variable(Float64("y", causality=Fmi3Causality.output,
                                       variability=Fmi3Variability.continuous,
                                       dimensions=by_n, getter=lambda: list(self.y)))
        self.register_variable(Int64("count", causality=Fmi3Causality.output,
                                     variability=Fmi3Variability.discrete,
                                     getter=lambda: self.offset + self.steps))
        self.register_variable(UInt64("big", causality=Fmi3Causality.output,
                                      variability=Fmi3Variability.discrete,
                                      getter=lambda: U64_MAX - self.steps))
        self.register_variable(Boolean("odd", causality=Fmi3Causality.output,
                                       variability=Fmi3Variability.discrete,
                                       getter=lambda: self.steps % 2 == 1))
        self.register_variable(String("label", causality=Fmi3Causality.output,
                                      variability=Fmi3Variability.discrete,
                                      getter=lambda: f"n={self.n} step {self.steps}"))
        self.register_variable(UInt64("echo_big", causality=Fmi3Causality.output,
                                      variability=Fmi3Variability.discrete))
        self.register_variable(String("echo_label", causality=Fmi3Causality.output,
                                      variability=Fmi3Variability.discrete))

    def _set_n(self, value):
        self.n = int(value)
        self.gains = [float(i + 1) for i in range(self.n)]
        self.y = [0.0] * self.n

    def _set_gains(self, values):
        self.gains = [float(x) for x in values]

    def do_step(self, current_time, step_size):
        self.y = [g * self.u + self.steps for g in self.gains]
        self.echo_big = int(self.big_in)
        self.echo_label = f"{self.label_in}!"
        self.steps += 1
        self.time = current_time + step_size
        return True
