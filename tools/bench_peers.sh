#!/usr/bin/env bash
# tools/bench_peers.sh — the planar chain (N = 2, 8, 32, 100) and two 3-D
# models (a binary tree of 31 rods on ball and universal joints, a chain of 32
# rods on ball joints) in mbgc's generated code, a hand-written O(N) model,
# MuJoCo, Simbody and DART, built and run side by side (bench/peers/main.cpp
# and tree_main.cpp say how), and the rotating beam and the flexible
# crank-rocker against their equations written by hand (bench/modal).
# Installs what the README's set-up installs plus libmujoco-dev,
# libsimbody-dev and libdart-dev, builds a Release tree in build-bench/
# (BUILD_DIR=... for another), and writes
# bench/peers/chain_peers.{csv,png}, bench/peers/{binary_tree,spherical_chain}_peers.csv,
# bench/peers/tree_peers.png, bench/modal/rotating_beam.txt,
# bench/modal/crank_rocker_flexible.txt and (where ../shared/bench/hand_chain
# is, or HAND_CHAIN_DIR) bench/peers/hand_chain.{csv,txt}: the generated
# 32-rod chain against that hand-written one as whole processes, under
# CMake's Release flags and with -march=native (tools/bench_hand_chain.sh).
set -euo pipefail
# Before common.sh, which defaults BUILD_DIR to the test build (build/).
BUILD_DIR=${BUILD_DIR:-build-bench}
# shellcheck source=tools/common.sh
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
BUILD_TYPE=Release
# libqhull-dev: Debian's mujoco::mujoco target names /usr/include/libqhull_r, which only it provides.
MBGC_PACKAGES+=(libmujoco-dev libsimbody-dev libqhull-dev libdart-dev)

mbgc_install_packages
step "Configuring $BUILD_DIR (Release, bench only)"
generator=()
[ -f "$BUILD_DIR/CMakeCache.txt" ] || generator=(-G Ninja)
cmake -S "$MBGC_ROOT" -B "$BUILD_DIR" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release -DMBGC_BENCH=ON -DBUILD_TESTING=OFF
step "Building chain_peers, tree_peers, rotating_beam_by_hand and crank_rocker_flexible_by_hand ($JOBS jobs; the generated models of chain_100 and the 3-D models take g++ a while)"
cmake --build "$BUILD_DIR" --parallel "$JOBS" --target chain_peers tree_peers rotating_beam_by_hand crank_rocker_flexible_by_hand mbgc mbgrt

out=bench/peers
step "Running $BUILD_DIR/bench/peers/chain_peers $out/chain_peers.csv"
"$BUILD_DIR/bench/peers/chain_peers" "$out/chain_peers.csv"
gnuplot -e "csv='$out/chain_peers.csv'; png='$out/chain_peers.png'" "$MBGC_ROOT/tools/plot_chain_peers.gp"
echo "wrote $out/chain_peers.{csv,png}"

for model in binary_tree spherical_chain; do
  step "Running $BUILD_DIR/bench/peers/tree_peers $model $out/${model}_peers.csv"
  "$BUILD_DIR/bench/peers/tree_peers" "$model" "$out/${model}_peers.csv"
done
gnuplot -e "tree='$out/binary_tree_peers.csv'; chain='$out/spherical_chain_peers.csv'; png='$out/tree_peers.png'" \
  "$MBGC_ROOT/tools/plot_tree_peers.gp"
echo "wrote $out/{binary_tree,spherical_chain}_peers.csv and $out/tree_peers.png"

step "The rotating beam: mbgc against its modal equations by hand (bench/modal)"
"$BUILD_DIR/bench/modal/rotating_beam_by_hand" "$BUILD_DIR/bench/modal/bench_rotating_beam" | tee bench/modal/rotating_beam.txt

step "The flexible crank-rocker: mbgc against its equations by hand (bench/modal)"
"$BUILD_DIR/bench/modal/crank_rocker_flexible_by_hand" "$BUILD_DIR/bench/modal/bench_crank_rocker_flexible" |
  tee bench/modal/crank_rocker_flexible.txt

step "The 32-rod chain against ../shared/bench/hand_chain, whole processes, two sets of flags (tools/bench_hand_chain.sh)"
"$MBGC_ROOT/tools/bench_hand_chain.sh" "$BUILD_DIR" "$out/hand_chain.csv" | tee "$out/hand_chain.txt"
