"""What the tests leave in the temporary directory: nothing. Ecos and
libcosim unpack every system or FMU they load into a new folder under
TMPDIR and never remove it (4-6 MB each), fmpy's `extract` without a folder
makes a new one each time, and `simulate_fmu` leaves its own when the FMU
fails: a day of test runs had left 5.6 GB in /tmp. The session gives them a
directory of its own (conftest), removed when it passes."""

import pathlib
import tempfile

import conftest
from conftest import WHEEL, extracted, fmu_path
from test_ssp import ssp  # noqa: F401  (the fixture)


def test_the_masters_unpack_into_the_sessions_own_directory(ssp):  # noqa: F811
    from ecospy import EcosSimulation
    from libcosimpy.CosimExecution import CosimExecution

    session = conftest.SESSION_TMP
    assert session is not None and pathlib.Path(tempfile.gettempdir()) == session
    before = set(session.iterdir())
    with EcosSimulation(ssp_path=str(ssp), step_size=0.01) as sim:
        assert sim.init()
        sim.terminate()
    execution = CosimExecution.from_ssp_file(str(ssp), step_size=10_000_000)  # ns
    assert execution.step()
    made = {p.name.split("_")[0] for p in set(session.iterdir()) - before}
    assert {"ecos", "libcosim"} <= made, made


def test_an_fmu_is_unpacked_once_beside_it(tmp_path):
    fmu = tmp_path / "w.fmu"
    fmu.write_bytes(fmu_path(WHEEL).read_bytes())
    folder = pathlib.Path(extracted(fmu))
    assert folder == tmp_path / "w.fmu.unzipped"
    assert (folder / "modelDescription.xml").is_file()
    (folder / "marker").write_text("kept")
    assert pathlib.Path(extracted(fmu)) == folder
    assert (folder / "marker").read_text() == "kept"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["w.fmu", "w.fmu.unzipped"]
