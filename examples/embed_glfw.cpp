// An application that draws Meniscus's liquid into its own OpenGL frame
// (docs/compositing.md, "Into an application's GL frame"): a small lit scene
// of its own (a floor and a block standing in the water), the built-in
// simulator running live (a column of water falling over around the block),
// and an orbit camera (drag to turn, wheel to zoom, Escape to quit). Each
// frame the application draws its scene into its own colour and depth
// textures, then Renderer::drawIntoHost composites the liquid into them and
// writes the finished frame into the window: nothing of the frame goes to the
// CPU.
//
//   meniscus_embed_example [--frames N] [--screenshot PATH] [--write-layers DIR] [--particle-buffer]
//
// --particle-buffer keeps the particles in a GL buffer of the application's
// own (a vertex buffer of x, y, z and a spare float each, as a game holds
// its particles), updated each frame, and hands Meniscus that buffer
// (HostParticleBuffer) instead of the positions: they are read on the GPU.
//
// --frames N stops after N frames (0: when the window is closed);
// --screenshot PATH writes the last frame's window as a PNG; --write-layers
// DIR writes what the last frame composited the liquid into (the host's
// colour as PNG, its window depth as OpenEXR), the particles, and a render
// scene file that makes `meniscus render DIR/scene.json --backend cpu` the
// CPU reference of the same frame (the test of this example compares them).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <epoxy/gl.h>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <nlohmann/json.hpp>

#include "meniscus/io.h"
#include "meniscus/renderer.h"
#include "meniscus/sim.h"
#include "meniscus/window.h"

namespace {

using namespace meniscus;

// ---- The application's own scene: lit boxes drawn with depth --------------

const char* kVertexShader = R"(#version 430 core
layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aNormal;
layout(location = 0) uniform mat4 uViewProjection;
out vec3 vNormal;
out vec3 vWorld;
void main() {
    vNormal = aNormal;
    vWorld = aPosition;
    gl_Position = uViewProjection * vec4(aPosition, 1.0);
})";

// Lambert and an ambient term, a checker on the floor; written as 8-bit sRGB
// codes (the colour texture is RGBA8, HostLayers::colorIsSrgb).
const char* kFragmentShader = R"(#version 430 core
in vec3 vNormal;
in vec3 vWorld;
layout(location = 1) uniform vec3 uColor;
layout(location = 2) uniform int uChecker;
out vec4 fragColor;
float encode(float x) { x = clamp(x, 0.0, 1.0); return x <= 0.0031308 ? 12.92 * x : 1.055 * pow(x, 1.0 / 2.4) - 0.055; }
void main() {
    vec3 base = uColor;
    if (uChecker != 0 && (int(floor(vWorld.x * 5.0)) + int(floor(vWorld.z * 5.0))) % 2 != 0) base *= 0.6;
    const vec3 light = normalize(vec3(0.4, 1.0, 0.3));
    const vec3 c = base * (0.25 + 0.75 * max(dot(normalize(vNormal), light), 0.0));
    fragColor = vec4(encode(c.r), encode(c.g), encode(c.b), 1.0);
})";

GLuint compile(GLenum kind, const char* source) {
    const GLuint s = glCreateShader(kind);
    glShaderSource(s, 1, &source, nullptr);
    glCompileShader(s);
    GLint ok = 0;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[2048];
        glGetShaderInfoLog(s, sizeof(log), nullptr, log);
        std::fprintf(stderr, "embed example: a shader does not compile: %s\n", log);
    }
    return s;
}

// Six faces of an axis-aligned box, two triangles each: position, normal.
void appendBox(std::vector<float>& out, glm::vec3 lo, glm::vec3 hi) {
    const glm::vec3 n[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (const glm::vec3& normal : n) {
        const int axis = normal.x != 0 ? 0 : normal.y != 0 ? 1 : 2;
        const int u = (axis + 1) % 3, v = (axis + 2) % 3;
        glm::vec3 corner[4];
        for (int k = 0; k < 4; ++k) {
            glm::vec3 p;
            p[axis] = normal[axis] > 0 ? hi[axis] : lo[axis];
            p[u] = (k == 1 || k == 2) ? hi[u] : lo[u];
            p[v] = (k >= 2) ? hi[v] : lo[v];
            corner[k] = p;
        }
        // Wound counter-clockwise seen from outside (no culling is used, so
        // the order only has to be consistent).
        for (int k : {0, 1, 2, 0, 2, 3}) {
            out.insert(out.end(), {corner[k].x, corner[k].y, corner[k].z, normal.x, normal.y, normal.z});
        }
    }
}

struct HostScene {
    GLuint program = 0, vertexArray = 0, vertexBuffer = 0;
    GLsizei floorVertices = 0, blockVertices = 0;
    GLuint color = 0, depth = 0, framebuffer = 0;
    int width = 0, height = 0;

    HostScene(int w, int h, glm::vec3 blockLo, glm::vec3 blockHi) : width(w), height(h) {
        program = glCreateProgram();
        const GLuint vs = compile(GL_VERTEX_SHADER, kVertexShader), fs = compile(GL_FRAGMENT_SHADER, kFragmentShader);
        glAttachShader(program, vs);
        glAttachShader(program, fs);
        glLinkProgram(program);
        glDeleteShader(vs);
        glDeleteShader(fs);
        std::vector<float> vertices;
        appendBox(vertices, {-1.5f, -0.05f, -1.0f}, {1.5f, 0.0f, 1.0f});  // the floor, a thin slab
        floorVertices = GLsizei(vertices.size() / 6);
        appendBox(vertices, blockLo, blockHi);
        blockVertices = GLsizei(vertices.size() / 6) - floorVertices;
        glGenVertexArrays(1, &vertexArray);
        glBindVertexArray(vertexArray);
        glGenBuffers(1, &vertexBuffer);
        glBindBuffer(GL_ARRAY_BUFFER, vertexBuffer);
        glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(vertices.size() * sizeof(float)), vertices.data(), GL_STATIC_DRAW);
        glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), nullptr);
        glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), reinterpret_cast<void*>(3 * sizeof(float)));
        glEnableVertexAttribArray(0);
        glEnableVertexAttribArray(1);
        glBindVertexArray(0);
        // The frame's colour (8-bit sRGB codes) and depth, as textures the
        // liquid can read.
        glGenTextures(1, &color);
        glBindTexture(GL_TEXTURE_2D, color);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, w, h, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
        glGenTextures(1, &depth);
        glBindTexture(GL_TEXTURE_2D, depth);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT32F, w, h, 0, GL_DEPTH_COMPONENT, GL_FLOAT, nullptr);
        glBindTexture(GL_TEXTURE_2D, 0);
        glGenFramebuffers(1, &framebuffer);
        glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, color, 0);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, depth, 0);
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
    }
    ~HostScene() {
        glDeleteFramebuffers(1, &framebuffer);
        const GLuint textures[2] = {color, depth};
        glDeleteTextures(2, textures);
        glDeleteBuffers(1, &vertexBuffer);
        glDeleteVertexArrays(1, &vertexArray);
        glDeleteProgram(program);
    }

    void draw(const glm::mat4& viewProjection) const {
        glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
        glViewport(0, 0, width, height);
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_LESS);
        glClearColor(0.62f, 0.73f, 0.84f, 1.0f);  // the sky, sRGB codes
        glClearDepth(1.0);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        glUseProgram(program);
        glUniformMatrix4fv(0, 1, GL_FALSE, glm::value_ptr(viewProjection));
        glBindVertexArray(vertexArray);
        glUniform3f(1, 0.8f, 0.78f, 0.72f);
        glUniform1i(2, 1);
        glDrawArrays(GL_TRIANGLES, 0, floorVertices);
        glUniform3f(1, 0.75f, 0.22f, 0.15f);
        glUniform1i(2, 0);
        glDrawArrays(GL_TRIANGLES, floorVertices, blockVertices);
        glBindVertexArray(0);
        glUseProgram(0);
        glDisable(GL_DEPTH_TEST);
    }
};

// ---- The orbit camera -----------------------------------------------------

struct Orbit {
    glm::vec3 target{0.0f, 0.15f, 0.0f};
    float azimuthDeg = 35.0f, elevationDeg = 25.0f, distanceM = 1.6f;
    glm::vec3 eye() const {
        const float a = glm::radians(azimuthDeg), e = glm::radians(elevationDeg);
        return target + distanceM * glm::vec3(std::sin(a) * std::cos(e), std::sin(e), std::cos(a) * std::cos(e));
    }
};

constexpr float kFovYDeg = 45.0f, kNearM = 0.01f, kFarM = 1000.0f;  // kNearM, kFarM: as `meniscus render`'s camera

// ---- What the CPU reference needs -------------------------------------------

bool writeLayers(const std::filesystem::path& dir, const HostScene& host, const std::vector<glm::vec3>& positions,
                 const Orbit& orbit, float radius) {
    std::filesystem::create_directories(dir);
    const int W = host.width, H = host.height;
    std::vector<std::uint8_t> rgba(std::size_t(W) * std::size_t(H) * 4);
    std::vector<float> depth(std::size_t(W) * std::size_t(H));
    glBindFramebuffer(GL_READ_FRAMEBUFFER, host.framebuffer);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, W, H, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
    glReadPixels(0, 0, W, H, GL_DEPTH_COMPONENT, GL_FLOAT, depth.data());
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    Image<glm::u8vec4> color(W, H);
    Image<float> z(W, H);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const std::size_t i = std::size_t(H - 1 - y) * std::size_t(W) + std::size_t(x);  // GL rows bottom first
            color.at(x, y) = {rgba[4 * i], rgba[4 * i + 1], rgba[4 * i + 2], 255};
            z.at(x, y) = depth[i];
        }
    ParticleSet set;
    set.positions = positions;
    const glm::vec3 eye = orbit.eye();
    char kind[64];
    std::snprintf(kind, sizeof(kind), "window:%g,%g", double(kNearM), double(kFarM));
    const nlohmann::json scene = {
        {"particles", "particles.bgeo"},
        {"backdrop", "host_color.png"},
        {"backdrop_depth", "host_depth.exr"},
        {"backdrop_depth_kind", kind},
        {"camera", {{"eye", {eye.x, eye.y, eye.z}}, {"target", {orbit.target.x, orbit.target.y, orbit.target.z}},
                    {"fov", kFovYDeg}}},
        {"width", W},
        {"height", H},
        {"radius", radius},
    };
    std::ofstream(dir / "scene.json") << scene.dump(2) << "\n";
    for (const Status& st : {writePng(dir / "host_color.png", color, false), writeExr(dir / "host_depth.exr", {{"Z", &z}}),
                             writeParticles(dir / "particles.bgeo", set)})
        if (!st) {
            std::fprintf(stderr, "embed example: %s\n", st.error().describe().c_str());
            return false;
        }
    return true;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"Meniscus's liquid drawn into an application's own OpenGL frame, the simulator running live"};
    int frames = 0, width = 960, height = 540;
    std::string screenshot, layersDir;
    app.add_option("--frames", frames, "Stop after N frames (0: when the window is closed)")->check(CLI::NonNegativeNumber);
    app.add_option("--screenshot", screenshot, "Write the last frame's window as a PNG");
    app.add_option("--write-layers", layersDir,
                   "Write the last frame's host layers, particles and a scene file for the CPU reference into DIR");
    app.add_option("--width", width, "Window width, pixels")->check(CLI::Range(16, 8192));
    app.add_option("--height", height, "Window height, pixels")->check(CLI::Range(16, 8192));
    bool particleBuffer = false;
    app.add_flag("--particle-buffer", particleBuffer,
                 "Hand Meniscus the particles in the application's own GL buffer (read on the GPU)");
    CLI11_PARSE(app, argc, argv);

    // The simulation: a column of water in a small tank falls over around a block.
    const glm::vec3 blockLo(0.05f, 0.0f, -0.08f), blockHi(0.2f, 0.12f, 0.08f);
    sim::Scene scene;
    scene.params.radius = 0.01f;
    scene.domain = {{-0.5f, 0.0f, -0.25f}, {0.5f, 0.8f, 0.25f}};
    sim::FluidBlock block;
    block.box = {{-0.5f, 0.0f, -0.25f}, {-0.25f, 0.35f, 0.25f}};
    scene.fluid.push_back(block);
    sim::Collider obstacle;
    obstacle.kind = sim::Collider::Kind::Box;
    obstacle.box = {blockLo, blockHi};
    scene.colliders.push_back(obstacle);
    auto simulator = sim::Simulator::create(scene);
    if (!simulator) {
        std::fprintf(stderr, "embed example: %s\n", simulator.error().describe().c_str());
        return 1;
    }

    auto window = Window::create(width, height, "Meniscus embedded");
    if (!window) {
        std::fprintf(stderr, "embed example: %s\n", window.error().describe().c_str());
        return 1;
    }
    const glm::ivec2 size = (*window)->framebufferSize();
    int status = 0;
    {
        auto renderer = Renderer::createOnCurrentGlContext();
        if (!renderer) {
            std::fprintf(stderr, "embed example: %s\n", renderer.error().describe().c_str());
            return 1;
        }
        std::printf("embed example: %s, %zu particles%s, %d x %d\n", renderer->backendName().c_str(),
                    (*simulator)->size(), particleBuffer ? " from the application's GL buffer" : "", size.x, size.y);
        HostScene host(size.x, size.y, blockLo, blockHi);
        RenderSettings settings;
        settings.radiusM = scene.params.radius;
        Orbit orbit;
        // --particle-buffer: the application's own particle buffer, x y z w per
        // particle (w spare: its own use), and the staging copy it fills it from.
        GLuint vbo = 0;
        std::vector<glm::vec4> staged;
        if (particleBuffer) glGenBuffers(1, &vbo);
        // Wall-clock time of each frame's two halves: the simulation's step
        // and the drawing (the host's scene, the liquid, the buffer swap).
        using Clock = std::chrono::steady_clock;
        double simulateMs = 0.0, drawMs = 0.0;
        int drawn = 0;
        for (int frame = 0; frames == 0 || frame < frames; ++frame) {
            if ((*window)->shouldClose()) break;
            // The simulation one frame further (60 frames a simulated second).
            const auto t0 = Clock::now();
            if (auto st = (*simulator)->advanceTo((*simulator)->time() + 1.0 / 60.0); !st) {
                std::fprintf(stderr, "embed example: %s\n", st.error().describe().c_str());
                status = 1;
                break;
            }
            const auto t1 = Clock::now();
            HostLayers layers;
            layers.colorTexture = host.color;
            layers.depthTexture = host.depth;
            layers.width = size.x;
            layers.height = size.y;
            layers.view = glm::lookAt(orbit.eye(), orbit.target, glm::vec3(0.0f, 1.0f, 0.0f));
            layers.projection = glm::perspective(glm::radians(kFovYDeg), float(size.x) / float(size.y), kNearM, kFarM);
            host.draw(layers.projection * layers.view);
            glBindFramebuffer(GL_FRAMEBUFFER, 0);  // the finished frame goes to the window
            const std::span<const glm::vec3> positions = (*simulator)->positions();
            Status st = okStatus();
            if (particleBuffer) {
                // The application's buffer (here filled from the CPU simulator;
                // a GPU simulation would write it in place), handed over by name.
                staged.resize(positions.size());
                for (std::size_t i = 0; i < positions.size(); ++i) staged[i] = glm::vec4(positions[i], 1.0f);
                glBindBuffer(GL_ARRAY_BUFFER, vbo);
                glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(staged.size() * sizeof(glm::vec4)), staged.data(),
                             GL_STREAM_DRAW);
                glBindBuffer(GL_ARRAY_BUFFER, 0);
                HostParticleBuffer buffer;
                buffer.buffer = vbo;
                buffer.count = positions.size();
                buffer.strideBytes = sizeof(glm::vec4);
                st = renderer->drawIntoHost(buffer, settings, layers);
            } else {
                st = renderer->drawIntoHost(ParticleView(positions), settings, layers);
            }
            if (!st) {
                std::fprintf(stderr, "embed example: %s\n", st.error().describe().c_str());
                status = 1;
                break;
            }
            const bool last = frames > 0 && frame + 1 == frames;
            if (last && !screenshot.empty())
                if (auto st = writePng(screenshot, (*window)->readPixels(), false); !st) {
                    std::fprintf(stderr, "embed example: %s\n", st.error().describe().c_str());
                    status = 1;
                }
            if (last && !layersDir.empty() &&
                !writeLayers(layersDir, host, std::vector<glm::vec3>(positions.begin(), positions.end()), orbit,
                             settings.radiusM))
                status = 1;
            (*window)->swapBuffers();
            simulateMs += std::chrono::duration<double, std::milli>(t1 - t0).count();
            drawMs += std::chrono::duration<double, std::milli>(Clock::now() - t1).count();
            ++drawn;
            (*window)->pollEvents();
            const WindowInput input = (*window)->takeInput();
            orbit.azimuthDeg -= 0.3f * float(input.drag.x);
            orbit.elevationDeg = glm::clamp(orbit.elevationDeg + 0.3f * float(input.drag.y), -5.0f, 85.0f);
            orbit.distanceM = glm::clamp(orbit.distanceM * std::pow(0.9f, float(input.scroll)), 0.3f, 10.0f);
            for (Key k : input.keys)
                if (k == Key::Escape || k == Key::Q) (*window)->requestClose();
        }
        if (drawn > 0)
            std::printf("embed example: %d frames, per frame %.1f ms simulating and %.1f ms drawing (wall clock)\n",
                        drawn, simulateMs / drawn, drawMs / drawn);
        if (vbo) glDeleteBuffers(1, &vbo);
    }  // the renderer goes before the window's context
    return status;
}
