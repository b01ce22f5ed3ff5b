// The viewer's present pass (see present.h): a fullscreen triangle whose
// fragment shader reads the colour buffer directly, so there is no texture
// copy and the flip from our top-row-first images to GL's bottom-row-first
// framebuffer is one subtraction.
#include "gl/present.h"

#include "gl/shaders.h"

namespace meniscus::gl {

Result<Presenter> Presenter::create() {
    Presenter p;
    auto program = loadRenderProgram("present.vert", "present.frag");
    if (!program) return program.error();
    p.program_ = std::move(*program);
    p.vertexArray_ = makeVertexArray();
    p.empty_.reserve(16);
    return p;
}

void Presenter::draw(const GpuImage& color, const PresentTarget& target, GLuint framebuffer) {
    const bool rgba = color.channels == 4 && color.buffer.id() != 0;
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
    glViewport(0, 0, target.width, target.height);
    glDisable(GL_FRAMEBUFFER_SRGB);  // the shader encodes; the framebuffer must store the levels as they are
    glDisable(GL_BLEND);
    glDisable(GL_DEPTH_TEST);
    // The stages' last writes to the colour buffer reach the fragment shader.
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    glUseProgram(program_.id());
    glUniform4i(0, rgba ? color.width : 0, rgba ? color.height : 0, target.height, target.left);
    glUniform1i(1, target.srgb ? 1 : 0);
    if (rgba) color.bind(0);
    else glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, empty_.id());
    glBindVertexArray(vertexArray_.id());
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
    glUseProgram(0);
}

}  // namespace meniscus::gl
