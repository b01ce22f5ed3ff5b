// Renders a small ball of particles through the installed public API only and
// writes a PNG; exits 0 when the frame has fluid in its centre.
#include <cstdio>
#include <vector>

#include "meniscus/camera.h"
#include "meniscus/io.h"
#include "meniscus/renderer.h"

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: consumer OUT.png\n");
        return 2;
    }
    std::vector<glm::vec3> ball;
    for (int z = -5; z <= 5; ++z)
        for (int y = -5; y <= 5; ++y)
            for (int x = -5; x <= 5; ++x)
                if (x * x + y * y + z * z <= 25) ball.push_back(0.02f * glm::vec3(x, y, z));
    meniscus::RenderSettings s;
    s.radiusM = 0.01f;
    s.camera.eye = {0.0f, 0.0f, 0.5f};
    s.camera.target = {0.0f, 0.0f, 0.0f};
    s.camera.width = 64;
    s.camera.height = 48;
    auto renderer = meniscus::Renderer::create(meniscus::BackendChoice::Cpu);
    if (!renderer) return 1;
    auto aovs = renderer->render(ball, s);
    if (!aovs) {
        std::fprintf(stderr, "%s\n", aovs.error().describe().c_str());
        return 1;
    }
    const bool fluid = aovs->depth.at(32, 24) < 1.0f;
    if (auto st = meniscus::writePng(argv[1], aovs->color); !st) {
        std::fprintf(stderr, "%s\n", st.error().describe().c_str());
        return 1;
    }
    std::printf("consumer: %zu particles on %s, fluid at the centre: %s\n", ball.size(),
                renderer->backendName().c_str(), fluid ? "yes" : "no");
    return fluid ? 0 : 1;
}
