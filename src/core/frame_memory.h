// What a frame costs in memory, checked before any stage allocates, so a huge
// frame is refused with the figure instead of swapping for minutes.
#pragma once

#include <cstdint>

#include "meniscus/memory_budget.h"
#include "meniscus/particle_view.h"
#include "meniscus/result.h"

namespace meniscus {

// Bytes of image buffers a W x H frame holds at its peak on the CPU backend
// (frame_memory.cpp lists them). The GL backend reads the same AOVs back into
// host images, so the host figure bounds it too.
// The optional stages add their images: with the surface noise, N and the
// foam AOV; with the velocity whitening, its map.
// With several fluids (fluids > 1), each keeps its layer's images until they
// are composited, and the fluid AOV is added.
// With colorOnly (RenderSettings::colorOnly, a PNG) the other AOVs' host
// copies are not made.
std::uint64_t frameBytes(int width, int height, bool noise = false, bool whitening = false, int fluids = 1,
                         bool colorOnly = false);

// Bytes a render holds per particle at its peak, beside the frame's images:
// the caller's arrays that `particles` views, the host stages' (anisotropy,
// ray-cast field) and the CPU backend's splat bins (frame_memory.cpp lists
// them). The GL backend uploads the same arrays, so the host figure bounds it.
std::uint64_t renderBytesPerParticle(const ParticleView& particles, bool anisotropy, bool raycast, bool noise);

// Refuses a render whose particles and frame (frameBytes +
// particles x renderBytesPerParticle) need more than the job's share of the
// budget (kJobShare): "rendering 67108864 particles into a 64x48 frame needs
// about 13.4 GB; ...; select fewer particles (--select) or use a larger machine".
Status checkRenderMemory(std::uint64_t particles, std::uint64_t bytesPerParticle, int width, int height,
                         std::uint64_t frame, const MemoryBudget& budget = availableMemory());

// Refuses a frame needing more than half of the process's memory budget
// (kFrameShare, include/meniscus/memory_budget.h: the rest is left to the
// particles and the program), with both figures: "a 16384x16384 frame needs
// about 19.3 GB; this process may use 23.4 GB (physical memory), and this at
// most half of it; choose a smaller --width/--height". A budget of 0 bytes
// (unknown) accepts every frame.
Status checkFrameMemory(int width, int height, const MemoryBudget& budget = availableMemory(), bool noise = false,
                        bool whitening = false, int fluids = 1, bool colorOnly = false);

}  // namespace meniscus
