# Sourced by scripts/build_portable.sh and scripts/build_wheel.sh: the one
# maturin invocation both run, so that the second finds everything compiled
# by the first (any difference in flags, target directory or working
# directory would compile every crate again, about 3.5 minutes).
#
# maturin's `--zig` links against zig's glibc stubs of the manylinux2014
# baseline (2.17). Run from inside the target directory: zig names its lib
# directory relative to the working directory when it lies below it, and
# the zig wrapper hands that to bindgen (in fmi-sys's build script), which
# runs elsewhere and then misses stddef.h.

# portable_target_dir: where the glibc 2.17 build goes, as an absolute
# path: its own directory (the native build keeps its build scripts),
# beside the native build ($CARGO_TARGET_DIR when it is set).
portable_target_dir() {
    local native_dir=${CARGO_TARGET_DIR:-target}
    case "$native_dir" in /*) ;; *) native_dir="$PWD/$native_dir" ;; esac
    echo "$native_dir/portable"
}

# maturin_build ROOT OUT: build the wheel of the repository at ROOT into the
# directory OUT, compiling in portable_target_dir; maturin's output goes to
# stderr.
maturin_build() {
    local root=$1 out=$2 target_dir
    target_dir=$(cd "$root" && portable_target_dir)
    mkdir -p "$target_dir"
    (cd "$target_dir" && PATH="$root/.venv/bin:$PATH" CARGO_TARGET_DIR="$target_dir" \
        "$root/.venv/bin/maturin" build --release --zig --quiet -m "$root/Cargo.toml" \
        -o "$out" >&2)
}
