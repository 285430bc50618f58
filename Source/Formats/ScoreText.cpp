#include "Formats/ScoreText.h"
#include <cmath>
#include <cstdio>

namespace armadillo::formats::scoretext {

std::string number(double v, int decimals)
{
    if (!std::isfinite(v)) v = 0.0;
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, "%.*f", decimals, v);
    std::string s = buffer;
    if (s.find('.') != std::string::npos) {
        while (!s.empty() && s.back() == '0') s.pop_back();
        if (!s.empty() && s.back() == '.') s.pop_back();
    }
    if (s == "-0") s = "0";
    return s;
}

std::string lengthNumber(double v)
{
    return number(std::ceil(v * 1e6) / 1e6 + 2e-6);
}

std::string motorSet(std::uint16_t mask)
{
    std::string s;
    for (int m = 0; m < 16; ++m)
        if (mask & (1u << m)) s += (s.empty() ? "" : ",") + std::to_string(m + 1);
    return s;
}

std::string name(std::string_view text, const std::string& fallback)
{
    std::string s;
    for (const char c : text) {
        const char l = (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c;
        if ((l >= 'a' && l <= 'z') || (l >= '0' && l <= '9')) s += l;
        else if (!s.empty() && s.back() != '-') s += '-';
    }
    while (!s.empty() && s.back() == '-') s.pop_back();
    if (s.size() > 40) s.resize(40);
    return s.empty() ? fallback : s;
}

std::string oneLine(std::string_view text)
{
    std::string s;
    for (const char c : text)
        if (c >= 0x20 && c < 0x7F && c != '#') s += c;
    return s;
}

} // namespace armadillo::formats::scoretext
