#!/usr/bin/env bash
# tools/bench_peers.sh — the planar chain (N = 2, 8, 32) in mbgc's generated
# code, a hand-written O(N) model, MuJoCo and Simbody, built and run side by
# side (bench/peers/main.cpp says how), and the rotating beam against its
# modal equations written by hand (bench/modal). Installs what the README's
# set-up installs plus libmujoco-dev and libsimbody-dev, builds a Release tree
# in build-bench/ (BUILD_DIR=... for another), and writes
# bench/peers/chain_peers.{csv,png} and bench/modal/rotating_beam.txt.
set -euo pipefail
# Before common.sh, which defaults BUILD_DIR to the test build (build/).
BUILD_DIR=${BUILD_DIR:-build-bench}
# shellcheck source=tools/common.sh
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
BUILD_TYPE=Release
# libqhull-dev: Debian's mujoco::mujoco target names /usr/include/libqhull_r, which only it provides.
MBGC_PACKAGES+=(libmujoco-dev libsimbody-dev libqhull-dev)

mbgc_install_packages
step "Configuring $BUILD_DIR (Release, bench only)"
generator=()
[ -f "$BUILD_DIR/CMakeCache.txt" ] || generator=(-G Ninja)
cmake -S "$MBGC_ROOT" -B "$BUILD_DIR" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release -DMBGC_BENCH=ON -DBUILD_TESTING=OFF
step "Building chain_peers and rotating_beam_by_hand ($JOBS jobs; chain_32's generated model takes g++ a while)"
cmake --build "$BUILD_DIR" --parallel "$JOBS" --target chain_peers rotating_beam_by_hand

out=bench/peers
step "Running $BUILD_DIR/bench/peers/chain_peers $out/chain_peers.csv"
"$BUILD_DIR/bench/peers/chain_peers" "$out/chain_peers.csv"
gnuplot -e "csv='$out/chain_peers.csv'; png='$out/chain_peers.png'" "$MBGC_ROOT/tools/plot_chain_peers.gp"
echo "wrote $out/chain_peers.{csv,png}"

step "The rotating beam: mbgc against its modal equations by hand (bench/modal)"
"$BUILD_DIR/bench/modal/rotating_beam_by_hand" "$BUILD_DIR/bench/modal/bench_rotating_beam" | tee bench/modal/rotating_beam.txt
