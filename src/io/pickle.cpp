// The restricted pickle reader (pickle.h). Opcodes and their meaning follow
// CPython's Lib/pickle.py and Lib/pickletools.py (protocols 0-5); numpy's
// array and dtype reconstruction follows numpy/core/src/multiarray
// (array_reduce / array_setstate: the state (version, shape, dtype,
// is_fortran, data); arraydescr_reduce / arraydescr_setstate: the state
// (version, byte order, ...)).
#include "io/pickle.h"

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <unordered_map>

#include "io/io_util.h"

namespace meniscus::io_util::pickle {

std::size_t Document::get(std::size_t dict, std::string_view key) const {
    if (dict >= values_.size() || values_[dict].kind != Kind::Dict) return npos;
    const Value& d = values_[dict];
    std::size_t found = npos;  // the last one set wins, as in Python
    for (std::size_t k = 0; k + 1 < d.items.size(); k += 2) {
        const Value& name = values_[d.items[k]];
        if ((name.kind == Kind::Str || name.kind == Kind::Bytes) && name.s == key) found = d.items[k + 1];
    }
    return found;
}

std::size_t Document::unwrap(std::size_t index) const {
    if (index >= values_.size()) return npos;
    const Value& v = values_[index];
    if (v.kind == Kind::Array && v.built && v.dtype.kind == 'O' && v.shape.empty() && v.payload < values_.size()) {
        const Value& items = values_[v.payload];
        if (items.kind == Kind::List && items.items.size() == 1) return items.items[0];
    }
    return index;
}

std::string_view Document::arrayBytes(std::size_t array) const {
    if (array >= values_.size()) return {};
    const Value& v = values_[array];
    if (v.kind != Kind::Array || !v.built || v.dtype.kind == 'O' || v.payload >= values_.size()) return {};
    return values_[v.payload].s;
}

bool parseDtype(std::string_view text, Dtype& d) {
    if (!text.empty() && (text[0] == '<' || text[0] == '>' || text[0] == '|' || text[0] == '=')) {
        d.order = text[0] == '=' ? '<' : text[0];  // '=': native, little-endian on every machine we build for
        text.remove_prefix(1);
    }
    if (text.empty()) return false;
    d.kind = text[0];
    text.remove_prefix(1);
    if (text.empty()) {
        d.size = d.kind == 'O' ? 8 : 0;
        return d.kind == 'O';
    }
    int size = 0;
    const auto r = std::from_chars(text.data(), text.data() + text.size(), size);
    if (r.ec != std::errc() || r.ptr != text.data() + text.size() || size <= 0 || size > (1 << 20)) return false;
    d.size = size;
    return true;
}

// The largest element count of an array (2^40); more is a damaged stream.
constexpr std::uint64_t kMaxElements = std::uint64_t(1) << 40;

class Machine {
public:
    explicit Machine(ByteView data) : data_(data) {}

    Document run() {
        for (;;) {
            const std::uint8_t op = byte();
            if (op == '.') {  // STOP
                doc_.root_ = pop();
                return std::move(doc_);
            }
            step(op);
        }
    }

private:
    ByteView data_;
    std::size_t pos_ = 0;
    Document doc_;
    std::vector<std::size_t> stack_;
    std::vector<std::vector<std::size_t>> marks_;
    std::unordered_map<std::uint64_t, std::size_t> memo_;
    // Bytes of new strings made from values already read (STACK_GLOBAL,
    // _codecs.encode): the memo lets a few opcodes repeat a large one, so
    // their total is held to a few times the input.
    std::uint64_t made_ = 0;
    void spend(std::uint64_t n) {
        made_ += n;
        if (made_ > 4 * std::uint64_t(data_.size()) + (std::uint64_t(1) << 20))
            fail("pickle data expands to far more than its own size");
    }

    std::vector<Value>& values() { return doc_.values_; }

    // ---- reading the stream
    void need(std::uint64_t n) {
        if (n > data_.size() - pos_) fail("pickle data is truncated");
    }
    std::uint8_t byte() {
        need(1);
        return data_[pos_++];
    }
    std::uint64_t littleEndian(int n) {
        need(std::uint64_t(n));
        std::uint64_t v = 0;
        for (int k = n - 1; k >= 0; --k) v = (v << 8) | data_[pos_ + std::size_t(k)];
        pos_ += std::size_t(n);
        return v;
    }
    std::string_view bytes(std::uint64_t n) {
        need(n);
        std::string_view s(reinterpret_cast<const char*>(data_.data()) + pos_, std::size_t(n));
        pos_ += std::size_t(n);
        return s;
    }
    std::string_view line() {
        const auto* begin = data_.data() + pos_;
        const auto* nl = static_cast<const std::uint8_t*>(std::memchr(begin, '\n', data_.size() - pos_));
        if (!nl) fail("pickle data is truncated (a text argument without its newline)");
        std::string_view s(reinterpret_cast<const char*>(begin), std::size_t(nl - begin));
        pos_ += s.size() + 1;
        if (!s.empty() && s.back() == '\r') s.remove_suffix(1);
        return s;
    }

    // ---- values and the stack
    std::size_t make(Kind kind) {
        values().push_back(Value{});
        values().back().kind = kind;
        return values().size() - 1;
    }
    std::size_t makeInt(std::int64_t i, Kind kind = Kind::Int) {
        const std::size_t v = make(kind);
        values()[v].i = i;
        return v;
    }
    std::size_t makeText(Kind kind, std::string_view s) {
        const std::size_t v = make(kind);
        values()[v].s.assign(s);
        return v;
    }
    void push(std::size_t v) { stack_.push_back(v); }
    std::size_t pop() {
        if (stack_.empty()) fail("malformed pickle (an opcode needs a value the stack does not have)");
        const std::size_t v = stack_.back();
        stack_.pop_back();
        return v;
    }
    std::size_t top() {
        if (stack_.empty()) fail("malformed pickle (an opcode needs a value the stack does not have)");
        return stack_.back();
    }
    std::vector<std::size_t> popMark() {
        if (marks_.empty()) fail("malformed pickle (no MARK for an opcode that needs one)");
        std::vector<std::size_t> items = std::move(stack_);
        stack_ = std::move(marks_.back());
        marks_.pop_back();
        return items;
    }
    Value& kindAt(std::size_t v) { return values()[v]; }

    void memoPut(std::uint64_t index) { memo_[index] = top(); }
    void memoGet(std::uint64_t index) {
        const auto it = memo_.find(index);
        if (it == memo_.end()) fail("malformed pickle (a memo entry that was never stored)");
        push(it->second);
    }

    static std::uint64_t textIndex(std::string_view s) {
        std::uint64_t v = 0;
        const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
        if (r.ec != std::errc() || r.ptr != s.data() + s.size()) fail("malformed pickle (a memo index is not a number)");
        return v;
    }

    std::size_t textInt(std::string_view s) {
        if (!s.empty() && s.back() == 'L') s.remove_suffix(1);  // protocol 0 longs
        if (s == "00") return makeInt(0, Kind::Bool);
        if (s == "01") return makeInt(1, Kind::Bool);
        std::int64_t v = 0;
        const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
        if (r.ec != std::errc() || r.ptr != s.data() + s.size()) return make(Kind::Opaque);  // beyond int64
        return makeInt(v);
    }

    // Two's complement little-endian of n bytes (LONG1, LONG4).
    std::size_t longInt(std::uint64_t n) {
        const std::string_view b = bytes(n);
        if (n > 8) return make(Kind::Opaque);
        std::uint64_t v = 0;
        for (std::size_t k = b.size(); k-- > 0;) v = (v << 8) | std::uint8_t(b[k]);
        if (n > 0 && n < 8 && (std::uint8_t(b[n - 1]) & 0x80)) v |= ~std::uint64_t(0) << (8 * n);  // sign
        return makeInt(std::int64_t(v));
    }

    std::size_t sequence(Kind kind, std::vector<std::size_t> items) {
        const std::size_t v = make(kind);
        values()[v].items = std::move(items);
        return v;
    }

    void appendTo(std::size_t target, const std::vector<std::size_t>& items, Kind want) {
        Value& t = kindAt(target);
        if (t.kind == Kind::Opaque) return;  // an object we do not model: its items are not needed
        if (t.kind != want) fail("malformed pickle (items added to a value that cannot hold them)");
        if (want == Kind::Dict && items.size() % 2 != 0) fail("malformed pickle (a dict item without its value)");
        t.items.insert(t.items.end(), items.begin(), items.end());
    }

    // ---- numpy
    // The callables numpy's pickles use; anything else is opaque.
    std::size_t call(std::size_t callable, std::size_t argsIndex) {
        const Value& f = kindAt(callable);
        const Value& args = kindAt(argsIndex);
        if (f.kind != Kind::Global || args.kind != Kind::Tuple) return make(Kind::Opaque);
        const std::string& g = f.s;
        auto arg = [&](std::size_t k) -> const Value* {
            return k < args.items.size() ? &values()[args.items[k]] : nullptr;
        };
        if (g == "numpy.core.multiarray._reconstruct" || g == "numpy._core.multiarray._reconstruct")
            return make(Kind::Array);  // filled by BUILD
        if (g == "numpy.dtype") {
            const Value* descr = arg(0);
            Dtype d;
            if (!descr || (descr->kind != Kind::Str && descr->kind != Kind::Bytes) || !parseDtype(descr->s, d))
                return make(Kind::Opaque);
            if (d.size == 1) d.order = '|';
            const std::size_t v = make(Kind::Dtype);
            values()[v].dtype = d;
            return v;
        }
        if (g == "numpy.core.multiarray.scalar" || g == "numpy._core.multiarray.scalar") {
            const Value* dt = arg(0);
            const Value* raw = arg(1);
            if (!dt || !raw || dt->kind != Kind::Dtype || (raw->kind != Kind::Bytes && raw->kind != Kind::Str) ||
                raw->s.size() != std::size_t(dt->dtype.size) || dt->dtype.size > 8)
                return make(Kind::Opaque);
            const Dtype d = dt->dtype;
            std::uint8_t b[8] = {};
            std::memcpy(b, raw->s.data(), std::size_t(d.size));
            if (d.order == '>') std::reverse(b, b + d.size);
            if (d.kind == 'f' && (d.size == 4 || d.size == 8)) {
                const std::size_t v = make(Kind::Float);
                if (d.size == 4) {
                    float x;
                    std::memcpy(&x, b, 4);
                    values()[v].f = x;
                } else {
                    std::memcpy(&values()[v].f, b, 8);
                }
                return v;
            }
            if (d.kind == 'i' || d.kind == 'u' || d.kind == 'b') {
                std::uint64_t u = 0;
                std::memcpy(&u, b, 8);
                if (d.kind == 'i' && d.size < 8 && (b[d.size - 1] & 0x80)) u |= ~std::uint64_t(0) << (8 * d.size);
                return makeInt(std::int64_t(u), d.kind == 'b' ? Kind::Bool : Kind::Int);
            }
            return make(Kind::Opaque);
        }
        if (g == "_codecs.encode") {
            // Protocol 2 keeps bytes as the latin-1 str of the same code points.
            const Value* text = arg(0);
            if (!text || text->kind != Kind::Str) return make(Kind::Opaque);
            spend(text->s.size());
            std::string out;
            out.reserve(text->s.size());
            const std::string& s = text->s;
            for (std::size_t k = 0; k < s.size();) {
                const std::uint8_t c = std::uint8_t(s[k]);
                if (c < 0x80) {
                    out += char(c);
                    ++k;
                } else if ((c & 0xE0) == 0xC0 && k + 1 < s.size()) {
                    const unsigned cp = ((c & 0x1Fu) << 6) | (std::uint8_t(s[k + 1]) & 0x3Fu);
                    if (cp > 0xFF) return make(Kind::Opaque);
                    out += char(cp);
                    k += 2;
                } else {
                    return make(Kind::Opaque);
                }
            }
            return makeText(Kind::Bytes, out);
        }
        if (g == "collections.OrderedDict" && args.items.empty()) return make(Kind::Dict);
        return make(Kind::Opaque);
    }

    void build(std::size_t target, std::size_t stateIndex) {
        // References into values(): BUILD makes no new value, so they stay valid.
        Value& obj = kindAt(target);
        const Value& state = kindAt(stateIndex);
        if (obj.kind == Kind::Dtype) {
            if (state.kind == Kind::Tuple && state.items.size() >= 2) {
                const Value& order = kindAt(state.items[1]);
                if ((order.kind == Kind::Str || order.kind == Kind::Bytes) && order.s.size() == 1) {
                    const char c = order.s[0];
                    if (c == '<' || c == '>' || c == '|') obj.dtype.order = c;
                    else if (c == '=') obj.dtype.order = '<';
                }
            }
            return;
        }
        if (obj.kind != Kind::Array) return;  // opaque objects keep no state
        if (obj.built) fail("malformed pickle (an array's state set twice)");
        if (state.kind != Kind::Tuple || (state.items.size() != 5 && state.items.size() != 4))
            fail("malformed pickle (a numpy array's state is not (version, shape, dtype, fortran, data))");
        const std::size_t o = state.items.size() == 5 ? 1 : 0;
        const Value& shape = kindAt(state.items[o]);
        const Value& dtype = kindAt(state.items[o + 1]);
        const Value& fortran = kindAt(state.items[o + 2]);
        const Value& raw = kindAt(state.items[o + 3]);
        if (shape.kind != Kind::Tuple || dtype.kind != Kind::Dtype || (fortran.kind != Kind::Bool && fortran.kind != Kind::Int))
            fail("malformed pickle (a numpy array's shape, dtype or order)");
        std::vector<std::uint64_t> dims;
        std::uint64_t count = 1;
        for (std::size_t d : shape.items) {
            const Value& n = kindAt(d);
            if (n.kind != Kind::Int || n.i < 0 || std::uint64_t(n.i) > kMaxElements)
                fail("malformed pickle (a numpy array dimension is not a count)");
            dims.push_back(std::uint64_t(n.i));
            count *= std::uint64_t(n.i);
            if (count > kMaxElements) fail("pickled numpy array declares more than 2^40 elements");
        }
        Value& a = kindAt(target);
        a.shape = std::move(dims);
        a.dtype = dtype.dtype;
        a.fortran = fortran.i != 0;
        if (a.dtype.kind == 'O') {
            if (raw.kind != Kind::List || raw.items.size() != count)
                fail("malformed pickle (an object array's items do not match its shape)");
        } else {
            if (raw.kind != Kind::Bytes && raw.kind != Kind::Str)
                fail("malformed pickle (a numpy array's data is not bytes)");
            // Sizes are checked for the number types the readers use ('U' counts
            // characters of 4 bytes, others are never read).
            const bool numeric = std::string_view("fiub").find(a.dtype.kind) != std::string_view::npos;
            if (numeric && raw.s.size() != count * std::uint64_t(a.dtype.size))
                fail("pickled numpy array declares " + std::to_string(count) + " elements of " +
                     std::to_string(a.dtype.size) + " bytes but holds " + std::to_string(raw.s.size()) + " bytes");
        }
        a.payload = state.items[o + 3];
        a.built = true;
    }

    void step(std::uint8_t op) {
        switch (op) {
            case 0x80: {  // PROTO
                if (byte() > 5) fail("pickle protocol newer than 5");
                break;
            }
            case 0x95: littleEndian(8); break;  // FRAME: only a read-ahead hint
            case '(': marks_.push_back(std::move(stack_)); stack_.clear(); break;  // MARK
            case '0':                                                              // POP
                if (!stack_.empty()) stack_.pop_back();
                else popMark();
                break;
            case '1': popMark(); break;  // POP_MARK
            case '2': push(top()); break;  // DUP
            case 'N': push(make(Kind::None)); break;
            case 0x88: push(makeInt(1, Kind::Bool)); break;  // NEWTRUE
            case 0x89: push(makeInt(0, Kind::Bool)); break;  // NEWFALSE
            case 'I': push(textInt(line())); break;
            case 'L': push(textInt(line())); break;
            case 'J': push(makeInt(std::int32_t(std::uint32_t(littleEndian(4))))); break;  // BININT
            case 'K': push(makeInt(byte())); break;                                        // BININT1
            case 'M': push(makeInt(std::int64_t(littleEndian(2)))); break;                 // BININT2
            case 0x8a: push(longInt(byte())); break;                                        // LONG1
            case 0x8b: {                                                                    // LONG4
                const std::int32_t n = std::int32_t(std::uint32_t(littleEndian(4)));
                if (n < 0) fail("malformed pickle (a negative length)");
                push(longInt(std::uint64_t(n)));
                break;
            }
            case 'F': {  // FLOAT (text)
                const std::string_view s = line();
                double v = 0;
                const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
                if (r.ec != std::errc()) fail("malformed pickle (a float that is not a number)");
                const std::size_t f = make(Kind::Float);
                values()[f].f = v;
                push(f);
                break;
            }
            case 'G': {  // BINFLOAT: big-endian IEEE double
                std::uint64_t bits = 0;
                for (char c : bytes(8)) bits = (bits << 8) | std::uint8_t(c);
                const std::size_t f = make(Kind::Float);
                std::memcpy(&values()[f].f, &bits, 8);
                push(f);
                break;
            }
            case 'S': {  // STRING: a quoted repr
                std::string_view s = line();
                if (s.size() >= 2 && (s.front() == '\'' || s.front() == '"') && s.back() == s.front())
                    s = s.substr(1, s.size() - 2);
                push(makeText(Kind::Str, s));
                break;
            }
            case 'T': push(makeText(Kind::Str, bytes(littleEndian(4)))); break;  // BINSTRING (Python 2 str)
            case 'U': push(makeText(Kind::Str, bytes(byte()))); break;            // SHORT_BINSTRING
            case 'V': push(makeText(Kind::Str, line())); break;                   // UNICODE
            case 'X': push(makeText(Kind::Str, bytes(littleEndian(4)))); break;   // BINUNICODE
            case 0x8c: push(makeText(Kind::Str, bytes(byte()))); break;           // SHORT_BINUNICODE
            case 0x8d: push(makeText(Kind::Str, bytes(littleEndian(8)))); break;  // BINUNICODE8
            case 'B': push(makeText(Kind::Bytes, bytes(littleEndian(4)))); break; // BINBYTES
            case 'C': push(makeText(Kind::Bytes, bytes(byte()))); break;          // SHORT_BINBYTES
            case 0x8e:                                                            // BINBYTES8
            case 0x96: push(makeText(Kind::Bytes, bytes(littleEndian(8)))); break;  // BYTEARRAY8
            case ')': push(make(Kind::Tuple)); break;  // EMPTY_TUPLE
            case 't': push(sequence(Kind::Tuple, popMark())); break;
            case 0x85: {  // TUPLE1
                const std::size_t a = pop();
                push(sequence(Kind::Tuple, {a}));
                break;
            }
            case 0x86: {  // TUPLE2
                const std::size_t b = pop(), a = pop();
                push(sequence(Kind::Tuple, {a, b}));
                break;
            }
            case 0x87: {  // TUPLE3
                const std::size_t c = pop(), b = pop(), a = pop();
                push(sequence(Kind::Tuple, {a, b, c}));
                break;
            }
            case ']': push(make(Kind::List)); break;  // EMPTY_LIST
            case 'l': push(sequence(Kind::List, popMark())); break;
            case 'a': {  // APPEND
                const std::size_t v = pop();
                appendTo(top(), {v}, Kind::List);
                break;
            }
            case 'e': {  // APPENDS
                const std::vector<std::size_t> items = popMark();
                appendTo(top(), items, Kind::List);
                break;
            }
            case '}': push(make(Kind::Dict)); break;  // EMPTY_DICT
            case 'd': {                               // DICT
                std::vector<std::size_t> items = popMark();
                if (items.size() % 2 != 0) fail("malformed pickle (a dict item without its value)");
                push(sequence(Kind::Dict, std::move(items)));
                break;
            }
            case 's': {  // SETITEM
                const std::size_t v = pop(), k = pop();
                appendTo(top(), {k, v}, Kind::Dict);
                break;
            }
            case 'u': {  // SETITEMS
                const std::vector<std::size_t> items = popMark();
                appendTo(top(), items, Kind::Dict);
                break;
            }
            case 0x8f: push(make(Kind::List)); break;  // EMPTY_SET: kept as a list
            case 0x90: {                               // ADDITEMS
                const std::vector<std::size_t> items = popMark();
                appendTo(top(), items, Kind::List);
                break;
            }
            case 0x91: push(sequence(Kind::List, popMark())); break;  // FROZENSET
            case 'c': {                                               // GLOBAL "module\nname\n"
                const std::string module(line());
                const std::string name(line());
                push(makeText(Kind::Global, module + "." + name));
                break;
            }
            case 0x93: {  // STACK_GLOBAL
                const std::size_t name = pop(), module = pop();
                if (kindAt(name).kind != Kind::Str || kindAt(module).kind != Kind::Str)
                    fail("malformed pickle (STACK_GLOBAL without a module and name)");
                spend(kindAt(module).s.size() + kindAt(name).s.size());
                const std::string text = kindAt(module).s + "." + kindAt(name).s;
                push(makeText(Kind::Global, text));
                break;
            }
            case 'R': {  // REDUCE
                const std::size_t args = pop(), f = pop();
                push(call(f, args));
                break;
            }
            case 'b': {  // BUILD
                const std::size_t state = pop();
                build(top(), state);
                break;
            }
            case 0x81: {  // NEWOBJ
                pop();
                pop();
                push(make(Kind::Opaque));
                break;
            }
            case 0x92: {  // NEWOBJ_EX
                pop();
                pop();
                pop();
                push(make(Kind::Opaque));
                break;
            }
            case 'p': memoPut(textIndex(line())); break;  // PUT
            case 'q': memoPut(byte()); break;             // BINPUT
            case 'r': memoPut(littleEndian(4)); break;    // LONG_BINPUT
            case 0x94: memoPut(memo_.size()); break;      // MEMOIZE
            case 'g': memoGet(textIndex(line())); break;  // GET
            case 'h': memoGet(byte()); break;             // BINGET
            case 'j': memoGet(littleEndian(4)); break;    // LONG_BINGET
            default: {
                char hex[8];
                std::snprintf(hex, sizeof hex, "0x%02x", op);
                fail(std::string("unsupported pickle opcode ") + hex + " at byte " + std::to_string(pos_ - 1) +
                     " (only plain data and numpy arrays are read)");
            }
        }
    }
};

Document load(ByteView data) { return Machine(data).run(); }

}  // namespace meniscus::io_util::pickle
