#pragma once
// Small text helpers shared by the rooms that read settings and options as text.
#include <string>
#include <string_view>

namespace armadillo::core {

/// `s` without leading and trailing spaces, tabs and line ends.
inline std::string trimmed(std::string_view s)
{
    constexpr std::string_view kSpace = " \t\r\n";
    const auto a = s.find_first_not_of(kSpace);
    if (a == std::string_view::npos) return {};
    return std::string(s.substr(a, s.find_last_not_of(kSpace) - a + 1));
}

} // namespace armadillo::core
