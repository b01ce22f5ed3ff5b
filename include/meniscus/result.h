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
    // The caller's settings are wrong (an option's value, a scene file's
    // setting), not the data or the run: the CLI exits 2 for such an error,
    // 1 for the others (docs/usage.md#errors).
    bool usage = false;

    // One line: "FILE: MESSAGE", or just "MESSAGE".
    std::string describe() const { return file.empty() ? message : file + ": " + message; }
};

inline Error makeError(std::string file, std::string message) {
    return Error{std::move(file), std::move(message)};
}
// An error in the caller's settings (Error::usage).
inline Error makeUsageError(std::string file, std::string message) {
    return Error{std::move(file), std::move(message), true};
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
