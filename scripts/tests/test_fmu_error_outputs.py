"""The FMU's running error estimate (scene `error_estimate = true`): the
exported FMU lists `sensor.<name>.deflection_error` and
`.acceleration_error` as outputs, and fmpy reads them finite and > 0 after
the first communication step; without the switch there are none."""

import subprocess

import numpy as np
from fmpy import read_model_description, simulate_fmu

from conftest import GUIDEWAY

ERRORS = ["sensor.midspan.deflection_error", "sensor.midspan.acceleration_error"]


def export(d, error_estimate):
    """The paper's wheel at 10 m/s exported into `d`, with or without the
    error outputs; the FMU's path."""
    scene = subprocess.run([str(GUIDEWAY), "scenes", "--show", "lee1994-wheel-10"],
                           check=True, capture_output=True, text=True).stdout
    if error_estimate:
        # A top-level key: before the first table.
        scene = "error_estimate = true\n" + scene
    toml, fmu = d / "wheel.toml", d / "wheel.fmu"
    toml.write_text(scene)
    subprocess.run([str(GUIDEWAY), "export", str(toml), "-o", str(fmu)], check=True,
                   capture_output=True)
    return str(fmu)


def test_the_error_outputs_are_listed_finite_and_positive(tmp_path):
    fmu = export(tmp_path, True)
    variables = {v.name: v for v in read_model_description(fmu).modelVariables}
    for name in ERRORS:
        assert variables[name].causality == "output", name
        assert variables[name].type == "Real", name
    result = simulate_fmu(fmu, output_interval=0.05, stop_time=1.0, output=ERRORS)
    assert len(result["time"]) == 21
    for name in ERRORS:
        after_first = result[name][1:]
        assert np.all(np.isfinite(after_first)), name
        assert np.all(after_first > 0.0), (name, after_first)


def test_without_the_switch_there_are_no_error_outputs(tmp_path):
    fmu = export(tmp_path, False)
    names = {v.name for v in read_model_description(fmu).modelVariables}
    assert not any(n.endswith("_error") and n.startswith("sensor.") for n in names)
