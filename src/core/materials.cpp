// Material presets of the shading equation (docs/pipeline.md#shading: water,
// murky water, milk, lava-like, sand-like opaque). Water is exactly the
// Material{} defaults of params.h, so the defaults live in one place. Colours
// are linear RGB; absorption in 1/m (Beer-Lambert), so with a dam-break tank of
// 1-2 m a value of a few per metre separates shallow (clear) from deep (tinted)
// fluid.
#include <array>

#include "meniscus/params.h"

namespace meniscus {

namespace {

struct Preset {
    const char* name;
    Material (*make)();
};

Material water() { return Material{}; }

// Greenish-brown, strongly absorbing: the floor vanishes within ~20 cm.
Material murky() {
    Material m;
    m.name = "murky";
    m.fluidColor = {0.075f, 0.085f, 0.030f};
    m.absorptionPerM = {9.0f, 7.0f, 12.0f};
    m.refraction = 1.0f;  // water's bend (Snell's law); the absorption hides the floor
    m.specular = 0.5f;
    return m;
}

// White and nearly opaque: thin films still let a little background through.
Material milk() {
    Material m;
    m.name = "milk";
    m.fluidColor = {0.82f, 0.82f, 0.78f};
    m.absorptionPerM = {60.0f, 60.0f, 60.0f};
    m.ior = 1.35f;
    m.refraction = 1.0f;  // Snell's law; thin films show a little bent background
    m.specular = 0.35f;
    m.shininess = 60.0f;
    m.opacity = 0.7f;
    return m;
}

// Molten rock: a saturated orange-red that is partly unlit (looks self-lit
// where the opacity lets the absorbed colour through), dull highlight.
Material lava() {
    Material m;
    m.name = "lava";
    m.fluidColor = {0.70f, 0.10f, 0.01f};
    m.absorptionPerM = {80.0f, 80.0f, 80.0f};
    m.ior = 1.5f;
    m.refraction = 0.0f;  // nearly opaque: the little background seen straight behind, no march
    m.specular = 0.15f;
    m.shininess = 30.0f;
    m.opacity = 0.6f;
    return m;
}

// Opaque granular material: diffuse sandy colour, faint broad highlight.
Material sand() {
    Material m;
    m.name = "sand";
    m.fluidColor = {0.55f, 0.40f, 0.21f};
    m.absorptionPerM = {100.0f, 100.0f, 100.0f};
    m.ior = 1.5f;
    m.refraction = 0.0f;  // opaque: no background seen, no march
    m.specular = 0.05f;
    m.shininess = 8.0f;
    m.opacity = 1.0f;
    return m;
}

constexpr std::array<Preset, 5> kPresets{{
    {"water", water},
    {"murky", murky},
    {"milk", milk},
    {"lava", lava},
    {"sand", sand},
}};

}  // namespace

bool materialPreset(const std::string& name, Material* out) {
    for (const Preset& p : kPresets)
        if (name == p.name) {
            if (out) *out = p.make();
            return true;
        }
    return false;
}

std::string materialPresetNames() {
    std::string s;
    for (const Preset& p : kPresets) {
        if (!s.empty()) s += ", ";
        s += p.name;
    }
    return s;
}

}  // namespace meniscus
