"""`guideway export --fmi 3`: the FMI 3.0 co-simulation FMU beside the FMI 2.0
one, from the same scene and variable table.

The reference is the FMI 2.0 FMU of the same scene (itself checked against
closed forms and the native model elsewhere): the FMI 3.0 front end must
give the same outputs to the bit in fmpy, with the same start values, and
its states must round-trip. fmpy's and fmutool's FMI 3.0 checks must pass,
and Ecos (ecospy), the other master here that imports FMI 3.0, runs it.
"""

import subprocess
import zipfile

import numpy as np
import pytest
from fmpy import read_model_description, simulate_fmu
from fmpy.validation import validate_fmu

from conftest import GUIDEWAY, ROOT, WHEEL

STEP = 0.01


@pytest.fixture(scope="module")
def fmus(tmp_path_factory):
    d = tmp_path_factory.mktemp("fmi3")
    paths = {}
    for version in ["2", "3"]:
        path = d / f"wheel{version}.fmu"
        r = subprocess.run([str(GUIDEWAY), "export", WHEEL, "--fmi", version, "-o", str(path)],
                           capture_output=True, text=True)
        assert r.returncode == 0, r.stderr
        paths[version] = path
    return paths


def test_fmpy_and_fmutool_find_no_problem(fmus):
    assert validate_fmu(str(fmus["3"])) == []
    r = subprocess.run([str(ROOT / ".venv" / "bin" / "fmutool"), "-input", str(fmus["3"]), "-check"],
                       capture_output=True, text=True, timeout=120)
    out = r.stdout + r.stderr
    assert r.returncode == 0 and "compliant with FMI-3.0" in out, out
    assert "No semantic error" in out and "ERROR" not in out, out


def test_same_variables_and_layout_as_the_fmi2_fmu(fmus):
    md2, md3 = (read_model_description(str(fmus[v])) for v in ["2", "3"])
    assert md3.fmiVersion == "3.0"
    v2 = {v.name: (v.valueReference, v.causality, v.start) for v in md2.modelVariables}
    v3 = {v.name: (v.valueReference, v.causality, v.start) for v in md3.modelVariables}
    time = v3.pop("time")
    assert time[1] == "independent" and time[0] == len(v2)
    assert v3 == v2
    types = {v.name: v.type for v in md3.modelVariables}
    assert types["wheel.x"] == "Float64" and types["contact.on_beam"] == "Int32"
    assert md3.defaultExperiment.stopTime == md2.defaultExperiment.stopTime
    with zipfile.ZipFile(fmus["3"]) as z:
        assert f"binaries/x86_64-linux/{md3.coSimulation.modelIdentifier}.so" in z.namelist()


@pytest.mark.parametrize("start_values", [{}, {"wheel.initial_speed": 20.0, "beam.bending_stiffness": 2e9}])
def test_outputs_equal_the_fmi2_fmus_to_the_bit(fmus, start_values):
    """Every output at every communication point to the default stop time
    (past the exit), in fmpy."""
    runs = [simulate_fmu(str(fmus[v]), step_size=STEP, output_interval=STEP,
                         start_values=start_values) for v in ["2", "3"]]
    r2, r3 = runs
    assert r2.dtype.names == r3.dtype.names and len(r2) == len(r3) > 300
    for name in r2.dtype.names:
        np.testing.assert_array_equal(r3[name], r2[name], err_msg=name)
    assert r3["contact.on_beam"][0] == 1 and r3["contact.on_beam"][-1] == 0


def test_a_serialized_state_continues_bit_identically(fmus, tmp_path):
    from fmpy import extract
    from fmpy.fmi3 import FMU3Slave

    md = read_model_description(str(fmus["3"]))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    fmu = FMU3Slave(guid=md.guid, unzipDirectory=extract(str(fmus["3"]), str(tmp_path)),
                    modelIdentifier=md.coSimulation.modelIdentifier, instanceName="s")
    fmu.instantiate()
    fmu.enterInitializationMode()
    fmu.exitInitializationMode()
    outputs = [vr["wheel.y"], vr["sensor.midspan.deflection"], vr["time"]]
    t = 0.0
    for _ in range(10):
        fmu.doStep(t, STEP)
        t += STEP
    state = fmu.serializeFMUState(fmu.getFMUState())
    first = []
    for _ in range(10):
        fmu.doStep(t + len(first) * STEP, STEP)
        first.append(fmu.getFloat64(outputs))
    fmu.setFMUState(fmu.deserializeFMUState(state))
    again = []
    for _ in range(10):
        fmu.doStep(t + len(again) * STEP, STEP)
        again.append(fmu.getFloat64(outputs))
    assert again == first
    assert first[-1][2] == pytest.approx(t + 10 * STEP, abs=1e-12)
    fmu.terminate()
    fmu.freeInstance()


def test_ecos_runs_the_fmi3_fmu_like_fmpy_runs_the_fmi2_one(fmus):
    from ecospy import EcosSimulation, EcosSimulationStructure

    reference = simulate_fmu(str(fmus["2"]), stop_time=20 * STEP, step_size=STEP,
                             output_interval=STEP, output=["sensor.midspan.deflection"])
    structure = EcosSimulationStructure()
    structure.add_model("g", str(fmus["3"]))
    with EcosSimulation(structure=structure, step_size=STEP) as sim:
        assert sim.init()
        deflections = []
        for _ in range(20):
            sim.step()
            deflections.append(sim.get_real("g::sensor.midspan.deflection"))
        sim.terminate()
    np.testing.assert_array_equal(deflections, reference["sensor.midspan.deflection"][1:21])
