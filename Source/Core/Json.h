#pragma once
// A small, strict JSON reader (RFC 8259) for calibration files: objects, arrays, numbers,
// strings, true/false/null. Every value remembers its line and column, so messages point at the
// problem (syntax errors say "column N: …").
// Nesting deeper than 64 levels is refused (no stack exhaustion on hostile input).
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace armadillo::core {

struct JsonValue {
    enum class Kind { Null, Bool, Number, String, Array, Object };
    Kind kind = Kind::Null;
    bool boolean = false;
    double number = 0.0;
    std::string string;
    std::vector<JsonValue> array;
    std::vector<std::pair<std::string, JsonValue>> object;   ///< in file order; duplicates refused
    long line = 0;
    long column = 0;   ///< 1-based byte column of the value's first character

    // Declared here, defaulted in Json.cpp: clang (with libstdc++'s C++20 vector) would otherwise
    // need std::pair<std::string, JsonValue> complete while JsonValue itself is not yet.
    JsonValue();
    ~JsonValue();
    JsonValue(const JsonValue&);
    JsonValue(JsonValue&&) noexcept;
    JsonValue& operator=(const JsonValue&);
    JsonValue& operator=(JsonValue&&) noexcept;

    const JsonValue* find(std::string_view key) const noexcept;
    static const char* kindName(Kind k) noexcept;
};

/// Parses text; throws InputError(source, line, "", message) on any syntax error.
JsonValue parseJson(std::string_view text, const std::string& source);

/// Appends s as a JSON string literal (quotes and escapes).
void appendJsonString(std::string& out, std::string_view s);

} // namespace armadillo::core
