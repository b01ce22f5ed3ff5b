#!/usr/bin/env bash
# Installs Meniscus's build and test dependencies from Debian 12 packages (run as root).
set -euo pipefail
export DEBIAN_FRONTEND=noninteractive
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends \
  ca-certificates cmake make g++ pkg-config \
  libglm-dev zlib1g-dev libpng-dev libopenexr-dev libtbb-dev \
  nlohmann-json3-dev libcli11-dev libtinyxml2-dev \
  libgtest-dev libgmock-dev libbenchmark-dev >/dev/null
echo "meniscus: dependencies installed"
