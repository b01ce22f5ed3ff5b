#include "surface/field.h"

#include <cmath>

namespace meniscus::surface {

Field makeField(const MeshParams& p) {
    Field f;
    f.kind = p.field;
    const float supportRadii = p.supportRadii > 0.0f ? p.supportRadii
                               : p.field == SurfaceField::Thesis ? defaults::kThesisSupportRadii
                                                                 : defaults::kSphSupportRadii;
    f.support = supportRadii * p.radiusM;
    f.support2 = f.support * f.support;
    f.invSupport2 = 1.0f / f.support2;
    f.invSupport = 1.0f / f.support;
    // F0: the field at an interior particle of a simple cubic lattice of
    // spacing 2r (refsurf's rho0), summed in the same float kernel.
    const float spacing = 2.0f * p.radiusM;
    const int m = int(std::ceil(f.support / spacing));
    double rest = 0.0;
    for (int i = -m; i <= m; ++i)
        for (int j = -m; j <= m; ++j)
            for (int k = -m; k <= m; ++k)
                rest += f.kernel(spacing * spacing * float(i * i + j * j + k * k));
    f.rest = rest;
    f.isoRaw = float(double(p.iso) * rest);
    return f;
}

}  // namespace meniscus::surface
