#!/usr/bin/env bash
# make demo: what a newcomer should see first.
set -euo pipefail
cd "$(dirname "$0")/.."
echo "== EPROM images"
for c in inc ssi stp; do head -4 "build/eprom/mac4-$c.size.txt"; done
echo
build/mac4sim --card inc --timestamps --script tools/demo.mac4
python3 tools/pngplot.py build/demo-move.csv build/demo-move.png "MAC4-INC AXIS 1 (EMULATED): WAP 8000 WPV 100 WPA 10 WPD 10"
echo "== plot of the move on axis 1: build/demo-move.png"

