#!/usr/bin/env bash
# Installs the Debian/Ubuntu packages the project needs, only those missing, and says which.
# Idempotent: a second run installs nothing.
set -euo pipefail

packages=(
  cmake g++ make git
  libeigen3-dev      # fixed-size linear algebra in the solver
  nlohmann-json3-dev # model files
  libtinyxml2-dev    # MJCF model files
  libcli11-dev       # the testbed command line
  libbullet-dev      # the references (its bullet-float64 variant: double precision)
  libmujoco-dev      # the mujoco reference (MuJoCo 2.2)
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
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#packages[@]} packages already installed"
  exit 0
fi

sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
echo "setup: installing ${missing[*]}"
# wait for another apt (an unattended upgrade) instead of failing on its lock
wait_lock=(-o DPkg::Lock::Timeout=300)
$sudo apt-get "${wait_lock[@]}" update -qq
DEBIAN_FRONTEND=noninteractive $sudo apt-get "${wait_lock[@]}" install -y -qq \
  --no-install-recommends "${missing[@]}" >/dev/null
echo "setup: installed ${missing[*]}"
