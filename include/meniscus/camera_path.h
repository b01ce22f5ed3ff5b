// Camera motion through a rendered sequence: key-framed paths (eye, target and
// field of view at times) and turns about the vertical (orbit, turntable). Pure
// geometry: no rendering, no file formats.
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "meniscus/camera.h"
#include "meniscus/params.h"

namespace meniscus {

// One key of a camera path: where the camera is and what it looks at, at
// `timeS` seconds of sequence time. World space, metres; fov in degrees.
struct CameraKey {
    double timeS = 0.0;
    glm::vec3 eye{0.0f, 0.0f, 5.0f};
    glm::vec3 target{0.0f};
    float fovYDegrees = defaults::kFovYDegrees;

    bool operator==(const CameraKey&) const = default;
};

// Empty when `keys` is a usable path, else what is wrong: no key, a
// non-finite value, a fov outside (0, 180), or a key (numbered from 1) whose
// time is not later than the one before.
std::string checkCameraPath(std::span<const CameraKey> keys);

// The path at `timeS`: a cubic Hermite curve through the keys with
// Catmull-Rom tangents for uneven times, (p[k+1] - p[k-1]) / (t[k+1] - t[k-1]),
// one-sided at the two ends. It passes through every key exactly and is C1 in
// time; before the first key it is the first key, after the last the last (a
// single key: a still camera). Eye, target and fov are interpolated alike.
// `keys` must pass checkCameraPath.
CameraKey cameraPathAt(std::span<const CameraKey> keys, double timeS);

// `point` turned by `degrees` about the vertical line (+y, the renderer's up)
// through `centre`: counter-clockwise seen from above (right-handed about +y).
// Exact for 0 degrees; the height is kept exactly.
glm::vec3 turnAboutVertical(const glm::vec3& point, const glm::vec3& centre, double degrees);

// How the camera moves through a sequence of `frames` frames, frame i being
// at time i / fps seconds.
struct CameraMotion {
    std::vector<CameraKey> path;  // empty: the start camera's eye, target and fov throughout
    double orbitDegPerS = 0.0;    // turn about +y through the target, degrees per second of sequence time
    bool turntable = false;       // one whole turn over the sequence: frame i of N at 360 i / N degrees
    std::size_t frames = 1;
    double fps = defaults::kVideoFps;

    // Whether any two frames can see the scene from different places.
    bool moves() const;
};

// Frame i's camera: `start` (its size, clip range and up) with eye, target and
// fov from the path at time i / fps when there is one, then the eye turned
// about the vertical through the target by orbitDegPerS * i / fps degrees, or
// 360 i / frames for a turntable (distance and elevation kept). Frame 0 of an
// orbit or turntable is the start camera, exactly.
Camera cameraForFrame(const Camera& start, const CameraMotion& motion, std::size_t i);

}  // namespace meniscus
