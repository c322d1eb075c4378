"""Shared fixtures of the FMU tests.

scripts/test.sh builds the FMUs of the built-in scenes into $GUIDEWAY_FMU_DIR
(default out/fmu), with the cross-check reference files in
$GUIDEWAY_FMU_DIR/cross-check, before running pytest.
"""

import csv
import os
import pathlib
import re
import shutil
import subprocess
import sys
import tempfile
import tomllib
import zipfile
from xml.etree import ElementTree
from ctypes import byref

import numpy as np
import pytest
from fmpy import extract, read_model_description
from fmpy.fmi2 import (
    FMU2Slave,
    fmi2CallbackFunctions,
    fmi2CallbackLoggerTYPE,
    fmi2CallbackAllocateMemoryTYPE,
    fmi2CallbackFreeMemoryTYPE,
)
from fmpy.logging import addLoggerProxy

ROOT = pathlib.Path(__file__).resolve().parents[2]
FMU_DIR = pathlib.Path(os.environ.get("GUIDEWAY_FMU_DIR", ROOT / "out" / "fmu"))
PROFILE = os.environ.get("GUIDEWAY_PROFILE", "release")
sys.path.insert(0, str(ROOT / "scripts"))
from built import TARGET_DIR, guideway_command  # noqa: E402

GUIDEWAY = guideway_command(PROFILE)

# The quarter-car FMU is built with pythonfmu, whose binary finalizes Python
# when the library is unloaded. libcosim and Ecos keep it loaded until the
# process exits, after pytest's own interpreter is finalized: a use-after-free
# (valgrind: an invalid read in `finalizePythonInterpreter` from `_dl_fini`)
# that aborts now and then with "corrupted double-linked list", after every
# test passed. Such a session leaves with its status, skipping exit handlers.
_EXIT_STATUS = 0
_HOSTS_KEEPING_FMUS = ("libcosimpy", "ecospy")


# libcosim and Ecos unpack every FMU or SSP they load into a folder of their
# own under the temporary directory (`libcosim_<uuid>`, `ecos_ssp_<uuid>`,
# 4-6 MB each) and never remove it: a test run left dozens in /tmp. They
# find that directory through TMPDIR, so the session gives them (and every
# other temporary file of its tests) one of its own, removed when it passes
# and named when it fails, for a look at what the failing tests left.
# (Made in `pytest_configure`: scripts that import this module for its
# helpers keep their own temporary directory.)
SESSION_TMP = None


def pytest_configure(config):
    global SESSION_TMP
    SESSION_TMP = pathlib.Path(tempfile.mkdtemp(prefix="guideway-pytest-"))
    os.environ["TMPDIR"] = str(SESSION_TMP)
    tempfile.tempdir = str(SESSION_TMP)


def pytest_sessionfinish(session, exitstatus):
    global _EXIT_STATUS
    _EXIT_STATUS = int(exitstatus)
    if SESSION_TMP is None:
        return
    if _EXIT_STATUS == 0:
        shutil.rmtree(SESSION_TMP, ignore_errors=True)
    else:
        print(f"\nthe tests' temporary files are kept in {SESSION_TMP}", file=sys.stderr)


def extracted(fmu):
    """`fmu` unpacked once, beside it (`<name>.unzipped`), for every instance
    a test makes of it: fmpy's `extract` without a folder makes a new one in
    the temporary directory each time and leaves it there."""
    fmu = pathlib.Path(fmu)
    folder = fmu.with_name(fmu.name + ".unzipped")
    if not folder.is_dir():
        extract(str(fmu), str(folder))
    return str(folder)


@pytest.hookimpl(trylast=True)
def pytest_unconfigure(config):
    if any(name in sys.modules for name in _HOSTS_KEEPING_FMUS):
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(_EXIT_STATUS)


# The built-in scenes whose FMUs the tests use: (scene name, body).
WHEEL = "lee1994-wheel-10"
GLIDER = "lee1994-glider-30"
SCENES = [WHEEL, GLIDER]


def identifier(scene_name):
    return re.sub(r"[^A-Za-z0-9]", "_", scene_name)


def fmu_path(scene_name):
    path = FMU_DIR / f"{identifier(scene_name)}.fmu"
    if not path.is_file():
        pytest.fail(f"{path} missing: run scripts/test.sh (it exports the FMUs first)")
    assert_well_formed(path)
    return path


def assert_well_formed(fmu):
    """Every exported FMU's modelDescription.xml must be XML (issue 13)."""
    with zipfile.ZipFile(fmu) as z:
        ElementTree.fromstring(z.read("modelDescription.xml"))


def read_csv(path):
    """A CSV with a header line as (names, 2-D float array)."""
    with open(path) as f:
        names = next(csv.reader(f))
    data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    return names, data


def scene_of(fmu):
    with zipfile.ZipFile(fmu) as z:
        return z.read("resources/scene.toml").decode()


def set_in_toml(text, section, key, value):
    """Replace `key = ...` inside `[section]` of a TOML text."""
    out, current, done = [], None, False
    for line in text.splitlines():
        m = re.match(r"^\[+([^\]]+)\]+\s*$", line)
        if m:
            current = m.group(1)
        elif current == section and re.match(rf"^{key}\s*=", line):
            line = f"{key} = {value!r}" if isinstance(value, float) else f"{key} = {value}"
            done = True
        out.append(line)
    assert done, f"{section}.{key} not in scene"
    return "\n".join(out) + "\n"


def native_reference(scene_toml_text, tmp_path):
    """Run a scene natively (no FMI) with `guideway export --cross-check`:
    every output at every solver step until the exit or the default stop."""
    scene = tmp_path / "scene.toml"
    scene.write_text(scene_toml_text)
    name = tomllib.loads(scene_toml_text)["name"]
    cc = tmp_path / "cc"
    subprocess.run(
        [str(GUIDEWAY), "export", str(scene), "-o", str(tmp_path / "x.fmu"), "--cross-check", str(cc)],
        check=True,
        capture_output=True,
    )
    return read_csv(cc / f"{identifier(name)}_ref.csv")


class Messages(list):
    """Log messages received through the FMU's logger callback."""

    def text(self):
        return "\n".join(self)


_MESSAGES = {}  # instance name -> Messages
_CALLBACKS = None


def _logger(env, instance, status, category, message):
    name = instance.decode() if instance else ""
    _MESSAGES.setdefault(name, Messages()).append(
        f"[{status}] {category.decode()}: {message.decode()}")


def make_callbacks(instance_name):
    """Callbacks whose logger collects the messages of `instance_name`.

    fmpy's logger proxy (which formats the variadic message) keeps a single
    Python logger, so one callback struct serves all instances and the
    messages are sorted by instance name."""
    global _CALLBACKS
    if _CALLBACKS is None:
        from fmpy import calloc, free
        cb = fmi2CallbackFunctions()
        cb.logger = fmi2CallbackLoggerTYPE(_logger)
        cb.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
        cb.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
        addLoggerProxy(byref(cb))
        _CALLBACKS = cb
    messages = _MESSAGES[instance_name] = Messages()
    return _CALLBACKS, messages


@pytest.fixture(scope="session")
def unzipped(tmp_path_factory):
    """Scene name -> (unzip dir, model description)."""
    cache = {}

    def get(scene_name):
        if scene_name not in cache:
            fmu = fmu_path(scene_name)
            d = extract(str(fmu), str(tmp_path_factory.mktemp(identifier(scene_name))))
            cache[scene_name] = (d, read_model_description(str(fmu)))
        return cache[scene_name]

    return get


class Slave:
    """An fmpy FMU2Slave with a message-capturing logger and names -> vrs."""

    def __init__(self, unzipped, scene_name, name="instance", logging_on=False):
        d, md = unzipped(scene_name)
        self.md = md
        self.vr = {v.name: v.valueReference for v in md.modelVariables}
        self.callbacks, self.messages = make_callbacks(name)
        self.fmu = FMU2Slave(
            guid=md.guid,
            unzipDirectory=d,
            modelIdentifier=md.coSimulation.modelIdentifier,
            instanceName=name,
        )
        self.fmu.instantiate(callbacks=self.callbacks, loggingOn=logging_on)

    def init(self, **params):
        self.fmu.setupExperiment(startTime=0.0)
        for k, v in params.items():
            if isinstance(v, int):
                self.fmu.setInteger([self.vr[k]], [v])
            else:
                self.fmu.setReal([self.vr[k]], [v])
        self.fmu.enterInitializationMode()
        self.fmu.exitInitializationMode()
        return self

    def real(self, *names):
        return self.fmu.getReal([self.vr[n] for n in names])

    def outputs(self):
        reals = [v.valueReference for v in self.md.modelVariables
                 if v.causality == "output" and v.type == "Real"]
        return np.array(self.fmu.getReal(reals))

    def free(self):
        self.fmu.freeInstance()


@pytest.fixture
def slave(unzipped):
    made = []

    def make(scene_name=WHEEL, **kw):
        s = Slave(unzipped, scene_name, **kw)
        made.append(s)
        return s

    yield make
    for s in made:
        try:
            s.fmu.fmi2FreeInstance(s.fmu.component)
        except Exception:
            pass
