"""`guideway export --ssp --ssp-version 2`: an SSP 2.0 system beside the SSP
1.0 one (test_ssp.py), each holding FMI 2.0 or FMI 3.0 FMUs (`--fmi 3`).

The SSD is validated against the normative SSP 2.0 schema
(scripts/tests/schema/ssp2, BSD-2-Clause, see its README) and loaded in
every master here that reads SSP. Which master reads which is asserted, not
assumed (docs/fmu.md has the table):

- Ecos 0.7.2 refuses SSP 2.0 ("Unsupported SSP version") and runs SSP 1.0,
  with FMI 3.0 FMUs too;
- libcosimpy 0.0.6 does not look at the version: it runs the SSP 2.0 system
  of FMI 2.0 FMUs (it cannot load FMI 3.0 FMUs at all);
- fmpy 0.3.32 validates every SSD against its SSP 1.0 schema (version "1.0"
  only), so it reads SSP 2.0 only unvalidated, and simulates FMI 1.0/2.0
  components only.

So SSP 1.0 stays the default. As in test_ssp.py the vehicle is a stand-in,
guideway's glider FMU: its output `glider.vx` wired to the wheel's input
`force_x`; the tests check the wiring, not physics.
"""

import pathlib
import subprocess
import zipfile

import pytest
from lxml import etree

from conftest import GLIDER, GUIDEWAY, WHEEL, fmu_path
from omsimulator import omsimulator, omsimulator_run

WIRE = "vehicle.glider.vx=guideway.wheel.force_x"
STEPS = 10
SCHEMA = pathlib.Path(__file__).parent / "schema" / "ssp2" / "SystemStructureDescription.xsd"
NS = {"ssd": "http://ssp-standard.org/SSP1/SystemStructureDescription",
      "ssc": "http://ssp-standard.org/SSP1/SystemStructureCommon"}


def export(args, cwd):
    return subprocess.run([str(GUIDEWAY), "export", *args], capture_output=True, text=True,
                          cwd=cwd)


# name -> (guideway's --fmi, --ssp-version, the vehicle's FMI version)
SYSTEMS = {"fmi3": ("3", "2", "3"), "mixed": ("3", "2", "2"), "fmi2": ("2", "2", "2"),
           "fmi3_ssp1": ("3", "1", "3"), "ssp1": ("2", "1", "2")}


@pytest.fixture(scope="module")
def systems(tmp_path_factory):
    d = tmp_path_factory.mktemp("ssp2")
    r = export([GLIDER, "--fmi", "3", "-o", str(d / "glider3.fmu")], d)
    assert r.returncode == 0, r.stderr
    vehicles = {"3": d / "glider3.fmu", "2": fmu_path(GLIDER)}
    out = {}
    for key, (fmi, ssp, vehicle) in SYSTEMS.items():
        r = export([WHEEL, "--fmi", fmi, "-o", str(d / f"w_{key}.fmu"), "--ssp",
                    str(d / f"{key}.ssp"), "--ssp-version", ssp, "--vehicle",
                    str(vehicles[vehicle]), "--connect", WIRE], d)
        assert r.returncode == 0, r.stderr
        out[key] = d / f"{key}.ssp"
    return out


def ssd_of(ssp):
    with zipfile.ZipFile(ssp) as z:
        return etree.fromstring(z.read("SystemStructure.ssd"))


def connector_types(root):
    """(component, connector) -> its SSP type element's local name."""
    return {(c.get("name"), k.get("name")): etree.QName(k[0]).localname
            for c in root.iterfind(".//ssd:Component", NS)
            for k in c.iterfind("ssd:Connectors/ssd:Connector", NS)}


@pytest.mark.parametrize("key", ["fmi3", "mixed", "fmi2"])
def test_the_ssp_2_ssd_validates_against_the_ssp_2_schema(systems, key):
    schema = etree.XMLSchema(file=str(SCHEMA))
    root = ssd_of(systems[key])
    assert schema.validate(root), schema.error_log
    assert root.get("version") == "2.0"
    # each connector is typed by its FMU: FMI 3.0 Float64, FMI 2.0 Real
    fmi, _, vehicle = SYSTEMS[key]
    typed = {"3": "Float64", "2": "Real"}
    assert connector_types(root) == {("guideway", "wheel.force_x"): typed[fmi],
                                     ("vehicle", "glider.vx"): typed[vehicle]}
    with zipfile.ZipFile(systems[key]) as z:
        assert sorted(z.namelist()) == ["SystemStructure.ssd", "resources/guideway.fmu",
                                        "resources/vehicle.fmu"]
        # SSP 2.0 §3: no entry may need a zip reader newer than 2.0
        assert all(i.extract_version <= 20 for i in z.infolist())


def test_ssp_1_types_fmi_3_variables_real(systems):
    """SSP 1.0 has one floating-point connector type, Real."""
    root = ssd_of(systems["fmi3_ssp1"])
    assert root.get("version") == "1.0"
    assert set(connector_types(root).values()) == {"Real"}


def test_the_schema_tells_the_versions_apart(systems):
    """The 2.0 schema also accepts the SSP 1.0 SSD; the SSP 1.0 schema that
    fmpy ships refuses the 2.0 one by its version alone (so a validating
    SSP 1.0 reader refuses it)."""
    import os
    from fmpy.ssp import ssd as fmpy_ssd

    ssp2 = etree.XMLSchema(file=str(SCHEMA))
    ssp1 = etree.XMLSchema(file=os.path.join(os.path.dirname(fmpy_ssd.__file__), "schema",
                                             "SystemStructureDescription.xsd"))
    assert ssp2.validate(ssd_of(systems["ssp1"])), ssp2.error_log
    assert ssp1.validate(ssd_of(systems["ssp1"])), ssp1.error_log
    assert ssp1.validate(ssd_of(systems["fmi3_ssp1"])), ssp1.error_log
    assert not ssp1.validate(ssd_of(systems["fmi2"]))
    assert "version" in str(ssp1.error_log)


def test_the_fmus_inside_are_the_ones_exported(systems):
    from fmpy import read_model_description

    for key, (fmi, _, vehicle) in SYSTEMS.items():
        with zipfile.ZipFile(systems[key]) as z:
            for component, version in [("guideway", fmi), ("vehicle", vehicle)]:
                with z.open(f"resources/{component}.fmu") as f:
                    assert read_model_description(f).fmiVersion == f"{version}.0", key


def ecos_run(ssp):
    """The vehicle's output and guideway's input after each of STEPS steps."""
    from ecospy import EcosSimulation

    rows = []
    with EcosSimulation(ssp_path=str(ssp), step_size=0.01) as sim:
        assert sim.init()
        for _ in range(STEPS):
            sim.step()
            rows.append((sim.get_real("vehicle::glider.vx"), sim.get_real("guideway::wheel.force_x")))
        sim.terminate()
    return rows


def test_ecos_runs_ssp_1_with_fmi_3_fmus_and_refuses_ssp_2(systems):
    rows = ecos_run(systems["fmi3_ssp1"])
    assert all(vx > 29.0 and force == vx for vx, force in rows), rows
    for key in ["fmi3", "mixed", "fmi2"]:
        with pytest.raises(Exception, match="Unsupported SSP version: '2.0'"):
            ecos_run(systems[key])


def test_libcosim_runs_the_ssp_2_system_of_fmi_2_fmus(systems):
    """The same check as test_ssp.py's on the SSP 1.0 system: libcosim
    transfers before each step, so the input of step k is the output after
    step k - 1."""
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimObserver import CosimObserver
    from fmpy import read_model_description

    execution = CosimExecution.from_ssp_file(str(systems["fmi2"]), step_size=10_000_000)  # ns
    observer = CosimObserver.create_last_value()
    execution.add_observer(observer)
    g = execution.slave_index_from_instance_name("guideway")
    v = execution.slave_index_from_instance_name("vehicle")

    def ref(scene, name):
        variables = read_model_description(str(fmu_path(scene))).modelVariables
        return next(x.valueReference for x in variables if x.name == name)

    fx, vx = ref(WHEEL, "wheel.force_x"), ref(GLIDER, "glider.vx")
    outputs, inputs = [], []
    for k in range(STEPS):
        assert execution.step(), f"step {k}"
        outputs.append(observer.last_real_values(v, [vx])[0])
        inputs.append(observer.last_real_values(g, [fx])[0])
    assert min(outputs) > 29.0
    assert inputs[1:] == outputs[:-1]


@pytest.mark.skipif(not omsimulator(), reason="OMSimulator not installed (docs/fmu.md: building it)")
def test_omsimulator_runs_real_connectors_and_refuses_float64_ones(systems, tmp_path):
    """OMSimulator 3.0 runs SSP 1.0 with FMI 3.0 FMUs and SSP 2.0 whose
    connectors are `Real` (FMI 2.0 FMUs), and refuses SSP 2.0's `Float64`
    connectors ("Failed to import ssd:Connector:type")."""
    for key in ["fmi3_ssp1", "fmi2", "ssp1"]:
        rows = omsimulator_run(systems[key], tmp_path, STEPS * 0.0025)
        assert len(rows) == STEPS + 1, key
        assert all(vx >= 29.0 and force == vx for vx, force in rows.values()), (key, rows)
    for key in ["fmi3", "mixed"]:
        with pytest.raises(RuntimeError, match="Failed to import ssd:Connector:type"):
            omsimulator_run(systems[key], tmp_path, STEPS * 0.0025)


def test_fmpy_reads_the_ssp_2_system_only_unvalidated(systems):
    """fmpy 0.3.32's `read_ssd` (and so `simulate_ssp`) validates against
    SSP 1.0 and refuses the SSD's version; unvalidated it reads both
    components and the wire."""
    from fmpy.ssp.ssd import read_ssd
    from fmpy.ssp.simulation import simulate_ssp

    with pytest.raises(Exception, match="version"):
        read_ssd(str(systems["fmi2"]))
    with pytest.raises(Exception, match="version"):
        simulate_ssp(str(systems["fmi2"]), stop_time=0.01, step_size=0.01)
    ssd = read_ssd(str(systems["fmi3"]), validate=False)
    assert ssd.version == "2.0"
    assert [e.name for e in ssd.system.elements] == ["guideway", "vehicle"]
    [c] = ssd.system.connections
    assert (c.startElement, c.startConnector, c.endElement, c.endConnector) == (
        "vehicle", "glider.vx", "guideway", "wheel.force_x")


def test_a_bad_connection_lists_the_float64_variables(tmp_path):
    r = export([WHEEL, "--fmi", "3", "-o", str(tmp_path / "w.fmu"), "--ssp",
                str(tmp_path / "s.ssp"), "--ssp-version", "2", "--vehicle", str(fmu_path(GLIDER)),
                "--connect",
                "vehicle.glider.vx=guideway.wheel.nope"], tmp_path)
    assert r.returncode == 2, r.stderr
    assert ("guideway has no variable `wheel.nope`; the Float64 inputs of guideway: "
            "wheel.force_x, wheel.force_y") in r.stderr, r.stderr
    assert list(tmp_path.iterdir()) == []
