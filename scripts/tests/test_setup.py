"""The set-up's decisions to install Debian packages: libclang
(scripts/lib/libclang.sh), run against temporary directory trees, and
libtbb12 and chromium (scripts/lib/packages.sh), run with stand-ins for
`ldconfig` and `chromium` on the PATH, so that none depends on this
machine."""

import os
import pathlib
import shutil
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


PACKAGES = ROOT / "scripts" / "lib" / "packages.sh"


def decide_package(check, tmp_path, commands):
    """Run `check` of packages.sh with only `commands` (name -> stdout) on
    the PATH, each a stand-in script, beside the shell's own tools."""
    bin_dir = tmp_path / "bin"
    bin_dir.mkdir()
    for name, stdout in commands.items():
        path = bin_dir / name
        path.write_text(f"#!/bin/sh\ncat <<'END'\n{stdout}\nEND\n")
        path.chmod(0o755)
    for tool in ("grep", "cat"):
        (bin_dir / tool).symlink_to(shutil.which(tool))
    result = subprocess.run(
        ["/bin/bash", "-c", f'. "{PACKAGES}"; {check} && echo present || echo install'],
        capture_output=True, text=True, env={"PATH": str(bin_dir)}, check=True,
    )
    return result.stdout.strip()


LDCONFIG_FRESH = """2 libs found in cache `/etc/ld.so.cache'
\tlibtbb.so.2 (libc6,x86-64) => /lib/x86_64-linux-gnu/libtbb.so.2
\tlibc.so.6 (libc6,x86-64) => /lib/x86_64-linux-gnu/libc.so.6"""


def test_libtbb12_is_installed_when_the_linker_knows_only_an_older_tbb(tmp_path):
    assert decide_package("has_libtbb12", tmp_path, {"ldconfig": LDCONFIG_FRESH}) == "install"


def test_libtbb12_known_to_the_linker_is_present(tmp_path):
    cache = LDCONFIG_FRESH + "\n\tlibtbb.so.12 (libc6,x86-64) => /lib/x86_64-linux-gnu/libtbb.so.12"
    assert decide_package("has_libtbb12", tmp_path, {"ldconfig": cache}) == "present"


def test_chromium_is_installed_unless_it_is_a_command(tmp_path):
    assert decide_package("has_chromium", tmp_path, {"ldconfig": ""}) == "install"
    other = tmp_path / "other"
    other.mkdir()
    assert decide_package("has_chromium", other, {"chromium": ""}) == "present"


def test_qemu_user_is_installed_unless_qemu_x86_64_is_a_command(tmp_path):
    assert decide_package("has_qemu_user", tmp_path, {"ldconfig": ""}) == "install"
    other = tmp_path / "other"
    other.mkdir()
    assert decide_package("has_qemu_user", other, {"qemu-x86_64": ""}) == "present"
