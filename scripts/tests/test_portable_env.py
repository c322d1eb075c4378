"""How scripts/test.sh builds the tests in maturin's environment
(scripts/lib/portable.sh): `changed_variables` keeps what maturin set, and
`record_maturin_env` records it from a stand-in maturin (a script in a
temporary repository's .venv) through the stand-in cargo, so that none of
it depends on maturin or zig being installed."""

import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
PORTABLE = ROOT / "scripts" / "lib" / "portable.sh"


def bash(script, *args, env=None, cwd=None):
    return subprocess.run(["bash", "-c", f'set -euo pipefail; . "{PORTABLE}"; {script}', "bash", *args],
                          capture_output=True, text=True, env=env, cwd=cwd)


def dump(path, variables):
    path.write_bytes(b"".join(f"{k}={v}".encode() + b"\0" for k, v in variables.items()))


def entries(path):
    return dict(e.split("=", 1) for e in path.read_bytes().decode().split("\0") if e)


def test_changed_variables_keeps_the_new_and_the_changed_but_not_the_path(tmp_path):
    dump(tmp_path / "before", {"KEPT": "1", "MOVED": "2", "PATH": "/bin", "SHLVL": "1"})
    dump(tmp_path / "during", {"KEPT": "1", "MOVED": "3", "PATH": "/x:/bin", "SHLVL": "2",
                               "NEW_LINKER": "/z/cc", "ARGS_x86_64-unknown": "-a 'b c'\nd"})
    r = bash('changed_variables "$1" "$2" > "$3"', tmp_path / "before", tmp_path / "during",
             tmp_path / "out")
    assert r.returncode == 0, r.stderr
    assert entries(tmp_path / "out") == {"MOVED": "3", "NEW_LINKER": "/z/cc",
                                         "ARGS_x86_64-unknown": "-a 'b c'\nd"}


def fake_repository(tmp_path, maturin_body):
    repo = tmp_path / "repo"
    (repo / ".venv" / "bin").mkdir(parents=True)
    maturin = repo / ".venv" / "bin" / "maturin"
    maturin.write_text("#!/usr/bin/env bash\n" + maturin_body)
    maturin.chmod(0o755)
    return repo


def test_record_maturin_env_records_what_maturin_gives_cargo_at_the_compile(tmp_path):
    # Like maturin: a query first (passed to the real cargo), then the compile.
    repo = fake_repository(tmp_path, "cargo --version > /dev/null\n"
                                     "FAKE_LINKER=/z/cc cargo rustc --release --bin guideway\n")
    env = {**os.environ, "CARGO_TARGET_DIR": str(tmp_path / "t")}
    r = bash('record_maturin_env "$1" "$2"', repo, tmp_path / "env", env=env, cwd=repo)
    assert r.returncode == 0, r.stderr
    recorded = entries(tmp_path / "env")
    assert recorded["FAKE_LINKER"] == "/z/cc"
    assert recorded["CARGO_TARGET_DIR"] == str(tmp_path / "t" / "portable")
    assert recorded["GUIDEWAY_PORTABLE"] == "1"  # build.rs's check, in the tests' build too
    assert "PATH" not in recorded and "GUIDEWAY_MATURIN_ENV" not in recorded


def test_record_maturin_env_fails_when_maturin_never_compiles(tmp_path):
    repo = fake_repository(tmp_path, "echo 'no Cargo.toml' >&2; exit 1\n")
    env = {**os.environ, "CARGO_TARGET_DIR": str(tmp_path / "t")}
    r = bash('record_maturin_env "$1" "$2"', repo, tmp_path / "env", env=env, cwd=repo)
    assert r.returncode != 0
    assert "no Cargo.toml" in r.stderr and "maturin never called cargo to compile" in r.stderr


def build_script(tmp_path):
    """build.rs compiled on its own, as cargo would (env! read at compile time)."""
    exe = tmp_path / "build-script"
    env = {**os.environ, "CARGO_MANIFEST_DIR": str(ROOT)}
    r = subprocess.run(["rustc", "--edition", "2021", "-O", str(ROOT / "build.rs"), "-o", str(exe)],
                       capture_output=True, text=True, env=env)
    assert r.returncode == 0, r.stderr
    return exe


@pytest.mark.parametrize("portable, features, refused", [
    ("1", "fxsr,sse,sse2", False),
    ("1", "fxsr,sse,sse2,x87", False),
    ("1", "avx,avx2,fma,fxsr,sse,sse2", True),
    ("1", "fxsr,popcnt,sse,sse2,sse4.2", True),
    (None, "avx,avx2,fma,fxsr,sse,sse2", False),  # a native build may
])
def test_build_rs_refuses_a_portable_build_for_one_cpu(tmp_path, portable, features, refused):
    env = {k: v for k, v in os.environ.items() if k != "GUIDEWAY_PORTABLE"}
    env.update({"CARGO_CFG_TARGET_ARCH": "x86_64", "CARGO_CFG_TARGET_FEATURE": features,
                "PROFILE": "release"})
    if portable:
        env["GUIDEWAY_PORTABLE"] = portable
    r = subprocess.run([build_script(tmp_path)], capture_output=True, text=True, env=env)
    assert (r.returncode != 0) == refused, r.stderr
    if refused:
        extra = [f for f in features.split(",") if f not in ("fxsr", "sse", "sse2", "x87")]
        assert f"enable {', '.join(extra)} " in r.stderr
