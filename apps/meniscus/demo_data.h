#pragma once
#include <cstdint>
#include <span>

// SPlisHSPlasH dam break, r = 0.025 m, frame 21 (t = 1.33 s), gzip BGEO: data/demo/.
inline constexpr const char* kDemoFrameName = "demo:dambreak_r0.025/ParticleData_Fluid_21.bgeo";
// The particle radius the simulation used (its scene file), so the demo shows the
// closed surface the simulation meant rather than the smaller spacing estimate.
inline constexpr float kDemoRadiusM = 0.025f;
std::span<const std::uint8_t> demoFrameBytes();
