"""`guideway export --ssp`: an SSP 1.0 system of the guideway FMU and a
vehicle FMU, loaded by two masters that read SSP (libcosim, Ecos).

Until the coupling ports land, the vehicle is a stand-in: guideway's own
glider FMU, its output `glider.vx` wired to the wheel's input `force_x`.
The tests check the wiring, not physics: after each step the input holds
the value the output had when the master last transferred it.
"""

import subprocess
import zipfile

import numpy as np
import pytest
from fmpy import read_model_description

from conftest import GLIDER, GUIDEWAY, WHEEL, fmu_path
from omsimulator import omsimulator, omsimulator_run

WIRE = "vehicle.glider.vx=guideway.wheel.force_x"
STEPS = 10


@pytest.fixture(scope="module")
def ssp(tmp_path_factory):
    d = tmp_path_factory.mktemp("ssp")
    r = subprocess.run([str(GUIDEWAY), "export", WHEEL, "-o", str(d / "w.fmu"), "--ssp", str(d / "sys.ssp"),
                        "--vehicle", str(fmu_path(GLIDER)), "--connect", WIRE],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    return d / "sys.ssp"


def test_the_archive_holds_both_fmus_and_the_connection(ssp):
    with zipfile.ZipFile(ssp) as z:
        assert sorted(z.namelist()) == ["SystemStructure.ssd", "resources/guideway.fmu",
                                        "resources/vehicle.fmu"]
        ssd = z.read("SystemStructure.ssd").decode()
    assert ('<ssd:Connection startElement="vehicle" startConnector="glider.vx" '
            'endElement="guideway" endConnector="wheel.force_x"/>') in ssd


def test_ecos_runs_the_system_with_the_input_following_the_output(ssp):
    from ecospy import EcosSimulation

    with EcosSimulation(ssp_path=str(ssp), step_size=0.01) as sim:
        assert sim.init()
        for _ in range(STEPS):
            sim.step()
            vx = sim.get_real("vehicle::glider.vx")
            assert vx > 29.0
            assert sim.get_real("guideway::wheel.force_x") == vx
        sim.terminate()


def test_libcosim_runs_the_system_with_the_input_following_the_output(ssp):
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimObserver import CosimObserver

    execution = CosimExecution.from_ssp_file(str(ssp), step_size=10_000_000)  # ns
    observer = CosimObserver.create_last_value()
    execution.add_observer(observer)
    g = execution.slave_index_from_instance_name("guideway")
    v = execution.slave_index_from_instance_name("vehicle")
    force_x = read_model_description(str(fmu_path(WHEEL))).modelVariables
    fx = next(x.valueReference for x in force_x if x.name == "wheel.force_x")
    vx = next(x.valueReference for x in read_model_description(str(fmu_path(GLIDER))).modelVariables
              if x.name == "glider.vx")
    outputs, inputs = [], []
    for k in range(STEPS):
        assert execution.step(), f"step {k}"
        outputs.append(observer.last_real_values(v, [vx])[0])
        inputs.append(observer.last_real_values(g, [fx])[0])
    assert min(outputs) > 29.0
    # libcosim transfers before each step: the input of step k is the
    # output after step k - 1.
    np.testing.assert_array_equal(inputs[1:], outputs[:-1])


@pytest.mark.parametrize("wire, message", [
    ("vehicle.glider.mass=guideway.wheel.force_x",
     "is a Real parameter; a connection goes from a Real output to a Real input; "
     "the Real outputs of vehicle: contact.gap, "),
    ("vehicle.glider.vx=guideway.wheel.nope",
     "guideway has no variable `wheel.nope`; the Real inputs of guideway: wheel.force_x, wheel.force_y"),
    ("car.glider.vx=guideway.wheel.force_x", "COMPONENT one of"),
])
def test_bad_connections_are_refused_before_anything_is_written(tmp_path, wire, message):
    """README "Exit codes": a usage error exits 2 and writes nothing (neither
    the FMU nor the system)."""
    r = subprocess.run([str(GUIDEWAY), "export", WHEEL, "-o", str(tmp_path / "w.fmu"), "--ssp",
                        str(tmp_path / "s.ssp"), "--vehicle", str(fmu_path(GLIDER)), "--connect", wire],
                       capture_output=True, text=True)
    assert r.returncode == 2 and message in r.stderr, r.stderr
    assert list(tmp_path.iterdir()) == []


def test_the_ssd_validates_and_carries_the_default_experiment(ssp):
    """The SSP 1.0 schema (as shipped with fmpy) accepts the SSD; its
    DefaultExperiment is the guideway FMU's, and OMSimulator's fixed-step
    master annotation has the FMU's step."""
    from lxml import etree
    from fmpy.ssp import ssd as fmpy_ssd
    import os

    schema_dir = os.path.join(os.path.dirname(fmpy_ssd.__file__), "schema")
    schema = etree.XMLSchema(file=os.path.join(schema_dir, "SystemStructureDescription.xsd"))
    with zipfile.ZipFile(ssp) as z:
        root = etree.fromstring(z.read("SystemStructure.ssd"))
        with z.open("resources/guideway.fmu") as f:
            guideway_md = read_model_description(f)
    assert schema.validate(root), schema.error_log
    ns = {"ssd": "http://ssp-standard.org/SSP1/SystemStructureDescription",
          "oms": "https://raw.githubusercontent.com/OpenModelica/OMSimulator/master/schema/oms.xsd"}
    experiment = root.find("ssd:DefaultExperiment", ns)
    fmu_experiment = guideway_md.defaultExperiment
    assert float(experiment.get("startTime")) == 0.0
    assert float(experiment.get("stopTime")) == float(fmu_experiment.stopTime)
    master = root.find(".//oms:FixedStepMaster", ns)
    assert float(master.get("stepSize")) == float(fmu_experiment.stepSize)


def test_fmpy_simulate_ssp_stamps_each_row_with_the_step_start(ssp):
    """fmpy's `simulate_ssp` records the values after the step from t to
    t + H in the row it stamps t (fmpy/ssp/simulation.py: `row = [time]`
    after `do_step(component, time, step_size)`): the shift is fmpy's, not
    the FMUs'. Reference: the vehicle FMU alone in fmpy's `simulate_fmu`,
    whose row at t + H holds the same value."""
    from fmpy import simulate_fmu
    from fmpy.ssp.simulation import simulate_ssp

    h = 0.01
    system = simulate_ssp(str(ssp), stop_time=STEPS * h, step_size=h)
    alone = simulate_fmu(str(fmu_path(GLIDER)), stop_time=(STEPS + 2) * h, step_size=h,
                         output_interval=h, output=["glider.vx"])
    vx = next(n for n in system.dtype.names if n.endswith("glider.vx"))
    n = len(system)
    assert n >= STEPS
    np.testing.assert_allclose(system["time"], alone["time"][:n], rtol=0, atol=1e-12)
    np.testing.assert_array_equal(system[vx], alone["glider.vx"][1:n + 1])



@pytest.mark.skipif(not omsimulator(), reason="OMSimulator not installed (docs/fmu.md: building it)")
def test_omsimulator_runs_the_ssp_as_shipped_with_the_input_following_the_output(ssp, tmp_path):
    """OMSimulator loads the SSD as written (no error, no "wrong/deprecated
    content" warning), runs it to the SSD's stop time, and after each
    communication point the input holds the output's value."""
    from lxml import etree

    with zipfile.ZipFile(ssp) as z:
        root = etree.fromstring(z.read("SystemStructure.ssd"))
    ns = {"ssd": "http://ssp-standard.org/SSP1/SystemStructureDescription"}
    stop = float(root.find("ssd:DefaultExperiment", ns).get("stopTime"))
    rows = omsimulator_run(ssp, tmp_path, stop)
    assert max(rows) == pytest.approx(stop, abs=1e-9)
    assert len(rows) > 100
    assert all(vx > 29.0 and force == vx for vx, force in rows.values())
