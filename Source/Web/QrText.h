#pragma once
// A QR code of a text (the page's address with its token) as lines of a terminal, so a phone's
// camera can open the page (libqrencode, Debian's libqrencode-dev). Two modules a character
// (Unicode half blocks); the light modules are the terminal's text colour, the dark ones its
// background, so it reads on a dark terminal (light text on dark), with a quiet zone of 2.
#include <string>
#include <vector>

namespace armadillo::web {

/// The lines (UTF-8), top to bottom; empty when the text cannot be encoded.
std::vector<std::string> qrLines(const std::string& text);

} // namespace armadillo::web
