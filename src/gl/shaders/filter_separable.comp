#version 430 core
#extension GL_GOOGLE_include_directive : require
// Separable Gaussian and binomial depth smoothing, one 1-D pass
// (docs/pipeline.md#smoothing; CPU: src/cpu/filter_gaussian.cpp after van der
// Laan, Green, Sainz, patent "System and method for rendering a particle-based
// fluid surface", and src/cpu/filter_binomial.cpp after Cords & Staadt,
// "Instant Liquids", JGT 2008, §2.2). The two differ only in the weight table
// uploaded.
#include "filter_separable_pass.glsl"
