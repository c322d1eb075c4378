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

# wheel_data_dir ROOT: where the wheel's data goes, made if missing: beside
# the portable build. pyproject.toml names target/wheel-data, which maturin
# wants to exist; a CARGO_TARGET_DIR elsewhere holds it, linked there.
wheel_data_dir() {
    local root=$1 native_dir data
    native_dir=$(dirname "$(cd "$root" && portable_target_dir)")
    data="$native_dir/wheel-data"
    mkdir -p "$data"
    if [ "$data" != "$root/target/wheel-data" ]; then
        mkdir -p "$root/target"
        rm -rf "$root/target/wheel-data"
        ln -s "$data" "$root/target/wheel-data"
    fi
    echo "$data"
}

# maturin_build ROOT OUT: build the wheel of the repository at ROOT into the
# directory OUT, compiling in portable_target_dir; maturin's output goes to
# stderr.
maturin_build() {
    local root=$1 out=$2 target_dir
    target_dir=$(cd "$root" && portable_target_dir)
    mkdir -p "$target_dir"
    wheel_data_dir "$root" > /dev/null
    # GUIDEWAY_PORTABLE: build.rs refuses flags that build for one CPU.
    (cd "$target_dir" && GUIDEWAY_PORTABLE=1 PATH="$root/.venv/bin:$PATH" CARGO_TARGET_DIR="$target_dir" \
        "$root/.venv/bin/maturin" build --release --zig --quiet -m "$root/Cargo.toml" \
        -o "$out" >&2)
}

# The triple of the glibc 2.17 build: the host's, so no Rust target needs
# installing (maturin passes it as --target).
PORTABLE_TRIPLE=x86_64-unknown-linux-gnu

# portable_release_dir: where cargo puts the glibc 2.17 build's binaries
# (the command, the tests' in deps/, libguideway.so).
portable_release_dir() {
    echo "$(portable_target_dir)/$PORTABLE_TRIPLE/release"
}

# record_maturin_env ROOT FILE: the variables maturin_build's maturin sets
# for cargo (zig's linker and C compilers for glibc 2.17, build scripts kept
# native), NUL-separated into FILE. A stand-in cargo on maturin's PATH
# passes its queries through and, at the compile, writes its environment
# and stops it: maturin's settings are read from maturin, never copied here
# (the wrappers' paths and names depend on its version).
record_maturin_env() {
    local root=$1 file=$2 standin
    standin=$(mktemp -d)
    cat > "$standin/cargo" <<'STANDIN'
#!/usr/bin/env bash
if [ "$1" = rustc ]; then
    env -0 > "$GUIDEWAY_MATURIN_ENV"
    exit 3
fi
PATH=$GUIDEWAY_CARGO_PATH exec cargo "$@"
STANDIN
    chmod +x "$standin/cargo"
    env -0 > "$standin/before"
    # maturin fails at the stopped compile; its messages go to a log shown
    # only when nothing was recorded.
    GUIDEWAY_MATURIN_ENV="$standin/during" GUIDEWAY_CARGO_PATH="$PATH" \
        PATH="$standin:$PATH" maturin_build "$root" "$standin/wheel" 2> "$standin/log" || true
    if [ ! -s "$standin/during" ]; then
        cat "$standin/log" >&2
        echo "record_maturin_env: maturin never called cargo to compile" >&2
        rm -rf "$standin"
        return 1
    fi
    changed_variables "$standin/before" "$standin/during" > "$file"
    rm -rf "$standin"
}

# changed_variables BEFORE DURING: the NAME=VALUE entries of DURING (both
# NUL-separated `env -0` dumps) that BEFORE lacks or has with another value,
# but the PATH and the shell's own (the caller sets the PATH).
changed_variables() {
    local entry name
    declare -A before=()
    while IFS= read -r -d '' entry; do
        before["${entry%%=*}"]=${entry#*=}
    done < "$1"
    while IFS= read -r -d '' entry; do
        name=${entry%%=*}
        case $name in PATH | PWD | OLDPWD | SHLVL | _ | GUIDEWAY_MATURIN_ENV | GUIDEWAY_CARGO_PATH) continue ;; esac
        if [ -z "${before[$name]+set}" ] || [ "${before[$name]}" != "${entry#*=}" ]; then
            printf '%s\0' "$entry"
        fi
    done < "$2"
}

# portable_cargo ROOT COMMAND ARGS...: `cargo COMMAND ARGS` for
# PORTABLE_TRIPLE in portable_target_dir, with maturin's environment
# (record_maturin_env) and from where maturin_build runs it. Every crate is
# then compiled as maturin compiles it: `portable_cargo ROOT build --release
# --all-targets` builds the tests, the command and libguideway.so against
# glibc 2.17 at once, and maturin_build afterwards finds them built (it
# would otherwise compile the library a third time, about 4 minutes of the
# test command; docs/performance-log.md, "The test command's time").
portable_cargo() {
    local root=$1 command=$2 target_dir vars=()
    shift 2
    target_dir=$(cd "$root" && portable_target_dir)
    mkdir -p "$target_dir"
    record_maturin_env "$root" "$target_dir/maturin.env"
    mapfile -d '' vars < "$target_dir/maturin.env"
    (cd "$target_dir" && env "${vars[@]}" PATH="$root/.venv/bin:$PATH" \
        cargo "$command" --target "$PORTABLE_TRIPLE" --manifest-path "$root/Cargo.toml" "$@")
}
