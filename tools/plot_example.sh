#!/usr/bin/env bash
# plot_example.sh NAME [simulator options...] — run examples/NAME's simulator
# (built by the README's set-up) and plot every output against time into
# examples/NAME/NAME.png with gnuplot.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
name="${1:?usage: tools/plot_example.sh NAME [simulator options]}"
shift
build="${BUILD_DIR:-$here/build}"
sim="$build/examples/$name"
[ -x "$sim" ] || { echo "no simulator $sim: build first (tools/demo.sh or cmake --build $build)" >&2; exit 1; }
mkdir -p "$build/plots"
csv="$build/plots/$name.csv"
"$sim" --quiet "$@" --out "$csv"
gnuplot -e "csv='$csv'; png='$here/examples/$name/$name.png'; name='$name'" "$here/tools/plot_csv.gp"
echo "wrote examples/$name/$name.png from $csv"
