// A restricted reader of Python pickles (internal to src/io), for the object
// arrays of numpy .npz files: PySPH's NumpyOutput saves its particle arrays as
// dicts, which numpy.savez stores as pickled 0-d object arrays (numpy's
// format.write_array, pickle protocol 3; Python 2 era files protocol 2).
//
// It runs the pickle machine of Python's Lib/pickle.py over the opcodes of
// protocols 0-5 that plain data uses (None, bools, ints, floats, str, bytes,
// tuples, lists, dicts, sets, the memo) and builds values, never code: the
// only callables it knows are the ones numpy arrays and dtypes are rebuilt
// with (numpy.core.multiarray._reconstruct, numpy.dtype,
// numpy.core.multiarray.scalar, _codecs.encode for protocol 2 byte strings,
// collections.OrderedDict); any other global becomes an opaque value that
// nothing reads. Memory is bounded by the input: every value comes from
// bytes of it.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "meniscus/types.h"

namespace meniscus::io_util::pickle {

enum class Kind { None, Bool, Int, Float, Str, Bytes, List, Tuple, Dict, Array, Dtype, Global, Opaque };

// A numpy dtype: the kind letter ('f', 'i', 'u', 'b', 'O', ...), the item
// size in bytes and the byte order ('<', '>' or '|').
struct Dtype {
    char kind = 0;
    int size = 0;
    char order = '<';
};

// A numpy type string as in .npy headers and dtype pickles: an optional
// byte order ('<', '>', '|', '=') then kind and size ("<f8", "|u1", "i4",
// "O"). False when it is not one.
bool parseDtype(std::string_view text, Dtype& d);

// Values live in one arena and refer to each other by index, as Python's
// objects do by reference (the memo may share one value among many).
struct Value {
    Kind kind = Kind::None;
    std::int64_t i = 0;           // Bool, Int
    double f = 0.0;               // Float
    std::string s;                // Str (UTF-8), Bytes; Global: "module.name"
    std::vector<std::size_t> items;  // List, Tuple; Dict: key, value, key, value...
    // Array: a numpy ndarray.
    Dtype dtype;                  // also Kind::Dtype
    std::vector<std::uint64_t> shape;
    bool fortran = false;
    // The value holding the elements, shared, never copied (a pickle may
    // give one bytes object to many arrays): Bytes/Str of the raw element
    // bytes, or, for object arrays, a List of one value per element.
    std::size_t payload = std::size_t(-1);
    bool built = false;           // the array's state was set (BUILD)
};

class Document {
public:
    const Value& at(std::size_t index) const { return values_.at(index); }
    std::size_t root() const { return root_; }
    // The value of `key` (a Str or Bytes of that text) in the Dict `dict`, or
    // npos.
    std::size_t get(std::size_t dict, std::string_view key) const;
    // A 0-d object array (what savez makes of a dict): its one element;
    // anything else: itself.
    std::size_t unwrap(std::size_t index) const;
    // A built non-object Array's element bytes (count x dtype.size of them
    // for the number kinds f, i, u, b).
    std::string_view arrayBytes(std::size_t array) const;
    static constexpr std::size_t npos = std::size_t(-1);

private:
    friend class Machine;
    std::vector<Value> values_;
    std::size_t root_ = 0;
};

// Runs the pickle in `data` to its STOP. Throws ParseFailure (io_util::fail)
// with what is wrong: a truncated stream, an unknown or unsupported opcode, a
// malformed array.
Document load(ByteView data);

}  // namespace meniscus::io_util::pickle
