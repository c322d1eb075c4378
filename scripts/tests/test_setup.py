"""The set-up's libclang decision (scripts/lib/libclang.sh), run against
temporary directory trees so that it does not depend on this machine."""

import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
CHECK = ROOT / "scripts" / "lib" / "libclang.sh"


def decide(root, libclang_path=None):
    env = {k: v for k, v in os.environ.items() if k != "LIBCLANG_PATH"}
    if libclang_path is not None:
        env["LIBCLANG_PATH"] = str(libclang_path)
    result = subprocess.run(
        ["bash", "-c", f'. "{CHECK}"; has_bindgen_libclang "$1" && echo present || echo install',
         "check", str(root)],
        capture_output=True, text=True, env=env, check=True,
    )
    return result.stdout.strip()


def tree(tmp_path, *files):
    for f in files:
        path = tmp_path / f
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_bytes(b"")
    return tmp_path


def test_a_fresh_machine_with_only_libclang_cpp_needs_the_install(tmp_path):
    # What a fresh machine of our kind has: the C++ interface only.
    root = tree(tmp_path,
                "usr/lib/llvm-14/lib/libclang-cpp.so.14",
                "usr/lib/x86_64-linux-gnu/libclang-cpp.so.14",
                "usr/lib/llvm-14/lib/libLLVM-14.so")
    assert decide(root) == "install"


def test_an_empty_machine_needs_the_install(tmp_path):
    assert decide(tmp_path) == "install"


@pytest.mark.parametrize("library", [
    "usr/lib/x86_64-linux-gnu/libclang.so.1",
    "usr/lib/llvm-14/lib/libclang.so",
    "usr/lib/llvm-14/lib/libclang-14.so.1",
    "usr/lib/x86_64-linux-gnu/libclang-14.so.14.0.6",
])
def test_a_library_bindgen_loads_is_present(tmp_path, library):
    root = tree(tmp_path, "usr/lib/llvm-14/lib/libclang-cpp.so.14", library)
    assert decide(root) == "present"


def test_libclang_path_is_honoured(tmp_path):
    root = tree(tmp_path, "usr/lib/llvm-14/lib/libclang-cpp.so.14", "opt/clang/libclang.so")
    assert decide(root) == "install"
    assert decide(root, libclang_path=tmp_path / "opt" / "clang") == "present"
