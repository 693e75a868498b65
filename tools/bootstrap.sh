#!/usr/bin/env bash
# bootstrap.sh - install what the build needs and fetch Musashi into build/.
# Idempotent: does nothing when everything is there.  Called by `make deps`,
# which `make`, `make test` and `make demo` depend on.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${BUILD:-build}
CROSS=${CROSS:-m68k-linux-gnu-}

# Debian packages: every line of tools/deps/apt.txt that is not installed.
need=()
while read -r pkg; do
    pkg=${pkg%%#*}; pkg=${pkg//[[:space:]]/}
    [ -n "$pkg" ] || continue
    dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q 'install ok installed' || need+=("$pkg")
done < tools/deps/apt.txt
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

# Python packages: every pin of tools/deps/python.txt not installed at that version.
pyneed=()
while read -r spec; do
    spec=${spec%%#*}; spec=${spec//[[:space:]]/}
    [ -n "$spec" ] || continue
    name=${spec%%==*}; ver=${spec##*==}
    have=$(python3 -c 'import sys, importlib.metadata as m
try: print(m.version(sys.argv[1]))
except m.PackageNotFoundError: print("")' "$name")
    [ "$have" = "$ver" ] || pyneed+=("$spec")
done < tools/deps/python.txt
if [ ${#pyneed[@]} -gt 0 ]; then
    echo "bootstrap: installing from PyPI: ${pyneed[*]}"
    python3 -m pip install -q "${pyneed[@]}"
fi

# Musashi: the pinned sdist, hash-checked, only src/musashi unpacked into
# musashi-orig (pristine, never edited); build/deps/musashi is made from it
# by our patch series (tools/musashi-patch.sh, harness/musashi-patches/).
MUS="$BUILD/deps/musashi-orig"
if [ ! -f "$MUS/.stamp" ]; then
    line=$(grep '^machine68k==' tools/deps/pypi.txt)
    spec=${line%% *}
    sha=${line##*sha256=}
    dl="$BUILD/deps/download"
    rm -rf "$dl" "$MUS"
    mkdir -p "$dl" "$MUS"
    # the checked sdist is kept in a cache outside the tree, shared by clones;
    # --no-binary names machine68k alone: with :all: pip builds the sdist's
    # build requirements (Cython) from source to read its metadata, minutes
    cache=${MAC4_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/mac4}
    cached="$cache/$sha.tar.gz"
    if [ -f "$cached" ] && echo "$sha  $cached" | sha256sum -c --quiet - 2>/dev/null; then
        cp "$cached" "$dl/${spec/==/-}.tar.gz"
    else
        echo "bootstrap: fetching $spec (source distribution) from PyPI"
        python3 -m pip download -q --no-deps --no-binary "${spec%%==*}" -d "$dl" "$spec"
    fi
    tarball=$(ls "$dl"/machine68k-*.tar.gz)
    echo "$sha  $tarball" | sha256sum -c --quiet - || { echo "bootstrap: hash mismatch for $tarball" >&2; exit 1; }
    mkdir -p "$cache" && cp "$tarball" "$cached" 2>/dev/null || true
    top=$(basename "$tarball" .tar.gz)
    tar xzf "$tarball" -C "$dl" "$top/src/musashi"
    cp -r "$dl/$top/src/musashi/." "$MUS/"
    touch "$MUS/.stamp"
fi

# Our patches to Musashi, applied in order and checked; a changed series
# rebuilds the patched tree.
tools/musashi-patch.sh "$MUS" "$BUILD/deps/musashi" harness/musashi-patches
