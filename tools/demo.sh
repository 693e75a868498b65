#!/usr/bin/env bash
# make demo: what a newcomer should see first.
set -euo pipefail   # pipefail: mac4sim's exit status survives the awk
cd "$(dirname "$0")/.."
echo "== EPROM images"
for c in inc ssi stp; do head -4 "build/eprom/mac4-$c.size.txt"; done
echo
# the budget table's last column, "used": say which budgets are met and
# which are aims not met yet (docs/performance.md)
build/mac4sim --card inc --timestamps --script tools/demo.mac4 | awk '
    /^  / && $NF ~ /^[0-9]+%$/ { u = $NF + 0
        print $0 (u <= 100 ? "  met" : "  NOT MET yet (an aim: make bench)"); next }
    { print }'
python3 tools/pngplot.py build/demo-move.csv build/demo-move.png "MAC4-INC AXIS 1 (WIRE 0, EMULATED): WAP 8000 WPV 100 WPA 10 WPD 10"
echo "== plot of the move on the manual's axis 1 (send 0 ...): build/demo-move.png"

