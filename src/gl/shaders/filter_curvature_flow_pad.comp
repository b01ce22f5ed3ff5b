#version 430 core
// Curvature flow (SPEC §3.5, src/cpu/filter_curvature_flow.cpp) on the GPU:
// the passes around the iterations.
// Mode 0 (pad): the (W + 2) x (H + 2) ping-pong buffers A and B are filled
//   with +inf by the host (a memset on llvmpipe); this copies the fluid pixels
//   into A's interior. The +inf frame makes the border "no fluid" as the CPU's
//   padded copies do (so the step shader needs no bounds tests). Each fluid
//   pixel also flags its tile (64 x kRows pixels, one work group of the step
//   shader), flags zeroed beforehand.
// Mode 1 (list): the flagged tiles are appended to the tile list, whose length
//   is the x group count of the step's indirect dispatch: the fluid set never
//   changes, so only tiles with fluid are ever visited (the rest stay +inf in
//   both buffers), the GPU twin of the CPU's per-row runs.
// Mode 2 (unpad): out pixel = A's padded pixel.
layout(local_size_x = 64) in;

layout(std430, binding = 1) readonly buffer Img { float img[]; };  // W*H, row 0 = top
layout(std430, binding = 2) buffer PadA { float padA[]; };
layout(std430, binding = 4) writeonly buffer Out { float outImg[]; };
layout(std430, binding = 5) buffer Tiles { uint tileFlags[]; };  // per tile, then...
layout(std430, binding = 6) buffer TileList { uint tileList[]; };
layout(std430, binding = 7) buffer Indirect { uint dispatchArgs[3]; };  // x = list length, y = z = 1

layout(location = 0) uniform ivec2 uSize;  // W, H of the image
layout(location = 1) uniform int uMode;    // 0 pad, 1 list, 2 unpad
layout(location = 2) uniform ivec3 uTiles; // tile width, tile height, tiles per row

const int kPerInvocation = 16;  // llvmpipe pays per work group: a few elements each

void main() {
    const int W = uSize.x, H = uSize.y, PW = W + 2;
    const int nTiles = uTiles.z * ((H + uTiles.y - 1) / uTiles.y);
    const int n = uMode == 1 ? nTiles : W * H;
    const int first = int(gl_WorkGroupID.x) * 64 * kPerInvocation + int(gl_LocalInvocationID.x);
    for (int j = 0; j < kPerInvocation; ++j) {
        const int k = first + 64 * j;
        if (k >= n) return;
        if (uMode == 0) {
            const int px = k % W, py = k / W;
            const float v = img[k];
            if (v < uintBitsToFloat(0x7f800000u)) {
                padA[(py + 1) * PW + px + 1] = v;
                tileFlags[(py / uTiles.y) * uTiles.z + px / uTiles.x] = 1u;
            }
        } else if (uMode == 1) {
            if (tileFlags[k] != 0u) tileList[atomicAdd(dispatchArgs[0], 1u)] = uint(k);
        } else {
            const int x = k % W, y = k / W;
            outImg[k] = padA[(y + 1) * PW + x + 1];
        }
    }
}
