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
python3 tools/plot.py build/demo-move.png build/demo-move-a{0,1,2,3}.csv \
    --title "MAC4-INC (emulated), four axes: WAP 8000, -8000, 6000, -6000; WPV 100 WPA 10 WPD 10"
echo "== plot of the four axes' moves: build/demo-move.png"

