#!/usr/bin/env python3
"""Fuzz the names and text of a scene through `guideway export` and an FMU
importer (issue 13).

Usage:
    .venv/bin/python scripts/fuzz_names.py [--cases 1000] [--seed 1]

Each case takes the default scene and replaces some of its scene name,
body name, sensor name and description with random text: lengths around
the limits (0, 1, 63 to 65 characters, 255, 256, up to 300, and longer),
drawn from identifier characters, XML's special characters (< & " ' ]]>),
non-ASCII letters and emoji, and characters XML 1.0 cannot carry (C0
controls, U+FFFE, U+FFFF). The scene is exported with `guideway export`.

Checks, per case:
  - the export exits 0 or 2, nothing else (no panic, no signal);
  - exit 2: stderr names the field, and no FMU is left at the -o path;
  - exit 0: modelDescription.xml parses as XML, fmpy reads and validates
    the model description, its model name and description are the scene's,
    and the FMU's binary loads and runs one step through fmpy (so the file
    names inside the FMU are usable).

Exit status 0 when every case passes.
"""

import argparse
import pathlib
import random
import subprocess
import sys
import tempfile
import time
import zipfile
from xml.etree import ElementTree

from built import ROOT, guideway_command

GUIDEWAY = guideway_command()

IDENTIFIER = "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_"
SPECIAL = ["-", ".", " ", "<", ">", "&", '"', "'", "]]>", "\\", "é", "ü", "∂", "😀", "\t"]
ILLEGAL = [chr(c) for c in range(0, 32) if c not in (9, 10, 13)] + ["\n", "\r", "\x7f",
                                                                   "\ufffe", "\uffff"]
LENGTHS = [0, 1, 2, 63, 64, 65, 100, 255, 256, 300, 1000, 1001, 5000]

# (field path in error messages, the text in the default scene's TOML)
FIELDS = [
    ("name", 'name = "lee1994-wheel-10"'),
    ("description", 'description = "'),
    ("body.name", 'name = "wheel"'),
    ("sensors[0].name", 'name = "midspan"'),
]


def toml_string(text):
    """A TOML basic string holding `text` exactly."""
    out = []
    for c in text:
        if c in '"\\':
            out.append("\\" + c)
        elif 32 <= ord(c) < 127:
            out.append(c)
        elif ord(c) <= 0xFFFF:
            out.append(f"\\u{ord(c):04X}")
        else:
            out.append(f"\\U{ord(c):08X}")
    return '"' + "".join(out) + '"'


def random_text(rng):
    length = rng.choice(LENGTHS) if rng.random() < 0.7 else rng.randint(0, 400)
    kind = rng.random()
    if kind < 0.5:  # a plausible identifier: only the length can be wrong
        first = rng.choice(IDENTIFIER[:52] + "_")
        return (first + "".join(rng.choice(IDENTIFIER) for _ in range(length)))[:max(length, 1)]
    pool = list(IDENTIFIER) + SPECIAL + (ILLEGAL if kind < 0.8 else [])
    return "".join(rng.choice(pool) for _ in range(length))


def make_case(rng, base):
    """The scene text and the fields changed: {path: new text}."""
    changed = {}
    for path, _ in FIELDS:
        if rng.random() < 0.5:
            changed[path] = random_text(rng)
    if not changed:
        path = rng.choice(FIELDS)[0]
        changed[path] = random_text(rng)
    text = base
    for path, marker in FIELDS:
        if path not in changed:
            continue
        if path == "description":
            start = text.index(marker)
            end = text.index("\n", start)
            text = text[:start] + "description = " + toml_string(changed[path]) + text[end:]
        else:
            key = marker.split(" = ")[0]
            text = text.replace(marker, f"{key} = {toml_string(changed[path])}", 1)
    return text, changed


def load_and_step(fmu, scene_text, workdir):
    """fmpy reads the FMU, and its binary loads and makes one step."""
    import tomllib
    from fmpy import extract, read_model_description
    from fmpy.fmi2 import FMU2Slave

    scene = tomllib.loads(scene_text)
    with zipfile.ZipFile(fmu) as z:
        ElementTree.fromstring(z.read("modelDescription.xml"))
    md = read_model_description(str(fmu), validate=True)
    assert md.modelName == scene["name"], (md.modelName, scene["name"])
    assert (md.description or "") == scene.get("description", ""), md.description
    unzipped = extract(str(fmu), unzipdir=str(workdir))
    slave = FMU2Slave(guid=md.guid, unzipDirectory=unzipped,
                      modelIdentifier=md.coSimulation.modelIdentifier, instanceName="fuzz")
    slave.instantiate()
    slave.setupExperiment(startTime=0.0)
    slave.enterInitializationMode()
    slave.exitInitializationMode()
    slave.doStep(0.0, 0.0025)
    slave.terminate()
    slave.freeInstance()


def check(rng, base, workdir):
    """None if the case passes, else what went wrong (with the scene)."""
    text, changed = make_case(rng, base)
    scene = workdir / "case.toml"
    scene.write_text(text, encoding="utf-8")
    fmu = workdir / "case.fmu"
    fmu.unlink(missing_ok=True)
    done = subprocess.run([str(GUIDEWAY), "export", str(scene), "-o", str(fmu)],
                          capture_output=True, timeout=60)
    stderr = done.stderr.decode(errors="replace")
    try:
        if done.returncode == 2:
            assert stderr.startswith("error: "), "no diagnostic"
            assert "panicked" not in stderr
            assert any(f"\n  {path} = " in stderr for path in changed), "no changed field named"
            assert not fmu.exists(), "an FMU was left"
            return "refused", None
        assert done.returncode == 0, f"exit {done.returncode}"
        step_dir = pathlib.Path(tempfile.mkdtemp(dir=workdir))
        load_and_step(fmu, text, step_dir)
        return "loaded", None
    except Exception as e:  # noqa: BLE001 - every failure is reported with its case
        return "failed", f"{type(e).__name__}: {e}\n{stderr}\nchanged: {changed!r}"


def fuzz(cases, seed=1, log=print):
    base = subprocess.run([str(GUIDEWAY), "scenes", "--show", "lee1994-wheel-10"],
                          capture_output=True, check=True, text=True).stdout
    tally = {"refused": 0, "loaded": 0, "failed": 0}
    failures = []
    started = time.monotonic()
    with tempfile.TemporaryDirectory() as tmp:
        for case in range(cases):
            rng = random.Random(seed + case)
            outcome, why = check(rng, base, pathlib.Path(tmp))
            tally[outcome] += 1
            if why:
                failures.append(f"seed {seed + case}: {why}")
                log(failures[-1])
    tally["seconds"] = round(time.monotonic() - started, 1)
    tally["failures"] = failures
    return tally


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--cases", type=int, default=1000)
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()
    s = fuzz(args.cases, args.seed)
    print(f"name fuzz: {args.cases} exports: {s['loaded']} exported and loaded by fmpy, "
          f"{s['refused']} refused naming the field, {len(s['failures'])} failures, "
          f"{s['seconds']} s")
    sys.exit(1 if s["failures"] else 0)


if __name__ == "__main__":
    main()
