// GL mesh path (see raster_mesh.h): the mesh is drawn with glDrawElements into
// an R32F eye-depth and an RGBA32F normal target with a float depth buffer
// (shaders/raster_mesh.vert, .frag), then shaders/raster_mesh_resolve.comp
// copies the targets into the GpuImage layout the later stages read. GL's
// rasteriser does the coverage (the fill rule is the driver's: the image is
// drawn upside down so that llvmpipe's, top-left in framebuffer rows, is the
// CPU's top-left in image rows), the clipping (the near plane as a clip
// distance) and the perspective-correct interpolation.
#include "gl/raster_mesh.h"
#include "gl/gl_backend.h"

#include <atomic>
#include <cstdint>
#include <limits>

#include "gl/dispatch.h"
#include "gl/shaders.h"
#include "meniscus/params.h"

namespace meniscus::gl {

namespace {
constexpr int kRasterMeshGroup = 64;  // local_size_x of raster_mesh_resolve.comp
// The targets are image-sized textures: GL 4.3 guarantees GL_MAX_TEXTURE_SIZE
// >= 16384, and validateCamera refuses any larger side.
static_assert(defaults::kMaxImageSizePx <= 16384, "the GL mesh path needs a check against GL_MAX_TEXTURE_SIZE");
}  // namespace

Result<MeshRasteriser> MeshRasteriser::create() {
    MeshRasteriser m;
    auto draw = loadRenderProgram("raster_mesh.vert", "raster_mesh.frag");
    if (!draw) return draw.error();
    m.draw_ = std::move(*draw);
    auto resolve = loadComputeProgram("raster_mesh_resolve.comp");
    if (!resolve) return resolve.error();
    m.resolve_ = std::move(*resolve);
    m.vertexArray_ = makeVertexArray();
    m.framebuffer_ = makeFramebuffer();
    m.empty_.reserve(16);
    return m;
}

namespace {
std::atomic<std::uint64_t> uploadedBytes{0};
}  // namespace

std::uint64_t meshUploadBytes() { return uploadedBytes; }

void GpuMesh::upload(const TriangleMesh& mesh, const std::vector<glm::vec2>* texcoords) {
    // As they are: glm::vec3 is three packed floats, glm::vec2 two.
    static_assert(sizeof(glm::vec3) == 3 * sizeof(float) && sizeof(glm::vec2) == 2 * sizeof(float));
    const auto vertexBytes = GLsizeiptr(mesh.positions.size() * sizeof(glm::vec3));
    positions.upload(mesh.positions.data(), vertexBytes);
    normals.upload(mesh.normals.data(), GLsizeiptr(mesh.normals.size() * sizeof(glm::vec3)));
    uploadedBytes += std::uint64_t(vertexBytes) + mesh.normals.size() * sizeof(glm::vec3);
    hasUv = texcoords && texcoords->size() == mesh.positions.size();
    if (hasUv) {
        uvs.upload(texcoords->data(), GLsizeiptr(texcoords->size() * sizeof(glm::vec2)));
        uploadedBytes += texcoords->size() * sizeof(glm::vec2);
    }
}

void GpuIndices::upload(std::span<const std::uint32_t> indices) {
    buffer.upload(indices.data(), GLsizeiptr(indices.size_bytes()));
    count = GLsizei(indices.size());
    uploadedBytes += indices.size_bytes();
}

void MeshRasteriser::run(const FrameParams& frame, const TriangleMesh& mesh, const GpuImage* sceneDepth,
                         GpuImage& depth, GpuImage& normal, const std::vector<glm::vec2>* uvs, GpuImage* uv) {
    mesh_.upload(mesh, uv ? uvs : nullptr);
    indices_.upload(mesh.indices);
    run(frame, mesh_, indices_, sceneDepth, depth, normal, uv);
}

void MeshRasteriser::run(const FrameParams& frame, const GpuMesh& mesh, const GpuIndices& indices,
                         const GpuImage* sceneDepth, GpuImage& depth, GpuImage& normal, GpuImage* uv) {
    const int W = frame.size.x, H = frame.size.y;
    const bool withUv = uv && mesh.hasUv;
    depth.resize(W, H, 1);
    normal.resize(W, H, 3);
    if (withUv) uv->resize(W, H, 2);
    if (W <= 0 || H <= 0) return;

    // The targets, made again only when the image size changes.
    if (W != targetW_ || H != targetH_) {
        auto target = [&](Texture& tex, GLenum format) {
            tex = makeTexture();
            glBindTexture(GL_TEXTURE_2D, tex.id());
            glTexStorage2D(GL_TEXTURE_2D, 1, format, W, H);
            glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
            glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        };
        target(depthTarget_, GL_R32F);
        target(normalTarget_, GL_RGBA32F);
        target(uvTarget_, GL_RG32F);
        target(zBuffer_, GL_DEPTH_COMPONENT32F);
        glBindTexture(GL_TEXTURE_2D, 0);
        glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_.id());
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, depthTarget_.id(), 0);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D, normalTarget_.id(), 0);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT2, GL_TEXTURE_2D, uvTarget_.id(), 0);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, zBuffer_.id(), 0);
        const GLenum buffers[3] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2};
        glDrawBuffers(3, buffers);
        targetW_ = W;
        targetH_ = H;
    }

    // The mesh's arrays.
    glBindVertexArray(vertexArray_.id());
    glBindBuffer(GL_ARRAY_BUFFER, mesh.positions.id());
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
    glBindBuffer(GL_ARRAY_BUFFER, mesh.normals.id());
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
    if (withUv) {
        glBindBuffer(GL_ARRAY_BUFFER, mesh.uvs.id());
        glEnableVertexAttribArray(2);
        glVertexAttribPointer(2, 2, GL_FLOAT, GL_FALSE, 0, nullptr);
    } else {
        glDisableVertexAttribArray(2);
        glVertexAttrib2f(2, 0.0f, 0.0f);
    }
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, indices.buffer.id());

    // The draw: no fluid (+inf, (0,0,0)) where no triangle lands; reversed
    // depth (near / eye depth, cleared to 0, GL_GREATER keeps the nearest and,
    // of equal depths, the first drawn, as the CPU's strict test).
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_.id());
    glViewport(0, 0, W, H);
    const float inf = std::numeric_limits<float>::infinity();
    const GLfloat clearDepth[4] = {inf, 0.0f, 0.0f, 0.0f}, clearNormal[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    glClearBufferfv(GL_COLOR, 0, clearDepth);
    glClearBufferfv(GL_COLOR, 1, clearNormal);
    glClearBufferfv(GL_COLOR, 2, clearNormal);
    const GLfloat clearZ = 0.0f;
    glClearBufferfv(GL_DEPTH, 0, &clearZ);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);
    glDisable(GL_SCISSOR_TEST);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_GREATER);
    glDepthMask(GL_TRUE);
    glEnable(GL_CLIP_DISTANCE0);
    const bool hasScene = sceneDepth && sceneDepth->width == W && sceneDepth->height == H &&
                          sceneDepth->channels == 1 && sceneDepth->buffer.id() != 0;
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);  // the scene stage's writes reach the fragment shader
    glUseProgram(draw_.id());
    glUniform1i(0, hasScene ? 1 : 0);
    if (hasScene) sceneDepth->bind(1);
    else glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, empty_.id());
    if (indices.count > 0) glDrawElements(GL_TRIANGLES, indices.count, GL_UNSIGNED_INT, nullptr);
    glDisable(GL_CLIP_DISTANCE0);
    glDisable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glBindVertexArray(0);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);

    // The targets into the images (rendering to a texture, then fetching it
    // in a later command, needs no barrier).
    glUseProgram(resolve_.id());
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, depthTarget_.id());
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D, normalTarget_.id());
    glActiveTexture(GL_TEXTURE2);
    glBindTexture(GL_TEXTURE_2D, uvTarget_.id());
    glUniform1i(0, withUv ? 1 : 0);
    depth.bind(2);
    normal.bind(3);
    if (withUv) uv->bind(4);
    else glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, empty_.id());
    glDispatchCompute(ceilDiv(GLuint(W), kRasterMeshGroup), GLuint(H), 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    glBindTexture(GL_TEXTURE_2D, 0);
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D, 0);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, 0);
    glUseProgram(0);
}

// ---- The stage's GL driver (core/backend.h StageDriver), named by its row
// in the stage list (src/render/stages.cpp).

namespace {

void runRasterise(GlBackend& g, const StageIo& io) {
    const StageSlots& at = io.at;
    g.forget(at.depth);
    g.forget(at.normal);
    static const TriangleMesh kNoMesh;  // no mesh: no fluid
    const FrameSettings& s = g.frame();
    g.pass<MeshRasteriser>().run(g.params(), s.mesh ? *s.mesh : kNoMesh, &g.img(at.sceneDepth), g.img(at.depth),
                                 g.img(at.normal));
}

}  // namespace

extern const StageDriver kRasteriseStage = {glPrepare<MeshRasteriser>, glRun<runRasterise>};

}  // namespace meniscus::gl
