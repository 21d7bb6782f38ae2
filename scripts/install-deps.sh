#!/usr/bin/env bash
# Install what a fresh Debian machine lacks for vprof: GHC and every Haskell library from
# Debian's packages (Hackage is not used), protoc and libprotobuf for the clients, and the
# Python protobuf runtime (libjs-chart.js: Debian's criterion writes its HTML report with
# it, for make bench). Idempotent and quiet when everything is there.
set -euo pipefail
SUDO=""
if [ "$(id -u)" != 0 ]; then SUDO="sudo"; fi
APT_PACKAGES=(
  ghc haskell-stack hspec-discover
  libghc-dimensional-dev libghc-vector-dev libghc-vector-algorithms-dev libghc-linear-dev
  libghc-hmatrix-dev libghc-optparse-applicative-dev libghc-aeson-dev libghc-scientific-dev
  libghc-cassava-dev libghc-network-dev libghc-async-dev libghc-criterion-dev
  libghc-chart-dev libghc-chart-cairo-dev libghc-lens-dev libghc-colour-dev
  libghc-data-default-class-dev libghc-hspec-dev libghc-quickcheck2-dev libghc-protobuf-dev
  libghc-cereal-dev libghc-unordered-containers-dev libghc-temporary-dev
  libghc-double-conversion-dev libghc-yaml-dev libghc-libyaml-dev libghc-attoparsec-dev libghc-conduit-dev
  libghc-resourcet-dev libghc-xml-conduit-dev libghc-file-embed-dev
  protobuf-compiler libprotobuf-dev pkg-config g++ make python3
  libjs-chart.js
)
missing=()
for p in "${APT_PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "install-deps: installing ${missing[*]}"
  $SUDO env DEBIAN_FRONTEND=noninteractive apt-get update -qq
  $SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${missing[@]}" >/dev/null
fi
# The Python protobuf runtime, matching protoc 3.21 (generated code needs >= 3.20).
if ! python3 -c 'import google.protobuf' 2>/dev/null; then
  echo "install-deps: installing the Python protobuf runtime"
  python3 -m pip install -q "protobuf==4.21.12" 2>/dev/null \
    || $SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq python3-protobuf >/dev/null
fi
python3 -c 'import google.protobuf' || { echo "install-deps: no Python protobuf runtime" >&2; exit 1; }
