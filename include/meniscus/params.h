// Every user-facing default lives here (and only here), with its unit.
#pragma once

namespace meniscus::defaults {

inline constexpr int kWidth = 1280;           // pixels
inline constexpr int kHeight = 720;           // pixels
inline constexpr float kFovYDegrees = 40.0f;  // vertical field of view of the auto camera
inline constexpr float kNearM = 0.01f;        // metres
inline constexpr float kFarM = 1000.0f;       // metres

// Auto-framing: the view direction from the target toward the eye, as azimuth
// around +y (0 = +z, positive toward +x) and elevation above the horizon.
inline constexpr float kAutoAzimuthDegrees = 35.0f;
inline constexpr float kAutoElevationDegrees = 25.0f;
// Fraction of the half-image the framed particles may fill (1 = touch the edges).
inline constexpr float kAutoFill = 0.9f;
// Fraction of particles (the outermost, e.g. lone spray) the auto camera may leave out.
inline constexpr float kAutoOutlierFraction = 0.001f;

}  // namespace meniscus::defaults
