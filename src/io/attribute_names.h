// The one table of attribute names every particle reader maps to the canonical
// attributes (types.h: id, velocity, density) and to positions. Each reader
// used to carry its own list; DualSPHysics (Pos.x, Vel.x, Rhop or Rho, Idp), PySPH
// (x y z, u v w, rho), ParaView (Points:0, Velocity), Houdini (P, v) and
// SPlisHSPlasH (velocity, density, id) now share this one.
//
// Names are compared case-insensitively after a trailing unit in brackets is
// removed ("Pos.x [m]" is "pos.x"; "Vel.x [m/s]" is "vel.x").
#pragma once

#include <array>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "meniscus/types.h"

namespace meniscus::io_util {

// "Pos.x [m]" -> "Pos.x"; "Rhop [kg/m^3]" -> "Rhop"; surrounding blanks trimmed.
std::string_view withoutUnit(std::string_view columnName);
// withoutUnit, then lower case: the key every lookup below compares.
std::string attributeKey(std::string_view columnName);

// The canonical attribute (kAttrVelocity, kAttrDensity or kAttrId) a whole
// array of `components` components called `fileName` stands for, or "" when
// it is no canonical attribute: velocity/vel/v (3), density/rho/rhop (1),
// id/idp (1). The caller still checks the type (ids must be whole numbers)
// and that the canonical name is not taken.
std::string_view canonicalArrayName(std::string_view fileName, int components);

// Three scalar columns that together make a vector, e.g. {"vel.x", "vel.y", "vel.z"}.
using ComponentNames = std::array<std::string_view, 3>;

// Column triples naming the position (x y z, points:0.., pos.x.., pos_x..,
// position_x.., px..) and the velocity (vx.., u v w, vel.x.., velocity:0..,
// velocity_x.., vel_x..), all lower case.
std::span<const ComponentNames> positionColumns();
std::span<const ComponentNames> velocityColumns();

// Which component (0..2) of which triple list a column is, by attributeKey;
// -1 when none.
int componentIn(std::span<const ComponentNames> triples, std::string_view columnName);

// For readers with one column per scalar (CSV, PLY, PySPH, H5Part): the
// positions' columns, the velocity's (when all three exist) and the density's
// and id's, as indices into `names` (-1 when absent; an empty name never
// matches). The first complete triple in the table's order wins; for density
// and id a column called "density" / "id" itself wins, else the first alias.
// Any other column of the same meaning is kept by its own name.
struct ColumnRoles {
    std::array<int, 3> position{-1, -1, -1};
    std::array<int, 3> velocity{-1, -1, -1};  // all -1 unless all three were found
    int density = -1;
    int id = -1;
    bool hasPosition() const { return position[0] >= 0 && position[1] >= 0 && position[2] >= 0; }
    bool hasVelocity() const { return velocity[0] >= 0; }
    // True when column i is one of the above.
    bool assigned(int i) const;
};
ColumnRoles findColumnRoles(std::span<const std::string> names);

// A name for an attribute kept under its own name that does not clash with a
// canonical one (a second density column, a scalar "velocity"): `name` with
// `suffix` appended when it is a canonical name, else `name`.
std::string nonCanonicalName(std::string name, std::string_view suffix);

// Ids written as floats (ParaView, DualSPHysics' CSV through a spreadsheet)
// become Int when every value is a whole number below 9e18 in magnitude;
// false, and `a` unchanged, otherwise.
bool floatIdsToInt(Attribute& a);

// For readers with one column per scalar (CSV, PLY): appends an empty
// attribute of that name, type and component count to `attrs`; its index.
std::size_t appendAttribute(std::vector<Attribute>& attrs, std::string name, AttributeType type, int components);

// For readers with whole arrays (BGEO, legacy VTK, VTK XML): renames, in
// order, each attribute whose name canonicalArrayName maps to a canonical
// one, when its type fits (velocity and density Float; id Int, or Float
// holding whole numbers, which floatIdsToInt converts) and no attribute of
// `attrs` has that name yet (a file's own "velocity" wins over its "v").
void applyCanonicalNames(std::vector<Attribute>& attrs);

}  // namespace meniscus::io_util
