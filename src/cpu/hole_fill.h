// CPU hole filling (docs/pipeline.md#hole-filling): the pixels
// the splat left uncovered inside a sheet get a depth and thickness before the
// smoothing. Formulas and the rule: src/shared/hole_fill.h.
#pragma once

#include "meniscus/camera.h"
#include "meniscus/params.h"
#include "meniscus/types.h"

namespace meniscus::cpu {

// Fills `depth` (the raw splat, +inf = no fluid) and `thickness` in place:
// each uncovered pixel that liquid of one surface closes in along its row,
// column and both diagonals (shared/hole_fill.h) takes the four lines' mean
// interpolated depth, and the larger of its thickness and theirs. Never where
// the result would lie behind `sceneDepth` (null or another size: no scene).
// `camera` is the images' (W x H); radius r in metres. The same pixels and
// bits for any thread count. A thickness of another size is left as it is.
// Returns the number of pixels filled.
std::size_t fillHoles(const Camera& camera, float radius, const HoleFillParams& p, const Image<float>* sceneDepth,
                      Image<float>& depth, Image<float>& thickness);

}  // namespace meniscus::cpu
