#pragma once
// The page's files (Resources/web: the HTML, its style sheet and its script), compiled into the
// program by cmake/EmbedWeb.cmake: nothing is read from the source tree or the disk at run time.
#include "Web/WebRequest.h"
#include <span>

namespace armadillo::web {

/// Every file of the page, by its path ("/index.html", "/app.js", "/style.css").
std::span<const PageFile> pageFiles() noexcept;

} // namespace armadillo::web
