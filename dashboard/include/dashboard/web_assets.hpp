// The dashboard's page: the files of dashboard/web, built into the program
// (cmake/embed_web.cmake), by URL path ("/index.html", "/dashboard.js", ...).
#pragma once

#include <map>
#include <string>

namespace dashboard {

struct WebAsset {
  std::string content_type;
  std::string body;
};

const std::map<std::string, WebAsset>& web_assets();

}  // namespace dashboard
