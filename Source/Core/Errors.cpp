#include "Core/Errors.h"

namespace armadillo::core {
namespace {
std::string describe(const std::string& file, long line, const std::string& column, const std::string& message)
{
    std::string s = file.empty() ? std::string("<input>") : file;
    if (line > 0) s += ":" + std::to_string(line);
    s += ": ";
    if (!column.empty()) s += "column '" + column + "': ";
    return s + message;
}
} // namespace

InputError::InputError(std::string file, long line, std::string column, const std::string& message)
    : std::runtime_error(describe(file, line, column, message)), file_(std::move(file)), line_(line),
      column_(std::move(column))
{
}

} // namespace armadillo::core
