"""The OpenSeesPy side of the peer bench: a simply supported
Euler–Bernoulli beam of elasticBeamColumn elements (consistent mass,
Newmark average acceleration, one factorisation) under (a) a moving force,
as Path time series of its Hermite nodal loads, or (b) a sprung mass on a
massless follower, coupled by a Python loop (the beam one step under the
last contact force, then the sprung mass over that step: first order in
the coupling). Written for this project from OpenSeesPy's documentation.

    python opensees_models.py CASE.json OUT.json [--no-history]

CASE.json: the case (scripts/peers/opensees_bench.py, `CASES`) with
`elements`, `step` and `steps`. OUT.json: `time` and `midspan` (up
positive, m) at every step from t = 0, and `wallSolve_s`, the time spent
in OpenSees' analyze calls. Runs in the peers venv, which has openseespy.
"""

import json
import sys
import time

# Imported in main(): the shape functions serve the tests without the peer.
ops = None


def hermite(x, length, elements):
    """(element, [N1, N2, N3, N4]) of the cubic Hermite shape functions at
    x (the last element at x = L), and their x-derivatives."""
    size = length / elements
    e = min(max(int(x / size), 0), elements - 1)
    s = x / size - e
    shape = [1 - 3 * s**2 + 2 * s**3, size * (s - 2 * s**2 + s**3), 3 * s**2 - 2 * s**3,
             size * (s**3 - s**2)]
    slope = [(-6 * s + 6 * s**2) / size, 1 - 4 * s + 3 * s**2, (6 * s - 6 * s**2) / size,
             3 * s**2 - 2 * s]
    return e, shape, slope


def build_beam(case):
    """Nodes 0..n along x, pinned at both ends; the axial DOF held (the
    beam carries no axial load, as guideway's Euler–Bernoulli beam)."""
    n, length = case["elements"], case["length"]
    ops.wipe()
    ops.model("basic", "-ndm", 2, "-ndf", 3)
    for i in range(n + 1):
        ops.node(i, length * i / n, 0.0)
        ops.fix(i, 1, 1 if i in (0, n) else 0, 0)
    ops.geomTransf("Linear", 1)
    for e in range(n):
        ops.element("elasticBeamColumn", e + 1, e, e + 1, 1.0, case["bending_stiffness"], 1.0, 1,
                    "-mass", case["mass_per_length"], "-cMass")


def set_up_analysis():
    ops.constraints("Plain")
    ops.numberer("RCM")
    ops.system("BandSPD")
    # Elastic: the tangent never changes, so it is factorised once.
    ops.algorithm("Linear", "-factorOnce")
    ops.integrator("Newmark", 0.5, 0.25)
    ops.analysis("Transient")


def moving_force_loads(case):
    """Per loaded DOF (node, dof), the nodal load at every step: the
    force's Hermite nodal loads at x = V t_k, nothing once it has left."""
    n, length, step = case["elements"], case["length"], case["step"]
    loads = {}
    for k in range(case["steps"] + 1):
        x = case["speed"] * k * step
        if x > length:
            continue
        e, shape, _ = hermite(x, length, n)
        for (node, dof), weight in zip([(e, 2), (e, 3), (e + 1, 2), (e + 1, 3)], shape):
            loads.setdefault((node, dof), [0.0] * (case["steps"] + 1))[k] -= case["force"] * weight
    return loads


def run_moving_force(case):
    build_beam(case)
    for tag, ((node, dof), values) in enumerate(sorted(moving_force_loads(case).items()), 1):
        ops.timeSeries("Path", tag, "-dt", case["step"], "-values", *values)
        ops.pattern("Plain", tag, tag)
        ops.load(node, 0.0, float(dof == 2), float(dof == 3))
    set_up_analysis()
    return march(case, lambda k: None)


def march(case, between):
    """`steps` analyze calls of one step each, `between(k)` after step k;
    the midspan deflection at every step and the time inside analyze."""
    middle, solve = case["elements"] // 2, 0.0
    times, midspan = [0.0], [0.0]
    for k in range(1, case["steps"] + 1):
        started = time.perf_counter()
        failed = ops.analyze(1, case["step"])
        solve += time.perf_counter() - started
        if failed:
            raise RuntimeError(f"OpenSees analyze failed at step {k}")
        times.append(ops.getTime())
        midspan.append(ops.nodeDisp(middle, 2))
        between(k)
    return times, midspan, solve


class Follower:
    """The sprung mass over its massless contact point, and the nodal
    loads that carry the contact force into the beam."""

    def __init__(self, case):
        self.case = case
        self.u = self.ud = self.a = 0.0
        self.force = case["sprung_mass"] * case["gravity"]
        n = case["elements"]
        ops.timeSeries("Constant", 1)
        ops.pattern("Plain", 1, 1)
        for i in range(n + 1):
            ops.load(i, 0.0, 0.0, 0.0)
        # One parameter per nodal load: updated in place each step, so
        # the domain (and the factorisation) never changes.
        for i in range(n + 1):
            ops.parameter(2 * i + 1, "loadPattern", 1, "loadAtNode", i, 2)
            ops.parameter(2 * i + 2, "loadPattern", 1, "loadAtNode", i, 3)
        self.loaded = []

    def place(self, t):
        """The current contact force as nodal loads at x = V t."""
        for tag in self.loaded:
            ops.updateParameter(tag, 0.0)
        self.loaded = []
        x = self.case["speed"] * t
        if 0.0 <= x <= self.case["length"]:
            e, shape, _ = hermite(x, self.case["length"], self.case["elements"])
            tags = [2 * e + 1, 2 * e + 2, 2 * e + 3, 2 * e + 4]
            for tag, weight in zip(tags, shape):
                ops.updateParameter(tag, -self.force * weight)
            self.loaded = tags

    def contact(self, t):
        """Deflection and its total rate at the contact point x = V t."""
        c = self.case
        x = c["speed"] * t
        if not 0.0 <= x <= c["length"]:
            return 0.0, 0.0
        e, shape, slope = hermite(x, c["length"], c["elements"])
        dofs = [(e, 2), (e, 3), (e + 1, 2), (e + 1, 3)]
        w = sum(s * ops.nodeDisp(node, dof) for s, (node, dof) in zip(shape, dofs))
        wd = sum(s * ops.nodeVel(node, dof) for s, (node, dof) in zip(shape, dofs))
        wx = sum(s * ops.nodeDisp(node, dof) for s, (node, dof) in zip(slope, dofs))
        return w, wd + c["speed"] * wx

    def advance(self, t):
        """The sprung mass from t − h to t by the trapezoidal rule (Newmark
        average acceleration) with the beam's contact point at t, then the
        contact force at t: M ü = −k δ − c δ̇, δ = u − w_c."""
        c, h = self.case, self.case["step"]
        w, wd = self.contact(t)
        mass, k, damping = c["sprung_mass"], c["stiffness"], c["damping"]
        a0 = self.a
        # u1 = u + h ud + h²/4 (a0 + a1), ud1 = ud + h/2 (a0 + a1), a1 from the spring at t.
        lhs = mass + damping * h / 2 + k * h * h / 4
        rhs = (-k * (self.u + h * self.ud + h * h / 4 * a0 - w)
               - damping * (self.ud + h / 2 * a0 - wd))
        a1 = rhs / lhs
        self.u += h * self.ud + h * h / 4 * (a0 + a1)
        self.ud += h / 2 * (a0 + a1)
        self.a = a1
        self.force = mass * c["gravity"] - k * (self.u - w) - damping * (self.ud - wd)


def run_sprung_mass(case):
    build_beam(case)
    follower = Follower(case)
    follower.place(case["step"])
    set_up_analysis()

    def between(k):
        t = k * case["step"]
        follower.advance(t)
        follower.place(t + case["step"])

    return march(case, between)


def main():
    global ops
    import openseespy.opensees

    ops = openseespy.opensees
    if len(sys.argv) not in (3, 4) or (len(sys.argv) == 4 and sys.argv[3] != "--no-history"):
        sys.exit(__doc__)
    case = json.loads(open(sys.argv[1]).read())
    run = {"moving_force": run_moving_force, "sprung_mass": run_sprung_mass}.get(case.get("case"))
    if run is None:
        sys.exit(f"case: {case.get('case')!r} is not moving_force or sprung_mass")
    times, midspan, solve = run(case)
    out = {"wallSolve_s": solve, "steps": case["steps"]}
    if len(sys.argv) == 3:
        out.update(time=times, midspan=midspan)
    with open(sys.argv[2], "w") as f:
        json.dump(out, f)


if __name__ == "__main__":
    main()
