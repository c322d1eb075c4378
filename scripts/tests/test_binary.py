"""The shipped FMU binary: stripped, the FMI 2.0 and FMI 3.0 APIs as its
only exports, and the glibc it needs no newer than the baseline docs/fmu-reference.md
states."""

import os
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


def standard_functions(header):
    """The functions a standard's header declares (`FMI2_Export ...TYPE name;`),
    from the copy of the standard's headers fmpy ships."""
    import fmpy

    text = open(os.path.join(os.path.dirname(fmpy.__file__), "c-code", header)).read()
    return set(re.findall(r"FMI[23]_Export\s+\w+TYPE\s+(fmi[23]\w+);", text))


# FMI 2.0's model-exchange functions, which a co-simulation-only FMU 2.0
# need not export (FMI 3.0 wants every function of its API in the binary).
FMI2_MODEL_EXCHANGE = {
    "fmi2EnterEventMode", "fmi2NewDiscreteStates", "fmi2EnterContinuousTimeMode",
    "fmi2CompletedIntegratorStep", "fmi2SetTime", "fmi2SetContinuousStates", "fmi2GetDerivatives",
    "fmi2GetEventIndicators", "fmi2GetContinuousStates", "fmi2GetNominalsOfContinuousStates",
}


def test_exactly_the_fmi2_and_fmi3_functions_are_exported(binary):
    symbols = {line.split()[-1] for line in run("nm", "-D", "--defined-only", str(binary)).splitlines()}
    fmi2, fmi3 = standard_functions("fmi2Functions.h"), standard_functions("fmi3Functions.h")
    assert FMI2_MODEL_EXCHANGE <= fmi2
    fmi2_co_simulation = fmi2 - FMI2_MODEL_EXCHANGE
    assert (len(fmi2_co_simulation), len(fmi3)) == (34, 75)
    assert symbols == fmi2_co_simulation | fmi3


def test_binary_is_stripped(binary):
    sections = run("readelf", "-S", "-W", str(binary))
    assert ".symtab" not in sections and ".debug_info" not in sections


def test_glibc_needed_is_at_most_the_baseline(binary):
    versions = {tuple(map(int, v.split("."))) for v in
                re.findall(r"\bGLIBC_(\d+\.\d+(?:\.\d+)?)\b", run("objdump", "-T", str(binary)))}
    assert versions, "no glibc symbol versions found"
    assert max(versions) <= GLIBC_BASELINE, sorted(versions)
