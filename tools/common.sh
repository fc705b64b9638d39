# shellcheck shell=bash
# tools/common.sh — shared by tools/demo.sh and tools/test.sh (source it; do not run it).
#
# Environment:
#   BUILD_DIR   build directory (default: build for tools/test.sh, build-demo
#               for tools/demo.sh; a relative path is taken from the repository
#               root)
#   BUILD_TYPE  CMAKE_BUILD_TYPE (default: the build directory's own; for a new
#               one CMake's plain Release (-O3) for tools/test.sh, and for
#               tools/demo.sh's Release at -O1, which builds mbgc in two
#               thirds of the time -O2 takes. Debug information costs half
#               again: BUILD_TYPE=RelWithDebInfo for gdb)
#   JOBS        parallel build jobs and ctest jobs (default: 2)

MBGC_ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$MBGC_ROOT" || exit 1
BUILD_TYPE=${BUILD_TYPE:-}
JOBS=${JOBS:-2}

# Debian packages the build, the tests and the demo's plot need.
MBGC_PACKAGES=(g++ cmake ninja-build pkg-config libeigen3-dev libfmt-dev libcli11-dev
               libsundials-dev libsuitesparse-dev libgtest-dev gnuplot-nox libjemalloc-dev libspectra-dev
               libopenmpi-dev openmpi-bin libtinygltf-dev nodejs chromium-headless-shell
               libminizip-dev libxml2-dev zlib1g-dev unzip zip)
# The sanitizer pass of .ci/run is built by clang, for libFuzzer (fuzz/).
MBGC_FUZZ_PACKAGES=(clang libclang-rt-14-dev)

step() { printf '\n==> %s\n' "$*"; }
die() { printf 'error: %s\n' "$*" >&2; exit 1; }

# Install the packages with apt-get, unless every one is installed already.
mbgc_install_packages() {
  local missing=() p
  for p in "${MBGC_PACKAGES[@]}"; do
    if ! dpkg -s "$p" 2>/dev/null | grep -q '^Status: install ok installed'; then
      missing+=("$p")
    fi
  done
  if [ ${#missing[@]} -eq 0 ]; then
    step "Debian packages: all installed"
    return 0
  fi
  step "Installing Debian packages (missing: ${missing[*]})"
  command -v apt-get >/dev/null || die "apt-get not found: install ${missing[*]} by hand"
  local sudo=""
  if [ "$(id -u)" -ne 0 ]; then
    command -v sudo >/dev/null || die "not root and sudo is not available: install ${missing[*]} as root"
    sudo=sudo
  fi
  $sudo apt-get update
  $sudo env DEBIAN_FRONTEND=noninteractive \
    apt-get install -y --no-install-recommends "${MBGC_PACKAGES[@]}"
}

# Configure BUILD_DIR (Ninja for a new directory). Arguments: cmake settings
# for a new directory (used when BUILD_TYPE is not set), then --, then the
# arguments for cmake every time.
mbgc_configure() {
  local fresh=() settings=()
  while [ $# -gt 0 ] && [ "$1" != -- ]; do fresh+=("$1"); shift; done
  [ $# -eq 0 ] || shift
  if [ -n "$BUILD_TYPE" ]; then
    settings=(-DCMAKE_BUILD_TYPE="$BUILD_TYPE")
  elif [ ! -f "$BUILD_DIR/CMakeCache.txt" ]; then
    settings=("${fresh[@]}")
  fi
  [ -f "$BUILD_DIR/CMakeCache.txt" ] || settings=(-G Ninja "${settings[@]}")
  step "Configuring $BUILD_DIR${settings:+ (${settings[*]})}"
  cmake -S "$MBGC_ROOT" -B "$BUILD_DIR" "${settings[@]}" "$@"
}

# Build the given targets (none: everything).
mbgc_build() {
  local targets=()
  [ $# -eq 0 ] || targets=(--target "$@")
  step "Building ${*:-everything} ($JOBS jobs)"
  cmake --build "$BUILD_DIR" --parallel "$JOBS" "${targets[@]}"
}

# The quick start's build (tools/demo.sh, tools/animate.sh): Release at -O1
# without MPI. Extra arguments go to the cmake configure step.
mbgc_configure_quick_start() {
  mbgc_configure -DCMAKE_BUILD_TYPE=Release "-DCMAKE_CXX_FLAGS_RELEASE=-O1 -DNDEBUG" -DMBGC_MPI=OFF -- "$@"
}

# Configure and build everything, warnings as errors (MBGC_WERROR). Extra
# arguments go to the cmake configure step. CMake's own Release flags (-O3),
# as a user, an IDE or a distribution builds; the gtest drivers are compiled
# at -O0 (MBGC_TESTS_O0; those that compute with Eigen themselves keep
# Release's): what they test, the compiler, the runtime and the generated
# simulators, keeps Release's.
mbgc_configure_and_build() {
  mbgc_configure -DCMAKE_BUILD_TYPE=Release -DMBGC_TESTS_O0=ON -- -DMBGC_WERROR=ON "$@"
  mbgc_build
}
