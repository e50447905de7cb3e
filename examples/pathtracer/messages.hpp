// Messages of the example tools: what a library reports, folded onto the one line that every
// error message of restir-render and restir-compare is.
#pragma once

#include <string>
#include <string_view>

namespace pt {

/// `text` on one line: each line's runs of spaces and tabs as one space, trimmed, the
/// non-empty lines joined with "; ".
inline std::string one_line(std::string_view text) {
    std::string result;
    bool new_line = false; // a line break since the last word
    bool space = false;    // a space or tab since the last word
    for (const char c : text) {
        if (c == '\n' || c == '\r') {
            new_line = true;
        } else if (c == ' ' || c == '\t') {
            space = true;
        } else {
            if (!result.empty() && (new_line || space))
                result += new_line ? "; " : " ";
            new_line = space = false;
            result += c;
        }
    }
    return result;
}

} // namespace pt
