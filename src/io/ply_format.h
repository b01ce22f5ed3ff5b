// The PLY format itself, shared by the particle reader (ply.cpp: the vertex
// element) and the mesh reader (mesh_reader.cpp: vertices and faces): the
// header, and element rows read one at a time from ASCII or binary data with
// every count checked against the bytes present. Internal to src/io.
//
// Greg Turk, "The PLY Polygon File Format" (1994), and Paul Bourke's summary
// (https://paulbourke.net/dataformats/ply/): a text header
//
//   ply
//   format ascii|binary_little_endian|binary_big_endian 1.0
//   comment ...            (ignored, as are obj_info lines)
//   element NAME COUNT
//   property TYPE NAME                        scalar property
//   property list COUNT_TYPE ITEM_TYPE NAME   list property (faces' vertex_indices)
//   end_header
//
// followed by the elements' data in header order: in ASCII one element per
// line, whitespace separated; in binary the values packed with no padding.
// TYPE is char uchar short ushort int uint float double, or int8 uint8 int16
// uint16 int32 uint32 float32 float64.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "meniscus/result.h"
#include "meniscus/types.h"

namespace meniscus::ply {

enum class Encoding { Ascii, BinaryLittle, BinaryBig };
enum class ScalarType { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

struct Property {
    std::string name;
    ScalarType type = ScalarType::Float32;  // the item type for a list
    bool isList = false;
    ScalarType countType = ScalarType::UInt8;  // lists only
};

struct Element {
    std::string name;
    std::uint64_t count = 0;
    std::vector<Property> properties;
};

struct Header {
    Encoding encoding = Encoding::Ascii;
    std::string formatName;
    std::vector<Element> elements;
    std::size_t bodyOffset = 0;  // first byte after the end_header line
    std::size_t lineCount = 0;   // header lines, for ASCII line numbers
};

std::size_t sizeOf(ScalarType t);
bool isIntegerType(ScalarType t);

// Index of the scalar property called `n` in `e`, or -1.
int findScalar(const Element& e, std::string_view n);

// The header at the start of `text`; errors name `name`.
Result<Header> parseHeader(std::string_view text, const std::string& name);

// Reads one element row at a time: the value of every scalar property, in
// order, into `values`; the items of the list property at index `keepList`
// (if any) into `*items`; other lists are read and dropped. `row` is for
// messages.
class RowSource {
public:
    virtual ~RowSource() = default;
    virtual Status readRow(const Element& e, std::uint64_t row, std::vector<double>& values, int keepList,
                           std::vector<double>* items) = 0;
    Status readRow(const Element& e, std::uint64_t row, std::vector<double>& values) {
        return readRow(e, row, values, -1, nullptr);
    }
    // Skips `e` completely (the default reads every row).
    virtual Status skipElement(const Element& e);
    // Rejects counts the remaining data cannot possibly hold.
    virtual Status checkCount(const Element& e) = 0;
};

// The rows after the header of `data` (the whole file), in its encoding.
// `data` and `name` must outlive the source.
std::unique_ptr<RowSource> makeRowSource(const Header& h, ByteView data, const std::string& name);

}  // namespace meniscus::ply
