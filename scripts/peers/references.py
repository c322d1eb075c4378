"""The closed forms the peer bench measures both codes against: Frýba's
series for a constant force crossing a simply supported beam, and a modal
superposition of Yang & Yau's sprung mass on a massless follower (the same
references as tests/physics/fryba.rs, tests/physics/moving_force_run.rs and
tests/physics/sprung_mass.rs, written again here in numpy), and the error of a
midspan history against either."""

import math

import numpy as np


def fryba_midspan(case, times):
    """Midspan deflection (up positive, m) of a force `case["force"]` (N,
    down) crossing at `case["speed"]`, during the passage, by Frýba's
    series (1972, ch. 1) with `terms` terms:
    v = v₀ Σ_j [sin jωt − (α/j) sin ω_j t] / (j²(j² − α²)) · sin(jπ/2)."""
    length, ei, mass = case["length"], case["bending_stiffness"], case["mass_per_length"]
    omega1 = (math.pi / length) ** 2 * math.sqrt(ei / mass)
    omega = math.pi * case["speed"] / length
    alpha = omega / omega1
    v0 = 2.0 * case["force"] * length**3 / (math.pi**4 * ei)
    t = np.asarray(times, dtype=float)[:, None]
    j = np.arange(1, case.get("terms", 400) + 1, dtype=float)[None, :]
    if np.any(np.abs(j - alpha) < 1e-9):
        raise ValueError(f"alpha = {alpha} is a resonance of the series; choose another speed")
    terms = (np.sin(j * omega * t) - alpha / j * np.sin(j * j * omega1 * t)) / (
        j * j * (j * j - alpha * alpha))
    return -v0 * (terms * np.sin(j * math.pi / 2.0)).sum(axis=1)


def green(length, ei, x, a):
    """Static deflection at x of a simply supported beam under a unit
    downward load at a (down positive, m/N): the closed form."""
    if a > x:
        x, a = a, x
    return a * (length - x) * (2.0 * length * x - x * x - a * a) / (6.0 * ei * length)


class SprungMass:
    """Yang & Yau's sprung mass on a massless follower over a simply
    supported beam, by `modes` sine modes and classical RK4 at `step`:
    q̈ₙ + ωₙ² qₙ = −(2/m̄L) φₙ(Vt) N, N = M g − k δ − c δ̇, δ = u − w_c,
    M ü = −k δ − c δ̇ (u from the static position, all up positive). The
    midspan output adds the static part of the modes left out (the
    closed-form influence line minus the retained modes' share)."""

    def __init__(self, case, modes=30):
        self.case, self.modes = case, modes
        length = case["length"]
        self.k = np.arange(1, modes + 1) * math.pi / length
        self.omega2 = self.k**4 * case["bending_stiffness"] / case["mass_per_length"]
        self.modal_load = 2.0 / (case["mass_per_length"] * length)

    def _rates(self, t, y):
        c = self.case
        m = self.modes
        q, qd, u, ud = y[:m], y[m:2 * m], y[2 * m], y[2 * m + 1]
        x = c["speed"] * t
        phi, dphi = np.sin(self.k * x), self.k * np.cos(self.k * x)
        w_c, wd_c = phi @ q, phi @ qd + c["speed"] * (dphi @ q)
        spring = -c["stiffness"] * (u - w_c) - c["damping"] * (ud - wd_c)
        force = c["sprung_mass"] * c["gravity"] + spring
        # A force off the beam loads nothing.
        on = 1.0 if 0.0 <= x <= c["length"] else 0.0
        qdd = -self.omega2 * q - on * self.modal_load * phi * force
        return np.concatenate([qd, qdd, [ud, spring / c["sprung_mass"]]]), force

    def midspan(self, step, count):
        """Midspan deflection at t = i·step, i = 0..count."""
        c, m = self.case, self.modes
        y = np.zeros(2 * m + 2)
        mid = np.sin(self.k * c["length"] / 2.0)
        out = np.empty(count + 1)
        for i in range(count + 1):
            t = i * step
            _, force = self._rates(t, y)
            out[i] = mid @ y[:m] - force * self._left_out(c["speed"] * t)
            k1, _ = self._rates(t, y)
            k2, _ = self._rates(t + step / 2, y + step / 2 * k1)
            k3, _ = self._rates(t + step / 2, y + step / 2 * k2)
            k4, _ = self._rates(t + step, y + step * k3)
            y = y + step / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)
        return out

    def _left_out(self, x):
        c = self.case
        if not 0.0 <= x <= c["length"]:
            return 0.0
        kept = self.modal_load / self.omega2 * np.sin(self.k * c["length"] / 2) * np.sin(self.k * x)
        return green(c["length"], c["bending_stiffness"], c["length"] / 2.0, x) - kept.sum()


def history_error(times, values, reference, until):
    """Largest |value − reference| over the rows with t ≤ until, relative
    to the reference's largest |value| there. `reference(times)` gives the
    reference at those times."""
    times = np.asarray(times, dtype=float)
    keep = times <= until * (1.0 + 1e-12)
    if not keep.any():
        raise ValueError("no row at or before the end of the passage")
    ref = np.asarray(reference(times[keep]))
    peak = np.abs(ref).max()
    if not peak > 0.0:
        raise ValueError("the reference is zero over the passage")
    return float(np.abs(np.asarray(values, dtype=float)[keep] - ref).max() / peak)
