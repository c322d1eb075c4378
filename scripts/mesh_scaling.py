#!/usr/bin/env python3
"""Step cost and peak memory against the mesh size (issue 29): whole runs of
`guideway run` under `/usr/bin/time -v`, one process each.

  python3 scripts/mesh_scaling.py wheel 16 256 300 16384
  python3 scripts/mesh_scaling.py train 3 10 100
  python3 scripts/mesh_scaling.py force 16 16384
  python3 scripts/mesh_scaling.py forces 10 100
  WRITE=DIR python3 scripts/mesh_scaling.py train 10 100

`wheel N`: the paper's wheel at 10 m/s (`lee1994-wheel-10`) on N elements
with HHT-α at its 2.5 ms step. `train S`: the eight coaches of
`scripts/scenes/bench-8-coaches-3x25-300-rigid.toml` (32 glider wheelsets on
Lee's rigid contact, HHT-α at 1 ms: the built-in train-8 before it moved to
Hertz contacts, kept so that this history stays comparable) over a
continuous bridge of S spans of 25 m, 25 elements a span. `force N`: the
moving forces of `bridge25-hslm` (HSLM-A1 at 50 m/s, no contact to solve)
on N elements with HHT-α at its 1 ms step, to 1 s. `forces S`: the same
viaduct as `train S`, its 32 axles as moving forces of the coaches' static
axle loads (no contact to solve): the structure's own share of a train
step, which `train S` less this is the contacts'. Prints a Markdown
table: steps, CPU (user + system, the fastest of REPEATS = 3 runs), CPU
per step and per element·step, peak RSS. GUIDEWAY=path measures another
build. WRITE=DIR writes each case's scene to DIR/CASE-N.toml (for
callgrind) and measures nothing.
"""

import json
import os
import re
import subprocess
import sys
import tempfile

REPEATS = int(os.environ.get("REPEATS", "3"))
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
GUIDEWAY = os.environ.get("GUIDEWAY", os.path.join(ROOT, "target", "release", "guideway"))


def shown(name):
    return subprocess.run(
        [GUIDEWAY, "scenes", "--show", name], check=True, capture_output=True, text=True
    ).stdout


def setting(text, key, value):
    """`text` with the first `key = ...` line's value replaced."""
    pattern = re.compile(rf"^{re.escape(key)} = .*?(\s+#.*)?$", re.M)
    new, count = pattern.subn(lambda m: f"{key} = {value}{m.group(1) or ''}", text, count=1)
    if count != 1:
        raise SystemExit(f"no `{key}` in the scene")
    return new


def wheel(elements):
    text = setting(shown("lee1994-wheel-10"), "elements", elements)
    return setting(text, "integrator", '"hht"'), elements


def force(elements):
    text = setting(shown("bridge25-hslm"), "elements", elements)
    text = setting(text, "integrator", '"hht"')
    # Its damping's modes 1 and 3 by frequency (f1 = 4 Hz on one pinned
    # span: f3 = 9 f1): beyond 4,096 elements the scene refuses modes.
    text = setting(text, "ratio", "[0.02, 0.02]").replace("\nratio = ", "\nratios = ", 1)
    text, count = re.subn(r"^modes = \[[^\]]*\]", "frequencies = [4.0, 36.0]", text, flags=re.M)
    if count != 1:
        raise SystemExit("no damping modes in the scene")
    return text.replace("[solver]\n", "[solver]\nend_time = 1.0\n", 1), elements


def train(spans):
    with open(os.path.join(ROOT, "scripts", "scenes", "bench-8-coaches-3x25-300-rigid.toml")) as f:
        text = f.read()
    text = setting(text, "length", f"{25.0 * spans}")
    text = setting(text, "elements", 25 * spans)
    supports = ", ".join(f"{25.0 * k}" for k in range(1, spans))
    # The intermediate supports' list spans several lines in the shown scene.
    text, count = re.subn(r"^intermediate = \[[^\]]*\]", f"intermediate = [{supports}]", text, flags=re.M)
    if count != 1:
        raise SystemExit("no intermediate supports in the scene")
    return text, 25 * spans


# The coaches of the bench scene: centres, axles about each centre (bogie
# half distance 8.75 m ± axle half distance 1.25 m) and the static axle load
# of body, two bogies and four wheelsets.
COACH_CENTRES = [-11.0 - 24.0 * k for k in range(8)]
AXLE_OFFSETS = [-10.0, -7.5, 7.5, 10.0]
AXLE_LOAD = (38884.0 + 2 * 2400.0 + 4 * 1400.0) * 9.81 / 4


def forces(spans):
    text, elements = train(spans)
    head = text[: text.index("[body]")]
    tail = text[text.index("[[sensors]]") :]
    blocks = []
    for coach, centre in enumerate(COACH_CENTRES):
        for axle, offset in enumerate(AXLE_OFFSETS):
            table = "[body]" if not blocks else "[[vehicles]]"
            blocks.append(
                f'{table}\nname = "coach{coach + 1}_axle{axle + 1}"\nkind = "moving_force"\n'
                f"mass = 1.0\ninitial_position = {centre + offset}\ninitial_speed = 83.3333\n"
                f"force_y = {-AXLE_LOAD}\n"
            )
    # The moving forces need no static start of bodies.
    tail = tail.replace('start = "static"\n', "")
    return head + "\n".join(blocks) + "\n" + tail, elements


def measure(text, elements):
    with tempfile.TemporaryDirectory() as tmp:
        scene = os.path.join(tmp, "scene.toml")
        summary = os.path.join(tmp, "summary.json")
        with open(scene, "w") as f:
            f.write(text)
        # The child's own CPU time and peak RSS, to the microsecond and kB
        # (`/usr/bin/time` rounds CPU to 10 ms); the fastest of `REPEATS`.
        best = None
        for _ in range(REPEATS):
            child = subprocess.Popen(
                ["/usr/bin/time", "-v", GUIDEWAY, "run", scene, "-q", "--summary", summary],
                stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
            )
            _, status, usage = os.wait4(child.pid, 0)
            if status != 0:
                raise SystemExit(f"{elements} elements: {child.stderr.read()[-2000:]}")
            # wait4 counts `time`'s waited-for child; its own maxrss is that
            # of the forked Python, so the peak RSS is the one `time` reports.
            cpu = usage.ru_utime + usage.ru_stime
            report = child.stderr.read()
            rss = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", report).group(1))
            time_user = float(re.search(r"User time \(seconds\): ([\d.]+)", report).group(1))
            assert abs(time_user - usage.ru_utime) < 0.02, (time_user, usage.ru_utime)
            best = (cpu, rss) if best is None else (min(best[0], cpu), max(best[1], rss))
        user, rss = best
        figures = json.load(open(summary))
    steps = figures["steps"]
    return steps, user, rss


def main():
    cases = {"wheel": wheel, "train": train, "force": force, "forces": forces}
    if len(sys.argv) < 3 or sys.argv[1] not in cases:
        raise SystemExit(__doc__)
    case = cases[sys.argv[1]]
    if os.environ.get("WRITE"):
        os.makedirs(os.environ["WRITE"], exist_ok=True)
        for size in sys.argv[2:]:
            path = os.path.join(os.environ["WRITE"], f"{sys.argv[1]}-{size}.toml")
            with open(path, "w") as f:
                f.write(case(int(size))[0])
            print(path)
        return
    print("| elements | steps | CPU (s) | µs per step | ns per element·step | peak RSS (MiB) |")
    print("|---:|---:|---:|---:|---:|---:|")
    for size in sys.argv[2:]:
        text, elements = case(int(size))
        steps, user, rss = measure(text, elements)
        per_step = user / steps
        print(
            f"| {elements} | {steps} | {user:.3f} | {per_step * 1e6:,.1f} "
            f"| {per_step / elements * 1e9:,.1f} | {rss / 1024:.1f} |",
            flush=True,
        )


if __name__ == "__main__":
    main()
