#!/usr/bin/env bash
# make demo: what a newcomer should see first.
set -euo pipefail
cd "$(dirname "$0")/.."
echo "== EPROM images"
for c in inc ssi stp; do head -4 "build/eprom/mac4-$c.size.txt"; done
echo
exec build/mac4sim --card inc --timestamps --script tools/demo.mac4
