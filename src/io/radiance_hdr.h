// The Radiance RGBE (.hdr) decoder of the environment map reader
// (src/io/radiance_hdr.cpp; docs/pipeline.md#environment-map). Internal to
// src/io: readEnvironmentMap calls it with the file's bytes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "meniscus/environment.h"

namespace meniscus::io {

// Decodes a whole Radiance picture held in `bytes` (`size` of them); `name`
// is the file the errors name. Bounded like the OpenEXR path (the image's
// size by kMaxEnvironmentWidth/Height, nothing allocated for the pixels
// before the bytes were seen to hold every scanline); never throws.
Result<EnvironmentImage> decodeRadianceHdr(const std::uint8_t* bytes, std::size_t size, const std::string& name);

}  // namespace meniscus::io
