#pragma once

// Text for HTML and XML: & < > " ' written as references, so that a name from a file or a
// launch parameter cannot open an element or end an attribute (the run report, a place's
// DDS-Security permissions).

#include <string>
#include <string_view>

namespace scancrew {

inline std::string markup_escape(std::string_view s) {
  std::string out;
  out.reserve(s.size());
  for (const char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&#39;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

}  // namespace scancrew
