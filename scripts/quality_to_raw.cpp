// Particle file -> refsurf raw (uint64 count, count*3 float32 LE), and prints
// the CLI's automatic camera (as apps/meniscus/main.cpp picks it for one frame) so
// that refsurf can use the same view. Used by scripts/quality_eval.sh; throwaway tool, not part of the build.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include "meniscus/camera.h"
#include "meniscus/io.h"
#include "meniscus/params.h"
#include "meniscus/particles.h"
int main(int argc, char** argv) {
    if (argc != 5) { std::fprintf(stderr, "usage: quality_to_raw IN OUT.raw W H\n"); return 2; }
    auto set = meniscus::readParticles(argv[1]);
    if (!set) { std::fprintf(stderr, "%s\n", set.error().describe().c_str()); return 1; }
    std::FILE* f = std::fopen(argv[2], "wb");
    if (!f) return 1;
    std::uint64_t n = set->positions.size();
    std::fwrite(&n, 8, 1, f);
    for (auto& p : set->positions) std::fwrite(&p.x, 4, 3, f);
    std::fclose(f);
    const float r = meniscus::estimateRadius(set->positions).radius;
    meniscus::Camera base;
    base.width = std::atoi(argv[3]);
    base.height = std::atoi(argv[4]);
    base.fovYDegrees = meniscus::defaults::kFovYDegrees;  // as the CLI does (40 deg, not Camera{}'s 45)
    // The CLI frames a subsample (stride size/20000) of the first frame.
    std::vector<glm::vec3> sample;
    const std::size_t stride = std::max<std::size_t>(1, n / 20000);
    for (std::size_t i = 0; i < n; i += stride) sample.push_back(set->positions[i]);
    const auto c = meniscus::autoFrameCamera(sample, r, base);
    // One line: radius eye target up fov
    std::printf("%.9g %.9g,%.9g,%.9g %.9g,%.9g,%.9g %.9g,%.9g,%.9g %.9g\n", r, c.eye.x, c.eye.y, c.eye.z, c.target.x,
                c.target.y, c.target.z, c.up.x, c.up.y, c.up.z, c.fovYDegrees);
}
