// What a frame costs in memory, checked before any stage allocates, so a huge
// frame is refused with the figure instead of swapping for minutes.
#pragma once

#include <cstdint>

#include "meniscus/result.h"

namespace meniscus {

// Bytes of image buffers a W x H frame holds at its peak on the CPU backend
// (frame_memory.cpp lists them). The GL backend reads the same AOVs back into
// host images, so the host figure bounds it too.
// The optional stages add their images: with the surface noise, N and the
// foam AOV; with the velocity whitening, its map.
// With several fluids (fluids > 1), each keeps its layer's images until they
// are composited, and the fluid AOV is added.
std::uint64_t frameBytes(int width, int height, bool noise = false, bool whitening = false, int fluids = 1);

// Physical memory of this machine in bytes (0 when unknown).
std::uint64_t physicalMemoryBytes();

// Refuses a frame needing more than half of `physicalBytes` (the rest is left
// to the particles, the system and other programs), with both figures:
// "a 16384x16384 frame needs about 19.3 GB; this machine has 23.4 GB, ...".
// physicalBytes 0 (unknown) accepts every frame.
Status checkFrameMemory(int width, int height, std::uint64_t physicalBytes = physicalMemoryBytes(),
                        bool noise = false, bool whitening = false, int fluids = 1);

}  // namespace meniscus
