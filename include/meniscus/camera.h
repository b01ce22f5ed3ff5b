// Pinhole camera and the pixel conventions of docs/conventions.md#conventions.
//  - right-handed world, metres, +y up; view space looks down -z;
//  - focal length in pixels f = (H/2) / tan(fov/2), square pixels;
//  - pixel (i, j): i column, j row, row 0 at the TOP, centre (i+1/2, j+1/2);
//  - view ray of a pixel d = ((i+1/2 - W/2)/f, -(j+1/2 - H/2)/f, -1);
//  - eye depth z = -z_view > 0, so the ray parameter along d IS the eye depth.
#pragma once

#include <span>

#include <glm/glm.hpp>

#include "meniscus/params.h"
#include "meniscus/result.h"
#include "meniscus/types.h"

namespace meniscus {

struct Camera {
    glm::vec3 eye{0.0f, 0.0f, 5.0f};   // metres, world space
    glm::vec3 target{0.0f};            // the point the camera looks at
    glm::vec3 up{0.0f, 1.0f, 0.0f};    // approximate up; orthogonalised
    float fovYDegrees = defaults::kFovYDegrees;  // full vertical field of view
    float nearM = defaults::kNearM;    // eye-depth clip range, metres
    float farM = defaults::kFarM;
    int width = defaults::kWidth;      // pixels
    int height = defaults::kHeight;

    bool operator==(const Camera&) const = default;

    // Focal length in pixels (same for x and y: square pixels).
    float focalPx() const;

    // World-space unit axes of view space: x = right, y = up, z = back (toward the eye).
    glm::vec3 right() const;
    glm::vec3 trueUp() const;
    glm::vec3 back() const;

    // World -> view space (camera at origin looking down -z).
    glm::vec3 toView(const glm::vec3& world) const;
    // View -> world space (a direction if w = 0).
    glm::vec3 toWorld(const glm::vec3& view) const;
    glm::vec3 dirToWorld(const glm::vec3& viewDir) const;

    // View-space ray through continuous pixel coordinates (px, py); its z is -1,
    // so the point at eye depth z is z * ray. Pixel centres are (i+0.5, j+0.5).
    glm::vec3 pixelRay(float px, float py) const;
    // View-space point seen at continuous pixel (px, py) with eye depth z.
    glm::vec3 unproject(float px, float py, float eyeDepth) const { return eyeDepth * pixelRay(px, py); }
    // Continuous pixel coordinates of a view-space point (must have z < 0).
    glm::vec2 projectView(const glm::vec3& view) const;
};

// Checks the camera describes a real view: finite vectors, eye != target, up not
// parallel to the view direction, 0 < fov < 180, 0 < near < far, W, H > 0.
Status validateCamera(const Camera& camera);

// The camera of an OpenGL application's view and projection matrices (glm's
// column-major layout, as glm::lookAt and glm::perspective make them), for an
// image of width x height pixels: the eye, view axes, vertical field of view
// and near/far planes they encode. The view must be rigid (rotation and
// translation, no scale or shear); the projection a symmetric perspective
// one with finite planes, whose aspect is width / height (square pixels).
// Anything else is an error saying what does not fit.
Result<Camera> cameraFromGlMatrices(const glm::mat4& view, const glm::mat4& projection, int width, int height);

// With no camera given: a pleasant three-quarter view (from the front-right,
// above; angles in params.h) of the particles themselves. The distance is the
// smallest at which all but the outermost kAutoOutlierFraction of the spheres
// (centres grown by `radiusM`) fit in kAutoFill of the image, and the target is
// shifted so that what is framed sits in the middle. Lone spray particles far
// from the fluid may fall outside. `fovYDegrees`, `width`, `height` come from
// `base`; eye, target, up, near and far are set (near/far scale with the scene).
// A far outlier moves neither the target nor the distance. `outside`, when
// given, receives how many points lie outside the image (estimated from a
// stride when there are more than ~50k). The view direction: from the target
// toward the eye at `azimuthDegrees` around +y (0 = from +z, 90 = from +x) and
// `elevationDegrees` above the horizon (clamped to +-89).
Camera autoFrameCamera(std::span<const glm::vec3> points, float radiusM, const Camera& base,
                       std::size_t* outside = nullptr, float azimuthDegrees = defaults::kAutoAzimuthDegrees,
                       float elevationDegrees = defaults::kAutoElevationDegrees);

// A valid camera moved on a sphere around its target, as a viewer's mouse
// moves it: `azimuthDegrees` about the `up` axis (positive = toward the camera's
// right), `elevationDegrees` toward `up` (the result stays within 89 degrees
// of the horizon, so the view never flips over the pole), and the distance
// times `zoom` (> 0). Up, size and field of view are kept. The near plane
// comes to no more than 1e-3 of the new distance, so content nearer the
// camera after a turn or a zoom is not clipped (eye depth is linear, so a
// small near plane costs no precision); the far plane grows with zoom > 1.
Camera orbitCamera(const Camera& camera, float azimuthDegrees, float elevationDegrees, float zoom);

}  // namespace meniscus
