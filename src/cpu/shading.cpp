// CPU shading and compositing, SPEC §3.8. After van der Laan, Green & Sainz 2009
// (US 8,947,430, eqs. 18-20) with the reflection/refraction of Cords & Staadt
// 2008 ("Instant Liquids" §3):
//   a     = lerp(C_fluid, S(x + beta n_x, y - beta n_y), exp(-k_rgb T))   (eq. 18)
//   C_out = a (1 - F) + b F + k_s (n·h)^alpha                              (eq. 20)
// with b the sky (environment map) along reflect(-v, n) in world space and F
// Schlick's Fresnel term.
//
// Choices:
//  - The refraction offset is beta = refraction * T * f / z pixels: the
//    thickness projected to the screen, so the image is scale-invariant (the
//    patent's beta = gamma T is in pixels per metre and is not). The offset is
//    along the view-space normal; row 0 is the top, hence -n_y.
//  - The background is sampled bilinearly with premultiplied alpha and the sky
//    along the view ray fills what the scene leaves transparent, so a missing
//    background blends smoothly into sky.
//  - Opaque materials (sand, milk, lava): opacity mixes the transmitted colour
//    toward a Lambert-lit fluid colour and fades the mirror reflection (a rough
//    opaque surface reflects diffusely, not like glass); the highlight stays.
//  - Everything per image (focal length, camera axes, light in view space, F0)
//    is computed once; per pixel there are 3 exp and the sky lookup, and a pow
//    only near the highlight.
#include "cpu/shading.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "cpu/filter_util.h"
#include "cpu/sky.h"

namespace meniscus::cpu {

namespace {

// Share of the diffuse lighting of opaque materials that does not depend on the
// light direction (sky fill), so faces turned away from the key light are not black.
constexpr float kAmbient = 0.35f;

// Bilinear sample of the scene colour at continuous pixel coordinates (pixel
// centres at +0.5), clamped to the image; premultiplied: returns (alpha * rgb, alpha).
inline glm::vec4 sampleScenePremul(const Image<glm::vec4>& img, float px, float py) {
    const float fx = std::clamp(px - 0.5f, 0.0f, float(img.width - 1));
    const float fy = std::clamp(py - 0.5f, 0.0f, float(img.height - 1));
    const int x0 = int(fx), y0 = int(fy);
    const int x1 = std::min(x0 + 1, img.width - 1), y1 = std::min(y0 + 1, img.height - 1);
    const float tx = fx - float(x0), ty = fy - float(y0);
    auto pm = [](const glm::vec4& c) { return glm::vec4(glm::vec3(c) * c.a, c.a); };
    const glm::vec4 top = glm::mix(pm(img.at(x0, y0)), pm(img.at(x1, y0)), tx);
    const glm::vec4 bottom = glm::mix(pm(img.at(x0, y1)), pm(img.at(x1, y1)), tx);
    return glm::mix(top, bottom, ty);
}

}  // namespace

Image<glm::vec4> shadeAndComposite(const Camera& camera, const SceneLayer& scene, const Image<float>& depth,
                                   const Image<glm::vec3>& normals, const Image<float>& thickness,
                                   const ShadingParams& params) {
    const int w = depth.width, h = depth.height;
    Image<glm::vec4> out(w, h, glm::vec4(0.0f));
    if (w <= 0 || h <= 0) return out;
    // A scene layer of another size (or none) counts as a transparent background.
    const bool hasScene = scene.color.width == w && scene.color.height == h && scene.depth.width == w &&
                          scene.depth.height == h;
    const bool hasNormals = normals.width == w && normals.height == h;
    const bool hasThickness = thickness.width == w && thickness.height == h;

    const Material& m = params.material;
    const float f = camera.focalPx();
    std::vector<float> rx(static_cast<std::size_t>(w)), ry(static_cast<std::size_t>(h));
    for (int x = 0; x < w; ++x) rx[std::size_t(x)] = (float(x) + 0.5f - 0.5f * float(w)) / f;
    for (int y = 0; y < h; ++y) ry[std::size_t(y)] = -(float(y) + 0.5f - 0.5f * float(h)) / f;
    const glm::vec3 axisX = camera.right(), axisY = camera.trueUp(), axisZ = camera.back();
    auto toWorld = [&](const glm::vec3& d) { return d.x * axisX + d.y * axisY + d.z * axisZ; };
    glm::vec3 light(glm::dot(params.lightDirWorld, axisX), glm::dot(params.lightDirWorld, axisY),
                    glm::dot(params.lightDirWorld, axisZ));
    const float lightLen = glm::length(light);
    light = lightLen > 0.0f ? light / lightLen : glm::vec3(0.0f, 0.0f, 1.0f);
    const float f0 = fresnelF0(m.ior);
    const float opacity = std::clamp(m.opacity, 0.0f, 1.0f);
    const glm::vec3 negK = -glm::max(m.absorptionPerM, glm::vec3(0.0f));
    // The highlight k_s (n.h)^s is skipped where it is below 1e-6 (invisible in
    // any output format): n.h < (1e-6 / k_s)^(1/s). Saves a pow on most pixels.
    const float nhMin = m.specular > 1e-6f && m.shininess > 0.0f ? std::pow(1e-6f / m.specular, 1.0f / m.shininess)
                                                                 : 2.0f;

    forEachRow(h, [&](int y) {
        for (int x = 0; x < w; ++x) {
            const glm::vec4 sc = hasScene ? scene.color.at(x, y) : glm::vec4(0.0f);
            const float sz = hasScene ? scene.depth.at(x, y) : INFINITY;
            const float z = depth.at(x, y);
            if (!(z < sz) || !(z > 0.0f)) {  // no fluid (+inf), or hidden by the scene
                out.at(x, y) = sc;
                continue;
            }
            const glm::vec3 ray(rx[std::size_t(x)], ry[std::size_t(y)], -1.0f);
            const glm::vec3 v = -ray / glm::length(ray);  // toward the eye
            glm::vec3 n = hasNormals ? normals.at(x, y) : v;
            if (!(glm::dot(n, n) > 0.0f)) n = v;
            const float nv = std::clamp(glm::dot(n, v), 0.0f, 1.0f);
            const float nl = glm::dot(n, light);
            float T = hasThickness ? thickness.at(x, y) : 0.0f;
            if (!(T > 0.0f) || !std::isfinite(T)) T = 0.0f;

            // Refraction: the background shifted along the normal by the projected thickness.
            const float beta = m.refraction * T * f / z;
            glm::vec3 s;
            if (hasScene) {
                const glm::vec4 pm = sampleScenePremul(scene.color, float(x) + 0.5f + beta * n.x,
                                                       float(y) + 0.5f - beta * n.y);
                s = glm::vec3(pm);
                if (pm.a < 1.0f) s += (1.0f - pm.a) * skyColor(toWorld(ray));
            } else {
                s = skyColor(toWorld(ray));
            }

            // Beer-Lambert absorption through thickness T (eq. 18).
            const glm::vec3 transmit(std::exp(negK.x * T), std::exp(negK.y * T), std::exp(negK.z * T));
            glm::vec3 a = m.fluidColor + (s - m.fluidColor) * transmit;
            float F = schlickFresnel(f0, nv);
            if (opacity > 0.0f) {
                const glm::vec3 diffuse = m.fluidColor * (kAmbient + (1.0f - kAmbient) * std::max(nl, 0.0f));
                a = glm::mix(a, diffuse, opacity);
                F *= 1.0f - opacity;
            }

            // Mirror reflection of the environment, reflect(-v, n) in world space.
            const glm::vec3 b = skyColor(toWorld(2.0f * nv * n - v));
            glm::vec3 c = a * (1.0f - F) + b * F;

            // Blinn-Phong highlight (eq. 20), only on the lit side.
            if (nl > 0.0f) {
                const float nh = glm::dot(n, glm::normalize(light + v));
                if (nh > nhMin) c += glm::vec3(m.specular * std::pow(nh, m.shininess));
            }
            out.at(x, y) = glm::vec4(c, 1.0f);
        }
    });
    return out;
}

}  // namespace meniscus::cpu
