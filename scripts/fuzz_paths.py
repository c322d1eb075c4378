#!/usr/bin/env python3
"""Fuzz the file paths of guideway's commands (issue 30, classes 2, 4, 7, 10).

Usage:
    python scripts/fuzz_paths.py [--cases 300] [--seed 1]

Each case builds a fresh folder with the lee1994-wheel-10 scene and a
profile table beside it, then draws one attack:
  - alias: a command's output (`run --out`, `run --summary`, `sweep --out`,
    `modes --out`, `export -o`) is the scene or the table under another
    spelling (the same path, `./x`, `sub/../x`, a symbolic link, a hard link,
    the file through a linked folder): the command must exit 2 saying the
    input "would be overwritten", and leave the input byte-identical;
  - fifo: the scene or the table is a named pipe: exit 2 within 20 s;
  - outside: the table is named by an absolute path, `../`, a link that
    leads out of the scene's folder, or a file in a linked folder outside:
    exit 2, and stderr shows no line of that file;
  - generated name: a glider named like a body another vehicle generates
    (`<bogie vehicle>_bogie1..2`, `_wheelset1..4`, `<sprung mass>_unsprung`):
    exit 2, naming the clash;
  - counts: a fleet of 1 to 300 maglev vehicles of 1 to 1,000 magnets (a
    few kB of scene): above the contact-row bound (2,000 rows, the product
    of the counts) exit 2 naming the rows and the bound, below it a two-step
    run (end_time 1e-4 s) ends (0 or 1) within 120 s.

Exit status 0 when every case passes; a failure names the case and seed.
"""

import argparse
import math
import os
import pathlib
import random
import subprocess
import sys
import tempfile

from built import ROOT, guideway_command

GUIDEWAY = guideway_command()
SECRET = "secret-line-7f3a,1"   # a line no refusal may show
TABLE = "0,0\n10,0.001\n30,0\n"


def guideway(args, cwd, timeout=20):
    try:
        p = subprocess.run([str(GUIDEWAY), *args], cwd=cwd, capture_output=True, text=True,
                           timeout=timeout, stdin=subprocess.DEVNULL)
        return p.returncode, p.stderr
    except subprocess.TimeoutExpired:
        return "timeout", ""


def scene_text(table_path):
    text = subprocess.run([str(GUIDEWAY), "scenes", "--show", "lee1994-wheel-10"],
                          capture_output=True, text=True, check=True).stdout
    return f'{text}\n[[track.irregularities]]\ntype = "table"\nfile = "{table_path}"\n'


def alias(rng, d, target):
    """Another spelling of `target` (a file in folder `d`), and its kind."""
    kind = rng.choice(["same", "dot", "updown", "symlink", "hardlink", "linked dir"])
    name = target.name
    if kind == "same":
        return str(target), kind
    if kind == "dot":
        return f"./{name}", kind
    if kind == "updown":
        (d / "sub").mkdir(exist_ok=True)
        return f"sub/../{name}", kind
    if kind == "symlink":
        (d / "l.out").symlink_to(target)
        return "l.out", kind
    if kind == "hardlink":
        os.link(target, d / "h.out")
        return "h.out", kind
    (d / "ld").symlink_to(d)
    return f"ld/{name}", kind


def case_alias(rng, d):
    scene, table = d / "s.toml", d / "t.csv"
    target = rng.choice([scene, table])
    before = target.read_bytes()
    out, how = alias(rng, d, target)
    command = rng.choice([["run", "s.toml", "--quiet", "--out", out],
                          ["run", "s.toml", "--quiet", "--summary", out],
                          ["sweep", "s.toml", "--speeds", "10", "--out", out],
                          ["modes", "s.toml", "--out", out],
                          ["export", "s.toml", "-o", out]])
    code, err = guideway(command, d)
    what = f"alias {command[0]} {command[-2]} onto {target.name} ({how})"
    if code != 2 or target.read_bytes() != before or "would be overwritten" not in err:
        return what, f"exit {code}, input {'un' if target.read_bytes() == before else ''}changed: {err[-300:]}"
    return what, None


def case_fifo(rng, d):
    which = rng.choice(["scene", "table"])
    if which == "scene":
        os.mkfifo(d / "p.toml")
        code, err = guideway(["run", "p.toml", "--quiet"], d)
    else:
        (d / "t.csv").unlink()
        os.mkfifo(d / "t.csv")
        code, err = guideway(["run", "s.toml", "--quiet"], d)
    what = f"fifo as {which}"
    return what, None if code == 2 else f"exit {code}: {err[-300:]}"


def case_outside(rng, d):
    outer = d.parent / "outside"
    outer.mkdir(exist_ok=True)
    (outer / "x.csv").write_text(f"0,0\n{SECRET}\n")
    how = rng.choice(["absolute", "dotdot", "symlink", "linked dir"])
    name = {"absolute": str(outer / "x.csv"), "dotdot": "../outside/x.csv",
            "symlink": "p.csv", "linked dir": "lo/x.csv"}[how]
    if how == "symlink":
        (d / "p.csv").symlink_to(outer / "x.csv")
    if how == "linked dir":
        (d / "lo").symlink_to(outer)
    (d / "s.toml").write_text(scene_text(name))
    code, err = guideway(["run", "s.toml", "--quiet"], d)
    what = f"table outside the folder ({how})"
    if code != 2 or "secret" in err:
        return what, f"exit {code}: {err[-300:]}"
    return what, None


GENERATED = [("bogie_vehicle", "_bogie1"), ("bogie_vehicle", "_bogie2"),
             ("bogie_vehicle", "_wheelset1"), ("bogie_vehicle", "_wheelset4"),
             ("sprung_mass", "_unsprung")]


def case_generated(rng, d):
    kind, suffix = rng.choice(GENERATED)
    base = {"bogie_vehicle": "train-3-coaches-2x25-5", "sprung_mass": None}[kind]
    if base:
        text = subprocess.run([str(GUIDEWAY), "scenes", "--show", base], capture_output=True,
                              text=True, check=True).stdout
        owner = rng.choice(["coach1", "coach2", "coach3"])
    else:
        text = subprocess.run([str(GUIDEWAY), "scenes", "--show", "lee1994-glider-30"],
                              capture_output=True, text=True, check=True).stdout
        text = (text.replace('kind = "glider"', 'kind = "sprung_mass"', 1)
                .replace('name = "glider"', 'name = "car"', 1)
                + "\n[body.suspension]\nstiffness = 1e6\nunsprung_mass = 10.0\n")
        owner = "car"
    clash = owner + suffix
    text += (f'\n[[vehicles]]\nname = "{clash}"\nkind = "glider"\nmass = 100.0\n'
             "initial_position = -60.0\ninitial_speed = 5.0\n")
    (d / "g.toml").write_text(text)
    code, err = guideway(["export", "g.toml", "-o", "g.fmu"], d)
    what = f"generated name {clash}"
    if code != 2 or clash not in err:
        return what, f"exit {code}: {err[-300:]}"
    return what, None


MAX_CONTACT_ROWS = 2000  # src/scene/limits.rs


def fleet(count, magnets):
    """`count` maglev vehicles of `magnets` magnets each on a 100 m beam."""
    text = ('name = "fleet"\ngravity = 9.81\n[beam]\nlength = 100.0\n'
            "mass_per_length = 2303.0\nbending_stiffness = 8.5e10\nsurface_offset = 0.0\n"
            'elements = 10\n[solver]\nstep = 5e-5\nend_time = 1e-4\nstart = "static"\n')
    for k in range(count):
        table, sub = ("[body]", "body") if k == 0 else ("[[vehicles]]", "vehicles")
        text += (f'{table}\nname = "car{k}"\nkind = "maglev_vehicle"\nmass = 30000.0\n'
                 f"initial_position = 50.0\ninitial_speed = 0.0\n[{sub}.maglev]\n"
                 f"car_inertia = 1.5e6\nmagnets = {magnets}\nmagnet_spacing = 0.001\n"
                 "magnet_mass = 600.0\nstiffness = 8.0e5\n")
    return text


def case_counts(rng, d):
    # Around the bound, on a log scale: rows from 1 to 300,000.
    count = max(1, int(10 ** rng.uniform(0, math.log10(300))))
    magnets = max(1, int(10 ** rng.uniform(0, 3)))
    rows = count * magnets
    (d / "f.toml").write_text(fleet(count, magnets))
    code, err = guideway(["run", "f.toml", "--quiet", "--max-steps", "2", "--out", "f.csv"],
                         d, timeout=120)
    what = f"counts {count} x {magnets} = {rows} rows"
    if rows > MAX_CONTACT_ROWS:
        ok = code == 2 and f"{rows} contact rows" in err and str(MAX_CONTACT_ROWS) in err
    else:
        ok = code in (0, 1)
    return what, None if ok else f"exit {code}: {err[-300:]}"


CASES = [case_alias] * 5 + [case_fifo, case_outside, case_generated, case_counts]


def run_case(seed):
    rng = random.Random(seed)
    with tempfile.TemporaryDirectory() as tmp:
        d = pathlib.Path(tmp) / "scene"
        d.mkdir()
        (d / "t.csv").write_text(TABLE)
        (d / "s.toml").write_text(scene_text("t.csv"))
        return rng.choice(CASES)(rng, d)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", type=int, default=300)
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args()
    tally, failures = {}, []
    for seed in range(args.seed, args.seed + args.cases):
        what, failure = run_case(seed)
        kind = what.split(" (")[0].split(" onto")[0]
        if kind.startswith("generated"):
            kind = "generated name"
        elif kind.startswith("counts"):
            over = int(what.split()[-2]) > MAX_CONTACT_ROWS
            kind = f"counts {'over' if over else 'within'} the contact-row bound"
        tally[kind] = tally.get(kind, 0) + 1
        if failure:
            failures.append(f"seed {seed}: {what}: {failure}")
    for k, v in sorted(tally.items()):
        print(f"{v:6d}  {k}")
    print(f"{args.cases} cases, {len(failures)} failures")
    for f in failures:
        print(f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
