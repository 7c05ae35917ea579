// The page's static files (static/), compiled into mostar_web: nothing to install beside the
// binary and nothing fetched from elsewhere at run time. The table is generated at build time
// by embed_assets.cmake.
#pragma once

#include <cstddef>
#include <string_view>

namespace mostar::web {

struct WebAsset {
  const char* path;          // "/app.js"
  const char* content_type;  // "text/javascript; charset=utf-8"
  const unsigned char* data;
  size_t size;
};

// The asset served at `path` ("/" is "/index.html"), or null.
const WebAsset* FindAsset(std::string_view path);

}  // namespace mostar::web
