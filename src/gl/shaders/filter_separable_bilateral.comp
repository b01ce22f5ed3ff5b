#version 430 core
#extension GL_GOOGLE_include_directive : require
// Separable bilateral depth smoothing, one 1-D pass (docs/pipeline.md#smoothing; CPU:
// src/cpu/filter_bilateral.cpp): the bilateral filter of the thesis
// (Janisz, §4.1.2.1, eqs. 4.1-4.3) split into x and y passes as in Pham & van
// Vliet, "Separable bilateral filtering for fast video preprocessing" (ICME
// 2005): Gaussian spatial weights times a Gaussian of the depth difference.
#define MENISCUS_BILATERAL 1
#include "filter_separable_pass.glsl"
