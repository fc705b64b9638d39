#!/usr/bin/env bash
# work_precision.sh NAME [simulator options...] — the speed/accuracy trade of
# examples/NAME (built by the README's set-up): runs its simulator with
# --work-precision (every integrator that fits, rtol 1e-3 ... 1e-10, rk4 steps
# interval/1 ... interval/128, errors against a reference at rtol 1e-12) and
# writes examples/NAME/work_precision.csv and a log-log plot of error against
# wall time, examples/NAME/work_precision.png. WP_DIR=examples/chain puts a
# simulator whose name is not its folder's (chain_8) there as
# work_precision_chain_8.{csv,png}.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
name="${1:?usage: tools/work_precision.sh NAME [simulator options]}"
shift
build="${BUILD_DIR:-$here/build}"
sim="$build/examples/$name"
[ -x "$sim" ] || { echo "no simulator $sim: build first (tools/demo.sh or cmake --build $build)" >&2; exit 1; }
dir="${WP_DIR:-$here/examples/$name}"
stem=work_precision
[ "$(basename "$dir")" = "$name" ] || stem="work_precision_$name"
csv="$dir/$stem.csv"
"$sim" --work-precision "$@" --out "$csv"
solvers=$(tail -n +2 "$csv" | cut -d, -f1 | grep -v reference | uniq | tr '\n' ' ')
gnuplot -e "csv='$csv'; png='$dir/$stem.png'; name='$name'; solvers='$solvers'" "$here/tools/plot_work_precision.gp"
echo "wrote $dir/$stem.{csv,png}"
