// GL separable depth smoothing (docs/pipeline.md#smoothing) and thickness blur
// (docs/pipeline.md#thickness): the GPU twins of cpu::filterGaussian /
// filterBilateral / filterBinomial (src/cpu/filter_separable.h) and of the
// full-resolution blur inside cpu::computeThickness. Needs a current GL 4.3
// context on the calling thread.
#pragma once

#include <optional>

#include "gl/fluid_segments.h"
#include "gl/gpu_image.h"
#include "gl/objects.h"
#include "meniscus/params.h"
#include "meniscus/result.h"
#include "shared/frame_params.h"

namespace meniscus::gl {

using shared::FrameParams;

// Owns the programs, the weight tables (shared::KernelTable's values, uploaded
// when the kernel cap changes) and a scratch image; reuse one across frames.
// The three filters this class runs (cpu::filterGaussian, filterBilateral,
// filterBinomial).
enum class SeparableKind { Gaussian, Bilateral, Binomial };
// The kind of a separable filter; nullopt for the others.
std::optional<SeparableKind> separableKind(const FilterParams& filter);

class SeparableFilters {
public:
    // Compiles the programs; an error carries the driver's log.
    static Result<SeparableFilters> create();

    // The separable filter `kind`, parameters from the block fields
    // (gaussianSigmaRadii, bilateral*, binomialSizeRadii, filterJumpRadii,
    // filterMaxKernelPx, filterIterations; radius, focal length, size).
    // `in`: W x H x 1 eye depth, +inf = no fluid. `out` (not `in`) is resized
    // and receives the result. The frame block must be bound (binding 0); the
    // kernel sizes are computed here from `frame` with the CPU's rounding.
    // Asynchronous: nothing waits for the GPU.
    void run(const FrameParams& frame, SeparableKind kind, const GpuImage& in, GpuImage& out);

    // The thickness blur of cpu::computeThickness at resolutionDivisor 1, in
    // place on `thickness` (W x H x 1): sigma = thicknessBlurSigmaRadii radii
    // projected with `rawDepth` (same size; pixels without fluid there keep
    // their value), kernel radius capped at min(thicknessMaxKernelPx, 255).
    // No-op when the sigma or the cap is 0 or the sizes differ.
    void blurThickness(const FrameParams& frame, const GpuImage& rawDepth, GpuImage& thickness);
    // The same on another grid (the low-resolution thickness): sigma projected
    // with focal length `focalPx` (f / d there) instead of the frame's.
    void blurThickness(const FrameParams& frame, const GpuImage& rawDepth, GpuImage& thickness, float focalPx);

private:
    enum class TableKind { None, Gaussian, Binomial };
    // The table for (kind, maxRadius) in `buffer`, rebuilt only when they change;
    // returns the groups of 4 taps stored per radius.
    struct CachedTable {
        Buffer buffer;
        TableKind kind = TableKind::None;
        int maxRadius = -1;
    };
    static int ensureTable(CachedTable& t, TableKind kind, int maxRadius, bool withDiffs);
    // With the program and its uniforms set: the x pass src -> scratch, then
    // the y pass scratch -> dst (dst may be src), each followed by its barrier;
    // over the whole image, or only over `segments` (bound by the caller).
    void xyPasses(const GpuImage& src, GpuImage& dst, const FluidSegments* segments = nullptr);

    Program plain_, bilateral_, thickness_;
    CachedTable filterTable_, thicknessTable_;
    GpuImage scratch_;
    FluidSegments segments_;  // the thickness blur's: fluid in the raw depth
    Texture srcTex_, tableTex_;  // buffer-texture views (texelFetch gathers well on llvmpipe)
};

}  // namespace meniscus::gl
