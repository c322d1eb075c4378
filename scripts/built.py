"""Where the project's builds are, for the scripts and the Python tests:
cargo's target directory, and the `guideway` command they run."""

import os
import pathlib

ROOT = pathlib.Path(__file__).resolve().parents[1]
# cargo builds into $CARGO_TARGET_DIR when it is set (relative to the root).
TARGET_DIR = ROOT / os.environ.get("CARGO_TARGET_DIR", "target")


def guideway_command(profile="release"):
    """$GUIDEWAY_BIN (scripts/test.sh sets it to its glibc 2.17 build), else
    cargo's build of `profile`."""
    return pathlib.Path(os.environ.get("GUIDEWAY_BIN", TARGET_DIR / profile / "guideway"))
