#!/usr/bin/env bash
# Installs the Debian packages foldfill needs (when missing), the npm packages
# of package-lock.json (three.js for `foldfill view`, puppeteer-core for the
# browser tests, which drive Debian's Chromium), and builds it in Release into
# build/. Idempotent; quick when everything is already there.
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(g++ cmake make libcgal-dev libeigen3-dev libgmp-dev libmpfr-dev libboost-dev
          libpng-dev libcli11-dev nlohmann-json3-dev libfmt-dev libgtest-dev libbenchmark-dev
          libsuitesparse-dev libopenblas0-serial chromium
          libcpp-httplib-dev                                     # the server of `serve`
          pybind11-dev python3-dev python3-numpy python3-pytest  # the Python module and its tests
          parallel                                               # the batch recipe's test
          blender xvfb xauth)                                    # the Blender add-on's tests
# Node.js and npm from Debian, unless a node and an npm are there already
# (another distribution's nodejs package may bring npm itself).
if ! command -v node >/dev/null || ! command -v npm >/dev/null; then
  packages+=(nodejs npm)
fi
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  sudo_cmd=()
  [ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
  "${sudo_cmd[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

# The npm packages, again whenever package-lock.json changed. Puppeteer never
# downloads a browser: the tests use Debian's Chromium.
lock_sum=$(sha256sum package-lock.json | cut -d' ' -f1)
if [ "$(cat node_modules/.foldfill-lock-sum 2>/dev/null)" != "$lock_sum" ]; then
  echo "setup: npm ci"
  PUPPETEER_SKIP_DOWNLOAD=1 npm ci --no-audit --no-fund --loglevel=error
  echo "$lock_sum" > node_modules/.foldfill-lock-sum
fi

build_dir=${FOLDFILL_BUILD_DIR:-build}
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release ${FOLDFILL_CMAKE_ARGS:-} >/dev/null
cmake --build "$build_dir" -j "$(nproc)"
