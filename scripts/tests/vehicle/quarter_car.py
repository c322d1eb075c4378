"""A quarter car for the coupling tests: a sprung mass M on a vertical
spring-damper (k, c) hanging on a guideway coupling body (the wheel or
glider the FMU's `couplings` name).

Inputs: the coupling body's vertical position `y_w` (m) and velocity `vy_w`
(m/s), global frame, y up. Output: `force_y` (N), the suspension's force on
the coupling body, to be fed into guideway's `<body>.coupling_force_y`.
The spring is preloaded with the sprung weight M g at the separation `d0`,
so the car starts in static equilibrium. Between communication points the
inputs are held (`extrapolate` = 0), or follow the line through their values
at the last two communication points (`extrapolate` = 1, second-order
coupling; the output at the end of the step then uses the extrapolated
inputs too); the sprung mass is integrated with classical RK4 in `substeps`
steps. Built into an FMU with pythonfmu by the tests.
"""

from pythonfmu import Fmi2Causality, Fmi2Slave, Fmi2Variability, Real, Integer


class quarter_car(Fmi2Slave):
    author = "guideway tests"
    description = "sprung mass on a spring-damper over a guideway coupling body"

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.mass = 5750.0
        self.stiffness = 1.595e6
        self.damping = 2.0e4
        self.gravity = 9.81
        self.d0 = 1.0
        self.y0 = 1.0
        self.substeps = 20
        self.extrapolate = 0
        self.history = None  # (time, y_w, vy_w) at the last communication point
        self.nominal = None  # the first communication step's size
        self.y_w = 0.0
        self.vy_w = 0.0
        self.y = 1.0
        self.vy = 0.0
        self.ay = 0.0
        self.force_y = 0.0
        par = dict(causality=Fmi2Causality.parameter, variability=Fmi2Variability.fixed)
        for name in ("mass", "stiffness", "damping", "gravity", "d0", "y0"):
            self.register_variable(Real(name, **par))
        self.register_variable(Integer("substeps", **par))
        self.register_variable(Integer("extrapolate", **par))
        for name in ("y_w", "vy_w"):
            self.register_variable(Real(name, causality=Fmi2Causality.input))
        for name in ("y", "vy", "ay", "force_y"):
            self.register_variable(Real(name, causality=Fmi2Causality.output))

    def suspension(self, y, vy, w):
        """Force of the suspension on the sprung mass (N, up) with the
        coupling body at w = (y_w, vy_w)."""
        stretch = y - w[0] - self.d0
        return self.mass * self.gravity - self.stiffness * stretch - self.damping * (vy - w[1])

    def acceleration(self, y, vy, w):
        return self.suspension(y, vy, w) / self.mass - self.gravity

    def outputs(self, w):
        self.ay = self.acceleration(self.y, self.vy, w)
        self.force_y = -self.suspension(self.y, self.vy, w)

    def exit_initialization_mode(self):
        self.y, self.vy = self.y0, 0.0
        self.outputs((self.y_w, self.vy_w))

    def inputs(self, current_time):
        """The inputs at current_time + s: held, or along the line through
        the last two communication points."""
        now = (current_time, self.y_w, self.vy_w)
        past, self.history = self.history, now
        if not self.extrapolate or past is None or current_time <= past[0]:
            return lambda s: (now[1], now[2])
        dt = self.snapped(current_time, current_time - past[0])
        rates = ((now[1] - past[1]) / dt, (now[2] - past[2]) / dt)
        return lambda s: (now[1] + rates[0] * s, now[2] + rates[1] * s)

    def snapped(self, current_time, step_size):
        """The step size, or the first step's if within a few ulp of the
        time of it: masters that count time in integers (libcosim) pass
        t[k+1] - t[k], off by ulps of t, and the results must not depend
        on it."""
        if self.nominal is None:
            self.nominal = step_size
        ulp = 2.0**-52 * max(abs(current_time) + step_size, self.nominal)
        if abs(step_size - self.nominal) <= 8 * ulp:
            return self.nominal
        return step_size

    def do_step(self, current_time, step_size):
        step_size = self.snapped(current_time, step_size)
        h = step_size / self.substeps
        y, v = self.y, self.vy
        a = self.acceleration
        w = self.inputs(current_time)
        for i in range(self.substeps):
            w0, wm, w1 = w(i * h), w((i + 0.5) * h), w((i + 1) * h)
            k1y, k1v = v, a(y, v, w0)
            k2y, k2v = v + h / 2 * k1v, a(y + h / 2 * k1y, v + h / 2 * k1v, wm)
            k3y, k3v = v + h / 2 * k2v, a(y + h / 2 * k2y, v + h / 2 * k2v, wm)
            k4y, k4v = v + h * k3v, a(y + h * k3y, v + h * k3v, w1)
            y += h / 6 * (k1y + 2 * k2y + 2 * k3y + k4y)
            v += h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v)
        self.y, self.vy = y, v
        self.outputs(w(step_size))
        return True
