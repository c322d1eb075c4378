# Sourced by scripts/setup.sh and by its test (scripts/tests/test_setup.py):
# whether this machine already has the Debian packages the tests need
# besides libclang (scripts/lib/libclang.sh). Both look on the PATH, so the
# test can put stand-ins there.

# has_libtbb12: exit 0 when the dynamic linker knows libtbb.so.12, which
# the Ecos master (PyPI ecospy) links and does not ship; an older libtbb.so.2
# does not count.
has_libtbb12() {
    ldconfig -p | grep 'libtbb\.so\.12 ' >/dev/null
}

# has_chromium: exit 0 when `chromium` is a command (it renders the bridge
# check's report headless in tests/product/bridge_check.rs).
has_chromium() {
    command -v chromium >/dev/null
}

# has_qemu_user: exit 0 when `qemu-x86_64` is a command: scripts/test.sh
# runs the guards' recorded bits on an emulated CPU without AVX and FMA,
# where glibc's and matrixmultiply's run-time choices differ from this
# machine's (docs/robustness.md, "The same bits on every CPU").
has_qemu_user() {
    command -v qemu-x86_64 >/dev/null
}
