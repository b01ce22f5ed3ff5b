// Scene files (src/sim/scene.cpp, docs/scenes.md): the shipped scenes parse
// and say what their descriptions claim; missing fields take the defaults;
// every field lands in its member; each class of malformed input is an error
// naming the file, the field path and the problem; the docs list every key;
// the glass mesh is closed; the Martin & Moyce scene fits its data.
#include <array>
#include <cmath>
#include <fstream>
#include <functional>
#include <map>
#include <numbers>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "meniscus/sim.h"
#include "test_util.h"

namespace meniscus::sim::sim_scene_test_local {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

fs::path sourceDir() { return fs::path(MENISCUS_SOURCE_DIR); }
fs::path scenePath(const std::string& file) { return sourceDir() / "scenes" / file; }

std::string readText(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

Scene readShipped(const std::string& file) {
    auto scene = readScene(scenePath(file));
    if (!scene) ADD_FAILURE() << scene.error().describe();
    return scene ? scene.value() : Scene{};
}

void expectVec(const glm::vec3& v, float x, float y, float z) {
    EXPECT_FLOAT_EQ(v.x, x);
    EXPECT_FLOAT_EQ(v.y, y);
    EXPECT_FLOAT_EQ(v.z, z);
}

// Every member of SimParams.
void expectParams(const SimParams& p, const SimParams& want) {
    EXPECT_EQ(p.solver, want.solver);
    EXPECT_FLOAT_EQ(p.radius, want.radius);
    EXPECT_FLOAT_EQ(p.restDensity, want.restDensity);
    EXPECT_FLOAT_EQ(p.particleVolume, want.particleVolume);
    expectVec(p.gravity, want.gravity.x, want.gravity.y, want.gravity.z);
    EXPECT_FLOAT_EQ(p.viscosity, want.viscosity);
    EXPECT_FLOAT_EQ(p.surfaceTension, want.surfaceTension);
    EXPECT_FLOAT_EQ(p.stiffness, want.stiffness);
    EXPECT_FLOAT_EQ(p.cfl, want.cfl);
    EXPECT_FLOAT_EQ(p.minDt, want.minDt);
    EXPECT_FLOAT_EQ(p.maxDt, want.maxDt);
    EXPECT_FLOAT_EQ(p.densityTolerance, want.densityTolerance);
    EXPECT_FLOAT_EQ(p.divergenceTolerance, want.divergenceTolerance);
    EXPECT_EQ(p.maxIterations, want.maxIterations);
    EXPECT_FLOAT_EQ(p.lifetime, want.lifetime);
    EXPECT_EQ(p.resortEvery, want.resortEvery);
}

void expectEmitter(const Emitter& e, const Emitter& want) {
    expectVec(e.position, want.position.x, want.position.y, want.position.z);
    expectVec(e.direction, want.direction.x, want.direction.y, want.direction.z);
    EXPECT_FLOAT_EQ(e.radius, want.radius);
    EXPECT_FLOAT_EQ(e.speed, want.speed);
    EXPECT_FLOAT_EQ(e.rate, want.rate);
    EXPECT_FLOAT_EQ(e.start, want.start);
    EXPECT_FLOAT_EQ(e.end, want.end);
}

bool inside(const Box& inner, const Box& outer) {
    for (int i = 0; i < 3; ++i)
        if (inner.min[i] < outer.min[i] || inner.max[i] > outer.max[i]) return false;
    return true;
}

// ---- the shipped scenes -------------------------------------------------------

TEST(SimSceneShipped, EveryFileInScenesParses) {
    std::set<std::string> found;
    for (const auto& entry : fs::directory_iterator(sourceDir() / "scenes")) {
        if (entry.path().extension() != ".json") continue;
        found.insert(entry.path().filename().string());
        auto scene = readScene(entry.path());
        ASSERT_TRUE(scene.ok()) << scene.error().describe();
        const Scene& s = scene.value();
        EXPECT_EQ(s.name, entry.path().stem().string()) << "a scene's name is its file's stem";
        EXPECT_FALSE(s.fluid.empty() && s.emitters.empty());
        for (const FluidBlock& b : s.fluid) EXPECT_TRUE(inside(b.box, s.domain)) << s.name;
        // Each runs in minutes on 2 cores: no scene finer than r = 1 mm.
        EXPECT_GE(s.params.radius, 0.001f) << s.name;
    }
    const std::set<std::string> expected = {"dam_break.json", "martin_moyce.json", "waterfall.json",
                                            "waterfall_ballistic.json", "drop.json", "glass.json"};
    for (const auto& f : expected) EXPECT_TRUE(found.count(f)) << "scenes/" << f << " is missing";
}

// SPlisHSPlasH's data/Scenes/DamBreakModel.json (docs/scenes.md gives each source).
TEST(SimSceneShipped, DamBreakIsSplishSplashsDamBreakModel) {
    const Scene s = readShipped("dam_break.json");
    expectVec(s.domain.min, -2.0f, 0.0f, -0.75f);
    expectVec(s.domain.max, 2.0f, 3.0f, 0.75f);
    ASSERT_EQ(s.fluid.size(), 1u);
    EXPECT_EQ(s.fluid[0].shape, FluidBlock::Shape::Box);
    expectVec(s.fluid[0].box.min, -1.95f, 0.05f, -0.5f);
    expectVec(s.fluid[0].box.max, -0.95f, 1.05f, 0.5f);
    EXPECT_TRUE(s.colliders.empty() && s.emitters.empty() && s.drains.empty());
    EXPECT_DOUBLE_EQ(s.duration, 4.0);
    EXPECT_DOUBLE_EQ(s.fps, 25.0);
    // The defaults but for these (designated in SimParams' order).
    const SimParams want{.solver = Solver::Dfsph, .radius = 0.025f, .restDensity = 1000.0f,
                         .particleVolume = 0.8f,  // FluidModel::initMasses' 0.8 (2r)^3
                         .gravity = {0.0f, -9.81f, 0.0f}, .viscosity = 0.01f, .surfaceTension = 0.0f,
                         .cfl = 1.0f, .minDt = 0.0001f, .maxDt = 0.005f,
                         .densityTolerance = 0.0005f,    // maxError 0.05 %
                         .divergenceTolerance = 0.001f,  // maxErrorV 0.1 %
                         .maxIterations = 100};
    expectParams(s.params, want);
}

TEST(SimSceneShipped, DropIsABallOverAPool) {
    const Scene s = readShipped("drop.json");
    ASSERT_EQ(s.fluid.size(), 2u);
    const FluidBlock& pool = s.fluid[0];
    const FluidBlock& ball = s.fluid[1];
    EXPECT_EQ(pool.shape, FluidBlock::Shape::Box);
    ASSERT_EQ(ball.shape, FluidBlock::Shape::Sphere);
    // The ball's box is its bounding box, and the ball is clear of the pool.
    expectVec(ball.box.min, ball.center.x - ball.radius, ball.center.y - ball.radius, ball.center.z - ball.radius);
    expectVec(ball.box.max, ball.center.x + ball.radius, ball.center.y + ball.radius, ball.center.z + ball.radius);
    EXPECT_GT(ball.box.min.y, pool.box.max.y);
    EXPECT_LT(ball.velocity.y, 0.0f);
}

TEST(SimSceneShipped, WaterfallsPourOntoALedgeAndDrain) {
    for (const char* file : {"waterfall.json", "waterfall_ballistic.json"}) {
        SCOPED_TRACE(file);
        const Scene s = readShipped(file);
        ASSERT_EQ(s.emitters.size(), 1u);
        ASSERT_EQ(s.colliders.size(), 1u);
        ASSERT_FALSE(s.drains.empty());
        const Collider& ledge = s.colliders[0];
        EXPECT_EQ(ledge.kind, Collider::Kind::Box);
        EXPECT_GT(s.emitters[0].position.y, ledge.box.max.y) << "the nozzle is above the ledge";
        EXPECT_LT(s.drains[0].box.max.y, ledge.box.min.y) << "the drain is below it";
    }
    EXPECT_EQ(readShipped("waterfall.json").params.solver, Solver::Dfsph);
    EXPECT_EQ(readShipped("waterfall_ballistic.json").params.solver, Solver::Ballistic);
}

// The glass's mesh path is resolved against the scene's folder.
TEST(SimSceneShipped, GlassMeshResolvesNextToTheScene) {
    const Scene s = readShipped("glass.json");
    ASSERT_EQ(s.colliders.size(), 1u);
    EXPECT_EQ(s.colliders[0].kind, Collider::Kind::Mesh);
    EXPECT_EQ(s.colliders[0].mesh, (sourceDir() / "scenes" / "glass.obj").lexically_normal());
    EXPECT_TRUE(fs::is_regular_file(s.colliders[0].mesh));
    ASSERT_EQ(s.emitters.size(), 1u);
}

// glass.obj is a closed, consistently and outward-oriented triangle mesh (every
// directed edge once, its reverse once; positive volume, the cup's), inside the
// glass scene's domain, with the nozzle over its opening.
TEST(SimSceneShipped, GlassMeshIsClosedAndOutward) {
    std::ifstream in(scenePath("glass.obj"));
    ASSERT_TRUE(in) << "scenes/glass.obj";
    std::vector<glm::dvec3> v;
    std::vector<std::array<int, 3>> tris;
    for (std::string line; std::getline(in, line);) {
        std::istringstream s(line);
        std::string tag;
        s >> tag;
        if (tag == "v") {
            glm::dvec3 p;
            s >> p.x >> p.y >> p.z;
            v.push_back(p);
        } else if (tag == "f") {
            std::array<int, 3> t;
            s >> t[0] >> t[1] >> t[2];
            for (int& i : t) --i;
            tris.push_back(t);
        }
    }
    ASSERT_GT(tris.size(), 100u);
    std::map<std::pair<int, int>, int> edges;
    double volume = 0.0;
    for (const auto& t : tris) {
        for (int k = 0; k < 3; ++k) {
            ASSERT_TRUE(t[k] >= 0 && t[k] < int(v.size()));
            ++edges[{t[k], t[(k + 1) % 3]}];
        }
        volume += glm::dot(v[t[0]], glm::cross(v[t[1]], v[t[2]])) / 6.0;
    }
    for (const auto& [edge, count] : edges) {
        EXPECT_EQ(count, 1) << "edge " << edge.first << "-" << edge.second << " used twice the same way";
        EXPECT_EQ(edges.count({edge.second, edge.first}), 1u) << "edge " << edge.first << "-" << edge.second << " is open";
    }
    // 32-gon prisms: outer r 0.08, h 0.2, less the cavity r 0.065, depth 0.18.
    const double gon = 16.0 * std::sin(2.0 * std::numbers::pi / 32.0);
    EXPECT_NEAR(volume, gon * (0.08 * 0.08 * 0.2 - 0.065 * 0.065 * 0.18), 1e-6);

    const Scene s = readShipped("glass.json");
    for (const auto& p : v)
        for (int i = 0; i < 3; ++i) {
            EXPECT_GE(float(p[i]), s.domain.min[i]);
            EXPECT_LE(float(p[i]), s.domain.max[i]);
        }
    const glm::vec3 nozzle = s.emitters[0].position;
    EXPECT_GT(nozzle.y, 0.2f);
    EXPECT_LT(std::hypot(nozzle.x, nozzle.z) + s.emitters[0].radius, 0.065f);
}

struct FrontPoint {
    double T, xOverA, a;
    std::string source;
};

std::vector<FrontPoint> martinMoyce() {
    std::ifstream in(test::testData("martin_moyce_1952.csv"));
    std::vector<FrontPoint> rows;
    std::string line;
    while (std::getline(in, line) && line.rfind("#", 0) == 0) {}
    EXPECT_EQ(line, "T,x_over_a,a_m,source");
    while (std::getline(in, line)) {
        std::istringstream s(line);
        FrontPoint p;
        char comma;
        s >> p.T >> comma >> p.xOverA >> comma >> p.a >> comma >> p.source;
        EXPECT_TRUE(s) << line;
        rows.push_back(p);
    }
    return rows;
}

// The data the lead's validation test reads: n^2 = 2, increasing, and dense in
// the tested range 1 <= T <= 3.
TEST(SimSceneShipped, MartinMoyceDataIsUsable) {
    const auto rows = martinMoyce();
    ASSERT_EQ(rows.size(), 40u);
    std::map<std::pair<std::string, double>, std::vector<FrontPoint>> series;
    for (const auto& r : rows) series[{r.source, r.a}].push_back(r);
    EXPECT_EQ(series.size(), 3u);
    for (const auto& [key, points] : series)
        for (std::size_t i = 1; i < points.size(); ++i) {
            EXPECT_GT(points[i].T, points[i - 1].T) << key.first;
            EXPECT_GT(points[i].xOverA, points[i - 1].xOverA) << key.first;
        }
    int tested = 0;
    for (const auto& r : series[{"table2", 0.05715}]) tested += r.T >= 1.0 && r.T <= 3.0;
    EXPECT_GE(tested, 8);
}

// The scene is the experiment: a column a wide and 2a high against the left
// wall across the tank's depth, run past T = 3.5, in a tank whose far wall the
// measured front does not reach by then.
TEST(SimSceneShipped, MartinMoyceFitsTheExperiment) {
    const Scene s = readShipped("martin_moyce.json");
    ASSERT_EQ(s.fluid.size(), 1u);
    const Box& col = s.fluid[0].box;
    // The free faces are r beyond a and 2a (their lattice starts 2r inside), so
    // the particles' cubes fill a x 2a.
    const double r = s.params.radius;
    const double a = col.max.x - col.min.x - r;
    EXPECT_NEAR(a, 0.05715, 1e-6);
    EXPECT_NEAR(col.max.y - col.min.y - r, 2.0 * a, 1e-6);
    EXPECT_EQ(col.min.x, s.domain.min.x);
    EXPECT_EQ(col.min.y, s.domain.min.y);
    EXPECT_EQ(col.min.z, s.domain.min.z);
    EXPECT_EQ(col.max.z, s.domain.max.z);
    const double g = std::fabs(s.params.gravity.y);
    const double toT = std::sqrt(2.0 * g / a);
    EXPECT_GE(s.duration * toT, 3.5);
    // Front at T = 3.5, interpolated in the digitised curve for this a.
    std::vector<FrontPoint> fig3;
    for (const auto& r : martinMoyce())
        if (r.source == "fig3" && std::fabs(r.a - a) < 1e-6) fig3.push_back(r);
    ASSERT_GE(fig3.size(), 2u);
    double front = 0.0;
    for (std::size_t i = 1; i < fig3.size(); ++i)
        if (fig3[i - 1].T <= 3.5 && fig3[i].T >= 3.5)
            front = fig3[i - 1].xOverA +
                    (3.5 - fig3[i - 1].T) / (fig3[i].T - fig3[i - 1].T) * (fig3[i].xOverA - fig3[i - 1].xOverA);
    ASSERT_GT(front, 4.0);
    EXPECT_LT(s.domain.min.x + front * a + 8.0 * s.params.radius, s.domain.max.x) << "the front would hit the far wall";
    // Frames fine enough to read the front every 0.1 of T.
    EXPECT_LE(toT / s.fps, 0.1);
}

// ---- defaults and fields ------------------------------------------------------

const char* const kMinimal = R"({
  "domain": {"min": [0, 0, 0], "max": [1, 1, 1]},
  "fluid": [{"box": {"min": [0, 0, 0], "max": [0.5, 0.5, 0.5]}}]
})";

TEST(SimSceneFields, MissingFieldsTakeTheDefaults) {
    auto r = parseScene(kMinimal, "some/where/minimal.json");
    ASSERT_TRUE(r.ok()) << r.error().describe();
    const Scene& s = r.value();
    const Scene d;
    EXPECT_EQ(s.name, "minimal");
    EXPECT_EQ(s.file, fs::path("some/where/minimal.json"));
    EXPECT_DOUBLE_EQ(s.duration, d.duration);
    EXPECT_DOUBLE_EQ(s.fps, defaults::kSimFps);
    expectParams(s.params, SimParams{});
    EXPECT_EQ(s.params.radius, defaults::kSimRadiusM);
    EXPECT_EQ(s.params.densityTolerance, defaults::kSimDensityTolerance);
    ASSERT_EQ(s.fluid.size(), 1u);
    expectVec(s.fluid[0].velocity, 0, 0, 0);

    // An emitter and a mesh collider with only what they must have.
    json j = json::parse(kMinimal);
    j["emitters"] = json::parse(R"([{"position": [0.5, 0.9, 0.5]}])");
    j["colliders"] = json::parse(R"([{"kind": "mesh", "mesh": "cup.obj"}, {"kind": "plane", "point": [0, 0, 0], "normal": [0, 1, 0]}])");
    auto r2 = parseScene(j.dump(), "minimal.json");
    ASSERT_TRUE(r2.ok()) << r2.error().describe();
    expectEmitter(r2.value().emitters[0], Emitter{.position = {0.5f, 0.9f, 0.5f}});
    const Collider& m = r2.value().colliders[0];
    EXPECT_EQ(m.mesh, fs::path("cup.obj"));
    expectVec(m.scale, 1, 1, 1);
    expectVec(m.translate, 0, 0, 0);
}

// Every key set to a value unlike its default lands in its own member.
TEST(SimSceneFields, EveryFieldReachesItsMember) {
    const char* text = R"({
      "version": 1, "name": "all", "description": "every field", "duration": 2.5, "fps": 60,
      "params": {"solver": "sph", "radius": 0.03, "rest_density": 998, "particle_volume": 0.9,
                 "gravity": [1, -2, 3],
                 "viscosity": 0.2, "surface_tension": 0.07, "stiffness": 3000, "cfl": 0.4,
                 "min_dt": 0.0002, "max_dt": 0.004, "density_tolerance": 0.001,
                 "divergence_tolerance": 0.002, "max_iterations": 7, "lifetime": 9, "resort_every": 11},
      "domain": {"min": [-1, -2, -3], "max": [4, 5, 6]},
      "fluid": [{"shape": "box", "box": {"min": [0, 0, 0], "max": [1, 2, 3]}, "velocity": [0.1, 0.2, 0.3]},
                {"shape": "sphere", "center": [2, 2, 2], "radius": 0.5}],
      "colliders": [{"kind": "box", "box": {"min": [0, 0, 0], "max": [0, 1, 1]}},
                    {"kind": "sphere", "center": [1, 1, 1], "radius": 0.25},
                    {"kind": "plane", "point": [0, 1, 0], "normal": [0, 0, 2]},
                    {"kind": "mesh", "mesh": "/abs/m.PLY", "scale": [2, 3, 4], "translate": [5, 6, 7]}],
      "emitters": [{"position": [1, 1, 1], "direction": [1, 0, 0], "radius": 0.1, "speed": 2,
                    "rate": 300, "start": 0.5, "end": 1.5}],
      "drains": [{"box": {"min": [3, -2, -3], "max": [4, 0, 6]}}]
    })";
    auto r = parseScene(text, "dir/all.json");
    ASSERT_TRUE(r.ok()) << r.error().describe();
    const Scene& s = r.value();
    EXPECT_EQ(s.name, "all");
    EXPECT_DOUBLE_EQ(s.duration, 2.5);
    EXPECT_DOUBLE_EQ(s.fps, 60.0);
    const SimParams want{.solver = Solver::Sph, .radius = 0.03f, .restDensity = 998.0f, .particleVolume = 0.9f,
                         .gravity = {1.0f, -2.0f, 3.0f}, .viscosity = 0.2f, .surfaceTension = 0.07f,
                         .stiffness = 3000.0f, .cfl = 0.4f, .minDt = 0.0002f, .maxDt = 0.004f,
                         .densityTolerance = 0.001f, .divergenceTolerance = 0.002f, .maxIterations = 7,
                         .lifetime = 9.0f, .resortEvery = 11};
    expectParams(s.params, want);
    expectVec(s.domain.min, -1, -2, -3);
    expectVec(s.domain.max, 4, 5, 6);
    ASSERT_EQ(s.fluid.size(), 2u);
    expectVec(s.fluid[0].box.max, 1, 2, 3);
    expectVec(s.fluid[0].velocity, 0.1f, 0.2f, 0.3f);
    EXPECT_EQ(s.fluid[1].shape, FluidBlock::Shape::Sphere);
    expectVec(s.fluid[1].center, 2, 2, 2);
    EXPECT_FLOAT_EQ(s.fluid[1].radius, 0.5f);
    expectVec(s.fluid[1].box.min, 1.5f, 1.5f, 1.5f);
    ASSERT_EQ(s.colliders.size(), 4u);
    EXPECT_EQ(s.colliders[0].kind, Collider::Kind::Box);
    expectVec(s.colliders[0].box.max, 0, 1, 1);  // a thin plate is allowed
    EXPECT_EQ(s.colliders[1].kind, Collider::Kind::Sphere);
    expectVec(s.colliders[1].center, 1, 1, 1);
    EXPECT_FLOAT_EQ(s.colliders[1].radius, 0.25f);
    EXPECT_EQ(s.colliders[2].kind, Collider::Kind::Plane);
    expectVec(s.colliders[2].point, 0, 1, 0);
    expectVec(s.colliders[2].normal, 0, 0, 2);
    EXPECT_EQ(s.colliders[3].kind, Collider::Kind::Mesh);
    EXPECT_EQ(s.colliders[3].mesh, fs::path("/abs/m.PLY"));  // absolute: kept
    expectVec(s.colliders[3].scale, 2, 3, 4);
    expectVec(s.colliders[3].translate, 5, 6, 7);
    ASSERT_EQ(s.emitters.size(), 1u);
    expectEmitter(s.emitters[0], Emitter{.position = {1, 1, 1}, .direction = {1, 0, 0}, .radius = 0.1f,
                                         .speed = 2.0f, .rate = 300.0f, .start = 0.5f, .end = 1.5f});
    ASSERT_EQ(s.drains.size(), 1u);
    expectVec(s.drains[0].box.min, 3, -2, -3);
}

TEST(SimSceneFields, RelativeMeshPathsResolveAgainstTheScenesFolder) {
    json j = json::parse(kMinimal);
    j["colliders"] = json::parse(R"([{"kind": "mesh", "mesh": "../models/cup.obj"}])");
    auto r = parseScene(j.dump(), "data/scenes/a.json");
    ASSERT_TRUE(r.ok()) << r.error().describe();
    EXPECT_EQ(r.value().colliders[0].mesh, fs::path("data/models/cup.obj"));
}

// ---- malformed scenes ------------------------------------------------------------

// A valid scene with one of each part; each bad case edits one thing.
json baseScene() {
    return json::parse(R"({
      "version": 1,
      "params": {"radius": 0.02},
      "domain": {"min": [0, 0, 0], "max": [1, 1, 1]},
      "fluid": [{"box": {"min": [0.1, 0.1, 0.1], "max": [0.5, 0.5, 0.5]}},
                {"box": {"min": [0.6, 0.1, 0.1], "max": [0.9, 0.5, 0.5]}}],
      "colliders": [{"kind": "sphere", "center": [0.7, 0.8, 0.5], "radius": 0.1}],
      "emitters": [{"position": [0.5, 0.9, 0.5]}],
      "drains": [{"box": {"min": [0.9, 0, 0], "max": [1, 0.1, 1]}}]
    })");
}

struct BadScene {
    const char* label;
    std::function<void(json&)> edit;  // applied to baseScene(), or
    const char* text;                 // used as it is when edit is empty
    const char* path;                 // the field path the error must name ("" for none)
    const char* problem;              // words the error must contain
};

const std::vector<BadScene>& badScenes() {
    static const std::vector<BadScene> cases = {
        {"radius zero", [](json& j) { j["params"]["radius"] = 0; }, nullptr, "params.radius", "must be > 0"},
        {"radius negative", [](json& j) { j["params"]["radius"] = -0.01; }, nullptr, "params.radius", "must be > 0, got -0.01"},
        {"radius a string", [](json& j) { j["params"]["radius"] = "0.02"; }, nullptr, "params.radius", "expected a number, got a string (\"0.02\")"},
        {"radius underflows a float", [](json& j) { j["params"]["radius"] = 1e-50; }, nullptr, "params.radius", "1e-50 is too small for a 32-bit float"},
        {"box corner missing", [](json& j) { j["domain"].erase("min"); j["domain"]["mni"] = {0, 0, 0}; }, nullptr, "domain.min", "missing (is \"mni\" a misspelling of it?)"},
        {"density beyond float", [](json& j) { j["params"]["rest_density"] = 1e39; }, nullptr, "params.rest_density", "out of range for a 32-bit float"},
        {"fps zero", [](json& j) { j["fps"] = 0; }, nullptr, "fps", "must be > 0"},
        {"duration negative", [](json& j) { j["duration"] = -1; }, nullptr, "duration", "must be >= 0"},
        {"domain min > max", [](json& j) { j["domain"]["max"][1] = -1; }, nullptr, "domain.max", "max.y = -1 must be above min.y = 0"},
        {"domain flat", [](json& j) { j["domain"]["max"][2] = 0; }, nullptr, "domain.max", "must be above min.z"},
        {"domain missing", [](json& j) { j.erase("domain"); }, nullptr, "domain", "missing"},
        {"domain min missing", [](json& j) { j["domain"].erase("min"); }, nullptr, "domain.min", "missing; a box {"},
        {"fluid box min > max", [](json& j) { j["fluid"][0]["box"]["min"][0] = 0.7; }, nullptr, "fluid[0].box.max", "max.x = 0.5 must be above min.x = 0.7"},
        {"fluid block outside", [](json& j) { j["fluid"][1]["box"]["max"][1] = 1.5; }, nullptr, "fluid[1].box", "above the domain's max.y = 1"},
        {"fluid block below", [](json& j) { j["fluid"][1]["box"]["min"][2] = -0.2; }, nullptr, "fluid[1].box", "below the domain's min.z = 0"},
        {"fluid without box", [](json& j) { j["fluid"][0].erase("box"); }, nullptr, "fluid[0].box", "missing"},
        {"fluid not an array", [](json& j) { j["fluid"] = j["fluid"][0]; }, nullptr, "fluid", "expected an array"},
        {"unknown fluid shape", [](json& j) { j["fluid"][0]["shape"] = "cone"; }, nullptr, "fluid[0].shape", "unknown shape \"cone\""},
        {"ball outside", [](json& j) { j["fluid"][0] = json::parse(R"({"shape": "sphere", "center": [0.5, 0.95, 0.5], "radius": 0.1})"); }, nullptr, "fluid[0].radius", "the ball reaches y = 1.05"},
        {"sphere block given a box", [](json& j) { j["fluid"][0]["shape"] = "sphere"; j["fluid"][0]["center"] = {0.5, 0.5, 0.5}; j["fluid"][0]["radius"] = 0.1; }, nullptr, "fluid[0].box", "unknown key"},
        {"gravity of two", [](json& j) { j["params"]["gravity"] = {0, -9.81}; }, nullptr, "params.gravity", "expected an array of 3 numbers [x, y, z], got an array of 2"},
        {"gravity with null", [](json& j) { j["params"]["gravity"] = json::parse("[0, null, 0]"); }, nullptr, "params.gravity[1]", "expected a number, got null"},
        {"unknown solver", [](json& j) { j["params"]["solver"] = "dsph"; }, nullptr, "params.solver", "unknown solver \"dsph\"; the solvers are dfsph, sph, ballistic, pbf"},
        {"fractional iterations", [](json& j) { j["params"]["max_iterations"] = 2.5; }, nullptr, "params.max_iterations", "whole number"},
        {"zero iterations", [](json& j) { j["params"]["max_iterations"] = 0; }, nullptr, "params.max_iterations", "must be from 1"},
        {"max_dt below min_dt", [](json& j) { j["params"]["min_dt"] = 0.01; j["params"]["max_dt"] = 0.001; }, nullptr, "params.max_dt", "below min_dt = 0.01"},
        {"tolerance as a percentage", [](json& j) { j["params"]["density_tolerance"] = 5; }, nullptr, "params.density_tolerance", "must be below 1"},
        {"negative lifetime", [](json& j) { j["params"]["lifetime"] = -1; }, nullptr, "params.lifetime", "must be >= 0"},
        {"params not an object", [](json& j) { j["params"] = 3; }, nullptr, "params", "expected an object"},
        {"collider kind unknown", [](json& j) { j["colliders"][0]["kind"] = "cone"; }, nullptr, "colliders[0].kind", "unknown collider kind \"cone\""},
        {"collider without kind", [](json& j) { j["colliders"][0].erase("kind"); }, nullptr, "colliders[0].kind", "missing"},
        {"sphere collider radius 0", [](json& j) { j["colliders"][0]["radius"] = 0; }, nullptr, "colliders[0].radius", "must be > 0"},
        {"box collider given a radius", [](json& j) { j["colliders"][0] = json::parse(R"({"kind": "box", "box": {"min": [0,0,0], "max": [1,1,1]}, "radius": 1})"); }, nullptr, "colliders[0].radius", "unknown key; a box collider has the keys: kind, box"},
        {"box collider min > max", [](json& j) { j["colliders"][0] = json::parse(R"({"kind": "box", "box": {"min": [0,2,0], "max": [1,1,1]}})"); }, nullptr, "colliders[0].box.max", "must be at least min.y = 2"},
        {"plane normal zero", [](json& j) { j["colliders"][0] = json::parse(R"({"kind": "plane", "point": [0,0,0], "normal": [0,0,0]})"); }, nullptr, "colliders[0].normal", "must not be [0, 0, 0]"},
        {"mesh not OBJ or PLY", [](json& j) { j["colliders"][0] = json::parse(R"({"kind": "mesh", "mesh": "cup.stl"})"); }, nullptr, "colliders[0].mesh", "not an OBJ or PLY file"},
        {"mesh scale negative", [](json& j) { j["colliders"][0] = json::parse(R"({"kind": "mesh", "mesh": "cup.obj", "scale": [1, -1, 1]})"); }, nullptr, "colliders[0].scale[1]", "must be > 0, got -1"},
        {"emitter outside", [](json& j) { j["emitters"][0]["position"] = {0.5, 1.2, 0.5}; }, nullptr, "emitters[0].position", "the nozzle reaches y = 1.2, above the domain's max.y = 1"},
        {"emitter ends before it starts", [](json& j) { j["emitters"][0]["start"] = 2; j["emitters"][0]["end"] = 1; }, nullptr, "emitters[0].end", "before start = 2"},
        {"emitter speed 0", [](json& j) { j["emitters"][0]["speed"] = 0; }, nullptr, "emitters[0].speed", "must be > 0"},
        {"emitter direction zero", [](json& j) { j["emitters"][0]["direction"] = {0, 0, 0}; }, nullptr, "emitters[0].direction", "must not be [0, 0, 0]"},
        {"emitter without position", [](json& j) { j["emitters"][0].erase("position"); }, nullptr, "emitters[0].position", "missing"},
        {"drain outside", [](json& j) { j["drains"][0]["box"] = json::parse(R"({"min": [2,0,0], "max": [3,1,1]})"); }, nullptr, "drains[0].box", "outside the domain along x"},
        {"nothing to simulate", [](json& j) { j.erase("fluid"); j.erase("emitters"); }, nullptr, "fluid", "no fluid block and no emitter"},
        {"version 2", [](json& j) { j["version"] = 2; }, nullptr, "version", "this reader knows version 1"},
        {"name a number", [](json& j) { j["name"] = 3; }, nullptr, "name", "expected a string, got a number"},
        {"misspelt key", [](json& j) { j["params"]["raduis"] = 0.01; }, nullptr, "params.raduis", "unknown key (did you mean \"radius\"?)"},
        {"param at the top", [](json& j) { j["radius"] = 0.01; }, nullptr, "radius", "unknown key (it belongs inside \"params\")"},
        {"unknown emitter key", [](json& j) { j["emitters"][0]["velocity"] = {0, 0, 0}; }, nullptr, "emitters[0].velocity", "an emitter has the keys: position, direction"},
        {"top level an array", {}, "[1, 2]", "", "expected an object {...} (a scene), got an array"},
        {"syntax error", {}, "{\n  \"domain\": {\"min\": [0, 0, 0],\n     \"max\": [1, 1 1]}\n}", "", "JSON error at line 3, column 19: syntax error while parsing array"},
        {"unterminated", {}, "{\"domain\": ", "", "JSON error at line 1, column 12: syntax error"},
        {"empty file", {}, "", "", "JSON error at line 1, column 1: syntax error"},
        {"number overflow", {}, "{\"duration\": 1e400}", "", "number overflow"},
        {"repeated key", {}, "{\"params\": {\"radius\": 0.01, \"radius\": 0.02}}", "params.radius", "repeated key"},
        {"repeated key in an array", {}, "{\"fluid\": [{}, {\"box\": 1, \"box\": 2}]}", "fluid[1].box", "repeated key"},
        {"too deep", {}, "{\"a\": [[[[[[[[[[[[[[[[[[[[]]]]]]]]]]]]]]]]]]]}", "", "nested deeper than 16 levels (line 1, column 22)"},
        {"fps past counting", [](json& j) { j["fps"] = 3e38; }, nullptr, "fps", "must be at most 1000, got 3e+38"},
        {"duration past counting", [](json& j) { j["duration"] = 3e38; }, nullptr, "duration", "must be at most 1e+06 s"},
    };
    return cases;
}

TEST(SimSceneErrors, EachNamesTheFileTheFieldAndTheProblem) {
    const std::string name = "scenes/bad_scene.json";
    ASSERT_GE(badScenes().size(), 15u);
    for (const BadScene& c : badScenes()) {
        SCOPED_TRACE(c.label);
        std::string text = c.text ? c.text : "";
        if (c.edit) {
            json j = baseScene();
            c.edit(j);
            text = j.dump(2);
        }
        auto r = parseScene(text, name);
        ASSERT_FALSE(r.ok()) << "accepted: " << text;
        EXPECT_EQ(r.error().file, name);
        const std::string said = r.error().describe();
        const std::string where = std::string(c.path).empty() ? name + ": " : name + ": " + c.path + ": ";
        EXPECT_EQ(said.rfind(where, 0), 0u) << "expected it to start with '" << where << "': " << said;
        EXPECT_NE(said.find(c.problem), std::string::npos) << "expected '" << c.problem << "' in: " << said;
    }
}

// The base of the table is itself valid, so each case fails for its own edit.
TEST(SimSceneErrors, TheBaseSceneIsValid) {
    auto r = parseScene(baseScene().dump(), "base.json");
    EXPECT_TRUE(r.ok()) << r.error().describe();
}

TEST(SimSceneErrors, UnknownKeyListsTheKnownOnes) {
    json j = baseScene();
    j["params"]["viscosityy"] = 1;
    auto r = parseScene(j.dump(), "x.json");
    ASSERT_FALSE(r.ok());
    const std::string said = r.error().describe();
    EXPECT_NE(said.find("did you mean \"viscosity\""), std::string::npos) << said;
    for (const char* key : {"solver", "radius", "rest_density", "density_tolerance", "resort_every"})
        EXPECT_NE(said.find(key), std::string::npos) << key << " not listed in: " << said;
}

TEST(SimSceneErrors, ReadSceneNamesTheFile) {
    const fs::path dir = test::tempDir();
    auto missing = readScene(dir / "nope.json");
    ASSERT_FALSE(missing.ok());
    EXPECT_NE(missing.error().describe().find("nope.json"), std::string::npos);

    // A mesh collider whose file is not beside the scene: named with its field.
    json j = json::parse(kMinimal);
    j["colliders"] = json::parse(R"([{"kind": "mesh", "mesh": "cup.obj"}])");
    test::writeText(dir / "cup_scene.json", j.dump());
    auto noMesh = readScene(dir / "cup_scene.json");
    ASSERT_FALSE(noMesh.ok());
    const std::string said = noMesh.error().describe();
    EXPECT_EQ(said.rfind((dir / "cup_scene.json").string() + ": colliders[0].mesh: no such file", 0), 0u) << said;
    EXPECT_NE(said.find((dir / "cup.obj").string()), std::string::npos) << said;
    test::writeText(dir / "cup.obj", "v 0 0 0\n");
    auto withMesh = readScene(dir / "cup_scene.json");
    ASSERT_TRUE(withMesh.ok()) << withMesh.error().describe();
    EXPECT_EQ(withMesh.value().colliders[0].mesh, dir / "cup.obj");
    EXPECT_EQ(withMesh.value().file, dir / "cup_scene.json");

    // A file far larger than any scene is refused before it is read.
    std::string big(5u << 20, ' ');
    big.replace(0, std::string(kMinimal).size(), kMinimal);
    test::writeText(dir / "big.json", big);
    auto tooBig = readScene(dir / "big.json");
    ASSERT_FALSE(tooBig.ok());
    EXPECT_NE(tooBig.error().describe().find("larger than the 4 MiB a simulation scene may be"), std::string::npos)
        << tooBig.error().describe();
}

// A field's value is the settings' error (Error::usage: the CLI exits 2);
// text that is not JSON is the data's (1).
TEST(SimSceneErrors, ValuesAreUsageErrorsSyntaxIsNot) {
    json j = baseScene();
    j["fps"] = -1;
    auto bad = parseScene(j.dump(), "v.json");
    ASSERT_FALSE(bad.ok());
    EXPECT_TRUE(bad.error().usage) << bad.error().describe();
    auto broken = parseScene("{\"fps\": ", "s.json");
    ASSERT_FALSE(broken.ok());
    EXPECT_FALSE(broken.error().usage) << broken.error().describe();
}

// ---- the docs -----------------------------------------------------------------

// The keys an object accepts, as its unknown-key error lists them.
std::vector<std::string> keysOf(const std::function<void(json&)>& addUnknown) {
    json j = baseScene();
    addUnknown(j);
    auto r = parseScene(j.dump(), "k.json");
    EXPECT_FALSE(r.ok());
    if (r.ok()) return {};
    const std::string said = r.error().message;
    const std::string marker = "has the keys: ";
    const std::size_t at = said.find(marker);
    EXPECT_NE(at, std::string::npos) << said;
    if (at == std::string::npos) return {};
    std::vector<std::string> keys;
    std::istringstream list(said.substr(at + marker.size()));
    for (std::string k; std::getline(list, k, ',');) keys.push_back(k.substr(k.find_first_not_of(' ')));
    return keys;
}

// docs/scenes.md documents every key the reader accepts (as `key`), so a key
// added to the reader without its documentation fails here.
TEST(SimSceneDocs, EveryKeyIsDocumented) {
    const std::string doc = readText(sourceDir() / "docs" / "scenes.md");
    ASSERT_FALSE(doc.empty());
    const std::vector<std::function<void(json&)>> objects = {
        [](json& j) { j["zz"] = 1; },
        [](json& j) { j["params"]["zz"] = 1; },
        [](json& j) { j["domain"]["zz"] = 1; },
        [](json& j) { j["fluid"][0]["zz"] = 1; },
        [](json& j) { j["fluid"][0] = json::parse(R"({"shape": "sphere", "center": [0.5,0.5,0.5], "radius": 0.1, "zz": 1})"); },
        [](json& j) { j["colliders"][0]["zz"] = 1; },
        [](json& j) { j["colliders"][0] = json::parse(R"({"kind": "box", "box": {"min": [0,0,0], "max": [1,1,1]}, "zz": 1})"); },
        [](json& j) { j["colliders"][0] = json::parse(R"({"kind": "plane", "point": [0,0,0], "normal": [0,1,0], "zz": 1})"); },
        [](json& j) { j["colliders"][0] = json::parse(R"({"kind": "mesh", "mesh": "a.obj", "zz": 1})"); },
        [](json& j) { j["emitters"][0]["zz"] = 1; },
        [](json& j) { j["drains"][0]["zz"] = 1; },
    };
    std::set<std::string> all;
    for (const auto& add : objects)
        for (const auto& key : keysOf(add)) all.insert(key);
    EXPECT_GE(all.size(), 40u);
    for (const auto& key : all) EXPECT_NE(doc.find("`" + key + "`"), std::string::npos) << "docs/scenes.md lacks `" << key << "`";
    for (const char* word : {"dfsph", "sph", "ballistic", "pbf", "box", "sphere", "plane", "mesh"})
        EXPECT_NE(doc.find(std::string("`\"") + word + "\"`"), std::string::npos) << "docs/scenes.md lacks `\"" << word << "\"`";
}

}  // namespace
}  // namespace meniscus::sim::sim_scene_test_local
