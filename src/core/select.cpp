// Particle selection (particles.h: parseSelection, applySelection): the CLI's
// --select, e.g. 'Type==fluid' to drop DualSPHysics' boundary particles or
// 'density>900 && velocity.y<0'.
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "meniscus/particles.h"

namespace meniscus {

namespace {

bool isBlank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; }

std::string_view trimmed(std::string_view s) {
    while (!s.empty() && isBlank(s.front())) s.remove_prefix(1);
    while (!s.empty() && isBlank(s.back())) s.remove_suffix(1);
    return s;
}

std::string lowered(std::string_view s) {
    std::string out(s);
    for (char& c : out) c = char(std::tolower(static_cast<unsigned char>(c)));
    return out;
}

bool nameStart(char c) { return std::isalpha(static_cast<unsigned char>(c)) || c == '_'; }
// Names as the readers keep them: ParaView's "Points:0", DualSPHysics' "Ace.x".
bool nameChar(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == ':' || c == '.'; }

// A number in full: decimal, exponent, optional sign; finite.
std::optional<double> number(std::string_view s) {
    if (!s.empty() && s.front() == '+') s.remove_prefix(1);
    double v = 0;
    const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (s.empty() || ec != std::errc() || ptr != s.data() + s.size() || !std::isfinite(v)) return std::nullopt;
    return v;
}

struct TypeName {
    std::string_view name;
    DualSphysicsType low, high;
};
constexpr TypeName kTypeNames[] = {
    {"fixed", DualSphysicsType::Fixed, DualSphysicsType::Fixed},
    {"moving", DualSphysicsType::Moving, DualSphysicsType::Moving},
    {"floating", DualSphysicsType::Floating, DualSphysicsType::Floating},
    {"bound", DualSphysicsType::Fixed, DualSphysicsType::Floating},
    {"boundary", DualSphysicsType::Fixed, DualSphysicsType::Floating},
    {"fluid", DualSphysicsType::Fluid, DualSphysicsType::Fluid},
};
constexpr std::string_view kTypeList = "fixed (0), moving (1), floating (2), bound (0 to 2), fluid (3)";

// The operand's name without a trailing component (".y", ".2"), lower case:
// "Type" for "type", "velocity" for "velocity.y".
std::string baseKey(std::string_view name) {
    const std::size_t dot = name.rfind('.');
    if (dot != std::string_view::npos && dot + 1 < name.size()) {
        const std::string_view c = name.substr(dot + 1);
        if (c == "x" || c == "y" || c == "z" || c == "X" || c == "Y" || c == "Z" ||
            std::all_of(c.begin(), c.end(), [](char d) { return std::isdigit(static_cast<unsigned char>(d)); }))
            name = name.substr(0, dot);
    }
    return lowered(name);
}

// "--select 'TEXT': ", and the clause when TEXT has more than one.
std::string prefix(const std::string& text, const std::string& clause) {
    return "--select '" + text + "': " + (clause == text ? std::string() : "'" + clause + "': ");
}

Result<SelectClause> parseClause(std::string_view clause, const std::string& text) {
    SelectClause out;
    out.text = std::string(trimmed(clause));
    auto bad = [&](const std::string& what) { return makeError("", prefix(text, out.text) + what); };
    std::string_view s = trimmed(clause);
    if (s.empty()) return bad("an empty clause (clauses are ATTR OP VALUE joined by &&)");

    // Operand: NAME or |NAME|.
    if (s.front() == '|') {
        out.magnitude = true;
        s.remove_prefix(1);
        s = trimmed(s);
    }
    std::size_t n = 0;
    if (s.empty() || !nameStart(s.front()))
        return bad("expected an attribute name first (e.g. density, Type, velocity.y), found '" +
                   std::string(s.substr(0, 12)) + "'");
    while (n < s.size() && nameChar(s[n])) ++n;
    out.attribute = std::string(s.substr(0, n));
    s = trimmed(s.substr(n));
    if (out.magnitude) {
        if (s.empty() || s.front() != '|') return bad("|" + out.attribute + " needs its closing '|'");
        s = trimmed(s.substr(1));
    }

    // Operator.
    struct OpName {
        std::string_view text;
        SelectOp op;
    };
    constexpr OpName kOps[] = {{"==", SelectOp::Equal},      {"!=", SelectOp::NotEqual}, {"<=", SelectOp::LessEqual},
                               {">=", SelectOp::GreaterEqual}, {"<", SelectOp::Less},     {">", SelectOp::Greater}};
    const OpName* op = nullptr;
    for (const OpName& o : kOps)
        if (s.substr(0, o.text.size()) == o.text) {
            op = &o;
            break;
        }
    if (!op) {
        if (!s.empty() && s.front() == '=') return bad("'=' is not an operator: use == to compare for equality");
        return bad("expected an operator (== != < <= > >=) after '" + out.attribute + "'" +
                   (s.empty() ? std::string(", found nothing") : ", found '" + std::string(s.substr(0, 12)) + "'"));
    }
    out.op = op->op;
    s = trimmed(s.substr(op->text.size()));

    // Value: a number, or a DualSPHysics type for an attribute called Type.
    if (s.empty()) return bad("expected a value after '" + std::string(op->text) + "'");
    if (const auto v = number(s)) {
        out.low = out.high = *v;
        return out;
    }
    const std::string word = lowered(s);
    for (const TypeName& t : kTypeNames) {
        if (word != t.name) continue;
        if (baseKey(out.attribute) != "type" || out.magnitude)
            return bad("'" + std::string(s) + "' is one of DualSPHysics' particle types, which only an attribute "
                       "called Type holds; for '" + out.attribute + "' give a number");
        out.low = double(int(t.low));
        out.high = double(int(t.high));
        if (out.low != out.high && out.op != SelectOp::Equal && out.op != SelectOp::NotEqual)
            return bad("'" + std::string(s) + "' is a group of types (0 to 2): compare it with == or !=");
        return out;
    }
    return bad("'" + std::string(s) + "' is not a number" +
               (baseKey(out.attribute) == "type" ? " or a DualSPHysics particle type: " + std::string(kTypeList)
                                                 : std::string()));
}

// Where one clause's values come from in a particular set.
struct Source {
    const std::vector<glm::vec3>* positions = nullptr;  // the positions (x, y, z, position)
    const Attribute* attr = nullptr;
    int component = -1;  // -1: all of them (a scalar, or the length with magnitude)
    int components = 1;
};

std::string attributeList(const ParticleSet& set) {
    std::string have;
    for (const Attribute& a : set.attributes)
        have += (have.empty() ? "" : ", ") + a.name + (a.components > 1 ? " (" + std::to_string(a.components) + ")" : "");
    return have.empty() ? std::string("none") : have;
}

const Attribute* findAttribute(const ParticleSet& set, std::string_view name) {
    if (const Attribute* a = set.find(name)) return a;
    const std::string key = lowered(name);
    const Attribute* found = nullptr;
    for (const Attribute& a : set.attributes)
        if (lowered(a.name) == key) {
            if (found) return nullptr;  // ambiguous in any case: only the exact name will do
            found = &a;
        }
    return found;
}

Result<Source> resolve(const ParticleSet& set, const SelectClause& c, const std::string& text) {
    auto bad = [&](const std::string& what) { return makeError("", prefix(text, c.text) + what); };
    Source src;
    std::string base = c.attribute;
    int component = -1;
    const Attribute* a = findAttribute(set, c.attribute);
    if (!a) {
        // NAME.C: a component of NAME.
        const std::size_t dot = c.attribute.rfind('.');
        if (dot != std::string::npos && dot + 1 < c.attribute.size()) {
            const std::string comp = lowered(c.attribute.substr(dot + 1));
            if (comp == "x" || comp == "y" || comp == "z") component = comp[0] - 'x';
            else if (std::all_of(comp.begin(), comp.end(), [](char d) { return std::isdigit(static_cast<unsigned char>(d)); }) &&
                     comp.size() < 4)
                component = std::stoi(comp);
            if (component >= 0) {
                base = c.attribute.substr(0, dot);
                a = findAttribute(set, base);
            }
        }
    }
    if (!a) {
        // The positions: x, y, z, or position / position.C (pos too).
        const std::string key = lowered(base);
        const bool axis = component < 0 && (key == "x" || key == "y" || key == "z");
        if (axis || key == "position" || key == "pos") {
            src.positions = &set.positions;
            src.components = 3;
            src.component = axis ? key[0] - 'x' : component;
            if (src.component > 2) return bad("positions have 3 components (x, y, z)");
            if (src.component < 0 && !c.magnitude)
                return bad("the position has 3 components: give position.x, .y or .z, or |position| for the "
                           "distance from the origin");
            return src;
        }
        return bad("no attribute '" + c.attribute + "' (the file has: " + attributeList(set) +
                   "; x, y, z are the positions)");
    }
    src.attr = a;
    src.components = a->components;
    src.component = component;
    if (a->components < 1 || a->count() != set.size() ||
        (a->type == AttributeType::Float ? a->floats.size() : a->ints.size()) != set.size() * std::size_t(a->components))
        return bad("attribute '" + a->name + "' does not hold " + std::to_string(a->components) + " value(s) for each of the " +
                   std::to_string(set.size()) + " particles");
    if (component >= a->components)
        return bad("'" + a->name + "' has " + std::to_string(a->components) + " component(s), so no component " +
                   c.attribute.substr(c.attribute.rfind('.') + 1));
    if (a->components == 1 && component <= 0) src.component = -1;
    if (src.component < 0 && a->components > 1 && !c.magnitude)
        return bad("'" + a->name + "' has " + std::to_string(a->components) + " components: give one (" + a->name +
                   ".x, " + a->name + ".y, ...) or |" + a->name + "| for its length");
    return src;
}

// The clause's value for particle i: the component, the scalar or the length.
double valueOf(const Source& src, std::size_t i, bool magnitude) {
    auto at = [&](int c) -> double {
        if (src.positions) return double((*src.positions)[i][c]);
        const std::size_t k = i * std::size_t(src.components) + std::size_t(c);
        return src.attr->type == AttributeType::Float ? double(src.attr->floats[k]) : double(src.attr->ints[k]);
    };
    if (src.component >= 0 || src.components == 1) {
        const double v = at(std::max(src.component, 0));
        return magnitude ? std::fabs(v) : v;
    }
    double sum = 0;  // |NAME| of a vector
    for (int c = 0; c < src.components; ++c) sum += at(c) * at(c);
    return std::sqrt(sum);
}

bool holds(SelectOp op, double v, double low, double high) {
    switch (op) {
        case SelectOp::Equal: return v >= low && v <= high;
        case SelectOp::NotEqual: return !(v >= low && v <= high);
        case SelectOp::Less: return v < low;
        case SelectOp::LessEqual: return v <= low;
        case SelectOp::Greater: return v > high;
        case SelectOp::GreaterEqual: return v >= high;
    }
    return false;
}

}  // namespace

Result<ParticleFilter> parseSelection(std::string_view text) {
    ParticleFilter filter;
    filter.text = std::string(trimmed(text));
    if (filter.text.empty()) return filter;
    const std::string where = "--select '" + filter.text + "': ";
    if (filter.text.find("||") != std::string::npos)
        return makeError("", where + "|| is not supported: clauses are joined by && (all must hold)");
    std::string_view rest = filter.text;
    while (true) {
        const std::size_t amp = rest.find("&&");
        const std::string_view clause = rest.substr(0, amp);
        if (clause.find('&') != std::string_view::npos)
            return makeError("", where + "a single '&': clauses are joined by &&");
        auto c = parseClause(clause, filter.text);
        if (!c) return c.error();
        filter.clauses.push_back(std::move(*c));
        if (amp == std::string_view::npos) break;
        rest = rest.substr(amp + 2);
    }
    return filter;
}

Status applySelection(ParticleSet& set, const ParticleFilter& filter, const std::string& name) {
    if (filter.empty()) return okStatus();
    const std::string where = "--select '" + filter.text + "': ";
    const std::size_t n = set.size();
    std::vector<std::uint8_t> keep(n, 1);
    for (const SelectClause& c : filter.clauses) {
        auto src = resolve(set, c, filter.text);
        if (!src) return makeError(name, src.error().message);
        // A float attribute is compared in float: the value rounded as its values were.
        const bool asFloat = src->positions || src->attr->type == AttributeType::Float;
        const double low = asFloat ? double(float(c.low)) : c.low;
        const double high = asFloat ? double(float(c.high)) : c.high;
        for (std::size_t i = 0; i < n; ++i)
            if (keep[i] && !holds(c.op, valueOf(*src, i, c.magnitude), low, high)) keep[i] = 0;
    }
    std::size_t kept = 0;
    for (std::uint8_t k : keep) kept += k;
    if (kept == 0)
        return makeError(name, where + "no particle matches (of " + std::to_string(n) + "); nothing left to draw");
    if (kept == n) return okStatus();
    auto compact = [&](auto& values, std::size_t comps) {
        std::size_t j = 0;
        for (std::size_t i = 0; i < n; ++i) {
            if (!keep[i]) continue;
            for (std::size_t c = 0; c < comps; ++c) values[j * comps + c] = values[i * comps + c];
            ++j;
        }
        values.resize(j * comps);
    };
    // Every attribute is checked before any is changed, so an error leaves the set whole.
    for (const Attribute& a : set.attributes)
        if (a.components < 1 ||
            (a.type == AttributeType::Float ? a.floats.size() : a.ints.size()) != n * std::size_t(a.components))
            return makeError(name, where + "attribute '" + a.name + "' does not hold " + std::to_string(a.components) +
                                       " value(s) for each of the " + std::to_string(n) + " particles");
    compact(set.positions, 1);
    for (Attribute& a : set.attributes) {
        if (a.type == AttributeType::Float) compact(a.floats, std::size_t(a.components));
        else compact(a.ints, std::size_t(a.components));
    }
    return okStatus();
}

}  // namespace meniscus
