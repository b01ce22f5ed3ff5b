// Backdrops (docs/compositing.md): another renderer's picture of a set, its
// colour and its depth seen by the same camera, that the liquid is composited
// into exactly as the scene geometry is: the set hides the liquid where it is
// nearer, and the liquid refracts and tints the set behind it. The backdrop
// takes the place of the studio in the scene layer; the scene geometry, the
// shadows and the environment's reflections work over it as over the studio.
#pragma once

#include <cstdint>
#include <span>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "meniscus/result.h"

namespace meniscus {

// What a backdrop's depth values mean (the renderer turns each into the
// linear eye depth of docs/conventions.md, metres along the view axis):
//   linear   eye depth itself (planar: distance from the camera's plane);
//   ray      distance from the camera's centre along the pixel's ray;
//   blender  Blender's Z pass: planar since Blender 3.0 in Cycles and EEVEE
//            (Cycles before 3.0 wrote the ray distance: use ray for those);
//            its background (about 1e10) is nothing, as any depth >= 1e9 m;
//   window   OpenGL's normalised window depth d in [0, 1] of a perspective
//            projection with planes near and far: z = n f / (f - d (f - n)),
//            d = 1 nothing.
// Depths that are not finite or not positive (and d outside [0, 1)) are
// nothing: the backdrop's colour is seen there, with nothing to hide the
// liquid.
enum class BackdropDepthKind { Linear, Ray, Blender, Window };

struct BackdropDepth {
    BackdropDepthKind kind = BackdropDepthKind::Linear;
    float nearM = 0.0f, farM = 0.0f;  // window only: the projection's planes, metres, 0 < near < far
    bool operator==(const BackdropDepth&) const = default;
};

// "linear", "ray", "blender" or "window:NEAR,FAR" (metres); an error says
// which forms there are.
Result<BackdropDepth> parseBackdropDepth(std::string_view text);
std::string backdropDepthText(const BackdropDepth& depth);

// A backdrop as read: width x height pixels, row 0 at the top. `color` is
// linear RGB and alpha (alpha 1 where the file has none); `depth` the file's
// values as they are, whose meaning `convention` gives.
struct BackdropImage {
    int width = 0, height = 0;
    std::vector<glm::vec4> color;
    std::vector<float> depth;
    BackdropDepth convention;
    std::string name;  // the colour file (or "the host's arrays"), for messages
};

// The readers' bounds, checked before anything is allocated.
inline constexpr int kMaxBackdropSidePx = 16384;
inline constexpr long long kMaxBackdropPixels = 1LL << 26;
inline constexpr std::uintmax_t kMaxBackdropFileBytes = std::uintmax_t(2) << 30;  // 2 GiB

// Reads a backdrop. `color`: an OpenEXR file with R, G and B (A if there is
// one) and, when `depth` is empty, its depth channel Z; or a PNG or JPEG
// (sRGB, decoded to linear), which then needs `depth`. `depth`: an OpenEXR
// file with a Z channel or a single channel of any name. Channels are found
// by their name, or by the last part of a layered name as Blender's
// multilayer EXR writes them ("ViewLayer.Combined.R", "ViewLayer.Depth.Z"),
// the Combined and Depth layers preferred. Both images must have the same
// size. Non-finite colours become 0. Errors name the file; no exception
// escapes.
Result<BackdropImage> readBackdrop(const std::filesystem::path& color, const std::filesystem::path& depth,
                                   const BackdropDepth& convention);

// The backdrop's picture must be the rendered picture's size: an error
// naming both sizes and the options that match them.
Status checkBackdropSize(const BackdropImage& backdrop, int width, int height);

// A backdrop from arrays (Python's numpy arrays, an application's own
// picture): `rgb` width x height x 3 (or 4 with alpha) linear floats, `depth`
// width x height values; checked as a file's are.
Result<BackdropImage> makeBackdrop(int width, int height, std::span<const float> color, int channels,
                                   std::span<const float> depth, const BackdropDepth& convention);

}  // namespace meniscus
