#!/usr/bin/env bash
# make demo: what a newcomer should see first.
set -euo pipefail
cd "$(dirname "$0")/.."
echo "== EPROM images"
for c in inc ssi stp; do head -4 "build/eprom/mac4-$c.size.txt"; done
echo
build/mac4sim --card inc --timestamps --script tools/demo.mac4
python3 tools/plot.py build/demo-move.png build/demo-move-a{0,1,2,3}.csv \
    --title "MAC4-INC (emulated), four axes: WAP 8000, -8000, 6000, -6000; WPV 100 WPA 10 WPD 10"
echo "== plot of the four axes' moves: build/demo-move.png"

