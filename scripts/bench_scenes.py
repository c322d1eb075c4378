#!/usr/bin/env python3
"""Write the scenes docs/performance.md measures issue 24's and issue 29's
costs on, so that each figure there can be counted again from a clone.

  python3 scripts/bench_scenes.py DIR
  python3 scripts/bench_scenes.py DIR --track-scale 2 --coaches 4 --end-time 0.1

writes into DIR:
- `rail.toml`: `scenes/train-8-coaches-20m-300-rail.toml` (eight coaches on
  1400 kg wheelsets, Hertz, the rail over a 20 m deck on the ballasted
  layer, HHT-α at 0.25 ms) to `end_time` (0.3 s unless given);
- `sleepers.toml`: `scenes/train-8-coaches-20m-300-sleepers.toml`, the same
  on sleepers;
- `followers.toml`: the rail scene without its rail and contact laws, on
  massless followers (the bare deck, Lee's rigid contact): the "same scene
  with followers" of issue 24's speed target;
- `S100_1s.toml`: `scripts/mesh_scaling.py`'s train over 100 spans of
  25 m, to 1 s.

`--track-scale S` multiplies the approach and run-off of the first three,
`--coaches N` keeps their first N coaches.
"""

import argparse
import os
import re

import mesh_scaling

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def replaced(text, key, value):
    """`text` with every `key = ...` line's value replaced (one or more)."""
    new, count = re.subn(rf"^{re.escape(key)} = .*$", f"{key} = {value}", text, flags=re.M)
    if count == 0:
        raise SystemExit(f"no `{key}` in the scene")
    return new


def first_coaches(text, coaches):
    """The scene with its `[body]` and the first `coaches - 1` vehicles."""
    head, *vehicles = text.split("[[vehicles]]")
    rest = vehicles[-1]
    after = rest.find("[[sensors]]")
    vehicles[-1], tail = rest[:after], rest[after:]
    return head + "".join("[[vehicles]]" + v for v in vehicles[: coaches - 1]) + tail


def without_tables(text, names):
    """The scene without the tables `[name]` (each up to the next table)."""
    for name in names:
        pattern = rf"^\[{re.escape(name)}\]\n(?:(?!\[).*\n|\n)*"
        text = re.sub(pattern, "", text, flags=re.M)
    return text


def template(name, args):
    with open(os.path.join(ROOT, "scenes", name)) as f:
        text = f.read()
    text = replaced(text, "end_time", args.end_time)
    for key in ("approach", "run_off"):
        value = float(re.search(rf"^{key} = (.*)$", text, flags=re.M).group(1))
        text = replaced(text, key, value * args.track_scale)
    return first_coaches(text, args.coaches)


def followers(rail):
    text = without_tables(rail, ["track.on_deck", "body.contact_law", "vehicles.contact_law"])
    text = replaced(text, "wheelset_mass", "0.0")
    return text.replace("-300-rail\"", "-300-followers\"", 1)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("dir")
    parser.add_argument("--track-scale", type=float, default=1.0)
    parser.add_argument("--coaches", type=int, default=8)
    parser.add_argument("--end-time", type=float, default=0.3)
    args = parser.parse_args()
    if not 1 <= args.coaches <= 8:
        raise SystemExit(f"--coaches {args.coaches}: between 1 and 8")
    os.makedirs(args.dir, exist_ok=True)
    rail = template("train-8-coaches-20m-300-rail.toml", args)
    scenes = {
        "rail.toml": rail,
        "sleepers.toml": template("train-8-coaches-20m-300-sleepers.toml", args),
        "followers.toml": followers(rail),
        "S100_1s.toml": replaced(mesh_scaling.train(100)[0], "end_time", 1.0),
    }
    for name, text in scenes.items():
        with open(os.path.join(args.dir, name), "w") as f:
            f.write(text)
        print(os.path.join(args.dir, name))


if __name__ == "__main__":
    main()
