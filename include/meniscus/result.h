// Result<T>: the library's way of reporting user errors (bad files, bad
// arguments) without throwing or exiting. Only apps/ turn errors into exit codes.
#pragma once

#include <string>
#include <utility>
#include <variant>

namespace meniscus {

struct Error {
    std::string file;     // the file the problem is in; empty when none applies
    std::string message;  // what is wrong, in words a user can act on

    // One line: "FILE: MESSAGE", or just "MESSAGE".
    std::string describe() const { return file.empty() ? message : file + ": " + message; }
};

inline Error makeError(std::string file, std::string message) {
    return Error{std::move(file), std::move(message)};
}

template <class T>
class [[nodiscard]] Result {
public:
    Result(T value) : v_(std::move(value)) {}
    Result(Error error) : v_(std::move(error)) {}

    bool ok() const { return v_.index() == 0; }
    explicit operator bool() const { return ok(); }

    T& value() & { return std::get<0>(v_); }
    const T& value() const& { return std::get<0>(v_); }
    T&& value() && { return std::get<0>(std::move(v_)); }
    T* operator->() { return &value(); }
    const T* operator->() const { return &value(); }
    T& operator*() & { return value(); }
    const T& operator*() const& { return value(); }

    const Error& error() const { return std::get<1>(v_); }

private:
    std::variant<T, Error> v_;
};

// For operations that return nothing on success.
using Status = Result<std::monostate>;
inline Status okStatus() { return std::monostate{}; }

}  // namespace meniscus
