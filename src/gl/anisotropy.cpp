// GL anisotropic kernels, docs/pipeline.md#anisotropic-kernels: the
// neighbour grid built on the GPU by a counting sort
// (shaders/anisotropy_grid.comp: count per bucket with atomics, prefix sum,
// scatter, each bucket put in index order), then one invocation per particle
// (shaders/anisotropy.comp) for the sums, the eigen-decomposition and the
// ellipsoid, by the CPU's formulas (src/shared/anisotropy.h). Per frame the
// host only uploads the positions (and the own radii) and dispatches.
#include "gl/anisotropy.h"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <vector>

#include "gl/dispatch.h"
#include "gl/shaders.h"

namespace meniscus::gl {

namespace {
constexpr GLuint kAnisotropyGroup = 64;            // local_size_x of both shaders
constexpr GLuint kChunk = 512;           // anisotropy_grid.comp's buckets per chunk of the prefix sum
constexpr GLuint kParticlesPerInvocation = 4;  // grid-stride: llvmpipe pays per work group
}  // namespace

Result<Anisotropy> Anisotropy::create() {
    Anisotropy a;
    auto grid = loadComputeProgram("anisotropy_grid.comp");
    if (!grid) return grid.error();
    auto pca = loadComputeProgram("anisotropy.comp");
    if (!pca) return pca.error();
    a.grid_ = std::move(*grid);
    a.pca_ = std::move(*pca);
    a.sortedTex_ = makeTexture();
    a.startsTex_ = makeTexture();
    return a;
}

void Anisotropy::run(std::span<const glm::vec3> positions, float radius, const AnisotropyParams& params,
                     std::span<const float> radii, float shapeScale, Buffer& centres, Buffer& shapes) {
    static_assert(sizeof(glm::vec3) == 3 * sizeof(float), "positions are uploaded as packed xyz floats");
    if (!positions.empty()) positions_.upload(positions.data(), GLsizeiptr(positions.size_bytes()));
    runOnDevice(GLuint(positions.size()), radius, params, radii, shapeScale, centres, shapes);
}

void Anisotropy::runOnDevice(GLuint n, float radius, const AnisotropyParams& params, std::span<const float> radii,
                             float shapeScale, Buffer& centres, Buffer& shapes) {
    const GLsizeiptr n1 = GLsizeiptr(std::max<GLuint>(n, 1));  // binding an empty buffer is an error
    centres.reserve(n1 * 3 * GLsizeiptr(sizeof(float)));
    shapes.reserve(n1 * 12 * GLsizeiptr(sizeof(float)));
    if (n == 0) return;
    // At least as many buckets as particles (a power of two): few cells share one.
    const GLuint buckets = std::bit_ceil(std::max<GLuint>(n, 1024));
    const GLuint chunks = ceilDiv(buckets, kChunk);
    const bool own = radii.size() == n;
    if (own) radii_.upload(radii.data(), GLsizeiptr(radii.size_bytes()));
    else radii_.reserve(4);
    counts_.reserve(GLsizeiptr(buckets) * 4);
    starts_.reserve(GLsizeiptr(buckets + 1) * 4);
    chunks_.reserve(GLsizeiptr(chunks) * 4);
    unsorted_.reserve(GLsizeiptr(n) * 4);
    sorted_.reserve(GLsizeiptr(n) * 16);
    bucketOf_.reserve(GLsizeiptr(n) * 4);
    counts_.fill(GLsizeiptr(buckets) * 4, 0u);

    // The CPU's neighbourhood in its float arithmetic (core/anisotropy.cpp).
    const float R = params.neighbourRadii * radius;
    const GLuint particleGroups = gridGroups(n, kAnisotropyGroup * kParticlesPerInvocation);

    glUseProgram(grid_.id());
    glUniform1ui(0, n);
    glUniform1ui(1, buckets);
    glUniform1f(2, 1.0f / R);
    const Buffer* gridBuffers[] = {&positions_, &counts_, &starts_, &chunks_, &unsorted_, &sorted_, &bucketOf_};
    for (GLuint b = 0; b < 7; ++b) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, b, gridBuffers[b]->id());
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
    const GLuint groupsOfPass[6] = {particleGroups, gridGroups(chunks, kAnisotropyGroup), 1, gridGroups(chunks, kAnisotropyGroup),
                                    particleGroups, particleGroups};
    for (int pass = 0; pass < 6; ++pass) {
        glUniform1i(3, pass);
        glDispatchCompute(groupsOfPass[pass], 1, 1);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    }

    glUseProgram(pca_.id());
    glUniform1ui(0, n);
    glUniform1ui(1, buckets);
    glUniform1f(2, 1.0f / R);
    glUniform1f(3, R * R);
    glUniform1f(4, 1.0f / (R * R * R));
    glUniform1i(5, params.minNeighbours);
    glUniform1f(6, params.kr);
    glUniform1f(7, params.kn);
    glUniform1f(8, params.smoothing * R);
    glUniform1i(9, params.keepSurface ? 1 : 0);
    glUniform1f(10, radius);
    glUniform1i(11, own ? 1 : 0);
    glUniform1f(12, shapeScale);
    const GLuint pcaBuffers[] = {radii_.id(), centres.id(), shapes.id()};
    for (GLuint b = 0; b < 3; ++b) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, b + 2, pcaBuffers[b]);
    attachBufferTexture(sortedTex_, GL_RGBA32F, sorted_, GLsizeiptr(n) * 16);
    attachBufferTexture(startsTex_, GL_R32UI, starts_, GLsizeiptr(buckets + 1) * 4);
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_BUFFER, startsTex_.id());
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_BUFFER, sortedTex_.id());
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
    glDispatchCompute(particleGroups, 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    glBindTexture(GL_TEXTURE_BUFFER, 0);
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_BUFFER, 0);
    glActiveTexture(GL_TEXTURE0);
    glUseProgram(0);
}

Result<Ellipsoids> anisotropyOnGpu(std::span<const glm::vec3> positions, float radius,
                                   const AnisotropyParams& params, std::span<const float> radii) {
    auto a = Anisotropy::create();
    if (!a) return a.error();
    Buffer centres, shapes;
    a->run(positions, radius, params, radii, 1.0f, centres, shapes);
    const std::size_t n = positions.size();
    Ellipsoids out;
    out.centres.resize(n);
    out.shapes.resize(n);
    if (n == 0) return out;
    std::vector<float> packed(12 * n);
    centres.download(out.centres.data(), GLsizeiptr(n * sizeof(glm::vec3)));
    shapes.download(packed.data(), GLsizeiptr(packed.size() * sizeof(float)));
    // The symmetric m and q from their upper triangles.
    auto symmetric = [](const float* v) {
        return glm::mat3(v[0], v[1], v[2], v[1], v[3], v[4], v[2], v[4], v[5]);
    };
    for (std::size_t i = 0; i < n; ++i) out.shapes[i] = {symmetric(&packed[12 * i]), symmetric(&packed[12 * i + 6])};
    return out;
}

}  // namespace meniscus::gl
