#version 430 core
// Silhouette reduction (Cords & Staadt 2008, "Instant Liquids" §3: the
// binary depth map smoothed over a window, the liquid shown only where it
// reaches 1; docs/pipeline.md#silhouette-reduction) on the GPU, per pixel after
// the summed-area table (silhouette_rows.comp, silhouette_columns.comp): the GL
// twin of the per-pixel loop of cpu::reduceSilhouettes. A fluid pixel's window
// (silhouetteWindow), its fluid count from the table's four corners, S =
// count / area (silhouetteFraction) and, where its alpha (silhouetteAlpha)
// is under 1, the colour faded in place into the scene colour behind it
// (silhouetteBlend); S is written everywhere, 0 where there is no fluid. A
// background pixel next to the liquid takes its fluid neighbours' mean colour
// (read from `liquid`, the colour before any fade) faded by its own window's
// alpha (silhouetteOuterColor).
// Formulas: src/shared/silhouette.h, `precise` there.
#extension GL_GOOGLE_include_directive : require
#include "silhouette.h"

layout(local_size_x = 64) in;

// Buffer textures and image buffers: llvmpipe gathers and scatters those in
// SIMD but runs storage-buffer accesses lane by lane.
layout(binding = 0) uniform samplerBuffer depth;    // W*H eye depth, +inf = none
layout(binding = 1) uniform usamplerBuffer sat;     // (W+1)*(H+1) counts
layout(binding = 2) uniform samplerBuffer behind;   // W*H linear RGBA, the scene colour
layout(binding = 3) uniform samplerBuffer liquid;   // W*H linear RGBA, the colour before the fade
layout(rgba32f, binding = 0) uniform imageBuffer color;              // W*H linear RGBA, faded in place
layout(r32f, binding = 1) writeonly uniform imageBuffer silhouette;  // W*H S, 0 = no fluid

layout(location = 0) uniform ivec2 uSize;     // W, H
layout(location = 1) uniform float uRadiusM;  // SilhouetteParams::radiusRadii * radius (host float, as the CPU)
layout(location = 2) uniform float uFocalPx;  // Camera::focalPx() (host)
layout(location = 3) uniform int uMaxPx;      // SilhouetteParams::maxPx
layout(location = 4) uniform float uFadeFrom; // SilhouetteParams::fadeFrom

#define kInf uintBitsToFloat(0x7f800000u)

int stride;

uint at(int x, int y) { return texelFetch(sat, y * stride + x).x; }

void main() {
    const int W = uSize.x, H = uSize.y;
    stride = W + 1;
    const uint pixels = uint(W) * uint(H);
    for (uint k = gl_GlobalInvocationID.x; k < pixels; k += gl_NumWorkGroups.x * gl_WorkGroupSize.x) {
        const int i = int(k);
        float z = texelFetch(depth, i).x;
        const bool fluid = z < kInf;
        const int x = int(k % uint(W)), y = int(k / uint(W));
        precise vec4 sum = vec4(0.0);
        int n = 0;
        if (!fluid) {  // past the contour: the fluid 8-neighbours, in row order (as the CPU)
            imageStore(silhouette, i, vec4(0.0));
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int xx = x + dx, yy = y + dy;
                    if ((dx == 0 && dy == 0) || xx < 0 || yy < 0 || xx >= W || yy >= H) continue;
                    const float zn = texelFetch(depth, yy * W + xx).x;
                    if (!(zn < kInf)) continue;
                    z = min(z, zn);
                    sum = sum + texelFetch(liquid, yy * W + xx);
                    ++n;
                }
            if (n == 0) continue;
        }
        const ivec4 w = silhouetteWindow(x, y, z, uRadiusM, uFocalPx, uMaxPx, W, H);
        // Unsigned as on the CPU: the partial sums may wrap, the count does not.
        const uint count = at(w.z, w.w) - at(w.x, w.w) - at(w.z, w.y) + at(w.x, w.y);
        const int area = (w.z - w.x) * (w.w - w.y);
        const float s = silhouetteFraction(int(count), area);
        const float a = silhouetteAlpha(s, uFadeFrom);
        if (fluid) {
            imageStore(silhouette, i, vec4(s));
            if (a < 1.0) imageStore(color, i, silhouetteBlend(imageLoad(color, i), texelFetch(behind, i), a));
        } else if (a > 0.0) {
            imageStore(color, i, silhouetteBlend(silhouetteOuterColor(sum, n), texelFetch(behind, i), a));
        }
    }
}
