#!/usr/bin/env bash
# Installs the Debian 12 packages vscan needs and the buf linter. Skips what is already present, so
# a second run is quick. With "build" only what configuring and building need; with "test" only
# what the tests add (the fuzz targets' clang, the Python client's packages, npm and buf, kubectl),
# which scripts/test.sh installs while the build runs. No argument: both.
set -euo pipefail
PHASE="${1:-all}"
case "$PHASE" in all|build|test) ;; *) echo "usage: install-deps.sh [build|test]" >&2; exit 2 ;; esac

BUILD_PACKAGES=(
  # toolchain
  build-essential cmake ninja-build ccache pkg-config git
  # contract and transport
  protobuf-compiler protobuf-compiler-grpc libprotobuf-dev libgrpc-dev libgrpc++-dev grpc-proto
  # engine
  libembree-dev libtbb-dev libeigen3-dev libassimp-dev libpcl-dev libbullet-dev libbullet-extras-dev
  liburdfdom-dev libtinyxml-dev libyaml-cpp-dev libegl-dev libegl-mesa0 libgl-dev libpng-dev
  # store, logging, metrics endpoint, command line
  libsqlite3-dev sqlite3 libssl-dev openssl libspdlog-dev libfmt-dev libcivetweb-dev libcli11-dev
  # the tests' and benchmarks' C++ side, found when configuring (Open3D: a benchmark peer)
  libgtest-dev libgmock-dev libbenchmark-dev liborocos-kdl-dev libkdl-parser-dev libopen3d-dev python3
  # three.js for the web view's page (vscand --web-listen serves /usr/share/javascript/three)
  libjs-three
)
TEST_PACKAGES=(
  # libFuzzer targets (scripts/build-fuzzers.sh)
  clang libclang-rt-14-dev lld
  # Python client and its tests; venv, pip, setuptools and wheel install it as a package
  python3-grpcio python3-protobuf python3-numpy python3-open3d
  python3-venv python3-pip python3-setuptools python3-wheel
  # the web view's page in a real browser (driven by puppeteer-core from .tools/)
  chromium
)
PACKAGES=()
if [ "$PHASE" != test ]; then PACKAGES+=("${BUILD_PACKAGES[@]}"); fi
if [ "$PHASE" != build ]; then PACKAGES+=("${TEST_PACKAGES[@]}"); fi

as_root() {
  if [ "$(id -u)" -eq 0 ]; then "$@"; else sudo "$@"; fi
}

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
if [ "$PHASE" != build ]; then
  if ! command -v npm >/dev/null 2>&1; then missing+=(npm); fi
  # kubectl renders deploy/kustomize in the tests; any kubectl will do, so an existing one is kept
  # (Debian's kubernetes-client would collide with it on /usr/bin/kubectl).
  if ! command -v kubectl >/dev/null 2>&1; then missing+=(kubernetes-client); fi
fi

if [ ${#missing[@]} -gt 0 ]; then
  echo "install-deps: installing ${#missing[@]} packages: ${missing[*]}"
  as_root apt-get update -qq
  as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
else
  echo "install-deps: all Debian packages present ($PHASE)"
fi
[ "$PHASE" = build ] && exit 0

# buf (protobuf linter) and puppeteer-core (drives Debian's chromium in the web view's tests) from
# npm, kept inside the checkout. One npm call for both, since an install without a package.json
# removes what the call does not name. Never a browser download: the tests use /usr/bin/chromium.
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
NPM_TOOLS=(@bufbuild/buf@1.75.0 puppeteer-core@24.31.0)
if [ ! -x "$ROOT/.tools/node_modules/.bin/buf" ] ||
   ! grep -q '"version": "24.31.0"' "$ROOT/.tools/node_modules/puppeteer-core/package.json" 2>/dev/null; then
  echo "install-deps: installing ${NPM_TOOLS[*]} into .tools/"
  mkdir -p "$ROOT/.tools"
  (cd "$ROOT/.tools" && PUPPETEER_SKIP_DOWNLOAD=1 npm install --no-save --no-audit --no-fund --loglevel=error \
    "${NPM_TOOLS[@]}" >/dev/null)
fi
