#!/usr/bin/env bash
# Installs every build and test dependency of ispars from Debian 12 packages, in one apt-get
# line. Safe to run any number of times: when everything is present it changes nothing.
set -euo pipefail

PACKAGES=(
  build-essential cmake ninja-build pkg-config
  libeigen3-dev libfcl-dev libassimp-dev libembree-dev libpng-dev libspdlog-dev libfmt-dev
  libfastrtps-dev libfastcdr-dev fastddsgen fastdds-tools default-jre-headless
  cyclonedds-dev cyclonedds-tools
  libcli11-dev libnanoflann-dev nlohmann-json3-dev libyaml-cpp-dev
  libgtest-dev libgmock-dev libbenchmark-dev libompl-dev
  coinor-libclp-dev zlib1g-dev
  libsystemd-dev libcpp-httplib-dev libboost-dev
  gnuplot-nox
  nodejs chromium
  nginx-core openssl
  gdb python3 clang-format
  python3-dev pybind11-dev python3-numpy python3-pytest python3-venv python3-pip python3-networkx python3-scipy
  iproute2 nftables
)

missing=()
for package in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$package")
  fi
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#PACKAGES[@]} packages already installed"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then
    SUDO="sudo"
  else
    echo "install-deps: missing packages (${missing[*]}) and not root; run as root or install sudo" >&2
    exit 1
  fi
fi
echo "install-deps: installing ${missing[*]}"
# nginx is for the tests, which start their own on loopback: its package must not start the
# system's nginx (listening on every address, port 80). A policy-rc.d saying 101 keeps
# invoke-rc.d from starting services during this install; one already there is left as it is.
policy=/usr/sbin/policy-rc.d
own_policy=""
if [ ! -e "$policy" ]; then
  printf '#!/bin/sh\nexit 101\n' | $SUDO tee "$policy" >/dev/null
  $SUDO chmod 755 "$policy"
  own_policy=1
fi
remove_policy() { if [ -n "$own_policy" ]; then $SUDO rm -f "$policy"; fi; }
trap remove_policy EXIT
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${PACKAGES[@]}"
