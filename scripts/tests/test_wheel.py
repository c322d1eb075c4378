"""`pip install guideway` (issue 27 item 7): the wheel that
scripts/build_wheel.sh builds with maturin installs, into a fresh venv, a
`guideway` command whose `export` writes a portable FMU that fmpy runs to
the same outputs as the FMU that scripts/test.sh exported."""

import os
import pathlib
import re
import subprocess
import sys
import zipfile

import numpy as np
import pytest
from fmpy import simulate_fmu

from conftest import ROOT, WHEEL, fmu_path

@pytest.fixture(scope="module")
def wheel():
    path = os.environ.get("GUIDEWAY_WHEEL")
    if not path or not pathlib.Path(path).is_file():
        pytest.fail("GUIDEWAY_WHEEL unset or missing: run scripts/test.sh (it builds the wheel)")
    return pathlib.Path(path)


@pytest.fixture(scope="module")
def installed(wheel, tmp_path_factory):
    """A fresh venv with the wheel installed from the file alone."""
    venv = tmp_path_factory.mktemp("venv")
    subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True)
    env = {k: v for k, v in os.environ.items() if not k.startswith("PIP_")}
    subprocess.run([str(venv / "bin" / "python"), "-m", "pip", "install", "-q", "--no-index",
                    "--no-deps", str(wheel)], check=True, env=env)
    return venv


def glibc_needed(binary):
    out = subprocess.run(["objdump", "-T", str(binary)], capture_output=True, text=True,
                         check=True).stdout
    versions = {tuple(int(x) for x in v.split(".")) for v in
                re.findall(r"\bGLIBC_(\d+\.\d+(?:\.\d+)?)\b", out)}
    return max(versions)


def test_the_wheel_is_manylinux2014_and_holds_the_command_and_the_fmu_binary(wheel):
    assert "manylinux2014_x86_64" in wheel.name, wheel.name
    with zipfile.ZipFile(wheel) as z:
        names = z.namelist()
    assert any(n.endswith(".data/scripts/guideway") for n in names), names
    assert any(n.endswith(".data/data/lib/guideway/libguideway.so") for n in names), names


def test_the_installed_command_exports_a_portable_fmu_that_fmpy_runs(installed, tmp_path):
    guideway = installed / "bin" / "guideway"
    assert glibc_needed(guideway) <= (2, 17)
    env = {k: v for k, v in os.environ.items() if k != "GUIDEWAY_CDYLIB"}
    version = subprocess.run([str(guideway), "--version"], capture_output=True, text=True,
                             env=env, check=True).stdout
    cargo = (ROOT / "Cargo.toml").read_text()
    assert version.split()[-1] in cargo, (version, "not the crate's version")
    out = tmp_path / "w.fmu"
    r = subprocess.run([str(guideway), "export", WHEEL, "-o", str(out)], capture_output=True,
                       text=True, env=env, cwd=tmp_path)
    # the installed FMU binary is found: no warning about a native build
    assert r.returncode == 0 and "warning" not in r.stderr, r.stderr
    with zipfile.ZipFile(out) as z:
        [binary] = [n for n in z.namelist() if n.startswith("binaries/")]
        (tmp_path / "lib.so").write_bytes(z.read(binary))
    assert glibc_needed(tmp_path / "lib.so") <= (2, 17)
    mine = simulate_fmu(str(out), stop_time=0.2, output_interval=0.01)
    reference = simulate_fmu(str(fmu_path(WHEEL)), stop_time=0.2, output_interval=0.01)
    for name in ("wheel.x", "wheel.y", "sensor.midspan.deflection"):
        assert np.all(np.isfinite(mine[name])), name
        assert np.array_equal(mine[name], reference[name]), name
