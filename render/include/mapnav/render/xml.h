#pragma once
// Text for SVG and HTML documents.
#include <string>
#include <string_view>

namespace mapnav::render {

/// `text` with & < > " ' as entities, for XML and HTML text and attribute values.
std::string escapeXml(std::string_view text);

}  // namespace mapnav::render
