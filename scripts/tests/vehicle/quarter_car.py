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
inputs too), or the parabola through the last three (`extrapolate` = 2), or
their Taylor polynomial from the exact derivatives at the communication
point (`extrapolate` = 3: d y_w/dt = vy_w, d vy_w/dt = the optional input
`ay_w`, the coupling body's acceleration; scripts/coupling_order.py); the
sprung mass is integrated with classical RK4 in `substeps` steps. The
outputs `ay` and `force_y` depend directly on the inputs: they are computed
at the end of each step from the inputs extrapolated to it (`consistent` =
0), or whenever they are read, from the state and the inputs as last set
(`consistent` = 1: a master that sets the inputs at t + H before reading
gets outputs consistent with them). Built into an FMU with pythonfmu by the
tests.
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
        self.consistent = 0
        self.history = []  # (time, y_w, vy_w) at the last communication points, newest first
        self.nominal = None  # the first communication step's size
        self.y_w = 0.0
        self.vy_w = 0.0
        self.ay_w = 0.0
        self.y = 1.0
        self.vy = 0.0
        self.ay = 0.0
        self.force_y = 0.0
        par = dict(causality=Fmi2Causality.parameter, variability=Fmi2Variability.fixed)
        for name in ("mass", "stiffness", "damping", "gravity", "d0", "y0"):
            self.register_variable(Real(name, **par))
        self.register_variable(Integer("substeps", **par))
        self.register_variable(Integer("extrapolate", **par))
        self.register_variable(Integer("consistent", **par))
        for name in ("y_w", "vy_w", "ay_w"):
            self.register_variable(Real(name, causality=Fmi2Causality.input))
        for name in ("y", "vy"):
            self.register_variable(Real(name, causality=Fmi2Causality.output))
        for name in ("ay", "force_y"):
            self.register_variable(Real(name, causality=Fmi2Causality.output,
                                        getter=lambda name=name: self.read(name)))

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

    def read(self, name):
        """An output with direct feedthrough, as `consistent` says."""
        if self.consistent:
            self.outputs((self.y_w, self.vy_w))
        return getattr(self, name)

    def exit_initialization_mode(self):
        self.y, self.vy = self.y0, 0.0
        self.outputs((self.y_w, self.vy_w))

    def inputs(self, current_time):
        """The inputs at current_time + s: held, or extrapolated from the
        last communication points, or from their exact derivatives."""
        now = (current_time, self.y_w, self.vy_w)
        past = [p for p in self.history if p[0] < current_time]
        self.history = [now] + past[:1]
        if self.extrapolate == 3:
            y, v, a = self.y_w, self.vy_w, self.ay_w
            return lambda s: (y + v * s + a * s * s / 2, v + a * s)
        if not self.extrapolate or not past:
            return lambda s: (now[1], now[2])
        dt = self.snapped(current_time, current_time - past[0][0])
        rates = [(now[i] - past[0][i]) / dt for i in (1, 2)]
        if self.extrapolate == 1 or len(past) < 2:
            return lambda s: (now[1] + rates[0] * s, now[2] + rates[1] * s)
        # the parabola through three equally spaced points
        curvature = [(now[i] - 2 * past[0][i] + past[1][i]) / dt**2 for i in (1, 2)]
        return lambda s: tuple(now[i + 1] + (rates[i] + curvature[i] * dt / 2) * s
                               + curvature[i] * s * s / 2 for i in (0, 1))

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
