"""`export` and `release` package the portable (glibc 2.17) FMU binary by
default: `export` takes it when `scripts/build_portable.sh` has built it
(else the native one, with a warning saying what that needs), `release`
refuses without it (README, "The FMU binary")."""

import os
import shutil
import subprocess
import zipfile

from conftest import GUIDEWAY, ROOT, TARGET_DIR, WHEEL

PORTABLE = TARGET_DIR / "portable" / "x86_64-unknown-linux-gnu" / "release" / "libguideway.so"


def run(binary, *args, cwd=None):
    env = {k: v for k, v in os.environ.items() if k != "GUIDEWAY_CDYLIB"}
    return subprocess.run([str(binary), *args], capture_output=True, text=True, env=env, cwd=cwd)


def packaged_binary(fmu):
    with zipfile.ZipFile(fmu) as z:
        [name] = [n for n in z.namelist() if n.startswith("binaries/")]
        return z.read(name)


def test_export_packages_the_portable_build_when_there_is_one(tmp_path):
    if not PORTABLE.is_file():
        import pytest
        pytest.skip("no portable build (scripts/test.sh makes one)")
    r = run(GUIDEWAY, "export", WHEEL, "-o", str(tmp_path / "w.fmu"))
    assert r.returncode == 0 and "warning" not in r.stderr, r.stderr
    assert packaged_binary(tmp_path / "w.fmu") == PORTABLE.read_bytes()


def test_without_a_portable_build_export_warns_and_release_refuses(tmp_path):
    # A target directory with the native build only.
    release_dir = tmp_path / "target" / "release"
    release_dir.mkdir(parents=True)
    shutil.copy2(GUIDEWAY, release_dir / "guideway")
    shutil.copy2(GUIDEWAY.parent / "libguideway.so", release_dir / "libguideway.so")
    r = run(release_dir / "guideway", "export", WHEEL, "-o", str(tmp_path / "w.fmu"))
    assert r.returncode == 0, r.stderr
    assert "warning: packaging" in r.stderr and "not the 2.17 baseline" in r.stderr, r.stderr
    r = run(release_dir / "guideway", "release", "--out", str(tmp_path / "dist"),
            "--changelog", str(ROOT / "CHANGELOG.md"))
    assert r.returncode == 1, r.stderr
    assert "a release ships the portable FMU binary, which is not built" in r.stderr, r.stderr
    assert "scripts/build_portable.sh" in r.stderr
    assert not (tmp_path / "dist").exists()
