#include "Web/QrText.h"
#include <qrencode.h>

namespace armadillo::web {

std::vector<std::string> qrLines(const std::string& text)
{
    QRcode* code = QRcode_encodeString8bit(text.c_str(), 0, QR_ECLEVEL_M);
    if (code == nullptr) return {};
    constexpr int quiet = 2;
    const int w = code->width, size = w + 2 * quiet;
    // Light: the quiet zone and the modules whose lowest bit is 0.
    auto light = [&](int x, int y) {
        x -= quiet;
        y -= quiet;
        if (x < 0 || y < 0 || x >= w || y >= w) return true;
        return (code->data[y * w + x] & 1) == 0;
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
    QRcode_free(code);
    return lines;
}

} // namespace armadillo::web
