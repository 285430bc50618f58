#include "Web/QrText.h"
#include <qrencode.h>

namespace armadillo::web {

std::vector<bool> qrModules(const std::string& text, int& width)
{
    width = 0;
    QRcode* code = QRcode_encodeString8bit(text.c_str(), 0, QR_ECLEVEL_M);
    if (code == nullptr) return {};
    width = code->width;
    std::vector<bool> dark(static_cast<std::size_t>(width) * static_cast<std::size_t>(width));
    for (std::size_t i = 0; i < dark.size(); ++i) dark[i] = (code->data[i] & 1) != 0;   // the lowest bit: dark
    QRcode_free(code);
    return dark;
}

std::vector<std::string> qrLines(const std::string& text)
{
    int w = 0;
    const std::vector<bool> dark = qrModules(text, w);
    if (dark.empty()) return {};
    constexpr int quiet = 2;
    const int size = w + 2 * quiet;
    // Light: the quiet zone and the light modules.
    auto light = [&](int x, int y) {
        x -= quiet;
        y -= quiet;
        if (x < 0 || y < 0 || x >= w || y >= w) return true;
        return !dark[static_cast<std::size_t>(y * w + x)];
    };
    std::vector<std::string> lines;
    for (int y = 0; y < size; y += 2) {
        std::string line;
        for (int x = 0; x < size; ++x) {
            const bool top = light(x, y), bottom = y + 1 < size ? light(x, y + 1) : false;
            line += top && bottom ? "\u2588" : top ? "\u2580" : bottom ? "\u2584" : " ";
        }
        lines.push_back(line);
    }
    return lines;
}

} // namespace armadillo::web
