#!/usr/bin/env bash
# work_precision_all.sh — the work-precision figures (tools/work_precision.sh)
# where the whole menu of integrators applies: the examples that are ODEs,
# and the mechanisms in joint coordinates (an ODE; their multipliers' DAE
# has IDA alone, and its figure beside). Then the table of the cheapest
# method per figure at a relative error of 1e-3 and 1e-6
# (tools/cheapest_method.py), written to bench/cheapest_method.md. The wall
# times of one sweep are compared with each other only.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
wp() {  # NAME DIR [simulator options]
  local name="$1" dir="$2"
  shift 2
  WP_DIR="$here/examples/$dir" "$here/tools/work_precision.sh" "$name" --quiet "$@"
}
figures=()
for name in dc_motor pendulum_mtf quarter_car torque_free_body two_track; do
  wp "$name" "$name"
  figures+=("$here/examples/$name/work_precision.csv")
done
wp chain_8_coordinates chain
figures+=("$here/examples/chain/work_precision_chain_8_coordinates.csv")
for name in pendulum andrews crank_rocker double_pendulum_3d rotating_beam crank_rocker_flexible; do
  wp "${name}_coordinates" "$name"
  figures+=("$here/examples/$name/work_precision_${name}_coordinates.csv")
done
# (the first 2 s: past them the buckling coupler's reference gives up, examples/flexible_double_pendulum)
wp flexible_double_pendulum_coordinates flexible_double_pendulum --t-end 2
figures+=("$here/examples/flexible_double_pendulum/work_precision_flexible_double_pendulum_coordinates.csv")
python3 "$here/tools/cheapest_method.py" "${figures[@]}" > "$here/bench/cheapest_method.md"
cat "$here/bench/cheapest_method.md"
