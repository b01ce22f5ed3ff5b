#version 430 core
#extension GL_GOOGLE_include_directive : require
// Narrow-range filter, one 1-D pass (x or y: uStep) (docs/pipeline.md#narrow-range-filter):
// see filter_narrow_range.glsl.
const bool kTwoD = false;
#include "filter_narrow_range.glsl"
