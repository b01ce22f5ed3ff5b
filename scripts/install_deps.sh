#!/usr/bin/env bash
# Installs Meniscus's build and test dependencies from Debian 12 packages (run as root).
# The scripts build with Ninja (ninja-build) when it is there, Make otherwise.
# The GL backend needs libepoxy + EGL; Mesa's llvmpipe (libgl1-mesa-dri,
# libegl-mesa0) gives CI a headless GL 4.5 context without a GPU, and
# glslang-tools checks every shader file. The viewer's window needs GLFW
# (libglfw3-dev, its context through Mesa's GLX: libglx-mesa0) and an X
# display; CI has none, so its tests run inside a virtual X server (xvfb-run
# from xvfb, which needs xauth); its panels are Dear ImGui (libimgui-dev,
# whose static library has the GLFW and OpenGL 3 backends). The fuzzers (scripts/fuzz.sh) need clang and
# its sanitizer and libFuzzer run-times (libclang-rt-14-dev, which clang-14
# only recommends). Movies (-o out.mp4) are encoded through FFmpeg's libraries
# (libavcodec-dev, libavformat-dev, libswscale-dev; Debian's libavcodec brings
# the libx264 H.264 encoder). VTK XML files (.vtu/.vtp) compressed with VTK's
# LZ4 or LZMA compressor are read through liblz4 and liblzma (liblz4-dev,
# liblzma-dev; zlib-compressed ones through zlib). H5Part and PySPH .hdf5
# files are read through HDF5's C library (libhdf5-dev), PySPH's .npz through
# libzip (libzip-dev). The Python module is built with pybind11 (pybind11-dev,
# python3-dev) and takes numpy arrays (python3-numpy). Sort-last rendering and
# frame-parallel sequences over several processes use MPI (libopenmpi-dev;
# openmpi-bin's mpirun runs the MPI tests). Scene geometry (meshes in OBJ,
# PLY, STL, glTF and more) is read through Assimp (libassimp-dev).
set -euo pipefail
export DEBIAN_FRONTEND=noninteractive
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends \
  ca-certificates cmake make ninja-build g++ pkg-config \
  libglm-dev zlib1g-dev libpng-dev libjpeg-dev libopenexr-dev libtbb-dev \
  nlohmann-json3-dev libcli11-dev libtinyxml2-dev liblz4-dev liblzma-dev \
  libgtest-dev libgmock-dev libbenchmark-dev \
  libepoxy-dev libegl-dev libgl1-mesa-dri libegl-mesa0 glslang-tools \
  libglfw3-dev libglx-mesa0 xvfb xauth libimgui-dev \
  libavcodec-dev libavformat-dev libswscale-dev libavutil-dev \
  libhdf5-dev libzip-dev pybind11-dev python3-dev python3-numpy \
  libopenmpi-dev openmpi-bin libassimp-dev \
  clang libclang-rt-14-dev >/dev/null
echo "meniscus: dependencies installed"
