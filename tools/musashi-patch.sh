#!/usr/bin/env bash
# musashi-patch.sh ORIG DEST SERIES - build the patched Musashi tree DEST from
# the pristine fetched sources ORIG and the ordered series of patches of ours
# SERIES/NNNN-name.patch (harness/musashi-patches/README.md).  Every patch
# must apply exactly (no fuzz, no offset guessing beyond patch's own, no
# rejects), otherwise the build stops here.  DEST/.stamp records the
# checksums of the series; a series that changed (a patch edited, added or
# removed) rebuilds DEST from ORIG, so m68kmake's tables are regenerated.
# Never edit DEST or ORIG by hand: they are build products.
set -euo pipefail
orig=$1 dest=$2 series=$3
[ -f "$orig/.stamp" ] || { echo "musashi-patch: no fetched Musashi in $orig" >&2; exit 1; }
shopt -s nullglob
patches=("$series"/[0-9][0-9][0-9][0-9]-*.patch)
sum=$( { echo "musashi-patch v1"; for p in "${patches[@]}"; do sha256sum "$p"; done; } )
if [ -f "$dest/.stamp" ] && [ "$(cat "$dest/.stamp")" = "$sum" ]; then
    touch "$dest/.stamp"    # up to date for make: the series is the same
    exit 0
fi
tmp="$dest.tmp"
rm -rf "$tmp"
cp -r "$orig" "$tmp"
rm -f "$tmp/.stamp"
for p in "${patches[@]}"; do
    echo "musashi-patch: applying $(basename "$p")"
    if ! out=$(patch -d "$tmp" -p1 --forward --batch --fuzz=0 --no-backup-if-mismatch -r - -i "$(realpath "$p")" 2>&1); then
        echo "$out" >&2
        echo "musashi-patch: $p does not apply to the fetched Musashi ($orig): build stopped" >&2
        rm -rf "$tmp"
        exit 1
    fi
done
rm -rf "$dest"
mv "$tmp" "$dest"
echo "$sum" > "$dest/.stamp"
