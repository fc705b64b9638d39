#!/usr/bin/env bash
# tools/ops_growth.sh — how the generated dynamics grow with the model, from
# mbgc --stats (operation counts, not timings): the planar chain of
# examples/chain at N = 8, 16, 32, 64 rods and the spatial binary tree of
# tests/numeric/models/binary_tree.mbg at N = 7, 15, 31, 63 bodies, each with
# lagrange multipliers and in joint coordinates. Prints CSV to stdout:
#
#   model,constraints,n,method,ops,expr_ops,solve_ops,solve_sizes,lines,file_bytes,ops_ratio,lines_ratio,bytes_ratio
#
# method is derivative_and_power or derivative (an ODE) or residual (a DAE); ops = expr_ops (its
# expressions, as written) + solve_ops (mbgrt::solve_linear's arithmetic,
# (4n^3 + 9n^2 - 7n)/6 per n x n solve; solve_sizes lists the n); lines are the
# method's, file_bytes the whole generated file's. The ratios are to the
# previous size of the same model and strategy (about 2 when the work is
# linear in the bodies, 4 when quadratic, 8 when cubic).
#
# In joint coordinates the code is outlined at every size (--outline always:
# with mbgc's default, auto, the small models are written inline and the
# large ones outlined, and the ratio across the switch compares two forms).
#
#   tools/ops_growth.sh [build dir, default build]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$root/build}"
mbgc="$build/compiler/mbgc"
[ -x "$mbgc" ] || { echo "no $mbgc: build it first (cmake --build $build --target mbgc)" >&2; exit 1; }

ratio() {  # new old -> new/old with 3 decimals, empty without an old value
  [ -n "$2" ] && awk -v a="$1" -v b="$2" 'BEGIN { printf "%.3f", a / b }' || true
}

echo "model,constraints,n,method,ops,expr_ops,solve_ops,solve_sizes,lines,file_bytes,ops_ratio,lines_ratio,bytes_ratio"
series() {  # model-file label strategy sizes...
  local file=$1 label=$2 strategy=$3
  shift 3
  local prev_ops="" prev_lines="" prev_bytes="" n csv row method ops lines solve_ops sizes bytes expr
  for n in "$@"; do
    local form=()
    [ "$strategy" = coordinates ] && form=(--outline always)
    csv=$("$mbgc" "$file" --set N="$n" --constraints "$strategy" "${form[@]}" --stats --stats-format csv)
    # function,lines,bytes,ops,add,mul,div,neg,call,compare,solve_sizes,solve_ops
    # (derivative_and_power where the model has an energy balance: derivative() calls it)
    row=$(grep -E '^derivative_and_power,' <<<"$csv" || grep -E '^(derivative|residual),' <<<"$csv")
    IFS=, read -r method lines _ ops _ _ _ _ _ _ sizes solve_ops <<<"$row"
    bytes=$(grep '^file,' <<<"$csv" | cut -d, -f3)
    expr=$((ops - solve_ops))
    echo "$label,$strategy,$n,$method,$ops,$expr,$solve_ops,$sizes,$lines,$bytes,$(ratio "$ops" "$prev_ops"),$(ratio "$lines" "$prev_lines"),$(ratio "$bytes" "$prev_bytes")"
    prev_ops=$ops prev_lines=$lines prev_bytes=$bytes
  done
}

for strategy in lagrange coordinates; do
  series "$root/examples/chain/chain.mbg" chain "$strategy" 8 16 32 64
done
for strategy in lagrange coordinates; do
  series "$root/tests/numeric/models/binary_tree.mbg" binary_tree "$strategy" 7 15 31 63
done
