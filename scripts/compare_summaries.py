#!/usr/bin/env python3
"""Two builds' `--summary` of the same scenes side by side (issue 29): for
each scene, whether every field but the wall time is equal and, for the
dynamic amplification factors (the fields that read the static envelope),
how many are bit-identical and the largest relative difference.

  python3 scripts/compare_summaries.py OLD_GUIDEWAY NEW_GUIDEWAY SCENE...
"""

import json
import os
import subprocess
import sys
import tempfile


def summary(guideway, scene, tmp):
    path = os.path.join(tmp, "summary.json")
    subprocess.run([guideway, "run", scene, "-q", "--summary", path], check=True,
                   stdout=subprocess.DEVNULL)
    with open(path) as f:
        return json.load(f)


def main():
    if len(sys.argv) < 4:
        raise SystemExit(__doc__)
    old_build, new_build, scenes = sys.argv[1], sys.argv[2], sys.argv[3:]
    worst = 0.0
    with tempfile.TemporaryDirectory() as tmp:
        for scene in scenes:
            old, new = summary(old_build, scene, tmp), summary(new_build, scene, tmp)
            a, b = old.get("dynamic_amplification", {}), new.get("dynamic_amplification", {})
            if a.keys() != b.keys():
                raise SystemExit(f"{scene}: the DAFs differ in name")
            relative = [abs(a[k] - b[k]) / abs(a[k]) for k in a if a[k]]
            largest = max(relative, default=0.0)
            worst = max(worst, largest)
            same = sum(a[k] == b[k] for k in a)
            skipped = ("wall_time_s", "dynamic_amplification")
            others = [k for k in old if k not in skipped and old[k] != new.get(k)]
            print(f"{scene}: {len(a)} DAFs, {same} bit-identical, largest relative "
                  f"difference {largest:.2e}; other fields that differ: {others or 'none'}",
                  flush=True)
    print(f"largest relative difference of a DAF: {worst:.2e}")


if __name__ == "__main__":
    main()
