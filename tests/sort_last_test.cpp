// Sort-last rendering (include/meniscus/sort_last.h): the splat's
// partials of any split of the particles combine exactly (nearest depth,
// wrapping sums of the fixed-point chords) into the whole's, so the root's
// picture is bit-identical to the one-process render. Here K "processes" run
// one after another in this process through an in-process compositor: shares
// 1 .. K-1 render first (not the root) and leave their partials in a shared
// store; share 0, the root, renders last and combines them all.
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "cpu/splat.h"
#include "cpu/thickness.h"
#include "meniscus/io.h"
#include "meniscus/particle_view.h"
#include "meniscus/particles.h"
#include "meniscus/renderer.h"
#include "meniscus/sort_last.h"
#include "shared/splat_chords.h"
#include "test_util.h"

namespace meniscus::sort_last_test_local {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// `into` combined with `other` as a compositor must: the nearest depth, the
// chords added mod 2^32.
void combine(SplatPartial& into, const SplatPartial& other) {
    ASSERT_EQ(into.depth.width, other.depth.width);
    ASSERT_EQ(into.depth.height, other.depth.height);
    ASSERT_EQ(into.chords.width, other.chords.width);
    ASSERT_EQ(into.chords.height, other.chords.height);
    for (std::size_t i = 0; i < into.depth.size(); ++i)
        into.depth.pixels[i] = std::min(into.depth.pixels[i], other.depth.pixels[i]);
    for (std::size_t i = 0; i < into.chords.size(); ++i) into.chords.pixels[i] += other.chords.pixels[i];
}

// The partials the processes that are not the root left, in the order they ran.
struct PartialStore {
    std::vector<SplatPartial> partials;
};

class InProcessCompositor final : public SplatCompositor {
public:
    InProcessCompositor(PartialStore& store, bool root) : store_(store), root_(root) {}
    Status composite(SplatPartial& partial) override {
        ++calls;
        if (!root_) {
            store_.partials.push_back(partial);
            partial = {};  // "unspecified" afterwards: nothing left
            return okStatus();
        }
        for (const SplatPartial& other : store_.partials) combine(partial, other);
        return okStatus();
    }
    bool root() const override { return root_; }
    int calls = 0;

private:
    PartialStore& store_;
    bool root_;
};

// The real small dam-break frame (test_util).
const ParticleSet& realFrame() { return test::smallFrame21(); }

// Spheres (the whole-frame shares turn the kernels on), and the whole data's
// studio, which sort-last needs set.
RenderSettings realFrameSettings(int width = 320, int height = 180) {
    const ParticleSet& set = realFrame();
    RenderSettings s = test::autoFramedSettings(set, width, height);
    s.anisotropy.enabled = false;
    s.scene.studioBounds = computeBounds(set.positions);
    return s;
}

// One share's particles: copies of the positions (and radii) it holds.
struct Share {
    std::vector<glm::vec3> positions;
    std::vector<float> radii;
    ParticleView view() const {
        ParticleView v{std::span<const glm::vec3>(positions)};
        if (!radii.empty()) v.radius = StridedView<float>(std::span<const float>(radii));
        return v;
    }
};

// The particles dealt at random into k shares of uneven sizes (share s
// takes weights[s] parts; a weight of 0 leaves it empty).
std::vector<Share> split(std::span<const glm::vec3> pts, std::span<const float> radii, const std::vector<int>& weights,
                         unsigned seed) {
    std::vector<Share> shares(weights.size());
    std::vector<int> table;
    for (std::size_t s = 0; s < weights.size(); ++s) table.insert(table.end(), std::size_t(weights[s]), int(s));
    std::mt19937 rng(seed);
    std::uniform_int_distribution<std::size_t> pick(0, table.size() - 1);
    for (std::size_t i = 0; i < pts.size(); ++i) {
        Share& sh = shares[std::size_t(table[pick(rng)])];
        sh.positions.push_back(pts[i]);
        if (!radii.empty()) sh.radii.push_back(radii[i]);
    }
    return shares;
}

// One frame on `renderer`, or on a fresh CPU renderer when null.
Result<Aovs> renderOn(Renderer* renderer, const ParticleView& particles, const RenderSettings& s,
                      std::vector<StageTime>* times = nullptr) {
    return renderer ? renderer->render(particles, s, times) : renderFrame(particles, s, times);
}

// Renders the shares as K processes would: 1 .. K-1 first (each must return
// empty Aovs), then the root (share 0), whose Aovs are returned. `stages`
// (when given) gets the root's stage names. On `renderer` (one for all, as
// the processes run one after another), or fresh CPU renderers.
Result<Aovs> renderSortLast(const std::vector<Share>& shares, RenderSettings s,
                            std::vector<std::string>* stages = nullptr, Renderer* renderer = nullptr) {
    PartialStore store;
    for (std::size_t k = 1; k < shares.size(); ++k) {
        InProcessCompositor c(store, false);
        s.compositor = &c;
        std::vector<StageTime> times;
        auto r = renderOn(renderer, shares[k].view(), s, &times);
        if (!r) return r;
        EXPECT_EQ(c.calls, 1);
        EXPECT_TRUE(r->color.empty() && r->depth.empty() && r->rawDepth.empty() && r->thickness.empty() &&
                    r->normal.empty())
            << "share " << k << " is not the root";
        std::vector<std::string> names;
        for (const StageTime& t : times) names.push_back(t.stage);
        EXPECT_EQ(names.back(), "composite") << "a process other than the root stops after the composite";
    }
    InProcessCompositor root(store, true);
    s.compositor = &root;
    std::vector<StageTime> times;
    auto r = renderOn(renderer, shares[0].view(), s, &times);
    EXPECT_EQ(root.calls, 1);
    if (stages)
        for (const StageTime& t : times) stages->push_back(t.stage);
    return r;
}

template <class T>
bool sameBits(const Image<T>& a, const Image<T>& b) {
    // (memcmp of an empty image's null data would be undefined: sizes first.)
    return a.width == b.width && a.height == b.height && a.size() == b.size() &&
           (a.size() == 0 || std::memcmp(a.pixels.data(), b.pixels.data(), a.size() * sizeof(T)) == 0);
}

// Every AOV of `got` has the bits of `want`.
void expectSameImage(const Aovs& want, const Aovs& got, const std::string& what) {
    ASSERT_FALSE(want.color.empty()) << what;
    EXPECT_TRUE(sameBits(want.color, got.color)) << what << ": color";
    EXPECT_TRUE(sameBits(want.depth, got.depth)) << what << ": depth";
    EXPECT_TRUE(sameBits(want.rawDepth, got.rawDepth)) << what << ": raw depth";
    EXPECT_TRUE(sameBits(want.thickness, got.thickness)) << what << ": thickness";
    EXPECT_TRUE(sameBits(want.normal, got.normal)) << what << ": normal";
    EXPECT_TRUE(sameBits(want.silhouette, got.silhouette)) << what << ": silhouette";
}

// The splits every look is checked with: K = 1 .. 4, uneven, one with an
// empty share (a process that holds nothing of this frame), one where the
// root holds nothing.
const std::vector<std::vector<int>> kSplits = {{1}, {3, 1}, {1, 5, 2}, {2, 1, 0, 4}, {0, 1, 1}};

void expectSortLastMatches(const RenderSettings& s, const std::string& what, std::span<const float> radii = {},
                           Renderer* renderer = nullptr) {
    const ParticleSet& set = realFrame();
    ParticleView all{std::span<const glm::vec3>(set.positions)};
    if (!radii.empty()) all.radius = StridedView<float>(radii);
    auto whole = renderOn(renderer, all, s);
    ASSERT_TRUE(whole) << whole.error().describe();
    double thickness = 0.0;
    for (float t : whole->thickness.pixels) thickness += t;
    ASSERT_GT(thickness, 0.0) << what << ": the frame shows liquid";
    unsigned seed = 1;
    for (const std::vector<int>& weights : kSplits) {
        const std::vector<Share> shares = split(set.positions, radii, weights, seed++);
        auto parts = renderSortLast(shares, s, nullptr, renderer);
        ASSERT_TRUE(parts) << parts.error().describe();
        expectSameImage(*whole, *parts, what + ", " + std::to_string(weights.size()) + " shares");
    }
}

}  // namespace

// ---- The splat's partials (cpu::splatPartial / cpu::resolveThickness) -----

// The partials of two subsets of the particles combine into the whole's
// partial exactly (depth and chord bits), at every thickness grid, with a
// scene depth clipping the chords and with spheres of their own radii; the
// order of the particles changes nothing; and resolving the whole's partial
// is splatDepthAndThickness.
TEST(SortLastPartial, SubsetsSumExactlyToTheWhole) {
    const ParticleSet& set = realFrame();
    const RenderSettings s = realFrameSettings();
    const Camera& cam = s.camera;
    const float r = s.radiusM;
    // A scene plane cutting the middle third of the image at the median fluid depth.
    const Image<float> depthAll = cpu::splatDepth(cam, set.positions, r);
    std::vector<float> finite;
    for (float z : depthAll.pixels)
        if (z < kInf) finite.push_back(z);
    ASSERT_GT(finite.size(), 1000u);
    std::nth_element(finite.begin(), finite.begin() + finite.size() / 2, finite.end());
    Image<float> scene(cam.width, cam.height, kInf);
    for (int y = 0; y < cam.height; ++y)
        for (int x = cam.width / 3; x < 2 * cam.width / 3; ++x) scene.at(x, y) = finite[finite.size() / 2];
    // Own radii: spheres of 0.7 .. 1.3 r.
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(0.7f, 1.3f);
    std::vector<EllipsoidShape> spheres;
    for (std::size_t i = 0; i < set.positions.size(); ++i) spheres.push_back(sphereShape(u(rng) * r));

    for (bool ownRadii : {false, true})
        for (int divisor : {1, 2, 4}) {
            ThicknessParams tp;
            tp.resolutionDivisor = divisor;
            const std::span<const EllipsoidShape> shapes = ownRadii ? std::span<const EllipsoidShape>(spheres)
                                                                    : std::span<const EllipsoidShape>();
            const SplatPartial whole = cpu::splatPartial(cam, set.positions, r, tp, &scene, shapes);
            // Interleaved subsets: every pixel gets chords from both.
            std::vector<glm::vec3> a, b;
            std::vector<EllipsoidShape> sa, sb;
            for (std::size_t i = 0; i < set.positions.size(); ++i) {
                (i % 3 == 1 ? b : a).push_back(set.positions[i]);
                if (ownRadii) (i % 3 == 1 ? sb : sa).push_back(spheres[i]);
            }
            SplatPartial pa = cpu::splatPartial(cam, a, r, tp, &scene, sa);
            const SplatPartial pb = cpu::splatPartial(cam, b, r, tp, &scene, sb);
            const std::string what = "divisor " + std::to_string(divisor) + (ownRadii ? ", own radii" : "");
            // The subsets' chords are each less than the whole's, somewhere.
            std::size_t partly = 0;
            for (std::size_t i = 0; i < whole.chords.size(); ++i)
                partly += pa.chords.pixels[i] != 0 && pb.chords.pixels[i] != 0;
            EXPECT_GT(partly, 100u) << what;
            combine(pa, pb);
            EXPECT_TRUE(sameBits(whole.depth, pa.depth)) << what;
            EXPECT_TRUE(sameBits(whole.chords, pa.chords)) << what;
            // The particles in reverse order: the same sums.
            std::vector<glm::vec3> reversed(set.positions.rbegin(), set.positions.rend());
            std::vector<EllipsoidShape> reversedShapes(spheres.rbegin(), spheres.rend());
            const SplatPartial backwards =
                cpu::splatPartial(cam, reversed, r, tp, &scene,
                                  ownRadii ? std::span<const EllipsoidShape>(reversedShapes)
                                           : std::span<const EllipsoidShape>());
            EXPECT_TRUE(sameBits(whole.chords, backwards.chords)) << what;
            // The thickness grid's size.
            EXPECT_EQ(whole.chords.width, (cam.width + divisor - 1) / divisor);
            EXPECT_EQ(whole.chords.height, (cam.height + divisor - 1) / divisor);
            // splatDepthAndThickness is the partial resolved.
            const cpu::DepthAndThickness one = cpu::splatDepthAndThickness(cam, set.positions, r, tp, &scene, shapes);
            EXPECT_TRUE(sameBits(one.depth, whole.depth)) << what;
            EXPECT_TRUE(sameBits(one.thickness, cpu::resolveThickness(cam, pa, r, tp))) << what;
        }
}

// Each chord is rounded to the nearest unit of r / kChordScale and the sum
// resolved as GL's splat_resolve.comp does; a huge chord is clamped, not
// undefined.
TEST(SortLastPartial, FixedPointFormulas) {
    const float r = 0.05f;
    EXPECT_EQ(shared::chordToFixed(r, r), 32768u);
    EXPECT_EQ(shared::chordToFixed(2.0f * r, r), 65536u);
    EXPECT_EQ(shared::chordToFixed(r / 32768.0f * 0.49f, r), 0u);
    EXPECT_EQ(shared::chordToFixed(r / 32768.0f * 0.51f, r), 1u);
    EXPECT_EQ(shared::chordToFixed(1e30f, r), 2147483520u);
    EXPECT_EQ(shared::chordToFixed(kInf, r), 2147483520u);
    const float w = 6.0f / 3.14159265f;
    EXPECT_EQ(shared::chordSumToMetres(65536u, r, w), (float(65536u) * (r / 32768.0f)) * w);
    EXPECT_EQ(shared::chordSumToMetres(0u, r, w), 0.0f);
}

// ---- The pipeline with a compositor ----------------------------------------

TEST(SortLast, DefaultLookIsBitIdenticalForAnySplit) {
    expectSortLastMatches(realFrameSettings(), "default look");
}

TEST(SortLast, ThicknessOptionsAreBitIdentical) {
    RenderSettings s = realFrameSettings();
    s.thickness.blurSigmaRadii = 2.0f;
    expectSortLastMatches(s, "thickness blur 2 r");
    s.thickness.resolutionDivisor = 2;
    expectSortLastMatches(s, "thickness resolution divisor 2");
    s.thickness.resolutionDivisor = 4;
    s.thickness.blurSigmaRadii = 0.0f;
    expectSortLastMatches(s, "thickness resolution divisor 4, no blur");
}

TEST(SortLast, ReducedResolutionIsBitIdentical) {
    RenderSettings s = realFrameSettings();
    s.fluidScale = 0.5f;
    expectSortLastMatches(s, "fluid scale 0.5");
    s.fluidScale = 0.25f;
    s.thickness.resolutionDivisor = 2;
    expectSortLastMatches(s, "fluid scale 0.25, thickness divisor 2");
}

TEST(SortLast, OwnRadiiAreBitIdentical) {
    const RenderSettings s = realFrameSettings();
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(0.75f, 1.25f);
    std::vector<float> radii(realFrame().positions.size());
    for (float& v : radii) v = u(rng) * s.radiusM;
    expectSortLastMatches(s, "own radii", radii);
}

TEST(SortLast, FiltersAreBitIdentical) {
    for (const char* name : {"none", "gaussian", "bilateral", "curvature-flow"}) {
        RenderSettings s = realFrameSettings();
        ASSERT_TRUE(filterFromName(name, &s.filter));
        expectSortLastMatches(s, name);
    }
    RenderSettings s = realFrameSettings();
    std::get<NarrowRangeParams>(s.filter).separable = true;
    expectSortLastMatches(s, "narrow-range (separable)");
}

TEST(SortLast, StudioSilhouetteAndHoleFillingAreBitIdentical) {
    RenderSettings s = realFrameSettings();
    s.silhouette.enabled = true;
    s.scene.background = false;
    expectSortLastMatches(s, "silhouette, no background");
    s = realFrameSettings();
    s.scene.walls = false;
    s.holeFill.enabled = false;
    expectSortLastMatches(s, "floor only, no hole filling");
}

// The debug views are drawn on the root from the combined AOVs.
TEST(SortLast, DebugViewsAreBitIdentical) {
    for (View v : {View::Thickness, View::RawDepth}) {
        RenderSettings s = realFrameSettings();
        s.view = v;
        s.colorOnly = true;
        const ParticleSet& set = realFrame();
        auto whole = renderFrame(set.positions, s);
        ASSERT_TRUE(whole);
        auto parts = renderSortLast(split(set.positions, {}, {1, 2, 1}, 9), s);
        ASSERT_TRUE(parts) << parts.error().describe();
        EXPECT_TRUE(sameBits(whole->color, parts->color));
    }
}

// The root's stages: the splat in three, the rest as usual; a process that is
// not the root stops after the composite (checked in renderSortLast), and
// without a compositor the stage names stay.
TEST(SortLast, StageNames) {
    const RenderSettings s = realFrameSettings(160, 90);
    const ParticleSet& set = realFrame();
    std::vector<std::string> stages;
    ASSERT_TRUE(renderSortLast(split(set.positions, {}, {1, 1}, 3), s, &stages));
    EXPECT_EQ(stages, (std::vector<std::string>{"scene", "depth-splat", "composite", "thickness", "fill-holes",
                                                "smooth", "normals", "shade"}));
    RenderSettings half = s;
    half.fluidScale = 0.5f;
    stages.clear();
    ASSERT_TRUE(renderSortLast(split(set.positions, {}, {1, 1}, 3), half, &stages));
    EXPECT_EQ(stages, (std::vector<std::string>{"scene", "reduce-scene-depth", "depth-splat", "composite", "thickness",
                                                "fill-holes", "smooth", "normals", "upsample", "shade", "fluid-edges"}));
    std::vector<StageTime> times;
    ASSERT_TRUE(renderFrame(set.positions, s, &times));
    EXPECT_EQ(times[1].stage, "depth-splat+thickness");
}

// A Renderer keeps no state of the compositor's between frames: the root and a
// non-root renderer reused over frames with and without one give the same.
TEST(SortLast, RenderersAreReusedAcrossFrames) {
    const RenderSettings s = realFrameSettings(160, 90);
    const ParticleSet& set = realFrame();
    const std::vector<Share> shares = split(set.positions, {}, {2, 1}, 4);
    auto whole = renderFrame(set.positions, s);
    ASSERT_TRUE(whole);
    Renderer root, other;
    for (int frame = 0; frame < 2; ++frame) {
        PartialStore store;
        InProcessCompositor c1(store, false), c0(store, true);
        RenderSettings s1 = s, s0 = s;
        s1.compositor = &c1;
        s0.compositor = &c0;
        auto r1 = other.render(shares[1].view(), s1);
        ASSERT_TRUE(r1);
        EXPECT_TRUE(r1->color.empty());
        EXPECT_TRUE(other.draw(shares[1].view(), s1));  // nothing more after the composite
        store.partials.resize(1);                       // draw() composited once more: keep one
        auto r0 = root.render(shares[0].view(), s0);
        ASSERT_TRUE(r0) << r0.error().describe();
        expectSameImage(*whole, *r0, "frame " + std::to_string(frame));
        // And without a compositor, the same renderer draws all the particles alone.
        auto alone = root.render(set.positions, s);
        ASSERT_TRUE(alone);
        expectSameImage(*whole, *alone, "alone after sort-last");
    }
}

// The compositor's error ends the frame, named; so does a combination of the
// wrong size.
TEST(SortLast, CompositorErrorsEndTheFrame) {
    struct Failing final : SplatCompositor {
        Status composite(SplatPartial&) override { return makeError("", "rank 3 did not answer"); }
        bool root() const override { return true; }
    } failing;
    struct Shrinking final : SplatCompositor {
        Status composite(SplatPartial& p) override {
            p.depth = Image<float>(2, 2, kInf);
            return okStatus();
        }
        bool root() const override { return true; }
    } shrinking;
    RenderSettings s = realFrameSettings(160, 90);
    s.compositor = &failing;
    auto r = renderFrame(realFrame().positions, s);
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().message.find("composite"), std::string::npos) << r.error().message;
    EXPECT_NE(r.error().message.find("rank 3 did not answer"), std::string::npos) << r.error().message;
    s.compositor = &shrinking;
    r = renderFrame(realFrame().positions, s);
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().message.find("same camera and settings"), std::string::npos) << r.error().message;
}

// What sort-last does not composite yet is an error naming the setting, on
// every process alike (before any stage runs, so none waits in a composite).
TEST(SortLast, RefusesWhatItDoesNotCompositeYet) {
    PartialStore store;
    InProcessCompositor c(store, true);
    const ParticleSet& set = realFrame();
    RenderSettings base = realFrameSettings(160, 90);
    base.compositor = &c;
    auto expectRefused = [&](const RenderSettings& s, const ParticleView& view, const std::string& name) {
        auto r = renderFrame(view, s);
        ASSERT_FALSE(r) << name;
        EXPECT_NE(r.error().message.find(name), std::string::npos) << r.error().message;
        EXPECT_NE(r.error().message.find("compositor"), std::string::npos) << r.error().message;
        EXPECT_EQ(c.calls, 0) << name;
    };
    const ParticleView all{std::span<const glm::vec3>(set.positions)};
    RenderSettings s = base;
    s.noise.enabled = true;
    expectRefused(s, all, "RenderSettings::noise");
    s = base;
    s.whitening.enabled = true;
    expectRefused(s, all, "RenderSettings::whitening");
    s = base;
    s.spray.enabled = true;
    expectRefused(s, all, "RenderSettings::spray");
    s = base;
    const std::vector<glm::vec3> drops = {set.positions[0]};
    s.diffuse.positions = drops;
    expectRefused(s, all, "RenderSettings::diffuse");
    s = base;
    s.anisotropy.enabled = true;
    expectRefused(s, all, "RenderSettings::anisotropy");
    s = base;
    s.raycast.enabled = true;
    expectRefused(s, all, "RenderSettings::raycast");
    s = base;
    TriangleMesh mesh;
    s.mesh = &mesh;
    expectRefused(s, all, "RenderSettings::mesh");
    s = base;
    s.scene.studioBounds = Bounds{};
    expectRefused(s, all, "RenderSettings::scene.studioBounds");
    const std::vector<std::int64_t> fluid(set.positions.size(), 0);
    ParticleView withFluid = all;
    withFluid.fluid = StridedView<std::int64_t>(std::span<const std::int64_t>(fluid));
    expectRefused(base, withFluid, "ParticleView::fluid");
}

// The GL backend reads its partial back and resolves the combination on the
// GPU as its own splat does: the root's picture is the GL one-process
// render's, bit for bit (one GL renderer for every share and the whole, as
// the shares would each have their own).
TEST(SortLast, GlBackendIsBitIdenticalToItsOwnRender) {
    auto gl = Renderer::create(BackendChoice::Gl);
    if (!gl) GTEST_SKIP() << "no GL: " << gl.error().describe();
    RenderSettings s = realFrameSettings();
    expectSortLastMatches(s, "GL, default look", {}, &*gl);
    s.thickness.resolutionDivisor = 2;
    expectSortLastMatches(s, "GL, thickness divisor 2", {}, &*gl);
    s.thickness.resolutionDivisor = 1;
    s.fluidScale = 0.5f;
    s.silhouette.enabled = true;
    expectSortLastMatches(s, "GL, fluid scale 0.5, silhouette", {}, &*gl);
    s = realFrameSettings();
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(0.75f, 1.25f);
    std::vector<float> radii(realFrame().positions.size());
    for (float& v : radii) v = u(rng) * s.radiusM;
    ASSERT_TRUE(filterFromName("curvature-flow", &s.filter));
    expectSortLastMatches(s, "GL, own radii, curvature flow", radii, &*gl);
}

// Every process given the whole frame and its share (RenderSettings::share):
// what reads more than a share (the anisotropic kernels' neighbours, the
// spray's split, the noise and whitening splatted again on the root, the
// drops) sees every particle, each process splats its contiguous index
// range, and the root's picture is the one-process render's for K = 1 .. 4,
// with a share that is empty.
void expectWholeFrameSharesMatch(const RenderSettings& s, const std::string& what) {
    const ParticleSet& set = realFrame();
    const ParticleView all = ParticleView::of(set);
    auto whole = renderFrame(all, s);
    ASSERT_TRUE(whole) << whole.error().describe();
    // The effects are in the picture (the comparisons below are not of empty images).
    const auto anyNonZero = [](const Image<float>& img) {
        return std::any_of(img.pixels.begin(), img.pixels.end(), [](float v) { return v != 0.0f; });
    };
    if (s.noise.enabled) {
        EXPECT_TRUE(anyNonZero(whole->noise)) << what;
    }
    if (s.whitening.enabled) {
        EXPECT_TRUE(anyNonZero(whole->whitening)) << what;
    }
    if (s.spray.enabled || !s.diffuse.empty()) {
        EXPECT_TRUE(anyNonZero(whole->spray)) << what;
    }
    const std::size_t n = set.size();
    for (const std::vector<std::size_t>& cuts :
         std::vector<std::vector<std::size_t>>{{0, n}, {0, n / 3, n}, {0, n / 4, n / 4, n}, {0, 1, n / 2, n - 7, n}}) {
        const std::size_t k = cuts.size() - 1;
        PartialStore store;
        for (std::size_t p = 1; p < k; ++p) {
            InProcessCompositor c(store, false);
            RenderSettings mine = s;
            mine.compositor = &c;
            mine.share = ParticleRange{cuts[p], cuts[p + 1]};
            auto r = renderFrame(all, mine);
            ASSERT_TRUE(r) << r.error().describe();
            EXPECT_TRUE(r->color.empty());
        }
        InProcessCompositor root(store, true);
        RenderSettings mine = s;
        mine.compositor = &root;
        mine.share = ParticleRange{cuts[0], cuts[1]};
        auto r = renderFrame(all, mine);
        ASSERT_TRUE(r) << r.error().describe();
        expectSameImage(*whole, *r, what + ", " + std::to_string(k) + " whole-frame shares");
        EXPECT_TRUE(sameBits(whole->noise, r->noise)) << what << ": noise";
        EXPECT_TRUE(sameBits(whole->whitening, r->whitening)) << what << ": whitening";
        EXPECT_TRUE(sameBits(whole->spray, r->spray)) << what << ": spray";
    }
}

TEST(SortLast, WholeFrameSharesKeepTheAnisotropicKernels) {
    RenderSettings s = realFrameSettings();
    s.anisotropy.enabled = true;
    expectWholeFrameSharesMatch(s, "anisotropic");
    // A share outside the particles is an error naming it; without a share the kernels are refused.
    const ParticleSet& set = realFrame();
    const ParticleView all{std::span<const glm::vec3>(set.positions)};
    PartialStore none;
    InProcessCompositor root(none, true);
    RenderSettings bad = s;
    bad.compositor = &root;
    bad.share = ParticleRange{2, set.size() + 1};
    auto r = renderFrame(all, bad);
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().message.find("RenderSettings::share"), std::string::npos) << r.error().message;
    bad.share.reset();
    r = renderFrame(all, bad);
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().message.find("anisotropy"), std::string::npos) << r.error().message;
}

TEST(SortLast, WholeFrameSharesKeepNoiseWhiteningSprayAndDiffuse) {
    RenderSettings s = realFrameSettings();
    s.anisotropy.enabled = true;
    s.noise.enabled = true;
    s.whitening.enabled = true;
    s.spray.enabled = true;
    s.view = View::Final;
    // A diffuse layer: a few drops above the liquid.
    const Bounds b = computeBounds(realFrame().positions);
    std::vector<glm::vec3> drops;
    for (int i = 0; i < 40; ++i)
        drops.push_back(glm::mix(b.min, b.max, glm::vec3(0.05f + 0.022f * float(i), 1.02f, 0.5f)));
    s.diffuse.positions = drops;
    ASSERT_TRUE(ParticleView::of(realFrame()).velocity.present()) << "the frame has velocities";
    expectWholeFrameSharesMatch(s, "noise, whitening, spray, diffuse");
    s.noise.enabled = s.whitening.enabled = false;
    expectWholeFrameSharesMatch(s, "spray and diffuse alone (the body's share sliced)");
}

}  // namespace meniscus::sort_last_test_local
