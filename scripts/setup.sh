#!/usr/bin/env bash
# Installs the Debian/Ubuntu packages the project needs, only those missing, and says which;
# then the jolt engine's npm package, at the version reference/jolt/package-lock.json pins, into
# reference/jolt/node_modules (the project's own folder, never globally). Idempotent: a second run
# installs nothing.
set -euo pipefail

packages=(
  cmake g++ make git
  libeigen3-dev      # fixed-size linear algebra in the solver
  nlohmann-json3-dev # model files
  libtinyxml2-dev    # MJCF model files
  libcli11-dev       # the testbed command line
  libbullet-dev      # the references (its bullet-float64 variant: double precision)
  libmujoco-dev      # the mujoco reference (MuJoCo 2.2)
  libmujoco-samples  # MuJoCo 2.2.2's published model files: the main job's humanoid.xml
  libode-dev         # the ode reference (ODE 0.16, double precision)
  pkg-config         # finds bullet-float64
  libgtest-dev       # tests
  libbenchmark-dev   # benchmarks/ and the performance gate
  python3-matplotlib # scripts/plot.py: plots and REPORT.md
  libglfw3-dev libimgui-dev libstb-dev # viewer/: window, panel, PNG screenshots
  libgl-dev libopengl-dev # OpenGL 3.3 headers, GLVND libOpenGL (CMake: OpenGL::OpenGL)
  libgl1-mesa-dri libglx-mesa0 # Mesa: its software renderer where there is no GPU
  xvfb xauth         # the viewer's headless tests (xvfb-run)
  clang-14 libclang-rt-14-dev # the clang build and the loader's fuzzer (scripts/fuzz.sh)
  doxygen            # the API reference (scripts/api_docs.sh)
  nodejs             # the jolt engine's driver (reference/jolt/server.mjs)
  pybind11-dev python3-dev python3-numpy python3-pytest # the Python package (python/), its tests
)
# npm installs the jolt engine's package: Debian's, unless a Node.js that brings its own is there
if ! command -v npm >/dev/null; then packages+=(npm); fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#packages[@]} packages already installed"
else
  sudo=""
  if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
  echo "setup: installing ${missing[*]}"
  # wait for another apt (an unattended upgrade) instead of failing on its lock
  wait_lock=(-o DPkg::Lock::Timeout=300)
  $sudo apt-get "${wait_lock[@]}" update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get "${wait_lock[@]}" install -y -qq \
    --no-install-recommends "${missing[@]}" >/dev/null
  echo "setup: installed ${missing[*]}"
fi

# the jolt engine's package, as the lock file pins it (its version and checksum)
jolt=reference/jolt
cd "$(dirname "$0")/.."
pinned=$(sed -n 's/^[[:space:]]*"jolt-physics": "\(.*\)"/\1/p' "$jolt/package.json")
have=""
if [ -f "$jolt/node_modules/jolt-physics/package.json" ]; then
  have=$(sed -n 's/^[[:space:]]*"version": "\(.*\)",*/\1/p' \
    "$jolt/node_modules/jolt-physics/package.json" | head -n 1)
fi
if [ "$have" = "$pinned" ]; then
  echo "setup: jolt-physics $pinned already installed"
else
  echo "setup: installing jolt-physics $pinned into $jolt/node_modules"
  # without it (no registry) the project still builds and runs: the jolt engine reads as not built
  log=${TMPDIR:-/tmp}/puppet-npm-ci.log
  if npm ci --prefix "$jolt" --no-audit --no-fund --loglevel=error >/dev/null 2>"$log"; then
    echo "setup: installed jolt-physics $pinned"
  else
    echo "setup: could not install jolt-physics $pinned (npm ci failed, $log): the jolt engine is left out"
  fi
fi
