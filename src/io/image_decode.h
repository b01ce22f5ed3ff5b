// Colour images read for scene geometry's textures (internal to src/io): PNG
// through libpng, JPEG through libjpeg, decoded to linear RGB floats. The
// image's size is read from its header and checked against the limits before
// any pixel is allocated; damaged data is an error naming the image.
#pragma once

#include <string>

#include "meniscus/geometry.h"
#include "meniscus/result.h"
#include "meniscus/types.h"

namespace meniscus::io {

// Decodes a PNG or a JPEG (told apart by their signatures, whatever the name
// says) into a texture: 8-bit sRGB samples (a 16-bit PNG reduced to 8 bits,
// grey made RGB, alpha dropped) turned linear (IEC 61966-2-1). `name` names
// the image in errors. Bounded by geometry_limits::kMaxTextureSidePx and
// kMaxTexturePixels.
Result<GeometryTexture> decodeTexture(ByteView data, const std::string& name);

}  // namespace meniscus::io
