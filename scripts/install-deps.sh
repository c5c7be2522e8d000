#!/usr/bin/env bash
# Installs mrr's build and run dependencies on Debian 12 (all from Debian's own packages;
# python3-matplotlib and python3-jinja2 make the `--report` pages and charts, run with
# /usr/bin/python3; fonts-dejavu-core labels scripts/make-doc-images.sh's pictures, and
# matplotlib's data package needs it too); python3-openimageio and python3-numpy run
# examples/foreign_renderer.py (docs/validate-your-own.md, tested by tests/cli/byo_test.cpp);
# pybind11-dev and python3-dev build the Python module mrr (python/, docs/python.md).
# `install-deps.sh test` adds what only the tests need: Chromium (the compare report's
# browser test), Selenium with chromedriver (`mrr explore`'s browser test), clang with its
# fuzzer runtime (scripts/fuzz.sh), and pytest, nbconvert and the IPython kernel (the Python
# module's tests and the notebook docs/learn-mrr.ipynb, executed).
# Safe to run repeatedly; skips apt when every package is already installed.
set -euo pipefail
pkgs=(
  build-essential cmake ninja-build pkg-config
  libembree-dev libtbb-dev libopenimageio-dev openimageio-tools libopencv-core-dev
  libglm-dev libtinygltf-dev libstb-dev nlohmann-json3-dev libcli11-dev
  libmeshoptimizer-dev libdraco-dev libcpp-httplib-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libegl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri
  python3-matplotlib python3-jinja2 fonts-dejavu-core
  python3-openimageio python3-numpy
  pybind11-dev python3-dev
)
if [ "${1:-}" = test ]; then
  pkgs+=(chromium clang libclang-rt-14-dev python3-selenium chromium-driver)
  pkgs+=(python3-pytest jupyter-nbconvert python3-nbclient python3-ipykernel)
fi
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#pkgs[@]} packages present" >&2
  exit 0
fi
echo "install-deps: installing ${missing[*]}" >&2
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "install-deps: done" >&2
