#!/usr/bin/env bash
# tools/test.sh — on a fresh Debian machine: install the packages, build, run every test.
#
#   tools/test.sh [--quick] [cmake -D options]   # build/ (BUILD_DIR=... to use another directory)
#
# --quick: after a first build, the edit-test loop: build what changed, then
# run only the unit, golden and docs tests (ctest -L; tests/README.md).
# Warnings are errors here (MBGC_WERROR=ON), as in CI; a user's own build
# leaves them warnings.
# Exits nonzero if anything fails. See tools/common.sh for BUILD_DIR, BUILD_TYPE, JOBS.
set -euo pipefail
# shellcheck source=tools/common.sh
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
BUILD_DIR=${BUILD_DIR:-build}

labels=""
if [ "${1:-}" = --quick ]; then
  shift
  labels='^(unit|golden|docs)$'
fi

mbgc_install_packages
mbgc_configure_and_build "$@"

# Every test carries one of the labels that select it (tests/README.md).
unlabelled=$(ctest --test-dir "$BUILD_DIR" -N -LE '^(unit|golden|numeric|runtime|fmi|fuzz|viewer|docs)$' | grep -c '^ *Test *#' || true)
[ "$unlabelled" -eq 0 ] || {
  ctest --test-dir "$BUILD_DIR" -N -LE '^(unit|golden|numeric|runtime|fmi|fuzz|viewer|docs)$'
  die "$unlabelled tests carry none of the labels unit, golden, numeric, runtime, fmi, fuzz, viewer, docs"
}

if [ -n "$labels" ]; then
  step "Running the unit, golden and docs tests: ctest --test-dir $BUILD_DIR -j$JOBS -L '$labels'"
  ctest --test-dir "$BUILD_DIR" -j"$JOBS" -L "$labels" --output-on-failure --no-tests=error
else
  step "Running the tests: ctest --test-dir $BUILD_DIR -j$JOBS --output-on-failure"
  ctest --test-dir "$BUILD_DIR" -j"$JOBS" --output-on-failure --no-tests=error
fi
