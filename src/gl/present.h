// The viewer's present pass: draws a colour image of the backend into the
// default framebuffer of the current context (a gl::Window's), sRGB-encoded as
// the PNG writer does (shaders/present.frag).
#pragma once

#include "core/backend.h"
#include "gl/gpu_image.h"
#include "gl/objects.h"
#include "meniscus/result.h"

namespace meniscus::gl {

class Presenter {
public:
    // Compiles the program; an error carries the driver's log.
    static Result<Presenter> create();

    // Fills `framebuffer` (0: the default one; target.width x target.height
    // pixels) with `color` (W x H x 4
    // linear RGBA, row 0 = top), the image's top-left pixel target.left
    // pixels right of the framebuffer's top-left; what the image does not
    // cover is black. One pixel per pixel, no scaling: the viewer renders at
    // the size of the area it shows the picture in. Does not swap buffers.
    void draw(const GpuImage& color, const PresentTarget& target, GLuint framebuffer);

private:
    Program program_;
    VertexArray vertexArray_;  // core profile: a draw needs a bound VAO, even with no attributes
    Buffer empty_;             // bound instead of an image that is not RGBA
};

}  // namespace meniscus::gl
