// GL raycast stage (docs/pipeline.md#ray-cast-surface): shaders/raycast.comp
// over the field's grid (core/sph_field.h), uploaded per call.
#include "gl/raycast.h"
#include "gl/gl_backend.h"

#include <algorithm>

#include "gl/shaders.h"

namespace meniscus::gl {

Result<Raycast> Raycast::create() {
    Raycast r;
    auto p = loadComputeProgram("raycast.comp");
    if (!p) return p.error();
    r.program_ = std::move(*p);
    return r;
}

void Raycast::run(const FrameParams& frame, const SphField* field, const RaycastParams& params, const GpuImage& start,
                  const GpuImage* sceneDepth, GpuImage& depth, GpuImage& normals) {
    const int W = frame.size.x, H = frame.size.y;
    depth.resize(W, H, 1);
    normals.resize(W, H, 3);
    if (W <= 0 || H <= 0) return;
    if (!field || field->grid.points().empty() || !start.sized(W, H, 1)) {  // nothing to cast: no fluid
        depth.buffer.fill(depth.bytes(), 0x7f800000u);
        normals.buffer.fill(normals.bytes(), 0u);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
        return;
    }
    const std::vector<glm::vec3>& pts = field->grid.points();
    packed_.resize(pts.size());
    for (std::size_t i = 0; i < pts.size(); ++i) packed_[i] = glm::vec4(pts[i], 0.0f);
    points_.upload(packed_.data(), GLsizeiptr(packed_.size() * sizeof(glm::vec4)));
    const std::vector<std::uint32_t>& st = field->grid.starts();
    starts_.upload(st.data(), GLsizeiptr(st.size() * sizeof(std::uint32_t)));
    quiet_.upload(field->quiet.data(), GLsizeiptr(field->quiet.size() * sizeof(std::uint32_t)));
    const bool scene = sceneDepth && sceneDepth->sized(W, H, 1);
    glUseProgram(program_.id());
    const glm::vec3 lo = field->grid.lo();
    const glm::ivec3 dims = field->grid.dims();
    glUniform3f(0, lo.x, lo.y, lo.z);
    glUniform1f(1, field->grid.invCell());
    glUniform3i(2, dims.x, dims.y, dims.z);
    glUniform1f(3, field->support);
    glUniform1f(4, field->isoRaw);
    glUniform1f(5, params.stepRadii * frame.radius);  // as the CPU's step
    glUniform1i(6, params.maxSteps);
    glUniform1i(7, params.newtonSteps);
    glUniform1f(9, 1.0f / (field->support * field->support));  // as evaluateSphField's h^2, inverted
    glUniform1i(8, scene ? 1 : 0);
    glBindBufferRange(GL_SHADER_STORAGE_BUFFER, 1, points_.id(), 0, GLsizeiptr(packed_.size() * sizeof(glm::vec4)));
    glBindBufferRange(GL_SHADER_STORAGE_BUFFER, 2, starts_.id(), 0, GLsizeiptr(st.size() * sizeof(std::uint32_t)));
    glBindBufferRange(GL_SHADER_STORAGE_BUFFER, 7, quiet_.id(), 0,
                      GLsizeiptr(field->quiet.size() * sizeof(std::uint32_t)));
    start.bind(3);
    (scene ? *sceneDepth : start).bind(4);
    depth.bind(5);
    normals.bind(6);
    glDispatchCompute(GLuint((W + 7) / 8), GLuint((H + 7) / 8), 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    glUseProgram(0);
}

// ---- The stage's GL driver (core/backend.h StageDriver), named by its row
// in the stage list (src/render/stages.cpp).

namespace {

void runRaycast(GlBackend& g, const StageIo& io) {
    const StageSlots& at = io.at;
    g.forget(at.depth);
    g.forget(at.normal);
    const FrameSettings& s = g.frame();
    g.pass<Raycast>().run(g.params(), s.field, s.raycast, g.img(at.raw), &g.img(at.sceneDepth), g.img(at.depth),
                          g.img(at.normal));
}

}  // namespace

extern const StageDriver kRaycastStage = {glPrepare<Raycast>, glRun<runRaycast>};

}  // namespace meniscus::gl
