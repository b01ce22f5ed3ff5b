// The VTK writers' shared pieces (particles: vtu_writer.cpp,
// vtk_legacy_writer.cpp; meshes: mesh_vtk_writer.cpp): names as each format
// encodes them, and the XML format's appended arrays. Internal to src/io.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>

namespace meniscus::io_write {

// A name in a legacy file, encoded as VTK does (%XX for spaces, '%', '"' and
// non-printable bytes); our reader (vtk_legacy.cpp) decodes it.
inline std::string vtkLegacyName(const std::string& name) {
    std::string out;
    for (const char ch : name) {
        const auto c = static_cast<unsigned char>(ch);
        if (c <= ' ' || c >= 127 || c == '%' || c == '"') {
            char hex[4];
            std::snprintf(hex, sizeof hex, "%%%02X", c);
            out += hex;
        } else {
            out += ch;
        }
    }
    return out;
}

// A name in an XML attribute.
inline std::string xmlEscaped(const std::string& s) {
    std::string out;
    for (const char c : s) {
        switch (c) {
            case '&': out += "&amp;"; break;
            case '<': out += "&lt;"; break;
            case '>': out += "&gt;"; break;
            case '"': out += "&quot;"; break;
            case '\'': out += "&apos;"; break;
            default: out += c;
        }
    }
    return out;
}

// One appended array: its header line and its place in the appended data.
struct Block {
    std::string xml;          // the <DataArray .../> element without offset
    std::uint64_t bytes = 0;  // data bytes (after the UInt64 count)
};

inline std::string dataArray(const std::string& type, const std::string& name, int components) {
    std::string s = "<DataArray type=\"" + type + "\" Name=\"" + xmlEscaped(name) + "\"";
    if (components != 1) s += " NumberOfComponents=\"" + std::to_string(components) + "\"";
    return s + " format=\"appended\"";
}

// The element for `b` at appended offset `offset`; advances it past the block.
inline std::string place(const Block& b, std::uint64_t& offset, const std::string& indent) {
    std::string s = indent + b.xml + " offset=\"" + std::to_string(offset) + "\"/>\n";
    offset += 8 + b.bytes;
    return s;
}

}  // namespace meniscus::io_write
