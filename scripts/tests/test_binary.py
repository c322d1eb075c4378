"""The shipped FMU binary: stripped, the FMI 2.0 API as its only exports,
and the glibc it needs no newer than the baseline docs/fmu-reference.md states."""

import re
import subprocess
import zipfile

import pytest

from conftest import SCENES, fmu_path

# docs/fmu-reference.md, "The FMU binary": the oldest glibc it runs on (scripts/build_portable.sh).
GLIBC_BASELINE = (2, 17)


@pytest.fixture(scope="module", params=SCENES)
def binary(request, tmp_path_factory):
    with zipfile.ZipFile(fmu_path(request.param)) as z:
        [name] = [n for n in z.namelist() if n.startswith("binaries/linux64/")]
        path = tmp_path_factory.mktemp("bin") / name.split("/")[-1]
        path.write_bytes(z.read(name))
    return path


def run(*cmd):
    return subprocess.run(cmd, capture_output=True, text=True, check=True).stdout


def test_only_fmi2_functions_are_exported(binary):
    symbols = [line.split()[-1] for line in run("nm", "-D", "--defined-only", str(binary)).splitlines()]
    assert [s for s in symbols if not s.startswith("fmi2")] == []
    for f in ["fmi2Instantiate", "fmi2DoStep", "fmi2GetReal", "fmi2SerializeFMUstate"]:
        assert f in symbols


def test_binary_is_stripped(binary):
    sections = run("readelf", "-S", "-W", str(binary))
    assert ".symtab" not in sections and ".debug_info" not in sections


def test_glibc_needed_is_at_most_the_baseline(binary):
    versions = {tuple(map(int, v.split("."))) for v in
                re.findall(r"\bGLIBC_(\d+\.\d+(?:\.\d+)?)\b", run("objdump", "-T", str(binary)))}
    assert versions, "no glibc symbol versions found"
    assert max(versions) <= GLIBC_BASELINE, sorted(versions)
