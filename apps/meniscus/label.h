// Captions drawn into an image (apps only): a 5x7 bitmap font.
#pragma once

#include <array>
#include <string>

#include "meniscus/types.h"

namespace meniscus::app {

// Draws `text` with its top-left corner at pixel (x, y), each font pixel
// `scale` x `scale` image pixels, in linear RGBA `color`. Characters without a
// glyph are left blank; lower case is drawn as upper case.
void drawLabel(Image<glm::vec4>& image, int x, int y, const std::string& text, int scale, const glm::vec4& color);
// Width in pixels of `text` at `scale`.
int labelWidth(const std::string& text, int scale);

}  // namespace meniscus::app
