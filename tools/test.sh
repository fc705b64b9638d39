#!/usr/bin/env bash
# tools/test.sh — on a fresh Debian machine: install the packages, build, run every test.
#
#   tools/test.sh [cmake -D options]   # build/ (BUILD_DIR=... to use another directory)
#
# Exits nonzero if anything fails. See tools/common.sh for BUILD_DIR, BUILD_TYPE, JOBS.
set -euo pipefail
# shellcheck source=tools/common.sh
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
BUILD_DIR=${BUILD_DIR:-build}

mbgc_install_packages
mbgc_configure_and_build "$@"

step "Running the tests: ctest --test-dir $BUILD_DIR -j$JOBS --output-on-failure"
ctest --test-dir "$BUILD_DIR" -j"$JOBS" --output-on-failure --no-tests=error
