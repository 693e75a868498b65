#!/usr/bin/env bash
# bootstrap.sh - install what the build needs and fetch Musashi into build/.
# Idempotent: does nothing when everything is there.  Called by `make deps`,
# which `make`, `make test` and `make demo` depend on.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${BUILD:-build}
CROSS=${CROSS:-m68k-linux-gnu-}

need=()
have_cmd() { command -v "$1" >/dev/null 2>&1; }
have_cmd "${CROSS}gcc" || need+=(gcc-m68k-linux-gnu)
have_cmd "${CROSS}objcopy" || need+=(binutils-m68k-linux-gnu)
[ -f /usr/include/cmocka.h ] || need+=(libcmocka-dev)
have_cmd pkg-config || need+=(pkg-config)
have_cmd python3 || need+=(python3)
have_cmd cc || need+=(gcc)
have_cmd make || need+=(make)
# hardening (docs/hardening.md): the qemu-m68k witness, cppcheck, and
# libFuzzer with clang for `make fuzz` (llvm: llvm-cov for `make fuzz-cov`)
have_cmd qemu-m68k || need+=(qemu-user)
have_cmd cppcheck || need+=(cppcheck)
have_cmd clang || need+=(clang)
have_cmd llvm-cov || need+=(llvm)
apt_updated=0
apt_install() {
    echo "bootstrap: installing Debian packages: $*"
    SUDO=""
    [ "$(id -u)" -ne 0 ] && SUDO="sudo"
    export DEBIAN_FRONTEND=noninteractive
    [ $apt_updated -eq 1 ] || $SUDO apt-get update -qq
    apt_updated=1
    $SUDO apt-get install -y -qq "$@"
}
if [ ${#need[@]} -gt 0 ]; then
    apt_install "${need[@]}"
fi
# libFuzzer's runtime comes in a package named after clang's major version
if have_cmd clang; then
    fuzzer_lib=$(clang --print-file-name="libclang_rt.fuzzer-$(uname -m).a")
    if [ ! -f "$fuzzer_lib" ]; then
        apt_install "libclang-rt-$(clang -dumpversion | cut -d. -f1)-dev"
    fi
fi

# pytest drives the system tests
if ! python3 -c 'import pytest' 2>/dev/null; then
    echo "bootstrap: installing pytest from PyPI"
    python3 -m pip install -q "pytest==8.3.3" 2>/dev/null || {
        SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
        $SUDO apt-get install -y -qq python3-pytest
    }
fi

# Musashi: the pinned sdist, hash-checked, only src/musashi unpacked.
MUS="$BUILD/deps/musashi"
if [ ! -f "$MUS/.stamp" ]; then
    line=$(grep '^machine68k==' tools/deps/pypi.txt)
    spec=${line%% *}
    sha=${line##*sha256=}
    dl="$BUILD/deps/download"
    rm -rf "$dl" "$MUS"
    mkdir -p "$dl" "$MUS"
    echo "bootstrap: fetching $spec (source distribution) from PyPI"
    python3 -m pip download -q --no-deps --no-binary :all: -d "$dl" "$spec"
    tarball=$(ls "$dl"/machine68k-*.tar.gz)
    echo "$sha  $tarball" | sha256sum -c --quiet - || { echo "bootstrap: hash mismatch for $tarball" >&2; exit 1; }
    top=$(basename "$tarball" .tar.gz)
    tar xzf "$tarball" -C "$dl" "$top/src/musashi"
    cp -r "$dl/$top/src/musashi/." "$MUS/"
    touch "$MUS/.stamp"
fi
