#pragma once
#include <stdexcept>
#include <string>

namespace armadillo::core {

/// Bad input from a file, packet, message or state blob. what() names the place:
/// "FILE:LINE: column 'C': message" (line and column when known). Maps to exit code 3.
class InputError : public std::runtime_error {
public:
    InputError(std::string file, long line, std::string column, const std::string& message);
    const std::string& file() const noexcept { return file_; }
    long line() const noexcept { return line_; }          ///< 1-based; 0 = whole file
    const std::string& column() const noexcept { return column_; }

private:
    std::string file_;
    long line_;
    std::string column_;
};

/// A device, port or file-system failure. Maps to exit code 4.
class IoError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

} // namespace armadillo::core
