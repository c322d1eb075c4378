# Sourced by scripts/setup.sh and by its test (scripts/tests/test_setup.py).
#
# bindgen (run by fmi-sys at build time) loads libclang.so, libclang.so.N or
# libclang-<version>.so[.N]. A fresh Debian machine of our kind has only
# libclang-cpp.so.14 (the C++ interface, which bindgen cannot use), so a loose
# glob such as libclang*.so* wrongly concludes that libclang is present.

# has_bindgen_libclang ROOT: exit 0 when a library that bindgen can load is
# found under ROOT (use / for this machine), or in $LIBCLANG_PATH.
has_bindgen_libclang() {
    local root=${1%/} dir lib name
    local dirs=("$root"/usr/lib/llvm-*/lib "$root"/usr/lib/*-linux-gnu "$root"/usr/lib "$root"/usr/local/lib)
    [ -n "${LIBCLANG_PATH:-}" ] && dirs+=("$LIBCLANG_PATH")
    for dir in "${dirs[@]}"; do
        [ -d "$dir" ] || continue
        for lib in "$dir"/libclang*.so*; do
            [ -e "$lib" ] || continue
            name=${lib##*/}
            case "$name" in
                libclang.so | libclang.so.* | libclang-[0-9]*.so | libclang-[0-9]*.so.*) return 0 ;;
            esac
        done
    done
    return 1
}
