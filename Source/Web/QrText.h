#pragma once
// A QR code of a text (the page's address with its token) as lines of a terminal, so a phone's
// camera can open the page (libqrencode, Debian's libqrencode-dev). Two modules a character
// (Unicode half blocks); the light modules are the terminal's text colour, the dark ones its
// background, so it reads on a dark terminal (light text on dark), with a quiet zone of 2.
#include <string>
#include <vector>

namespace armadillo::web {

/// The QR code's modules, row by row (true = dark), `width` modules a side, no quiet zone; empty
/// when the text cannot be encoded. The app draws these (Setup → Web page).
std::vector<bool> qrModules(const std::string& text, int& width);

/// The lines (UTF-8), top to bottom; empty when the text cannot be encoded.
std::vector<std::string> qrLines(const std::string& text);

} // namespace armadillo::web
