#!/bin/bash
# The viewer through a mouse cut, as a person makes it (#36: no gap over twice the median in the
# frames or the physics updates while the blade splits elements): X events from xdotool on a
# virtual display (Xvfb, Mesa's software OpenGL on the CPU, beside the physics), the default scene,
# a 240-pixel drag across the skin right of the panels, 300 steps paced to real time; once with
# each thread count, `xcut view --timing-csv` appending its row (tools/viewer/viewer_timing.h).
#
#   bash tools/bench/viewer_cut.sh [CSV] [REPEATS]   # default results/bench_viewer_cut.csv, 1
#
# A run writes to a file of its own when the CSV already exists (a record is never appended to).
set -euo pipefail
here=$(cd "$(dirname "$0")/../.." && pwd)
csv=${1:-$here/results/bench_viewer_cut.csv}
repeats=${2:-1}
xcut=$here/build/xcut
for tool in xvfb-run xdotool; do
  command -v $tool > /dev/null || { echo "error: $tool is missing (tools/install-deps.sh installs it)" >&2; exit 2; }
done
[ -x "$xcut" ] || { echo "error: $xcut is missing: build first" >&2; exit 2; }
if [ -e "$csv" ]; then
  csv=${csv%.csv}_$(date +%Y%m%d%H%M%S).csv
  echo "the record exists: this run writes $csv"
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cat > "$work/drag.sh" <<DRAG
"$xcut" view "$here/scenes/skin_slab.json" -j \$1 --steps 300 --set 'tools=[]' --timing-csv "$csv" \
  --screenshot "$work/cut.png" > "$work/view.log" 2>&1 & pid=\$!
wid=\$(xdotool search --sync --onlyvisible --name 'xcut view')
sleep 0.5
xdotool mousemove --window \$wid 760 500 mousedown 1
for i in \$(seq 1 30); do xdotool mousemove --window \$wid \$((760 - i / 2)) \$((500 - 8 * i)); sleep 0.02; done
xdotool mouseup 1
wait \$pid
DRAG
for r in $(seq 1 "$repeats"); do
  for threads in 2 1; do
    xvfb-run -a -s '-screen 0 1600x1200x24' bash "$work/drag.sh" $threads
    grep -E "^timing|elements split" "$work/view.log" | sed "s/^/-j $threads: /"
  done
done
echo "csv: $csv"
