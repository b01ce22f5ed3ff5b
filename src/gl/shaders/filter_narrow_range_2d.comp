#version 430 core
#extension GL_GOOGLE_include_directive : require
// Narrow-range filter, the 2-D disc (docs/pipeline.md#narrow-range-filter): see
// filter_narrow_range.glsl.
const bool kTwoD = true;
#include "filter_narrow_range.glsl"
