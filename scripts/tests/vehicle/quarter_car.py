"""A quarter car for the coupling tests: a sprung mass M on a vertical
spring-damper (k, c) hanging on a guideway coupling body (the wheel or
glider the FMU's `couplings` name).

Inputs: the coupling body's vertical position `y_w` (m) and velocity `vy_w`
(m/s), global frame, y up. Output: `force_y` (N), the suspension's force on
the coupling body, to be fed into guideway's `<body>.coupling_force_y`.
The spring is preloaded with the sprung weight M g at the separation `d0`,
so the car starts in static equilibrium. Between communication points the
inputs are held; the sprung mass is integrated with classical RK4 in
`substeps` steps. Built into an FMU with pythonfmu by the tests.
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
        for name in ("y_w", "vy_w"):
            self.register_variable(Real(name, causality=Fmi2Causality.input))
        for name in ("y", "vy", "ay", "force_y"):
            self.register_variable(Real(name, causality=Fmi2Causality.output))

    def suspension(self, y, vy):
        """Force of the suspension on the sprung mass (N, up)."""
        stretch = y - self.y_w - self.d0
        return self.mass * self.gravity - self.stiffness * stretch - self.damping * (vy - self.vy_w)

    def acceleration(self, y, vy):
        return self.suspension(y, vy) / self.mass - self.gravity

    def outputs(self):
        self.ay = self.acceleration(self.y, self.vy)
        self.force_y = -self.suspension(self.y, self.vy)

    def exit_initialization_mode(self):
        self.y, self.vy = self.y0, 0.0
        self.outputs()

    def do_step(self, current_time, step_size):
        h = step_size / self.substeps
        y, v = self.y, self.vy
        a = self.acceleration
        for _ in range(self.substeps):
            k1y, k1v = v, a(y, v)
            k2y, k2v = v + h / 2 * k1v, a(y + h / 2 * k1y, v + h / 2 * k1v)
            k3y, k3v = v + h / 2 * k2v, a(y + h / 2 * k2y, v + h / 2 * k2v)
            k4y, k4v = v + h * k3v, a(y + h * k3y, v + h * k3v)
            y += h / 6 * (k1y + 2 * k2y + 2 * k3y + k4y)
            v += h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v)
        self.y, self.vy = y, v
        self.outputs()
        return True
